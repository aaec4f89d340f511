"""The default layout checks the feet lifted by the swing height its plans make (eq 5.12
raised to MIN_SWING_HEIGHT_M), not eq 5.12's lower one (planner/workspace/foothold_layout.py
swing_height_m, issue 21).

The control: phasmid at h 0.1556 m (the 200-case corpus's #2, seed 20261202), where eq 5.12
gives 28 mm. Checked at 28 mm, position 2 of its right legs could not be lifted by the 50 mm
the plans swing with the body displaced by the shift reserve (RF and RH, in one of its 8
directions), and neither the crawl nor the creeping gait found a step.
"""

from __future__ import annotations

import numpy as np

from planner.model import planning_robot
from planner.presets import MIN_SWING_HEIGHT_M
from planner.workspace.foothold_layout import hip_depth_m, swing_height_m
from planner.workspace.layout import (
    RESERVE_DIRECTIONS,
    SHIFT_RESERVE_M,
    reachable_in_limits_of_legs,
    workspace_for,
)

#: The corpus case's height [m]: eq 5.12 is under MIN_SWING_HEIGHT_M there.
LOW_HEIGHT_M = 0.1556


def test_the_plans_swing_height_is_eq_5_12_raised_to_the_presets_least(phasmid):
    """Default: max(eq 5.12, MIN_SWING_HEIGHT_M); thesis: eq 5.12 as is (its layout keeps
    its checks)."""
    eq_5_12 = (LOW_HEIGHT_M - hip_depth_m(planning_robot(phasmid))) / 2.0
    assert eq_5_12 < MIN_SWING_HEIGHT_M
    assert swing_height_m(planning_robot(phasmid), LOW_HEIGHT_M) == MIN_SWING_HEIGHT_M
    assert swing_height_m(planning_robot(phasmid), LOW_HEIGHT_M, "thesis") == eq_5_12


def test_every_foot_lifts_at_position_2_with_the_shift_reserve(phasmid):
    """Each leg's position 2, lifted by the plans' swing height, is reachable within the
    joint limits with the body displaced by SHIFT_RESERVE_M in each of the 8 directions."""
    robot = planning_robot(phasmid)
    ws = workspace_for(robot, LOW_HEIGHT_M)
    lift = np.array([0.0, 0.0, swing_height_m(robot, LOW_HEIGHT_M)])
    shifts = np.vstack([np.zeros(3), SHIFT_RESERVE_M * RESERVE_DIRECTIONS])
    for k in range(4):
        points = ws.position_mid_in_base[k] + lift + shifts
        ok = reachable_in_limits_of_legs(robot.legs, np.full(len(points), k), points)
        assert ok.all(), (k, np.flatnonzero(~ok))


def test_the_corpus_case_crawls_within_its_tolerance(phasmid):
    """The corpus's #2 (seed 20261202, its path and start heading; h 0.1556 m) plans with
    the crawl and meets its tolerance: checked at eq 5.12's lift, the layout's footholds
    gave the crawl and the creeping gait no step at waypoint 0, and the plain fallback
    missed its tolerance (E_n 29.7 mm > 10 mm). It walks in physics (docs/robots.md)."""
    from benchmark_scripts import load_benchmark

    from planner import plan_path
    from planner.path.metrics import compute_metrics

    bench = load_benchmark("bench_corpus")
    ranges = dict.fromkeys(bench.ROBOTS, (0.2, 0.4))  # only phasmid's range sets a height
    case = bench.corpus_cases(200, bench.DEFAULT_SEED, list(bench.ROBOTS), ranges)[2]
    assert case.robot == "phasmid"
    plan = plan_path(
        phasmid, case.waypoints_in_world, LOW_HEIGHT_M, start_heading=case.start_heading
    )
    assert plan.gait == "crawl" and plan.fallback_reason is None
    assert compute_metrics(plan)["normalized_error_m"] <= plan.tolerance
