"""Footholds and strides of the default workspace inside the legs' reachable sets.

Each leg's position 2 (the centre of its footholds, thesis §4.2.1) is chosen on its rest ray (θ1
= 0, the middle of the hip-yaw range, as the thesis's square centre) inside its reachable set
(planner/workspace/reach_insect.py) eroded by the stability-shift reserve: the point giving the
longest segment along the body x axis (the path follower's travel direction), then among those
within CENTRE_TIE_M of it the longest along y, then the one farthest from the CoG. (Centres off
the rest ray give longer x segments but narrow, sideways stances whose transitions between
creeping and spinning need body shifts beyond the reserve: tried and dropped.) The stride along
x, λ_x, is the shortest such segment over the legs (all legs step λ); λ_y likewise. The stride
along x need not equal the one along y: a sideways leg with a ±57° hip yaw reaches far along x
and little along y. The x segments are fitted along x turned by 0 and ±CRAB_ROOM_RAD.

Then the stride is shortened until the creeping gait is statically stable: at every lift of a
cycle (4-2-B-3-1-B, gaits.py) the three stance feet must leave a point within STABLE_SHIFT_M of
the nominal CoG with support margin >= the threshold (the body shifts there before the lift,
steps.py). :func:`lift_margin` is the one place the stability criterion
(planner/stability/margin.support_margin) is called, so the whole-body criterion replaces it in
one line.
"""

from __future__ import annotations

import numpy as np

from planner.stability.margin import support_margin
from planner.ties import tie_key
from planner.workspace.reach_insect import ReachableSet, segment_half_lengths

#: Polar grid of candidate centres per leg [samples per axis].
CENTRE_SAMPLES = 30
#: The x segments are also fitted turned by ± this [rad], so the crab gait's footholds
#: (gaits.CRAB_MAX_RAD, tested equal) stay inside the reserve.
CRAB_ROOM_RAD = np.deg2rad(10.0)
#: Candidate centres this close to the best segment length count as ties [m].
CENTRE_TIE_M = 1e-3
#: How far the CoG may shift from its nominal position for a lift, in the feasibility test [m]:
#: 60 % of workspace.SHIFT_RESERVE_M, the reserve within which every foothold stays reachable
#: (the rest covers shifts carried over between lifts and the crab gait).
STABLE_SHIFT_M = 0.03
#: Disk of CoG positions tried within STABLE_SHIFT_M: radii x angles.
_DISK = np.array(
    [
        [r * np.cos(a), r * np.sin(a)]
        for r in np.linspace(0.0, 1.0, 5)
        for a in np.linspace(0.0, 2.0 * np.pi, 16, endpoint=False)
    ]
)


def lift_margin(stance_feet_xy: np.ndarray, position_cog_xy: np.ndarray) -> np.ndarray:
    """Support margin S_m [m] of three stance feet (N, 3, 2) for CoG projections (N, 2) in the
    same frame; (N,): the planner's criterion, planner/stability/margin.support_margin."""
    feet = np.asarray(stance_feet_xy, float)
    return support_margin(feet, np.ones(feet.shape[:2], bool), position_cog_xy)


def best_shifted_margin(stance_feet_xy: np.ndarray, shift_m: float) -> np.ndarray:
    """Largest common lift_margin over CoG positions within ``shift_m`` [m] of the origin
    (the nominal CoG), for groups of triangles (G, T, 3, 2) [m] that one CoG position must
    serve (the two lifts of a half cycle: the body does not move between them); (G,)."""
    g, t = stance_feet_xy.shape[:2]
    n = _DISK.shape[0]
    cog = np.tile(shift_m * _DISK, (g * t, 1))
    feet = np.repeat(stance_feet_xy.reshape(g * t, 3, 2), n, axis=0)
    return lift_margin(feet, cog).reshape(g, t, n).min(axis=1).max(axis=1)


def creep_pairs_from_hips(
    position_hip_in_base: np.ndarray, direction: np.ndarray
) -> tuple[tuple[int, int], tuple[int, int]]:
    """The pairs of gaits.creep_pairs (same rule, from the hips (4, 3) [m]): first the two legs
    right of the travel direction (unit (2,)), then the others, each rear leg first."""
    d = np.asarray(direction, float)
    right = np.array([d[1], -d[0]])
    hips = position_hip_in_base[:, :2]
    first = sorted(
        (k for k in range(4) if tie_key(hips[k] @ right) > 0), key=lambda k: tie_key(hips[k] @ d)
    )
    second = sorted(
        (k for k in range(4) if tie_key(hips[k] @ right) <= 0), key=lambda k: tie_key(hips[k] @ d)
    )
    return (first[0], first[1]), (second[0], second[1])


