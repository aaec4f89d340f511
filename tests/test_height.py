"""--height auto (planner/path/height.py, thesis §7.2): the least-time height, within the range."""

import json

import numpy as np
import pytest

from planner import PlannerInputError, compute_metrics, plan_path
from planner.path.height import best_height
from planner.studies.cases import STRAIGHT_WAYPOINTS_IN_WORLD, THESIS_HEIGHTS_M
from planner.workspace.layout import feasible_height_range
from viz.cli.main import main

#: Time in units does not depend on the sampling; this keeps the tests cheap.
FEW_SAMPLES = 5


@pytest.fixture(scope="module")
def straight_auto(silo4):
    return plan_path(
        silo4, STRAIGHT_WAYPOINTS_IN_WORLD, "auto", workspace="thesis", samples_per_unit=FEW_SAMPLES
    )


def test_auto_height_is_in_range_and_recorded(silo4, straight_auto) -> None:
    """The chosen height lies in feasible_height_range; the plan records the search and its
    time is the plan's own time."""
    lo, hi = feasible_height_range(silo4, "thesis")
    assert lo <= straight_auto.height <= hi
    search = straight_auto.height_search
    assert search["height_m"] == straight_auto.height
    assert search["feasible_range_m"] == [lo, hi]
    m = compute_metrics(straight_auto)
    assert search["time_units"] == pytest.approx(m["normalized_time"], abs=1e-9)
    assert m["height_search"] == search


def test_auto_height_beats_the_thesis_heights(silo4, straight_auto) -> None:
    """No Chapter 6 height, planned independently, walks the path in less time."""
    for h in THESIS_HEIGHTS_M:
        other = plan_path(
            silo4, STRAIGHT_WAYPOINTS_IN_WORLD, h, workspace="thesis", samples_per_unit=FEW_SAMPLES
        )
        assert straight_auto.trajectory.time_units[-1] <= other.trajectory.time_units[-1]


def test_best_height_is_the_minimum_of_what_it_evaluated(silo4) -> None:
    """Deterministic, and no evaluated height was faster (ties: lower E_n, then lower h)."""
    a = best_height(silo4, STRAIGHT_WAYPOINTS_IN_WORLD, workspace="thesis")
    b = best_height(silo4, STRAIGHT_WAYPOINTS_IN_WORLD, workspace="thesis")
    assert a.height_m == b.height_m
    np.testing.assert_array_equal(a.evaluated, b.evaluated)
    assert a.time_units == a.evaluated[:, 1].min()
    assert a.feasible_range_m[0] in a.evaluated[:, 0]
    assert a.feasible_range_m[1] in a.evaluated[:, 0]


def test_bad_height_word_is_refused(silo4) -> None:
    with pytest.raises(PlannerInputError, match="'auto'"):
        plan_path(silo4, [(0, 1)], "high")


def test_cli_height_auto_prints_and_records(tmp_path, capsys) -> None:
    """silo4 plan --height auto prints the chosen height and writes it to both JSON files."""
    out = tmp_path / "run"
    code = main(
        [
            "plan",
            "--waypoints",
            "0,1 0,2",
            "--height",
            "auto",
            "--workspace",
            "thesis",
            "--start-heading",
            "90",
            "--samples-per-unit",
            "5",
            "--no-html",
            "--no-plots",
            "--no-torques",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    printed = capsys.readouterr().out
    plan_json = json.loads((out / "plan.json").read_text())
    metrics = json.loads((out / "metrics.json").read_text())
    h = plan_json["height_m"]
    assert f"--height auto: h = {h:.3f} m" in printed
    assert plan_json["height_search"]["height_m"] == h == metrics["height_search"]["height_m"]


def test_cli_height_word_exits_2(tmp_path) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["plan", "--waypoints", "0,1", "--height", "tall", "--out", str(tmp_path / "x")])
    assert exc.value.code == 2
    assert not (tmp_path / "x").exists()


def test_height_search_is_bounded_by_work_before_it_plans(silo4) -> None:
    """--height auto on a 1 km path is refused at once, naming the bound; the thesis circle
    and straight path fit the same bound."""
    from planner.model import as_planning_model
    from planner.path.height import check_search_budget
    from planner.studies.cases import path_waypoints
    from planner.workspace.layout import feasible_height_range

    model = as_planning_model(silo4)
    lo, hi = feasible_height_range(model.planning_robot)
    for path in ("straight", "circle"):
        check_search_budget(model, path_waypoints(path)[0], lo, hi, "default", np.pi / 2)
    with pytest.raises(PlannerInputError, match="give a height in metres, or split the path"):
        plan_path(silo4, [[0.0, 1000.0]], "auto", samples_per_unit=5)


def test_auto_height_is_one_the_run_plans_within_its_effort_budget(phasmid) -> None:
    """The search skips heights whose plan needs more than the preset's effort budget
    standing still (0.85 x URDF effort), as the run pipeline does: it judged them against the
    URDF effort itself, and on this phasmid path (a corpus case) picked h = 0.39 m, where the
    run refused `LH_hip_pitch needs 34.31 N m standing still, above its effort budget ...
    34.00 N m`. The height it picks plans through the run pipeline."""
    from planner.outputs.pipeline import RunRequest, plan_run

    robot = phasmid
    waypoints = np.array([[0.55, 0.63], [-0.31, 0.70], [-0.67, 0.16]])
    heading = np.deg2rad(152.0)
    choice = best_height(robot, waypoints, start_heading=heading)
    run = plan_run(robot, waypoints, choice.height_m, RunRequest(), start_heading=heading)
    assert run.plan.height == choice.height_m
