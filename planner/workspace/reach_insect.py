"""Reachable ground set of a leg at a body height, from forward kinematics and joint limits.

The default workspace (workspace.py) plans inside the set of points each foot can really reach
not inside the thesis's square built from one reference pose (§4.2.1, Fig 4.7).

For an insect leg (vertical first axis, foot in the plane of the two parallel pitch axes,
silo4kin/discovery.py) the hip yaw θ1 only turns the leg plane, so the ground points the foot
reaches at foot height z (in B) form an annular sector about the hip-yaw axis:

    {hip + r (cos φ, sin φ) : r in [r_min, r_max], φ in [θb + θ1_min, θb + θ1_max]}

[r_min, r_max] is found from the forward kinematics (eq 3.5) alone: FK on a grid of
(θ2, θ3) within the joint limits, knee-down and at least ``knee_margin`` from the stretched
singularity θ3 = 0 (|det J| ∝ |sin θ3|, eq 3.46), then the crossings of the level z along the
grid lines, linearly interpolated. Nothing here uses the closed-form IK, so the IK check that
the workspace applies to the chosen footholds (workspace.reachable_in_limits) is independent.

A foothold must stay reachable while the swing foot is lifted (the swing path climbs to h_max,
eq 5.12) and while the body is shifted for stability (up to SHIFT_RESERVE_M in any direction):
:class:`ReachableSet` is the intersection of the sectors at several foot heights and
:meth:`ReachableSet.contains` erodes it by a distance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from silo4kin.geometry import LegGeometry
from silo4kin.kinematics import forward_kinematics

#: FK grid over (θ2, θ3) within the limits [samples per joint]: 1.1° steps on SILO4's 180°
#: pitch range; the interval ends are interpolated, so they are exact to ~(L2+L3)·Δθ²/8.
PITCH_SAMPLES = 161
KNEE_SAMPLES = 161
#: Largest gap in the sorted crossing radii still read as one interval, in grid steps
#: (L2 + L3) · Δθ [-]: a real gap in the reachable radii is wider.
GAP_STEPS = 4.0


@dataclass(frozen=True)
class ReachableSet:
    """Ground points one foot reaches at one body height: an annular sector in B.

    Attributes:
        leg_name: e.g. "LF".
        position_hip_in_base: hip-yaw axis (x, y) [m], shape (2,).
        yaw_lower_rad, yaw_upper_rad: direction φ of the foot seen from the hip axis, yaw in
            B [rad] (θb + θ1 limits).
        radius_lower_m, radius_upper_m: horizontal distance of the foot from the hip axis [m];
            lower > upper when the foot reaches no point at every foot height asked for.
        foot_heights_in_base: the foot heights z in B whose sectors were intersected [m].
    """

    leg_name: str
    position_hip_in_base: np.ndarray
    yaw_lower_rad: float
    yaw_upper_rad: float
    radius_lower_m: float
    radius_upper_m: float
    foot_heights_in_base: tuple[float, ...]

    @property
    def empty(self) -> bool:
        """Whether no ground point is reachable."""
        return not self.radius_lower_m < self.radius_upper_m

    def edge_normals(self) -> np.ndarray:
        """Inward unit normals (2, 2) of the wedge's two edge lines through the hip axis. A
        wedge wider than 180° (θ1 range > 180°) is narrowed to 180°, so the set stays the
        intersection of an annulus with two half-planes (the hip-yaw limits of SILO4,
        ±90°, are exactly 180°)."""
        mid = 0.5 * (self.yaw_lower_rad + self.yaw_upper_rad)
        half = min(0.5 * (self.yaw_upper_rad - self.yaw_lower_rad), np.pi / 2)
        lo, hi = mid - half, mid + half
        return np.array([[-np.sin(lo), np.cos(lo)], [np.sin(hi), -np.cos(hi)]])

    def contains(self, position_in_base: np.ndarray, erosion_m: float = 0.0) -> np.ndarray:
        """Whether each point (N, 2) or (N, 3) [m] (only x, y used) lies in the set shrunk by
        ``erosion_m`` [m] (every point within that distance of it also in the set); (N,)."""
        q = np.atleast_2d(np.asarray(position_in_base, float))[:, :2] - self.position_hip_in_base
        r = np.hypot(q[:, 0], q[:, 1])
        inside = (r >= self.radius_lower_m + erosion_m) & (r <= self.radius_upper_m - erosion_m)
        for normal in self.edge_normals():
            inside &= q @ normal >= erosion_m
        return inside

    def outline(self, n: int = 48) -> np.ndarray:
        """Closed boundary polygon (x, y) in B [m], shape (2n + 1, 2); (0, 2) when empty."""
        if self.empty:
            return np.zeros((0, 2))
        phi = np.linspace(self.yaw_lower_rad, self.yaw_upper_rad, n)
        outer = self.radius_upper_m * np.stack([np.cos(phi), np.sin(phi)], axis=1)
        inner = self.radius_lower_m * np.stack([np.cos(phi[::-1]), np.sin(phi[::-1])], axis=1)
        ring = np.vstack([outer, inner, outer[:1]])
        return ring + self.position_hip_in_base


_GRIDS: dict[tuple, tuple[np.ndarray, np.ndarray, float] | None] = {}


def _planar_grid(
    leg_key: tuple, leg: LegGeometry, knee_margin_rad: float
) -> tuple[np.ndarray, np.ndarray, float] | None:
    """(ρ, z) of the foot relative to the hip axis on the (θ2, θ3) grid [m], both
    (PITCH_SAMPLES, KNEE_SAMPLES), and the grid step in foot travel [m]; None when the knee
    range leaves nothing knee-down beyond the margin. Vectorised FK (eq 3.5) at θ1 = 0;
    cached per planar leg geometry (``leg_key``), which the hip position does not enter."""
    key = (*leg_key, knee_margin_rad)
    if key not in _GRIDS:
        _GRIDS[key] = _compute_grid(leg, knee_margin_rad)
    return _GRIDS[key]


def _compute_grid(
    leg: LegGeometry, knee_margin_rad: float
) -> tuple[np.ndarray, np.ndarray, float] | None:
    lo, hi = leg.theta_lower, leg.theta_upper
    knee_hi = min(hi[2], -knee_margin_rad)
    if knee_hi <= lo[2]:
        return None
    t2 = np.linspace(lo[1], hi[1], PITCH_SAMPLES)
    t3 = np.linspace(lo[2], knee_hi, KNEE_SAMPLES)
    g2, g3 = np.meshgrid(t2, t3, indexing="ij")
    theta = np.stack([np.zeros_like(g2), g2, g3], axis=-1).reshape(-1, 3)
    feet = forward_kinematics(leg, leg.dh_to_joint(theta)).reshape(*g2.shape, 3)
    rel = feet - leg.position_hip_in_base
    u = np.array([np.cos(leg.theta_b), np.sin(leg.theta_b)])  # leg plane at θ1 = 0
    step = (leg.L2 + leg.L3) * max(t2[1] - t2[0], t3[1] - t3[0])
    return rel[..., :2] @ u, rel[..., 2], float(step)


def _leg_key(leg: LegGeometry) -> tuple:
    return (leg.L1, leg.L2, leg.L3, *leg.theta_lower.tolist(), *leg.theta_upper.tolist())


def radial_interval(
    leg: LegGeometry, foot_height_in_base: float, knee_margin_rad: float
) -> tuple[float, float]:
    """[r_min, r_max] [m]: horizontal distances from the hip-yaw axis at which the foot of
    ``leg`` reaches height z = ``foot_height_in_base`` within its pitch and knee limits,
    knee-down with |θ3| >= ``knee_margin_rad`` (module docstring). (inf, -inf) if none.

    Crossings of the level on the FK grid, along θ2 and along θ3 lines, interpolated; when
    they form several intervals (limits can split the level set) the widest is returned.
    """
    key = (
        _leg_key(leg),
        float(knee_margin_rad),
        float(foot_height_in_base - leg.position_hip_in_base[2]),
    )
    if key not in _INTERVALS:  # legs of one planar shape share it (SILO4: all four)
        if len(_INTERVALS) > 4096:
            _INTERVALS.clear()
        _INTERVALS[key] = _radial_interval(leg, key[0], key[1], key[2])
    return _INTERVALS[key]


#: radial_interval by (planar leg geometry, knee margin, foot height below the hip).
_INTERVALS: dict[tuple, tuple[float, float]] = {}


def _radial_interval(
    leg: LegGeometry, leg_key: tuple, knee_margin_rad: float, foot_below_hip_m: float
) -> tuple[float, float]:
    """radial_interval of the foot at ``foot_below_hip_m`` [m] relative to the hip axis."""
    grid = _planar_grid(leg_key, leg, knee_margin_rad)
    if grid is None:
        return float("inf"), float("-inf")
    rho, z, step = grid
    dz = z - foot_below_hip_m
    radii = []
    for axis in (0, 1):  # crossings along θ2 and along θ3 lines
        a = np.moveaxis(dz, axis, 0)
        r = np.moveaxis(rho, axis, 0)
        za, zb, ra, rb = a[:-1], a[1:], r[:-1], r[1:]
        cross = (za * zb <= 0) & (za != zb)
        s = za[cross] / (za[cross] - zb[cross])
        radii.append(ra[cross] + s * (rb[cross] - ra[cross]))
    r_all = np.sort(np.concatenate(radii))
    r_all = r_all[r_all > 0]
    if r_all.size == 0:
        return float("inf"), float("-inf")
    breaks = np.flatnonzero(np.diff(r_all) > GAP_STEPS * step)
    starts = np.concatenate([[0], breaks + 1])
    ends = np.concatenate([breaks, [r_all.size - 1]])
    k = int(np.argmax(r_all[ends] - r_all[starts]))
    return float(r_all[starts[k]]), float(r_all[ends[k]])


def reachable_set(
    leg: LegGeometry, foot_heights_in_base: tuple[float, ...], knee_margin_rad: float
) -> ReachableSet:
    """The leg's ground set: sectors at every foot height z in ``foot_heights_in_base`` [m]
    (e.g. the ground and the swing apex) intersected (module docstring)."""
    intervals = np.array([radial_interval(leg, z, knee_margin_rad) for z in foot_heights_in_base])
    lo, hi = leg.theta_lower[0], leg.theta_upper[0]
    return ReachableSet(
        leg_name=leg.name,
        position_hip_in_base=np.asarray(leg.position_hip_in_base[:2], float),
        yaw_lower_rad=float(leg.theta_b + lo),
        yaw_upper_rad=float(leg.theta_b + hi),
        radius_lower_m=float(intervals[:, 0].max()),
        radius_upper_m=float(intervals[:, 1].min()),
        foot_heights_in_base=tuple(float(z) for z in foot_heights_in_base),
    )


def _circle_roots(q: np.ndarray, d: np.ndarray, radius: float) -> tuple[np.ndarray, ...]:
    """t where |q + t d| = radius for points q (M, 2) and unit d (2,): (t-, t+, real?)."""
    qd = q @ d
    disc = qd * qd - np.einsum("ij,ij->i", q, q) + radius * radius
    root = np.sqrt(np.clip(disc, 0.0, None))
    return -qd - root, -qd + root, disc > 0


def segment_half_lengths(
    sets: ReachableSet, centres_in_base: np.ndarray, direction: np.ndarray, erosion_m: float
) -> np.ndarray:
    """Largest a [m] per centre (M, 2) such that the segment centre ± a·direction (unit (2,))
    lies inside the set eroded by ``erosion_m`` [m]; 0 where the centre itself is outside.
    Closed form: the outer circle and the two wedge half-planes bound a on both sides, the
    inner circle on the side it lies (it cannot straddle a centre outside it)."""
    c = np.atleast_2d(np.asarray(centres_in_base, float))[:, :2]
    q = c - sets.position_hip_in_base
    d = np.asarray(direction, float)[:2]
    t_lo, t_hi, _ = _circle_roots(q, d, sets.radius_upper_m - erosion_m)
    a = np.minimum(t_hi, -t_lo)
    s_lo, s_hi, real = _circle_roots(q, d, sets.radius_lower_m + erosion_m)
    a = np.where(real & (s_lo >= 0), np.minimum(a, s_lo), a)
    a = np.where(real & (s_hi <= 0), np.minimum(a, -s_hi), a)
    for normal in sets.edge_normals():
        nd = abs(float(normal @ d))
        room = q @ normal - erosion_m
        if nd > 1e-12:
            a = np.minimum(a, room / nd)
    ok = sets.contains(c, erosion_m)
    return np.where(ok, np.clip(a, 0.0, None), 0.0)