def creep_lift_triangles(
    position_hip_in_base: np.ndarray,
    position_mid_in_base: np.ndarray,
    stride_m: float,
    direction: np.ndarray,
) -> np.ndarray:
    """Stance triangles (4, 3, 2) [m] in B at the four lifts of a creeping cycle along
    ``direction`` (gaits.py: the pair at the rear swings to the front, rear leg first; the body
    then moves λ/2, which puts the other pair at the rear)."""
    d = np.asarray(direction, float)[:2]
    mid = position_mid_in_base[:, :2]
    first, second = creep_pairs_from_hips(position_hip_in_base, d)
    out = []
    for rear_pair, other in ((first, second), (second, first)):
        a1, a2 = rear_pair
        feet = mid.copy()
        feet[a1] -= 0.5 * stride_m * d
        feet[a2] -= 0.5 * stride_m * d
        out.append(feet[[a2, other[0], other[1]]])  # a1 lifts
        feet[a1] = mid[a1] + 0.5 * stride_m * d
        out.append(feet[[a1, other[0], other[1]]])  # a2 lifts
    return np.array(out)


def stable_stride(
    position_hip_in_base: np.ndarray,
    position_mid_in_base: np.ndarray,
    longest_m: float,
    directions: np.ndarray,
    threshold_m: float,
    shift_m: float = STABLE_SHIFT_M,
    samples: int = 32,
    iterations: int = 12,
) -> float:
    """Longest stride <= ``longest_m`` [m] whose creeping lifts along every direction (D, 2)
    each keep a margin >= ``threshold_m`` [m] with the CoG shifted at most
    ``shift_m`` [m] from its nominal position; 0 when none does. Stability need not be
    monotonic in the stride, so the strides are scanned from the longest down on a grid of
    ``samples`` and the first passing one refined by bisection towards the failing one above
    it (vectorised over the grid)."""

    def ok(strides: np.ndarray) -> np.ndarray:  # (S,) -> (S,) bool
        tri = np.stack(
            [
                np.concatenate(
                    [
                        creep_lift_triangles(
                            position_hip_in_base, position_mid_in_base, float(lam), d
                        )
                        for d in directions
                    ]
                )
                for lam in strides
            ]
        )  # (S, 4 D, 3, 2)
        n = tri.shape[1]
        margins = best_shifted_margin(tri.reshape(-1, 1, 3, 2), shift_m).reshape(-1, n)
        return np.all(margins >= threshold_m, axis=1)

    if ok(np.array([longest_m]))[0]:
        return float(longest_m)
    grid = np.linspace(longest_m, 0.0, samples)
    passing = np.flatnonzero(ok(grid))
    if passing.size == 0:
        return 0.0
    i = int(passing[0])
    good, bad = float(grid[i]), float(grid[i - 1])
    for _ in range(iterations):
        m = 0.5 * (good + bad)
        good, bad = (m, bad) if ok(np.array([m]))[0] else (good, m)
    return good


def choose_centres(
    sets: tuple[ReachableSet, ...], erosion_m: float, yaw_reserve_rad: float
) -> tuple[np.ndarray, np.ndarray]:
    """Position 2 of every leg (4, 2) [m] in B and its segment extents (4, 2) [m] (full
    lengths along x and y) inside the reachable sets eroded by ``erosion_m`` [m] (module
    docstring). Position 2 keeps ``yaw_reserve_rad`` [rad] from both hip-yaw limits: the
    spinning gait turns the stance about it. A leg whose eroded set is empty gets its hip
    position and zero extents."""
    centres = np.zeros((len(sets), 2))
    extents = np.zeros((len(sets), 2))
    for k, s in enumerate(sets):
        r_lo, r_hi = s.radius_lower_m + erosion_m, s.radius_upper_m - erosion_m
        yaw_lo, yaw_hi = s.yaw_lower_rad + yaw_reserve_rad, s.yaw_upper_rad - yaw_reserve_rad
        if not (r_lo < r_hi and yaw_lo < yaw_hi):
            centres[k] = s.position_hip_in_base
            continue
        rest = 0.5 * (s.yaw_lower_rad + s.yaw_upper_rad)  # θ1 = 0 for symmetric limits
        rr, pp = np.meshgrid(np.linspace(r_lo, r_hi, CENTRE_SAMPLES * 4), np.array([rest]))
        cand = s.position_hip_in_base + np.stack(
            [rr.ravel() * np.cos(pp.ravel()), rr.ravel() * np.sin(pp.ravel())], axis=1
        )
        ax = np.min(
            [
                segment_half_lengths(s, cand, np.array([np.cos(a), np.sin(a)]), erosion_m)
                for a in (-CRAB_ROOM_RAD, 0.0, CRAB_ROOM_RAD)
            ],
            axis=0,
        )
        ay = segment_half_lengths(s, cand, np.array([0.0, 1.0]), erosion_m)
        if not np.any(ax > 0):
            centres[k] = s.position_hip_in_base
            continue
        keep = ax >= ax.max() - CENTRE_TIE_M
        keep &= ay >= ay[keep].max() - CENTRE_TIE_M
        spread = np.where(keep, np.hypot(cand[:, 0], cand[:, 1]), -np.inf)
        i = int(np.argmax(spread))
        centres[k] = cand[i]
        extents[k] = 2.0 * ax[i], 2.0 * ay[i]
    return centres, extents
