"""The fewest time units the continuous crawl (planner/gaits/crawl.py, with its creeping
fallback planner/gaits/crawl_or_creep.py: gait "crawl") can take on a request's waypoints,
found without building a step.

Why it is a lower bound. The crawl walks the nominal CoG in the straight segments of
walk_without_turning (planner/gaits/without_turning.py), as the creeping gait does, so the
walks, aims and arrival slack are those of planner/gaits/creep_duration.py; what differs is
how fast a segment of length d along the unit direction u (base frame B, the gait never
turns) can be walked. With r = r(u) the ellipse radius along u and D = FOUR_FOOT_UNITS
(Crawl.to: a_nom = 2 r / (3 + 2 D), the steady state's advance per swing), each step the
crawl keeps is one of

- a swing (moving_transfer): exactly TRANSFER_UNITS = 1 unit, the nominal CoG advanced by
  t <= t_want <= a_nom (reachable_advance caps t_want by the stance feet's ellipses and
  halves it for reach, never raises it);
- a four-foot phase (Crawl._four_foot): at least D units (StepBuilder.four_foot_units only
  lengthens it, sway_timing.py), the nominal CoG advanced by at most D a_nom;
- a sway or an arrival (body steps off the nominal CoG, Phase.SHIFT or "crawl arrive"):
  some time, no advance;
- a creeping half cycle where the crawl finds no step (CrawlOrCreep; the crawl's attempt is
  rolled back, its steps and time dropped): at least HALF_CYCLE_UNITS = 3 units, an advance
  of at most r (creep_duration.py).

So every unit of the plan advances the nominal CoG by at most
v(u) = max(a_nom, r / HALF_CYCLE_UNITS) = a_nom (2 / (3 + 2 D) >= 1 / 3 for D <= 1.5), and
a segment takes at least d / v(u) units: the least over the walks is the bound. It ignores
the ramp from a standing start, the sways and the advances the stance feet's ellipses and
reach cut (SILO4 on the thesis straight path at 0.40-0.60 m: 0.67-0.89 of the crawl's
time), so it decides heights whose stride is too short to beat the time in hand, and
candidates near it only in their last segment.
"""

from __future__ import annotations

import numpy as np

from planner.gaits.crawl import FOUR_FOOT_UNITS
from planner.gaits.creep_duration import HALF_CYCLE_UNITS, STEP_ROUNDING_M, WalkBound
from planner.workspace.layout import Workspace

#: Relative slack on the advance per unit (the planner's float sums of the advances).
ADVANCE_SLACK = 1e-9


def advance_per_unit_m(radius_m: float, four_foot_units: float = FOUR_FOOT_UNITS) -> float:
    """The most the crawl (or its creeping fallback) advances the nominal CoG in one time
    unit along a direction of ellipse radius ``radius_m`` [m] (module docstring) [m]."""
    r = radius_m + STEP_ROUNDING_M
    swing = 2.0 * r / (3.0 + 2.0 * four_foot_units)
    return max(swing, r / HALF_CYCLE_UNITS) * (1.0 + ADVANCE_SLACK)


def fewest_crawl_units(
    ws: Workspace,
    waypoints_in_world: np.ndarray,
    start_heading: float,
    tolerance_m: float,
    four_foot_units: float = FOUR_FOOT_UNITS,
) -> float:
    """A lower bound [units] on the duration of the continuous crawl's plan through
    ``waypoints_in_world`` (K, 2) [m] from the start pose (nominal CoG at the origin, heading
    ``start_heading`` [rad]) with path tolerance ``tolerance_m`` [m] (module docstring); 0
    where none is computed."""

    return crawl_walk_bound(
        ws, waypoints_in_world, start_heading, tolerance_m, four_foot_units
    ).total()


def crawl_walk_bound(
    ws: Workspace,
    waypoints_in_world: np.ndarray,
    start_heading: float,
    tolerance_m: float,
    four_foot_units: float = FOUR_FOOT_UNITS,
) -> WalkBound:
    """The :class:`~planner.gaits.creep_duration.WalkBound` of the crawl (module
    docstring): d / v(u) units a segment."""

    def segment_units(d: float, r: float) -> float:
        return d / advance_per_unit_m(r, four_foot_units)

    return WalkBound(ws, waypoints_in_world, start_heading, tolerance_m, segment_units)
