"""The fewest time units the omnidirectional creeping gait (planner/gaits/omni.py) can take on
a request's waypoints, found without building a step.

Gait "auto" (planner/gaits/combinators.py Fastest) builds the continuous crawl first and then
the creeping gait only until its steps take as long as the crawl's plan (NotFaster). Where
this lower bound already reaches the crawl's time, the creeping gait cannot be the faster one
and is not built at all: the plan is the one building it would give.

Why it is a lower bound. walk_without_turning (planner/gaits/without_turning.py) walks the
nominal CoG in straight segments from where it stands to the waypoint it aims at, and lands on
it (omni_to stops within ARRIVAL_M). In a segment of length d along the unit direction u (base
frame B; the gait never turns) every half cycle

- takes at least HALF_CYCLE_UNITS: two transfers of TRANSFER_UNITS and a body phase of
  OMNI_BODY_UNITS (a stability shift only adds a unit; a refused candidate is rolled back);
- advances the nominal CoG by at most the ellipse radius r(u) (omni._ranked rounds a step to
  1 nm, STEP_ROUNDING_M),

so the segment takes at least ceil(d / r(u)) half cycles. Which waypoints are aimed at
depends on where the nominal CoG stands (waypoint_passing.line_of_sight, the tolerance test),
known to ARRIVAL_M: every aim that a position that close could give is tried
(:func:`_candidate_aims`), and the bound is the least time over those walks.
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np

from planner.gaits.foothold_ellipse import ellipse_radius, ellipse_semi_axes
from planner.gaits.omni import OMNI_BODY_UNITS
from planner.gaits.steps import TRANSFER_UNITS
from planner.gaits.waypoint_passing import PASS_FRACTION
from planner.workspace.layout import Workspace

#: Least duration of one half cycle of the creeping gait [units] (module docstring).
HALF_CYCLE_UNITS = 2.0 * TRANSFER_UNITS + OMNI_BODY_UNITS
#: How far the nominal CoG may stand from a waypoint it arrived at [m] (omni_to's test).
ARRIVAL_M = 1e-9
#: What omni._ranked's rounding of a step to 9 decimals [m] may add to it.
STEP_ROUNDING_M = 5e-10
#: Slack on every distance compared with a threshold here [m]: covers ARRIVAL_M and the
#: rounding of the planner's own comparisons (which this bound must not decide otherwise).
DECISION_SLACK_M = 1e-7
#: Relative slack on the ellipse radius along a segment's direction, which the nominal CoG's
#: ARRIVAL_M error turns by up to 2 ARRIVAL_M / d [rad] (d >= SHORT_SEGMENT_M).
RADIUS_SLACK = 1e-4
#: Segments shorter than this [m] use the ellipse's largest semi-axis (their direction is not
#: known well enough for RADIUS_SLACK).
SHORT_SEGMENT_M = 1e-4
#: Waypoints beyond which no bound is computed (0: the gait is built as before); the search
#: below grows with the cube of their number where many lie on one line.
MAX_WAYPOINTS = 200


def fewest_creep_units(
    ws: Workspace,
    waypoints_in_world: np.ndarray,
    start_heading: float,
    tolerance_m: float,
) -> float:
    """A lower bound [units] on the duration of the creeping gait's plan through
    ``waypoints_in_world`` (K, 2) [m] from the start pose (nominal CoG at the origin, heading
    ``start_heading`` [rad]) with path tolerance ``tolerance_m`` [m] (module docstring); 0
    where none is computed."""
    wp = np.asarray(waypoints_in_world, dtype=float)
    semi_axes = ellipse_semi_axes(ws)
    if len(wp) == 0 or len(wp) > MAX_WAYPOINTS or np.any(semi_axes <= 0.0):
        return 0.0
    largest = float(np.max(semi_axes))
    cos_h, sin_h = math.cos(start_heading), math.sin(start_heading)
    points = np.vstack([wp, np.zeros((1, 2))])  # index -1: the start (the origin)
    n = len(wp)

    def walk_units(frm: int, to: int) -> float:
        """Least units of a straight walk from point ``frm`` to waypoint ``to``."""
        dx, dy = points[to] - points[frm]
        length = math.hypot(dx, dy)
        d = length - 2.0 * ARRIVAL_M
        if d <= 0.0:
            return 0.0
        if d < SHORT_SEGMENT_M:
            r = largest
        else:
            u_in_base = np.array([cos_h * dx + sin_h * dy, -sin_h * dx + cos_h * dy]) / length
            r = ellipse_radius(ws, u_in_base) * (1.0 + RADIUS_SLACK)
        half_cycles = math.ceil(d / (r + STEP_ROUNDING_M) - 1e-6)
        return HALF_CYCLE_UNITS * max(half_cycles, 0)

    @cache
    def least(k: int, at: int) -> float:
        """Least units from the loop's waypoint ``k`` (with nothing aimed beyond it) with the
        nominal CoG on point ``at`` (-1: the start)."""
        if k == n:
            return 0.0
        best = math.inf
        for aim in _candidate_aims(points, k, at, tolerance_m):
            if aim > k:
                best = min(best, walk_units(at, aim) + least(aim, aim))
                continue
            dist = float(np.hypot(*(points[k] - points[at])))
            if dist > tolerance_m - DECISION_SLACK_M:  # it may walk to waypoint k
                best = min(best, walk_units(at, k) + least(k + 1, k))
            if dist <= tolerance_m + DECISION_SLACK_M:  # it may stay (k within tolerance)
                best = min(best, least(k + 1, at))
        return best

    bound = least(0, -1)
    return 0.0 if not math.isfinite(bound) else bound


def _candidate_aims(points: np.ndarray, k: int, at: int, tolerance_m: float) -> range:
    """The waypoints line_of_sight(wp, k, start, tolerance) may return for a start within
    ARRIVAL_M of ``points[at]``: k up to the waypoint before the first j whose line from the
    start surely passes further than PASS_FRACTION x tolerance (+ DECISION_SLACK_M) from one
    of waypoints k..j-1 (line_of_sight stops at its first failing j, and its other tests only
    make it stop sooner)."""
    start = points[at]
    limit = PASS_FRACTION * tolerance_m + DECISION_SLACK_M
    n = len(points) - 1
    for j in range(k + 1, n):
        d = points[j] - start
        length2 = float(d @ d)
        between = points[k:j] - start
        if length2 > 0.0:
            s = np.clip((between @ d) / length2, 0.0, 1.0)
            gap = np.hypot(*(between - s[:, None] * d).T)
        else:
            gap = np.hypot(*between.T)
        if np.any(gap > limit):
            return range(k, j)
    return range(k, n)
