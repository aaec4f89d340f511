"""Walking straight past waypoints within the tolerance: which waypoint the follower walks to
next, and where the CoG as walked came nearest a waypoint it passed (its E_n, eq 6.1)."""

from __future__ import annotations

import numpy as np

from planner.gaits.builder import StepBuilder

#: Fraction of the tolerance within which a straight walk must pass a waypoint for the
#: follower to walk past it to a later one (the rest is room for stability shifts).
PASS_FRACTION = 0.5


def line_of_sight(wp: np.ndarray, k: int, start_xy: np.ndarray, tolerance_m: float) -> int:
    """The last waypoint j >= k such that the straight line from ``start_xy`` (2,) [m] to
    wp[j] passes within PASS_FRACTION x tolerance of every waypoint k..j-1 (K, 2) [m], in
    order: the follower walks straight to wp[j] and passes the others (their E_n is taken
    where the CoG as walked comes nearest, planner/path/plan_path.py)."""
    best = k
    for j in range(k + 1, len(wp)):
        a, d = np.asarray(start_xy, float), wp[j] - np.asarray(start_xy, float)
        length2 = float(d @ d)
        if length2 <= 1e-18:
            break
        s = np.clip(((wp[k:j] - a) @ d) / length2, 0.0, 1.0)
        if not (
            np.all(np.diff(s) >= 0)
            and np.all(np.hypot(*(a + s[:, None] * d - wp[k:j]).T) <= PASS_FRACTION * tolerance_m)
        ):
            break
        best = j
    return best


def nearest_on_segment(point_xy: np.ndarray, t0: float, t1: float, b: StepBuilder) -> np.ndarray:
    """The point of the nominal CoG path between times t0 and t1 [units] (body steps of
    ``b``) nearest to ``point_xy`` (2,) [m]."""
    ends = [s.position_base_start_in_world[:2] for s in b.steps if t0 <= s.t_start < t1]
    ends.append(b.nominal_base[:2])
    pts = np.array(ends)
    return pts[int(np.argmin(np.hypot(*(pts - np.asarray(point_xy, float)).T)))].copy()
