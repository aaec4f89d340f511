"""The fused kernels of the planner's hot loops equal their reference formulation bit for bit
(planner/stability/swing_com.py leg_moments against silo4kin.kinematics.knee_down_dh_angles
and the link moments written out as in silo4kin.com.leg_mass_moment_in_base)."""

from __future__ import annotations

import numpy as np
import pytest

from planner.model import planning_model
from planner.stability.swing_com import leg_moments, rows_of
from silo4kin.kinematics import knee_down_dh_angles
from silo4kin.mammal_constants import MammalConstants
from silo4kin.robot import load_robot


@pytest.fixture(scope="module")
def model():
    return planning_model(load_robot(None))


def _reference_moments(const, leg, position_foot_in_base, horizontal):
    """leg_moments written with the one knee-down IK (θ1 included, NaN rows set on θ)."""
    g = rows_of(const, leg)
    rel = position_foot_in_base - g.hip
    rho = np.hypot(rel[:, 0], rel[:, 1])
    c, s = rel[:, 0] / rho, rel[:, 1] / rho
    theta = knee_down_dh_angles(rel, 0.0, g.l1, g.l2, g.l3).q
    theta2, theta3 = theta[:, 1], theta[:, 2]
    c2, s2 = np.cos(theta2), np.sin(theta2)
    c23, s23 = np.cos(theta2 + theta3), np.sin(theta2 + theta3)
    a_r = (
        g.m0_k00
        + g.m1 * (g.l1 + g.k10 * c2 + g.k12 * s2)
        + g.m2 * (g.l1 + g.l2 * c2 + g.k20 * c23 + g.k22 * s23)
    )
    out = g.hip_moment.copy()
    out[:, 0] += a_r * c - g.a_t * s
    out[:, 1] += a_r * s + g.a_t * c
    if not horizontal:
        out[:, 2] += (
            g.m0_k02
            + g.m1 * (g.k10 * s2 - g.k12 * c2)
            + g.m2 * (g.l2 * s2 + g.k20 * s23 - g.k22 * c23)
        )
    return out


@pytest.mark.parametrize("horizontal", [False, True])
def test_leg_moments_equal_the_reference_bit_for_bit(model, horizontal):
    """Every leg, targets about the nominal feet at 0.2-0.6 m below the hips and some out of
    reach: the same values (NaN where the reference has NaN)."""
    rng = np.random.default_rng(23)
    const = model.leg_constants
    leg = np.tile(np.arange(4), 500)
    target = const.hip[leg] + rng.uniform((-0.6, -0.6, -0.7), (0.6, 0.6, -0.1), (leg.size, 3))
    got = leg_moments(const, leg, target, horizontal=horizontal)
    want = _reference_moments(const, leg, target, horizontal)
    unreachable = np.isnan(want[:, 0])
    assert 0 < unreachable.sum() < leg.size  # both kinds of rows are exercised
    np.testing.assert_array_equal(got, want)


def test_mammal_rows_equal_leg_by_leg_bit_for_bit():
    """go2's four legs in one pass (MammalConstants.of_rows): the IK (q, reachable, within
    limits) and the mass moments of every row equal those of each leg's own call, NaN rows
    included."""
    from silo4kin import mammal

    robot = load_robot("go2")
    legs = tuple(robot.legs)
    rng = np.random.default_rng(23)
    leg = rng.integers(0, 4, 2000)
    hip = np.array([g.position_hip_in_base for g in legs])[leg]
    target = hip + rng.uniform((-0.4, -0.3, -0.5), (0.4, 0.3, 0.0), (leg.size, 3))
    rows = MammalConstants.of_rows(legs, leg)
    ik = mammal.inverse_kinematics(rows, target)
    moment = mammal.leg_mass_moment_in_base(rows, ik.q)
    assert 0 < (~ik.reachable).sum() < leg.size
    for k, geo in enumerate(legs):
        mine = leg == k
        own = mammal.inverse_kinematics(geo, target[mine])
        np.testing.assert_array_equal(ik.q[mine], own.q)
        np.testing.assert_array_equal(ik.reachable[mine], own.reachable)
        np.testing.assert_array_equal(ik.within_limits[mine], own.within_limits)
        np.testing.assert_array_equal(moment[mine], mammal.leg_mass_moment_in_base(geo, own.q))


def test_cross3_is_np_cross_bit_for_bit():
    """silo4kin.frames.cross3 (the mammal legs' kinematics and the rolling feet) equals
    np.cross byte for byte under broadcasting, signed zeros, infinities and NaN included."""
    from silo4kin.frames import cross3

    rng = np.random.default_rng(3)
    special = np.array([0.0, -0.0, 1.0, -1.0, np.inf, -np.inf, np.nan, 1e-300, 3.7])
    shapes = [((3,), (5, 3)), ((5, 3), (5, 3)), ((1, 3), (4, 2, 3)), ((2, 3), (3,))]
    for trial in range(400):
        sa, sb = shapes[trial % len(shapes)]
        a = rng.choice(special, size=sa) if trial % 3 == 0 else rng.normal(size=sa)
        b = rng.choice(special, size=sb) if trial % 5 == 0 else rng.normal(size=sb)
        with np.errstate(all="ignore"):
            want, got = np.cross(a, b), cross3(a, b)
        assert got.shape == want.shape
        assert got.tobytes() == want.tobytes()


