"""Walking a terrain file's surfaces (docs/terrain.md): SILO4 at h = 0.4 m plans block, stairs,
gap, ramp and stones with ``silo4 plan --terrain``, and the run folder is checked from
trajectory.csv and the terrain file alone, with geometry written here, not the planner's:

- every stance foot is on a top face (a box's top rectangle, a post's top disc, the floor)
  within 1 mm and at least the edge margin (foot radius 0.025 m + 0.02 m) from that face's
  edges, and on the floor that far from every box and post standing on it;
- no sampled foot is below the ground under it (the highest top face over it).
"""

from __future__ import annotations

import base64
import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest
import umsgpack
import yaml
from terrain_oracle import Face

from viz.cli.main import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "terrain"
LEGS = ("LF", "RF", "LH", "RH")
#: SILO4's foot radius + 2 cm [m] (docs/terrain.md).
EDGE_MARGIN_M = 0.045
ON_SURFACE_M = 1e-3
#: Fewer samples than the default keep the test short; every sample is checked.
SAMPLES_PER_UNIT = 20
#: Walks along +y that end on a surface of each example.
WALKS = {
    "block": "0,2.6",
    "stairs": "0,3.8",
    "gap": "0,3.0",
    "ramp": "0,3.3",
    "stones": "0,3.3",
}


def _faces(document):
    return [Face(box=b) for b in document.get("boxes") or []] + [
        Face(cylinder=c) for c in document.get("cylinders") or []
    ]


def _ground(document, faces, xy):
    floor = document.get("floor", 0.0)
    z = np.full(len(xy), -np.inf if floor is None else float(floor))
    for face in faces:
        z = np.maximum(z, face.height(xy))
    return z


def _read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    feet = np.array([[[float(r[f"foot_{leg}_{a}"]) for a in "xyz"] for leg in LEGS] for r in rows])
    contact = np.array(
        [[r[f"contact_{leg}"] in ("1", "True", "true") for leg in LEGS] for r in rows]
    )
    return feet, contact


@pytest.fixture(scope="module", params=sorted(WALKS))
def walked(request, tmp_path_factory):
    name = request.param
    out = tmp_path_factory.mktemp(name) / "run"
    code = main(
        [
            "plan",
            "--waypoints",
            WALKS[name],
            "--height",
            "0.4",
            "--samples-per-unit",
            str(SAMPLES_PER_UNIT),
            "--no-plots",
            "--terrain",
            str(EXAMPLES / f"{name}.yaml"),
            "--out",
            str(out),
        ]
    )
    assert code == 0
    document = yaml.safe_load((EXAMPLES / f"{name}.yaml").read_text()) or {}
    return name, out, document


def test_every_stance_foot_is_on_a_surface_keeping_the_edge_margin(walked):
    name, out, document = walked
    feet, contact = _read_csv(out / "trajectory.csv")
    faces = _faces(document)
    stance = feet[contact]  # (M, 3)
    xy, z = stance[:, :2], stance[:, 2]
    heights = np.array([face.height(xy) for face in faces]).reshape(len(faces), len(xy))
    ground = _ground(document, faces, xy)
    assert np.all(np.abs(z - ground) <= ON_SURFACE_M), name
    on_face = np.abs(heights - z) <= ON_SURFACE_M  # (F, M)
    for i in range(len(xy)):
        standing = np.flatnonzero(on_face[:, i])
        if standing.size:  # on a box or post top: its edges are that far
            face = faces[standing[0]]
            assert face.footprint_distance(xy[i : i + 1])[0] >= EDGE_MARGIN_M - 1e-6, (name, xy[i])
        else:  # on the floor: every solid standing on it is that far
            assert document.get("floor", 0.0) is not None
            for face in faces:
                assert face.footprint_distance(xy[i : i + 1])[0] <= -EDGE_MARGIN_M + 1e-6, (
                    name,
                    xy[i],
                )


def test_no_sampled_foot_is_below_the_ground(walked):
    name, out, document = walked
    feet, _ = _read_csv(out / "trajectory.csv")
    xy = feet.reshape(-1, 3)
    ground = _ground(document, _faces(document), xy[:, :2])
    assert np.all(xy[:, 2] >= ground - 1e-6), name


def _drawn_paths(html: str) -> set[str]:
    """The scene paths of every object animation.html sets (its base64 msgpack commands)."""
    paths = set()
    for blob in re.findall(r'"([A-Za-z0-9+/]{64,}={0,2})"', html):
        try:
            command = umsgpack.unpackb(base64.b64decode(blob))
        except Exception:  # noqa: BLE001 - not a command blob
            continue
        if isinstance(command, dict) and command.get("type") == "set_object":
            paths.add(str(command.get("path")))
    return paths


