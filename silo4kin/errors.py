"""One exception root for the whole toolkit (style.md §6).

Every error a user can cause derives from :class:`Silo4Error`; the CLI turns it into one
line on stderr and exit code 2. Subclasses carry the offending value and the valid choices.
"""

from __future__ import annotations

from collections.abc import Iterable


class Silo4Error(Exception):
    """Root of every error raised on purpose by silo4kin, planner and viz."""


class RobotDescriptionError(Silo4Error):
    """A robot file is missing, malformed, or not of the expected architecture."""


class XacroArgumentError(RobotDescriptionError):
    """A xacro argument is unknown or its value is not a number.

    Attributes:
        name: the offending argument name.
        valid: the argument names the xacro file declares.
    """

    def __init__(self, message: str, name: str, valid: Iterable[str]) -> None:
        super().__init__(message)
        self.name = name
        self.valid = tuple(sorted(valid))


class UnreachableTargetError(Silo4Error):
    """A foot target lies outside a leg's reach (inverse kinematics, eq 3.10-3.24).

    Attributes:
        leg: leg name.
        target: the first unreachable target, foot position in the base frame [m], shape (3,).
        reach: (min, max) distance from the hip-pitch joint the leg can reach [m].
    """

    def __init__(
        self, message: str, leg: str, target: tuple[float, ...], reach: tuple[float, float]
    ) -> None:
        super().__init__(message)
        self.leg = leg
        self.target = target
        self.reach = reach


class ClosedFormNotApplicableError(Silo4Error):
    """The closed-form model's assumptions do not hold for this robot's inertial data."""
