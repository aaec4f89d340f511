"""Robots by name: ``silo4`` (the shipped xacro) and example-robot-data's quadrupeds.

``load_robot("go2")`` resolves the URDF, its meshes (``package://`` against the
example-robot-data share folder) and its standing pose (the SRDF's reference configuration,
which picks the knee branch of a mammal leg) from the installed example-robot-data package,
without building example-robot-data's own RobotWrapper (which loads every mesh).
This module imports nothing heavy: ``silo4 --help`` lists its names.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import NamedTuple

from .errors import RobotDescriptionError

#: Suffix of robot_descriptions.py's names (``go2_description``): the same robot as ``go2``.
DESCRIPTION_SUFFIX = "_description"

#: example-robot-data quadrupeds this toolkit supports (loader names), in listing order.
EXAMPLE_QUADRUPEDS: tuple[str, ...] = (
    "go2",
    "go1",
    "a1",
    "b1",
    "laikago",
    "solo12",
    "anymal",
    "anymal_c",
    "hyq",
)
#: Names refused with a reason when asked for (kept so the message is about the robot).
EXAMPLE_OTHERS: tuple[str, ...] = ("solo8",)
#: The name of the robot this toolkit ships.
SILO4 = "silo4"


class RobotSource(NamedTuple):
    """Where a named robot's files are (a NamedTuple, not a dataclass: ``silo4 --help``
    lists the names of this module and must not import dataclasses, tests/test_lazy_imports.py).

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


def canonical_robot_name(name: str) -> str:
    """The loader name of a robot name: ``go2_description`` (robot_descriptions.py's
    spelling, and the name inside go2's URDF) -> ``go2``; case and surrounding blanks
    ignored."""
    word = name.strip().lower()
    if word.endswith(DESCRIPTION_SUFFIX) and len(word) > len(DESCRIPTION_SUFFIX):
        word = word[: -len(DESCRIPTION_SUFFIX)]
    return word


def unknown_robot_message(name: str, candidates: tuple[str, ...]) -> str:
    """``unknown robot 'go3': did you mean go2? ...``: the closest known names (difflib)
    first, then every name accepted."""
    import difflib

    unique = tuple(dict.fromkeys(candidates))
    close = difflib.get_close_matches(canonical_robot_name(name), unique, n=3, cutoff=0.6)
    hint = f"did you mean {' or '.join(close)}? " if close else ""
    return (
        f"unknown robot {name!r}: {hint}give a .urdf/.urdf.xacro path or one of "
        f"{', '.join(known_robot_names())}"
    )


def resolve_example_robot(name: str) -> RobotSource:
    """Files of an example-robot-data robot by its loader name (e.g. ``"go2"``, or
    ``"go2_description"``: :func:`canonical_robot_name`). Names of example-robot-data robots
    that are not quadrupeds (``ur5``, ``talos``) resolve too: the leg discovery then refuses
    them as not quadrupeds.

    Raises:
        RobotDescriptionError: unknown name (the message suggests the closest and lists the
            known ones), or example-robot-data is not installed.
    """
    asked, name = name, canonical_robot_name(name)
    try:
        from example_robot_data import robots_loader
    except ImportError as exc:  # the data package without its loader package
        if name not in EXAMPLE_QUADRUPEDS + EXAMPLE_OTHERS:
            raise RobotDescriptionError(unknown_robot_message(asked, known_robot_names())) from None
        raise RobotDescriptionError(
            f"robot {name!r} comes from example-robot-data: pip install "
            "example-robot-data example-robot-data-loaders"
        ) from exc
    if name not in robots_loader.ROBOTS:
        raise RobotDescriptionError(
            unknown_robot_message(
                asked, (*known_robot_names(), *EXAMPLE_OTHERS, *sorted(robots_loader.ROBOTS))
            )
        )
    loader = robots_loader.ROBOTS[name]
    sub = os.path.join(loader.path, loader.urdf_subpath, loader.urdf_filename)
    models = loader.model_path or robots_loader.getModelPath(sub)
    srdf = None
    if getattr(loader, "srdf_filename", None):
        srdf = Path(models, loader.path, loader.srdf_subpath, loader.srdf_filename)
    # meshes are package://example-robot-data/robots/...: resolve against the share folder
    return RobotSource(
        name=name,
        urdf=Path(models, sub),
        package_dirs=(os.path.dirname(os.path.dirname(models)),),
        srdf=srdf if srdf is not None and srdf.is_file() else None,
        reference_posture=getattr(loader, "ref_posture", None),
    )
