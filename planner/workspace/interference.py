"""Leg interference (thesis §3.6): neighbouring legs keep a clearance on every sample.

The thesis notes that the legs' workspaces overlap (Fig 3.4) and that a gait must make sure the
legs do not interfere; its square workspace did that by construction. The default workspace
plans inside the true reachable sets (planner/workspace/reach_insect.py), which overlap, so
every plan is checked instead: on every sample the feet of neighbouring legs (around the body:
LF-RF, RF-RH, RH-LH, LH-LF) stay at least ``clearance_m`` apart in 3-D. That covers footholds
(both feet down) and swing paths (one foot moving past a standing neighbour).
"""

from __future__ import annotations

import numpy as np

from planner.errors import PlanningError
from planner.trajectory.samples import LEGS, Trajectory

#: Neighbouring legs around the body, as indices into LEGS (LF, RF, LH, RH).
NEIGHBOURS: tuple[tuple[int, int], ...] = ((0, 1), (1, 3), (3, 2), (2, 0))
#: Least distance between neighbouring feet [m]: two SILO4 foot spheres (radius 0.025 m,
#: urdf/silo4.urdf.xacro) plus 1 cm.
LEG_CLEARANCE_M = 0.06


def neighbour_distances(trajectory: Trajectory) -> np.ndarray:
    """Distance between the feet of each neighbouring pair (NEIGHBOURS) [m], shape (N, 4)."""
    feet = trajectory.position_foot_in_world
    return np.stack(
        [np.linalg.norm(feet[:, a] - feet[:, b], axis=1) for a, b in NEIGHBOURS], axis=1
    )


def check_interference(
    trajectory: Trajectory,
    clearance_m: float = LEG_CLEARANCE_M,
    steps=None,
    waypoints_in_world: np.ndarray | None = None,
) -> float:
    """The smallest neighbouring-feet distance [m]; raises PlanningError naming the two legs,
    their distance and the time of the first sample closer than ``clearance_m`` [m], and,
    given the plan's ``steps`` (planner/gaits/steps.py Step: ``t_start``, ``waypoint_index``,
    ``label``) and ``waypoints_in_world`` (K, 2) [m], the waypoint and step being walked
    then."""
    d = neighbour_distances(trajectory)
    bad = np.argwhere(d < clearance_m)
    if bad.size:
        i, k = (int(v) for v in bad[0])
        a, b = NEIGHBOURS[k]
        t_units = float(trajectory.time_units[i])
        reason = (
            f"legs {LEGS[a]} and {LEGS[b]} interfere: feet {d[i, k]:.3f} m apart (< clearance "
            f"{clearance_m:.3f} m) at t = {t_units:.2f} units"
        )
        if not steps or waypoints_in_world is None:
            raise PlanningError(reason)
        starts = np.array([step.t_start for step in steps])
        at = int(np.clip(np.searchsorted(starts, t_units, side="right") - 1, 0, len(steps) - 1))
        step = steps[at]
        j = step.waypoint_index
        wp = np.asarray(waypoints_in_world, dtype=float)
        raise PlanningError(
            f"{reason} ({step.label})", j, None if j is None else (float(wp[j, 0]), float(wp[j, 1]))
        )
    return float(d.min()) if d.size else float("inf")
