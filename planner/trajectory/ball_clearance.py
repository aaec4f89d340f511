"""How far a ball foot keeps from a terrain file's ground, and the first sample where one
enters it (planner/trajectory/terrain_clearance.py checks every plan on a terrain with it).

A ball of radius r centred on the foot frame (silo4kin.foot_contact.FootBall: the rolling
radius, the equivalent ball of an offset one) enters the terrain when its centre is nearer
than r to it. A ball resting on a ramp of slope a touches it at centre - r n, r / cos(a)
above the surface straight under the centre; a centre put r straight above a point of the
ramp enters it by r (1 - cos a) although that point is on the surface. So the measure is
the centre's distance to the terrain, not a height: :func:`ball_clearance`, exact for the
floor (its half-space), boxes and cylinders (TerrainMap.sphere_clearance, their signed
distances) and a height map (the distance to the triangles of its grid squares near the
centre, planner/terrain/heightmap.py's triangulation; TerrainMap.sphere_clearance samples a
disc there, which on a slope counts a resting ball as inside).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from planner.terrain.heightmap import HeightMap
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.samples import LEGS
from silo4kin.frames import rotation_z
from silo4kin.legs import forward_kinematics

#: How far inside the ground a sampled foot may be (rounding) [m].
BELOW_TOLERANCE_M = 1e-6
#: A height map's distance is measured exactly up to this multiple of the ball's radius
#: (beyond it, the clearance is a lower bound: the check needs it exact below the radius).
REACH_FACTOR = 1.1
#: Points measured against a height map's triangles per vectorised pass.
HEIGHTMAP_CHUNK = 2048


def ball_centres_in_world(legs, trajectory) -> np.ndarray:
    """The foot frames (N, 4, 3) [m] in W of the sampled joints: the closed-form forward
    kinematics of each leg (``legs`` in B, the planning robot's) turned by the body's yaw
    onto its base, so what the robot does rather than the targets it was asked for."""
    n = len(trajectory)
    q = np.asarray(trajectory.q, dtype=float).reshape(n, -1, 3)
    foot_in_base = np.stack([forward_kinematics(leg, q[:, k]) for k, leg in enumerate(legs)], 1)
    turned = np.einsum("nij,nkj->nki", rotation_z(trajectory.yaw_base_in_world), foot_in_base)
    return np.asarray(trajectory.position_base_in_world, dtype=float)[:, None, :] + turned


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance (...) [m] of points p from the segments a-b (..., 3)."""
    ab = b - a
    t = np.clip(np.sum((p - a) * ab, -1) / np.maximum(np.sum(ab * ab, -1), 1e-300), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[..., None] * ab), axis=-1)


