"""Closed-form kinematics of one insect leg (thesis Ch. 3), vectorised over N samples.

All functions take URDF joint values ``q: (N, 3)`` [rad] (or (3,)) and a :class:`LegGeometry`;
inside they work with the thesis's DH angles ``theta = axis_sign * q + zero_offset``
(geometry.py). Positions are the foot in the base frame B [m]; derivatives are with respect
to the URDF joint values.

Equations (docs/errata.md lists where the printed thesis is wrong):
    FK            eq 3.5
    IK            eq 3.10-3.24, knee-down, solved in atan2/acos form (3.21-3.22 divide by
                  zero at A + C = 0), theta1 wrapped to (-pi, pi] (3.10), theta3 per corrected 3.24
    Jacobian      eq 3.26-3.35
    dJ/dt         eq 3.37-3.45 (3.45 is dJ(3,3), printed as J(3,3))
    det J         eq 3.46
    q, q', q''    eq 3.10-3.24, 3.25 and 3.36 fused for many samples (:func:`joint_motion`)

FK, the Jacobians and the rates live here; the knee-down IK is silo4kin/knee_down_ik.py and
the fused sampling kernel silo4kin/joint_motion.py, both re-exported.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .geometry import LegGeometry
from .joint_motion import JointMotion, Vectors, joint_motion
from .knee_down_ik import (
    IK_COS_SLACK,
    IKResult,
    KneeDownLegs,
    KneeDownTerms,
    _as_2d,
    inverse_kinematics,
    inverse_kinematics_masked,
    knee_down_dh_angles,
    knee_down_ik_of_legs,
    knee_down_terms,
)

__all__ = [
    "IK_COS_SLACK",
    "IKResult",
    "JointMotion",
    "KneeDownLegs",
    "KneeDownTerms",
    "SingularityDistance",
    "Vectors",
    "forward_kinematics",
    "foot_velocity",
    "inverse_kinematics",
    "inverse_kinematics_masked",
    "jacobian",
    "jacobian_derivative",
    "jacobian_determinant",
    "joint_acceleration",
    "joint_motion",
    "joint_velocity",
    "knee_down_dh_angles",
    "knee_down_ik_of_legs",
    "knee_down_terms",
    "singularity_distance",
]


def _planar(leg: LegGeometry, theta: np.ndarray) -> tuple[np.ndarray, ...]:
    """Shared terms: phi = theta_b + theta1, rho (radial reach from the hip axis), sines."""
    t1, t2, t3 = theta[:, 0], theta[:, 1], theta[:, 2]
    phi = leg.theta_b + t1
    c2, s2 = np.cos(t2), np.sin(t2)
    c23, s23 = np.cos(t2 + t3), np.sin(t2 + t3)
    rho = leg.L1 + leg.L2 * c2 + leg.L3 * c23
    return phi, c2, s2, c23, s23, rho


def forward_kinematics(leg: LegGeometry, q: np.ndarray) -> np.ndarray:
    """Foot position in the base frame, eq 3.5.

    Args:
        leg: leg geometry.
        q: joint values [rad], shape (N, 3) or (3,).

    Returns:
        position_foot_in_base [m], shape (N, 3) or (3,).
    """
    q2, single = _as_2d(q)
    theta = leg.joint_to_dh(q2)
    phi, c2, s2, c23, s23, rho = _planar(leg, theta)
    p = np.empty_like(theta)
    p[:, 0] = leg.position_hip_in_base[0] + np.cos(phi) * rho
    p[:, 1] = leg.position_hip_in_base[1] + np.sin(phi) * rho
    p[:, 2] = leg.position_hip_in_base[2] + leg.L2 * s2 + leg.L3 * s23
    return p[0] if single else p


def jacobian(leg: LegGeometry, q: np.ndarray) -> np.ndarray:
    """Foot linear-velocity Jacobian in the base frame, eq 3.26-3.35: dp/dt = J dq/dt.

    The thesis writes each entry in product-to-sum form; this is the same matrix factored by
    phi = theta_b + theta1 (tests compare both).

    Returns:
        J [m/rad], shape (N, 3, 3) or (3, 3), with respect to URDF joint values.
    """
    q2, single = _as_2d(q)
    theta = leg.joint_to_dh(q2)
    phi, c2, s2, c23, s23, rho = _planar(leg, theta)
    cphi, sphi = np.cos(phi), np.sin(phi)
    d_rho_2 = -leg.L2 * s2 - leg.L3 * s23  # d rho / d theta2
    d_rho_3 = -leg.L3 * s23  # d rho / d theta3
    d_z_2 = leg.L2 * c2 + leg.L3 * c23  # d z / d theta2
    d_z_3 = leg.L3 * c23  # d z / d theta3
    J = np.zeros((theta.shape[0], 3, 3))
    J[:, 0, 0] = -sphi * rho  # eq 3.27
    J[:, 1, 0] = cphi * rho  # eq 3.30
    J[:, 0, 1] = cphi * d_rho_2  # eq 3.28
    J[:, 1, 1] = sphi * d_rho_2  # eq 3.31
    J[:, 2, 1] = d_z_2  # eq 3.34
    J[:, 0, 2] = cphi * d_rho_3  # eq 3.29
    J[:, 1, 2] = sphi * d_rho_3  # eq 3.32
    J[:, 2, 2] = d_z_3  # eq 3.35
    J *= leg.axis_sign[None, None, :]
    return J[0] if single else J


def jacobian_derivative(leg: LegGeometry, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Time derivative of the Jacobian, eq 3.37-3.45: p'' = J q'' + dJ q'  (eq 3.36).

    Args:
        q: joint values [rad], shape (N, 3) or (3,).
        qd: joint velocities [rad/s], same shape.

    Returns:
        dJ/dt [m/(rad s)], shape (N, 3, 3) or (3, 3).
    """
    q2, single = _as_2d(q)
    qd2, _ = _as_2d(qd)
    theta = leg.joint_to_dh(q2)
    td = leg.axis_sign * qd2
    phi, c2, s2, c23, s23, rho = _planar(leg, theta)
    cphi, sphi = np.cos(phi), np.sin(phi)
    w1, w2, w23 = td[:, 0], td[:, 1], td[:, 1] + td[:, 2]
    d_rho_2 = -leg.L2 * s2 - leg.L3 * s23
    d_rho_3 = -leg.L3 * s23
    rho_dot = d_rho_2 * td[:, 1] + d_rho_3 * td[:, 2]
    d_rho_2_dot = -leg.L2 * c2 * w2 - leg.L3 * c23 * w23
    d_rho_3_dot = -leg.L3 * c23 * w23
    d_z_2_dot = -leg.L2 * s2 * w2 - leg.L3 * s23 * w23  # eq 3.44
    d_z_3_dot = -leg.L3 * s23 * w23  # eq 3.45 (dJ(3,3))
    Jd = np.zeros((theta.shape[0], 3, 3))
    Jd[:, 0, 0] = -cphi * w1 * rho - sphi * rho_dot  # eq 3.37
    Jd[:, 1, 0] = -sphi * w1 * rho + cphi * rho_dot  # eq 3.40
    Jd[:, 0, 1] = -sphi * w1 * d_rho_2 + cphi * d_rho_2_dot  # eq 3.38
    Jd[:, 1, 1] = cphi * w1 * d_rho_2 + sphi * d_rho_2_dot  # eq 3.41
    Jd[:, 2, 1] = d_z_2_dot
    Jd[:, 0, 2] = -sphi * w1 * d_rho_3 + cphi * d_rho_3_dot  # eq 3.39
    Jd[:, 1, 2] = cphi * w1 * d_rho_3 + sphi * d_rho_3_dot  # eq 3.42
    Jd[:, 2, 2] = d_z_3_dot
    Jd *= leg.axis_sign[None, None, :]
    return Jd[0] if single else Jd


