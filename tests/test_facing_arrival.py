"""Facing the path lands the CoG as walked on every waypoint (planner/gaits/facing.py): its
folded shifts leave the body off the nominal CoG when a waypoint is reached, and the next
base move (here a spin's rotation) brings it back there; E_n (eq 6.1) takes where the CoG
as walked comes nearest each waypoint before the next one is reached.

The case is the random corpus's case 4 of 30 (benchmarks/bench_corpus.py, seed 20261202):
mantis at h 0.2221 m, where its workspace has no lateral stride and the plan faces the path.
E_n was taken at the arrival, 73.8 mm off waypoint 0 (E_n 18.5 mm > 10 mm), although the
body stands on it 6 units later; the plan walks in MuJoCo."""

from __future__ import annotations

import numpy as np

from planner import plan_path

WAYPOINTS = np.array(
    [
        [0.37181768352253725, -0.2986675342467766],
        [1.096000726183181, -0.4015058952464602],
        [0.5534281219004987, -0.5299804931407317],
        [0.29379234923339365, -0.8575772930028346],
    ]
)


def test_facing_the_path_is_measured_where_the_cog_reaches_each_waypoint(mantis) -> None:
    robot = mantis
    plan = plan_path(robot, WAYPOINTS, 0.2221, start_heading=-0.6041946406018477)
    assert plan.gait == "facing"
    trajectory = plan.trajectory
    t = trajectory.time_units
    base = trajectory.position_base_in_world[:, :2]
    # independently of the planner's bookkeeping: the closest the sampled CoG comes to each
    # waypoint before the next waypoint's arrival time
    ends = [*plan.time_reached_units[1:], t[-1]]
    for k, (waypoint, end) in enumerate(zip(WAYPOINTS, ends)):
        window = t <= end + 1e-9
        nearest = float(np.min(np.hypot(*(base[window] - waypoint).T)))
        assert nearest <= plan.tolerance, (k, nearest)
        walked = plan.position_walked_in_world[k]
        assert abs(float(np.hypot(*(walked - waypoint))) - nearest) < 1e-12
    errors = np.hypot(*(plan.position_walked_in_world - WAYPOINTS).T)
    assert errors.mean() <= plan.tolerance
    # the arrival itself stood 74 mm off waypoint 0: the shift folded into its last step
    arrival = int(np.searchsorted(t, 12.0))
    assert np.hypot(*(base[arrival] - WAYPOINTS[0])) > 0.05
