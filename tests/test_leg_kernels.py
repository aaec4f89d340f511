"""The one knee-down IK kernel and the LegFamily protocol, against Pinocchio.

silo4kin.kinematics.knee_down_terms is the one knee-down IK: inverse_kinematics_masked (one
leg), knee_down_ik_of_legs (several legs in one pass) and joint_motion (q, q', q'') all call
it, so their joint values are equal bit for bit; Pinocchio's FK of those joint values lands
on the targets. Each leg family's FK, Jacobian, J' q' and IK (silo4kin.leg_family) match
Pinocchio's frame placement, frame Jacobian and classical acceleration, on insect legs
(SILO4, mantis, phasmid) and mammal legs (Go2), on seeded random states inside the limits.
"""

from __future__ import annotations

import numpy as np
import pytest

from silo4kin import load_robot
from silo4kin.check import pinocchio_samples, random_states
from silo4kin.kinematics import (
    KneeDownLegs,
    inverse_kinematics_masked,
    joint_motion,
    knee_down_ik_of_legs,
)
from silo4kin.leg_family import INSECT, family_of

#: Foot positions round-trip to rounding of ~1e-16 m x a few operations; 1e-9 m is far above.
POSITION_M = 1e-9
#: Jacobian [m/rad] and J' q' [m/s^2] entries of legs ~0.3 m and unit-normal rates.
DERIVATIVE = 1e-9
INSECT_ROBOTS = {
    "silo4": None,
    "mantis": "tests/robots/mantis.urdf",
    "phasmid": "tests/robots/phasmid.urdf.xacro",
}
N = 200


def _in_closed_form_domain(robot, q: np.ndarray) -> np.ndarray:
    """Rows of q (N, 12) [rad] where every insect foot is in front of its hip-yaw axis
    (rho = L1 + L2 cos θ2 + L3 cos(θ2 + θ3) > 0: behind it the closed form reads the target
    as a foot turned by π, which may be out of reach) and not within 1e-3 rad of a
    stretched or folded knee; (N,) bool."""
    keep = np.ones(len(q), dtype=bool)
    for k, leg in enumerate(robot.legs):
        theta = leg.joint_to_dh(q[:, 3 * k : 3 * k + 3])
        rho = leg.L1 + leg.L2 * np.cos(theta[:, 1]) + leg.L3 * np.cos(theta[:, 1] + theta[:, 2])
        keep &= (rho > 1e-3) & (np.abs(np.sin(theta[:, 2])) > 1e-3)
    return keep


def _robot(name: str):
    if name == "go2":
        pytest.importorskip("example_robot_data")
        return load_robot("go2")
    path = INSECT_ROBOTS[name]
    return load_robot() if path is None else load_robot(path)


@pytest.mark.parametrize("name", list(INSECT_ROBOTS))
def test_knee_down_kernel_round_trips_pinocchio_fk(name: str) -> None:
    """Targets at Pinocchio's FK of random joint values: every path through the kernel gives
    the same joint values bit for bit, and Pinocchio's FK of them is the target."""
    robot = _robot(name)
    q, v, a = random_states(robot, 4 * N, seed=31)
    keep = np.flatnonzero(_in_closed_form_domain(robot, q))[:N]
    assert keep.size == N
    q, v, a = q[keep], v[keep], a[keep]
    foot = pinocchio_samples(robot, q, v, a).foot  # (N, 4, 3) in B
    legs = tuple(robot.legs)
    table = KneeDownLegs.of(legs)
    idx = np.repeat(np.arange(4), N)
    targets = foot.transpose(1, 0, 2).reshape(-1, 3)  # leg-major
    together = knee_down_ik_of_legs(table, idx, targets)
    q_ik = np.empty_like(q)
    for k, leg in enumerate(legs):
        res = inverse_kinematics_masked(leg, foot[:, k])
        assert res.reachable.all()
        rows = slice(k * N, (k + 1) * N)
        assert np.array_equal(together.q[rows], res.q)
        motion = joint_motion(leg, foot[:, k], np.zeros((N, 3)), np.zeros((N, 3)))
        assert np.array_equal(motion.q, res.q)
        q_ik[:, 3 * k : 3 * k + 3] = res.q
    back = pinocchio_samples(robot, q_ik, np.zeros_like(q), np.zeros_like(q)).foot
    np.testing.assert_allclose(back, foot, atol=POSITION_M, rtol=0)


@pytest.mark.parametrize("name", ["silo4", "mantis", "go2"])
def test_leg_family_protocol_against_pinocchio(name: str) -> None:
    """FK, Jacobian, J' q' and the FK of the IK of each family (family_of(leg)) equal
    Pinocchio's on random states (the IK on insect legs inside the closed form's domain);
    insect robots get the insect family, Go2 the mammal."""
    robot = _robot(name)
    q, v, a = random_states(robot, N, seed=32)
    ref = pinocchio_samples(robot, q, v, a)
    domain = _in_closed_form_domain(robot, q) if name != "go2" else np.ones(N, dtype=bool)
    assert domain.sum() > N // 4
    for k, leg in enumerate(robot.legs):
        family = family_of(leg)
        assert (family is INSECT) == (name != "go2")
        assert family.has_hip_yaw == (name != "go2")
        qk, vk = q[:, 3 * k : 3 * k + 3], v[:, 3 * k : 3 * k + 3]
        p = family.forward_kinematics(leg, qk)
        np.testing.assert_allclose(p, ref.foot[:, k], atol=POSITION_M, rtol=0)
        np.testing.assert_allclose(
            family.jacobian(leg, qk), ref.jacobian[:, k], atol=DERIVATIVE, rtol=0
        )
        np.testing.assert_allclose(
            family.jacobian_derivative_times_velocity(leg, qk, vk),
            ref.jdot_qd[:, k],
            atol=DERIVATIVE,
            rtol=0,
        )
        ik = family.inverse_kinematics(leg, p[domain])
        assert ik.reachable.all()
        np.testing.assert_allclose(
            family.forward_kinematics(leg, ik.q), p[domain], atol=POSITION_M, rtol=0
        )
