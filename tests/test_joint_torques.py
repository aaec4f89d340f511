"""Joint torques along synthetic plans: motion (eq A.14) + support (eq A.34), vs Pinocchio.

Synthetic stances: footholds on the ground around each hip (one per leg, seeded), body at a
height h, joints by IK; contact patterns of four and three feet. The whole-robot check puts
the computed reactions on the FREE-FLYER model as external forces and asks Pinocchio's rnea
for the base wrench (should vanish) and the joint torques (should equal ours).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from silo4kin import kinematics as K
from silo4kin.errors import Silo4Error
from silo4kin.joint_torques import (
    center_of_mass_in_base,
    feet_in_base,
    free_flyer_q_index,
    joint_torques,
    motion_torques,
    support_torques,
)
from silo4kin.robot import STANDARD_GRAVITY
from silo4kin.support import SupportError, support_reactions

#: RNEA vs closed-form Lagrange [N m]: both exact for the URDF model (dynamics.py equals
#: Pinocchio to 1e-14 per leg); torques here are < 100 N m, so 1e-10 leaves 4 digits of room.
MOTION_TOLERANCE = 1e-10
#: Free-flyer rnea with external forces vs ours [N m or N]: same physics, different
#: recursions; errors ~ eps * 400 N * 0.5 m ~ 1e-13, 1e-9 is safe.
WHOLE_ROBOT_TOLERANCE = 1e-9

G = STANDARD_GRAVITY


def _stance_q(robot, n: int, seed: int, height=(0.25, 0.45)) -> tuple[np.ndarray, np.ndarray]:
    """Joint values (n, 12) putting every foot on the ground (z = -h in the base frame)."""
    rng = np.random.default_rng(seed)
    h = rng.uniform(*height, n)
    q = np.empty((n, 12))
    for k, leg in enumerate(robot.legs):
        yaw = leg.theta_b + rng.uniform(-0.35, 0.35, n)
        rho = rng.uniform(0.20, 0.33, n)  # hip-axis to foot, horizontal [m]
        p = np.stack(
            [
                leg.position_hip_in_base[0] + rho * np.cos(yaw),
                leg.position_hip_in_base[1] + rho * np.sin(yaw),
                -h,
            ],
            axis=1,
        )
        q[:, 3 * k : 3 * k + 3] = K.inverse_kinematics(leg, p)
    return q, h


def _smooth(robot, n: int, seed: int) -> tuple[np.ndarray, ...]:
    """q(t) = q0 + a sin(w t + phi) with analytic qd, qdd, around a stance; t in [0, 4] s."""
    rng = np.random.default_rng(seed)
    q0, _ = _stance_q(robot, 1, seed)
    t = np.linspace(0.0, 4.0, n)[:, None]
    a, w, phi = rng.uniform(0.05, 0.3, 12), rng.uniform(0.5, 4.0, 12), rng.uniform(0, 6, 12)
    return (
        q0 + a * np.sin(w * t + phi),
        a * w * np.cos(w * t + phi),
        -a * w**2 * np.sin(w * t + phi),
    )


def _free_flyer_rnea(robot, q, qd, qdd, reactions, height, yaw):
    """Pinocchio rnea on the free-flyer model, base at rest at (0, 0, h) yawed, with the
    reactions (0, 0, F_z) applied at the feet. Returns (base wrench (N, 6), tau (N, 12) ours)."""
    model = robot.model_free_flyer
    data = model.createData()
    idx = free_flyer_q_index(robot)
    vidx = idx - 1
    knee = [model.getJointId(leg.joint_names[2]) for leg in robot.legs]
    foot = [model.getFrameId(leg.foot_frame) for leg in robot.legs]
    base, tau = [], []
    for i in range(q.shape[0]):
        qf = np.zeros(model.nq)
        qf[2] = height[i]
        qf[5], qf[6] = np.sin(yaw[i] / 2), np.cos(yaw[i] / 2)
        qf[idx] = q[i]
        v, a = np.zeros(model.nv), np.zeros(model.nv)
        v[vidx], a[vidx] = qd[i], qdd[i]
        pin.framesForwardKinematics(model, data, qf)
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        for k in range(4):
            p = data.oMf[foot[k]].translation
            f = np.array([0.0, 0.0, reactions[i, k]])
            fext[knee[k]] = data.oMi[knee[k]].actInv(pin.Force(f, np.cross(p, f)))
        out = pin.rnea(model, data, qf, v, a, fext)
        base.append(out[:6].copy())
        tau.append(out[vidx])
    return np.array(base), np.array(tau)


def _contacts(n: int, seed: int) -> np.ndarray:
    """Contact patterns: four feet, or three with a random leg lifted."""
    rng = np.random.default_rng(seed)
    c = np.ones((n, 4), bool)
    lifted = rng.integers(-1, 4, n)
    c[np.flatnonzero(lifted >= 0), lifted[lifted >= 0]] = False
    return c


def test_rnea_equals_closed_form_lagrange(silo4):
    """Batched Pinocchio RNEA (fixed hips) equals the corrected Lagrange model A.14-A.29
    along a smooth synthetic trajectory, for all 12 joints in our joint order."""
    q, qd, qdd = _smooth(silo4, 1500, seed=11)
    rnea = motion_torques(silo4, q, qd, qdd, method="rnea")
    lagrange = motion_torques(silo4, q, qd, qdd, method="closed_form")
    assert np.abs(rnea - lagrange).max() < MOTION_TOLERANCE
    assert np.abs(rnea).max() > 1.0  # the comparison is not between zeros


def test_rnea_batch_equals_per_sample_rnea_and_maps_joint_order(silo4):
    """The batch call returns, per sample, pin.rnea of the fixed-base model mapped by name."""
    q, qd, qdd = _smooth(silo4, 50, seed=12)
    ours = motion_torques(silo4, q, qd, qdd)
    data = silo4.model.createData()
    ref = np.array(
        [
            silo4.from_pinocchio_q(
                pin.rnea(silo4.model, data, *(silo4.to_pinocchio_q(x[i]) for x in (q, qd, qdd)))
            )
            for i in range(50)
        ]
    )
    assert np.abs(ours - ref).max() < 1e-12


def test_reused_rnea_pool_keeps_each_batch_its_own(silo4):
    """The RNEA's ModelPool, kept in the robot's memo between calls, carries nothing from one
    batch to the next (a batch of 50 then one of 7 gives what a fresh robot gives for the 7,
    and at another gravity the pool of that gravity), and the robot still pickles (the memo
    is left out; the copy builds its own)."""
    import pickle

    from silo4kin import load_robot

    q, qd, qdd = _smooth(silo4, 50, seed=21)
    motion_torques(silo4, q, qd, qdd)
    small = motion_torques(silo4, q[:7] * 0.5, qd[:7], qdd[:7])
    fresh = load_robot()
    assert np.array_equal(small, motion_torques(fresh, q[:7] * 0.5, qd[:7], qdd[:7]))
    g98 = motion_torques(silo4, q[:7], qd[:7] * 0, qdd[:7] * 0, gravity=9.8)
    assert not np.allclose(g98, motion_torques(silo4, q[:7], qd[:7] * 0, qdd[:7] * 0))
    copy = pickle.loads(pickle.dumps(silo4))
    assert np.array_equal(motion_torques(copy, q, qd, qdd), motion_torques(silo4, q, qd, qdd))


def test_gravity_argument(silo4):
    """Static torques scale with g (thesis g = 9.8)."""
    q, _ = _stance_q(silo4, 20, seed=13)
    z = np.zeros_like(q)
    t1 = motion_torques(silo4, q, z, z, gravity=9.8)
    t2 = motion_torques(silo4, q, z, z, gravity=G)
    assert np.abs(t1 * G / 9.8 - t2).max() < MOTION_TOLERANCE


def test_free_flyer_static_total_load_is_equilibrium(silo4):
    """load="total", static poses, 4 and 3 stance feet, yawed base: Pinocchio's free-flyer
    rnea with our reactions as external forces needs no base wrench, and its joint torques
    are ours: the feet carry the whole robot and tau = motion + Jᵀ(-F) holds it."""
    n = 120
    q, h = _stance_q(silo4, n, seed=14)
    z = np.zeros_like(q)
    contact = _contacts(n, seed=14)
    keep = ~support_reactions(
        feet_in_base(silo4, q)[:, :, :2] - center_of_mass_in_base(silo4, q)[:, None], contact, 1.0
    ).unloadable
    q, h, z, contact = q[keep], h[keep], z[keep], contact[keep]
    assert keep.sum() > 60 and (contact.sum(axis=1) == 3).sum() > 20
    jt = joint_torques(silo4, q, z, z, contact, load="total")
    yaw = np.random.default_rng(15).uniform(-np.pi, np.pi, q.shape[0])
    base, tau = _free_flyer_rnea(silo4, q, z, z, jt.reactions, h, yaw)
    assert np.abs(base).max() < WHOLE_ROBOT_TOLERANCE
    assert np.abs(tau - jt.total).max() < WHOLE_ROBOT_TOLERANCE


def test_free_flyer_body_load_residual_is_the_legs_weight(silo4):
    """load="body" (thesis): joint torques still equal Pinocchio's for the same foot forces,
    but the base wrench left over is the legs' weight (12.44 kg * g up) and its moment: the
    thesis's feet carry only the 30 kg body; the legs hang from the base through their hips."""
    n = 60
    q, h = _stance_q(silo4, n, seed=16)
    z = np.zeros_like(q)
    contact = np.ones((n, 4), bool)
    jt = joint_torques(silo4, q, z, z, contact, load="body")
    base, tau = _free_flyer_rnea(silo4, q, z, z, jt.reactions, h, np.zeros(n))
    assert np.abs(tau - jt.total).max() < WHOLE_ROBOT_TOLERANCE
    legs_weight = (silo4.total_mass - silo4.body_mass) * G
    assert np.abs(base[:, 2] - legs_weight).max() < WHOLE_ROBOT_TOLERANCE
    assert np.abs(base[:, :2]).max() < WHOLE_ROBOT_TOLERANCE
    com = center_of_mass_in_base(silo4, q) * silo4.total_mass * G
    assert np.abs(base[:, 3] - com[:, 1]).max() < WHOLE_ROBOT_TOLERANCE  # c_y M g
    assert np.abs(base[:, 4] + com[:, 0]).max() < WHOLE_ROBOT_TOLERANCE  # -c_x M g


