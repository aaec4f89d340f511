"""Closed-form kinematics (thesis Ch. 3) against Pinocchio and against finite differences.

Every comparison runs per leg on the 1000 seeded random configurations of conftest.py.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from silo4kin import UnreachableTargetError
from silo4kin import kinematics as K
from silo4kin.check import (
    FK_TOLERANCE,
    IK_TOLERANCE,
    IK_UNIQUE_MIN_KNEE,
    IK_UNIQUE_MIN_RADIAL,
    JACOBIAN_TOLERANCE,
    JDOT_TOLERANCE,
)

LEGS = range(4)
#: Central differences with step 1e-6 rad: truncation O(h^2 * |p'''|) ~ 1e-12 m/rad,
#: rounding O(eps * |p| / h) ~ 1e-10; 1e-8 bounds both with margin.
FD_STEP = 1e-6
FD_TOLERANCE = 1e-8


def _columns(k: int) -> slice:
    return slice(3 * k, 3 * k + 3)


@pytest.mark.parametrize("k", LEGS)
def test_fk_equals_pinocchio_foot_position(silo4, pin_reference, k):
    """eq 3.5 with theta_b mapped to REP-103 gives Pinocchio's foot frame to 1e-12 m."""
    leg = silo4.legs[k]
    p = K.forward_kinematics(leg, pin_reference.q[:, _columns(k)])
    assert np.abs(p - pin_reference.foot[:, k]).max() < FK_TOLERANCE


@pytest.mark.parametrize("k", LEGS)
def test_fk_matches_printed_eq_3_5_in_thesis_axes(silo4, pin_reference, k):
    """Eq 3.5 as printed (thesis x right, y forward, thesis theta_b), mapped (yt, -xt)."""
    leg = silo4.legs[k]
    theta_b_thesis = leg.theta_b + np.pi / 2
    Lb = np.hypot(*leg.position_hip_in_base[:2])
    Lz = -leg.hip_height
    t1, t2, t3 = pin_reference.q[:, _columns(k)].T
    reach = leg.L1 + leg.L2 * np.cos(t2) + leg.L3 * np.cos(t2 + t3)
    x_t = Lb * np.cos(theta_b_thesis) + np.cos(t1 + theta_b_thesis) * reach
    y_t = Lb * np.sin(theta_b_thesis) + np.sin(t1 + theta_b_thesis) * reach
    z = leg.L2 * np.sin(t2) + leg.L3 * np.sin(t2 + t3) - Lz
    p_base = np.stack([y_t, -x_t, z], axis=1)
    assert np.abs(p_base - pin_reference.foot[:, k]).max() < FK_TOLERANCE


@pytest.mark.parametrize("k", LEGS)
def test_jacobian_equals_pinocchio(silo4, pin_reference, k):
    """eq 3.26-3.35 == getFrameJacobian(LOCAL_WORLD_ALIGNED), linear rows."""
    J = K.jacobian(silo4.legs[k], pin_reference.q[:, _columns(k)])
    assert np.abs(J - pin_reference.jacobian[:, k]).max() < JACOBIAN_TOLERANCE


@pytest.mark.parametrize("k", LEGS)
def test_jacobian_equals_finite_differences_of_fk(silo4, pin_reference, k):
    leg = silo4.legs[k]
    q = pin_reference.q[:200, _columns(k)]
    J = K.jacobian(leg, q)
    for j in range(3):
        dq = np.zeros(3)
        dq[j] = FD_STEP
        fd = (K.forward_kinematics(leg, q + dq) - K.forward_kinematics(leg, q - dq)) / (2 * FD_STEP)
        assert np.abs(J[:, :, j] - fd).max() < FD_TOLERANCE


@pytest.mark.parametrize("k", LEGS)
def test_jdot_qd_equals_pinocchio_classical_acceleration(silo4, pin_reference, k):
    """eq 3.37-3.45: dJ q' == foot classical acceleration at q'' = 0."""
    leg = silo4.legs[k]
    q, v = pin_reference.q[:, _columns(k)], pin_reference.v[:, _columns(k)]
    jdqd = np.einsum("nij,nj->ni", K.jacobian_derivative(leg, q, v), v)
    assert np.abs(jdqd - pin_reference.jdot_qd[:, k]).max() < JDOT_TOLERANCE


