"""Joint torques along a plan: leg motion + body support (thesis App. A.2.1-A.2.2).

    tau = tau_motion + tau_support
    tau_motion  = M(q) q'' + H(q, q') + G(q) of each leg with its hip fixed   (eq A.14)
    tau_support = Jᵀ (-F),  F = (0, 0, F_z) the upward ground reaction       (eq A.34)

The motion part uses the thesis's model: each leg on a hip fixed in an inertial frame
(Pinocchio's fixed-base model, whose legs are independent chains). The real base moves
(slowly, in a creeping gait); its acceleration and rotation are neglected, as in the thesis.
It is computed by Pinocchio's batched RNEA (``pin.rneaInParallel``) or, with
``method="closed_form"``, by the corrected Lagrange model of silo4kin.dynamics (equal to
1e-12 N m). Joint order is ours (robot.joint_names); Pinocchio's order is mapped by name.

The support part carries a load on the stance feet (silo4kin.support): ``load="body"`` the
thesis's choice, the body mass m_b at the body CoG (the legs' own weight is then carried
only inside tau_motion, via their fixed hips); ``load="total"`` the whole robot's mass at the
whole robot's CoG, which makes the feet carry everything: for a static pose the result is
then an exact equilibrium of the free-floating robot (tests/test_joint_torques.py).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np
import pinocchio as pin

from .com import center_of_mass_closed_form
from .dynamics import inverse_dynamics
from .errors import Silo4Error
from .legs import forward_kinematics, jacobian
from .memo import memoised
from .robot import STANDARD_GRAVITY, Robot
from .support import SupportReactions, support_reactions

Load = Literal["body", "total"]
Method = Literal["rnea", "closed_form"]
LOADS: tuple[str, ...] = ("body", "total")
METHODS: tuple[str, ...] = ("rnea", "closed_form")


@dataclass(frozen=True)
class JointTorques:
    """Joint torques over N samples, our joint order (robot.joint_names).

    Attributes:
        motion: leg-motion torques, hip fixed (eq A.14) [N m], shape (N, 12).
        support: body-support torques Jᵀ(-F) (eq A.34) [N m], shape (N, 12).
        total: motion + support [N m], shape (N, 12).
        reactions: upward vertical ground reaction on each foot [N], shape (N, 4).
        unloadable: samples where no non-negative reactions carry the load, shape (N,).
        corrected: samples where the least-norm split (eq A.31) asked a foot to pull and the
            non-negative split was used, shape (N,).
    """

    motion: np.ndarray
    support: np.ndarray
    total: np.ndarray
    reactions: np.ndarray
    unloadable: np.ndarray
    corrected: np.ndarray


def _model_with_gravity(model: pin.Model, gravity: float) -> pin.Model:
    if np.isclose(model.gravity.linear[2], -gravity, rtol=0.0, atol=1e-12):
        return model
    out = pin.Model(model)
    out.gravity.linear = np.array([0.0, 0.0, -gravity])
    return out


def _rnea_pool(robot: Robot, gravity: float, num_threads: int) -> tuple[pin.Model, pin.ModelPool]:
    """The fixed-base model at ``gravity`` and a ModelPool of it, kept in the robot's memo
    per calling thread (a pool's datas are scratch space: two threads must not share one)."""
    key = ("rnea_pool", float(gravity), int(num_threads), threading.get_ident())

    def build() -> tuple[pin.Model, pin.ModelPool]:
        model = _model_with_gravity(robot.model, gravity)
        return model, pin.ModelPool(model, num_threads)

    memo = getattr(robot, "_memo", None)
    return build() if memo is None else memoised(memo, key, build)


def _check_joint_arrays(*arrays: np.ndarray) -> int:
    n = np.asarray(arrays[0]).shape[0]
    for name, a in zip(("q", "qd", "qdd"), arrays):
        a = np.asarray(a)
        if a.shape != (n, 12):
            raise Silo4Error(f"{name} has shape {a.shape}, expected ({n}, 12)")
        if not np.all(np.isfinite(a)):
            raise Silo4Error(
                f"{name} has non-finite values (first at sample "
                f"{int(np.argwhere(~np.isfinite(a))[0, 0])})"
            )
    return n


def rnea_batch(
    model: pin.Model,
    q_pin: np.ndarray,
    v_pin: np.ndarray,
    a_pin: np.ndarray,
    num_threads: int = 1,
    pool: pin.ModelPool | None = None,
) -> np.ndarray:
    """Pinocchio RNEA over N samples in one call (``pin.rneaInParallel``).

    Args:
        model: any Pinocchio model; q_pin (N, nq), v_pin and a_pin (N, nv) in ITS order.
        pool: a ``pin.ModelPool`` of ``model`` with ``num_threads`` datas to reuse (one is
            built otherwise, ~40 us: most of a small batch's cost); one thread at a time.

    Returns:
        generalized forces [N m or N], shape (N, nv).
    """
    n = q_pin.shape[0]
    if pool is None:
        pool = pin.ModelPool(model, num_threads)
    tau = pin.rneaInParallel(
        num_threads,
        pool,
        np.asfortranarray(q_pin.T),
        np.asfortranarray(v_pin.T),
        np.asfortranarray(a_pin.T),
    )
    return np.asarray(tau).T.reshape(n, model.nv)


def motion_torques(
    robot: Robot,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    *,
    gravity: float = STANDARD_GRAVITY,
    method: Method = "rnea",
    num_threads: int = 1,
) -> np.ndarray:
    """Leg-motion torques, every leg with its hip fixed (eq A.14), our joint order.

    Args:
        q, qd, qdd: joint values [rad], rates [rad/s], accelerations [rad/s^2], (N, 12).
        gravity: g along -z of the base [m/s^2] (the thesis uses 9.8).
        method: "rnea" (Pinocchio batch) or "closed_form" (silo4kin.dynamics, per leg).

    Returns:
        tau_motion [N m], shape (N, 12).
    """
    _check_joint_arrays(q, qd, qdd)
    q, qd, qdd = (np.asarray(a, dtype=float) for a in (q, qd, qdd))
    if method == "rnea":
        model, pool = _rnea_pool(robot, gravity, num_threads)
        tau_pin = rnea_batch(
            model,
            robot.to_pinocchio_q(q),
            robot.to_pinocchio_q(qd),
            robot.to_pinocchio_q(qdd),
            num_threads,
            pool,
        )
        return robot.from_pinocchio_q(tau_pin)
    if method == "closed_form":
        return np.concatenate(
            [
                inverse_dynamics(
                    leg,
                    q[:, 3 * k : 3 * k + 3],
                    qd[:, 3 * k : 3 * k + 3],
                    qdd[:, 3 * k : 3 * k + 3],
                    gravity,
                )
                for k, leg in enumerate(robot.legs)
            ],
            axis=1,
        )
    raise Silo4Error(f"unknown torque method {method!r}; choose one of {list(METHODS)}")


def feet_in_base(robot: Robot, q: np.ndarray) -> np.ndarray:
    """Foot positions in the base frame by FK (eq 3.5; mammal legs: mammal.py, through
    silo4kin.legs) [m], shape (N, 4, 3)."""
    q = np.asarray(q, dtype=float)
    return np.stack(
        [forward_kinematics(leg, q[:, 3 * k : 3 * k + 3]) for k, leg in enumerate(robot.legs)],
        axis=1,
    )


def free_flyer_q_index(robot: Robot) -> np.ndarray:
    """Index into the free-flyer model's q (nq 19) of each of our 12 joints, shape (12,)."""
    m = robot.model_free_flyer
    return np.array([m.joints[m.getJointId(name)].idx_q for name in robot.joint_names])


def center_of_mass_in_base(robot: Robot, q: np.ndarray, num_threads: int = 1) -> np.ndarray:
    """Whole-robot CoM, horizontal part, in the (level) base frame [m], shape (N, 2).

    From the gravity wrench on the free-flyer's base at rest (batched RNEA): the base moment
    about its origin is c x (M g) with c the CoM, so c_x = -tau_y / (M g), c_y = tau_x / (M g).
    """
    q = np.asarray(q, dtype=float)
    n = q.shape[0]
    model = robot.model_free_flyer
    q_ff = np.zeros((n, model.nq))
    q_ff[:, 6] = 1.0  # identity quaternion (x, y, z, w)
    q_ff[:, free_flyer_q_index(robot)] = q
    zeros = np.zeros((n, model.nv))
    wrench = rnea_batch(model, q_ff, zeros, zeros, num_threads)
    mg = robot.total_mass * -model.gravity.linear[2]
    return np.stack([-wrench[:, 4] / mg, wrench[:, 3] / mg], axis=1)


def support_torques(robot: Robot, q: np.ndarray, reactions: np.ndarray) -> np.ndarray:
    """Joint torques holding vertical reactions F_z at the feet, tau = Jᵀ(-F) (eq A.34).

    Args:
        q: joint values [rad], shape (N, 12).
        reactions: upward ground reaction on each foot [N], shape (N, 4) (0 in swing).

    Returns:
        tau_support [N m], shape (N, 12); only J's z row enters as F = (0, 0, F_z).
    """
    q = np.asarray(q, dtype=float)
    f = np.asarray(reactions, dtype=float)
    return np.concatenate(
        [
            -f[:, k, None] * jacobian(leg, q[:, 3 * k : 3 * k + 3])[:, 2, :]
            for k, leg in enumerate(robot.legs)
        ],
        axis=1,
    )


def support_split(
    robot: Robot,
    q: np.ndarray,
    contact: np.ndarray,
    position_foot_in_base: np.ndarray,
    load: Load,
    gravity: float,
    nonnegative: bool = True,
    share: np.ndarray | None = None,
) -> SupportReactions:
    """The vertical reactions carrying ``load`` (eq A.31-A.33; arguments as
    :func:`joint_torques`'), feet (N, 4, 3) in the root frame [m]."""
    n = q.shape[0]
    if load == "body":
        cog = np.broadcast_to(robot.position_body_com_in_base[:2], (n, 2))
        weight = robot.body_mass * gravity
    else:
        # the closed form (silo4kin.com; = pin.centerOfMass to 1e-12 on SILO4 and 1e-10 on
        # mammal legs, tests/test_com.py, tests/test_mammal.py) at ~1/10 the cost of
        # center_of_mass_in_base's free-flyer RNEA; the equilibrium against Pinocchio's
        # free-flyer RNEA is tests/test_joint_torques.py's
        cog = center_of_mass_closed_form(robot, q)[:, :2]
        weight = robot.total_mass * gravity
    rel = position_foot_in_base[:, :, :2] - cog[:, None, :]
    return support_reactions(rel, contact, weight, nonnegative=nonnegative, share=share)


def joint_torques(
    robot: Robot,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    contact: np.ndarray,
    *,
    position_foot_in_base: np.ndarray | None = None,
    load: Load = "body",
    gravity: float = STANDARD_GRAVITY,
    method: Method = "rnea",
    nonnegative: bool = True,
    num_threads: int = 1,
    share: np.ndarray | None = None,
) -> JointTorques:
    """Motion + support torques for all 12 joints over N samples (App. A.2).

    Args:
        q, qd, qdd: joint trajectories, our joint order, shape (N, 12).
        contact: stance flags, shape (N, 4), legs LF, RF, LH, RH; >= 3 per sample.
        position_foot_in_base: foot positions in the level base frame [m], (N, 4, 3);
            default FK of q (identical for a consistent plan).
        load: "body" (thesis: m_b at the body CoG) or "total" (whole robot at its CoG).
        gravity: g [m/s^2]; nonnegative: see silo4kin.support.support_reactions.
        share: each foot's share of the load (N, 4) in [0, 1] (silo4kin.load_transfer:
            feet loaded and unloaded over a transfer time at contact changes); None: the
            thesis's split of every sample on its own (eq A.31 / A.33).

    Raises:
        SupportError: a sample has fewer than three (or collinear) stance feet.
        Silo4Error: bad shapes, non-finite values, unknown load or method.
    """
    n = _check_joint_arrays(q, qd, qdd)
    if load not in LOADS:
        raise Silo4Error(f"unknown load {load!r}; choose one of {list(LOADS)}")
    if not np.isfinite(gravity) or gravity <= 0:
        raise Silo4Error(f"gravity must be > 0 m/s^2, got {gravity}")
    q = np.asarray(q, dtype=float)
    feet = (
        feet_in_base(robot, q)
        if position_foot_in_base is None
        else np.asarray(position_foot_in_base, dtype=float)
    )
    if feet.shape != (n, 4, 3):
        raise Silo4Error(f"position_foot_in_base has shape {feet.shape}, expected ({n}, 4, 3)")
    r = support_split(robot, q, contact, feet, load, gravity, nonnegative, share)
    motion = motion_torques(
        robot, q, qd, qdd, gravity=gravity, method=method, num_threads=num_threads
    )
    support = support_torques(robot, q, r.force)
    return JointTorques(
        motion=motion,
        support=support,
        total=motion + support,
        reactions=r.force,
        unloadable=r.unloadable,
        corrected=r.corrected,
    )


def benchmark_torques(
    robot: Robot,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    contact: np.ndarray | None = None,
    repeats: int = 3,
) -> dict[str, float]:
    """Wall time [s] of the torque computation over N samples, best of ``repeats``.

    Returns a JSON-able dict: samples, rnea_batch_s (motion torques by pin.rneaInParallel,
    1 thread), closed_form_s (vectorised Lagrange), rnea_loop_s (per-sample pin.rnea in a
    Python loop), loop_over_batch (ratio), and with ``contact`` (N, 4) joint_torques_s
    (the whole :func:`joint_torques`: reactions + motion + support, load "body").
    """
    q, qd, qdd = (np.asarray(a, dtype=float) for a in (q, qd, qdd))
    q_pin, v_pin, a_pin = (robot.to_pinocchio_q(a) for a in (q, qd, qdd))

    def best(fn: Callable[[], object]) -> float:
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
        return min(times)

    data = robot.model.createData()

    def loop() -> None:
        for i in range(q.shape[0]):
            pin.rnea(robot.model, data, q_pin[i], v_pin[i], a_pin[i])

    out = {
        "samples": float(q.shape[0]),
        "rnea_batch_s": best(lambda: motion_torques(robot, q, qd, qdd, method="rnea")),
        "closed_form_s": best(lambda: motion_torques(robot, q, qd, qdd, method="closed_form")),
        "rnea_loop_s": best(loop),
    }
    out["loop_over_batch"] = out["rnea_loop_s"] / out["rnea_batch_s"]
    if contact is not None:
        out["joint_torques_s"] = best(lambda: joint_torques(robot, q, qd, qdd, contact))
    return out
