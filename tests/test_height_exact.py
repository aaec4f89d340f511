"""--height auto (planner/path/height.py) returns what the grid search of its module docstring
returns when every candidate is planned in full: the same height, time, E_n and refined heights.
The reference here is written out on its own (not best_height with its bound switched off), so
a change to how the search orders, stops, skips or plans again its candidates is compared with
the plain grid it must stay equal to."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from planner.errors import PlanningError
from planner.model import as_planning_model
from planner.path.at_height import plan_at_height
from planner.path.height import (
    COARSE_STEP_M,
    FINE_STEP_M,
    REFINE_COUNT,
    SEARCH_SAMPLES_PER_UNIT,
    _grid,
    best_height,
)
from planner.presets import preset_for
from planner.trajectory.clearance import check_ground_clearance
from planner.trajectory.limits import check_static_effort
from planner.workspace.layout import feasible_height_range
from silo4kin import load_robot

MANTIS = Path(__file__).parent / "robots" / "mantis.urdf"


def exhaustive_search(robot, waypoints, workspace: str, **kwargs):  # noqa: ANN001, ANN003, ANN201
    """(chosen height [m], its (time [units], E_n [m]), {height: (time, E_n)}) of the grid
    search with every candidate planned in full: the coarse grid, then the fine grid around
    the REFINE_COUNT best coarse heights; refused heights score (inf, inf)."""
    model = as_planning_model(robot)
    lo, hi = feasible_height_range(model.planning_robot, preset_for(workspace).name)

    def score(h: float) -> tuple[float, float]:
        try:
            plan = plan_at_height(
                model,
                waypoints,
                h,
                workspace=workspace,
                samples_per_unit=SEARCH_SAMPLES_PER_UNIT,
                **kwargs,
            )
            check_static_effort(
                model.robot, plan.trajectory, plan.preset.load, plan.preset.torque_headroom
            )
            check_ground_clearance(
                model.robot, plan.trajectory, None, min_clearance_m=plan.preset.ground_clearance_m
            )
        except PlanningError:
            return (np.inf, np.inf)
        errors = np.hypot(*(plan.position_walked_in_world - plan.waypoints_in_world).T)
        return (float(plan.trajectory.time_units[-1]), float(errors.mean()))

    scores = {float(h): score(float(h)) for h in _grid(lo, hi, COARSE_STEP_M)}
    ranked = sorted(scores, key=lambda h: (*scores[h], h))
    for h0 in ranked[:REFINE_COUNT]:
        if np.isfinite(scores[h0][0]):
            for h in _grid(max(lo, h0 - COARSE_STEP_M), min(hi, h0 + COARSE_STEP_M), FINE_STEP_M):
                if float(h) not in scores:
                    scores[float(h)] = score(float(h))
    best = min(scores, key=lambda h: (*scores[h], h))
    return best, scores[best], scores


@pytest.mark.parametrize(
    ("robot_name", "waypoints", "heading_deg", "provisional_factor"),
    [
        ("silo4", [(0.0, 0.6), (0.4, 0.9)], 90.0, None),
        ("mantis", [(0.0, 0.6), (0.4, 0.9)], 90.0, None),
        # the first coarse time is the fastest: with the coarse heights stopped at it (a
        # provisional factor of 1), four are planned again (or not) once the second is known
        ("mantis", [(0.5, 0.5)], 90.0, 1.0),
    ],
)
def test_the_search_picks_what_planning_every_candidate_in_full_picks(
    monkeypatch: pytest.MonkeyPatch,
    robot_name: str,
    waypoints: list,
    heading_deg: float,
    provisional_factor: float | None,
) -> None:
    """Same height, time and E_n as the exhaustive grid; the same heights evaluated (so the
    same refined ones); every time the search finished is the exhaustive one, and every
    height it stopped is at least as slow as the choice. PROVISIONAL_FACTOR changes only the
    work, so any value must give the same."""
    import planner.path.height as height

    if provisional_factor is not None:
        monkeypatch.setattr(height, "PROVISIONAL_FACTOR", provisional_factor)
    robot = load_robot(None if robot_name == "silo4" else str(MANTIS))
    heading = float(np.deg2rad(heading_deg))
    choice = best_height(robot, waypoints, workspace="default", start_heading=heading)
    best, (units, error), scores = exhaustive_search(
        robot, waypoints, "default", start_heading=heading
    )
    assert (choice.height_m, choice.time_units, choice.normalized_error_m) == (best, units, error)
    assert {float(h) for h in choice.evaluated[:, 0]} == set(scores)
    for h, t in choice.evaluated:
        if float(h) in choice.stopped_m:
            assert scores[float(h)][0] >= choice.time_units
        else:
            assert t == scores[float(h)][0]
    assert choice.stopped_m, "nothing was stopped: the comparison would not see a wrong bound"
