"""The creeping gait's lower bound on its duration (planner/gaits/creep_duration.py) holds, and
gait "auto" plans the same whether it uses the bound or builds the creeping gait."""

from __future__ import annotations

import numpy as np
import pytest

from planner.gaits.creep_duration import fewest_creep_units
from planner.gaits.without_turning import OmniCreep
from planner.path.plan_path import plan_path
from planner.studies.cases import path_waypoints


def _random_paths(seed: int, count: int) -> list[tuple[np.ndarray, float, float, float]]:
    """(waypoints (K, 2) [m], height [m], start heading [rad], tolerance [m]) of ``count``
    seeded paths of 1-5 waypoints 0.02-1 m apart, some within the tolerance of each other."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        heading = float(rng.uniform(-np.pi, np.pi))
        direction, point, waypoints = heading, np.zeros(2), []
        for _ in range(int(rng.integers(1, 6))):
            direction += float(rng.uniform(-2.5, 2.5))
            step_m = rng.uniform(0.02, 1.0)
            point = point + step_m * np.array([np.cos(direction), np.sin(direction)])
            waypoints.append(point.copy())
        tolerance = float(rng.choice([0.01, 0.05, 0.15]))
        out.append((np.array(waypoints), float(rng.uniform(0.22, 0.58)), heading, tolerance))
    return out


@pytest.mark.parametrize("case", range(14))
def test_the_creeping_gait_takes_no_fewer_units_than_its_bound(silo4, case) -> None:
    """On the Chapter 6 paths and seeded random ones (tolerances 0.01-0.15 m), the creeping
    gait's plan lasts at least fewest_creep_units."""
    if case < 4:
        path, h = [("straight", 0.4), ("circle", 0.6), ("circle-reduced", 0.2), ("straight", 0.6)][
            case
        ]
        waypoints, tolerance = path_waypoints(path)
        heading = np.pi / 2
    else:
        waypoints, h, heading, tolerance = _random_paths(23, 10)[case - 4]
    plan = plan_path(
        silo4,
        waypoints,
        h,
        start_heading=heading,
        tolerance=tolerance,
        gait="creep",
        samples_per_unit=2,
    )
    units = plan.steps[-1].t_end if plan.steps else 0.0
    bound = fewest_creep_units(plan.workspace, plan.waypoints_in_world, heading, plan.tolerance)
    assert 0.0 <= bound <= units


def test_auto_plans_the_same_without_the_bound(silo4, monkeypatch) -> None:
    """Where the bound reaches the crawl's time (the thesis straight path at h = 0.4 m), gait
    "auto" skips the creeping gait, and its plan is the one building the creeping gait to
    its stop (NotFaster) gives."""
    waypoints, tolerance = path_waypoints("straight")

    def plan():
        return plan_path(silo4, waypoints, 0.4, tolerance=tolerance, samples_per_unit=5)

    with_bound = plan()
    assert with_bound.gait == "crawl"
    bound = fewest_creep_units(
        with_bound.workspace, with_bound.waypoints_in_world, np.pi / 2, with_bound.tolerance
    )
    assert bound >= with_bound.steps[-1].t_end  # the creeping gait is skipped
    monkeypatch.setattr(OmniCreep, "fewest_units", lambda self, request: 0.0)
    built = plan()
    assert (built.gait, built.fallback_reason) == (with_bound.gait, with_bound.fallback_reason)
    assert [s.label for s in built.steps] == [s.label for s in with_bound.steps]
    for name in ("t", "q", "position_base_in_world", "contact"):
        np.testing.assert_array_equal(
            getattr(built.trajectory, name), getattr(with_bound.trajectory, name)
        )
