"""A lift's stability shift keeps the stance legs within their effort budget
(planner/gaits/load_caps.py, StepBuilder._capped; issue 21).

Before: the shift put the CoM at the nearest point with the margin, near the diagonal of two
stance feet. SILO4 at h 0.2203 m (the random corpus's case 0): the omnidirectional gait's
first shift moved the CoG 0.105 m, then RF swung with RH a half stride behind its centre,
RH_hip_pitch 59.3 N m standing still, 1.16 x its budget (0.85 x 60 N m): every gait refused."""

from __future__ import annotations

import numpy as np
import pytest

from planner.gaits.load_caps import share_bounds
from planner.presets import TORQUE_HEADROOM


def test_share_bounds_are_the_reactions_each_joint_allows():
    """|G - F J_z| <= b per joint: a joint with J_z = -0.3 m and G = 2 N m allows
    F <= (b - G) / 0.3; one with J_z = 0 only asks |G| <= b."""
    lo, hi = share_bounds(np.array([[2.0, 1.0]]), np.array([[-0.3, 0.0]]), np.array([50.0, 5.0]))
    assert lo[0] == 0.0
    assert hi[0] == pytest.approx(48.0 / 0.3)
    lo, hi = share_bounds(np.array([[0.0, 9.0]]), np.array([[-0.3, 0.0]]), np.array([50.0, 5.0]))
    assert lo[0] > hi[0]  # the second joint breaks its budget at any load


#: The random corpus's SILO4 cases refused before (benchmarks/bench_corpus.py, seed 20261202,
#: robots silo4 mantis phasmid): (height [m], start heading [rad], waypoints [m]).
SILO4_CASES = [
    (0.2203, -0.2618, [[-0.18, 0.41], [0.07, 0.14]]),
    (0.3420, -1.9373, [[0.76, -0.01], [1.35, 0.67], [2.08, 0.21], [2.46, 0.44]]),
]


@pytest.mark.parametrize("height, heading, waypoints", SILO4_CASES)
def test_the_creeping_gaits_shifts_keep_the_budget(silo4, height, heading, waypoints):
    """The omnidirectional creeping gait (gait "creep") on these paths: every sample's
    static torque (the plan at rest, the whole robot carried, the load passed over the
    transfer time: the run's check) within 0.85 x URDF effort, and near it (the caps bind)."""
    from planner import plan_path
    from planner.trajectory.limits import at_rest, urdf_limits
    from planner.trajectory.torques import trajectory_torques

    plan = plan_path(silo4, np.array(waypoints), height, start_heading=heading, gait="creep")
    tau = trajectory_torques(silo4, at_rest(plan.trajectory), load="total").total
    _, effort = urdf_limits(silo4)
    ratio = np.abs(tau) / (TORQUE_HEADROOM * effort)
    assert 0.9 < ratio.max() <= 1.0
