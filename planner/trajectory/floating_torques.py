"""Joint torques of the free-floating robot along a plan: whole-body inverse dynamics.

The thesis's torques (App. A.2, silo4kin.joint_torques) move each leg on a hip fixed in an
inertial frame and carry the load with vertical reactions only: the body's acceleration, and
the force and moment a swinging leg's motion puts on the body, reach no stance leg. In
physics (`silo4 simulate`: PD servos with the plan's torques as feed-forward) the stance
servos then take that difference as a position error, the body yaws by ~0.1 deg in each
swing, and each touchdown freezes the yaw of the moment into the foothold: ANYmal at
h 0.4553 m (benchmarks/bench_corpus.py, 200 cases, #65, 3 m at a fixed heading) ended
1.2 deg off its heading and 25.8 mm off its path; with these torques 0.4 mm
(docs/physics.md, "Feed-forward").

Here the robot floats. Its base (the URDF root, level, at the plan's CoG position and yaw)
moves as the samples do, the joints as q, q̇, q̈; Pinocchio's RNEA of the free-flyer model
gives the generalised force τ_ff (nv = 18) that this motion needs under gravity. The first
six rows are the wrench [f; m] on the base (its axes, moment about its origin) that only the
ground can give; the stance feet give it with forces f_i (W axes turned by the yaw: the base's
axes) at their contact points p_i (in the base frame):

    Σ_i f_i = τ_ff[0:3],   Σ_i p_i × f_i = τ_ff[3:6]                    (6 equations)

With three or four feet these have many solutions. The one taken changes the quasi-static
split f0_i = (0, 0, F_z,i) (silo4kin.support with the load shares of silo4kin.load_transfer:
the reactions of load "total") by the least weighted amount,

    f_i = f0_i + w_i A_iᵀ λ,   A_i = [I; [p_i]×] (6 × 3),
    (Σ_i w_i A_i A_iᵀ) λ = τ_ff[0:6] - Σ_i A_i f0_i,

w_i the foot's load share (0 in swing): a foot being loaded or unloaded takes the change in
proportion to its load, so the forces stay continuous through contact changes as the
quasi-static ones do and its friction demand stays that of a loaded foot. At rest (q̇ = q̈ = 0
and the base still) f0 already balances the robot, λ = 0 and the torques are the quasi-static
ones (tests/test_floating_torques.py).

Each leg's joints then hold its contact force: τ_j = τ_ff[joints] - J_cᵀ f_i, J_c the contact
point's Jacobian: the foot frame's (silo4kin.legs.jacobian) and, for a ball foot whose contact
point is d_i below its centre, the moment d_i × f_i through the foot link's angular Jacobian
(planner/trajectory/rolling_feet.py). The residual of the floating robot's equations is
checked against Pinocchio's frame Jacobians sample by sample in the tests.

The base's velocity and acceleration come from the samples (central differences of the CoG
position and yaw over t: the profiles are smooth, the error O(Δt²)), except on a trajectory
whose joints are at rest (q̇ = q̈ = 0 at every sample: planner.trajectory.limits.at_rest's
static pose), whose base is at rest too.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from planner.trajectory.rolling_feet import angular_velocity_foot_in_base
from planner.trajectory.samples import Trajectory, position_foot_in_base
from silo4kin import legs as leg_families
from silo4kin.foot_contact import foot_ball
from silo4kin.frames import cross3
from silo4kin.joint_torques import (
    JointTorques,
    _model_with_gravity,
    feet_in_base,
    rnea_batch,
    support_split,
)
from silo4kin.load_transfer import load_shares
from silo4kin.robot import STANDARD_GRAVITY, Robot

#: Weight added to every stance foot's load share in the least-change split (module
#: docstring): it keeps the 6 x 6 system posed at the instants a share is exactly zero, and
#: is small enough that such a foot takes no force worth the name (<< 1 mN).
SHARE_FLOOR = 1e-9


class FloatingTorques(NamedTuple):
    """The floating robot's torques and contact forces over N samples.

    Attributes:
        torques: joint torques and their parts (motion = τ_ff's joint rows, support =
            -J_cᵀ f), our joint order (robot.joint_names).
        force_foot_in_base: ground force on each foot at its contact point, base axes [N],
            shape (N, 4, 3) (zero in swing).
        wrench_residual: largest |Σ A_i f_i - τ_ff[0:6]| of each sample [N, N m], shape (N,).
    """

    torques: JointTorques
    force_foot_in_base: np.ndarray
    wrench_residual: np.ndarray


def base_rates(trajectory: Trajectory) -> tuple[np.ndarray, np.ndarray]:
    """The root's twist and its rate in the base's own axes, (N, 6) each: linear velocity
    [m/s] of the URDF root and yaw rate [rad/s] (rows 0-2, 3-5 as Pinocchio's free flyer
    orders them), and their time derivatives [m/s², rad/s²] (module docstring: central
    differences; zero for a trajectory whose joints are at rest)."""
    n = len(trajectory)
    v = np.zeros((n, 6))
    a = np.zeros((n, 6))
    if n < 3 or (not np.any(trajectory.qd) and not np.any(trajectory.qdd)):
        return v, a
    t = trajectory.t
    yaw = np.unwrap(trajectory.yaw_base_in_world)
    c, s = np.cos(yaw), np.sin(yaw)
    p = trajectory.position_base_in_world  # the CoG; its offset from the root turns with yaw
    pd = np.gradient(p, t, axis=0, edge_order=2)
    v[:, 0] = c * pd[:, 0] + s * pd[:, 1]
    v[:, 1] = -s * pd[:, 0] + c * pd[:, 1]
    v[:, 2] = pd[:, 2]
    v[:, 5] = np.gradient(yaw, t, edge_order=2)
    a = np.asarray(np.gradient(v, t, axis=0, edge_order=2))
    return v, a


def _root_twist(robot: Robot, v_cog: np.ndarray, a_cog: np.ndarray):  # noqa: ANN202
    """The root's twist from the CoG's (both in base axes): v_root = v_cog - ω × c, c the
    CoG in the root frame (constant), and its rate."""
    c = np.asarray(robot.position_body_com_in_base, dtype=float)
    v, a = v_cog.copy(), a_cog.copy()
    v[:, :3] -= cross3(v_cog[:, 3:], np.broadcast_to(c, (len(v), 3)))
    a[:, :3] -= cross3(a_cog[:, 3:], np.broadcast_to(c, (len(a), 3)))
    return v, a


def _angular_jacobian(leg, q: np.ndarray) -> np.ndarray:  # noqa: ANN001
    """The foot link's angular Jacobian in the base frame, (N, 3, 3): column j = ω for
    q̇_j = 1 (the map is linear in q̇)."""
    zero = np.zeros_like(q)
    cols = []
    for j in range(3):
        unit = zero.copy()
        unit[:, j] = 1.0
        cols.append(angular_velocity_foot_in_base(leg, q, unit, zero)[0])
    return np.stack(cols, axis=2)


def floating_torques(
    robot: Robot,
    trajectory: Trajectory,
    *,
    gravity: float = STANDARD_GRAVITY,
    transfer_s: float = 0.0,
) -> FloatingTorques:
    """Whole-body inverse dynamics of a plan (module docstring).

    Args:
        robot: the robot in its URDF frame.
        trajectory: the plan's samples (level body; contact points position_foot_in_world).
        gravity: g [m/s²].
        transfer_s: load transfer time at contact changes [s] (silo4kin.load_transfer).
    """
    n = len(trajectory)
    q = np.asarray(trajectory.q, dtype=float)
    yaw = trajectory.yaw_base_in_world
    c, s = np.cos(yaw), np.sin(yaw)
    com = np.asarray(robot.position_body_com_in_base, dtype=float)
    contact_in_root = position_foot_in_base(trajectory) + com
    share = (
        load_shares(trajectory.contact, trajectory.t, transfer_s)
        if transfer_s > 0
        else trajectory.contact.astype(float)
    )
    quasi = support_split(
        robot,
        q,
        trajectory.contact,
        contact_in_root,
        "total",
        gravity,
        share=share if transfer_s > 0 else None,
    )

    model = _model_with_gravity(robot.model_free_flyer, gravity)
    idx_q = np.array([model.joints[model.getJointId(j)].idx_q for j in robot.joint_names])
    idx_v = np.array([model.joints[model.getJointId(j)].idx_v for j in robot.joint_names])
    v_cog, a_cog = base_rates(trajectory)
    v_root, a_root = _root_twist(robot, v_cog, a_cog)
    q_ff = np.zeros((n, model.nq))
    q_ff[:, 0:2] = trajectory.position_base_in_world[:, :2] - np.stack(
        [c * com[0] - s * com[1], s * com[0] + c * com[1]], axis=1
    )
    q_ff[:, 2] = trajectory.position_base_in_world[:, 2] - com[2]
    q_ff[:, 5] = np.sin(yaw / 2)
    q_ff[:, 6] = np.cos(yaw / 2)
    q_ff[:, idx_q] = q
    v_ff = np.zeros((n, model.nv))
    a_ff = np.zeros((n, model.nv))
    v_ff[:, :6], a_ff[:, :6] = v_root, a_root
    v_ff[:, idx_v] = trajectory.qd
    a_ff[:, idx_v] = trajectory.qdd
    tau_ff = rnea_batch(model, q_ff, v_ff, a_ff)

    # the least-change split of the base wrench (module docstring)
    f0 = np.zeros((n, 4, 3))
    f0[..., 2] = quasi.force
    w = np.where(trajectory.contact, share + SHARE_FLOOR, 0.0)  # (N, 4)
    p = contact_in_root
    need = tau_ff[:, :6] - _wrench(p, f0)
    # Σ_k w_k A_k A_kᵀ in blocks: [[W I, -[P]×], [[P]×, Σ w (|p|² I - p pᵀ)]], P = Σ w p
    weight = w.sum(axis=1)
    moment_p = np.einsum("nk,nkd->nd", w, p)
    m = np.zeros((n, 6, 6))
    m[:, :3, :3] = weight[:, None, None] * np.eye(3)
    m[:, 3:, :3] = _skew(moment_p)
    m[:, :3, 3:] = -m[:, 3:, :3]
    m[:, 3:, 3:] = np.einsum("nk,nk->n", w, np.einsum("nkd,nkd->nk", p, p))[:, None, None] * np.eye(
        3
    ) - np.einsum("nk,nki,nkj->nij", w, p, p)
    stance = trajectory.contact.sum(axis=1) >= 3
    lam = np.zeros((n, 6))
    lam[stance] = np.linalg.solve(m[stance], need[stance][..., None])[..., 0]
    force = f0.copy()
    for k in range(4):
        # A_kᵀ λ = λ_f + λ_m × p_k... written out: [I, [p]×ᵀ] λ = λ_f - p × λ_m
        force[:, k] += w[:, k, None] * (lam[:, :3] - cross3(p[:, k], lam[:, 3:]))
    residual = np.abs(_wrench(p, force) - tau_ff[:, :6]).max(axis=1)

    # a ball foot's contact point lies below its centre (point feet: the foot frame itself)
    ball = foot_ball(robot).radius_m > 0.0
    ball_centre = feet_in_base(robot, q) if ball else contact_in_root
    support = np.zeros((n, 12))
    for k, leg in enumerate(robot.legs):
        cols = slice(3 * k, 3 * k + 3)
        j_lin = leg_families.jacobian(leg, q[:, cols])  # (N, 3, 3)
        gen = np.einsum("nij,ni->nj", j_lin, force[:, k])
        if ball:
            moment = cross3(contact_in_root[:, k] - ball_centre[:, k], force[:, k])
            gen += np.einsum("nij,ni->nj", _angular_jacobian(leg, q[:, cols]), moment)
        support[:, cols] = -gen
    motion = tau_ff[:, idx_v]
    torques = JointTorques(
        motion=motion,
        support=support,
        total=motion + support,
        reactions=force[..., 2],
        unloadable=quasi.unloadable,
        corrected=quasi.corrected,
    )
    return FloatingTorques(torques, force, residual)


def _skew(v: np.ndarray) -> np.ndarray:
    """[v]× for rows v (N, 3), shape (N, 3, 3)."""
    z = np.zeros(len(v))
    return np.stack(
        [
            np.stack([z, -v[:, 2], v[:, 1]], axis=1),
            np.stack([v[:, 2], z, -v[:, 0]], axis=1),
            np.stack([-v[:, 1], v[:, 0], z], axis=1),
        ],
        axis=1,
    )


def _wrench(p: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Σ_i [f_i; p_i × f_i] of forces f (N, 4, 3) at points p (N, 4, 3), shape (N, 6)."""
    return np.concatenate([f.sum(axis=1), sum(cross3(p[:, k], f[:, k]) for k in range(4))], axis=1)
