"""Walking a height map (docs/terrain.md, "Height maps"): SILO4 at h = 0.4 m plans
examples/terrain/rough.yaml with ``silo4 plan --terrain`` and walks it in ``silo4 simulate``;
the run is checked from trajectory.csv and the map file alone, with the map's ground written
here (MuJoCo's hfield triangulation, each triangle's plane solved from its three samples),
not the planner's:

- every stance foot is on the ground within 1 mm, on a triangle tilted at most 20 deg, and no
  grid sample within the edge margin (foot radius 0.025 m + 0.02 m) leaves the plane of that
  triangle by more than the height map's step, 0.01 m;
- no sampled foot is below the ground.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from terrain_oracle import HeightGrid

from viz.cli.main import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "terrain"
LEGS = ("LF", "RF", "LH", "RH")
#: docs/terrain.md: SILO4's foot radius + 2 cm, the height map's step, the steepest tilt.
EDGE_MARGIN_M = 0.045
STEP_M = 0.01
MAX_TILT_DEG = 20.0
ON_SURFACE_M = 1e-3
#: Fewer samples than the default keep the test short; every sample is checked.
SAMPLES_PER_UNIT = 20


class Grid(HeightGrid):
    """The height map of a terrain file: heights (R, C) [m], rows along y, columns along x,
    sample (r, c) at origin + resolution (c, r); squares split from (r, c) to (r+1, c+1)."""

    def __init__(self, terrain_file: Path) -> None:
        super().__init__(yaml.safe_load(terrain_file.read_text()), terrain_file.parent)

    def sample(self, r: int, c: int) -> np.ndarray:
        """The grid sample (r, c) as a point (3,) [m]."""
        x, y = self.origin + self.resolution * np.array([c, r])
        return np.array([x, y, self.floor + self.heights[r, c]])

    def triangle(self, xy) -> tuple[np.ndarray, np.ndarray] | None:
        """(point on the plane (3,), unit normal (3,)) of the triangle under xy, or None
        off the grid."""
        g = (np.asarray(xy, float) - self.origin) / self.resolution
        rows, cols = self.heights.shape
        if not (0 <= g[0] <= cols - 1 and 0 <= g[1] <= rows - 1):
            return None
        c, r = min(int(g[0]), cols - 2), min(int(g[1]), rows - 2)
        u, v = g[0] - c, g[1] - r
        corners = [(r, c), (r + 1, c + 1), (r + 1, c) if v > u else (r, c + 1)]
        a, b, d = (self.sample(*k) for k in corners)
        normal = np.cross(b - a, d - a)
        normal *= np.sign(normal[2]) / np.linalg.norm(normal)
        return a, normal

    def height(self, xy) -> float:
        """Ground z [m] under xy: the triangle's plane, the floor off the grid."""
        tri = self.triangle(xy)
        if tri is None:
            return self.floor
        a, n = tri
        return float(a[2] - (n[0] * (xy[0] - a[0]) + n[1] * (xy[1] - a[1])) / n[2])

    def samples_within(self, xy, radius_m: float) -> np.ndarray:
        """Grid samples (K, 3) [m] within radius_m of xy."""
        rows, cols = self.heights.shape
        pts = np.array([self.sample(r, c) for r in range(rows) for c in range(cols)])
        return pts[np.hypot(*(pts[:, :2] - np.asarray(xy)).T) <= radius_m]


def _read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    feet = np.array([[[float(r[f"foot_{leg}_{a}"]) for a in "xyz"] for leg in LEGS] for r in rows])
    contact = np.array(
        [[r[f"contact_{leg}"] in ("1", "True", "true") for leg in LEGS] for r in rows]
    )
    return feet, contact


@pytest.fixture(scope="module")
def rough_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("rough") / "run"
    code = main(
        [
            "plan",
            "--waypoints",
            "0,3.0",
            "--height",
            "0.4",
            "--samples-per-unit",
            str(SAMPLES_PER_UNIT),
            "--no-plots",
            "--no-html",
            "--terrain",
            str(EXAMPLES / "rough.yaml"),
            "--out",
            str(out),
        ]
    )
    assert code == 0
    return out


def test_every_stance_foot_stands_on_the_map_away_from_its_steps(rough_run):
    grid = Grid(EXAMPLES / "rough.yaml")
    feet, contact = _read_csv(rough_run / "trajectory.csv")
    footholds = np.unique(np.round(feet[contact], 6), axis=0)
    on_map = 0
    for foot in footholds:
        assert abs(foot[2] - grid.height(foot[:2])) <= ON_SURFACE_M, foot
        tri = grid.triangle(foot[:2])
        if tri is None:
            continue
        a, n = tri
        assert np.degrees(np.arccos(n[2])) <= MAX_TILT_DEG + 1e-9, foot
        near = grid.samples_within(foot[:2], EDGE_MARGIN_M)
        off_plane = (near - foot) @ n / n[2]  # vertical distance from the foot's plane
        assert np.all(np.abs(off_plane) <= STEP_M + 1e-9), (foot, off_plane)
        on_map += foot[2] > ON_SURFACE_M
    assert on_map >= 10  # the walk crosses the map: most of its footholds stand on it


def test_no_sampled_foot_is_below_the_map(rough_run):
    grid = Grid(EXAMPLES / "rough.yaml")
    feet, _ = _read_csv(rough_run / "trajectory.csv")
    points = feet.reshape(-1, 3)[::3]  # every third sample of every foot
    below = [p[2] - grid.height(p[:2]) for p in points]
    assert min(below) >= -1e-6


