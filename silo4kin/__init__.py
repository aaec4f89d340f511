"""silo4kin: robot model, closed-form kinematics and dynamics of insect-leg quadrupeds.

Layer 1 of the toolkit (docs/architecture.md): numpy arrays and frozen dataclasses in and out;
never imports ``planner`` or ``viz``.
"""

from importlib import import_module
from typing import TYPE_CHECKING, Any

from .errors import (
    ClosedFormNotApplicableError,
    RobotDescriptionError,
    Silo4Error,
    UnreachableTargetError,
    XacroArgumentError,
)

#: Names served lazily (PEP 562): importing ``silo4kin.errors`` (every CLI module does) must
#: not import numpy and Pinocchio, or ``silo4 --help`` costs 10x a bare Python start.
_LAZY = {
    "NotInsectLegError": "discovery",
    "LEG_NAMES": "geometry",
    "LegGeometry": "geometry",
    "LinkInertia": "geometry",
    "DEFAULT_XACRO": "robot",
    "Robot": "robot",
    "load_robot": "robot",
}

if TYPE_CHECKING:
    from .discovery import NotInsectLegError
    from .geometry import LEG_NAMES, LegGeometry, LinkInertia
    from .robot import DEFAULT_XACRO, Robot, load_robot


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "DEFAULT_XACRO",
    "LEG_NAMES",
    "ClosedFormNotApplicableError",
    "LegGeometry",
    "LinkInertia",
    "NotInsectLegError",
    "Robot",
    "RobotDescriptionError",
    "Silo4Error",
    "UnreachableTargetError",
    "XacroArgumentError",
    "load_robot",
]
