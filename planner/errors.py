"""Errors of the planner layer (all derive from :class:`silo4kin.errors.Silo4Error`)."""

from __future__ import annotations

from silo4kin.errors import Silo4Error


class PlannerInputError(Silo4Error):
    """A planner argument is out of range: names the value and what is allowed."""


class PlanningError(Silo4Error):
    """No statically stable, reachable step exists for a waypoint.

    Attributes:
        waypoint_index: index of the waypoint being planned for (0-based), or None.
        waypoint: the waypoint (x, y) in the world frame [m], or None.
        reason: what failed (stability, reach, joint limit ...).
    """

    def __init__(self, reason: str, waypoint_index: int | None = None,
                 waypoint: tuple[float, float] | None = None) -> None:
        where = "planning"
        if waypoint_index is not None:
            where = f"waypoint {waypoint_index}"
            if waypoint is not None:
                where += f" ({waypoint[0]:.4g}, {waypoint[1]:.4g}) m"
        super().__init__(f"{where}: {reason}")
        self.waypoint_index = waypoint_index
        self.waypoint = waypoint
        self.reason = reason