def triangle_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Distance (...) [m] of points p (..., 3) from the triangles a, b, c (..., 3): to the
    plane where the projection falls inside the triangle, else to the nearest edge."""
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    height = np.sum((p - a) * normal, -1)
    foot = p - height[..., None] * normal
    inside = np.ones(height.shape, dtype=bool)
    for u, v in ((a, b), (b, c), (c, a)):  # the foot on the inner side of every edge
        inside &= np.sum(np.cross(v - u, foot - u) * normal, -1) >= 0.0
    edges = np.minimum(
        np.minimum(_segment_distance(p, a, b), _segment_distance(p, b, c)),
        _segment_distance(p, c, a),
    )
    return np.where(inside, np.abs(height), edges)


def heightmap_distance(heightmap: HeightMap, centre_in_world: np.ndarray, reach_m: float):
    """Signed distance (N,) [m] of points (N, 3) from the height map's surface: minus the
    depth below it where a point is under it, else the distance to the nearest triangle of
    the grid squares within ``reach_m`` [m] of it (exact below ``reach_m``; ``reach_m``, a
    lower bound, where it is farther). The map's border, where it stops above the floor, is
    not a face here (nor in TerrainMap.sphere_clearance's disc)."""
    pts = np.asarray(centre_in_world, dtype=float).reshape(-1, 3)
    out = np.full(len(pts), np.inf)
    top, _ = heightmap.top_at(pts[:, :2])
    below = np.isfinite(top) & (pts[:, 2] < top)
    out[below] = pts[below, 2] - top[below]
    h, res = heightmap.heights, heightmap.resolution
    rows, cols = h.shape
    lo, _ = heightmap.extent_in_world
    window = np.arange(int(np.ceil(2.0 * reach_m / res)) + 1)  # squares across 2 reach_m
    dc, dr = (g.ravel() for g in np.meshgrid(window, window))
    todo = np.flatnonzero(~below)
    for start in range(0, len(todo), HEIGHTMAP_CHUNK):
        idx = todo[start : start + HEIGHTMAP_CHUNK]
        cell = np.floor((pts[idx, :2] - reach_m - lo) / res).astype(int)  # (M, 2): col, row
        col = np.clip(cell[:, None, 0] + dc[None], 0, cols - 2)
        row = np.clip(cell[:, None, 1] + dr[None], 0, rows - 2)

        def vertex(dcol: int, drow: int, col=col, row=row) -> np.ndarray:
            xy = lo + res * np.stack([col + dcol, row + drow], axis=-1)
            z = heightmap.base_z + h[row + drow, col + dcol]
            return np.concatenate([xy, z[..., None]], axis=-1)

        v00, v10, v01, v11 = vertex(0, 0), vertex(1, 0), vertex(0, 1), vertex(1, 1)
        p = np.broadcast_to(pts[idx, None, :], v00.shape)
        near = np.minimum(  # the two triangles of each square, split along (c, r)-(c+1, r+1)
            triangle_distance(p, v00, v10, v11), triangle_distance(p, v00, v11, v01)
        ).min(axis=1)
        # a surface point nearer than reach_m lies over the window: near is exact below
        # reach_m, and the distance is at least reach_m where near is not
        out[idx] = np.minimum(near, reach_m)
    return out


def ball_clearance(terrain: TerrainMap, centre_in_world: np.ndarray, radius_m: float):
    """Signed clearance (N,) [m] of balls of ``radius_m`` [m] centred at points (N, 3) from
    the terrain (module docstring): the least over the parts of the centre's distance less
    the radius; negative: the ball enters the ground."""
    pts = np.asarray(centre_in_world, dtype=float).reshape(-1, 3)
    if terrain.heightmap is None:
        return terrain.sphere_clearance(pts, radius_m)
    rest = replace(terrain, heightmap=None).sphere_clearance(pts, radius_m)
    reach = REACH_FACTOR * radius_m  # exact where it matters, below the radius
    return np.minimum(rest, heightmap_distance(terrain.heightmap, pts, reach) - radius_m)


def foot_violation(legs, trajectory, terrain: TerrainMap, foot_radius_m: float) -> str | None:
    """The first sample where a foot enters the terrain, in words naming the terrain and the
    part under the foot; None when none does. A point foot (``foot_radius_m`` 0) is its
    sampled contact point, measured by its height above the ground under it; a ball foot is
    the ball of ``foot_radius_m`` [m] on its foot frame (:func:`ball_centres_in_world`),
    measured by :func:`ball_clearance`. Either may be BELOW_TOLERANCE_M inside (rounding)."""
    if foot_radius_m > 0.0:
        feet = ball_centres_in_world(legs, trajectory)
        low = ball_clearance(terrain, feet.reshape(-1, 3), foot_radius_m)
        what = f"the {1e3 * foot_radius_m:.1f} mm ball of foot"
    else:
        feet = trajectory.position_foot_in_world  # (N, 4, 3)
        low = terrain.lowest_clearance(feet.reshape(-1, 3))
        what = "foot"
    low = low.reshape(feet.shape[:2])
    bad = np.argwhere(low < -BELOW_TOLERANCE_M)
    if not bad.size:
        return None
    i, k = bad[0]
    return (
        f"{terrain.label()}: {what} {LEGS[k]} is {1e3 * -low[i, k]:.3g} mm inside the terrain "
        f"over {terrain.describe_at(feet[i, k, :2])} at t = {trajectory.t[i]:.2f} s"
    )
