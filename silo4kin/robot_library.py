"""Robots by name: ``silo4`` (the shipped xacro) and example-robot-data's quadrupeds.

``load_robot("go2")`` resolves the URDF, its meshes (``package://`` against the
example-robot-data share folder) and its standing pose (the SRDF's reference configuration,
which picks the knee branch of a mammal leg) from the installed example-robot-data package,
without building example-robot-data's own RobotWrapper (which loads every mesh).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from .errors import RobotDescriptionError

#: example-robot-data quadrupeds this toolkit supports (loader names), in listing order.
EXAMPLE_QUADRUPEDS: tuple[str, ...] = (
    "go2", "go1", "a1", "b1", "laikago", "solo12", "anymal", "anymal_c", "hyq")
#: Names refused with a reason when asked for (kept so the message is about the robot).
EXAMPLE_OTHERS: tuple[str, ...] = ("solo8",)
#: The name of the robot this toolkit ships.
SILO4 = "silo4"


@dataclass(frozen=True)
class RobotSource:
    """Where a named robot's files are.

    Attributes:
        name: the name asked for.
        urdf: URDF file [path].
        package_dirs: folders ``package://`` mesh URIs resolve against.
        srdf: SRDF with the reference (standing) configuration, or None.
        reference_posture: name of that configuration in the SRDF, or None.
    """

    name: str
    urdf: Path
    package_dirs: tuple[str, ...]
    srdf: Path | None
    reference_posture: str | None


def known_robot_names() -> tuple[str, ...]:
    """Every name ``load_robot`` accepts instead of a path."""
    return (SILO4, *EXAMPLE_QUADRUPEDS)


#: Longest robot name looked up (longer words are treated as file names and reported so).
MAX_NAME_LENGTH = 64


def looks_like_name(text: str) -> bool:
    """A short bare word (no folder, no suffix) that is not an existing file or folder, or
    that is a known robot's name beside a folder of that name: ``silo4 plan --robot go2
    --out go2`` makes one, and ``silo4 simulate go2`` then still means the robot go2 (any
    other folder is reported as "a folder", not as an unknown name)."""
    if len(text) > MAX_NAME_LENGTH or os.sep in text or "/" in text or "." in text:
        return False
    try:
        path = Path(text)
        return not path.exists() or (path.is_dir() and text in known_robot_names())
    except OSError:  # a name the system refuses: let the file reader report it
        return False


def resolve_example_robot(name: str) -> RobotSource:
    """Files of an example-robot-data robot by its loader name (e.g. ``"go2"``).

    Raises:
        RobotDescriptionError: unknown name (the message lists the known ones), or
            example-robot-data is not installed.
    """
    if name not in EXAMPLE_QUADRUPEDS + EXAMPLE_OTHERS:
        raise RobotDescriptionError(
            f"unknown robot {name!r}: give a .urdf/.urdf.xacro path or one of "
            f"{', '.join(known_robot_names())}")
    try:
        from example_robot_data import robots_loader
    except ImportError as exc:  # the data package without its loader package
        raise RobotDescriptionError(
            f"robot {name!r} comes from example-robot-data: pip install "
            "example-robot-data example-robot-data-loaders") from exc
    loader = robots_loader.ROBOTS[name]
    sub = os.path.join(loader.path, loader.urdf_subpath, loader.urdf_filename)
    models = loader.model_path or robots_loader.getModelPath(sub)
    srdf = None
    if getattr(loader, "srdf_filename", None):
        srdf = Path(models, loader.path, loader.srdf_subpath, loader.srdf_filename)
    # meshes are package://example-robot-data/robots/...: resolve against the share folder
    return RobotSource(name=name, urdf=Path(models, sub),
                       package_dirs=(os.path.dirname(os.path.dirname(models)),),
                       srdf=srdf if srdf is not None and srdf.is_file() else None,
                       reference_posture=getattr(loader, "ref_posture", None))
