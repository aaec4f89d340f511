"""The lower bounds on a gait's time (planner/gaits/crawl_duration.py, creep_spin_duration.py,
creep_duration.py) hold on real plans: the crawl's bound on the rest of its walk, recorded
after every swing and four-foot phase and wherever the gait checks its time limit, never
exceeds the time the plan then still takes (SILO4, mantis, phasmid, go2; seeded paths and
heights), and the bounds of facing the path and of the plain creeping and spinning gait
never exceed their plans' times."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from planner.errors import PlanningError
from planner.gaits.base import NotFaster, fewest_units
from planner.gaits.builder import StepBuilder
from planner.gaits.crawl import Crawl
from planner.gaits.registry import gait_for
from planner.model import as_planning_model
from planner.path.at_height import plan_at_height
from planner.presets import preset_for
from planner.studies.cases import path_waypoints
from planner.workspace.layout import feasible_height_range
from silo4kin.robot import load_robot

ROBOTS = Path(__file__).with_name("robots")
SOURCES = {
    "silo4": None,
    "mantis": str(ROBOTS / "mantis.urdf"),
    "phasmid": str(ROBOTS / "phasmid.urdf.xacro"),
    "go2": "go2",
}
#: A limit no plan reaches: the gaits check it (and record their bound) but never stop.
NO_LIMIT_UNITS = 1e9


def _paths(model, seed: int, count: int) -> list[tuple[np.ndarray, float, float, float]]:  # noqa: ANN001
    """(waypoints (K, 2) [m], height [m], start heading [rad], tolerance [m]) of ``count``
    seeded paths of 1-4 waypoints 0.05-0.8 m apart in any direction, at heights where the
    robot walks any direction (the rest of its range walks only along its body)."""
    lo, hi = feasible_height_range(model.planning_robot, "default", any_direction=True)
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        heading = float(rng.uniform(-np.pi, np.pi))
        direction, point, waypoints = heading, np.zeros(2), []
        for _ in range(int(rng.integers(1, 5))):
            direction += float(rng.uniform(-2.5, 2.5))
            point = point + rng.uniform(0.05, 0.8) * np.array(
                [np.cos(direction), np.sin(direction)]
            )
            waypoints.append(point.copy())
        tolerance = float(rng.choice([0.01, 0.05, 0.15]))
        out.append((np.array(waypoints), float(rng.uniform(lo, hi)), heading, tolerance))
    return out


def _crawl_records(monkeypatch: pytest.MonkeyPatch):
    """(records, finished): the (time so far [units], bound on the rest [units], steps built,
    last step) after every crawl swing and four-foot phase and at every time-limit check,
    and the steps and time of each finished walk."""
    records: list[tuple[float, float, int, object]] = []
    finished: list[tuple[list, float]] = []

    def record(b: StepBuilder) -> None:
        if b.rest_units is not None:
            rest = b.rest_units(b.nominal_base[:2])
            records.append((b.t_plan, rest, len(b.steps), b.steps[-1] if b.steps else None))

    for name in ("_swing", "_four_foot"):
        original = getattr(Crawl, name)

        def wrapped(self, b, *args, _original=original, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
            out = _original(self, b, *args, **kwargs)
            record(b)
            return out

        monkeypatch.setattr(Crawl, name, wrapped)
    check = StepBuilder.check_time_limit

    def checked(self: StepBuilder) -> None:
        record(self)
        check(self)

    monkeypatch.setattr(StepBuilder, "check_time_limit", checked)
    import planner.gaits.walk as walk

    finish = walk.finish_plan

    def finishing(request, name, b, walked, smooth):  # noqa: ANN001, ANN202
        finished.append((list(b.steps), b.t_plan))
        return finish(request, name, b, walked, smooth=smooth)

    monkeypatch.setattr(walk, "finish_plan", finishing)
    return records, finished


@pytest.mark.parametrize("robot", sorted(SOURCES))
@pytest.mark.parametrize("gait", ["crawl", "creep"])
def test_the_walk_takes_at_least_its_bound_from_every_step(
    monkeypatch: pytest.MonkeyPatch, robot: str, gait: str
) -> None:
    """On seeded paths and heights (and the thesis straight path on SILO4), the time the
    crawl has taken at each swing, four-foot phase and time-limit check of its plan (the
    creeping gait: at each time-limit check, before every half cycle), plus its bound on the
    rest from there, is at most the plan's time."""
    model = as_planning_model(load_robot(SOURCES[robot]))
    cases = _paths(model, 2312 + len(robot) + len(gait), 4)
    if robot == "silo4":
        straight, _ = path_waypoints("straight")
        cases += [(straight, h, np.pi / 2, 0.01) for h in (0.3, 0.41, 0.5)]
    records, finished = _crawl_records(monkeypatch)
    checked = plans = 0
    for waypoints, h, heading, tolerance in cases:
        records.clear()
        finished.clear()
        try:
            plan = _plan(model, waypoints, h, heading, tolerance, gait, NO_LIMIT_UNITS)
        except (PlanningError, NotFaster):  # NotFaster: its bound is infinite (no stride)
            continue
        plans += 1
        steps, units = finished[-1]  # the creeping gait's last walk (foothold replacements)
        assert units == pytest.approx(plan.steps[-1].t_end)
        bound = fewest_units(gait_for(preset_for("default"), gait), plan_request(plan, model))
        assert 0.0 <= bound <= units + 1e-9
        for t, rest, n, last in records:
            if n and (n > len(steps) or steps[n - 1] is not last):
                continue  # a step rolled back (CrawlOrCreep) or of a walk made again
            checked += 1
            assert t + rest <= units + 1e-9, (h, t, rest, units)
    assert plans >= 2 and checked >= (10 if gait == "crawl" else 3) * plans


