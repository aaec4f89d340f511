"""plan_path refuses bad Python input with PlannerInputError, and bounds its work (issue 13).

The work budget's estimate (planner/request.py) is checked against real plans: it must not
undercount what the planner then produces by more than a small factor, or the budget would
not bound anything.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import planner.path.at_height as path_module
import planner.request as inputs
from planner.errors import PlannerInputError
from planner.path.plan_path import plan_path
from planner.request import estimate_time_units
from planner.workspace.layout import workspace_for

WP = [[0.0, 0.5], [0.3, 0.8]]


@pytest.mark.parametrize(
    "kwargs,fragment",
    [
        ({"height": "0.4"}, "height must be a number [m] or 'auto'"),
        ({"height": None}, "height must be a real number"),
        ({"height": True}, "height must be a real number"),
        ({"height": complex(0.4, 0)}, "height must be a real number"),
        ({"height": float("nan")}, "height must be a finite number"),
        ({"start_heading": "north"}, "start_heading must be a real number"),
        ({"start_heading": None}, "start_heading must be a real number"),
        ({"waypoints_in_world": [[0.0, 0.5 + 1j]]}, "complex numbers"),
        ({"waypoints_in_world": "0,1"}, "text"),
        ({"waypoints_in_world": None}, "object values"),
        ({"waypoints_in_world": [[0.0, 1.0], [1.0]]}, "shape (K, 2)"),
        ({"waypoints_in_world": [[True, False]]}, "booleans"),
        ({"waypoints_in_world": [[1e9, 0.0]]}, "more than"),
        ({"workspace": 3}, "workspace must be a preset name"),
        ({"tolerance": "0.1"}, "tolerance must be a real number"),
        ({"tolerance": -0.1}, "tolerance must be in"),
        ({"stability_threshold": float("inf")}, "stability_threshold must be a finite"),
        ({"samples_per_unit": 10.0}, "samples_per_unit must be an integer"),
        ({"samples_per_unit": True}, "samples_per_unit must be an integer"),
        ({"unit_time_s": 1e300}, "unit_time_s must be in"),
        ({"unit_time_s": "1"}, "unit_time_s must be a real number"),
        ({"robot": None}, "robot must be a silo4kin Robot"),
    ],
)
def test_bad_python_input_is_a_planner_input_error(silo4, kwargs, fragment) -> None:
    """Strings, None, bools, complex numbers, wrong shapes: PlannerInputError naming the value
    (before: numpy TypeError, or complex waypoints silently truncated to their real part)."""
    call = {"robot": silo4, "waypoints_in_world": WP, "height": 0.4, **kwargs}
    robot, wp, h = call.pop("robot"), call.pop("waypoints_in_world"), call.pop("height")
    with pytest.raises(PlannerInputError, match=None) as info:
        plan_path(robot, wp, h, **call)
    assert fragment in str(info.value)


def test_numpy_scalars_and_integer_waypoints_are_accepted(silo4) -> None:
    """Valid input in other numeric types still plans (int waypoints, numpy scalars)."""
    plan = plan_path(
        silo4,
        np.array([[0, 1]]),
        np.float32(0.4),
        start_heading=np.float64(1.5),
        samples_per_unit=np.int64(5),
        unit_time_s=2,
    )
    assert len(plan.trajectory) > 1 and plan.trajectory.unit_time_s == 2.0


def test_far_waypoint_is_refused_before_any_step(silo4, monkeypatch) -> None:
    """A waypoint 1000 km away is refused by the estimate alone: no step is built."""

    def never(*args, **kwargs):
        raise AssertionError("the planner ran")

    monkeypatch.setattr(path_module, "gait_for", never)
    with pytest.raises(PlannerInputError, match="split the path"):
        plan_path(silo4, [[0.0, 999_000.0]], 0.4)
    with pytest.raises(PlannerInputError, match=r"at most \d+ samples per unit"):
        plan_path(silo4, [[0.0, 1000.0]], 0.4)  # ~24 500 units: 20 per unit would fit


def test_waypoint_count_budget(silo4, monkeypatch) -> None:
    """More than MAX_WAYPOINTS waypoints: refused, saying to split the path."""
    monkeypatch.setattr(inputs, "MAX_WAYPOINTS", 3)
    with pytest.raises(PlannerInputError, match="4 waypoints exceed the budget of 3"):
        plan_path(silo4, np.zeros((4, 2)), 0.4)


def test_budget_limit_is_the_configured_one(silo4, monkeypatch) -> None:
    """Lowering MAX_TOTAL_SAMPLES refuses a plan the default budget accepts."""
    plan_path(silo4, [[0.0, 1.0]], 0.4, samples_per_unit=10)
    monkeypatch.setattr(inputs, "MAX_TOTAL_SAMPLES", 50)
    with pytest.raises(PlannerInputError, match="over the budget of 50"):
        plan_path(silo4, [[0.0, 1.0]], 0.4, samples_per_unit=10)


@pytest.mark.parametrize("preset", ["default", "thesis"])
@pytest.mark.parametrize(
    "waypoints,heading",
    [
        ([[0.0, 1.0], [1.0, 1.0], [0.0, 2.0], [0.0, 3.0]], math.pi / 2),  # thesis straight path
        ([[2.0, 0.0]], math.pi / 2),  # a turn first
        ([[0.0, 3.0]], math.pi / 2),  # straight ahead
        ([[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]], 0.0),  # a square
    ],
)
def test_estimate_tracks_the_planned_length(silo4, preset, waypoints, heading) -> None:
    """The estimate (O(K), before planning) is within a factor 2 of the planned time units
    (2.6 above for the default preset, whose continuous crawl covers a stride in about 5
    units against the estimate's 8 of the thesis's creeping gait: (2, 0) plans in 22 units
    against an estimate of 56.2), so the sample budget bounds the real work."""
    plan = plan_path(
        silo4, waypoints, 0.4, start_heading=heading, workspace=preset, samples_per_unit=5
    )
    ws = workspace_for(silo4, 0.4, preset)
    estimate = estimate_time_units(np.array(waypoints, float), heading, ws.stride_m, ws.psi_max_rad)
    planned = float(plan.trajectory.time_units[-1])
    assert 0.5 <= estimate / planned <= (2.6 if preset == "default" else 2.0), (estimate, planned)