def test_the_run_records_the_map_inline(rough_run):
    recorded = json.loads((rough_run / "plan.json").read_text())["inputs"]["terrain"]
    grid = Grid(EXAMPLES / "rough.yaml")
    np.testing.assert_array_equal(np.array(recorded["heightmap"]["heights"]), grid.heights)


def test_silo4_simulate_walks_the_rough_map(rough_run):
    pytest.importorskip("mujoco")
    code = main(["simulate", str(rough_run), "--no-html", "--no-plots"])
    verdict = json.loads((rough_run / "sim.json").read_text())
    assert code == 0 and verdict["walks"], verdict["reasons"]
    assert not verdict["non_foot_contacts"]


def _spike_map(spike_m: float):
    from planner.terrain.heightmap import HeightMap
    from planner.terrain.terrain_map import TerrainMap

    heights = np.zeros((21, 21))
    heights[10, 10] = spike_m  # at (0.5, 0.5) m
    return TerrainMap(heightmap=HeightMap(heights, 0.05, np.zeros(2)))


@pytest.mark.parametrize(
    ("spike_m", "distance_m", "valid"),
    [
        (0.005, 0.0, True),  # a 5 mm bump under the foot: within the step
        (0.02, 0.03, False),  # a 2 cm one within the edge margin: an edge
        (0.02, 0.2, True),  # 0.2 m away: beyond the wall margin
        (0.0, 0.03, True),
    ],
)
def test_a_step_within_the_edge_margin_is_an_edge(spike_m, distance_m, valid):
    """A foothold on a height map keeps the step rule: no grid sample within the edge margin
    rises or drops more than HEIGHTMAP_STEP_M from its plane."""
    from planner.gaits.surface_footholds import HEIGHTMAP_STEP_M, SurfaceFootholds

    assert HEIGHTMAP_STEP_M == STEP_M
    search = SurfaceFootholds(_spike_map(spike_m), (), 0.4)
    ok, _ = search.valid(np.array([[0.5 + distance_m, 0.5]]))
    assert bool(ok[0]) is valid


def test_the_grid_samples_within_the_margin_are_asked_between_the_rings():
    """A spike one sample wide on a 5 mm grid, 0.04 m from the foothold between two rays of
    the edge rings, is met by the grid-sample stage."""
    from planner.gaits.surface_footholds import EDGE_DIRECTIONS, SurfaceFootholds
    from planner.terrain.heightmap import HeightMap
    from planner.terrain.terrain_map import TerrainMap

    heights = np.zeros((41, 41))
    angle = np.pi / EDGE_DIRECTIONS  # half way between two rays
    centre = np.array([0.1, 0.1])
    spike = centre + 0.04 * np.array([np.cos(angle), np.sin(angle)])
    r, c = np.round(spike / 0.005).astype(int)[::-1]
    heights[r, c] = 0.05
    terrain = TerrainMap(heightmap=HeightMap(heights, 0.005, np.zeros(2)))
    search = SurfaceFootholds(terrain, (), 0.4)
    rings = search._stages
    ring_points = np.vstack([ring for ring, is_wall in rings if not is_wall]) + centre
    sample_xy = np.array([c, r]) * 0.005
    assert np.min(np.hypot(*(ring_points - sample_xy).T)) > 0.005  # the rings miss it
    assert not search.valid(centre[None])[0][0]
    heights[r, c] = 0.0
    flat = SurfaceFootholds(TerrainMap(heightmap=HeightMap(heights, 0.005, np.zeros(2))), (), 0.4)
    assert flat.valid(centre[None])[0][0]


def test_a_swing_apex_rises_over_a_ridge_between_its_footholds():
    """Over a 0.1 m ridge half way between lift-off and touch-down the apex rises so that
    the foot keeps 0.02 m times the lift profile above the ground at every phase."""
    from planner.gaits.steps import Phase, Step, StepKind
    from planner.terrain.heightmap import HeightMap
    from planner.terrain.terrain_map import TerrainMap
    from planner.trajectory.profiles import cosine_blend, lift
    from planner.trajectory.terrain_clearance import CLEARANCE_M, step_swing_heights

    heights = np.zeros((5, 21))
    heights[:, 10] = 0.1  # a ridge along y at x = 0.5 m
    terrain = TerrainMap(heightmap=HeightMap(heights, 0.05, np.array([0.0, -0.1])))
    f0, f1 = np.array([0.3, 0.0, 0.0]), np.array([0.7, 0.0, 0.0])
    base = np.array([0.5, 0.0, 0.4])
    step = Step(
        StepKind.TRANSFER,
        "LF",
        0.0,
        1.0,
        base,
        base,
        0.0,
        0.0,
        foothold_start_in_world=f0,
        foothold_end_in_world=f1,
        phase=Phase.CREEP,
    )
    (apex,) = step_swing_heights(terrain, (step,), 0.05, smooth=False)
    assert apex > 0.1 + CLEARANCE_M - 1e-9
    tau = np.linspace(0.0, 1.0, 2001)
    s, w = cosine_blend(tau, 1.0).s, lift(tau, 1.0, 1.0).s
    x = f0[0] + (f1[0] - f0[0]) * s
    z = apex * w
    ground = terrain.height_at(np.column_stack([x, np.zeros_like(x)]))
    keep = w >= 0.05
    assert np.all(z[keep] - ground[keep] >= CLEARANCE_M * w[keep] - 1e-4)
    (flat,) = step_swing_heights(_spike_map(0.0), (step,), 0.05, smooth=False)
    assert flat == 0.05