def _plan(model, waypoints, h, heading, tolerance, gait, slower_than):  # noqa: ANN001, ANN202
    """``gait``'s plan of one seeded case at 2 samples per unit."""
    return plan_at_height(
        model,
        waypoints,
        h,
        start_heading=heading,
        tolerance=tolerance,
        samples_per_unit=2,
        gait=gait,
        slower_than=slower_than,
    )


def plan_request(plan, model):  # noqa: ANN001, ANN201
    """The PlanRequest of ``plan`` (its workspace, waypoints, heading and tolerance)."""
    from planner.gaits.base import PlanRequest
    from planner.terrain.base import FlatGround

    return PlanRequest(
        model=model,
        preset=preset_for("default"),
        workspace=plan.workspace,
        waypoints_in_world=plan.waypoints_in_world,
        start_heading=float(plan.start_heading),
        tolerance=plan.tolerance,
        threshold=plan.workspace.stability_threshold_m,
        samples_per_unit=2,
        unit_time_s=1.0,
        terrain=FlatGround(),
        first_walk_memo=None,
    )


@pytest.mark.parametrize("robot", ["silo4", "mantis"])
@pytest.mark.parametrize("gait", ["facing", "plain", "auto"])
def test_a_gait_takes_at_least_its_bound(robot: str, gait: str) -> None:
    """Facing the path, the plain creeping and spinning gait and gait "auto" (the least of
    its gaits' bounds) take at least their bound on seeded paths (the creeping gait's:
    tests/test_creep_duration.py)."""
    model = as_planning_model(load_robot(SOURCES[robot]))
    walker = gait_for(preset_for("default"), gait)
    plans = 0
    for waypoints, h, heading, tolerance in _paths(model, 77 + len(gait), 3):
        try:
            plan = _plan(model, waypoints, h, heading, tolerance, gait, None)
        except PlanningError:
            continue
        plans += 1
        bound = fewest_units(walker, plan_request(plan, model))
        assert 0.0 <= bound <= plan.steps[-1].t_end + 1e-9, (h, bound, plan.steps[-1].t_end)
    assert plans >= 2