@pytest.mark.parametrize("k", LEGS)
def test_jdot_equals_finite_difference_of_j_along_qd(silo4, pin_reference, k):
    """dJ/dt = d/ds J(q + s q') at s = 0, entry by entry."""
    leg = silo4.legs[k]
    q, v = pin_reference.q[:200, _columns(k)], pin_reference.v[:200, _columns(k)]
    fd = (K.jacobian(leg, q + FD_STEP * v) - K.jacobian(leg, q - FD_STEP * v)) / (2 * FD_STEP)
    assert np.abs(K.jacobian_derivative(leg, q, v) - fd).max() < FD_TOLERANCE


@pytest.mark.parametrize("k", LEGS)
def test_determinant_is_eq_3_46_and_det_of_j(silo4, pin_reference, k):
    leg = silo4.legs[k]
    q = pin_reference.q[:, _columns(k)]
    det = K.jacobian_determinant(leg, q)
    assert np.abs(det - np.linalg.det(pin_reference.jacobian[:, k])).max() < JACOBIAN_TOLERANCE


def test_determinant_vanishes_at_the_stretched_knee(silo4):
    """Singularity of eq 3.46: theta3 = 0 (leg stretched) and rho = 0."""
    leg = silo4.legs[0]
    assert abs(K.jacobian_determinant(leg, np.array([0.3, -0.4, 0.0]))) < 1e-15
    d = K.singularity_distance(leg, np.array([[0.3, -0.4, 0.0], [0.0, 0.0, -np.pi / 2]]))
    assert d.knee_rad[0] == 0.0 and d.knee_rad[1] == pytest.approx(np.pi / 2)
    assert d.radial_m[1] == pytest.approx(leg.L1 + leg.L2)


@pytest.mark.parametrize("k", LEGS)
def test_ik_recovers_the_pinocchio_configuration(silo4, pin_reference, k):
    """Knee-down IK (3.10-3.24 corrected) of Pinocchio's foot returns the sampled q
    wherever that solution is unique; elsewhere FK(IK(p)) = p."""
    leg = silo4.legs[k]
    q = pin_reference.q[:, _columns(k)]
    p = pin_reference.foot[:, k]
    q_ik = K.inverse_kinematics(leg, p)
    d = K.singularity_distance(leg, q)
    unique = (d.knee_rad > IK_UNIQUE_MIN_KNEE) & (d.radial_m > IK_UNIQUE_MIN_RADIAL)
    assert unique.sum() > 500
    assert np.abs(q_ik - q)[unique].max() < IK_TOLERANCE
    assert np.abs(K.forward_kinematics(leg, q_ik) - p).max() < FK_TOLERANCE
    assert np.all(q_ik[:, 2] <= 0.0)  # knee-down


def test_ik_single_target_and_theta1_wrapping(silo4):
    """A rear leg reaching backwards keeps theta1 in (-pi, pi] (eq 3.10 unwrapped fails)."""
    for leg in silo4.legs:
        q = np.array([0.7, -0.3, -1.2])
        q_ik = K.inverse_kinematics(leg, K.forward_kinematics(leg, q))
        assert q_ik.shape == (3,)
        assert np.abs(q_ik - q).max() < IK_TOLERANCE


def test_unreachable_target_names_the_target_and_the_reach(silo4):
    leg = silo4.legs[1]
    targets = np.array([[0.3, -0.3, -0.4], [1.5, -1.5, -0.4]])
    with pytest.raises(UnreachableTargetError) as err:
        K.inverse_kinematics(leg, targets)
    message = str(err.value)
    assert "RF" in message and "1.5" in message and "0.4800" in message and "sample 1" in message
    assert err.value.reach == pytest.approx((0.0, 0.48))
    res = K.inverse_kinematics_masked(leg, targets)
    assert res.reachable.tolist() == [True, False]
    assert np.all(np.isnan(res.q[1])) and np.all(np.isfinite(res.q[0]))


