"""Closed form against Pinocchio: the report behind ``silo4 check``.

For each leg and quantity, the largest deviation over ``n`` seeded random configurations
inside the joint limits (velocities and accelerations standard normal [rad/s], [rad/s^2]):

    quantity      closed form                        Pinocchio (fixed base)
    fk            kinematics.forward_kinematics      oMf[foot].translation
    jacobian      kinematics.jacobian                getFrameJacobian(LOCAL_WORLD_ALIGNED)
    jdot_qd       kinematics.jacobian_derivative @ qd getFrameClassicalAcceleration (a = 0)
    ik            inverse_kinematics(foot_pin)       the sampled q (where IK is unique: foot
                                                     outside the yaw axis, knee not straight)

Mammal legs (mammal.py) get the fk, jacobian, jdot_qd and ik rows (IK on the sampled q's own
knee branch); their dynamics has no closed form here, Pinocchio's RNEA is the only model.
    mass          dynamics.mass_matrix               crba (upper triangle, symmetrised)
    coriolis      dynamics.coriolis_vector           computeCoriolisMatrix @ v
    gravity       dynamics.gravity_vector            computeGeneralizedGravity
    rnea          dynamics.inverse_dynamics          rnea

Tolerances are named constants below, each with its reason.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from . import dynamics, kinematics, mammal
from .geometry import LegGeometry
from .mammal import MammalLegGeometry
from .robot import Robot

#: Foot position [m]: both sides are a handful of products of O(0.5 m) terms, rounding
#: ~1e-16; the issue asks for 1e-12 m.
FK_TOLERANCE = 1e-12
#: Jacobian [m/rad]: same magnitudes as FK.
JACOBIAN_TOLERANCE = 1e-12
#: J̇q̇ [m/s^2] with |q̇| ~ 1 rad/s: terms O(1) m/s^2, a few more roundings than J.
JDOT_TOLERANCE = 1e-11
#: IK [rad] on Pinocchio's foot positions vs the sampled q: acos amplifies rounding by
#: 1 / |sin theta3|, at most 1e3 on the compared samples (|theta3| > IK_UNIQUE_MIN_KNEE).
IK_TOLERANCE = 1e-9
#: IK is compared only where the knee-down solution is unique and well conditioned:
#: |theta3| > 1 mrad from the stretched knee and the foot > 1 mm outside the yaw axis
#: (a foot behind the yaw axis has the same position with theta1 +- pi, outside the limits).
IK_UNIQUE_MIN_KNEE = 1e-3
IK_UNIQUE_MIN_RADIAL = 1e-3
#: Mass matrix [kg m^2]: entries O(0.1-1).
MASS_TOLERANCE = 1e-12
#: Torques [N m]: entries O(10) (gravity on 3 kg at 0.3 m), |q̈| ~ 1.
TORQUE_TOLERANCE = 1e-10

TOLERANCES: dict[str, float] = {
    "fk": FK_TOLERANCE,
    "jacobian": JACOBIAN_TOLERANCE,
    "jdot_qd": JDOT_TOLERANCE,
    "ik": IK_TOLERANCE,
    "mass": MASS_TOLERANCE,
    "coriolis": TORQUE_TOLERANCE,
    "gravity": TORQUE_TOLERANCE,
    "rnea": TORQUE_TOLERANCE,
}
UNITS = {
    "fk": "m",
    "jacobian": "m/rad",
    "jdot_qd": "m/s^2",
    "ik": "rad",
    "mass": "kg m^2",
    "coriolis": "N m",
    "gravity": "N m",
    "rnea": "N m",
}


@dataclass(frozen=True)
class CheckRow:
    """One line of the report: the worst deviation of one quantity on one leg."""

    quantity: str
    leg: str
    max_deviation: float
    tolerance: float

    @property
    def ok(self) -> bool:
        return bool(self.max_deviation <= self.tolerance)


@dataclass(frozen=True)
class PinocchioSamples:
    """Pinocchio's values on random states, in our joint order.

    Shapes: q, v, a (n, 12); foot (n, 4, 3); jacobian (n, 4, 3, 3); jdot_qd (n, 4, 3);
    mass (n, 12, 12); coriolis, gravity, rnea (n, 12).
    """

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    foot: np.ndarray
    jacobian: np.ndarray
    jdot_qd: np.ndarray
    mass: np.ndarray
    coriolis: np.ndarray
    gravity: np.ndarray
    rnea: np.ndarray


def random_states(robot: Robot, n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """q uniform inside the joint limits, v and a standard normal; each (n, 12), our order."""
    rng = np.random.default_rng(seed)
    lower = np.concatenate([leg.q_lower for leg in robot.legs])
    upper = np.concatenate([leg.q_upper for leg in robot.legs])
    q = rng.uniform(lower, upper, size=(n, 12))  # ANYmal: ±3π, every turn of the joint
    return q, rng.standard_normal((n, 12)), rng.standard_normal((n, 12))


def pinocchio_samples(
    robot: Robot, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> PinocchioSamples:
    """Evaluate Pinocchio on each state (the reference; a per-sample loop by nature)."""
    model = robot.model
    data = model.createData()
    n = q.shape[0]
    idx = robot.q_index
    fids = [model.getFrameId(leg.foot_frame) for leg in robot.legs]
    foot = np.empty((n, 4, 3))
    jac = np.empty((n, 4, 3, 3))
    jdqd = np.empty((n, 4, 3))
    mass = np.empty((n, 12, 12))
    cor = np.empty((n, 12))
    grav = np.empty((n, 12))
    tau = np.empty((n, 12))
    frame = pin.LOCAL_WORLD_ALIGNED
    for i in range(n):
        qp, vp, ap = (
            robot.to_pinocchio_q(q[i]),
            robot.to_pinocchio_q(v[i]),
            robot.to_pinocchio_q(a[i]),
        )
        pin.forwardKinematics(model, data, qp, vp, np.zeros(model.nv))
        pin.updateFramePlacements(model, data)
        pin.computeJointJacobians(model, data, qp)
        for k, fid in enumerate(fids):
            foot[i, k] = data.oMf[fid].translation
            jac[i, k] = pin.getFrameJacobian(model, data, fid, frame)[:3, idx[3 * k : 3 * k + 3]]
            jdqd[i, k] = pin.getFrameClassicalAcceleration(model, data, fid, frame).linear
        m = pin.crba(model, data, qp)
        m = np.triu(m) + np.triu(m, 1).T
        mass[i] = m[np.ix_(idx, idx)]
        cor[i] = (pin.computeCoriolisMatrix(model, data, qp, vp) @ vp)[idx]
        grav[i] = pin.computeGeneralizedGravity(model, data, qp)[idx]
        tau[i] = pin.rnea(model, data, qp, vp, ap)[idx]
    return PinocchioSamples(q, v, a, foot, jac, jdqd, mass, cor, grav, tau)


def compare_leg(
    leg: LegGeometry, k: int, ref: PinocchioSamples, gravity: float
) -> dict[str, float]:
    """Max |closed form - Pinocchio| per quantity for leg number k (columns 3k..3k+2)."""
    sl = slice(3 * k, 3 * k + 3)
    q, v, a = ref.q[:, sl], ref.v[:, sl], ref.a[:, sl]
    p = kinematics.forward_kinematics(leg, q)
    jdqd = np.einsum("nij,nj->ni", kinematics.jacobian_derivative(leg, q, v), v)
    q_ik = kinematics.inverse_kinematics_masked(leg, ref.foot[:, k]).q
    dist = kinematics.singularity_distance(leg, q)
    unique = (dist.knee_rad > IK_UNIQUE_MIN_KNEE) & (dist.radial_m > IK_UNIQUE_MIN_RADIAL)
    out = {
        "fk": np.abs(p - ref.foot[:, k]).max(),
        "jacobian": np.abs(kinematics.jacobian(leg, q) - ref.jacobian[:, k]).max(),
        "jdot_qd": np.abs(jdqd - ref.jdot_qd[:, k]).max(),
        "ik": np.nan_to_num(np.abs(q_ik - q)[unique], nan=np.inf).max(initial=0.0),
        "mass": np.abs(dynamics.mass_matrix(leg, q) - ref.mass[:, sl, sl]).max(),
        "coriolis": np.abs(dynamics.coriolis_vector(leg, q, v) - ref.coriolis[:, sl]).max(),
        "gravity": np.abs(dynamics.gravity_vector(leg, q, gravity) - ref.gravity[:, sl]).max(),
        "rnea": np.abs(dynamics.inverse_dynamics(leg, q, v, a, gravity) - ref.rnea[:, sl]).max(),
    }
    return {key: float(val) for key, val in out.items()}


#: Mammal legs: the closed form assumes the HAA axis exactly along x and the two pitch axes
#: exactly parallel. URDFs write these rotations with ~11 digits (HyQ: π/2 as 1.57079632679,
#: axes off by 5e-12 rad), which moves the foot by misalignment x leg size. The tolerance of
#: a mammal leg's rows grows by MISALIGNMENT_GAIN x misalignment [rad] x leg size [m] (J̇q̇:
#: x 10 more, |q̇|² ~ 10), far below anything physical.
MISALIGNMENT_GAIN = 10.0
#: IK of a mammal leg is compared where |cos θ3| and the foot's distance from the HAA axis are
#: this far from degenerate (mammal.ik_is_unique) [-], [m²].
IK_MAMMAL_MARGIN = 1e-6
#: Rows a mammal leg has (no closed-form Lagrange dynamics for this family: RNEA is Pinocchio's).
MAMMAL_QUANTITIES = ("fk", "jacobian", "jdot_qd", "ik")


def compare_mammal_leg(leg: MammalLegGeometry, k: int, ref: PinocchioSamples) -> dict[str, float]:
    """Max |closed form - Pinocchio| of fk, jacobian, jdot_qd, ik for mammal leg k.

    IK is compared on the sampled q's own knee branch and foot side, modulo 2π (ANYmal's
    joints turn ±3π),
    where it is unique: knee not stretched or folded flat, foot off the HAA axis.
    """
    sl = slice(3 * k, 3 * k + 3)
    q, v = ref.q[:, sl], ref.v[:, sl]
    foot = ref.foot[:, k]
    q_ik = mammal.inverse_kinematics(
        leg, foot, mammal.branch_of(leg, q[:, 2]), mammal.foot_side_of(leg, q)
    ).q
    unique = mammal.ik_is_unique(leg, foot, IK_MAMMAL_MARGIN)
    diff = np.angle(np.exp(1j * (q_ik - q)))
    out = {
        "fk": np.abs(mammal.forward_kinematics(leg, q) - foot).max(),
        "jacobian": np.abs(mammal.jacobian(leg, q) - ref.jacobian[:, k]).max(),
        "jdot_qd": np.abs(
            mammal.jacobian_derivative_times_velocity(leg, q, v) - ref.jdot_qd[:, k]
        ).max(),
        "ik": np.nan_to_num(np.abs(diff)[unique], nan=np.inf).max(initial=0.0),
    }
    return {key: float(val) for key, val in out.items()}


def _tolerance(leg: LegGeometry | MammalLegGeometry, quantity: str) -> float:
    base = TOLERANCES[quantity]
    if not isinstance(leg, MammalLegGeometry):
        return base
    if quantity == "ik":  # [rad]: acos amplifies by up to 1/sqrt(margin) near the margin
        return base + MISALIGNMENT_GAIN * leg.axis_misalignment_rad / np.sqrt(IK_MAMMAL_MARGIN)
    slack = MISALIGNMENT_GAIN * leg.axis_misalignment_rad * leg.size_m
    return base + slack * (10.0 if quantity == "jdot_qd" else 1.0)


def cross_check(
    robot: Robot, n: int = 1000, seed: int = 0, legs: Sequence[LegGeometry] | None = None
) -> list[CheckRow]:
    """Closed form vs Pinocchio on ``n`` random states; one row per quantity and leg.

    Args:
        robot: the loaded robot (Pinocchio side).
        n: number of random states.
        seed: random seed.
        legs: leg geometries for the closed-form side (default: robot.legs); pass perturbed
            ones to see the check fail.
    """
    q, v, a = random_states(robot, n, seed)
    ref = pinocchio_samples(robot, q, v, a)
    gravity = float(np.linalg.norm(robot.model.gravity.linear))
    rows = []
    for k, leg in enumerate(legs if legs is not None else robot.legs):
        devs = (
            compare_mammal_leg(leg, k, ref)
            if isinstance(leg, MammalLegGeometry)
            else compare_leg(leg, k, ref, gravity)
        )
        for quantity, dev in devs.items():
            rows.append(CheckRow(quantity, leg.name, dev, _tolerance(leg, quantity)))
    return rows


def format_report(rows: Sequence[CheckRow]) -> str:
    """A plain-text table: quantity x leg, max deviation, tolerance, verdict."""
    legs = list(dict.fromkeys(r.leg for r in rows))
    quantities = list(dict.fromkeys(r.quantity for r in rows))
    table = {(r.quantity, r.leg): r for r in rows}
    head = (
        f"{'quantity':<10}{'unit':<8}"
        + "".join(f"{leg:>11}" for leg in legs)
        + f"{'tolerance':>12}  verdict"
    )
    lines = [head, "-" * len(head)]
    for qty in quantities:
        cells = [table[(qty, leg)] for leg in legs]
        ok = all(c.ok for c in cells)
        lines.append(
            f"{qty:<10}{UNITS[qty]:<8}"
            + "".join(f"{c.max_deviation:>11.2e}" for c in cells)
            + f"{cells[0].tolerance:>12.0e}  {'ok' if ok else 'FAIL'}"
        )
    return "\n".join(lines)
