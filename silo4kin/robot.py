"""Load a robot: xacro -> URDF -> Pinocchio models (fixed base, free flyer, visuals) + legs.

    robot = load_robot()                                  # SILO4 from urdf/silo4.urdf.xacro
    robot = load_robot(xacro_args={"L3": 0.3})            # a variant, one argument away
    robot = load_robot("my_robot.urdf")                   # a plain URDF

The xacro is expanded by the PyPI ``xacro`` package (no ROS). xacro silently ignores unknown
arguments; we refuse them and list the valid ones.
"""

from __future__ import annotations

import contextlib
import importlib.resources
import math
import xml.etree.ElementTree as ET
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin

from .discovery import (
    MAMMAL,
    NotInsectLegError,
    body_com,
    discover_legs,
    discover_mammal_legs,
    knee_convention,
    leg_family,
)
from .errors import RobotDescriptionError, XacroArgumentError
from .geometry import LEG_NAMES, LegGeometry, extract_leg_geometry
from .mammal import MammalLegGeometry, extract_mammal_leg_geometry
from .robot_library import SILO4, RobotSource, looks_like_name, resolve_example_robot

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

#: Joint naming convention of docs/design.md: {leg}_{hip_yaw,hip_pitch,knee}, foot frame {leg}_foot.
JOINT_SUFFIXES: tuple[str, str, str] = ("hip_yaw", "hip_pitch", "knee")


@dataclass(frozen=True, eq=False)
class Robot:
    """A loaded insect-leg quadruped.

    Attributes:
        name: robot name from the URDF.
        urdf_xml: the expanded URDF text.
        model: fixed-base Pinocchio model, nq = 12; its root frame is the URDF's root link
            (for SILO4 the body CoG; for other robots see position_body_com_in_base).
        model_free_flyer: the same robot on a free-flyer joint, nq = 19.
        visual_model: visual geometry of the fixed-base model.
        legs: leg geometry in array order LF, RF, LH, RH.
        source: file the robot was loaded from, or None.
        xacro_args: the xacro arguments used (strings).
        family: leg family, "insect" (vertical first axis, the thesis's) or "mammal" (hip
            ab/adduction about x first); legs are LegGeometry or MammalLegGeometry.
        library_name: the name it was loaded by (``load_robot("go2")``), or None.
    """

    name: str
    urdf_xml: str = field(repr=False)
    model: pin.Model = field(repr=False)
    model_free_flyer: pin.Model = field(repr=False)
    visual_model: pin.GeometryModel = field(repr=False)
    legs: tuple[LegGeometry, ...] = field(repr=False)
    source: Path | None = None
    xacro_args: Mapping[str, str] = field(default_factory=dict)
    family: str = "insect"
    library_name: str | None = None
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    @property
    def joint_names(self) -> list[str]:
        """The 12 actuated joint names in array order (leg by leg, yaw/pitch/knee)."""
        return [jn for leg in self.legs for jn in leg.joint_names]

    @property
    def q_index(self) -> np.ndarray:
        """Index into the fixed-base model's q of each of our 12 joints, shape (12,).

        Pinocchio orders joints by name, not by file: always map through this.
        """
        return np.array([self.model.joints[self.model.getJointId(n)].idx_q
                         for n in self.joint_names])

    @property
    def body_mass(self) -> float:
        """Mass of the base link alone [kg]."""
        return float(self.model_free_flyer.inertias[1].mass)

    @property
    def total_mass(self) -> float:
        """Body plus legs [kg]."""
        return float(pin.computeTotalMass(self.model_free_flyer))

    @property
    def position_body_com_in_base(self) -> np.ndarray:
        """Body (base link) centre of mass in the base frame [m], shape (3,)."""
        return np.array(self.model_free_flyer.inertias[1].lever)

    def to_pinocchio_q(self, q: np.ndarray) -> np.ndarray:
        """Our joint order (..., 12) -> Pinocchio fixed-base order (..., 12)."""
        q = np.asarray(q, dtype=float)
        out = np.empty_like(q)
        out[..., self.q_index] = q
        return out

    def from_pinocchio_q(self, q_pin: np.ndarray) -> np.ndarray:
        """Pinocchio fixed-base order (..., 12) -> our joint order (..., 12)."""
        return np.asarray(q_pin, dtype=float)[..., self.q_index]

    def leg(self, name: str) -> LegGeometry:
        """Leg by name; raises with the valid names."""
        for leg in self.legs:
            if leg.name == name:
                return leg
        raise RobotDescriptionError(
            f"no leg {name!r}; legs are {[leg.name for leg in self.legs]}")


