"""A robot description file to Pinocchio models: the SILO4 xacro shipped with the project,
reading a ``.urdf`` or ``.urdf.xacro`` file to URDF text (bounded size, UTF-8), and the
fixed-base, free-flyer and visual models built from that text."""

from __future__ import annotations

import importlib.resources
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin

from .errors import RobotDescriptionError, XacroArgumentError
from .xacro_files import expand_xacro

#: Where the SILO4 description lives in the repository (its source: edit this one).
REPO_XACRO = Path(__file__).resolve().parent.parent / "urdf" / "silo4.urdf.xacro"


def _shipped_xacro() -> Path:
    """The SILO4 xacro: the copy inside the installed package (``silo4kin/data``, put there
    when the wheel is built, setup.py), else the repository's ``urdf/`` (a checkout or an
    editable install)."""
    try:
        resource = importlib.resources.files("silo4kin").joinpath("data/silo4.urdf.xacro")
        if resource.is_file():
            return Path(str(resource))
    except (ModuleNotFoundError, OSError, TypeError):  # pragma: no cover (zip imports)
        pass
    return REPO_XACRO


#: The SILO4 description shipped with the project.
DEFAULT_XACRO = _shipped_xacro()

#: Standard gravity [m/s^2]; the thesis uses 9.8 (docs/decisions.md).
STANDARD_GRAVITY = 9.81

#: Largest robot description read [bytes] (SILO4's expanded URDF is ~30 kB).
MAX_ROBOT_FILE_BYTES = 20_000_000


def read_robot_description(
    path: str | Path | None = None,
    xacro_args: Mapping[str, object] | None = None,
    package_dirs: Sequence[str | Path] = (),
) -> str:
    """Return URDF text from a ``.urdf`` or ``.xacro`` file (default: SILO4).

    Raises:
        RobotDescriptionError: missing, not a regular file, too large, not UTF-8 text.
    """
    path = Path(path) if path is not None else DEFAULT_XACRO
    try:
        if not path.is_file():
            what = (
                "is a folder"
                if path.is_dir()
                else ("is not a regular file" if path.exists() else "not found")
            )
            raise RobotDescriptionError(f"robot file {what}: {path}")
        if path.stat().st_size > MAX_ROBOT_FILE_BYTES:
            raise RobotDescriptionError(
                f"robot file {path}: larger than {MAX_ROBOT_FILE_BYTES // 1_000_000} MB"
            )
    except OSError as exc:
        raise RobotDescriptionError(f"robot file {path}: {exc.strerror or exc}") from exc
    if path.suffix == ".xacro" or path.name.endswith(".urdf.xacro"):
        return expand_xacro(
            path, xacro_args, package_dirs, trusted=path.resolve() == DEFAULT_XACRO.resolve()
        )
    if xacro_args:
        raise XacroArgumentError(
            f"xacro arguments given for a plain URDF ({path.name})", next(iter(xacro_args)), ()
        )
    try:
        return path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise RobotDescriptionError(
            f"robot file {path}: not UTF-8 text (byte {exc.start}: {exc.reason}); is it a URDF?"
        ) from None
    except OSError as exc:
        raise RobotDescriptionError(f"robot file {path}: {exc.strerror or exc}") from exc


def build_models(
    urdf_xml: str, package_dirs: list[str] | None = None
) -> tuple[pin.Model, pin.Model, pin.GeometryModel]:
    """Fixed-base model, free-flyer model and visual model from URDF text."""
    try:
        ET.fromstring(urdf_xml)
    except ET.ParseError as exc:
        raise RobotDescriptionError(f"malformed URDF XML: {exc}") from exc
    try:
        model = pin.buildModelFromXML(urdf_xml)
        model_ff = pin.buildModelFromXML(urdf_xml, pin.JointModelFreeFlyer())
        visual = pin.buildGeomFromUrdfString(
            model, urdf_xml, pin.GeometryType.VISUAL, package_dirs=package_dirs or []
        )
    except (ValueError, RuntimeError) as exc:
        hint = ""
        if "could not be found" in str(exc):
            hint = (
                "; give the folder holding the robot's meshes (or its package) with --package-dir"
            )
        raise RobotDescriptionError(f"Pinocchio refused the URDF: {exc}{hint}") from exc
    for m in (model, model_ff):
        m.gravity.linear = np.array([0.0, 0.0, -STANDARD_GRAVITY])
    return model, model_ff, visual
