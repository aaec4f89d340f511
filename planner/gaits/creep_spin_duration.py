"""The fewest time units the gaits that creep in half cycles of λ/2 and spin to turn can
take on a request's waypoints, found without building a step: facing the path
(planner/gaits/facing.py FacingPath) and the creeping and spinning gait of thesis §5.5
(planner/gaits/thesis_walk.py CreepSpin, "plain" and "thesis").

Both walk the waypoints in order, from the nominal CoG at the origin, and reach each one in
creeping half cycles (creep_spin.creep_half_cycle: two transfers of at least TRANSFER_UNITS,
StepBuilder.transfer's swing pace only lengthens them, and a body phase of BODY_UNITS, a
fold keeps its time): at least HALF_CYCLE_UNITS = 4 units each. Spins, transitions and
shifts only add time and do not move the nominal CoG (a spin turns about it). So

- FacingPath: a waypoint more than the tolerance from the nominal CoG is walked to in
  ceil(d / (λ/2)) half cycles (the last one shortened: the nominal CoG lands on it); one
  within the tolerance is passed standing. The walks through the waypoints are followed
  with both choices where the distance is within DECISION_SLACK_M of the tolerance.
- CreepSpin: n = round(d / (λ/2)) half cycles (2 round(d / λ) where the workspace walks
  whole cycles), none for a waypoint within the tolerance of the base's axis ahead. The
  nominal CoG then stands within E = max(hypot(λ/4 + tol/2, tol), sqrt(2) tol) of the
  waypoint (a walk after a spin ends on the line to it, at most λ/4 short or past; one
  along the axis, the waypoint within tol to the side, walks round(d / (λ/2)) half cycles
  of the distance d, which exceeds the distance ahead by at most tol/2; a pass leaves it
  within the tolerance along both axes; λ/2 for whole cycles), so
  with D the distance between consecutive waypoints (the first from the origin, E = 0),
  d >= D - E, and round(x) >= ceil(x - 1/2) gives n >= ceil((D - E) / (λ/2) - 1/2), or 0
  when D - E is within sqrt(2) tol (it may stand).
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np

from planner.gaits.steps import BODY_UNITS, TRANSFER_UNITS
from planner.workspace.layout import Workspace

#: Least duration of one creeping half cycle of these gaits [units] (module docstring).
HALF_CYCLE_UNITS = 2.0 * TRANSFER_UNITS + BODY_UNITS
#: Slack on every distance compared with a threshold or divided into half cycles [m]: the
#: float error of the nominal CoG's landing on a waypoint.
DECISION_SLACK_M = 1e-7
#: Waypoints beyond which no bound is computed (0): the facing bound's search doubles where
#: many waypoints lie within the tolerance of each other.
MAX_WAYPOINTS = 200


def fewest_facing_units(ws: Workspace, waypoints_in_world: np.ndarray, tolerance_m: float) -> float:
    """A lower bound [units] on the duration of FacingPath's plan through
    ``waypoints_in_world`` (K, 2) [m] with path tolerance ``tolerance_m`` [m] (module
    docstring); 0 where none is computed."""
    wp = np.asarray(waypoints_in_world, dtype=float)
    half = 0.5 * ws.stride_m
    if len(wp) == 0 or len(wp) > MAX_WAYPOINTS or not half > 0.0:
        return 0.0
    points = np.vstack([wp, np.zeros((1, 2))])  # index -1: the start (the origin)
    n = len(wp)

    @cache
    def least(k: int, at: int) -> float:
        """Least units from waypoint ``k`` on, the nominal CoG on point ``at``."""
        if k == n:
            return 0.0
        dist = float(np.hypot(*(points[k] - points[at])))
        best = math.inf
        if dist > tolerance_m - DECISION_SLACK_M:  # it may walk to waypoint k
            half_cycles = max(math.ceil((dist - DECISION_SLACK_M) / half - 1e-6), 0)
            best = min(best, HALF_CYCLE_UNITS * half_cycles + least(k + 1, k))
        if dist <= tolerance_m + DECISION_SLACK_M:  # it may stand (k within tolerance)
            best = min(best, least(k + 1, at))
        return best

    bound = least(0, -1)
    return 0.0 if not math.isfinite(bound) else bound


def fewest_creep_spin_units(
    ws: Workspace, waypoints_in_world: np.ndarray, tolerance_m: float
) -> float:
    """A lower bound [units] on the duration of CreepSpin's plan through
    ``waypoints_in_world`` (K, 2) [m] with path tolerance ``tolerance_m`` [m] (module
    docstring); 0 where none is computed."""
    wp = np.asarray(waypoints_in_world, dtype=float)
    lam = ws.stride_m
    if len(wp) == 0 or not lam > 0.0:
        return 0.0
    per = 0.5 * lam if ws.half_cycles else lam  # the length one count of round() walks
    cycles = 1 if ws.half_cycles else 2  # half cycles per count
    error_m = max(
        math.hypot(0.5 * per + 0.5 * tolerance_m, tolerance_m), math.sqrt(2.0) * tolerance_m
    )
    error_m += DECISION_SLACK_M
    units, previous, error = 0.0, np.zeros(2), 0.0
    for target in wp:
        d = float(np.hypot(*(target - previous))) - error
        if d > math.sqrt(2.0) * tolerance_m + DECISION_SLACK_M:
            count = max(math.ceil(d / per - 0.5 - 1e-6), 0)
            units += HALF_CYCLE_UNITS * cycles * count
        previous, error = target, error_m
    return units