@pytest.mark.parametrize("k", LEGS)
def test_velocity_and_acceleration_inversions(silo4, pin_reference, k):
    """q' = J^-1 p' and q'' = J^-1 (p'' - dJ q') invert eq 3.25 and 3.36."""
    leg = silo4.legs[k]
    sl = _columns(k)
    q, v, a = pin_reference.q[:, sl], pin_reference.v[:, sl], pin_reference.a[:, sl]
    d = K.singularity_distance(leg, q)
    ok = (d.knee_rad > 0.05) & (np.abs(d.radial_m) > 0.05)
    q, v, a = q[ok], v[ok], a[ok]
    J = K.jacobian(leg, q)
    pd = np.einsum("nij,nj->ni", J, v)
    pdd = np.einsum("nij,nj->ni", J, a) + np.einsum(
        "nij,nj->ni", K.jacobian_derivative(leg, q, v), v
    )
    #: conditioning |J^-1| <= ~1 / (0.05 * 0.05) on these samples: 1e-10 is safe.
    assert np.abs(K.joint_velocity(leg, q, pd) - v).max() < 1e-10
    assert np.abs(K.joint_acceleration(leg, q, v, pdd) - a).max() < 1e-10


def test_a_perturbed_link_length_makes_the_cross_check_fail(silo4, pin_reference):
    """The check can fail: 0.1 mm on L2 of one leg is caught by FK, J and IK."""
    leg = dataclasses.replace(silo4.legs[1], L2=silo4.legs[1].L2 + 1e-4)
    q = pin_reference.q[:, _columns(1)]
    assert np.abs(K.forward_kinematics(leg, q) - pin_reference.foot[:, 1]).max() > 1e-5
    assert np.abs(K.jacobian(leg, q) - pin_reference.jacobian[:, 1]).max() > 1e-5


@pytest.mark.parametrize("k", LEGS)
def test_joint_motion_inverts_pinocchio_foot_motion(silo4, pin_reference, k):
    """The fused IK + rates used by the planner (joint_motion) recovers q, q', q'' from
    Pinocchio's foot position, velocity J q' and acceleration J q'' + dJ q', wherever the
    knee-down solution is unique and the Jacobian well conditioned."""
    leg = silo4.legs[k]
    sl = _columns(k)
    q, v, a = pin_reference.q[:, sl], pin_reference.v[:, sl], pin_reference.a[:, sl]
    J = pin_reference.jacobian[:, k]
    p = pin_reference.foot[:, k]
    pd = np.einsum("nij,nj->ni", J, v)
    pdd = np.einsum("nij,nj->ni", J, a) + pin_reference.jdot_qd[:, k]
    d = K.singularity_distance(leg, q)
    ok = (d.knee_rad > 0.05) & (d.radial_m > 0.05)
    got = K.joint_motion(leg, p, pd, pdd)
    assert got.reachable.all()
    #: |J^-1| <= ~1 / (0.05 * 0.05) rad/m on these samples, inputs exact to ~1e-15: 1e-10.
    for mine, ref in ((got.q, q), (got.qd, v), (got.qdd, a)):
        assert np.abs(mine - ref)[ok].max() < 1e-10


def test_joint_motion_unreachable_rows_are_nan(silo4):
    """A target beyond reach gives NaN q, q', q'' and reachable False; other rows unaffected."""
    leg = silo4.legs[0]
    p = np.array(
        [
            leg.position_hip_in_base + [5.0, 0.0, 0.0],
            K.forward_kinematics(leg, 0.5 * (leg.q_lower + leg.q_upper)),
        ]
    )
    got = K.joint_motion(leg, p, np.zeros((2, 3)), np.zeros((2, 3)))
    assert got.reachable.tolist() == [False, True]
    assert np.isnan(got.q[0]).all() and np.isnan(got.qd[0]).all() and np.isnan(got.qdd[0]).all()
    assert np.isfinite(got.q[1]).all() and np.isfinite(got.qdd[1]).all()
