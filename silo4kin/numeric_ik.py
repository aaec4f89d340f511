"""Numeric inverse kinematics of one leg: Pinocchio damped least squares within joint limits.

The fallback for a 3-DoF leg of no known family, and an independent reference for the two
closed forms (kinematics.py for insect legs, mammal.py for mammal legs): tests/test_mammal.py
checks all three against each other. Per target, from ``q_start``:

    e = p_target - p(q)                      (foot error in the base frame [m])
    Δq = Jᵀ (J Jᵀ + λ² I)⁻¹ e                 (damped least squares, λ = DAMPING)
    q ← clip(q + Δq, q_lower, q_upper)       (joint limits as a projection)

until |e| < tolerance, restarting from seeded random in-limit starts when an attempt stalls
(a limit or a local minimum). It is a per-sample loop over Pinocchio calls by nature (Newton
iterations): the planner uses the closed forms, which are vectorised.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pinocchio as pin

#: Damping λ [m]: keeps the step bounded near a stretched knee; small enough that the
#: iteration converges quadratically away from singularities.
DAMPING = 1e-6
#: Foot position error at which a target counts as reached [m].
TOLERANCE = 1e-11
#: Iteration cap per start.
MAX_ITERATIONS = 100
#: Extra starts (seeded, uniform within the limits) tried when ``q_start`` does not converge:
#: a projected Newton step can stall against a joint limit or in the wrong basin.
RESTARTS = 12


class NumericIK(NamedTuple):
    """q: joint values [rad] (N, 3); converged: error below tolerance (N,); error: final
    foot position error [m] (N,)."""

    q: np.ndarray
    converged: np.ndarray
    error: np.ndarray


def dls_inverse_kinematics(
    robot: object,
    leg_index: int,
    position_foot_in_base: np.ndarray,
    q_start: np.ndarray,
    tolerance: float = TOLERANCE,
    max_iterations: int = MAX_ITERATIONS,
) -> NumericIK:
    """Joint values of leg ``leg_index`` putting its foot at each target.

    Args:
        robot: a loaded ``silo4kin.robot.Robot`` (any leg family).
        leg_index: 0..3 in the order LF, RF, LH, RH.
        position_foot_in_base: targets in the base (URDF root) frame [m], (N, 3).
        q_start: initial joint values [rad], (3,) or (N, 3).
    """
    model = robot.model  # type: ignore[attr-defined]
    leg = robot.legs[leg_index]  # type: ignore[attr-defined]
    data = model.createData()
    idx_q = np.array([model.joints[model.getJointId(n)].idx_q for n in leg.joint_names])
    fid = model.getFrameId(leg.foot_frame)
    targets = np.atleast_2d(np.asarray(position_foot_in_base, dtype=float))
    n = targets.shape[0]
    start = np.broadcast_to(np.asarray(q_start, dtype=float), (n, 3))
    lower, upper = leg.q_lower, leg.q_upper
    q_out = np.empty((n, 3))
    err_out = np.empty(n)
    q_full = pin.neutral(model)
    rng = np.random.default_rng(0)
    # wide limits (ANYmal's ±3π) sample one turn around the middle
    mid = 0.5 * (lower + upper)
    lo, hi = np.maximum(lower, mid - np.pi), np.minimum(upper, mid + np.pi)
    extra_starts = rng.uniform(lo, hi, size=(RESTARTS, 3))

    def solve(target: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, float]:
        q = np.clip(q, lower, upper)
        err = np.inf
        for _ in range(max_iterations):
            q_full[idx_q] = q
            pin.framesForwardKinematics(model, data, q_full)
            e = target - data.oMf[fid].translation
            err = float(np.linalg.norm(e))
            if err < tolerance:
                break
            jac = pin.computeFrameJacobian(model, data, q_full, fid, pin.LOCAL_WORLD_ALIGNED)[
                :3, idx_q
            ]
            step = jac.T @ np.linalg.solve(jac @ jac.T + DAMPING**2 * np.eye(3), e)
            q = np.clip(q + step, lower, upper)
        return q, err

    for i in range(n):
        q, err = solve(targets[i], start[i])
        for alternative in extra_starts:
            if err < tolerance:
                break
            q, err = solve(targets[i], alternative)
        q_out[i], err_out[i] = q, err
    return NumericIK(q_out, err_out < tolerance, err_out)
