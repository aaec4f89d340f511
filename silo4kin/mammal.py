"""Closed-form kinematics of a mammal leg: hip ab/adduction about x, then two parallel pitches.

Most quadrupeds people own (Go2, A1, Solo12, ANYmal, HyQ...) have this leg: a first revolute
joint whose axis is the body's x axis (hip ab/adduction, HAA), then a hip flexion (HFE) and a
knee (KFE) whose axes are parallel to each other and perpendicular to x. The insect leg of the
thesis (kinematics.py) has a vertical first axis instead; see docs/robots.md.

Geometry (silo4kin/mammal_geometry.py), read from the model at q = 0 (silo4kin/mammal_extract.py;
never a robot number typed twice, like geometry.py):
``p1`` a point on the HAA axis (its joint origin), ``e_x`` = x̂, ``e_a`` the HFE axis at
q1 = 0 (unit, ⊥ x̂), ``e_n = e_x × e_a``. Components along ``e_a`` never change under the two
pitch rotations, so the leg is a planar 2R chain in the (e_x, e_n) plane, offset sideways by

    d = e_a · (p_foot - p1)                                  (constant lateral offset [m])

and the planar points ``c0 = P(p2 - p1)``, thigh ``u = P(p3 - p2)``, shank ``w = P(p_f - p3)``
with P(v) = (v·e_x, v·e_n). A rotation by θ about e_a acts on planar coordinates as R(-θ).
With DH-like angles θ = (s1 q1, q2, s3 q3) (s1 = sign of the HAA axis along x̂, s3 = sign of
the knee axis along e_a):

    m(θ3)  = u + R(-θ3) w
    P(θ)   = c0 + R(-θ2) m                                   (foot in the leg plane)
    p(q)   = p1 + Rx(θ1) (d e_a + P_x e_x + P_n e_n)          (foot in the base frame)

Inverse kinematics (both knee branches σ = ±1): with r = p - p1,
``n = -sqrt(|r_yz|² - d²)`` (the foot below the HAA axis, sign from the rest pose),
``θ1 = atan2(r_z, r_y) - atan2(r0_z, r0_y)``, then the planar 2R solution
``θ3 = α_w - α_u - σ acos((|v|² - |u|² - |w|²) / (2|u||w|))`` with v = P - c0,
``θ2 = angle(m) - angle(v)``. Angles are wrapped around the middle of each joint's limits.

Jacobian and J̇q̇ are the analytic derivatives of p(q) (no finite differences), cross-checked
against Pinocchio by ``silo4 check`` (check.py) on every robot of this family.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .frames import cross3
from .joint_limits import within_joint_limits
from .mammal_constants import MammalConstants
from .mammal_geometry import MammalLegGeometry

#: Slack on reachability tests (|cos| <= 1, |r_yz| >= |d|) for targets computed by FK [-], [m].
REACH_TOLERANCE = 1e-12

_J2 = np.array([[0.0, -1.0], [1.0, 0.0]])  # d/dφ R(φ) = J2 R(φ)


# The helpers below fill an np.empty instead of np.stack-ing their components (the same
# values: the mammal legs' kinematics run on a few rows at a time, where np.stack's
# bookkeeping cost more than the arithmetic: go2's height search called them ~1.4 M times).


def _rot2(angle: np.ndarray, v: np.ndarray) -> np.ndarray:
    """R(angle) @ v for stacks: angle (...,), v (..., 2) or (2,) -> (..., 2)."""
    c, s = np.cos(angle), np.sin(angle)
    v = np.broadcast_to(v, np.shape(angle) + (2,))
    out = np.empty(np.shape(angle) + (2,))
    out[..., 0] = c * v[..., 0] - s * v[..., 1]
    out[..., 1] = s * v[..., 0] + c * v[..., 1]
    return out


def _perp(v: np.ndarray) -> np.ndarray:
    """J2 @ v (rotate +90°), (..., 2)."""
    out = np.empty(np.shape(v))
    out[..., 0] = -v[..., 1]
    out[..., 1] = v[..., 0]
    return out


def _rot_x(angle: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rx(angle) @ v for stacks: angle (...,), v (..., 3) -> (..., 3)."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.empty(np.broadcast_shapes(np.shape(angle) + (3,), np.shape(v)))
    out[..., 0] = v[..., 0]
    out[..., 1] = c * v[..., 1] - s * v[..., 2]
    out[..., 2] = s * v[..., 1] + c * v[..., 2]
    return out


def _embed(
    leg: MammalLegGeometry | MammalConstants, planar: np.ndarray, lateral: float | np.ndarray
) -> np.ndarray:
    """d e_a + P_x x̂ + P_n e_n, (..., 3)."""
    e_a, e_n = leg.axis_pitch_in_base, leg.axis_normal_in_base
    lateral = np.asarray(lateral, dtype=float)
    return (
        lateral[..., None] * e_a
        + planar[..., :1] * np.array([1.0, 0.0, 0.0])
        + planar[..., 1:] * e_n
    )


class _Chain(NamedTuple):
    theta: np.ndarray  # (N, 3)
    m: np.ndarray  # (N, 2) u + R(-θ3) w
    w_rot: np.ndarray  # (N, 2) R(-θ3) w
    planar: np.ndarray  # (N, 2) c0 + R(-θ2) m
    r0: np.ndarray  # (N, 3) foot relative to p1 at θ1 = 0


def _chain(leg: MammalLegGeometry | MammalConstants, q: np.ndarray) -> _Chain:
    theta = np.asarray(q, dtype=float) * leg.signs
    w_rot = _rot2(-theta[..., 2], leg.shank_in_plane)
    m = leg.thigh_in_plane + w_rot
    planar = leg.offset_pitch_in_plane + _rot2(-theta[..., 1], m)
    return _Chain(theta, m, w_rot, planar, _embed(leg, planar, leg.lateral_offset))


def forward_kinematics(leg: MammalLegGeometry, q: np.ndarray) -> np.ndarray:
    """Foot position in the base frame [m], (..., 3), for joint values q (..., 3) [rad]."""
    c = _chain(leg, q)
    return leg.position_hip_in_base + _rot_x(c.theta[..., 0], c.r0)


def jacobian(leg: MammalLegGeometry, q: np.ndarray) -> np.ndarray:
    """∂p/∂q of the foot in the base frame [m/rad], (..., 3, 3)."""
    return _jacobian_of(leg, _chain(leg, q))


def _jacobian_of(leg: MammalLegGeometry | MammalConstants, c: _Chain) -> np.ndarray:
    """:func:`jacobian` of the chain ``c`` of :func:`_chain`."""
    theta = c.theta
    x_hat = np.array([1.0, 0.0, 0.0])
    col1 = cross3(x_hat, _rot_x(theta[..., 0], c.r0))
    # d/dθ2 R(-θ2) m = -J2 R(-θ2) m ; d/dθ3 R(-θ2)(u + R(-θ3) w) = -J2 R(-θ2) R(-θ3) w
    d2 = -_perp(_rot2(-theta[..., 1], c.m))
    d3 = -_perp(_rot2(-theta[..., 1], c.w_rot))
    col2 = _rot_x(theta[..., 0], _embed(leg, d2, 0.0))
    col3 = _rot_x(theta[..., 0], _embed(leg, d3, 0.0))
    # θ = signs q scales column k by signs[k]; signs (3,) of a leg or (R, 3) per row
    return np.stack([col1, col2, col3], axis=-1) * np.asarray(leg.signs)[..., None, :]


def jacobian_derivative_times_velocity(
    leg: MammalLegGeometry, q: np.ndarray, qd: np.ndarray
) -> np.ndarray:
    """J̇(q, q̇) q̇: the foot's acceleration at q̈ = 0, base frame [m/s²], (..., 3).

    p = p1 + Rx(θ1) r0(θ2, θ3) gives p̈|q̈=0 = θ̇1² x̂×(x̂×Rx r0) + 2 θ̇1 x̂×(Rx ṙ0) + Rx r̈0, with
    Ṗ = -θ̇2 J2 R(-θ2) m + R(-θ2) ṁ, ṁ = -θ̇3 J2 R(-θ3) w and
    P̈ = -θ̇2² R(-θ2) m - 2 θ̇2 J2 R(-θ2) ṁ - θ̇3² R(-θ2) R(-θ3) w.
    """
    return _jacobian_derivative_of(leg, _chain(leg, q), qd)


def _jacobian_derivative_of(leg: MammalLegGeometry, c: _Chain, qd: np.ndarray) -> np.ndarray:
    """:func:`jacobian_derivative_times_velocity` of the chain ``c`` of :func:`_chain`."""
    theta, td = c.theta, np.asarray(qd, dtype=float) * leg.signs
    x_hat = np.array([1.0, 0.0, 0.0])
    t1, t2, t3 = td[..., 0:1], td[..., 1:2], td[..., 2:3]
    m_dot = -t3 * _perp(c.w_rot)
    planar_dot = -t2 * _perp(_rot2(-theta[..., 1], c.m)) + _rot2(-theta[..., 1], m_dot)
    planar_ddot = (
        -(t2**2) * _rot2(-theta[..., 1], c.m)
        - 2.0 * t2 * _perp(_rot2(-theta[..., 1], m_dot))
        - t3**2 * _rot2(-theta[..., 1], c.w_rot)
    )
    r = _rot_x(theta[..., 0], c.r0)
    r_dot = _rot_x(theta[..., 0], _embed(leg, planar_dot, 0.0))
    r_ddot = _rot_x(theta[..., 0], _embed(leg, planar_ddot, 0.0))
    return t1**2 * cross3(x_hat, cross3(x_hat, r)) + 2.0 * t1 * cross3(x_hat, r_dot) + r_ddot


class MammalIK(NamedTuple):
    """Inverse kinematics of a stack of targets.

    Attributes:
        q: joint values [rad], (N, 3); NaN where unreachable.
        reachable: the target is reachable by this branch (geometry only), (N,).
        within_limits: reachable and inside the joint limits, (N,).
    """

    q: np.ndarray
    reachable: np.ndarray
    within_limits: np.ndarray


def _wrap_around(value: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """value + 2πk closest to centre."""
    return centre + np.mod(value - centre + np.pi, 2.0 * np.pi) - np.pi


def inverse_kinematics(
    leg: MammalLegGeometry | MammalConstants,
    position_foot_in_base: np.ndarray,
    knee_branch: int | np.ndarray | None = None,
    foot_side: float | np.ndarray | None = None,
) -> MammalIK:
    """Joint values putting the foot at ``position_foot_in_base`` (..., 3) [m].

    A target has up to four solutions: two knee branches and the foot below or above the
    HAA axis (n < 0 or n > 0 in the leg plane, θ1 differing by about π). ``leg`` is one
    leg, or :meth:`MammalConstants.of_rows` of (R, 3) targets of several legs (one pass).

    Args:
        knee_branch: σ = ±1 (see the module docstring), scalar or per target (...,);
            default the rest pose's branch.
        foot_side: sign of n, scalar or per target; default the rest pose's (-1: below).
    """
    c = leg if isinstance(leg, MammalConstants) else MammalConstants.of_leg(leg)
    target = np.asarray(position_foot_in_base, dtype=float)
    shape = target.shape[:-1]
    r = target.reshape(-1, 3) - c.position_hip_in_base
    sigma = np.broadcast_to(
        np.asarray(c.knee_branch if knee_branch is None else knee_branch, dtype=float), shape
    ).ravel()
    side = np.broadcast_to(
        np.asarray(c.foot_below_sign if foot_side is None else foot_side, dtype=float), shape
    ).ravel()
    d = c.lateral_offset
    rho2 = r[:, 1] ** 2 + r[:, 2] ** 2
    ok_yz = rho2 >= d * d - REACH_TOLERANCE
    n = side * np.sqrt(np.maximum(rho2 - d * d, 0.0))
    planar = np.stack([r[:, 0], n], axis=-1)
    r0 = _embed(c, planar, d)
    theta1 = np.arctan2(r[:, 2], r[:, 1]) - np.arctan2(r0[:, 2], r0[:, 1])
    v = planar - c.offset_pitch_in_plane
    u, w = c.thigh_in_plane, c.shank_in_plane
    nu, nw = c.thigh_length, c.shank_length
    cos3 = (np.sum(v * v, axis=-1) - nu * nu - nw * nw) / (2.0 * nu * nw)
    ok_planar = np.abs(cos3) <= 1.0 + REACH_TOLERANCE
    theta3 = c.shank_angle - c.thigh_angle - sigma * np.arccos(np.clip(cos3, -1.0, 1.0))
    m = u + _rot2(-theta3, w)
    theta2 = np.arctan2(m[:, 1], m[:, 0]) - np.arctan2(v[:, 1], v[:, 0])
    q = np.stack([theta1, theta2, theta3], axis=-1) * c.signs
    q = _wrap_around(q, 0.5 * (c.q_lower + c.q_upper))
    reachable = ok_yz & ok_planar
    q[~reachable] = np.nan
    inside = reachable & within_joint_limits(q, c.q_lower, c.q_upper)
    return MammalIK(q.reshape(shape + (3,)), reachable.reshape(shape), inside.reshape(shape))


def ik_is_unique(
    leg: MammalLegGeometry, position_foot_in_base: np.ndarray, margin: float = 1e-6
) -> np.ndarray:
    """Targets whose IK on a given branch is unique and well conditioned, (...,).

    The knee is neither stretched nor folded flat (|cos| < 1 - margin) and the foot is off
    the HAA axis by more than the lateral offset (|r_yz|² - d² > margin [m²]).
    """
    r = np.asarray(position_foot_in_base, dtype=float) - leg.position_hip_in_base
    rho2 = r[..., 1] ** 2 + r[..., 2] ** 2
    d = leg.lateral_offset
    nu, nw = np.linalg.norm(leg.thigh_in_plane), np.linalg.norm(leg.shank_in_plane)
    ok = rho2 - d * d > margin
    for side in (-1.0, 1.0):  # both sides of the HAA axis must be well conditioned
        n = side * np.sqrt(np.maximum(rho2 - d * d, 0.0))
        v = np.stack([r[..., 0], n], axis=-1) - leg.offset_pitch_in_plane
        cos3 = (np.sum(v * v, axis=-1) - nu * nu - nw * nw) / (2.0 * nu * nw)
        ok &= (np.abs(cos3) < 1.0 - margin) | (np.abs(cos3) > 1.0 + margin)
    return ok


def branch_of(leg: MammalLegGeometry, q3: np.ndarray | float) -> np.ndarray:
    """σ (±1) of the IK branch whose θ3 equals the knee value q3, same shape as q3."""
    u, w = leg.thigh_in_plane, leg.shank_in_plane
    alpha = np.arctan2(w[1], w[0]) - np.arctan2(u[1], u[0])
    s = np.sin(alpha - leg.knee_sign * np.asarray(q3, dtype=float))  # sign of α_w - α_u - θ3
    return np.where(s >= 0.0, 1, -1)


def foot_side_of(leg: MammalLegGeometry, q: np.ndarray) -> np.ndarray:
    """Sign of the foot's n coordinate in the leg plane (-1: below the HAA axis), (...,)."""
    return np.where(_chain(leg, q).planar[..., 1] >= 0.0, 1.0, -1.0)


