"""silo4kin: robot model, closed-form kinematics and dynamics of insect-leg quadrupeds.

Layer 1 of the toolkit (docs/architecture.md): numpy arrays and frozen dataclasses in and out;
never imports ``planner`` or ``viz``.
"""

from .discovery import NotInsectLegError
from .errors import (
    ClosedFormNotApplicableError,
    RobotDescriptionError,
    Silo4Error,
    UnreachableTargetError,
    XacroArgumentError,
)
from .geometry import LEG_NAMES, LegGeometry, LinkInertia
from .robot import DEFAULT_XACRO, Robot, load_robot

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
