"""Expand a xacro file to URDF text with the PyPI ``xacro`` package (no ROS).

xacro silently ignores unknown arguments; :func:`expand_xacro` refuses them and lists the
valid ones, refuses non-numeric or huge values for numeric ones, and resolves ``$(find pkg)``
in the folders given.
"""

from __future__ import annotations

import contextlib
import math
import xml.etree.ElementTree as ET
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path

from .errors import RobotDescriptionError, XacroArgumentError

#: Largest magnitude of a numeric xacro argument (SI units); beyond it FK overflows.
MAX_XACRO_NUMBER = 1e4


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
    subst._eval_find = eval_find
    subst._eval_dict["find"] = eval_find
    try:
        yield
    finally:
        subst._eval_find = saved[0]
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
