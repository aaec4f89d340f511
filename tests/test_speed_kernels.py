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
