"""Round feet: the ball read from the URDF, and stance feet planned as they roll.

The independent reference is Pinocchio: the ball centre from its forward kinematics of the
planned joints, and the foot link's angular velocity from its frame velocity, integrated by
the same trapezoid (planner/trajectory/rolling_feet.py) over each stance.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner import plan_path
from planner.trajectory.sampling import sample_steps
from silo4kin.foot_contact import POINT_FOOT, foot_ball
from silo4kin.robot import load_robot

#: The rolled-back contact point of a stance is fixed to this [m] (the fixed point converges
#: to 1e-12 m; Pinocchio and the closed form agree to ~1e-13 m).
CONTACT_FIXED_M = 1e-9
#: A go2 stance at h = 0.30 m rolls its ball by ~10 mm; one that rolls < 1 mm is not rolling.
MIN_ROLL_PER_STANCE_M = 1e-3
#: Central differences at 1000 samples per unit (tests/test_planner_invariants.py).
FD_SAMPLES_PER_UNIT = 1000
FD_REL, FD_ABS = 1e-3, 1e-3


@pytest.fixture(scope="module")
def go2_plan(go2):
    return plan_path(go2, np.array([[0.3, 0.0]]), 0.30, start_heading=0.0)


def test_foot_ball_comes_from_the_urdf_collision_geometry(go2, solo12, anymal):
    """go2 and solo12 collide through meshes (their lowest point below the foot frame),
    anymal and a1 through spheres; SILO4's sphere is visual only (a point foot)."""
    ball = foot_ball(go2)
    assert ball.source == "collision mesh" and ball.radius_m == pytest.approx(0.0229, abs=1e-4)
    solo = foot_ball(solo12)
    assert solo.source == "collision mesh" and solo.radius_m == pytest.approx(0.0160, abs=1e-4)
    ball = foot_ball(anymal)
    assert (ball.radius_m, ball.centre_z_in_foot_m) == (0.031, 0.02325)
    assert foot_ball(load_robot("a1")).radius_m == 0.02
    assert foot_ball(load_robot()) == POINT_FOOT
    assert foot_ball(go2, radius_m=0.01).radius_m == 0.01


def _stance_runs(stance: np.ndarray) -> list[slice]:
    edges = np.flatnonzero(np.diff(np.concatenate([[0], stance.astype(int), [0]])))
    return [slice(a, b) for a, b in zip(edges[::2], edges[1::2])]


def test_stance_contact_rolls_back_to_the_touchdown_point_by_pinocchio(go2, go2_plan):
    """Pinocchio FK of the ball centre of the planned joints, minus r ẑ, is the planned
    contact point; minus the rolling integral of Pinocchio's foot angular velocity, it is
    the touchdown point for the whole stance (the ball rolls without slipping)."""
    tr, ball = go2_plan.trajectory, foot_ball(go2)
    model, data = go2.model, go2.model.createData()
    q_pin, v_pin = go2.to_pinocchio_q(tr.q), go2.to_pinocchio_q(tr.qd * tr.unit_time_s)
    root = go2.position_body_com_in_base  # planning frame B = body CoG
    c, s = np.cos(tr.yaw_base_in_world), np.sin(tr.yaw_base_in_world)
    dt = tr.time_units[1] - tr.time_units[0]
    rolled_any = 0
    for j, leg in enumerate(go2.legs):
        fid = model.getFrameId(leg.foot_frame)
        centre_b, omega_b = np.empty((len(tr), 3)), np.empty((len(tr), 3))
        for i in range(len(tr)):
            pin.forwardKinematics(model, data, q_pin[i], v_pin[i])
            placement = pin.updateFramePlacement(model, data, fid)
            centre_b[i] = placement.translation - root
            omega_b[i] = pin.getFrameVelocity(
                model, data, fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
            ).angular
        rot = lambda v: np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1], v[:, 2]], 1)  # noqa: E731
        contact_w = tr.position_base_in_world + rot(centre_b)
        contact_w[:, 2] -= ball.contact_offset_m
        np.testing.assert_allclose(contact_w, tr.position_foot_in_world[:, j], atol=CONTACT_FIXED_M)
        omega_w = rot(omega_b)  # + ψ̇ ẑ of the body, which does not roll the ball
        roll_rate = ball.radius_m * np.stack(
            [omega_w[:, 1], -omega_w[:, 0], np.zeros(len(tr))], axis=1
        )
        for run in _stance_runs(tr.contact[:, j]):
            v = roll_rate[run]
            d = np.vstack([np.zeros(3), np.cumsum(0.5 * (v[1:] + v[:-1]) * dt, axis=0)])
            unrolled = contact_w[run] - d
            assert np.abs(unrolled - unrolled[0]).max() <= CONTACT_FIXED_M
            assert np.abs(contact_w[run, 2]).max() <= CONTACT_FIXED_M  # on the ground
            rolled_any += np.linalg.norm(d[-1, :2]) > MIN_ROLL_PER_STANCE_M
    assert rolled_any >= 4, "the balls should roll by millimetres over the stances"


def test_rolling_plan_rates_match_finite_differences(go2, go2_plan):
    """q̇ and q̈ of a rolling plan equal central differences of q (1000 samples per unit)."""
    steps = go2_plan.steps
    tr = sample_steps(
        _planning(go2),
        steps,
        go2_plan.workspace.swing_height_m,
        FD_SAMPLES_PER_UNIT,
        smooth=go2_plan.gait in ("creep", "crawl"),
    )
    dt = 1.0 / FD_SAMPLES_PER_UNIT
    boundaries = np.array([st.t_start for st in steps] + [steps[-1].t_end])
    interior = np.min(np.abs(tr.time_units[:, None] - boundaries[None]), axis=1) > 1.5 * dt
    inner = interior[1:-1]
    fd_qd = (tr.q[2:] - tr.q[:-2]) / (2 * dt)
    fd_qdd = (tr.qd[2:] - tr.qd[:-2]) / (2 * dt)
    assert np.abs(fd_qd - tr.qd[1:-1])[inner].max() <= FD_REL * np.abs(tr.qd).max() + FD_ABS
    assert np.abs(fd_qdd - tr.qdd[1:-1])[inner].max() <= FD_REL * np.abs(tr.qdd).max() + FD_ABS


def _planning(robot):
    from planner.model import planning_robot

    return planning_robot(robot)


def test_point_foot_keeps_the_stance_frames_still(go2, go2_plan):
    """The same steps sampled as point feet keep every stance foot frame still (the thesis's
    model), so the rolling is what moves the contact points of the ball plan."""
    tr = sample_steps(
        _planning(go2),
        go2_plan.steps,
        go2_plan.workspace.swing_height_m,
        100,
        smooth=go2_plan.gait in ("creep", "crawl"),
        foot=POINT_FOOT,
    )
    for j in range(4):
        both = tr.contact[1:, j] & tr.contact[:-1, j]
        step = np.abs(np.diff(tr.position_foot_in_world[:, j], axis=0)).max(axis=1)
        assert step[both].max() <= CONTACT_FIXED_M
    rolled = go2_plan.trajectory.position_foot_in_world
    both = go2_plan.trajectory.contact[1:] & go2_plan.trajectory.contact[:-1]
    assert np.abs(np.diff(rolled, axis=0)).max(axis=2)[both].max() > 1e-5
