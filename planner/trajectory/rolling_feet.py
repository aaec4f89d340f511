"""Round feet planned as they roll: the ball centre of a stance foot follows its link's rotation.

A ball foot of radius r (silo4kin/foot_contact.py: FootBall.rolling_radius_m) that stands
on flat ground and does not slip rolls: when its link turns with angular velocity ω (world
axes), the ball's centre moves with

    v_centre = ω × (r ẑ) = r (ω_y, -ω_x, 0)                                   (rolling)

and the contact point, the centre minus r ẑ, moves with it; on a surface of unit normal n
(a ramp: SampledFeet.normal) the centre stands r n from the contact point and moves with
v_centre = ω × (r n), along the plane (:func:`rolling_velocity_on_plane`). The material
point of the ball that touches the ground is at rest (no slip). Over one stance the centre
and the contact point move by the rolling displacement d(t) = ∫ v_centre dt from touchdown
(zero at touchdown); a rotation about the normal does not roll the ball.

The planner's footholds are where each foot touches down; during the stance that follows,
the foot frame's target is the foothold plus d(t), and the swing that ends the stance
starts where the ball rolled to: its horizontal blend carries d(lift-off) to zero at the
next touchdown (the target is f(τ) + d_lift (1 - s(τ)), s the swing's blend). ω depends on
q, which depends on the target: :func:`roll_feet` solves this fixed point by iteration
(each pass shrinks the error by about r / leg length, ~0.1), to ROLL_TOLERANCE_M.

d(t) is the trapezoidal integral of v_centre over the samples, so that q, q̇ and q̈ are
exactly those of the targets, and a Pinocchio forward kinematics of the ball centre minus r ẑ
minus the same integral of Pinocchio's frame angular velocity gives the touchdown point
back (tests/test_round_feet.py). Point feet (r = 0) never reach this module.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from silo4kin import legs as leg_families
from silo4kin.foot_contact import FootBall
from silo4kin.frames import cross3

#: Convergence of the rolling fixed point: the largest change of d between two passes [m].
#: Far below the 1e-9 m of the fingerprints and checks; reached in ~10 passes.
ROLL_TOLERANCE_M = 1e-12
#: Passes of the fixed point before giving up (the contraction ~0.1 needs ~12 for 1e-12).
MAX_ROLL_PASSES = 40

#: Joint motion of leg j for foot-frame targets in W: (leg index, target, rate, acceleration
#: (n, 3) each, per time unit) -> q, q̇, q̈ (n, 3) each.
SolveLeg = Callable[[int, np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, ...]]


class RollingRates:
    """Per-sample rates of the base and the feet (per unit) and the swing blend, which the
    sampler (sampling.py) keeps block by block for the rolling pass (round feet only)."""

    def __init__(self, n: int) -> None:
        self.feet_d, self.feet_dd = np.zeros((n, 4, 3)), np.zeros((n, 4, 3))
        self.base_d, self.base_dd = np.zeros((n, 3)), np.zeros((n, 3))
        self.yaw_d, self.yaw_dd = np.zeros(n), np.zeros(n)
        self.swing_s, self.swing_ds, self.swing_dds = np.zeros(n), np.zeros(n), np.zeros(n)

    def swing_blend(self, rows: slice, idx: np.ndarray, blend) -> None:
        at = rows.start + idx
        self.swing_s[at], self.swing_ds[at], self.swing_dds[at] = blend.s, blend.ds, blend.dds

    def keep(self, rows: slice, feet_d, feet_dd, base_d, base_dd, yaw_d, yaw_dd) -> None:
        self.feet_d[rows], self.feet_dd[rows] = feet_d, feet_dd
        self.base_d[rows], self.base_dd[rows] = base_d, base_dd
        self.yaw_d[rows], self.yaw_dd[rows] = yaw_d, yaw_dd


@dataclass(frozen=True)
class SampledFeet:
    """The foot-frame targets of point feet and what the rolling pass needs (per time unit).

    Attributes:
        feet, feet_d, feet_dd: foot-frame targets in W and their rates [m, m/unit, m/unit²]
            (N, 4, 3): stance feet at their footholds, swing feet on their curves.
        swing_s, swing_ds, swing_dds: the horizontal blend s(τ) of the swinging leg and its
            rates [-, 1/unit, 1/unit²] (N,); 0 where no leg swings.
        yaw, yaw_d: body yaw ψ and ψ̇ [rad, rad/unit] (N,).
        contact: foot on the ground (N, 4).
        dt_units: time between samples [unit].
        normal: unit normal in W (N, 4, 3) of the surface each stance foot stands on, or
            None for level ground (ẑ everywhere: the level formula, bit for bit).
        yaw_dd: ψ̈ [rad/unit²] (N,), or None (0); only a tilted ``normal`` uses it (a yaw
            rate rolls a ball on a tilted plane: ψ̇ ẑ × n is not 0).
        ground: None (each stance rolls on the plane of ``normal``), or the height map the
            balls roll over (planner/trajectory/heightmap_rest.py Ground: centres -> centres
            resting on it, contact normals): each stance sample rolls on the normal of the
            triangle its ball touches (``normal`` where the map gives none) and a centre the
            integral carried into the map is lifted out of it.
    """

    feet: np.ndarray
    feet_d: np.ndarray
    feet_dd: np.ndarray
    swing_s: np.ndarray
    swing_ds: np.ndarray
    swing_dds: np.ndarray
    yaw: np.ndarray
    yaw_d: np.ndarray
    contact: np.ndarray
    dt_units: float
    normal: np.ndarray | None = None
    yaw_dd: np.ndarray | None = None
    ground: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]] | None = None


def _insect_omega(leg, q, qd, qdd):
    """ω and ω̇ of the insect foot link in B (N, 3): θ1 about ẑ, θ2 and θ3 about
    a = (sin φ, -cos φ, 0), φ = θb + θ1 (silo4kin/geometry.py, eq 3.5)."""
    s = np.asarray(leg.axis_sign, dtype=float)
    theta1 = s[0] * q[:, 0] + leg.zero_offset[0]
    phi = leg.theta_b + theta1
    d1, dd1 = s[0] * qd[:, 0], s[0] * qdd[:, 0]
    d23 = s[1] * qd[:, 1] + s[2] * qd[:, 2]
    dd23 = s[1] * qdd[:, 1] + s[2] * qdd[:, 2]
    a = np.stack([np.sin(phi), -np.cos(phi), np.zeros_like(phi)], axis=1)
    a_dot = np.stack([np.cos(phi), np.sin(phi), np.zeros_like(phi)], axis=1) * d1[:, None]
    z = np.zeros_like(phi)
    omega = d23[:, None] * a + np.stack([z, z, d1], axis=1)
    omega_d = dd23[:, None] * a + d23[:, None] * a_dot + np.stack([z, z, dd1], axis=1)
    return omega, omega_d


def mammal_omega_in_base(leg, q, qd, qdd):
    """ω and ω̇ of the mammal foot link in B (N, 3): θ1 about x̂, θ2 and θ3 about
    e(θ1) = R_x(θ1) e_a (silo4kin/mammal.py)."""
    s = np.asarray(leg.signs)  # (3,) of one leg, or (N, 3) per row (MammalConstants.of_rows)
    theta1 = s[..., 0] * q[:, 0]
    d1, dd1 = s[..., 0] * qd[:, 0], s[..., 0] * qdd[:, 0]
    d23 = s[..., 1] * qd[:, 1] + s[..., 2] * qd[:, 2]
    dd23 = s[..., 1] * qdd[:, 1] + s[..., 2] * qdd[:, 2]
    ea = np.asarray(leg.axis_pitch_in_base, dtype=float)
    c, sn = np.cos(theta1), np.sin(theta1)
    e = np.stack(
        [np.broadcast_to(ea[..., 0], c.shape), c * ea[..., 1] - sn * ea[..., 2],
         sn * ea[..., 1] + c * ea[..., 2]], 1,
    )  # fmt: skip
    x_cross_e = np.stack([np.zeros_like(c), -e[:, 2], e[:, 1]], axis=1)
    x_hat = np.array([1.0, 0.0, 0.0])
    omega = d1[:, None] * x_hat + d23[:, None] * e
    omega_d = dd1[:, None] * x_hat + dd23[:, None] * e + (d23 * d1)[:, None] * x_cross_e
    return omega, omega_d


def angular_velocity_foot_in_base(leg, q, qd, qdd) -> tuple[np.ndarray, np.ndarray]:
    """ω and ω̇ of the foot link relative to the base, in B axes (N, 3) each [rad/unit,
    rad/unit²], from joint values q, q̇, q̈ (N, 3) of either leg family."""
    if leg_families.family_of(leg) is leg_families.INSECT:
        return _insect_omega(leg, q, qd, qdd)
    return mammal_omega_in_base(leg, q, qd, qdd)


def rolling_velocity_in_world(
    radius_m: float, omega_in_base, omega_d_in_base, yaw, yaw_d
) -> tuple[np.ndarray, np.ndarray]:
    """v_centre = r ω × ẑ in W and its rate (N, 3) [m/unit, m/unit²] for the level body
    (yaw ψ, ψ̇ (N,)): ω_W = R_z(ψ) ω_B + ψ̇ ẑ, whose ẑ part does not roll."""
    w = radius_m * np.stack([omega_in_base[:, 1], -omega_in_base[:, 0]], axis=1)
    w_d = radius_m * np.stack([omega_d_in_base[:, 1], -omega_d_in_base[:, 0]], axis=1)
    c, s = np.cos(yaw), np.sin(yaw)
    v = np.stack([c * w[:, 0] - s * w[:, 1], s * w[:, 0] + c * w[:, 1]], axis=1)
    v_d = np.stack([c * w_d[:, 0] - s * w_d[:, 1], s * w_d[:, 0] + c * w_d[:, 1]], axis=1)
    v_d += yaw_d[:, None] * np.stack([-v[:, 1], v[:, 0]], axis=1)
    zero = np.zeros((len(v), 1))
    return np.hstack([v, zero]), np.hstack([v_d, zero])


def rolling_velocity_on_plane(
    radius_m: float, omega_in_base, omega_d_in_base, yaw, yaw_d, yaw_dd, normal_in_world
) -> tuple[np.ndarray, np.ndarray]:
    """v_centre = r ω_W × n in W and its rate (N, 3) [m/unit, m/unit²] of a ball rolling on
    a plane of unit normal ``normal_in_world`` (N, 3), fixed during the stance: the ball's
    centre stays r along n from the contact point, and the material point at the contact
    is at rest, so the centre moves with ω_W × (r n), parallel to the plane. The level body
    (yaw ψ, ψ̇, ψ̈ (N,)) gives ω_W = R_z(ψ) ω_B + ψ̇ ẑ and ω̇_W = R_z(ψ) ω̇_B + ψ̇ ẑ × R_z(ψ) ω_B
    + ψ̈ ẑ. With n = ẑ this is :func:`rolling_velocity_in_world`."""
    c, s = np.cos(yaw), np.sin(yaw)
    u = np.stack(
        [c * omega_in_base[:, 0] - s * omega_in_base[:, 1],
         s * omega_in_base[:, 0] + c * omega_in_base[:, 1], omega_in_base[:, 2]], axis=1,
    )  # fmt: skip
    u_d = np.stack(
        [c * omega_d_in_base[:, 0] - s * omega_d_in_base[:, 1],
         s * omega_d_in_base[:, 0] + c * omega_d_in_base[:, 1], omega_d_in_base[:, 2]], axis=1,
    )  # fmt: skip
    z_hat = np.array([0.0, 0.0, 1.0])
    u_d = u_d + yaw_d[:, None] * cross3(z_hat, u)
    omega_w = u + yaw_d[:, None] * z_hat
    omega_w_d = u_d + yaw_dd[:, None] * z_hat
    n = np.asarray(normal_in_world, dtype=float)
    return radius_m * cross3(omega_w, n), radius_m * cross3(omega_w_d, n)


def stance_integral(v: np.ndarray, stance: np.ndarray, dt: float) -> np.ndarray:
    """∫ v dt from the start of each stance run (trapezoid; 0 at its first sample) (N, 3);
    0 outside stance. ``v`` (N, 3), ``stance`` (N,) bool, ``dt`` the sample step."""
    n = len(v)
    inc = np.zeros_like(v)
    inc[1:] = 0.5 * (v[1:] + v[:-1]) * dt
    starts = stance & ~np.concatenate([[False], stance[:-1]])
    inc[starts | ~stance] = 0.0
    total = np.cumsum(inc, axis=0)
    start_index = np.maximum.accumulate(np.where(starts, np.arange(n), 0))
    d = total - total[start_index]
    d[~stance] = 0.0
    return d


def _liftoff_offsets(d: np.ndarray, stance: np.ndarray) -> np.ndarray:
    """d at the last stance sample before each sample (N, 3): the swing's start offset."""
    n = len(d)
    last = np.maximum.accumulate(np.where(stance, np.arange(n), -1))
    out = np.where((last >= 0)[:, None], d[np.maximum(last, 0)], 0.0)
    out[stance] = 0.0
    return out


