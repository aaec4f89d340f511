"""Torques along real plans (issue 4): the thesis straight path at h = 0.4 m, both presets.

RNEA (Pinocchio, hip fixed) against the closed-form Lagrange model; support reactions that sum
to the body weight with zero moment about the CoG at every sample; a foot in the air carries
nothing; the free-flyer model in equilibrium at stance samples (with the whole-robot load).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner import plan_path
from planner.trajectory.torques import position_foot_in_base, trajectory_torques
from silo4kin.joint_torques import free_flyer_q_index, joint_torques
from silo4kin.robot import STANDARD_GRAVITY

STRAIGHT = np.array([[0.0, 1.0], [1.0, 1.0], [0.0, 2.0], [0.0, 3.0]])
#: RNEA vs closed form [N m]: two exact evaluations of the same model, torques O(10 N m).
LAGRANGE_TOLERANCE = 1e-10
#: Force and moment balance of the reactions [N], [N m]: a 3x3 / 4x3 solve of O(300 N).
BALANCE_TOLERANCE = 1e-9


@pytest.fixture(scope="module", params=["thesis", "default"])
def plan_and_torques(request, silo4):
    plan = plan_path(silo4, STRAIGHT, 0.4, workspace=request.param, samples_per_unit=20)
    return plan, trajectory_torques(silo4, plan.trajectory, load="body")


def test_rnea_equals_closed_form_lagrange_along_the_plan(silo4, plan_and_torques):
    plan, jt = plan_and_torques
    tr = plan.trajectory
    lagrange = trajectory_torques(silo4, tr, load="body", method="closed_form")
    assert np.abs(jt.motion - lagrange.motion).max() < LAGRANGE_TOLERANCE
    assert np.abs(jt.motion).max() > 0.5  # the legs do move


def test_reactions_carry_the_body_with_zero_moment(silo4, plan_and_torques):
    """With load="body" (the thesis's model): sum F = m_b g and sum F (x, y) = 0 about the
    CoG at every sample; swing feet carry 0."""
    plan, jt = plan_and_torques
    tr = plan.trajectory
    weight = silo4.body_mass * STANDARD_GRAVITY
    feet = position_foot_in_base(tr)
    assert np.abs(jt.reactions.sum(axis=1) - weight).max() < BALANCE_TOLERANCE
    moment = np.einsum("nk,nkd->nd", jt.reactions, feet[..., :2])
    assert np.abs(moment).max() < BALANCE_TOLERANCE
    assert np.all(jt.reactions[~tr.contact] == 0.0)
    assert np.all(jt.reactions >= -1e-9) and not np.any(jt.unloadable)


def test_support_dominates_as_in_figs_a2_a3(plan_and_torques):
    """Thesis App. A.2: the torque to carry the body is larger than the torque to move the
    legs (hip pitch and knee)."""
    _, jt = plan_and_torques
    for k in (1, 2):  # hip pitch, knee
        assert np.abs(jt.support[:, k::3]).max() > 3 * np.abs(jt.motion[:, k::3]).max()


def test_free_flyer_equilibrium_in_the_plans_postures(silo4, plan_and_torques):
    """Holding each planned posture (q' = q'' = 0) with the whole-robot load: Pinocchio's
    free-flyer rnea with our foot reactions as external forces gives a zero base wrench and
    exactly our joint torques."""
    plan, _ = plan_and_torques
    tr = plan.trajectory
    pick = np.arange(0, len(tr), 97)
    zeros = np.zeros((pick.size, 12))
    jt = joint_torques(silo4, tr.q[pick], zeros, zeros, tr.contact[pick], load="total")
    model = silo4.model_free_flyer
    data = model.createData()
    idx = free_flyer_q_index(silo4)  # our joint k sits at q[idx[k]], v[idx[k] - 1]
    for n, i in enumerate(pick):
        q = np.zeros(model.nq)
        q[6] = 1.0  # identity base quaternion (x, y, z, w)
        q[idx] = tr.q[i]
        pin.framesForwardKinematics(model, data, q)
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        for k, leg in enumerate(silo4.legs):
            jid = model.getJointId(leg.joint_names[2])
            oMi = data.oMi[jid]
            force = oMi.rotation.T @ np.array([0.0, 0.0, jt.reactions[n, k]])
            lever = oMi.rotation.T @ (
                data.oMf[model.getFrameId(leg.foot_frame)].translation - oMi.translation
            )
            fext[jid] = pin.Force(force, np.cross(lever, force))
        tau = pin.rnea(model, data, q, np.zeros(model.nv), np.zeros(model.nv), fext)
        #: equilibrium residual [N, N m]: solves of O(400 N) forces, rounding only
        assert np.abs(tau[:6]).max() < 1e-8
        assert np.abs(tau[idx - 1] - jt.total[n]).max() < 1e-8


def _free_flyer_base_wrench(robot, tr, reactions, pick, with_motion: bool) -> np.ndarray:
    """Base wrench [N, N m] of Pinocchio's free-flyer rnea with our reactions as external
    forces at the feet, base at rest in the level base frame, shape (len(pick), 6); joint
    rates and accelerations from the plan when ``with_motion``."""
    model = robot.model_free_flyer
    data = model.createData()
    idx = free_flyer_q_index(robot)
    out = []
    for n, i in enumerate(pick):
        q = np.zeros(model.nq)
        q[6] = 1.0
        q[idx] = tr.q[i]
        v, a = np.zeros(model.nv), np.zeros(model.nv)
        if with_motion:
            v[idx - 1], a[idx - 1] = tr.qd[i], tr.qdd[i]
        pin.framesForwardKinematics(model, data, q)
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        for k, leg in enumerate(robot.legs):
            jid = model.getJointId(leg.joint_names[2])
            oMi = data.oMi[jid]
            force = oMi.rotation.T @ np.array([0.0, 0.0, reactions[n, k]])
            lever = oMi.rotation.T @ (
                data.oMf[model.getFrameId(leg.foot_frame)].translation - oMi.translation
            )
            fext[jid] = pin.Force(force, np.cross(lever, force))
        out.append(pin.rnea(model, data, q, v, a, fext)[:6].copy())
    return np.array(out)


def test_default_load_balances_the_whole_robot_along_the_default_plan(silo4):
    """The default torques (load "total") carry the whole robot: in every 7th posture of the
    default plan held still, Pinocchio's free-flyer rnea with our reactions as external
    forces leaves a base wrench < 1e-8 (rounding), while the thesis's body load leaves the
    legs' weight (122 N). In motion the reactions are 3-D and balance the floating robot
    with its accelerations (tests/test_floating_torques.py)."""
    from planner.trajectory.limits import at_rest

    plan = plan_path(silo4, STRAIGHT, 0.4, samples_per_unit=20)
    tr = plan.trajectory
    pick = np.arange(0, len(tr), 7)
    jt = trajectory_torques(silo4, at_rest(tr))
    static = _free_flyer_base_wrench(silo4, tr, jt.reactions[pick], pick, with_motion=False)
    print(f"free-flyer base wrench, full load: {np.abs(static).max():.2g}")
    assert np.abs(static).max() < 1e-8
    body = trajectory_torques(silo4, tr, load="body")
    legs_weight = (silo4.total_mass - silo4.body_mass) * STANDARD_GRAVITY
    residual = _free_flyer_base_wrench(silo4, tr, body.reactions[pick], pick, False)
    np.testing.assert_allclose(np.abs(residual[:, 2]), legs_weight, rtol=1e-9)


def test_torques_of_the_same_trajectory_are_computed_once(silo4) -> None:
    """trajectory_torques keeps its last result for the same trajectory object, robot and
    options (gait "auto" checks a crawl's limits, the outputs then ask again): the same
    arrays, read-only; other options or another trajectory are computed afresh."""
    from dataclasses import replace

    from planner import plan_path
    from planner.trajectory.torques import trajectory_torques

    tr = plan_path(silo4, [[0.0, 0.5]], 0.4, samples_per_unit=10).trajectory
    first = trajectory_torques(silo4, tr, load="total")
    assert trajectory_torques(silo4, tr, load="total") is first
    assert not first.total.flags.writeable
    body = trajectory_torques(silo4, tr, load="body")
    assert body is not first and not np.array_equal(body.total, first.total)
    copy = replace(tr)
    again = trajectory_torques(silo4, copy, load="total")
    assert again is not first and np.array_equal(again.total, first.total)