def declared_xacro_args(path: Path) -> dict[str, str | None]:
    """Names and defaults of the ``<xacro:arg>`` elements a xacro file declares."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise RobotDescriptionError(f"{path}: malformed XML: {exc}") from exc
    out: dict[str, str | None] = {}
    for el in root.iter():
        tag = el.tag.split("}")[-1]
        if tag == "arg" and "name" in el.attrib:
            out[el.attrib["name"]] = el.attrib.get("default")
    return out


def _is_numeric_default(default: str | None) -> bool:
    if default is None:
        return False
    if default.startswith("${"):
        return True
    try:
        float(default)
    except ValueError:
        return False
    return True


def find_package(name: str, package_dirs: Sequence[str | Path]) -> Path:
    """The folder of ROS package ``name`` among ``package_dirs`` (for xacro's ``$(find)`` and
    ``package://``): ``DIR/name``, or ``DIR`` itself when it is named ``name``.

    Raises:
        RobotDescriptionError: not found (names the folders searched).
    """
    for folder in map(Path, package_dirs):
        for candidate in (folder / name, folder):
            if candidate.name == name and candidate.is_dir():
                return candidate.resolve()
    where = ", ".join(str(d) for d in package_dirs) or "none given"
    raise RobotDescriptionError(
        f"xacro $(find {name}): package {name!r} not found in the --package-dir folders "
        f"({where}); give the folder that holds {name}/ with --package-dir")


@contextlib.contextmanager
def _xacro_find(package_dirs: Sequence[str | Path]) -> Iterator[None]:
    """Make xacro's ``$(find pkg)`` look in ``package_dirs`` (it needs ROS otherwise)."""
    from xacro import substitution_args as subst

    def eval_find(pkg: str) -> str:
        return str(find_package(pkg, package_dirs))

    saved = subst._eval_find, subst._eval_dict.get("find")
    subst._eval_find = eval_find  # type: ignore[assignment]
    subst._eval_dict["find"] = eval_find
    try:
        yield
    finally:
        subst._eval_find = saved[0]  # type: ignore[assignment]
        subst._eval_dict["find"] = saved[1]


def expand_xacro(path: Path, xacro_args: Mapping[str, object] | None = None,
                 package_dirs: Sequence[str | Path] = ()) -> str:
    """Expand a xacro file to URDF text, validating the argument names and values.

    Raises:
        XacroArgumentError: unknown argument name, or a non-numeric value for a numeric one.
        RobotDescriptionError: the file is missing or xacro fails on it.
    """
    import xacro  # local: module-global state, not thread-safe (stack-notes.md)

    declared = declared_xacro_args(path)
    mappings: dict[str, str] = {}
    for name, value in (xacro_args or {}).items():
        if name not in declared:
            raise XacroArgumentError(
                f"unknown xacro argument {name!r} for {path.name}; valid arguments: "
                f"{', '.join(sorted(declared))}", name, declared)
        text = str(value)
        if _is_numeric_default(declared[name]):
            try:
                number = float(text)
            except ValueError:
                raise XacroArgumentError(
                    f"xacro argument {name}={text!r} is not a number", name, declared) from None
            if not math.isfinite(number) or abs(number) > MAX_XACRO_NUMBER:
                raise XacroArgumentError(
                    f"xacro argument {name}={text!r} is not a finite number within "
                    f"±{MAX_XACRO_NUMBER:g} (SI units: m, kg, rad)", name, declared)
        mappings[name] = text
    try:
        with _xacro_find(package_dirs):
            return str(xacro.process_file(str(path), mappings=mappings).toxml())
    except RobotDescriptionError:
        raise
    except Exception as exc:  # xacro raises XacroException, XML errors, NameError, ...
        if isinstance(exc.__context__, RobotDescriptionError):  # our $(find), re-wrapped
            raise exc.__context__ from None
        raise RobotDescriptionError(f"{path}: xacro failed: {exc}") from exc


#: Largest magnitude of a numeric xacro argument (SI units); beyond it FK overflows.
MAX_XACRO_NUMBER = 1e4

#: Largest robot description read [bytes] (SILO4's expanded URDF is ~30 kB).
MAX_ROBOT_FILE_BYTES = 20_000_000


def read_robot_description(path: str | Path | None = None,
                           xacro_args: Mapping[str, object] | None = None,
                           package_dirs: Sequence[str | Path] = ()) -> str:
    """Return URDF text from a ``.urdf`` or ``.xacro`` file (default: SILO4).

    Raises:
        RobotDescriptionError: missing, not a regular file, too large, not UTF-8 text.
    """
    path = Path(path) if path is not None else DEFAULT_XACRO
    try:
        if not path.is_file():
            what = "is a folder" if path.is_dir() else (
                "is not a regular file" if path.exists() else "not found")
            raise RobotDescriptionError(f"robot file {what}: {path}")
        if path.stat().st_size > MAX_ROBOT_FILE_BYTES:
            raise RobotDescriptionError(f"robot file {path}: larger than "
                                        f"{MAX_ROBOT_FILE_BYTES // 1_000_000} MB")
    except OSError as exc:
        raise RobotDescriptionError(f"robot file {path}: {exc.strerror or exc}") from exc
    if path.suffix == ".xacro" or path.name.endswith(".urdf.xacro"):
        return expand_xacro(path, xacro_args, package_dirs)
    if xacro_args:
        raise XacroArgumentError(
            f"xacro arguments given for a plain URDF ({path.name})", next(iter(xacro_args)), ())
    try:
        return path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise RobotDescriptionError(f"robot file {path}: not UTF-8 text (byte {exc.start}: "
                                    f"{exc.reason}); is it a URDF?") from None
    except OSError as exc:
        raise RobotDescriptionError(f"robot file {path}: {exc.strerror or exc}") from exc


def build_models(urdf_xml: str, package_dirs: list[str] | None = None
                 ) -> tuple[pin.Model, pin.Model, pin.GeometryModel]:
    """Fixed-base model, free-flyer model and visual model from URDF text."""
    try:
        ET.fromstring(urdf_xml)
    except ET.ParseError as exc:
        raise RobotDescriptionError(f"malformed URDF XML: {exc}") from exc
    try:
        model = pin.buildModelFromXML(urdf_xml)
        model_ff = pin.buildModelFromXML(urdf_xml, pin.JointModelFreeFlyer())
        visual = pin.buildGeomFromUrdfString(model, urdf_xml, pin.GeometryType.VISUAL,
                                             package_dirs=package_dirs or [])
    except (ValueError, RuntimeError) as exc:
        hint = ""
        if "could not be found" in str(exc):
            hint = ("; give the folder holding the robot's meshes (or its package) with "
                    "--package-dir")
        raise RobotDescriptionError(f"Pinocchio refused the URDF: {exc}{hint}") from exc
    for m in (model, model_ff):
        m.gravity.linear = np.array([0.0, 0.0, -STANDARD_GRAVITY])
    return model, model_ff, visual


def silo4_leg_names(model: pin.Model) -> dict[str, tuple[tuple[str, str, str], str]]:
    """Legs by the SILO4 naming convention: {leg}_{hip_yaw,hip_pitch,knee}, frame {leg}_foot.

    ``load_robot`` no longer uses this (it discovers legs from the geometry,
    :func:`silo4kin.discovery.discover_legs`); kept to check that both agree on SILO4.
    """
    legs = {}
    for leg in LEG_NAMES:
        names = tuple(f"{leg}_{s}" for s in JOINT_SUFFIXES)
        missing = [n for n in names if not model.existJointName(n)]
        if missing:
            found = [n for n in model.names[1:]]
            raise RobotDescriptionError(
                f"leg {leg}: expected joints {list(names)}, missing {missing}; "
                f"the model has joints {found}")
        legs[leg] = (names, f"{leg}_foot")
    return legs  # type: ignore[return-value]


def load_robot(path: str | Path | None = None,
               xacro_args: Mapping[str, object] | None = None,
               package_dirs: list[str] | None = None) -> Robot:
    """Load a quadruped of a supported leg family; legs are discovered from the geometry.

    Args:
        path: ``.urdf`` or ``.urdf.xacro`` file, or a robot name (``"silo4"``, or an
            example-robot-data quadruped such as ``"go2"``: robot_library.py); default
            ``urdf/silo4.urdf.xacro``.
        xacro_args: xacro argument overrides, e.g. ``{"L3": 0.3}``.
        package_dirs: folders to resolve mesh paths against.

    Raises:
        NotInsectLegError: the robot is not an insect-leg quadruped (the message names the
            chain, the joint and the broken assumption; docs/robots.md).
        RobotDescriptionError: missing/malformed file, unknown argument, body without mass.
    """
    named: RobotSource | None = None
    if path is not None and isinstance(path, str) and looks_like_name(path):
        if path == SILO4:
            path = None
        else:
            named = resolve_example_robot(path)
            path = named.urdf
            package_dirs = [*named.package_dirs, *(package_dirs or [])]
    src = Path(path) if path is not None else DEFAULT_XACRO
    urdf_xml = read_robot_description(src, xacro_args, package_dirs or ())
    model, model_ff, visual = build_models(urdf_xml, package_dirs)
    try:
        family = leg_family(model)
        legs: tuple[LegGeometry, ...] | tuple[MammalLegGeometry, ...]
        if family == MAMMAL:
            rest = _reference_posture(model, named)
            legs = tuple(
                extract_mammal_leg_geometry(
                    model, leg, names, foot,
                    None if rest is None else rest[[model.joints[model.getJointId(n)].idx_q
                                                    for n in names]])
                for leg, (names, foot) in discover_mammal_legs(model).items())
        else:
            found = discover_legs(model)
            legs = tuple(extract_leg_geometry(model, leg, names, foot)
                         for leg, (names, foot) in found.items())
            for leg in legs:
                knee_convention(leg)  # refuses a knee that cannot bend down
        body_com(model)  # refuses a massless body: its CoG is the stability point
    except RobotDescriptionError as exc:
        raise type(exc)(f"{src.name}: {exc}", *_extra_args(exc)) from exc
    return Robot(name=model.name, urdf_xml=urdf_xml, model=model, model_free_flyer=model_ff,
                 visual_model=visual, legs=legs, source=src,  # type: ignore[arg-type]
                 xacro_args={k: str(v) for k, v in (xacro_args or {}).items()},
                 family=family, library_name=named.name if named else None)


def _reference_posture(model: pin.Model, named: RobotSource | None) -> np.ndarray | None:
    """The SRDF's standing configuration of a named robot (fixed-base q, Pinocchio order)."""
    if named is None or named.srdf is None or named.reference_posture is None:
        return None
    try:
        pin.loadReferenceConfigurations(model, str(named.srdf), False)
        return np.array(model.referenceConfigurations[named.reference_posture])
    except (RuntimeError, ValueError, KeyError, IndexError):
        return None  # no usable standing pose: the knee branch comes from the limits


def _extra_args(exc: RobotDescriptionError) -> tuple[object, ...]:
    """Constructor arguments after the message, to re-raise an error with the file name."""
    return (exc.chain,) if isinstance(exc, NotInsectLegError) else ()
