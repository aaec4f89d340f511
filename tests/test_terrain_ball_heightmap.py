"""Ball feet on a height map (docs/physics.md, "Round feet"; planner/trajectory/heightmap_rest.py):
a stance ball rolls over the map's triangles, not along the plane under its foothold, and a
ball whose contact point is near a concave crease rests on both triangles.

go2 (22.9 mm balls) plans examples/terrain/rough.yaml at h = 0.28 m; every sampled ball
centre is measured against the map's triangles with a distance written here (each grid
square's two triangles, split from (c, r) to (c+1, r+1), MuJoCo's hfield triangulation; the
nearest point by barycentric coordinates), not the planner's. Before, each stance rolled
along its foothold's plane and entered the map where the next triangle rose: up to 1.5 mm
at 100 samples per unit, and the plan was refused (`the 22.9 mm ball of foot RH is 0.00152
mm inside the terrain` at 10 samples per unit).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from terrain_oracle import HeightGrid

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "terrain"
#: The exact ball check's rounding (planner/trajectory/ball_clearance.py BELOW_TOLERANCE_M).
TOLERANCE_M = 1e-6
#: Fewer samples than the default keep the test short; every sample is checked.
SAMPLES_PER_UNIT = 10
HEIGHT_M = 0.28


class Map(HeightGrid):
    """The terrain file's floor and height map (tests/terrain_oracle.py HeightGrid): heights
    (R, C) [m], rows along y, columns along x, sample (r, c) at origin + resolution (c, r)."""

    def __init__(self, terrain_file: Path) -> None:
        super().__init__(yaml.safe_load(terrain_file.read_text()), terrain_file.parent)

    def corner(self, r, c) -> np.ndarray:
        x, y = (self.origin[:, None] + self.resolution * np.array([c, r])).reshape(2, -1)
        return np.column_stack([x, y, self.floor + self.heights[r, c].ravel()])

    def triangles(self, xy: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """The triangles (a, b, c each (N, 3)) of the 3 x 3 grid squares around each point
        (N, 2): every triangle nearer than a cell to it (the ball is smaller than a cell)."""
        rows, cols = self.heights.shape
        cell = np.floor((xy - self.origin) / self.resolution).astype(int)
        out = []
        for dc in (-1, 0, 1):
            for dr in (-1, 0, 1):
                c = np.clip(cell[:, 0] + dc, 0, cols - 2)
                r = np.clip(cell[:, 1] + dr, 0, rows - 2)
                v00, v10 = self.corner(r, c), self.corner(r, c + 1)
                v01, v11 = self.corner(r + 1, c), self.corner(r + 1, c + 1)
                out += [(v00, v10, v11), (v00, v11, v01)]
        return out

    def on_grid(self, xy: np.ndarray) -> np.ndarray:
        rows, cols = self.heights.shape
        g = (xy - self.origin) / self.resolution
        return (g[:, 0] >= 0) & (g[:, 0] <= cols - 1) & (g[:, 1] >= 0) & (g[:, 1] <= rows - 1)

    def height(self, xy: np.ndarray) -> np.ndarray:
        """The ground's z under points (N, 2): the triangle's plane on the grid, else the
        floor."""
        rows, cols = self.heights.shape
        g = (xy - self.origin) / self.resolution
        c = np.clip(np.floor(g[:, 0]).astype(int), 0, cols - 2)
        r = np.clip(np.floor(g[:, 1]).astype(int), 0, rows - 2)
        u, v = g[:, 0] - c, g[:, 1] - r
        h = self.heights
        lower = h[r, c] + u * (h[r, c + 1] - h[r, c]) + v * (h[r + 1, c + 1] - h[r, c + 1])
        upper = h[r, c] + u * (h[r + 1, c + 1] - h[r + 1, c]) + v * (h[r + 1, c] - h[r, c])
        z = self.floor + np.where(v > u, upper, lower)
        return np.where(self.on_grid(xy), np.maximum(z, self.floor), self.floor)


def _segment(p, a, b) -> np.ndarray:
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


def triangle_distance(p, a, b, c) -> np.ndarray:
    """Distance (N,) of points p from triangles a, b, c (N, 3): to the plane where the
    plane's nearest point has barycentric coordinates all >= 0, else to the nearest edge."""
    e0, e1, w = b - a, c - a, p - a
    d00, d01, d11 = (np.einsum("ij,ij->i", x, y) for x, y in ((e0, e0), (e0, e1), (e1, e1)))
    d20, d21 = np.einsum("ij,ij->i", w, e0), np.einsum("ij,ij->i", w, e1)
    den = d00 * d11 - d01 * d01
    beta, gamma = (d11 * d20 - d01 * d21) / den, (d00 * d21 - d01 * d20) / den
    foot = a + beta[:, None] * e0 + gamma[:, None] * e1
    inside = (beta >= 0) & (gamma >= 0) & (beta + gamma <= 1)
    edges = np.minimum(np.minimum(_segment(p, a, b), _segment(p, b, c)), _segment(p, c, a))
    return np.where(inside, np.linalg.norm(p - foot, axis=1), edges)


