"""TerrainMap.sphere_clearance (planner/terrain/terrain_map.py) against an independent
computation: the distance from the sphere's centre to the nearest of many random points that
lie under the terrain's ``height_at`` (inside the ground a ray from above sees), less the
radius; and a sphere beside a riser that the height-under-the-centre measure passes."""

from __future__ import annotations

import numpy as np
import pytest

from planner.terrain.shapes import Box, Cylinder
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.clearance import sphere_clearance

BLOCK = Box(np.array([0.0, 0.5, 0.035]), np.array([1.0, 0.4, 0.07]))


def _brute_force_clearance(terrain: TerrainMap, center: np.ndarray, radius: float) -> float:
    """Least distance from ``center`` to a sampled point below ``height_at``, less radius."""
    rng = np.random.default_rng(0)
    half = 0.12
    pts = center + rng.uniform(-half, half, size=(400_000, 3))
    inside = pts[:, 2] < terrain.height_at(pts[:, :2])
    assert inside.any()
    return float(np.min(np.linalg.norm(pts[inside] - center, axis=1))) - radius


@pytest.mark.parametrize(
    ("terrain", "center"),
    [
        (TerrainMap(boxes=(BLOCK,)), np.array([0.1, 0.27, 0.05])),  # beside the riser
        (TerrainMap(boxes=(BLOCK,)), np.array([0.1, 0.26, 0.09])),  # off the top edge
        (TerrainMap(boxes=(BLOCK,)), np.array([0.1, 0.5, 0.12])),  # over the top
        (
            TerrainMap(
                boxes=(
                    Box(
                        np.array([0.0, 0.5, 0.05]),
                        np.array([0.3, 0.3, 0.1]),
                        np.array([0.0, 0.0, 30.0]),
                    ),
                )
            ),
            np.array([0.2, 0.5, 0.06]),  # beside a yawed box
        ),
        (
            TerrainMap(cylinders=(Cylinder(np.array([0.0, 0.5, 0.05]), 0.1, 0.1),)),
            np.array([0.05, 0.37, 0.04]),  # beside a post
        ),
    ],
)
def test_sphere_clearance_matches_sampled_distance(terrain, center):
    radius = 0.02
    got = float(terrain.sphere_clearance(center[None], radius)[0])
    expected = _brute_force_clearance(terrain, center, radius)
    assert got == pytest.approx(expected, abs=4e-3)


def test_sphere_beside_a_riser_is_seen_where_the_height_under_it_is_not():
    """A calf-sized sphere (r 0.02 m) 0.01 m in front of the block's riser, 0.04 m up: the
    floor is 0.02 m under its lowest point, the riser 0.01 m inside it."""
    terrain = TerrainMap(boxes=(BLOCK,))
    center = np.array([[0.0, 0.3 - 0.01, 0.04]])
    old = terrain.lowest_clearance(center)[0] - 0.02
    assert old == pytest.approx(0.02)
    assert terrain.sphere_clearance(center, 0.02)[0] == pytest.approx(-0.01)


def test_flat_floor_is_the_height_above_it():
    terrain = TerrainMap(floor_z=0.1)
    pts = np.array([[0.3, -2.0, 0.25], [5.0, 1.0, 0.05]])
    np.testing.assert_allclose(terrain.sphere_clearance(pts, 0.01), pts[:, 2] - 0.1 - 0.01)


def test_terrain_without_sphere_measure_falls_back_to_height_under():
    class Step:
        def height_at(self, xy):
            return np.where(np.asarray(xy)[:, 1] > 0.0, 0.1, 0.0)

    centers = np.array([[[0.0, -0.01, 0.05], [0.0, 0.01, 0.15]]])
    np.testing.assert_allclose(sphere_clearance(Step(), centers, 0.02), [[0.03, 0.03]])
