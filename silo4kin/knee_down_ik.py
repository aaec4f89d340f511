"""Knee-down inverse kinematics of insect legs (thesis eq 3.10-3.24, corrected), vectorised.

:func:`knee_down_terms` is the one implementation; :func:`knee_down_dh_angles` gives its DH
angles, :func:`inverse_kinematics_masked` / :func:`inverse_kinematics` one leg's URDF joint
values, :func:`knee_down_ik_of_legs` several legs' in one pass, and
silo4kin/joint_motion.py reuses its planar terms for q', q''. tests/test_leg_kernels.py
checks they agree bit for bit and round-trip Pinocchio's FK.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .errors import UnreachableTargetError
from .geometry import LegGeometry

#: Slack on the law of cosines in IK [dimensionless]: a target at full stretch computed by
#: FK lands at |cos| = 1 + O(1e-16); 1e-9 accepts it without accepting real misses (1e-9 of
#: cos near 1 is ~ 45 µrad of knee angle, ~ 10 µm of reach at SILO4's size).
IK_COS_SLACK = 1e-9


def _as_2d(x: np.ndarray) -> tuple[np.ndarray, bool]:
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        return x[None, :], True
    return x, False


class IKResult(NamedTuple):
    """Batch inverse kinematics.

    Attributes:
        q: joint values [rad], shape (N, 3); NaN where unreachable.
        reachable: True where the target is within the leg's reach, shape (N,).
    """

    q: np.ndarray
    reachable: np.ndarray


class KneeDownLegs(NamedTuple):
    """Per-leg constants of :func:`knee_down_ik_of_legs`, one row per leg (L legs).

    Attributes:
        hip: position_hip_in_base [m], shape (L, 3).
        theta_b: rest directions [rad], shape (L,).
        lengths: (L1, L2, L3) [m], shape (L, 3).
        zero_offset, axis_sign: the DH map of each leg (geometry.py), shape (L, 3).
    """

    hip: np.ndarray
    theta_b: np.ndarray
    lengths: np.ndarray
    zero_offset: np.ndarray
    axis_sign: np.ndarray

    @classmethod
    def of(cls, legs: tuple[LegGeometry, ...]) -> KneeDownLegs:
        """The table of ``legs`` (insect legs)."""
        return cls(
            hip=np.array([leg.position_hip_in_base for leg in legs], dtype=float),
            theta_b=np.array([leg.theta_b for leg in legs], dtype=float),
            lengths=np.array([(leg.L1, leg.L2, leg.L3) for leg in legs], dtype=float),
            zero_offset=np.array([leg.zero_offset for leg in legs], dtype=float),
            axis_sign=np.array([leg.axis_sign for leg in legs], dtype=float),
        )


class KneeDownTerms(NamedTuple):
    """The knee-down IK's angles and the planar terms :func:`joint_motion` reuses, (N,) each.

    Attributes:
        theta1, theta2, theta3: DH angles [rad] (not masked: NaN or clipped where unreachable).
        reachable: |cos theta3| within 1 + IK_COS_SLACK.
        rho: radial reach from the hip-yaw axis [m]; r = rho - L1 [m]; z: height [m].
        c3, s3: cos and sin of theta3 (s3 <= 0, knee down).
        kx, ky: L2 + L3 c3 and L3 s3 [m]; num_c, num_s: the atan2 arguments of theta2 [m^2].
    """

    theta1: np.ndarray
    theta2: np.ndarray
    theta3: np.ndarray
    reachable: np.ndarray
    rho: np.ndarray
    r: np.ndarray
    z: np.ndarray
    c3: np.ndarray
    s3: np.ndarray
    kx: np.ndarray
    ky: np.ndarray
    num_c: np.ndarray
    num_s: np.ndarray


def knee_down_terms(
    x: np.ndarray,
    y: np.ndarray,
    z: np.ndarray,
    theta_b: np.ndarray | float,
    l1: np.ndarray | float,
    l2: np.ndarray | float,
    l3: np.ndarray | float,
) -> KneeDownTerms:
    """The one knee-down IK of an insect leg, eq 3.10-3.24 (corrected), on the foot target
    minus the hip-yaw joint position (x, y, z) in B [m] (N,):

    theta1 = atan2(cb y - sb x, cb x + sb y), cb, sb = cos, sin theta_b  (eq 3.10, wrapped
    to (-pi, pi] by the one atan2 of the target turned by -theta_b);
    r = rho - L1 and z are the planar target of links 2-3 (eq 3.11-3.13);
    theta3 = -acos(D), D = (r^2 + z^2 - L2^2 - L3^2) / (2 L2 L3), knee-down theta3 <= 0;
    theta2 = atan2(z, r) - atan2(L3 sin theta3, L2 + L3 cos theta3), as the one atan2
    atan2(z kx - r ky, r kx + z ky) (the "+" root of 3.21 and the corrected 3.24, without
    dividing by A + C). The leg constants are scalars (one leg) or (N,) arrays."""
    cb, sb = np.cos(theta_b), np.sin(theta_b)
    theta1 = np.arctan2(cb * y - sb * x, cb * x + sb * y)
    rho = np.sqrt(x * x + y * y)
    r = rho - l1
    cos3 = (r * r + z * z - l2 * l2 - l3 * l3) / (2.0 * l2 * l3)
    reachable = np.abs(cos3) <= 1.0 + IK_COS_SLACK
    c3 = np.minimum(np.maximum(cos3, -1.0), 1.0)  # np.clip, with less overhead
    theta3 = -np.arccos(c3)
    s3 = -np.sqrt(1.0 - c3 * c3)
    kx, ky = l2 + l3 * c3, l3 * s3
    num_c, num_s = r * kx + z * ky, z * kx - r * ky
    theta2 = np.arctan2(num_s, num_c)
    return KneeDownTerms(theta1, theta2, theta3, reachable, rho, r, z, c3, s3, kx, ky, num_c, num_s)


def knee_down_dh_angles(
    position_foot_in_hip: np.ndarray,
    theta_b: np.ndarray | float,
    l1: np.ndarray | float,
    l2: np.ndarray | float,
    l3: np.ndarray | float,
) -> IKResult:
    """The knee-down IK (:func:`knee_down_terms`) as DH angles, vectorised over targets and
    legs.

    Args:
        position_foot_in_hip: foot targets minus the hip-yaw joint position, in B [m], (N, 3).
        theta_b, l1, l2, l3: rest direction [rad] and link lengths [m], scalar or (N,).

    Returns:
        IKResult of DH angles theta (N, 3) [rad] (NaN where unreachable) and reachable (N,).
    """
    rel = position_foot_in_hip
    t = knee_down_terms(rel[:, 0], rel[:, 1], rel[:, 2], theta_b, l1, l2, l3)
    theta = np.empty((len(t.theta1), 3))
    theta[:, 0], theta[:, 1], theta[:, 2] = t.theta1, t.theta2, t.theta3
    if not t.reachable.all():
        theta[~t.reachable] = np.nan
    return IKResult(theta, t.reachable)


def knee_down_ik_of_legs(
    legs: KneeDownLegs, leg_index: np.ndarray, position_foot_in_base: np.ndarray
) -> IKResult:
    """:func:`inverse_kinematics_masked` of target i (N, 3) [m] for leg ``leg_index[i]`` of
    the table ``legs``, all legs in one pass; the same values, bit for bit
    (tests/test_kinematics.py)."""
    idx = leg_index
    lengths = legs.lengths[idx]
    dh = knee_down_dh_angles(
        position_foot_in_base - legs.hip[idx],
        legs.theta_b[idx],
        lengths[:, 0],
        lengths[:, 1],
        lengths[:, 2],
    )
    return IKResult((dh.q - legs.zero_offset[idx]) * legs.axis_sign[idx], dh.reachable)


def inverse_kinematics_masked(leg: LegGeometry, position_foot_in_base: np.ndarray) -> IKResult:
    """Knee-down inverse kinematics for many targets (:func:`knee_down_dh_angles`) in URDF
    joint values.

    Joint limits are not applied here (silo4kin.joint_limits); targets beyond reach give NaN.

    Args:
        position_foot_in_base: targets [m], shape (N, 3) or (3,).
    """
    p, single = _as_2d(position_foot_in_base)
    dh = knee_down_dh_angles(p - leg.position_hip_in_base, leg.theta_b, leg.L1, leg.L2, leg.L3)
    q = leg.dh_to_joint(dh.q)
    if single:
        return IKResult(q[0], dh.reachable[0])
    return IKResult(q, dh.reachable)


def inverse_kinematics(leg: LegGeometry, position_foot_in_base: np.ndarray) -> np.ndarray:
    """Knee-down inverse kinematics; raises on the first unreachable target.

    Returns:
        q [rad], shape (N, 3) or (3,).

    Raises:
        UnreachableTargetError: naming the target and the leg's reach.
    """
    res = inverse_kinematics_masked(leg, position_foot_in_base)
    if not np.all(res.reachable):
        p, _ = _as_2d(position_foot_in_base)
        bad = int(np.flatnonzero(~np.atleast_1d(res.reachable))[0])
        target = p[bad]
        rel = target - leg.position_hip_in_base
        dist = float(np.hypot(np.hypot(rel[0], rel[1]) - leg.L1, rel[2]))
        lo, hi = leg.reach
        raise UnreachableTargetError(
            f"leg {leg.name}: foot target {np.round(target, 4).tolist()} m (sample {bad}) is "
            f"{dist:.4f} m from the hip-pitch axis; reach is [{lo:.4f}, {hi:.4f}] m",
            leg.name,
            tuple(float(v) for v in target),
            (lo, hi),
        )
    return res.q
