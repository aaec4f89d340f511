"""Torque headroom: a run's planned peaks stay within a fraction of the URDF effort limits
(planner/trajectory/limits.py, planner/outputs/pipeline.py)."""

from __future__ import annotations

import numpy as np
import pytest

from planner import plan_path
from planner.outputs.pipeline import RunRequest
from planner.trajectory.limits import (
    TORQUE_HEADROOM,
    JointLimitError,
    enforce_limits,
    urdf_limits,
)
from planner.trajectory.torques import trajectory_torques

#: Relative rounding of the torque computation (limits.LIMIT_RTOL).
RTOL = 1e-9


@pytest.fixture(scope="module")
def short_plan(silo4):
    return plan_path(silo4, np.array([[0.0, 0.6]]), 0.4, start_heading=np.pi / 2)


def test_one_headroom_for_plan_cases_and_sweeps_the_thesis_keeps_the_full_limit():
    """silo4 plan, silo4 cases and sweeps all take the preset's headroom (RunRequest None):
    0.85 for the default preset, 1.0 for the thesis preset (Table 6.2)."""
    from planner.presets import PRESETS
    from viz.cli.main import build_parser

    args = build_parser().parse_args(
        ["plan", "--waypoints", "0,1", "--height", "0.4", "--out", "x"]
    )
    assert args.torque_headroom is None and RunRequest().torque_headroom is None
    assert PRESETS["default"].torque_headroom == TORQUE_HEADROOM == 0.85
    assert PRESETS["thesis"].torque_headroom == 1.0


def test_a_fixed_unit_time_beyond_the_budget_is_refused_naming_joint_and_time(silo4, short_plan):
    """At unit time 0.5 s (velocities within limits) a budget 10 % under the plan's peak
    effort ratio refuses it naming joint and time; 10 % over keeps it."""
    at_half, _ = enforce_limits(silo4, short_plan.trajectory, 0.5, load="total")
    _, effort = urdf_limits(silo4)
    peak = float(np.max(np.abs(trajectory_torques(silo4, at_half, load="total").total) / effort))
    tight = round(0.9 * peak, 6)
    with pytest.raises(
        JointLimitError,
        match=rf"joint \w+ .*effort budget \({tight:g} x URDF, --torque-headroom\).*t(_units)? =",
    ):
        enforce_limits(silo4, short_plan.trajectory, 0.5, load="total", headroom=tight)
    enforce_limits(silo4, short_plan.trajectory, 0.5, load="total", headroom=min(1.0, 1.1 * peak))


def test_auto_unit_time_retimes_to_keep_the_budget(silo4, short_plan):
    """--unit-time auto with headroom 0.85 finds a unit time no shorter than with the full
    limits, at which every joint's peak is within 85 % of its URDF effort (or velocity)."""
    fast, _ = enforce_limits(silo4, short_plan.trajectory, "auto", load="total", headroom=1.0)
    kept, check = enforce_limits(silo4, short_plan.trajectory, "auto", load="total", headroom=0.85)
    assert kept.unit_time_s >= fast.unit_time_s
    _, effort = urdf_limits(silo4)
    tau = trajectory_torques(silo4, kept, load="total").total
    assert np.max(np.abs(tau) / effort) <= 0.85 * (1 + RTOL)
    assert check.violation is None
    tau_fast = trajectory_torques(silo4, fast, load="total").total
    if np.max(np.abs(tau_fast) / effort) > 0.85 * (1 + RTOL):  # the budget bound the time
        assert kept.unit_time_s > fast.unit_time_s
