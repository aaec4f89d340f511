"""Sweep grid, rows and summaries without Dask: ranges, keys, the row of one configuration
against the planner's own numbers, refused and failing configurations, the Pareto front
against brute force, best heights, rank correlation, the resumable table."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from silo4kin.errors import Silo4Error
from silo4sweep.grid import (
    SweepConfig,
    SweepInputError,
    design_grid,
    parse_values,
    parse_xacro_sweeps,
)
from silo4sweep.report import rank_correlation, render_sweep_page
from silo4sweep.summary import best_heights, pareto_mask
from silo4sweep.table import CSV_NAME, SweepTable, read_table
from silo4sweep.task import ERROR, OK, REFUSED, SweepSettings, plan_row

#: Coarse sampling keeps every plan of these tests cheap (peaks are then coarse too).
COARSE = SweepSettings(samples_per_unit=5)


def test_ranges_include_the_end_and_have_one_spelling():
    assert parse_values("0.2:0.6:0.05", "--heights") == [
        0.2,
        0.25,
        0.3,
        0.35,
        0.4,
        0.45,
        0.5,
        0.55,
        0.6,
    ]
    assert parse_values("0.3,0.2:0.4:0.1,0.45", "h") == [0.2, 0.3, 0.4, 0.45]
    assert parse_values("0.1:0.25:0.1", "h") == [0.1, 0.2]  # 0.25 is not on the grid


@pytest.mark.parametrize(
    "text", ["", "a", "0.2:0.1:0.05", "0.2:0.6:0", "0.2:0.6:-1", "nan", "0:1:1e-9"]
)
def test_bad_values_are_refused_naming_the_option(text):
    with pytest.raises(SweepInputError, match="--heights"):
        parse_values(text, "--heights")


def test_xacro_sweeps_parse_and_refuse_malformed_items():
    assert parse_xacro_sweeps(["L2=0.2,0.25", "L3=0.2:0.3:0.05"]) == {
        "L2": [0.2, 0.25],
        "L3": [0.2, 0.25, 0.3],
    }
    for bad in (["L2"], ["=0.2"], ["L2=0.2", "L2=0.3"]):
        with pytest.raises(SweepInputError):
            parse_xacro_sweeps(bad)


def test_grid_is_the_cartesian_product_in_a_fixed_order():
    grid = design_grid(
        ["straight", "circle"], [0.2, 0.4], {"L2": [0.2, 0.25], "L3": [0.3]}, ["default", "thesis"]
    )
    assert len(grid) == 2 * 2 * 2 * 1 * 2
    assert len({c.key for c in grid}) == len(grid)
    expected = {
        (p, h, pr, (("L2", l2), ("L3", 0.3)))
        for p, h, pr, l2 in itertools.product(
            ["straight", "circle"], [0.2, 0.4], ["default", "thesis"], [0.2, 0.25]
        )
    }
    assert {(c.path, c.height_m, c.preset, c.xacro_args) for c in grid} == expected
    assert grid[0].xacro_args[0] == ("L2", 0.2) and grid[-1].xacro_args[0] == ("L2", 0.25)


def test_a_row_repeats_the_planners_own_numbers(silo4):
    """The row's time, error and peaks equal what planner and torques give directly
    (joint types found by joint name, not by position)."""
    from planner.path.metrics import compute_metrics
    from planner.path.plan_path import plan_path
    from planner.studies.cases import START_HEADING_RAD, path_waypoints
    from planner.trajectory.torques import add_torques

    row = plan_row(SweepConfig("straight", 0.4, "default"), COARSE)
    assert row["status"] == OK and row["reason"] == ""
    waypoints, tol = path_waypoints("straight")
    plan = plan_path(
        silo4, waypoints, 0.4, start_heading=START_HEADING_RAD, tolerance=tol, samples_per_unit=5
    )
    metrics = compute_metrics(plan)
    # the load of the plan's policy where plans have one (planner issue 9), else App. A's body
    load = str(plan.preset.load) if hasattr(plan, "preset") else "body"
    assert row["load"] == load
    traj = add_torques(silo4, plan.trajectory, load=load)
    assert row["normalized_time"] == metrics["normalized_time"]
    assert row["normalized_error_m"] == metrics["normalized_error_m"]
    # the whole-body margin where the planner reports it
    assert row["min_margin_m"] == metrics.get("min_margin_com_m", metrics["min_stability_margin_m"])
    names = np.array(traj.joint_names)
    for kind in ("hip_yaw", "hip_pitch", "knee"):
        cols = np.char.endswith(names, kind)
        assert cols.sum() == 4
        assert row[f"tau_peak_{kind}_Nm"] == np.abs(traj.tau[:, cols]).max()
        assert row[f"qd_peak_{kind}_rad_s"] == np.abs(traj.qd[:, cols]).max()
    assert row["tau_peak_Nm"] == np.abs(traj.tau).max()
    # eq A.35 with the default mu = 100, eta = 0.7
    assert row["motor_tau_peak_Nm"] == pytest.approx(np.abs(traj.tau).max() / 70.0, rel=1e-12)


def test_a_configuration_that_cannot_be_planned_is_a_row_with_its_reason():
    row = plan_row(SweepConfig("straight", 0.1, "default"), COARSE)
    assert row["status"] == REFUSED
    assert "feasible range" in row["reason"] and "0.1" in row["reason"]
    assert "normalized_time" not in row
    bad_leg = plan_row(SweepConfig("straight", 0.4, "default", (("L3", -0.2),)), COARSE)
    assert bad_leg["status"] == REFUSED and bad_leg["reason"]


def test_a_bug_is_a_row_with_status_error(monkeypatch):
    import planner.outputs.pipeline

    def broken(*args, **kwargs):
        raise ZeroDivisionError("boom")

    monkeypatch.setattr(planner.outputs.pipeline, "plan_path", broken)  # the sweep's planner
    row = plan_row(SweepConfig("straight", 0.4, "default"), COARSE)
    assert row["status"] == ERROR and row["reason"] == "ZeroDivisionError: boom"


def test_pareto_mask_matches_brute_force():
    rng = np.random.default_rng(15)
    for _ in range(20):
        points = rng.integers(0, 6, size=(12, 2)).astype(float)  # many ties on purpose
        brute = [not any(np.all(q <= p) and np.any(q < p) for q in points) for p in points]
        assert pareto_mask(points).tolist() == brute


def test_rank_correlation_against_hand_values():
    assert rank_correlation([1, 2, 3, 4], [1, 3, 2, 4]) == pytest.approx(0.8)  # 1 - 6*2/60
    assert rank_correlation([1, 2, 3], [30, 20, 10]) == pytest.approx(-1.0)
    # ties: average ranks (1.5, 1.5, 3) vs (1, 2, 3): Pearson = sqrt(3)/2
    assert rank_correlation([5, 5, 7], [1, 2, 3]) == pytest.approx(math.sqrt(3) / 2)
    assert math.isnan(rank_correlation([1, 1, 1], [1, 2, 3]))


def _row(path, h, time, err, tau, status=OK, l2=0.2):
    return {
        "path": path,
        "preset": "default",
        "L2": l2,
        "height_m": h,
        "status": status,
        "normalized_time": time,
        "normalized_error_m": err,
        "tau_peak_Nm": tau,
        "stride_m": 0.3,
        "min_margin_m": 0.02,
        "motor_tau_peak_Nm": tau and tau / 70,
        "motor_speed_peak_rpm": 1000.0,
        "reason": "",
        "load": "body",
    }


def test_best_height_is_the_fastest_ties_to_the_more_accurate():
    rows = [
        _row("straight", 0.2, 130, 0.05, 40),
        _row("straight", 0.3, 120, 0.04, 38),
        _row("straight", 0.4, 120, 0.02, 36),
        _row("straight", 0.5, None, None, None, status=REFUSED),
    ]
    (entry,) = best_heights(rows, ["L2"])
    assert entry["best"]["height_m"] == 0.4
    assert entry["heights_refused_m"] == [0.5]
    assert entry["design"] == {"L2": 0.2}


def test_results_page_states_agreement_from_the_numbers():
    rows = [
        _row("straight", h, t, e, 40)
        | {
            "stride_m": s,
            "qd_peak_hip_yaw_rad_s": q,
            "qd_peak_hip_pitch_rad_s": q,
            "qd_peak_knee_rad_s": q,
            "tau_peak_hip_pitch_Nm": 30.0,
            "tau_peak_knee_Nm": 20.0,
        }
        for h, s, t, e, q in [
            (0.2, 0.38, 128, 0.07, 2.0),
            (0.4, 0.33, 144, 0.03, 3.0),
            (0.6, 0.14, 320, 0.02, 4.0),
        ]
    ]
    page = render_sweep_page(rows, ["L2"], command="silo4 sweep ...")
    assert "rank correlation of stride with time -1.00 (agrees" in page
    assert "rank correlation of stride with E_n +1.00 (agrees" in page
    flipped = [r | {"normalized_error_m": 0.1 - r["normalized_error_m"]} for r in rows]
    assert "E_n -1.00 (does not agree" in render_sweep_page(flipped, ["L2"], command="x")


def test_table_resumes_and_drops_a_row_cut_short(tmp_path):
    grid = design_grid(["straight"], [0.1, 0.4], {"L3": [0.24]}, ["default"])
    table = SweepTable(tmp_path, ["L3"], COARSE)
    assert table.missing(grid) == grid
    table.start()
    for c in grid:
        table.add(c, plan_row(c, COARSE))
    table.finish(grid)
    text = (tmp_path / CSV_NAME).read_text()
    again = SweepTable(tmp_path, ["L3"], COARSE)
    assert again.missing(grid) == []
    # an interrupted run leaves half a line: that row is planned again
    (tmp_path / CSV_NAME).write_text(text[:-5])
    cut = SweepTable(tmp_path, ["L3"], COARSE)
    assert cut.missing(grid) == grid[-1:]
    rows = read_table(tmp_path / CSV_NAME)
    assert [r["status"] for r in rows][:1] == [REFUSED]
    with pytest.raises(Silo4Error, match="other settings"):
        SweepTable(tmp_path, ["L3"], SweepSettings(samples_per_unit=6))
    assert (
        SweepTable(tmp_path, ["L3"], SweepSettings(samples_per_unit=6), force=True).missing(grid)
        == grid
    )


def test_simulate_adds_the_physics_verdict_of_the_sim_package(monkeypatch):
    """plan_row hands the planned trajectory (with torques) to silo4sim.run.simulate and keeps
    its verdict; a stand-in sim module records the call (the real one is issue 10's)."""
    import sys
    import types

    seen = {}

    def simulate(robot, trajectory):
        seen["tau"] = trajectory.tau
        return types.SimpleNamespace(metrics={"walks": False, "reasons": ["fell at t = 3 s"]})

    fake = types.ModuleType("silo4sim.run")
    fake.simulate = simulate
    monkeypatch.setitem(sys.modules, "silo4sim", types.ModuleType("silo4sim"))
    monkeypatch.setitem(sys.modules, "silo4sim.run", fake)
    row = plan_row(
        SweepConfig("straight", 0.4, "default"), SweepSettings(samples_per_unit=5, simulate=True)
    )
    assert row["status"] == OK
    assert (row["sim_verdict"], row["sim_reason"]) == ("fails", "fell at t = 3 s")
    assert seen["tau"] is not None and np.abs(seen["tau"]).max() == row["tau_peak_Nm"]


def test_rank_correlation_matches_scipy_with_ties():
    stats = pytest.importorskip("scipy.stats")
    rng = np.random.default_rng(7)
    for _ in range(10):
        x, y = rng.integers(0, 5, size=(2, 30))  # many ties
        assert rank_correlation(x, y) == pytest.approx(stats.spearmanr(x, y).statistic, abs=1e-12)
