"""The terrain in animation.html (viz/animation/terrain.py): every box, post, the height map
and each forbidden region is in the scene, where the terrain map puts it."""

from __future__ import annotations

import numpy as np
import pytest
import umsgpack

from planner.path.plan_path import plan_path
from planner.terrain import terrain_from_document
from viz.animation.page import ROOT, build_scene
from viz.animation.terrain import clip_polygon, heightmap_triangles

TERRAIN = {
    "boxes": [{"center": [1.0, 0.5, 0.05], "size": [0.4, 1.0, 0.1], "rpy": [5, 0, 30]}],
    "cylinders": [{"center": [-1.0, 0.3, 0.1], "radius": 0.08, "height": 0.2}],
    "forbidden": [[[-10000.0, 1.5], [10000.0, 1.5], [10000.0, 1.65], [-10000.0, 1.65]]],
    "heightmap": {
        "heights": [[0.0, 0.01, 0.0], [0.02, 0.04, 0.01], [0.0, 0.0, 0.03]],
        "resolution": 0.1,
        "origin": [0.5, -1.0],
    },
}


@pytest.fixture(scope="module")
def scene(silo4):
    """The recorded commands by (type, path) of a short plan's scene on TERRAIN."""
    plan = plan_path(silo4, np.array([[0.0, 0.3]]), 0.4, samples_per_unit=2)
    rec, _ = build_scene(silo4, plan.trajectory, terrain=terrain_from_document(TERRAIN))
    commands = [umsgpack.unpackb(blob) for blob in rec.commands()]
    return {(c["type"], c.get("path")): c for c in commands}


def _vertices(command) -> np.ndarray:
    geometry = command["object"]["geometries"][0]
    blob = geometry["data"]["attributes"]["position"]["array"]
    return np.frombuffer(blob.data, dtype="<f4").reshape(-1, 3).astype(float)


def test_every_terrain_object_is_in_the_scene(scene):
    """One object per box, post, the height map and the forbidden strip."""
    for name in ("box0", "cylinder0", "heightmap", "forbidden0"):
        assert ("set_object", f"{ROOT}/terrain/{name}") in scene, name


def test_a_box_is_drawn_with_its_size_and_pose(scene):
    """The box's geometry has its edge lengths and its transform its rotation and centre."""
    terrain = terrain_from_document(TERRAIN)
    box = terrain.boxes[0]
    obj = scene[("set_object", f"{ROOT}/terrain/box0")]["object"]["geometries"][0]
    assert [obj["width"], obj["height"], obj["depth"]] == pytest.approx(list(box.size))
    matrix = np.array(scene[("set_transform", f"{ROOT}/terrain/box0")]["matrix"]).reshape(4, 4).T
    np.testing.assert_allclose(matrix[:3, :3], box.rotation_box_to_world, atol=1e-12)
    np.testing.assert_allclose(matrix[:3, 3], box.center_in_world, atol=1e-12)


def test_the_heightmap_mesh_lies_on_the_terrain(scene):
    """Every vertex of the drawn mesh, and each triangle's centroid, is on the ground the
    planner uses (float32 vertices: 1e-6 m)."""
    terrain = terrain_from_document(TERRAIN)
    drawn = _vertices(scene[("set_object", f"{ROOT}/terrain/heightmap")])
    assert len(drawn) == 3 * 2 * 2 * 2  # 2 x 2 squares, 2 triangles each
    np.testing.assert_allclose(terrain.height_at(drawn[:, :2]), drawn[:, 2], atol=1e-6)
    centroids = heightmap_triangles(terrain).mean(axis=1)
    np.testing.assert_allclose(terrain.height_at(centroids[:, :2]), centroids[:, 2], atol=1e-12)


def test_the_forbidden_strip_is_shaded_where_the_robot_walks(scene):
    """The 20 km strip is drawn clipped around the path, with its y edges kept."""
    drawn = _vertices(scene[("set_object", f"{ROOT}/terrain/forbidden0")])
    assert drawn[:, 1].min() == pytest.approx(1.5) and drawn[:, 1].max() == pytest.approx(1.65)
    assert np.abs(drawn[:, 0]).max() < 10.0


def test_clip_polygon_keeps_the_part_inside():
    """A square half outside the box is cut at its edge; one wholly outside is empty."""
    square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    cut = clip_polygon(square, np.array([-1.0, -1.0]), np.array([1.0, 1.0]))
    assert sorted(map(tuple, np.round(cut, 12))) == [(0, 0), (0, 1), (1, 0), (1, 1)]
    assert len(clip_polygon(square + 5.0, np.array([-1.0, -1.0]), np.array([1.0, 1.0]))) == 0


