"""Terrain files in the planner and ``silo4 plan --terrain``: the thesis's ditch as a file
plans as planner/studies/ditch.py plans it, a terrain without footholds is refused by name,
plan.json records the file's content and the HTML draws it."""

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


def test_the_ditch_file_plans_the_ditch_study_plan(silo4):
    """The route the ditch study finds, planned on ditch.yaml, is the study's plan sample for
    sample; a route the study's terrain refuses is refused the same way on the file."""
    outcome = plan_ditch_crossing(
        silo4, Ditch(1.5, 0.15), DITCH_HEIGHT_M, workspace="default", samples_per_unit=FEW_SAMPLES
    )
    terrain = load_terrain(DITCH_FILE)
    plan = _plan_or_refusal(silo4, outcome.route_in_world, terrain)
    assert not isinstance(plan, str), plan
    ours, theirs = _trajectory_arrays(plan), _trajectory_arrays(outcome.plan)
    for name in ours:
        np.testing.assert_array_equal(ours[name], theirs[name], err_msg=name)
    assert plan.gait == outcome.plan.gait
    study = Ditch(1.5, 0.15).terrain(FOOT_CLEARANCE_M)
    for route in (np.array([[0.0, 0.9], [0.0, 3.0]]), np.array([[0.2, 0.9], [-0.3, 3.2]])):
        on_file, on_study = (_plan_or_refusal(silo4, route, t) for t in (terrain, study))
        if isinstance(on_study, str):
            assert on_file == on_study
        else:
            assert not isinstance(on_file, str), on_file
            np.testing.assert_array_equal(on_file.trajectory.q, on_study.trajectory.q)


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
    tells a run on another terrain apart)."""
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
    assert run_options(args) == {
        **OPTION_DEFAULTS,
        "terrain": load_terrain(DITCH_FILE).to_document(),
    }
