"""Signed clearance of capsules (a segment inflated by a radius) from a TerrainMap's parts.

A capsule's clearance from a solid is the least signed distance of its axis from the solid,
less its radius. TerrainMap.sphere_clearance measures one sphere; a capsule measured as
spheres at points of its axis misses the part of the axis between them that is nearest: a
sloping shank crossing a block's top edge is nearest the edge at a point of the axis no
point was put on (up to half the spacing of the points too far off, the distance being
1-Lipschitz). Here each part is measured along the whole axis:

- floor: the half-space under ``floor_z``: the lower end of the axis (exact);
- boxes and cylinders: their signed distance (planner/terrain/shapes.py) is a convex function
  of the point (the signed distance of a convex solid), so along the axis p(t) = a + t (b - a),
  t in [0, 1], it has one minimum, found by golden-section search to GOLDEN_TOLERANCE of the
  axis length (the ends are measured too);
- height map: not convex: the axis is cut into points at most HEIGHTMAP_SPACING_M apart, each
  measured as TerrainMap.sphere_clearance measures a sphere on the map (a sampled disc).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

#: Golden-section search stops when the bracket is this fraction of the axis length (the
#: distance found is then within this fraction of the length of the least: 0.3 µm on a
#: 0.3 m shank).
GOLDEN_TOLERANCE = 1e-6
#: Spacing of the points of a capsule's axis measured against a height map [m].
HEIGHTMAP_SPACING_M = 0.005
_INVERSE_GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


def segment_minimum(
    distance: Callable[[np.ndarray], np.ndarray], start: np.ndarray, end: np.ndarray
) -> np.ndarray:
    """The least value (N,) of a convex function ``distance`` of points (N, 3) -> (N,) along
    each segment ``start`` -> ``end`` (N, 3) [m]: golden-section search on t in [0, 1],
    vectorised over the segments, the ends included."""
    start = np.asarray(start, dtype=float).reshape(-1, 3)
    step = np.asarray(end, dtype=float).reshape(-1, 3) - start
    low, high = np.zeros(len(start)), np.ones(len(start))

    def at(t: np.ndarray) -> np.ndarray:
        return distance(start + t[:, None] * step)

    left = high - _INVERSE_GOLDEN * (high - low)
    right = low + _INVERSE_GOLDEN * (high - low)
    f_left, f_right = at(left), at(right)
    iterations = int(np.ceil(np.log(GOLDEN_TOLERANCE) / np.log(_INVERSE_GOLDEN)))
    for _ in range(iterations):
        keep_low = f_left <= f_right  # the minimum lies in [low, right]: right moves in
        high = np.where(keep_low, right, high)
        low = np.where(keep_low, low, left)
        fresh = np.where(
            keep_low, high - _INVERSE_GOLDEN * (high - low), low + _INVERSE_GOLDEN * (high - low)
        )
        f_fresh = at(fresh)
        left, right, f_left, f_right = (
            np.where(keep_low, fresh, right),
            np.where(keep_low, left, fresh),
            np.where(keep_low, f_fresh, f_right),
            np.where(keep_low, f_left, f_fresh),
        )
    ends = np.minimum(at(np.zeros(len(start))), at(np.ones(len(start))))
    return np.minimum(np.minimum(f_left, f_right), ends)


def _ground_distances(terrain, start: np.ndarray, end: np.ndarray, radius: np.ndarray) -> list:
    """The axis distances (N,) [m] from the floor and the height map, those present."""
    from planner.terrain.terrain_map import TerrainMap

    rows = []
    if terrain.floor_z is not None:
        rows.append(np.minimum(start[:, 2], end[:, 2]) - float(terrain.floor_z))
    if terrain.heightmap is not None:
        alone = TerrainMap(floor_z=None, heightmap=terrain.heightmap)
        length = float(np.max(np.linalg.norm(end - start, axis=1), initial=0.0))
        points = max(2, int(np.ceil(length / HEIGHTMAP_SPACING_M)) + 1)
        t = np.linspace(0.0, 1.0, points)
        axis = start[:, None, :] + t[None, :, None] * (end - start)[:, None, :]
        each = alone.sphere_clearance(axis.reshape(-1, 3), np.repeat(radius, points))
        rows.append(each.reshape(len(start), points).min(axis=1) + radius)
    return rows


def _segments(start_in_world, end_in_world, radius_m) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # noqa: ANN001
    start = np.asarray(start_in_world, dtype=float).reshape(-1, 3)
    end = np.asarray(end_in_world, dtype=float).reshape(-1, 3)
    return start, end, np.broadcast_to(np.asarray(radius_m, dtype=float), (len(start),))


def capsule_clearance_by_part(
    terrain, start_in_world: np.ndarray, end_in_world: np.ndarray, radius_m
) -> np.ndarray:
    """Signed clearance [m] of capsules (axis ends (N, 3) in W [m], radius (N,) or one [m])
    from each part of the TerrainMap ``terrain``, shape (K, N) for its K parts in
    ``terrain.part_names()`` order (module docstring); +inf for a part out of reach."""
    start, end, radius = _segments(start_in_world, end_in_world, radius_m)
    rows = _ground_distances(terrain, start, end, radius)
    for solid in (*terrain.boxes, *terrain.cylinders):
        rows.append(segment_minimum(solid.signed_distance, start, end))
    if not rows:
        return np.full((0, len(start)), np.inf)
    return np.array(rows) - radius[None, :]


def capsule_clearance(
    terrain, start_in_world: np.ndarray, end_in_world: np.ndarray, radius_m
) -> np.ndarray:
    """The least over the parts of :func:`capsule_clearance_by_part`, shape (N,) [m] (+inf
    for a terrain without parts), searching a solid only on the capsules it may be nearest:
    the signed distance is 1-Lipschitz, so along an axis of half length l it is at least its
    value at the axis's midpoint less l; where that bound is no less than the least distance
    found so far the solid cannot lower it (the same answer, without the search)."""
    start, end, radius = _segments(start_in_world, end_in_world, radius_m)
    best = np.full(len(start), np.inf)
    for row in _ground_distances(terrain, start, end, radius):
        best = np.minimum(best, row)
    middle, half = 0.5 * (start + end), 0.5 * np.linalg.norm(end - start, axis=1)
    for solid in (*terrain.boxes, *terrain.cylinders):
        rows = np.flatnonzero(solid.signed_distance(middle) - half < best)
        if rows.size:
            near = segment_minimum(solid.signed_distance, start[rows], end[rows])
            best[rows] = np.minimum(best[rows], near)
    return best - radius


def capsule_clears(
    terrain, start_in_world: np.ndarray, end_in_world: np.ndarray, radius_m, min_clearance_m: float
) -> np.ndarray:
    """(N,) bool: whether :func:`capsule_clearance` is at least ``min_clearance_m`` [m], the
    same answer measuring a part only on the capsules it may bring under it, and only while
    the capsule is still clear: a height map where the axis's lower end is within
    ``min_clearance_m`` + radius of its highest sample, a solid where the axis's midpoint is
    within ``min_clearance_m`` + radius + half the axis's length of it (the bound of
    :func:`capsule_clearance`). The foothold search asks this of many candidates
    (planner/gaits/shank_clearance.py)."""
    from planner.terrain.terrain_map import TerrainMap

    start, end, radius = _segments(start_in_world, end_in_world, radius_m)
    low = np.minimum(start[:, 2], end[:, 2])
    clear = np.ones(len(start), dtype=bool)
    if terrain.floor_z is not None:
        clear &= low - float(terrain.floor_z) - radius >= min_clearance_m
    if terrain.heightmap is not None:
        top = terrain.heightmap.base_z + float(np.max(terrain.heightmap.heights))
        rows = np.flatnonzero(clear & (low - top - radius < min_clearance_m))
        if rows.size:
            alone = TerrainMap(floor_z=None, heightmap=terrain.heightmap)
            (least,) = _ground_distances(alone, start[rows], end[rows], radius[rows])
            clear[rows] = least - radius[rows] >= min_clearance_m
    middle, half = 0.5 * (start + end), 0.5 * np.linalg.norm(end - start, axis=1)
    for solid in (*terrain.boxes, *terrain.cylinders):
        rows = np.flatnonzero(clear)
        if not rows.size:
            break
        near = solid.signed_distance(middle[rows]) - half[rows] - radius[rows] < min_clearance_m
        rows = rows[near]
        if rows.size:
            least = segment_minimum(solid.signed_distance, start[rows], end[rows])
            clear[rows] = least - radius[rows] >= min_clearance_m
    return clear
