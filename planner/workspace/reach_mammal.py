"""Reachable ground set of a mammal leg (hip ab/adduction first) at a body height.

The insect leg's set is an annular sector about its vertical hip-yaw axis
(planner/workspace/reach_insect.py). A mammal leg (silo4kin/mammal.py: HAA about the body's x
axis, then two parallel pitch axes) has no vertical axis: at foot height z (in the planning
frame B) the foot reaches a region under the hip, bounded in x by the hip flexion (HFE) and knee
(KFE) limits and the leg's length, in y by the HAA limits and the lateral offset d. Its shape is
not a sector, so it is held as a mask on a regular (x, y) grid in B, GRID_STEP_M apart, around
the HAA point:

    node (x, y) is in the set  <=>  at every foot height z in ``foot_heights_in_base`` the
    target (x, y, z) has an IK solution on the rest pose's branch (knee branch and foot below
    the HAA axis, mammal.inverse_kinematics) within the URDF limits, with the knee at least
    ``knee_margin`` from stretched (the planar knee angle between thigh and shank, whose
    sine is |det J| up to the lengths; the insect counterpart keeps θ3 away from 0).

The mask is intersected over the foot heights (ground, half and full swing height, as the
insect set), and :meth:`MammalReachableSet.contains` erodes it by a distance (a point is
inside when it and EROSION_DIRECTIONS points at that distance around it all fall on nodes of
the set). :class:`MammalReachableSet` has the interface of reach.ReachableSet that
workspace.py, footholds.py and the workspace plot use (``contains``, ``outline``, ``empty``,
``radius_upper_m``, ``position_hip_in_base``, ``leg_name``, ``foot_heights_in_base``) and
:func:`segment_half_lengths` that of reach.segment_half_lengths (by marching instead of the
sector's closed form). tests/test_reach_mammal.py checks the mask against FK of the joint
space independently of the IK.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from silo4kin.joint_limits import within_joint_limits
from silo4kin.mammal import MammalLegGeometry, inverse_kinematics
from silo4kin.memo import cached_on_first_argument

#: Grid spacing of the mask [m]: 4 mm, ~1 % of a Go2 leg (0.43 m), 1.3 % of Solo12's.
GRID_STEP_M = 0.004
#: Points on the erosion circle checked by ``contains`` [-].
EROSION_DIRECTIONS = 16
#: Steps of the march along a segment in :func:`segment_half_lengths` [m].
MARCH_STEP_M = 0.002
#: Steps of the march tested at once (vectorised) in :func:`segment_half_lengths` [-].
MARCH_BLOCK = 32
#: Share of the longest x segment a centre on the legs' rest line may give up [-]: without
#: it the longest segment pulls the hind feet of Go2 within 6 cm of each other.
STRIDE_GIVE = 0.1


@dataclass(frozen=True, eq=False)
class MammalReachableSet:
    """Ground points one mammal foot reaches at one body height: a grid mask in B.

    Attributes:
        leg_name: e.g. "LF".
        position_hip_in_base: HAA joint origin (x, y) [m], (2,).
        x0, y0: coordinates of node (0, 0) [m]; step: grid spacing [m].
        mask: (ny, nx) bool, rows along y.
        foot_heights_in_base: the foot heights z in B whose masks were intersected [m].
    """

    leg_name: str
    position_hip_in_base: np.ndarray
    x0: float
    y0: float
    step: float
    mask: np.ndarray
    foot_heights_in_base: tuple[float, ...]
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    @property
    def empty(self) -> bool:
        """Whether no ground point is reachable."""
        return not bool(self.mask.any())

    @property
    def nodes_in_base(self) -> np.ndarray:
        """(x, y) of the nodes in the set [m], (K, 2)."""
        iy, ix = np.nonzero(self.mask)
        return np.column_stack([self.x0 + ix * self.step, self.y0 + iy * self.step])

    @property
    def radius_upper_m(self) -> float:
        """Largest horizontal distance of a reachable point from the HAA point [m] (0 if empty)."""
        if self.empty:
            return 0.0
        return float(np.max(np.hypot(*(self.nodes_in_base - self.position_hip_in_base).T)))

    def lookup_in_mask(self, mask: np.ndarray, xy: np.ndarray) -> np.ndarray:
        """Whether each point xy (..., 2) [m] in the base frame falls on a True cell of ``mask``
        (a mask on this set's grid: its own or an eroded one), (...) bool; False off the grid."""
        ny, nx = mask.shape
        ix = np.rint((xy[..., 0] - self.x0) / self.step).astype(int)
        iy = np.rint((xy[..., 1] - self.y0) / self.step).astype(int)
        ok = (ix >= 0) & (ix < nx) & (iy >= 0) & (iy < ny)
        return ok & mask[np.clip(iy, 0, ny - 1), np.clip(ix, 0, nx - 1)]

    def eroded_mask(self, erosion_m: float) -> np.ndarray:
        """The mask shrunk by ``erosion_m`` [m]: a node stays when it and the
        EROSION_DIRECTIONS nodes nearest the circle of that radius around it are all in the
        set (cached per set and distance)."""
        return _eroded(self, round(float(erosion_m), 9))

    def contains(self, position_in_base: np.ndarray, erosion_m: float = 0.0) -> np.ndarray:
        """Whether each point (N, 2) or (N, 3) [m] (x, y used) lies in the set shrunk by
        ``erosion_m`` [m] (module docstring): the nearest node of the eroded mask; (N,)."""
        p = np.atleast_2d(np.asarray(position_in_base, float))[:, :2]
        return self.lookup_in_mask(self.eroded_mask(erosion_m), p)

    def outline(self, erosion_m: float = 0.0) -> np.ndarray:
        """Closed boundary polygon (x, y) in B [m] of the set eroded by ``erosion_m`` (the
        convex hull of its nodes: a drawing, not a test), (K + 1, 2); (0, 2) when empty."""
        mask = self.eroded_mask(erosion_m)
        if not mask.any():
            return np.zeros((0, 2))
        iy, ix = np.nonzero(mask)
        hull = _convex_hull(np.column_stack([self.x0 + ix * self.step, self.y0 + iy * self.step]))
        return np.vstack([hull, hull[:1]])

    def eroded_outline(self, erosion_m: float) -> np.ndarray:
        """:meth:`outline` of the eroded set (the workspace plot's dashed line)."""
        return self.outline(erosion_m)


@cached_on_first_argument(256)
def _eroded(sets: MammalReachableSet, erosion_m: float) -> np.ndarray:
    mask = sets.mask
    if erosion_m <= 0:
        return mask
    out = mask.copy()
    ny, nx = mask.shape
    for a in np.linspace(0.0, 2.0 * np.pi, EROSION_DIRECTIONS, endpoint=False):
        dx = int(np.rint(erosion_m * np.cos(a) / sets.step))
        dy = int(np.rint(erosion_m * np.sin(a) / sets.step))
        shifted = np.zeros_like(mask)  # shifted[i, j] = mask[i + dy, j + dx]
        shifted[max(0, -dy) : ny - max(0, dy), max(0, -dx) : nx - max(0, dx)] = mask[
            max(0, dy) : ny - max(0, -dy), max(0, dx) : nx - max(0, -dx)
        ]
        out &= shifted
    return out


def _convex_hull(points: np.ndarray) -> np.ndarray:
    """Monotone-chain convex hull, counter-clockwise, (K, 2)."""
    pts = np.unique(points, axis=0)
    if len(pts) < 3:
        return pts

    def half(seq: np.ndarray) -> list:
        out: list = []
        for p in seq:
            while len(out) >= 2 and np.cross(out[-1] - out[-2], p - out[-2]) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def reachable_mask_at(
    leg: MammalLegGeometry, position_in_base_xy: np.ndarray, z: float, knee_margin_rad: float
) -> np.ndarray:
    """Whether each ground point (..., 2) [m] at foot height ``z`` [m] in B is reachable on the
    rest pose's branch within limits and ``knee_margin_rad`` from stretched; (...,)."""
    xy = np.asarray(position_in_base_xy, float)
    target = np.concatenate([xy, np.full(xy.shape[:-1] + (1,), float(z))], axis=-1)
    ik = inverse_kinematics(leg, target)
    q = np.where(np.isfinite(ik.q), ik.q, 0.0)
    ok = ik.reachable & within_joint_limits(q, leg.q_lower, leg.q_upper)
    return ok & (knee_angle(leg, q) >= knee_margin_rad)


def knee_angle(leg: MammalLegGeometry, q: np.ndarray) -> np.ndarray:
    """Angle between thigh and shank in the leg plane [rad], (...,): 0 stretched, π folded;
    the leg is singular at 0 (|det J| ∝ its sine)."""
    theta3 = np.asarray(q, float)[..., 2] * leg.knee_sign
    u, w = leg.thigh_in_plane, leg.shank_in_plane
    c, s = np.cos(-theta3), np.sin(-theta3)
    wr = np.stack([c * w[0] - s * w[1], s * w[0] + c * w[1]], axis=-1)
    cross = u[0] * wr[..., 1] - u[1] * wr[..., 0]
    return np.abs(np.arctan2(cross, wr @ u))


def reachable_set(
    leg: MammalLegGeometry,
    foot_heights_in_base: tuple[float, ...],
    knee_margin_rad: float,
    step_m: float = GRID_STEP_M,
) -> MammalReachableSet:
    """The leg's ground set: masks at every foot height in ``foot_heights_in_base`` [m]
    intersected (module docstring)."""
    hip = np.asarray(leg.position_hip_in_base[:2], float)
    # the foot stays within L = |c0| + |u| + |w| of the HFE point along x, and within
    # R = sqrt(d² + L²) of the HAA axis: at depth dz below it, |dy| <= sqrt(R² - dz²)
    length = leg.size_m - abs(leg.lateral_offset)
    radius2 = leg.lateral_offset**2 + length**2
    dz = min(abs(float(z) - float(leg.position_hip_in_base[2])) for z in foot_heights_in_base)
    half_y = float(np.sqrt(max(radius2 - dz * dz, 0.0))) + step_m
    half_x = length + step_m
    xs = np.arange(hip[0] - half_x, hip[0] + half_x + step_m, step_m)
    ys = np.arange(hip[1] - half_y, hip[1] + half_y + step_m, step_m)
    grid = np.stack(np.meshgrid(xs, ys), axis=-1)  # (ny, nx, 2)
    mask = np.ones(grid.shape[:2], bool)
    for z in foot_heights_in_base:  # each level only where all before pass
        iy, ix = np.nonzero(mask)
        mask[iy, ix] = reachable_mask_at(leg, grid[iy, ix], z, knee_margin_rad)
    return MammalReachableSet(
        leg_name=leg.name,
        position_hip_in_base=hip,
        x0=float(xs[0]),
        y0=float(ys[0]),
        step=float(step_m),
        mask=mask,
        foot_heights_in_base=tuple(float(z) for z in foot_heights_in_base),
    )


def segment_half_lengths(
    sets: MammalReachableSet, centres_in_base: np.ndarray, direction: np.ndarray, erosion_m: float
) -> np.ndarray:
    """Largest a [m] per centre (M, 2) such that the segment centre ± a·direction (unit (2,))
    lies inside the set eroded by ``erosion_m`` [m] (marched in MARCH_STEP_M steps, both ways
    at once); 0 where the centre itself is outside.

    The march is vectorised over centres and MARCH_BLOCK steps at a time (the same result as
    one step at a time: a is the last step before the first one that leaves the set)."""
    c = np.atleast_2d(np.asarray(centres_in_base, float))[:, :2]
    d = np.asarray(direction, float)[:2]
    mask = sets.eroded_mask(erosion_m)
    steps = np.arange(0.0, 2.0 * sets.step * sets.mask.shape[1] + MARCH_STEP_M, MARCH_STEP_M)
    a = np.zeros(len(c))
    alive = sets.lookup_in_mask(mask, c)
    for start in range(1, len(steps), MARCH_BLOCK):
        idx = np.flatnonzero(alive)
        if idx.size == 0:
            break
        t = steps[start : start + MARCH_BLOCK]  # (B,)
        offset = t[None, :, None] * d  # (1, B, 2)
        ok = sets.lookup_in_mask(mask, c[idx, None, :] + offset) & sets.lookup_in_mask(
            mask, c[idx, None, :] - offset
        )  # (m, B)
        fails = ~ok
        first = np.where(fails.any(axis=1), np.argmax(fails, axis=1), t.size)  # steps kept
        kept = first > 0
        a[idx[kept]] = t[first[kept] - 1]
        alive[idx[first < t.size]] = False
    return a


def rest_lateral_in_base(leg: MammalLegGeometry) -> float:
    """y of the foot with the HAA at zero (leg plane vertical) in B [m]: the HAA point's y
    plus the lateral offset d along the pitch axis (its y component)."""
    return float(leg.position_hip_in_base[1] + leg.lateral_offset * leg.axis_pitch_in_base[1])


def choose_centres(
    sets: tuple[MammalReachableSet, ...],
    erosion_m: float,
    crab_rad: float,
    rest_y_in_base: np.ndarray | None = None,
    candidate_step_m: float = 0.01,
) -> tuple[np.ndarray, np.ndarray]:
    """Position 2 of every leg (4, 2) [m] in B and its segment extents (4, 2) [m] (full
    lengths along x and y), as footholds.choose_centres does for insect legs: among the set's
    nodes on a ``candidate_step_m`` sub-grid (eroded by ``erosion_m``), the one with the
    longest segment along x (fitted along x turned by 0 and ±crab_rad), then among those
    within STRIDE_GIVE of it the one nearest the middle of the set in x and, in
    y, the foot's rest line ``rest_y_in_base`` (4,) [m] (:func:`rest_lateral_in_base`, HAA
    at zero: the legs stand upright as in the robots' rest poses; centres nearer the body
    put the hind feet within the interference clearance of each other). Without
    ``rest_y_in_base``: the longest along y, then the set's middle. A leg whose eroded set is
    empty gets its HAA point and zero extents."""
    from planner.workspace.footholds import CENTRE_TIE_M

    centres = np.zeros((len(sets), 2))
    extents = np.zeros((len(sets), 2))
    for k, s in enumerate(sets):
        nodes = s.nodes_in_base
        sub = max(1, int(round(candidate_step_m / s.step)))
        ix = np.rint((nodes[:, 0] - s.x0) / s.step).astype(int)
        iy = np.rint((nodes[:, 1] - s.y0) / s.step).astype(int)
        cand = nodes[(ix % sub == 0) & (iy % sub == 0)]
        cand = cand[s.contains(cand, erosion_m)] if len(cand) else cand
        if len(cand) == 0:
            centres[k] = s.position_hip_in_base
            continue
        ax = np.min(
            [
                segment_half_lengths(s, cand, np.array([np.cos(a), np.sin(a)]), erosion_m)
                for a in (-crab_rad, 0.0, crab_rad)
            ],
            axis=0,
        )
        along_y = np.array([0.0, 1.0])
        ay = None
        if rest_y_in_base is None:
            ay = segment_half_lengths(s, cand, along_y, erosion_m)
            keep = ax >= ax.max() - CENTRE_TIE_M
            keep &= ay >= ay[keep].max() - CENTRE_TIE_M
        else:
            keep = ax >= (1.0 - STRIDE_GIVE) * ax.max()
        middle = nodes.mean(axis=0)
        if rest_y_in_base is not None:
            middle[1] = rest_y_in_base[k]
        off = np.where(keep, np.hypot(*(cand - middle).T), np.inf)
        i = int(np.argmin(off))
        centres[k] = cand[i]
        # on the rest line only the chosen centre's y extent is read: march it alone (each
        # centre's march is independent; a quarter of `silo4 robots`' segment marches)
        ay_i = (
            ay[i]
            if ay is not None
            else segment_half_lengths(s, cand[i : i + 1], along_y, erosion_m)[0]
        )
        extents[k] = 2.0 * ax[i], 2.0 * ay_i
    return centres, extents
