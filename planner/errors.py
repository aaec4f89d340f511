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
        step_start_units: start [units] of the step a check of the samples refused, or None
            (planner/trajectory/verify.py; the omnidirectional gait replaces the foothold of
            a refused swing, planner/gaits/foothold_replacement.py).
    """

    step_start_units: float | None = None

    def __init__(
        self,
        reason: str,
        waypoint_index: int | None = None,
        waypoint: tuple[float, float] | None = None,
    ) -> None:
        where = "planning"
        if waypoint_index is not None:
            where = f"waypoint {waypoint_index}"
            if waypoint is not None:
                where += f" ({waypoint[0]:.4g}, {waypoint[1]:.4g}) m"
        super().__init__(f"{where}: {reason}")
        self.waypoint_index = waypoint_index
        self.waypoint = waypoint
        self.reason = reason


class FootholdRefused(Silo4Error):
    """The terrain refuses a foothold a step would place (planner/terrain/base.py).

    Not a PlanningError: a refused foothold rules out the gait being built (plan_path's
    "auto" tries another; the continuous crawl undoes the swing), never a fallback to a
    slower gait on the same ground.

    Attributes:
        position_foot_in_world: the foothold (3,) in W [m].
        reason: why the terrain refuses it.
    """

    def __init__(self, position_foot_in_world, reason: str = "not allowed by the terrain") -> None:
        x, y, z = (float(v) for v in position_foot_in_world)
        super().__init__(f"foothold ({x:.4g}, {y:.4g}, {z:.4g}) m refused: {reason}")
        self.position_foot_in_world = (x, y, z)
        self.reason = reason


class GaitRefused(PlanningError):
    """A gait that cannot give this plan, for a reason that names no waypoint: its finished
    plan breaks a rule it is held to (URDF speed or effort limits, the shank slope), it is
    not offered for these legs, or every gait of a combination failed (``reasons``, one
    per gait: "continuous crawl: ..."). The message is the reason."""

    def __init__(self, reason: str, reasons: tuple[str, ...] = ()) -> None:
        Silo4Error.__init__(self, reason)
        self.waypoint_index = None
        self.waypoint = None
        self.reason = reason
        self.reasons = reasons or (reason,)
