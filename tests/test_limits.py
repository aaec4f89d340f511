"""URDF velocity and effort limits along plans; the shortest allowed unit time (issue 9)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from test_cli_plan import assert_one_line_error, run_cli

from planner import PlannerInputError, plan_path
from planner.studies.cases import path_waypoints
from planner.trajectory.limits import (
    JointLimitError,
    _first_violation,
    _torques,
    enforce_limits,
    retime,
    shortest_unit_time,
    shortest_unit_time_closed_form,
    urdf_limits,
)
from silo4kin import load_robot
from viz.cli.main import EXIT_BAD_INPUT, EXIT_OK

#: Bisection on the real torque computation stops at this relative bracket [-].
BISECTION_RTOL = 1e-6


@pytest.fixture(scope="module")
def straight_plan(silo4):
    wp, _ = path_waypoints("straight")
    return plan_path(silo4, wp, 0.4, samples_per_unit=10)


def test_urdf_limits_are_read_by_joint_name(silo4):
    vel, eff = urdf_limits(silo4)
    np.testing.assert_array_equal(vel, np.full(12, 10.0))  # urdf/silo4.urdf.xacro
    np.testing.assert_array_equal(eff, np.full(12, 60.0))
    vel, eff = urdf_limits(load_robot(xacro_args={"joint_velocity": 4, "joint_effort": 30}))
    assert np.all(vel == 4.0) and np.all(eff == 30.0)


def test_retime_equals_planning_at_that_unit_time(silo4):
    """q̇ scales 1/T and q̈ 1/T² exactly: retiming equals sampling again at T."""
    wp = [(0.3, 0.6)]
    one = plan_path(silo4, wp, 0.4, samples_per_unit=10, unit_time_s=1.0)
    half = plan_path(silo4, wp, 0.4, samples_per_unit=10, unit_time_s=0.5)
    fast = retime(one.trajectory, 0.5)
    np.testing.assert_allclose(fast.t, half.trajectory.t, atol=1e-12)
    np.testing.assert_allclose(fast.qd, half.trajectory.qd, atol=1e-9)
    np.testing.assert_allclose(fast.qdd, half.trajectory.qdd, atol=1e-9)


@pytest.mark.parametrize("load,xacro", [("body", None), ("total", {"joint_effort": 55})])
def test_closed_form_unit_time_equals_bisection_on_real_torques(load, xacro):
    """The shortest unit time from τ = τ_static + τ_dyn / T² equals a bisection that only
    asks the real torque computation (RNEA + support reactions) whether a unit time keeps
    every limit; with a lower effort limit the effort bound is the one that binds."""
    robot = load_robot(xacro_args=xacro)
    wp, _ = path_waypoints("straight")
    traj = plan_path(robot, wp, 0.4, samples_per_unit=10).trajectory
    t_cf = shortest_unit_time_closed_form(robot, traj, load)

    def ok(t: float) -> bool:
        fast = retime(traj, t)
        return _first_violation(robot, fast, _torques(robot, fast, load)) is None

    good, bad = 10.0, 0.01
    assert ok(good) and not ok(bad)
    while good - bad > BISECTION_RTOL * good:
        mid = 0.5 * (good + bad)
        good, bad = (mid, bad) if ok(mid) else (good, mid)
    assert t_cf == pytest.approx(good, rel=10 * BISECTION_RTOL)
    assert shortest_unit_time(robot, traj, load) >= t_cf


def test_a_fast_unit_time_is_refused_naming_joint_value_limit_and_time(silo4, straight_plan):
    with pytest.raises(
        JointLimitError,
        match=r"joint \w+ velocity [\d.]+ rad/s exceeds its "
        r"URDF limit 10\.000 rad/s at t = [\d.]+ s",
    ):
        enforce_limits(silo4, straight_plan.trajectory, 0.3)
    traj, check = enforce_limits(silo4, straight_plan.trajectory, "auto")
    assert check.unit_time_s == check.shortest_unit_time_s == traj.unit_time_s
    vel, eff = urdf_limits(silo4)
    assert np.all(np.abs(traj.qd) <= vel * (1 + 1e-9))
    assert max(check.velocity_ratio, check.effort_ratio) == pytest.approx(1.0, abs=2e-3)


def test_too_heavy_for_its_motors_at_any_speed():
    """5 N m joints: the default preset has no height whose creeping stances keep the
    effort budget (planner/workspace/stance_budget.py), and says so; the thesis preset
    plans it, and no unit time makes its static torques fit."""
    robot = load_robot(xacro_args={"joint_effort": 5})
    with pytest.raises(PlannerInputError, match="effort budget"):
        plan_path(robot, [(0.0, 0.3)], 0.4, samples_per_unit=4)
    traj = plan_path(robot, [(0.0, 0.3)], 0.4, samples_per_unit=4, workspace="thesis").trajectory
    with pytest.raises(JointLimitError, match="no unit time helps"):
        shortest_unit_time(robot, traj)


def test_cli_unit_time_refused_or_auto(capsys, tmp_path):
    """`--unit-time 0.3` on the thesis straight path: one line naming the joint, nothing
    written; `--unit-time auto`: metrics.json gives the shortest unit time the joint limits
    allow and the one used (no shorter; longer where friction needs it)."""
    args = [
        "plan",
        "--waypoints",
        "0,1 1,1 0,2 0,3",
        "--height",
        "0.4",
        "--samples-per-unit",
        "10",
        "--no-html",
        "--no-plots",
    ]
    code, _, err = run_cli(capsys, *args, "--unit-time", "0.3", "--out", str(tmp_path / "a"))
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, "joint", "URDF limit", "t = ", "--unit-time auto")
    assert not (tmp_path / "a").exists()
    code, _, _ = run_cli(capsys, *args, "--unit-time", "auto", "--out", str(tmp_path / "b"))
    assert code == EXIT_OK
    limits = json.loads((tmp_path / "b" / "metrics.json").read_text())["joint_limits"]
    # the shortest unit time of the joint limits, or longer where the friction demand of the
    # crawl's sway needs it (planner/outputs/pipeline.py, mu_plan 0.5)
    assert limits["unit_time_s"] >= limits["shortest_unit_time_s"] > 0.3
    with pytest.raises(SystemExit) as exc:  # argparse: usage + exit 2
        run_cli(capsys, *args, "--unit-time", "fast", "--out", str(tmp_path / "c"))
    assert exc.value.code == EXIT_BAD_INPUT and "'auto'" in capsys.readouterr().err