_Z_HAT = np.array([0.0, 0.0, 1.0])


def _rest(ground, centres: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(centres resting on ``ground`` (M, 3) [m] ..., their contact normals (M, 3)): NaN
    centres (a foot out of reach) stay NaN."""
    with np.errstate(invalid="ignore"):
        return ground(centres)


def _rest_stance(ground, foothold: np.ndarray, d: np.ndarray, stance, plane: np.ndarray):
    """(d (N, 3) with each stance sample's centre foothold + d rested on ``ground``, the
    normals (N, 3) each sample rolls on) for one leg: ``foothold`` (N, 3) the sampled foot
    frames, ``plane`` (N, 3) the normal under each foothold."""
    moved, contact_normal = _rest(ground, foothold[stance] + d[stance])
    d = d.copy()
    d[stance] = moved - foothold[stance]
    return d, _contact_normals(plane, stance, contact_normal)


def _contact_normals(plane: np.ndarray, stance: np.ndarray, contact: np.ndarray):
    """The normals (N, 3) each sample rolls on: ``contact`` (M, 3) at the stance samples
    where it is finite, else ``plane`` (N, 3), the surface under the foothold."""
    normal = plane.copy()
    at = np.flatnonzero(stance)
    known = np.isfinite(contact).all(axis=1)
    normal[at[known]] = contact[known]
    return normal


def roll_feet(
    legs,
    ball: FootBall,
    sampled: SampledFeet,
    solve: SolveLeg,
    tolerance_m: float = ROLL_TOLERANCE_M,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """q, q̇, q̈ (N, 12) [rad, per unit] and the foot-frame targets in W (N, 4, 3) [m] of
    feet that roll (module docstring); ``legs`` the four leg geometries in B.

    Each pass solves the legs' joints for the targets of the previous pass's rolling (in
    stance: the foothold plus d, rate v_centre, acceleration its rate; in the swing: the
    curve plus d_lift (1 - s)), then integrates the rolling of those joints again, until d
    changes by less than ``tolerance_m`` [m]."""
    n = len(sampled.contact)
    q_all, qd_all, qdd_all = np.empty((n, 12)), np.empty((n, 12)), np.empty((n, 12))
    targets = np.empty((n, 4, 3))
    keep = 1.0 - sampled.swing_s
    yaw_dd = np.zeros(n) if sampled.yaw_dd is None else sampled.yaw_dd
    for j, leg in enumerate(legs):
        stance = sampled.contact[:, j]
        in_stance = stance[:, None]
        d, v, v_d = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3))
        normal = None if sampled.normal is None else sampled.normal[:, j]
        if sampled.ground is not None and stance.any():
            plane = np.tile(_Z_HAT, (n, 1)) if normal is None else np.array(normal)
            d, normal = _rest_stance(sampled.ground, sampled.feet[:, j], d, stance, plane)
        for _ in range(MAX_ROLL_PASSES):
            lift = _liftoff_offsets(d, stance)
            target = sampled.feet[:, j] + np.where(in_stance, d, lift * keep[:, None])
            target_d = sampled.feet_d[:, j] + np.where(
                in_stance, v, -lift * sampled.swing_ds[:, None]
            )
            target_dd = sampled.feet_dd[:, j] + np.where(
                in_stance, v_d, -lift * sampled.swing_dds[:, None]
            )
            q, qd, qdd = solve(j, target, target_d, target_dd)
            omega, omega_d = angular_velocity_foot_in_base(leg, q, qd, qdd)
            if normal is None:
                v, v_d = rolling_velocity_in_world(
                    ball.rolling_radius_m, omega, omega_d, sampled.yaw, sampled.yaw_d
                )
            else:
                v, v_d = rolling_velocity_on_plane(
                    ball.rolling_radius_m, omega, omega_d, sampled.yaw, sampled.yaw_d,
                    yaw_dd, normal,
                )  # fmt: skip
            v, v_d = np.nan_to_num(v) * in_stance, np.nan_to_num(v_d) * in_stance
            d_new = stance_integral(v, stance, sampled.dt_units)
            if sampled.ground is not None and stance.any():  # on the triangle it touches
                d_new, normal = _rest_stance(
                    sampled.ground, sampled.feet[:, j], d_new, stance, plane
                )
            change = float(np.max(np.abs(d_new - d), initial=0.0))
            d = d_new
            if change < tolerance_m:
                break
        cols = slice(3 * j, 3 * j + 3)
        q_all[:, cols], qd_all[:, cols], qdd_all[:, cols] = q, qd, qdd
        targets[:, j] = target
    return q_all, qd_all, qdd_all, targets


def stance_normals(terrain, position_foot_in_world: np.ndarray, contact: np.ndarray):
    """The unit normals in W (N, 4, 3) of the surfaces under the stance feet (foot frames
    ``position_foot_in_world`` (N, 4, 3) [m], ``contact`` (N, 4)) on ``terrain`` (a
    planner.terrain.terrain_map.TerrainMap: its normal_at), ẑ for swinging feet; None when
    the terrain has no normals or every stance foot stands level, so that level ground
    rolls by the level formula, bit for bit. The sampler passes its stance feet at their
    footholds, so each stance rolls on the plane under its foothold throughout (as
    planner/gaits/rolled_contacts.py predicts it), but on a height map, where roll_feet rolls
    each sample on the triangle its ball touches and this plane is only the fallback
    (planner/trajectory/heightmap_rest.py); the normal is asked under the foot frame,
    r n_xy (<= r sin 20 deg) from its contact point: within the foothold's edge margin
    (r + 2 cm, planner/gaits/surface_footholds.py), so on the same plane (on a height map,
    possibly its neighbouring triangle: asking under the contact point instead was tried
    and moved no go2 height-map refusal of bench_terrain.py)."""
    if not hasattr(terrain, "normal_at"):
        return None
    feet = np.asarray(position_foot_in_world, dtype=float)
    normal = np.zeros(feet.shape)
    normal[..., 2] = 1.0
    stance = np.asarray(contact, dtype=bool)
    if stance.any():
        normal[stance] = terrain.normal_at(feet[stance][:, :2])
    normal[~np.isfinite(normal).all(axis=-1)] = (0.0, 0.0, 1.0)
    if np.array_equal(normal[..., :2], np.zeros(feet.shape[:-1] + (2,))):
        return None
    return normal