def test_mammal_joint_rates_are_joint_motions_bit_for_bit():
    """silo4kin.mammal.joint_rates (q, q̇ without q̈) equals joint_motion's q, q̇ and
    reachability byte for byte on random stacks of go2's legs (feet placed by FK of random
    joint values, so the rows are reachable, near-singular ones included); a stack with an
    unreachable row (J at q = 0, the straight knee) raises LinAlgError in both."""
    from silo4kin import mammal

    robot = load_robot("go2")
    rng = np.random.default_rng(29)
    for leg in robot.legs:
        q0 = rng.uniform((-0.8, -1.5, -2.7), (0.8, 3.4, -0.1), (500, 3))
        target = mammal.forward_kinematics(leg, q0)
        velocity, acceleration = rng.normal(size=(500, 3)), rng.normal(size=(500, 3))
        with np.errstate(all="ignore"):
            q, qd, _, reachable = mammal.joint_motion(leg, target, velocity, acceleration)
            q2, qd2, reachable2 = mammal.joint_rates(leg, target, velocity)
        assert reachable.all()
        assert q2.tobytes() == q.tobytes()
        assert qd2.tobytes() == qd.tobytes()
        np.testing.assert_array_equal(reachable2, reachable)
        far = np.vstack([target[:3], leg.position_hip_in_base + [0.0, 0.0, -5.0]])
        with pytest.raises(np.linalg.LinAlgError):
            mammal.joint_motion(leg, far, velocity[:4], acceleration[:4])
        with pytest.raises(np.linalg.LinAlgError):
            mammal.joint_rates(leg, far, velocity[:4])


def _segment_all_legs(contacts, leg, pose_start, pose_end, foot):
    """rolled_contacts' _segment as it was (level ground): all four legs through roll_feet,
    the three not standing with nothing to roll, q̈ by joint_motion."""
    from planner.gaits.rolled_contacts import PREDICTION_TOLERANCE_M, SEGMENT_SAMPLES
    from planner.trajectory.rolling_feet import SampledFeet, roll_feet
    from planner.trajectory.sampling import _foot_in_base, joint_motion

    k = SEGMENT_SAMPLES
    frac = np.linspace(0.0, 1.0, k + 1)
    n = len(frac)
    rate = np.broadcast_to(pose_end - pose_start, (n, 4))
    path = pose_start + rate * frac[:, None]
    base, base_d, zero = path[:, :3], rate[:, :3], np.zeros((n, 3))
    yaw, yaw_d, zero_n = path[:, 3], rate[:, 3], np.zeros(n)
    contact = np.zeros((n, 4), dtype=bool)
    contact[:, leg] = True
    feet = np.zeros((n, 4, 3))
    feet[:, leg] = foot

    def solve(j, target, target_d, target_dd):
        if j != leg:
            return zero, zero, zero
        u = _foot_in_base(target, target_d, target_dd, base, base_d, zero, yaw, yaw_d, zero_n)
        motion = joint_motion(contacts.legs[j], *u)
        return motion[0], motion[1], motion[2]

    sampled = SampledFeet(
        feet=feet,
        feet_d=np.zeros((n, 4, 3)),
        feet_dd=np.zeros((n, 4, 3)),
        swing_s=zero_n,
        swing_ds=zero_n,
        swing_dds=zero_n,
        yaw=yaw,
        yaw_d=yaw_d,
        contact=contact,
        dt_units=1.0 / k,
    )
    with np.errstate(invalid="ignore"):
        _, _, _, targets = roll_feet(
            contacts.legs, contacts.ball, sampled, solve, PREDICTION_TOLERANCE_M
        )
    return targets[-1, leg] - foot


def test_rolled_contacts_roll_one_leg_without_accelerations():
    """The ball's rolling displacement the step builder predicts (planner/gaits/
    rolled_contacts.py _segment: the standing leg rolled alone, its q and q̇ by
    mammal.joint_rates) equals byte for byte the four-leg roll with q̈ (joint_motion) it
    replaced, on random straight base moves of go2 (d integrates v = r ω × n, and ω depends
    on q and q̇ only; roll_feet treats each leg's columns on their own)."""
    from planner.gaits import rolled_contacts as rc
    from silo4kin.foot_contact import foot_ball

    go2 = load_robot("go2")
    robot, ball = planning_model(go2).planning_robot, foot_ball(go2)
    assert ball.rolls
    contacts = rc.RolledContacts(robot.legs, ball)
    rng = np.random.default_rng(31)
    hips = np.array([leg.position_hip_in_base for leg in robot.legs])
    rolled = 0.0
    for trial in range(24):
        leg = trial % 4
        start = np.array([0.0, 0.0, 0.3, 0.0]) + rng.uniform(-0.05, 0.05, 4)
        end = start + rng.uniform(-0.08, 0.08, 4)
        foot = hips[leg] * [1.0, 1.0, 0.0] + rng.uniform(-0.03, 0.03, 3) * [1.0, 1.0, 0.0]
        got = contacts._segment(leg, start, end, foot, None)
        want = _segment_all_legs(contacts, leg, start, end, foot)
        assert got.tobytes() == want.tobytes()
        rolled = max(rolled, float(np.abs(got).max()))
    assert rolled > 1e-5  # the feet do roll