def joint_motion(
    leg: MammalLegGeometry,
    position_foot_in_base: np.ndarray,
    velocity_foot_in_base: np.ndarray,
    acceleration_foot_in_base: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """q = IK(p) on the rest pose's branch, q̇ = J⁻¹ ṗ, q̈ = J⁻¹ (p̈ - J̇q̇), for (N, 3) stacks.

    The mammal counterpart of kinematics.joint_motion (same meaning, same units per time
    unit); returns (q, qd, qdd, reachable) with NaN where a target is out of reach and
    non-finite rates at singular poses (callers check np.isfinite).
    """
    q, qd, reachable, chain, jac = _joint_rates(leg, position_foot_in_base, velocity_foot_in_base)
    with np.errstate(divide="ignore", invalid="ignore"):
        rhs = np.asarray(acceleration_foot_in_base, dtype=float).reshape(
            -1, 3
        ) - _jacobian_derivative_of(leg, chain, qd)
        qdd = np.linalg.solve(jac, rhs[..., None])[..., 0]
    qd[~reachable] = np.nan
    qdd[~reachable] = np.nan
    return q, qd, qdd, reachable


def joint_rates(
    leg: MammalLegGeometry, position_foot_in_base: np.ndarray, velocity_foot_in_base: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """q = IK(p) and q̇ = J⁻¹ ṗ of :func:`joint_motion` (the same values, bit for bit: the
    same IK, chain, J and solve), without q̈ (no J̇q̇, no second solve): (q, qd, reachable),
    for a caller whose result depends on the pose and the rates only (a rolling ball's
    displacement, planner/gaits/rolled_contacts.py)."""
    q, qd, reachable, _, _ = _joint_rates(leg, position_foot_in_base, velocity_foot_in_base)
    qd[~reachable] = np.nan
    return q, qd, reachable


def joint_rates_of_rows(
    rows: MammalConstants, position_foot_in_base: np.ndarray, velocity_foot_in_base: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`joint_rates` of targets of several legs in one pass, ``rows`` their legs'
    constants row by row (MammalConstants.of_rows: the same operations on the same numbers
    as one leg at a time): (q, q̇, reachable) for (R, 3) targets and rates."""
    q, qd, reachable, _, _ = _joint_rates(rows, position_foot_in_base, velocity_foot_in_base)
    qd[~reachable] = np.nan
    return q, qd, reachable


def _joint_rates(
    leg: MammalLegGeometry | MammalConstants,
    position_foot_in_base: np.ndarray,
    velocity_foot_in_base: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, _Chain, np.ndarray]:
    """(q, q̇ before NaN-ing the unreachable rows, reachable, the chain at q, J) for
    :func:`joint_motion` and :func:`joint_rates`."""
    p = np.asarray(position_foot_in_base, dtype=float).reshape(-1, 3)
    ik = inverse_kinematics(leg, p)
    q = ik.q
    chain = _chain(leg, np.nan_to_num(q))  # once for J and J̇q̇ (the same values)
    jac = _jacobian_of(leg, chain)
    with np.errstate(divide="ignore", invalid="ignore"):
        qd = np.linalg.solve(
            jac, np.asarray(velocity_foot_in_base, dtype=float).reshape(-1, 3)[..., None]
        )[..., 0]
    return q, qd, ik.reachable, chain, jac


def _rotate_about(axis: np.ndarray, angle: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rodrigues: rotate v (N, 3) about the unit axes (N, 3) by angle (N,)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return v * c + cross3(axis, v) * s + axis * np.sum(axis * v, axis=-1)[:, None] * (1.0 - c)


def leg_mass_moment_in_base(leg: MammalLegGeometry | MammalConstants, q: np.ndarray) -> np.ndarray:
    """Σ m_i c_i over the leg's three links, c_i the link CM in the base frame [kg m], (N, 3).

    Each link's CM at q = 0 turns with the joints before it: the hip link by θ1 about x̂
    through p1; the thigh also by θ2 about e_a through the HFE point; the shank also by θ3
    about e_a through the knee point (e_a and both points carried by the earlier rotations).
    ``leg`` is one leg, or :meth:`MammalConstants.of_rows` of N rows of several legs.
    """
    c = leg if isinstance(leg, MammalConstants) else MammalConstants.of_leg(leg)
    theta = np.atleast_2d(np.asarray(q, dtype=float)) * c.signs
    n = theta.shape[0]
    e_a = np.broadcast_to(c.axis_pitch_in_base, (n, 3))
    p1, p2, p3 = c.position_hip_in_base, c.position_pitch_in_base, c.position_knee_in_base
    coms = c.link_coms_at_zero
    c_hip, c_thigh, c_shank = coms[..., 0, :], coms[..., 1, :], coms[..., 2, :]
    # in the θ1 = 0 leg: rotate the shank about the knee, then thigh+shank about the HFE point
    shank = p3 + _rotate_about(e_a, theta[:, 2], np.broadcast_to(c_shank - p3, (n, 3)))
    shank = p2 + _rotate_about(e_a, theta[:, 1], shank - p2)
    thigh = p2 + _rotate_about(e_a, theta[:, 1], np.broadcast_to(c_thigh - p2, (n, 3)))
    hip = np.broadcast_to(c_hip, (n, 3))
    m = c.link_masses
    moment_zero_yaw = (
        m[..., 0, None] * (hip - p1)
        + m[..., 1, None] * (thigh - p1)
        + m[..., 2, None] * (shank - p1)
    )
    return _rot_x(theta[:, 0], moment_zero_yaw) + c.link_mass_total * p1
