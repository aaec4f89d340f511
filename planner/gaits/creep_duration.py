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
from collections.abc import Callable
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

    return creep_walk_bound(ws, waypoints_in_world, start_heading, tolerance_m).total()


def creep_walk_bound(
    ws: Workspace,
    waypoints_in_world: np.ndarray,
    start_heading: float,
    tolerance_m: float,
) -> WalkBound:
    """The :class:`WalkBound` of the creeping gait (module docstring): ceil(d / r) half
    cycles of HALF_CYCLE_UNITS a segment."""

    def segment_units(d: float, r: float) -> float:
        half_cycles = math.ceil(d / (r + STEP_ROUNDING_M) - 1e-6)
        return HALF_CYCLE_UNITS * max(half_cycles, 0)

    return WalkBound(ws, waypoints_in_world, start_heading, tolerance_m, segment_units)


class WalkBound:
    """A lower bound on the time of the walks walk_without_turning may make through
    ``waypoints_in_world`` (K, 2) [m] (the aims of the module docstring), each straight
    segment costing at least ``segment_units(d, r)``: d its length less the arrival slack
    [m], r the ellipse radius along it with its slack [m] (a gait's bound on a segment's
    units, non-decreasing in d): from the start pose (:meth:`total`) and from a nominal CoG
    on its way to a waypoint (:meth:`rest_units`). 0 where none is computed; infinite where
    every walk needs a step and the workspace has no stride along a body axis (no plan)."""

    def __init__(
        self,
        ws: Workspace,
        waypoints_in_world: np.ndarray,
        start_heading: float,
        tolerance_m: float,
        segment_units: Callable[[float, float], float],
    ) -> None:
        self.ws = ws
        self.wp = np.asarray(waypoints_in_world, dtype=float).reshape(-1, 2)
        self.cos_h, self.sin_h = math.cos(start_heading), math.sin(start_heading)
        self.tolerance_m = float(tolerance_m)
        self.segment_units = segment_units
        semi_axes = ellipse_semi_axes(ws)
        #: False: no bound is computed (0)
        self.computed = 0 < len(self.wp) <= MAX_WAYPOINTS
        # no stride along a body axis: ellipse_radius is 0 along every direction and the
        # gaits refuse the first step of any walk (omni_to, Crawl.to: radius < MIN_STEP_M)
        self.no_ellipse = bool(np.any(semi_axes <= 0.0))
        self.largest_m = float(np.max(semi_axes))
        self.points = np.vstack([self.wp, np.zeros((1, 2))])  # index -1: the start (origin)
        self.least = cache(self._least)

    def total(self) -> float:
        """The bound on the whole walk from the start pose [units]."""
        if not self.computed:
            return 0.0
        bound = self.least(0, -1)
        return bound if self.no_ellipse or math.isfinite(bound) else 0.0

    def rest_units(self, nominal_xy: np.ndarray, aim: int) -> float:
        """A lower bound [units] on the rest of the walk with the nominal CoG at
        ``nominal_xy`` (2,) [m] walking straight to waypoint ``aim`` (walk_without_turning's
        segment; it arrives within ARRIVAL_M, and the loop goes on from that waypoint)."""
        if not self.computed:
            return 0.0
        here = np.asarray(nominal_xy, dtype=float)[:2]
        bound = self._walk_units(here, self.points[aim]) + self.least(aim, aim)
        return bound if self.no_ellipse or math.isfinite(bound) else 0.0

    def _walk_units(self, frm: np.ndarray, to: np.ndarray) -> float:
        """Least units of a straight walk from ``frm`` (2,) to ``to`` (2,) [m]."""
        dx, dy = to - frm
        length = math.hypot(dx, dy)
        d = length - 2.0 * ARRIVAL_M
        if d <= 0.0:
            return 0.0
        if self.no_ellipse:
            return math.inf
        if d < SHORT_SEGMENT_M:
            r = self.largest_m
        else:
            cos_h, sin_h = self.cos_h, self.sin_h
            u_in_base = np.array([cos_h * dx + sin_h * dy, -sin_h * dx + cos_h * dy]) / length
            r = ellipse_radius(self.ws, u_in_base) * (1.0 + RADIUS_SLACK)
        return self.segment_units(d, r)

    def _least(self, k: int, at: int) -> float:
        """Least units from the loop's waypoint ``k`` (with nothing aimed beyond it) with the
        nominal CoG on point ``at`` (-1: the start)."""
        points, tolerance_m = self.points, self.tolerance_m
        if k == len(self.wp):
            return 0.0
        best = math.inf
        for aim in _candidate_aims(points, k, at, tolerance_m):
            if aim > k:
                best = min(best, self._walk_units(points[at], points[aim]) + self.least(aim, aim))
                continue
            dist = float(np.hypot(*(points[k] - points[at])))
            if dist > tolerance_m - DECISION_SLACK_M:  # it may walk to waypoint k
                best = min(best, self._walk_units(points[at], points[k]) + self.least(k + 1, k))
            if dist <= tolerance_m + DECISION_SLACK_M:  # it may stay (k within tolerance)
                best = min(best, self.least(k + 1, at))
        return best


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
