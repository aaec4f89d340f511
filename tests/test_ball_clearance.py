"""The ball-foot measures on tilted ground, checked against geometry computed another way:
the distance to a height map (planner/trajectory/ball_clearance.py) against a plane's
closed form and a dense sampling of the surface; the rolling velocity on a plane
(planner/trajectory/rolling_feet.py) against the level formula and finite differences."""

from __future__ import annotations

import numpy as np

from planner.terrain.heightmap import HeightMap
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.ball_clearance import ball_clearance, heightmap_distance
from planner.trajectory.rolling_feet import rolling_velocity_in_world, rolling_velocity_on_plane

RADIUS_M = 0.0229
SLOPE = 0.15  # dz/dx of the tilted map


def _tilted_map() -> HeightMap:
    x = np.arange(41) * 0.02
    heights = np.tile(SLOPE * x, (41, 1))  # rows along y, columns along x
    return HeightMap(heights, 0.02, np.array([0.0, 0.0]))


def test_a_ball_resting_on_a_tilted_height_map_touches_it():
    """A centre r along the plane's normal from a point of it is r from the map (the plane's
    distance formula), so the ball's clearance is 0; 0.1 mm further in, -0.1 mm. The disc
    the terrain's sphere clearance samples counts the resting ball as inside."""
    terrain = TerrainMap(floor_z=0.0, heightmap=_tilted_map())
    normal = np.array([-SLOPE, 0.0, 1.0]) / np.hypot(SLOPE, 1.0)
    xy = np.array([[0.31, 0.4], [0.4, 0.37], [0.5525, 0.5]])
    surface = np.column_stack([xy, SLOPE * xy[:, 0]])
    centres = surface + RADIUS_M * normal
    np.testing.assert_allclose(ball_clearance(terrain, centres, RADIUS_M), 0.0, atol=1e-12)
    inner = centres - 1e-4 * normal
    np.testing.assert_allclose(ball_clearance(terrain, inner, RADIUS_M), -1e-4, atol=1e-12)
    assert np.all(terrain.sphere_clearance(centres, RADIUS_M) < -1e-4)


def test_height_map_distance_matches_a_dense_sampling_of_its_surface():
    """Over a bumpy map, the distance of points near it equals the least distance to the
    surface sampled every 0.5 mm (to the sampling's resolution, never above it)."""
    rng = np.random.default_rng(3)
    heights = rng.uniform(0.0, 0.03, (21, 21))
    hmap = HeightMap(heights, 0.02, np.array([0.0, 0.0]))
    xy = rng.uniform(0.1, 0.3, (12, 2))
    top, _ = hmap.top_at(xy)
    centres = np.column_stack([xy, top + rng.uniform(0.002, 0.03, 12)])
    exact = heightmap_distance(hmap, centres, 0.05)
    g = np.arange(-0.05, 0.05 + 1e-12, 0.0005)
    gx, gy = np.meshgrid(g, g)
    for c, d in zip(centres, exact):
        pts = np.column_stack([c[0] + gx.ravel(), c[1] + gy.ravel()])
        z, _ = hmap.top_at(pts)
        sampled = np.min(np.linalg.norm(np.column_stack([pts, z]) - c, axis=1))
        assert d <= sampled + 1e-12
        assert sampled - d < 6e-4  # the sampling spacing bounds its error
    below = centres - [0.0, 0.0, 0.05]
    assert np.all(heightmap_distance(hmap, below, 0.05) < 0.0)


def _smooth_motion(n: int = 401):
    t = np.linspace(0.0, 1.0, n)
    omega = np.stack([np.sin(3 * t), np.cos(2 * t), 0.5 * t**2], axis=1)
    omega_d = np.stack([3 * np.cos(3 * t), -2 * np.sin(2 * t), t], axis=1)
    yaw, yaw_d, yaw_dd = 0.3 + 0.8 * t**2, 1.6 * t, np.full(n, 1.6)
    return t, omega, omega_d, yaw, yaw_d, yaw_dd


def test_rolling_on_a_plane_is_the_level_formula_on_level_ground_and_stays_on_the_plane():
    """n = ẑ gives the level formula; on a tilted plane the centre's velocity is
    perpendicular to n, and its rate is the finite difference of the velocity."""
    t, omega, omega_d, yaw, yaw_d, yaw_dd = _smooth_motion()
    up = np.tile([0.0, 0.0, 1.0], (len(t), 1))
    v, v_d = rolling_velocity_on_plane(RADIUS_M, omega, omega_d, yaw, yaw_d, yaw_dd, up)
    v_level, v_d_level = rolling_velocity_in_world(RADIUS_M, omega, omega_d, yaw, yaw_d)
    np.testing.assert_allclose(v, v_level, atol=1e-15)
    np.testing.assert_allclose(v_d, v_d_level, atol=1e-14)
    n = np.tile(np.array([0.1, -0.25, 1.0]) / np.linalg.norm([0.1, -0.25, 1.0]), (len(t), 1))
    v, v_d = rolling_velocity_on_plane(RADIUS_M, omega, omega_d, yaw, yaw_d, yaw_dd, n)
    np.testing.assert_allclose(np.sum(v * n, axis=1), 0.0, atol=1e-15)
    fd = np.gradient(v, t, axis=0)
    np.testing.assert_allclose(v_d[2:-2], fd[2:-2], rtol=0, atol=1e-5)
