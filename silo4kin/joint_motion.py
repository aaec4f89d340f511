"""q, q', q'' of many foot states of one insect leg in one fused pass (thesis eq 3.10-3.24,
3.25, 3.36): the planner's sampling kernel (:func:`joint_motion`)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .geometry import LegGeometry
from .knee_down_ik import knee_down_terms


class JointMotion(NamedTuple):
    """Joint values and their time derivatives for many foot samples of one leg.

    Attributes:
        q: joint values [rad], shape (N, 3); NaN where unreachable.
        qd: joint velocities [rad/unit], shape (N, 3); NaN where unreachable.
        qdd: joint accelerations [rad/unit^2], shape (N, 3); NaN where unreachable.
        reachable: True where the target is within the leg's reach, shape (N,).
    """

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    reachable: np.ndarray


#: Per-sample vectors for :func:`joint_motion`: an (N, 3) array or its (x, y, z) columns.
Vectors = np.ndarray | tuple[np.ndarray, np.ndarray, np.ndarray]


def _columns(v: Vectors) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x, y, z of an (N, 3) array, or of a 3-tuple of (N,) component arrays."""
    if isinstance(v, (tuple, list)):
        return v[0], v[1], v[2]
    v = np.asarray(v, dtype=float)
    return v[:, 0], v[:, 1], v[:, 2]


def joint_motion(
    leg: LegGeometry,
    position_foot_in_base: Vectors,
    velocity_foot_in_base: Vectors,
    acceleration_foot_in_base: Vectors,
    out: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> JointMotion:
    """q = IK(p) (eq 3.10-3.24), q' = J^-1 p' (3.25), q'' = J^-1 (p'' - dJ q') (3.36), fused.

    The same results as :func:`inverse_kinematics_masked`, :func:`joint_velocity` and
    :func:`joint_acceleration` (to rounding), from one evaluation of the shared terms and no
    trigonometric call besides the IK angles: the planner samples tens of thousands of foot
    states per leg. In the leg's cylindrical frame (e_r, e_t, e_z) at phi = theta_b + theta1,
    with rho the radial reach of eq 3.5 (cos phi = x / rho, sin phi = y / rho from the hip),
    r = rho - L1 and z the height of the foot above the hip, the Jacobian of eq 3.26-3.35 is
    block diagonal:

        v_t = rho theta1'
        [v_r, v_z] = [[-z, -L3 s23], [r, L3 c23]] [theta2', theta3']
        (eq 3.28/3.31 give -z = d rho/d theta2, eq 3.34 gives r = dz/d theta2),

    whose 2x2 determinant is L2 L3 sin theta3 (eq 3.46 without the factor rho). dJ q' of
    eq 3.37-3.45 becomes the centripetal and Coriolis terms of the rotating frame:

        a_t = rho theta1'' + 2 v_r theta1'
        a_r = [-z, -L3 s23] theta'' - rho theta1'^2 - L2 c2 theta2'^2 - L3 c23 (theta2' + theta3')^2
        a_z = [r, L3 c23] theta'' - L2 s2 theta2'^2 - L3 s23 (theta2' + theta3')^2

    Time derivatives are per whatever time unit the inputs use. Singular rows (rho = 0 or
    sin theta3 = 0) give inf or NaN rates, which callers detect with np.isfinite.

    Args:
        position_foot_in_base: targets p [m], shape (N, 3), or a 3-tuple (x, y, z) of (N,).
        velocity_foot_in_base: p' [m/unit], the same form.
        acceleration_foot_in_base: p'' [m/unit^2], the same form.
        out: optional (q, qd, qdd) arrays (N, 3) (views allowed) to write the results into.
    """
    px, py, pz = _columns(position_foot_in_base)
    pd = _columns(velocity_foot_in_base)
    pdd = _columns(acceleration_foot_in_base)
    L1, L2, L3 = leg.L1, leg.L2, leg.L3
    hip = leg.position_hip_in_base
    x, y, z = px - hip[0], py - hip[1], pz - hip[2]
    if out is None:
        out = (np.empty((x.shape[0], 3)), np.empty((x.shape[0], 3)), np.empty((x.shape[0], 3)))
    q, qd, qdd = out
    with np.errstate(divide="ignore", invalid="ignore"):
        # IK (eq 3.10-3.24): the one knee-down kernel, and its planar terms
        t = knee_down_terms(x, y, z, leg.theta_b, L1, L2, L3)
        theta1, theta2, theta3, reachable = t.theta1, t.theta2, t.theta3, t.reachable
        rho, r, c3, s3, kx, ky, num_c, num_s = (
            t.rho,
            t.r,
            t.c3,
            t.s3,
            t.kx,
            t.ky,
            t.num_c,
            t.num_s,
        )
        r2 = r * r + z * z
        norm = np.sqrt(r2 * (kx * kx + ky * ky))
        c2, s2 = num_c / norm, num_s / norm
        c23, s23 = c2 * c3 - s2 * s3, s2 * c3 + c2 * s3
        # velocities (eq 3.25) in the cylindrical frame
        cphi, sphi = x / rho, y / rho
        v_r = cphi * pd[0] + sphi * pd[1]
        v_t = cphi * pd[1] - sphi * pd[0]
        v_z = pd[2]
        inv_det = 1.0 / (L2 * L3 * s3)
        w1 = v_t / rho
        w2 = (L3 * c23 * v_r + L3 * s23 * v_z) * inv_det
        w3 = -(r * v_r + z * v_z) * inv_det
        # accelerations (eq 3.36 with dJ q' of eq 3.37-3.45)
        w23 = w2 + w3
        a_r = cphi * pdd[0] + sphi * pdd[1]
        a_t = cphi * pdd[1] - sphi * pdd[0]
        rhs_r = a_r + rho * w1 * w1 + L2 * c2 * w2 * w2 + L3 * c23 * w23 * w23
        rhs_z = pdd[2] + L2 * s2 * w2 * w2 + L3 * s23 * w23 * w23
        sign, offset = leg.axis_sign, leg.zero_offset
        for j, (theta, rate, acc) in enumerate(
            (
                (theta1, w1, (a_t - 2.0 * v_r * w1) / rho),
                (theta2, w2, (L3 * c23 * rhs_r + L3 * s23 * rhs_z) * inv_det),
                (theta3, w3, -(r * rhs_r + z * rhs_z) * inv_det),
            )
        ):
            q[:, j] = (theta - offset[j]) * sign[j]  # dh_to_joint
            qd[:, j] = sign[j] * rate
            qdd[:, j] = sign[j] * acc
    bad = ~reachable
    if bad.any():
        q[bad] = np.nan
        qd[bad] = np.nan
        qdd[bad] = np.nan
    return JointMotion(q, qd, qdd, reachable)
