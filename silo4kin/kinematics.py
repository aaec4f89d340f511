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
        return cls(hip=np.array([leg.position_hip_in_base for leg in legs], dtype=float),
                   theta_b=np.array([leg.theta_b for leg in legs], dtype=float),
                   lengths=np.array([(leg.L1, leg.L2, leg.L3) for leg in legs], dtype=float),
                   zero_offset=np.array([leg.zero_offset for leg in legs], dtype=float),
                   axis_sign=np.array([leg.axis_sign for leg in legs], dtype=float))


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


def knee_down_terms(x: np.ndarray, y: np.ndarray, z: np.ndarray,
                    theta_b: np.ndarray | float, l1: np.ndarray | float,
                    l2: np.ndarray | float, l3: np.ndarray | float) -> KneeDownTerms:
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
    c3 = np.clip(cos3, -1.0, 1.0)
    theta3 = -np.arccos(c3)
    s3 = -np.sqrt(1.0 - c3 * c3)
    kx, ky = l2 + l3 * c3, l3 * s3
    num_c, num_s = r * kx + z * ky, z * kx - r * ky
    theta2 = np.arctan2(num_s, num_c)
    return KneeDownTerms(theta1, theta2, theta3, reachable, rho, r, z, c3, s3, kx, ky,
                         num_c, num_s)


def knee_down_dh_angles(position_foot_in_hip: np.ndarray, theta_b: np.ndarray | float,
                        l1: np.ndarray | float, l2: np.ndarray | float,
                        l3: np.ndarray | float) -> IKResult:
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
    theta = np.stack([t.theta1, t.theta2, t.theta3], axis=1)
    theta[~t.reachable] = np.nan
    return IKResult(theta, t.reachable)


def knee_down_ik_of_legs(legs: KneeDownLegs, leg_index: np.ndarray,
                         position_foot_in_base: np.ndarray) -> IKResult:
    """:func:`inverse_kinematics_masked` of target i (N, 3) [m] for leg ``leg_index[i]`` of
    the table ``legs``, all legs in one pass; the same values, bit for bit
    (tests/test_kinematics.py)."""
    idx = leg_index
    lengths = legs.lengths[idx]
    dh = knee_down_dh_angles(position_foot_in_base - legs.hip[idx], legs.theta_b[idx],
                             lengths[:, 0], lengths[:, 1], lengths[:, 2])
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
            leg.name, tuple(float(v) for v in target), (lo, hi))
    return res.q


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
    d_rho_2 = -leg.L2 * s2 - leg.L3 * s23          # d rho / d theta2
    d_rho_3 = -leg.L3 * s23                        # d rho / d theta3
    d_z_2 = leg.L2 * c2 + leg.L3 * c23             # d z / d theta2
    d_z_3 = leg.L3 * c23                           # d z / d theta3
    J = np.zeros((theta.shape[0], 3, 3))
    J[:, 0, 0] = -sphi * rho                       # eq 3.27
    J[:, 1, 0] = cphi * rho                        # eq 3.30
    J[:, 0, 1] = cphi * d_rho_2                    # eq 3.28
    J[:, 1, 1] = sphi * d_rho_2                    # eq 3.31
    J[:, 2, 1] = d_z_2                             # eq 3.34
    J[:, 0, 2] = cphi * d_rho_3                    # eq 3.29
    J[:, 1, 2] = sphi * d_rho_3                    # eq 3.32
    J[:, 2, 2] = d_z_3                             # eq 3.35
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
    d_z_2_dot = -leg.L2 * s2 * w2 - leg.L3 * s23 * w23   # eq 3.44
    d_z_3_dot = -leg.L3 * s23 * w23                      # eq 3.45 (dJ(3,3))
    Jd = np.zeros((theta.shape[0], 3, 3))
    Jd[:, 0, 0] = -cphi * w1 * rho - sphi * rho_dot                  # eq 3.37
    Jd[:, 1, 0] = -sphi * w1 * rho + cphi * rho_dot                  # eq 3.40
    Jd[:, 0, 1] = -sphi * w1 * d_rho_2 + cphi * d_rho_2_dot          # eq 3.38
    Jd[:, 1, 1] = cphi * w1 * d_rho_2 + sphi * d_rho_2_dot           # eq 3.41
    Jd[:, 2, 1] = d_z_2_dot
    Jd[:, 0, 2] = -sphi * w1 * d_rho_3 + cphi * d_rho_3_dot          # eq 3.39
    Jd[:, 1, 2] = cphi * w1 * d_rho_3 + sphi * d_rho_3_dot           # eq 3.42
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


def joint_velocity(leg: LegGeometry, q: np.ndarray, foot_velocity_in_base: np.ndarray
                   ) -> np.ndarray:
    """q' = J^-1 p' (eq 3.25 solved) [rad/s], shape like q."""
    return np.linalg.solve(jacobian(leg, q), np.asarray(foot_velocity_in_base)[..., None])[..., 0]


def joint_acceleration(leg: LegGeometry, q: np.ndarray, qd: np.ndarray,
                       foot_acceleration_in_base: np.ndarray) -> np.ndarray:
    """q'' = J^-1 (p'' - dJ q') (eq 3.36 solved) [rad/s^2], shape like q."""
    jdqd = np.einsum("...ij,...j->...i", jacobian_derivative(leg, q, qd), qd)
    rhs = np.asarray(foot_acceleration_in_base) - jdqd
    return np.linalg.solve(jacobian(leg, q), rhs[..., None])[..., 0]


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


def joint_motion(leg: LegGeometry, position_foot_in_base: Vectors, velocity_foot_in_base: Vectors,
                 acceleration_foot_in_base: Vectors,
                 out: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None) -> JointMotion:
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
        rho, r, c3, s3, kx, ky, num_c, num_s = (t.rho, t.r, t.c3, t.s3, t.kx, t.ky, t.num_c,
                                                t.num_s)
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
        for j, (theta, rate, acc) in enumerate((
                (theta1, w1, (a_t - 2.0 * v_r * w1) / rho),
                (theta2, w2, (L3 * c23 * rhs_r + L3 * s23 * rhs_z) * inv_det),
                (theta3, w3, -(r * rhs_r + z * rhs_z) * inv_det))):
            q[:, j] = (theta - offset[j]) * sign[j]       # dh_to_joint
            qd[:, j] = sign[j] * rate
            qdd[:, j] = sign[j] * acc
    bad = ~reachable
    if bad.any():
        q[bad] = np.nan
        qd[bad] = np.nan
        qdd[bad] = np.nan
    return JointMotion(q, qd, qdd, reachable)
