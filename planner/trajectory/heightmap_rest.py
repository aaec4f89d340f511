"""A ball foot resting on, and rolling over, a height map's triangles (docs/physics.md, "Round
feet", and docs/terrain.md, "Height maps").

A height map is piecewise linear (planner/terrain/heightmap.py: two flat triangles per grid
square). A ball of radius r touches it where its centre is r from the surface: at the point
of the triangles nearest the centre, p, with the contact normal m = (centre - p) / r. Inside
a triangle m is the triangle's normal; over a convex crease (the ground falls away) p stays
on the crease while m turns from one triangle's normal to the next; at a concave crease (the
next triangle rises) the ball touches both triangles and, rolled on, leaves the first one for
the second: its centre, which followed the first plane, follows the second. Rolling without
slip on the triangle it touches moves the centre with v = ω × (r m), parallel to the ground
there (planner/trajectory/rolling_feet.py), so a stance ball keeps r from the map.

A stance ball that rolled along the plane under its foothold throughout (the model for
ramps and boxes) enters the next triangle where the map rises: go2's 22.9 mm balls roll
~22 mm per stance on examples/terrain/rough.yaml, across a crease in most stances, and went
up to 1.5 mm into the map (at 100 samples per unit; the terrain check refused the plan at
the first sample 1 µm in). Here the rolling uses the contact normal of each sample instead,
and :func:`rest_on_heightmap` lifts a centre the trapezoidal integral carried nearer than r
(the sample where the contact changes triangle; O(v dt δ), δ the crease's angle) along m
until it is r from every triangle: the least lift out of the ground, so a ball that touches
its triangle keeps touching it. Footholds are placed the same way
(planner/gaits/ball_stance.py): a contact point within r tan(δ/2) of a concave crease would
put the centre, r along its triangle's normal, inside the neighbouring triangle.

Only the height map's triangles are asked: where another part of the terrain (the floor
beyond the map, a box) is nearer the centre than the map, :func:`heightmap_contact` gives
NaN and the stance keeps the normal of the surface under its foothold.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from planner.terrain.heightmap import HeightMap
from planner.trajectory.ball_clearance import HEIGHTMAP_CHUNK, REACH_FACTOR

#: Passes of the lift out of the map (each puts the centre r from the triangle it is
#: nearest; a concave corner needs two).
REST_PASSES = 8

#: Centres (M, 3) [m] -> (the centres resting on the ground (M, 3) [m], the contact normals
#: (M, 3); NaN rows where the height map is not the ground the ball touches).
Ground = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]


def _nearer(best, cand):
    """Keep, point by point, the nearer of (distance (M, K), x, y, z) ``best`` and ``cand``."""
    take = cand[0] < best[0]
    return tuple(np.where(take, c, b) for b, c in zip(best, cand))


def _edge(px, py, pz, ax, ay, az, bx, by, bz):
    """(distance, x, y, z) (M, K) of the points of segments a-b nearest the points p, from
    their components (M, K) each (the grid's edges: no (M, K, 3) temporaries)."""
    ex, ey, ez = bx - ax, by - ay, bz - az
    t = ((px - ax) * ex + (py - ay) * ey + (pz - az) * ez) / (ex * ex + ey * ey + ez * ez)
    t = np.clip(t, 0.0, 1.0)
    x, y, z = ax + t * ex, ay + t * ey, az + t * ez
    return np.sqrt((px - x) ** 2 + (py - y) ** 2 + (pz - z) ** 2), x, y, z


def _face(px, py, pz, x0, y0, z0, gx, gy, res, upper: bool):
    """(distance, x, y, z) (M, K) of the foot of p on the plane z = z0 + gx (x - x0) + gy
    (y - y0) where it falls inside the grid square's lower (upper) triangle (module
    planner/terrain/heightmap.py: split along (c, r)-(c+1, r+1)), distance inf elsewhere."""
    scale = np.sqrt(1.0 + gx * gx + gy * gy)
    height = (pz - z0 - gx * (px - x0) - gy * (py - y0)) / scale  # along n = (-gx, -gy, 1)/s
    x = px + height * gx / scale
    y = py + height * gy / scale
    z = pz - height / scale
    u, v = (x - x0) / res, (y - y0) / res
    if upper:
        inside = (u >= 0.0) & (v <= 1.0) & (u <= v)
    else:
        inside = (v >= 0.0) & (u <= 1.0) & (v <= u)
    return np.where(inside, np.abs(height), np.inf), x, y, z


def heightmap_nearest(heightmap: HeightMap, points_in_world: np.ndarray, reach_m: float):
    """(distance (N,) [m], nearest point (N, 3) [m]) of points (N, 3) to the height map's
    triangles in the grid squares within ``reach_m`` [m] of them (exact where the distance
    is below ``reach_m``, as planner/trajectory/ball_clearance.py heightmap_distance, whose
    window this is): the nearer of the feet inside the triangles and the nearest points of
    the grid's edges (every square's five: its sides and its diagonal)."""
    pts = np.asarray(points_in_world, dtype=float).reshape(-1, 3)
    distance, nearest = np.full(len(pts), np.inf), np.full((len(pts), 3), np.nan)
    h, res = heightmap.heights, heightmap.resolution
    rows, cols = h.shape
    lo, _ = heightmap.extent_in_world
    window = np.arange(int(np.ceil(2.0 * reach_m / res)) + 1)
    dc, dr = (g.ravel() for g in np.meshgrid(window, window))
    for start in range(0, len(pts), HEIGHTMAP_CHUNK):
        p = pts[start : start + HEIGHTMAP_CHUNK]
        cell = np.floor((p[:, :2] - reach_m - lo) / res).astype(int)
        col = np.clip(cell[:, None, 0] + dc[None], 0, cols - 2)
        row = np.clip(cell[:, None, 1] + dr[None], 0, rows - 2)
        x0, y0 = lo[0] + res * col, lo[1] + res * row
        x1, y1 = x0 + res, y0 + res
        z00, z10 = heightmap.base_z + h[row, col], heightmap.base_z + h[row, col + 1]
        z01, z11 = heightmap.base_z + h[row + 1, col], heightmap.base_z + h[row + 1, col + 1]
        px, py, pz = (np.broadcast_to(p[:, i, None], x0.shape) for i in range(3))
        best = _face(px, py, pz, x0, y0, z00, (z10 - z00) / res, (z11 - z10) / res, res, False)
        best = _nearer(
            best, _face(px, py, pz, x0, y0, z00, (z11 - z01) / res, (z01 - z00) / res, res, True)
        )
        for a, b in (
            ((x0, y0, z00), (x1, y0, z10)),  # the square's sides and its diagonal
            ((x0, y0, z00), (x0, y1, z01)),
            ((x0, y0, z00), (x1, y1, z11)),
            ((x0, y1, z01), (x1, y1, z11)),
            ((x1, y0, z10), (x1, y1, z11)),
        ):
            best = _nearer(best, _edge(px, py, pz, *a, *b))
        k = np.argmin(best[0], axis=1)
        at = np.arange(len(p))
        distance[start : start + len(p)] = best[0][at, k]
        nearest[start : start + len(p)] = np.column_stack([c[at, k] for c in best[1:]])
    return distance, nearest


def heightmap_contact(terrain, centre_in_world: np.ndarray, radius_m: float):
    """(distance (N,) [m], contact normal (N, 3)) of balls of ``radius_m`` centred at points
    (N, 3) on a terrain with a height map: the centre's distance to the map's triangles and
    the unit vector from the nearest point to the centre; NaN normals where the map is
    farther than REACH_FACTOR r or than another part of the terrain (its distance,
    TerrainMap.sphere_clearance), or the centre is under the map."""
    pts = np.asarray(centre_in_world, dtype=float).reshape(-1, 3)
    heightmap = terrain.heightmap
    reach = REACH_FACTOR * radius_m
    distance, nearest = heightmap_nearest(heightmap, pts, reach)
    other = replace(terrain, heightmap=None).sphere_clearance(pts)
    top, _ = heightmap.top_at(pts[:, :2])
    ok = (distance < reach) & (distance <= other) & (distance > 0.0)
    ok &= ~(np.isfinite(top) & (pts[:, 2] < top))
    normal = np.full(pts.shape, np.nan)
    normal[ok] = (pts[ok] - nearest[ok]) / distance[ok, None]
    return distance, normal


def rest_on_heightmap(terrain, centre_in_world: np.ndarray, radius_m: float):
    """(centres (N, 3) [m], contact normals (N, 3)) of balls of ``radius_m`` [m] centred at
    points (N, 3) on a terrain's height map (module docstring): a centre nearer than r to
    the map's triangles is moved along its contact normal until it is r from the triangle
    it is nearest, again until it is r from every one (REST_PASSES); a centre that keeps r
    stays. The normals are those of :func:`heightmap_contact` at the centres returned.
    Repeated centres (a stance foot while the base stands still) are asked once."""
    given = np.asarray(centre_in_world, dtype=float).reshape(-1, 3)
    pts, back = np.unique(given, axis=0, return_inverse=True)
    for _ in range(REST_PASSES):
        distance, normal = heightmap_contact(terrain, pts, radius_m)
        inside = np.isfinite(normal[:, 0]) & (distance < radius_m)
        if not inside.any():
            break
        pts[inside] += (radius_m - distance[inside, None]) * normal[inside]
    back = back.reshape(-1)
    return pts[back], normal[back]


def heightmap_ground(terrain, radius_m: float) -> Ground | None:
    """The ground a rolling ball of ``radius_m`` [m] stands on (:data:`Ground`,
    :func:`rest_on_heightmap`) when ``terrain`` has a height map; None otherwise (level
    ground, ramps and boxes: the plane under each foothold, as before)."""
    if getattr(terrain, "heightmap", None) is None or radius_m <= 0.0:
        return None

    def ground(centres: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return rest_on_heightmap(terrain, centres, radius_m)

    return ground