def test_free_flyer_moving_legs_residual_is_leg_inertia(silo4):
    """Moving joints, load="total": joint torques equal Pinocchio's (the base is at rest in
    both); the base wrench left is the legs' inertial force, bounded here by 5 % of M g."""
    q, qd, qdd = _smooth(silo4, 80, seed=17)
    contact = np.ones((80, 4), bool)
    jt = joint_torques(silo4, q, qd, qdd, contact, load="total")
    ok = ~jt.unloadable
    base, tau = _free_flyer_rnea(
        silo4, q[ok], qd[ok], qdd[ok], jt.reactions[ok], np.full(ok.sum(), 0.4), np.zeros(ok.sum())
    )
    assert np.abs(tau - jt.total[ok]).max() < WHOLE_ROBOT_TOLERANCE
    assert 1e-6 < np.abs(base[:, :3]).max() < 0.05 * silo4.total_mass * G


def test_printed_sign_w_minus_mg_gives_opposite_torque(silo4):
    """Eq A.32 as printed (W = (0, 0, -m g)) gives support torques opposite to the holding
    torques Pinocchio's free-flyer equilibrium requires; W = +m g gives them (errata)."""
    n = 40
    q, h = _stance_q(silo4, n, seed=18)
    z = np.zeros_like(q)
    contact = np.ones((n, 4), bool)
    jt = joint_torques(silo4, q, z, z, contact, load="total")
    _, tau_pin = _free_flyer_rnea(silo4, q, z, z, jt.reactions, h, np.zeros(n))
    support_pin = tau_pin - jt.motion  # what the feet must hold, per Pinocchio
    printed_f = -jt.reactions  # A F = (0, 0, -m g) is linear in W
    printed = support_torques(silo4, q, printed_f)
    assert np.abs(support_pin - jt.support).max() < WHOLE_ROBOT_TOLERANCE
    assert np.abs(printed + support_pin).max() < WHOLE_ROBOT_TOLERANCE
    assert np.abs(printed - support_pin).max() > 10.0  # [N m]: the sign matters