def jacobian_determinant(leg: LegGeometry, q: np.ndarray) -> np.ndarray:
    """det J = -L2 L3 sin(theta3) (L1 + L2 cos theta2 + L3 cos(theta2 + theta3)), eq 3.46.

    Zero at the knee singularity (theta3 = 0 or pi: leg stretched or folded) and when the
    foot is above the hip-yaw axis (rho = 0). Sign includes the URDF axis signs.

    Returns:
        det J [m^2/rad^3], shape (N,) or ().
    """
    q2, single = _as_2d(q)
    theta = leg.joint_to_dh(q2)
    _, _, _, _, _, rho = _planar(leg, theta)
    det = -leg.L2 * leg.L3 * np.sin(theta[:, 2]) * rho * np.prod(leg.axis_sign)
    return det[0] if single else det


class SingularityDistance(NamedTuple):
    """How far a leg configuration is from the two singularities of eq 3.46.

    Attributes:
        knee_rad: angular distance of theta3 from 0 or ±pi (stretched / folded) [rad], (N,).
        radial_m: signed horizontal distance of the foot from the hip-yaw axis along the leg's
            direction (rho of eq 3.46) [m], (N,); negative when the foot is behind the axis.
    """

    knee_rad: np.ndarray
    radial_m: np.ndarray


def singularity_distance(leg: LegGeometry, q: np.ndarray) -> SingularityDistance:
    """Distance to the singular configurations of eq 3.46 (see :class:`SingularityDistance`)."""
    q2, single = _as_2d(q)
    theta = leg.joint_to_dh(q2)
    _, _, _, _, _, rho = _planar(leg, theta)
    t3 = np.abs(np.arctan2(np.sin(theta[:, 2]), np.cos(theta[:, 2])))
    knee = np.minimum(t3, np.pi - t3)
    if single:
        return SingularityDistance(knee[0], rho[0])
    return SingularityDistance(knee, rho)


def foot_velocity(leg: LegGeometry, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Foot linear velocity in the base frame, eq 3.25 [m/s], shape like q."""
    return np.einsum("...ij,...j->...i", jacobian(leg, q), qd)


def joint_velocity(
    leg: LegGeometry, q: np.ndarray, foot_velocity_in_base: np.ndarray
) -> np.ndarray:
    """q' = J^-1 p' (eq 3.25 solved) [rad/s], shape like q."""
    return np.linalg.solve(jacobian(leg, q), np.asarray(foot_velocity_in_base)[..., None])[..., 0]


def joint_acceleration(
    leg: LegGeometry, q: np.ndarray, qd: np.ndarray, foot_acceleration_in_base: np.ndarray
) -> np.ndarray:
    """q'' = J^-1 (p'' - dJ q') (eq 3.36 solved) [rad/s^2], shape like q."""
    jdqd = np.einsum("...ij,...j->...i", jacobian_derivative(leg, q, qd), qd)
    rhs = np.asarray(foot_acceleration_in_base) - jdqd
    return np.linalg.solve(jacobian(leg, q), rhs[..., None])[..., 0]