def map_distance(ground: Map, points: np.ndarray) -> np.ndarray:
    """Distance (N,) of points (N, 3) from the ground: the floor's plane, and the map's
    triangles near points over the grid."""
    out = points[:, 2] - ground.floor
    on = ground.on_grid(points[:, :2])
    for a, b, c in ground.triangles(points[on, :2]):
        out[on] = np.minimum(out[on], triangle_distance(points[on], a, b, c))
    return out


@pytest.fixture(scope="module")
def go2_on_rough(go2):
    from planner import plan_path
    from planner.terrain.terrain_file import load_terrain
    from silo4kin.foot_contact import foot_ball

    robot = go2
    terrain = load_terrain(EXAMPLES / "rough.yaml")
    plan = plan_path(
        robot,
        np.array([[0.0, 1.5]]),  # onto the map (y 0.5 .. 2.5) and across its first metre
        HEIGHT_M,
        samples_per_unit=SAMPLES_PER_UNIT,
        gait="plain",  # what gait auto falls back to for go2 here (docs/terrain.md)
        terrain=terrain,
    )
    return robot, plan, foot_ball(robot).rolling_radius_m


def _centres(robot, plan) -> np.ndarray:
    from planner.model import planning_model
    from planner.trajectory.ball_clearance import ball_centres_in_world

    legs = planning_model(robot).planning_robot.legs
    return ball_centres_in_world(legs, plan.trajectory)  # the FK of the sampled joints


def test_no_ball_of_go2_enters_the_height_map(go2_on_rough):
    robot, plan, radius = go2_on_rough
    assert radius == pytest.approx(0.0229, abs=1e-4)
    centres = _centres(robot, plan)
    distance = map_distance(Map(EXAMPLES / "rough.yaml"), centres.reshape(-1, 3))
    assert distance.min() >= radius - TOLERANCE_M
    on_map = Map(EXAMPLES / "rough.yaml").on_grid(centres.reshape(-1, 3)[:, :2])
    stance = plan.trajectory.contact.ravel()
    assert (on_map & stance).sum() > 100  # it stood on the map, and every ball touched it:
    np.testing.assert_allclose(distance[on_map & stance], radius, atol=TOLERANCE_M)


def test_go2_stance_contact_points_lie_on_the_map_r_from_the_ball_centres(go2_on_rough):
    robot, plan, radius = go2_on_rough
    trajectory = plan.trajectory
    stance = trajectory.contact
    contact = trajectory.position_foot_in_world[stance]
    ground = Map(EXAMPLES / "rough.yaml")
    assert np.abs(contact[:, 2] - ground.height(contact[:, :2])).max() < TOLERANCE_M
    centres = _centres(robot, plan)[stance]
    np.testing.assert_allclose(np.linalg.norm(centres - contact, axis=1), radius, atol=1e-9)


def _valley(slope: float):
    """A V-shaped map along x: z = slope |x - 0.2| over x 0 .. 0.4 (cells of 0.02 m), the
    concave crease at x = 0.2."""
    from planner.terrain.heightmap import HeightMap
    from planner.terrain.terrain_map import TerrainMap

    x = np.arange(21) * 0.02
    heights = np.tile(slope * np.abs(x - 0.2), (21, 1))
    return TerrainMap(floor_z=-1.0, heightmap=HeightMap(heights, 0.02, np.array([0.0, 0.0])))


def test_a_ball_near_a_concave_crease_is_lifted_out_of_the_rising_triangle():
    """Its contact point 2 mm from the valley's crease, a ball r along the left slope's
    normal enters the right slope; placed, it keeps r from both planes and touches the
    ground (r from the nearer), at a point within 2 r tan(δ/2) of the one asked (δ the
    crease's angle; the distance between the two points where a ball seated in the crease
    touches it); far from the crease it is r along the normal, unchanged."""
    from planner.gaits.ball_stance import foot_frames_on_surface

    slope, r = 0.15, 0.0229
    terrain = _valley(slope)
    contact = np.array([[0.198, 0.2, slope * 0.002], [0.1, 0.2, slope * 0.1]])
    left = np.array([slope, 0.0, 1.0]) / np.hypot(slope, 1.0)
    right = np.array([-slope, 0.0, 1.0]) / np.hypot(slope, 1.0)
    crease = np.array([0.2, 0.2, 0.0])
    frames = foot_frames_on_surface(terrain, contact, r)
    np.testing.assert_allclose(frames[1], contact[1] + r * left, atol=1e-15)
    naive = contact[0] + r * left
    assert np.dot(naive - crease, right) < r - 1e-4  # inside the right slope
    distances = [np.dot(frames[0] - crease, n) for n in (left, right)]
    assert min(distances) == pytest.approx(r, abs=1e-12)
    assert max(distances) >= r
    touching = frames[0] - r * (left if distances[0] < distances[1] else right)
    delta = 2.0 * np.arctan(slope)
    assert np.linalg.norm(touching - contact[0]) <= 2.0 * r * np.tan(delta / 2.0)
