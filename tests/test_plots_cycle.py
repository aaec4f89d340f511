"""Figs 5.2-5.7 (cycle_cartesian): the numbers behind the figure against independent ones.

The figure differentiates sampled positions; here the foot velocity comes from the closed-form
Jacobian, J(q) q' (eq 3.26-3.35), and the body's from the sine body trajectory's properties
(eq 5.13-5.15: at rest at both ends, moves lambda/2 along its heading).
"""

from __future__ import annotations

import numpy as np
import pytest

from planner.path.plan_path import plan_path, robot_in_body_com_frame
from silo4kin import Robot
from silo4kin.kinematics import jacobian
from viz.plots.cycle import cycle_series

#: Finite differences of 100 samples per unit against J q' [m/s]: central differences of a
#: sine of period ~1 s have relative error ~(pi h)^2 / 6 ~ 2e-4; the swing peaks at ~0.5 m/s.
VELOCITY_TOLERANCE_M_S = 1e-3


@pytest.fixture(scope="module")
def plan(silo4: Robot):  # noqa: ANN201
    return plan_path(silo4, np.array([[0.0, 1.0]]), 0.4, face_path=True)  # Figs 5.2-5.7


def test_foot_velocity_matches_the_jacobian(silo4: Robot, plan) -> None:  # noqa: ANN001
    """Left column: the foot's velocity in B equals J(q) q' of the closed form during the
    transfer (the body stands still in a creep transfer, so B is fixed in W)."""
    foot, _ = cycle_series(plan.trajectory)
    assert foot is not None and "LF" in foot.label
    traj = plan.trajectory
    leg = robot_in_body_com_frame(silo4).legs[0]
    k = foot.samples
    v_base = np.einsum("nij,nj->ni", jacobian(leg, traj.q[k, 0:3]), traj.qd[k, 0:3])
    inner = slice(1, -1)  # np.gradient's one-sided ends are second order too, but coarser
    np.testing.assert_allclose(foot.velocity[inner], v_base[inner], atol=VELOCITY_TOLERANCE_M_S)
    assert np.max(foot.position[:, 2]) > 0.05  # the foot lifts
    np.testing.assert_allclose(foot.position[[0, -1], 2], 0.0, atol=1e-9)  # and lands


def test_body_phase_moves_half_a_stride_from_rest_to_rest(plan) -> None:  # noqa: ANN001
    """Right column: the CoG starts and ends at rest and advances lambda/2 along x of B."""
    _, body = cycle_series(plan.trajectory)
    assert body is not None
    assert abs(body.position[-1, 0] - plan.workspace.stride_m / 2) < 1e-6
    np.testing.assert_allclose(body.position[:, 1:], 0.0, atol=1e-9)
    peak = np.max(np.abs(body.velocity[:, 0]))
    assert np.all(np.abs(body.velocity[[0, -1], 0]) < 0.02 * peak)
