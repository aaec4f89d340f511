"""Terrain files in the planner and ``silo4 plan --terrain``: the thesis's ditch as a file
is crossed head-on by the foothold search on surfaces, a terrain without footholds is
refused by name, plan.json records the file's content and the HTML draws it."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from planner.path.plan_path import plan_path
from planner.studies.cases import START_HEADING_RAD
from planner.studies.ditch import FOOT_CLEARANCE_M, Ditch, plan_ditch_crossing
from planner.terrain import load_terrain
from planner.terrain.terrain_map import FORBIDDEN_CLEARANCE_M
from silo4kin.errors import Silo4Error
from viz.cli.main import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "terrain"
DITCH_FILE = EXAMPLES / "ditch.yaml"
#: Few samples per time unit: the footholds (what the terrain decides) do not depend on it.
FEW_SAMPLES = 4
#: Fig 6.30's body height [m].
DITCH_HEIGHT_M = 0.3


def _trajectory_arrays(plan) -> dict[str, np.ndarray]:
    t = plan.trajectory
    return {
        name: np.asarray(getattr(t, name))
        for name in ("q", "position_base_in_world", "position_foot_in_world", "contact")
    }


def _plan_or_refusal(robot, route, terrain):
    try:
        return plan_path(
            robot,
            route,
            DITCH_HEIGHT_M,
            start_heading=START_HEADING_RAD,
            workspace="default",
            samples_per_unit=FEW_SAMPLES,
            terrain=terrain,
        )
    except Silo4Error as exc:
        return f"{type(exc).__name__}: {exc}"


def test_the_ditch_file_is_the_ditch_study_terrain():
    """ditch.yaml is Ditch(1.5, 0.15).terrain(FOOT_CLEARANCE_M): the same strip, and the
    default clearance of a terrain file's forbidden polygons is the study's."""
    terrain = load_terrain(DITCH_FILE)
    study = Ditch(1.5, 0.15).terrain(FOOT_CLEARANCE_M)
    assert FORBIDDEN_CLEARANCE_M == FOOT_CLEARANCE_M == terrain.forbidden_clearance_m
    np.testing.assert_array_equal(terrain.forbidden_xy_in_world[0], study.polygons_xy_in_world[0])


def _stance_contact_y(plan) -> np.ndarray:
    """y [m] of every stance foot sample (SILO4's feet are points: frame = contact point)."""
    t = plan.trajectory
    return np.asarray(t.position_foot_in_world)[np.asarray(t.contact, bool)][:, 1]


@pytest.mark.parametrize("height_m", [DITCH_HEIGHT_M, 0.4])
def test_the_ditch_file_is_crossed_head_on_by_the_foothold_search(silo4, height_m):
    """ditch.yaml's strip is walked across straight, the footholds searched around it as on
    any terrain file's surfaces (planner/gaits/surface_footholds.py; the ditch study's
    terrain, ForbiddenPolygons, refuses a foothold instead of moving it: at 0.4 m it refused
    this route). Every stance foot stays the clearance out of the strip (y in [1.5, 1.65]
    m), measured on the trajectory's feet."""
    route = np.array([[0.0, 0.9], [0.0, 2.72]])
    plan = _plan_or_refusal(silo4, route, load_terrain(DITCH_FILE))
    assert not isinstance(plan, str), plan
    y = _stance_contact_y(plan)
    assert (y > 1.65).any() and (y < 1.5).any()  # it crossed
    outside = np.minimum(np.abs(y - 1.5), np.abs(y - 1.65))
    in_strip = (y > 1.5) & (y < 1.65)
    assert not in_strip.any()
    assert outside.min() >= FORBIDDEN_CLEARANCE_M - 1e-9


def test_the_ditch_file_plans_the_ditch_study_route(silo4):
    """The route the ditch study finds also plans on ditch.yaml, its feet out of the strip."""
    outcome = plan_ditch_crossing(
        silo4, Ditch(1.5, 0.15), DITCH_HEIGHT_M, workspace="default", samples_per_unit=FEW_SAMPLES
    )
    plan = _plan_or_refusal(silo4, outcome.route_in_world, load_terrain(DITCH_FILE))
    assert not isinstance(plan, str), plan
    y = _stance_contact_y(plan)
    assert not (
        (y > 1.5 - FORBIDDEN_CLEARANCE_M + 1e-9) & (y < 1.65 + FORBIDDEN_CLEARANCE_M - 1e-9)
    ).any()


def test_silo4_plan_terrain_records_the_file_and_draws_it(tmp_path, capsys):
    """silo4 plan --terrain ditch.yaml: plan.json's inputs.terrain is the file's content
    (load_terrain(...).to_document()); a height map with no foothold on it (a checkerboard
    of 0.05 m steps) exits 2 with one line naming it, and writes nothing."""
    out = tmp_path / "run"
    code = main(
        [
            "plan",
            "--waypoints",
            "0,0.9 0,2.72",
            "--height",
            "0.3",
            "--samples-per-unit",
            str(FEW_SAMPLES),
            "--no-plots",
            "--terrain",
            str(DITCH_FILE),
            "--out",
            str(out),
        ]
    )
    captured = capsys.readouterr()
    assert code == 0, captured.err
    recorded = json.loads((out / "plan.json").read_text())["inputs"]["terrain"]
    assert recorded == load_terrain(DITCH_FILE).to_document()
    assert (out / "animation.html").is_file()  # its terrain: tests/test_terrain_scene.py
    checkers = 0.05 * (np.indices((41, 31)).sum(axis=0) % 2)
    np.save(tmp_path / "checkers.npy", checkers)
    terrain_file = tmp_path / "checkers.yaml"
    terrain_file.write_text(
        "heightmap: {file: checkers.npy, resolution: 0.05, origin: [-0.75, 0.5]}\n"
    )
    code = main(
        [
            "plan",
            "--waypoints",
            "0,1",
            "--height",
            "0.4",
            "--no-plots",
            "--no-html",
            "--terrain",
            str(terrain_file),
            "--out",
            str(tmp_path / "checkers"),
        ]
    )
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "checkers.yaml" in err and "over height map" in err
    assert not (tmp_path / "checkers").exists()


def test_a_malformed_terrain_file_exits_2_before_planning(tmp_path, capsys):
    """A bad field: exit 2, one line naming it, no folder."""
    bad = tmp_path / "bad.yaml"
    bad.write_text("boxes: [{center: [0, 0], size: [1, 1, 1]}]\n")
    code = main(
        [
            "plan",
            "--waypoints",
            "0,1",
            "--height",
            "0.4",
            "--terrain",
            str(bad),
            "--out",
            str(tmp_path / "run"),
        ]
    )
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "boxes[0].center" in err, err
    assert not (tmp_path / "run").exists()


def test_the_terrain_option_is_recorded_as_the_file_content():
    """--terrain changes exactly the "terrain" key of the recorded options (the folder check
    tells a run on another terrain apart), from the TerrainMap the run read."""
    from planner.outputs.export import OPTION_DEFAULTS
    from viz.cli.main import build_parser
    from viz.report.run_outputs import run_options

    args = build_parser().parse_args(
        [
            "plan",
            "--waypoints",
            "0,1",
            "--height",
            "0.4",
            "--out",
            "x",
            "--terrain",
            str(DITCH_FILE),
        ]
    )
    assert run_options(args) == OPTION_DEFAULTS  # not read yet: silo4 plan reads it once
    args.terrain_map = load_terrain(args.terrain)  # what viz/cli/plan.py does first
    assert run_options(args) == {
        **OPTION_DEFAULTS,
        "terrain": load_terrain(DITCH_FILE).to_document(),
    }


def _ramp_file(folder: Path, angle_deg: float) -> Path:
    """A 0.4 m plank rolled angle_deg about x, its lower edge on the floor at y = 1 m, then a
    platform at its upper edge's height (box 0: the plank, box 1: the platform)."""
    a = np.radians(angle_deg)
    length, thick, y0 = 0.4, 0.02, 1.0
    normal = np.array([0.0, -np.sin(a), np.cos(a)])
    top_middle = np.array([0.0, y0 + 0.5 * length * np.cos(a), 0.5 * length * np.sin(a)])
    centre = top_middle - 0.5 * thick * normal
    rise, y1 = length * np.sin(a), y0 + length * np.cos(a)
    document = {
        "boxes": [
            {"center": centre.tolist(), "size": [1.2, length, thick], "rpy": [angle_deg, 0, 0]},
            {"center": [0.0, y1 + 0.75, rise / 2], "size": [1.2, 1.5, rise]},
        ]
    }
    path = folder / f"ramp{angle_deg:g}.json"
    path.write_text(json.dumps(document))
    return path


def _plan_ramp(path: Path, out: Path) -> int:
    return main(
        [
            "plan",
            "--waypoints",
            "0,2.4",
            "--height",
            "0.4",
            "--unit-time",
            "auto",
            "--samples-per-unit",
            str(FEW_SAMPLES * 5),
            "--no-plots",
            "--no-html",
            "--terrain",
            str(path),
            "--out",
            str(out),
        ]
    )


def test_a_20_deg_ramp_plans_with_its_feet_on_the_slope(tmp_path, capsys):
    """SILO4 at h = 0.4 m walks up a 20 deg ramp onto a platform at mu_plan 0.5: tan 20 deg =
    0.36 of a standing foot plus the crawl's accelerations, slowed to fit (--unit-time auto
    retimes by the friction demand in the ramp's frame); footholds stand on the slope."""
    ramp = _ramp_file(tmp_path, 20.0)
    code = _plan_ramp(ramp, tmp_path / "run")
    assert code == 0, capsys.readouterr().err
    feet = np.load(tmp_path / "run" / "trajectory.npz")
    stance = feet["position_foot_in_world"][feet["contact"].astype(bool)]
    normals = load_terrain(ramp).normal_at(stance[:, :2])
    assert np.sum(np.degrees(np.arccos(normals[:, 2])) > 19.9) > 0


def test_a_30_deg_ramp_is_refused_naming_it_and_its_angle(tmp_path, capsys):
    """30 deg > atan(0.5) = 26.6 deg: a foot standing on it would ask more friction than
    mu_plan; the refusal names the box and the angle, in one line, and writes nothing."""
    code = _plan_ramp(_ramp_file(tmp_path, 30.0), tmp_path / "run")
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "over box 0, which slopes 30.0 deg, steeper than 26.6 deg (atan(mu_plan 0.5)" in err
    assert not (tmp_path / "run").exists()


def test_the_friction_demand_of_a_standing_pose_on_a_ramp_is_tan_of_its_angle():
    """Standing still on a slope of angle a: each foot pushes m g / 4 ... along z, which in
    the slope's frame is m g sin a tangential over m g cos a normal: tan a; on level ground
    the same function gives |F_xy| / F_z = 0."""
    from planner.stability.contact_forces import contact_forces

    a = np.radians(20.0)
    n = np.array([0.0, -np.sin(a), np.cos(a)])
    feet = np.array([[0.3, 0.3, 0.0], [-0.3, 0.3, 0.0], [0.3, -0.3, 0.0], [-0.3, -0.3, 0.0]])
    feet[:, 2] = feet[:, 1] * np.tan(a)  # on the plane through the origin with normal n
    samples = 5
    mass, g = 45.0, 9.81
    forces = contact_forces(
        np.repeat(feet[None], samples, axis=0),
        np.ones((samples, 4), dtype=bool),
        np.tile([0.0, 0.0, 0.4], (samples, 1)),
        np.arange(samples, dtype=float),
        mass,
        g,
        0.0,
        np.tile(n, (samples, 4, 1)),
    )
    weight = mass * g
    hand = (weight * np.sin(a)) / (weight * np.cos(a))
    np.testing.assert_allclose(forces.foot_friction_demand, hand, rtol=1e-12)
    assert forces.friction_demand.max() == 0.0  # world z sees no tangential force


def test_the_friction_unit_time_on_a_slope_is_the_least_that_keeps_mu():
    """friction_unit_time_squared against a bisection on the surface demand itself: at the
    returned T the demand is <= mu, 0.1 % faster it is > mu (random accelerations and
    slopes within atan(mu), seeded)."""
    from planner.stability.contact_forces import (
        friction_unit_time_squared,
        surface_friction_demand,
    )

    rng = np.random.default_rng(22)
    mu, g = 0.5, 9.81
    acc = rng.normal(scale=0.3, size=(200, 3))
    tilt = np.radians(rng.uniform(0.0, 25.0, size=(200, 4)))
    heading = rng.uniform(0.0, 2 * np.pi, size=(200, 4))
    normals = np.stack(
        [np.sin(tilt) * np.cos(heading), np.sin(tilt) * np.sin(heading), np.cos(tilt)], axis=-1
    )
    need = friction_unit_time_squared(acc, normals, mu, g)  # (200, 4)
    binding = need > 1e-6
    assert binding.sum() > 50  # most feet need a slower plan than T = 1 s gives
    # each foot at its own T: one row per (sample, foot)
    acc_rows = np.repeat(acc, 4, axis=0)
    normal_rows = normals.reshape(-1, 1, 3)
    upright = np.ones(len(acc_rows), dtype=bool)
    for scale, keeps in ((1.0 + 1e-9, True), (1.0 - 1e-3, False)):
        t2 = np.maximum(need.reshape(-1) * scale, 1e-12)
        force = acc_rows / t2[:, None] + [0.0, 0.0, g]
        demand = surface_friction_demand(force, normal_rows, upright)[:, 0]
        if keeps:
            assert np.all(demand[binding.reshape(-1)] <= mu + 1e-9)
        else:
            assert np.all(demand[binding.reshape(-1)] > mu)


def test_silo4_plan_reads_the_terrain_file_once(tmp_path, monkeypatch):
    """plan.json, animation.html and the sim of ``silo4 plan --terrain --simulate`` use the
    TerrainMap the run read first: the file is parsed once."""
    import planner.terrain.terrain_file as terrain_file

    pytest.importorskip("mujoco")
    parsed = []
    original = terrain_file.terrain_from_document

    def counting(*args, **kwargs):
        parsed.append(kwargs.get("name"))
        return original(*args, **kwargs)

    monkeypatch.setattr(terrain_file, "terrain_from_document", counting)
    out = tmp_path / "run"
    code = main(
        [
            "plan",
            "--waypoints",
            "0,0.9 0,2.72",
            "--height",
            "0.3",
            "--samples-per-unit",
            str(FEW_SAMPLES),
            "--no-plots",
            "--simulate",
            "--terrain",
            str(DITCH_FILE),
            "--out",
            str(out),
        ]
    )
    assert code in (0, 1)  # 1: the sim's verdict (tests/test_terrain_walk.py judges walks)
    assert (out / "animation.html").is_file() and (out / "sim.json").is_file()
    assert parsed.count(str(DITCH_FILE)) == 1, parsed