def test_the_run_records_and_draws_the_terrain(walked):
    """plan.json records the file's boxes and posts; animation.html draws one object each."""
    name, out, document = walked
    recorded = json.loads((out / "plan.json").read_text())["inputs"]["terrain"]
    boxes, posts = document.get("boxes") or [], document.get("cylinders") or []
    assert len(recorded["boxes"]) == len(boxes) and len(recorded["cylinders"]) == len(posts)
    drawn = {p.rsplit("/", 1)[-1] for p in _drawn_paths((out / "animation.html").read_text())}
    wanted = {f"box{i}" for i in range(len(boxes))} | {f"cylinder{i}" for i in range(len(posts))}
    assert wanted <= drawn, (name, wanted - drawn)


@pytest.mark.parametrize("walked", ["block"], indirect=True)
def test_every_swing_passes_the_block_edges_above_its_top(walked):
    """Every swing that crosses one of the block's edges (y = 1.2 m, 1.8 m) passes it above
    the block's top (0.08 m), the foot's height at the crossing interpolated between the two
    samples around it: the apexes are raised over the block."""
    _, out, _ = walked
    feet, contact = _read_csv(out / "trajectory.csv")
    crossings = []
    for k in range(4):
        y, z, up = feet[:, k, 1], feet[:, k, 2], ~contact[:, k]
        for edge in (1.2, 1.8):
            i = np.flatnonzero(up[:-1] & up[1:] & ((y[:-1] - edge) * (y[1:] - edge) <= 0))
            f = (edge - y[i]) / (y[i + 1] - y[i])
            crossings += list(z[i] + f * (z[i + 1] - z[i]))
    assert len(crossings) >= 8  # each foot onto the block and off it
    assert min(crossings) > 0.08


def test_a_foothold_near_an_edge_moves_to_the_nearest_valid_point(silo4):
    """A nominal foothold on the block 1 cm inside its near edge moves onto the block, the edge
    margin from the edge (the floor in front of the riser is 0.1 m away: farther)."""
    from planner.gaits.surface_footholds import SurfaceFootholds
    from planner.model import as_planning_model
    from planner.terrain import load_terrain

    terrain = load_terrain(EXAMPLES / "block.yaml")
    search = SurfaceFootholds(terrain, tuple(as_planning_model(silo4).planning_robot.legs), 0.4)
    base = np.array([0.0, 0.9, 0.4])
    moved = search.place(0, np.array([-0.312, 1.21, 0.0]), base, np.pi / 2)
    assert moved[2] == pytest.approx(0.08, abs=1e-12)
    assert EDGE_MARGIN_M <= moved[1] - 1.2 <= EDGE_MARGIN_M + 0.01
    assert moved[0] == pytest.approx(-0.312)
    kept = search.place(0, np.array([-0.312, 1.4, 0.0]), base, np.pi / 2)  # valid already
    np.testing.assert_allclose(kept, [-0.312, 1.4, 0.08], atol=1e-12)


def test_a_block_beyond_the_legs_is_refused_naming_the_terrain(silo4, tmp_path):
    """A 0.4 m block at h = 0.4 m: the front foot reaches its top 0.107 m past the edge, but
    its shank lies on that edge (the capsule into the block at touch-down) and no point
    within the search's radius clears it; the refusal names the file, the block and the
    capsule, in one line. (Before the foothold search knew the shank the step was taken and
    the body over the stance feet then left a hind foot on the floor out of reach:
    tests/test_terrain_neighbours.py keeps that refusal, on a 0.2 m block.)"""
    from planner.errors import FootholdRefused
    from planner.path.plan_path import plan_path
    from planner.terrain import load_terrain

    high = tmp_path / "high.yaml"
    high.write_text("boxes:\n  - {center: [0.0, 1.5, 0.2], size: [1.2, 0.6, 0.4]}\n")
    terrain = load_terrain(high)
    with pytest.raises(FootholdRefused) as info:
        plan_path(silo4, np.array([[0.0, 2.6]]), 0.4, samples_per_unit=2, terrain=terrain)
    message = str(info.value)
    assert f"terrain file {high}" in message and "\n" not in message
    assert "leg RF's nominal foothold is over box 0" in message
    # the nearest point otherwise valid, within the search radius (0.2 m: -1.3 mm; 0.12 m:
    # -5.3 mm), brings its capsule into the block
    assert re.search(r"brings its tibia capsule -\d+\.\d mm from box 0 at touch-down", message)


@pytest.mark.parametrize("walked", ["block"], indirect=True)
def test_silo4_simulate_walks_the_block(walked):
    """`silo4 simulate` builds the block from plan.json and the plan walks on it (the default
    limits: no fall, drift <= 20 mm, slip <= 5 mm, no non-foot contact)."""
    pytest.importorskip("mujoco")
    _, out, _ = walked
    code = main(["simulate", str(out), "--no-html", "--no-plots"])
    verdict = json.loads((out / "sim.json").read_text())
    assert code == 0 and verdict["walks"], verdict["reasons"]
    assert not verdict["non_foot_contacts"]
