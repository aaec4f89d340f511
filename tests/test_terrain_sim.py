"""The terrain in MuJoCo (silo4sim/terrain.py): a ray cast straight down into the robot's
sim model (mujoco.mj_ray) meets the ground where the planner's TerrainMap.height_at puts it,
for every example terrain, on random points; the sim reads plan.json's document itself, so
this checks one implementation against another."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from planner.terrain import load_terrain

mujoco = pytest.importorskip("mujoco")

from silo4kin.foot_contact import foot_contact_offset_m  # noqa: E402
from silo4sim.model import build_sim_model  # noqa: E402
from silo4sim.settings import SimSettings  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "terrain"
#: Ray casts agree with height_at to this [m] (the hfield stores float32 elevations).
RAY_TOLERANCE_M = 1e-6
#: Random points per terrain, over the examples' extent [m].
N_POINTS = 400
RAY_START_Z_M = 10.0
#: A geom group the robot's geoms are moved to, so the rays see the terrain only.
ROBOT_GROUP = 5


def _ray_heights(sim_model, xy: np.ndarray) -> np.ndarray:
    """Where a ray down from RAY_START_Z_M first meets a terrain geom, in the sim's z [m];
    -inf where it meets none."""
    m = sim_model.model
    m.geom_group[m.geom_bodyid != 0] = ROBOT_GROUP
    data = mujoco.MjData(m)
    mujoco.mj_forward(m, data)
    groups = np.ones(6, dtype=np.uint8)
    groups[ROBOT_GROUP] = 0
    hit = np.zeros(1, dtype=np.int32)
    out = []
    for x, y in xy:
        distance = mujoco.mj_ray(
            m, data, np.array([x, y, RAY_START_Z_M]), np.array([0.0, 0.0, -1.0]), groups, 1, -1, hit
        )
        out.append(RAY_START_Z_M - distance if distance >= 0 else -np.inf)
    return np.array(out)


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.yaml")), ids=lambda p: p.name)
def test_ray_casts_meet_the_planner_ground(silo4, path):
    """mj_ray's first hit - the floor shift (foot offset - foot radius) == height_at, to
    RAY_TOLERANCE_M, and the sim has ground exactly where the planner has (no floor: the
    rays between the solids fall through)."""
    terrain = load_terrain(path)
    settings = SimSettings()
    shift = foot_contact_offset_m(silo4) - settings.foot_radius_m
    sim_model = build_sim_model(silo4, settings, terrain.to_document())
    xy = np.random.default_rng(11).uniform([-1.2, -1.2], [1.2, 4.5], size=(N_POINTS, 2))
    expected = terrain.height_at(xy)
    got = _ray_heights(sim_model, xy) - shift
    solid = np.isfinite(expected)
    assert np.array_equal(np.isfinite(got), solid)
    np.testing.assert_allclose(got[solid], expected[solid], rtol=0, atol=RAY_TOLERANCE_M)
    if terrain.floor_z is None:
        assert not solid.all()  # some rays fall through the void


def test_without_a_terrain_the_model_has_the_flat_floor(silo4):
    """No terrain document: one plane, the floor, at the shift (the model as before)."""
    sim_model = build_sim_model(silo4)
    m = sim_model.model
    world = [m.geom(i).name for i in range(m.ngeom) if m.geom_bodyid[i] == 0]
    assert world == ["floor"]


def test_a_turned_tilted_box_and_a_void_meet_the_planner_ground(silo4):
    """A box turned and tilted about all three axes (rpy = (5, -8, 30) deg), a post, over
    no floor: the sim's rotation of rpy is the planner's."""
    from planner.terrain import terrain_from_document

    terrain = terrain_from_document(
        {
            "floor": None,
            "boxes": [{"center": [0.0, 0.0, 0.1], "size": [1.0, 0.6, 0.2], "rpy": [5, -8, 30]}],
            "cylinders": [{"center": [0.9, 0.2, 0.0], "radius": 0.1, "height": 0.3}],
        }
    )
    settings = SimSettings()
    shift = foot_contact_offset_m(silo4) - settings.foot_radius_m
    sim_model = build_sim_model(silo4, settings, terrain.to_document())
    xy = np.random.default_rng(5).uniform([-0.8, -0.8], [1.1, 0.8], size=(N_POINTS, 2))
    expected = terrain.height_at(xy)
    got = _ray_heights(sim_model, xy) - shift
    solid = np.isfinite(expected)
    assert 0.2 < solid.mean() < 0.9
    assert np.array_equal(np.isfinite(got), solid)
    np.testing.assert_allclose(got[solid], expected[solid], rtol=0, atol=RAY_TOLERANCE_M)


def test_silo4_simulate_builds_the_terrain_plan_json_records(tmp_path, capsys):
    """silo4 simulate RUN reads inputs.terrain from RUN/plan.json: a box added to it is in
    model.xml at its place (raised by the floor shift), and the short walk beside it walks."""
    import json

    from viz.cli.main import main

    out = tmp_path / "run"
    plan = ["plan", "--waypoints", "0,0.3", "--height", "0.4", "--samples-per-unit", "20"]
    terrain_file = str(EXAMPLES / "ditch.yaml")
    flags = ["--no-html", "--no-plots", "--terrain", terrain_file, "--out", str(out)]
    assert main([*plan, *flags]) == 0, capsys.readouterr().err
    document = json.loads((out / "plan.json").read_text())
    box = {"center": [5.0, 0.0, 0.1], "size": [0.5, 0.5, 0.2], "rpy": [0.0, 0.0, 0.0]}
    document["inputs"]["terrain"]["boxes"] = [box]
    (out / "plan.json").write_text(json.dumps(document))
    assert main(["simulate", str(out), "--no-html", "--no-plots"]) == 0, capsys.readouterr()
    spec = mujoco.MjSpec.from_file(str(out / "model.xml"))
    placed = spec.geom("box0")
    assert placed is not None
    np.testing.assert_allclose(placed.size, [0.25, 0.25, 0.1])
    assert placed.pos[:2].tolist() == [5.0, 0.0]