def test_plan_and_animate_hand_the_run_terrain_to_the_page(tmp_path, monkeypatch, capsys):
    """silo4 plan --terrain draws the file's terrain; silo4 animate RUN draws the terrain
    plan.json records (the same one)."""
    from pathlib import Path

    import viz.animation.page
    from planner.terrain import load_terrain
    from viz.cli.main import main

    ditch = Path(__file__).resolve().parents[1] / "examples" / "terrain" / "ditch.yaml"
    drawn = []
    real = viz.animation.page.write_animation_html

    def spy(path, robot, trajectory, **options):
        drawn.append(options.get("terrain"))
        return real(path, robot, trajectory, **options)

    monkeypatch.setattr(viz.animation.page, "write_animation_html", spy)
    out = tmp_path / "run"
    argv = ["plan", "--waypoints", "0,0.3", "--height", "0.4", "--samples-per-unit", "4"]
    assert main([*argv, "--no-plots", "--terrain", str(ditch), "--out", str(out)]) == 0
    assert main(["animate", str(out), "--out", str(tmp_path / "again.html")]) == 0
    capsys.readouterr()
    expected = load_terrain(ditch).to_document()
    assert [t.to_document() for t in drawn] == [expected, expected]


def test_no_floor_hides_the_ground_patch(silo4):
    """Over a terrain without a floor the page shows no ground patch nor grid (the void);
    with a floor they stay."""
    plan = plan_path(silo4, np.array([[0.0, 0.3]]), 0.4, samples_per_unit=2)
    hidden = {}
    for floor in (None, 0.0):
        document = {"floor": floor, "boxes": [{"center": [0, 0, -0.25], "size": [2, 2, 0.5]}]}
        rec, _ = build_scene(silo4, plan.trajectory, terrain=terrain_from_document(document))
        hidden[floor] = {
            c["path"]
            for c in map(umsgpack.unpackb, rec.commands())
            if c["type"] == "set_property" and c.get("value") is False
        }
    assert {f"{ROOT}/ground_patch", f"{ROOT}/grid"} <= hidden[None]
    assert f"{ROOT}/ground_patch" not in hidden[0.0]


def _ground_transforms(rec) -> dict[str, np.ndarray]:
    """The last recorded transform (4, 4) of the ground patch and of its grid."""
    found = {}
    for command in map(umsgpack.unpackb, rec.commands()):
        if command["type"] == "set_transform" and command["path"] in (
            f"{ROOT}/ground_patch",
            f"{ROOT}/grid",
        ):
            found[command["path"]] = np.array(command["matrix"]).reshape(4, 4).T
    return found


@pytest.mark.parametrize("floor", [-0.3, 0.0, 0.12])
def test_the_ground_patch_and_grid_sit_at_the_floor(silo4, floor):
    """The ground patch's top face (it is 0.01 m thick) and the grid lines are at the
    terrain's floor height, and the patch stays centred under the walk in x and y."""
    plan = plan_path(silo4, np.array([[0.0, 0.3]]), 0.4, samples_per_unit=2)
    flat, _ = build_scene(silo4, plan.trajectory)
    document = {"floor": floor, "boxes": [{"center": [2, 0, floor + 0.05], "size": [0.2] * 3}]}
    rec, _ = build_scene(silo4, plan.trajectory, terrain=terrain_from_document(document))
    drawn, level = _ground_transforms(rec), _ground_transforms(flat)
    patch = drawn[f"{ROOT}/ground_patch"]
    box = next(
        c["object"]["geometries"][0]
        for c in map(umsgpack.unpackb, rec.commands())
        if c["type"] == "set_object" and c["path"] == f"{ROOT}/ground_patch"
    )
    assert patch[2, 3] + 0.5 * box["depth"] == pytest.approx(floor, abs=2e-4)
    np.testing.assert_allclose(patch[:2, 3], level[f"{ROOT}/ground_patch"][:2, 3], atol=1e-12)
    grid = drawn.get(f"{ROOT}/grid", np.eye(4))
    assert grid[2, 3] == pytest.approx(floor, abs=1e-12)


def test_the_report_shows_the_terrain_from_above(tmp_path, capsys):
    """silo4 plan --terrain writes terrain_top_view.png and report.html shows it; the view's
    grid holds the block's top (0.08 m) over the block's footprint (x -0.6..0.6, y 1.2..1.8)
    and the floor (0) elsewhere, rows along y and columns along x."""
    from pathlib import Path

    from planner.terrain import load_terrain
    from viz.cli.main import main
    from viz.report.terrain_view import ground_grid

    block = Path(__file__).resolve().parents[1] / "examples" / "terrain" / "block.yaml"
    out = tmp_path / "run"
    argv = ["plan", "--waypoints", "0,0.3", "--height", "0.4", "--samples-per-unit", "4"]
    assert main([*argv, "--no-plots", "--terrain", str(block), "--out", str(out)]) == 0
    capsys.readouterr()
    assert (out / "terrain_top_view.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert 'src="terrain_top_view.png"' in (out / "report.html").read_text()
    x, y, z = ground_grid(load_terrain(block), np.array([-1.0, 0.0]), np.array([1.0, 2.5]))
    on_block = (np.abs(x)[None, :] < 0.59) & (np.abs(y - 1.5)[:, None] < 0.29)
    off_block = (np.abs(x)[None, :] > 0.61) | (np.abs(y - 1.5)[:, None] > 0.31)
    assert z.shape == (len(y), len(x))
    np.testing.assert_allclose(z[on_block], 0.08, atol=1e-12)
    np.testing.assert_allclose(z[off_block], 0.0, atol=1e-12)