def test_thesis_notes_example_rf_position_3(silo4):
    """docs/thesis-notes.md: leg 2 (RF) at position 3, h = 0.39, 73.5 N:
    tau = (0, -3.55, +13.10)."""
    x_max = 0.3726  # the thesis's printed stride at h = 0.39 (§4.2.1)
    p = np.array([(0.155 + x_max) / 2, -0.155, -0.39])
    leg = silo4.legs[1]
    q = K.inverse_kinematics(leg, p)
    tau = -73.5 * K.jacobian(leg, q)[2]
    assert np.abs(tau - [0.0, -3.55, 13.10]).max() < 0.01  # [N m], printed to 2 decimals


def test_swing_leg_has_no_support_torque(silo4):
    """A leg in the air gets no support torque (its reaction is 0)."""
    q, _ = _stance_q(silo4, 30, seed=19)
    z = np.zeros_like(q)
    contact = np.ones((30, 4), bool)
    contact[:, 2] = False
    jt = joint_torques(silo4, q, z, z, contact)
    assert np.all(jt.support[:, 6:9] == 0.0) and np.all(jt.reactions[:, 2] == 0.0)
    assert np.array_equal(jt.total, jt.motion + jt.support)


def test_fewer_than_three_stance_feet_names_sample(silo4):
    q, _ = _stance_q(silo4, 10, seed=20)
    z = np.zeros_like(q)
    contact = np.ones((10, 4), bool)
    contact[7, 1:3] = False
    with pytest.raises(SupportError, match="sample 7 has 2 stance feet"):
        joint_torques(silo4, q, z, z, contact)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"load": "legs"}, "unknown load 'legs'"),
        ({"method": "euler"}, "unknown torque method 'euler'"),
        ({"gravity": -9.8}, "gravity must be > 0"),
        ({"position_foot_in_base": np.zeros((3, 4, 2))}, "position_foot_in_base has shape"),
    ],
)
def test_bad_arguments(silo4, kwargs, match):
    q, _ = _stance_q(silo4, 3, seed=21)
    z = np.zeros_like(q)
    with pytest.raises(Silo4Error, match=match):
        joint_torques(silo4, q, z, z, np.ones((3, 4), bool), **kwargs)


def test_bad_joint_arrays(silo4):
    q, _ = _stance_q(silo4, 3, seed=22)
    with pytest.raises(Silo4Error, match=r"qd has shape \(3, 11\)"):
        joint_torques(silo4, q, np.zeros((3, 11)), np.zeros_like(q), np.ones((3, 4), bool))
    q[1, 4] = np.nan
    with pytest.raises(Silo4Error, match="q has non-finite values .* sample 1"):
        motion_torques(silo4, q, np.zeros_like(q), np.zeros_like(q))


def test_planner_glue_yawed_moving_base(silo4):
    """add_torques on a Trajectory whose base moves and yaws in the world: feet rotated back
    by -yaw give the same torques as FK feet in the base frame (App. A's model, each load);
    parts sum to tau. (The floating robot of load "total" in motion:
    tests/test_floating_torques.py.)"""
    from planner.trajectory.limits import at_rest
    from planner.trajectory.samples import Trajectory
    from planner.trajectory.torques import add_torques, position_foot_in_base

    n = 200
    q, qd, qdd = _smooth(silo4, n, seed=23)
    t = np.linspace(0.0, 4.0, n)
    base = np.stack([0.1 * t, 0.05 * t, np.full(n, 0.4)], axis=1)
    yaw = 0.3 + 0.2 * t
    feet_b = feet_in_base(silo4, q)
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    feet_w = np.stack(
        [
            c * feet_b[..., 0] - s * feet_b[..., 1],
            s * feet_b[..., 0] + c * feet_b[..., 1],
            feet_b[..., 2],
        ],
        axis=2,
    )
    feet_w += base[:, None, :]
    contact = np.ones((n, 4), bool)
    traj = Trajectory(
        t=t,
        unit_time_s=1.0,
        position_base_in_world=base,
        yaw_base_in_world=yaw,
        joint_names=tuple(silo4.joint_names),
        q=q,
        qd=qd,
        qdd=qdd,
        position_foot_in_world=feet_w,
        contact=contact,
        margin=np.ones(n),
        phase=np.full(n, "body"),
    )
    assert np.abs(position_foot_in_base(traj) - feet_b).max() < 1e-12
    for load in ("body", "total"):
        ref = joint_torques(silo4, q, qd, qdd, contact, load=load)
        out = add_torques(silo4, traj, load=load)
        if load == "total":  # the floating robot: App. A's model with transfer 0, at rest
            out = add_torques(silo4, at_rest(traj), load=load, transfer_s=0.0)
            ref = joint_torques(silo4, q, 0 * qd, 0 * qdd, contact, load=load)
        assert np.abs(out.tau - ref.total).max() < 1e-9
        assert np.array_equal(out.tau, out.tau_parts["motion"] + out.tau_parts["support"])
    three = np.ones((n, 4), bool)
    three[:, 0] = False
    bad = np.flatnonzero(support_reactions(feet_b, three, 1.0).unloadable)
    assert bad.size  # some samples put the CoG outside the RF-LH-RH triangle
    with pytest.raises(Silo4Error, match=f"sample {bad[0]} .* cannot carry the load"):
        add_torques(silo4, dataclasses.replace(traj, contact=three), load="body")
    contact[5, :2] = False
    with pytest.raises(SupportError, match="sample 5 has 2 stance feet"):
        add_torques(silo4, dataclasses.replace(traj, contact=contact))
