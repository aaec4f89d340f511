"""The omnidirectional gait refuses a stall instead of repeating it (planner/gaits/omni.py
Stall): a step halved towards zero until its footholds are reachable made no progress and
the plan ran until a 10,000 half-cycle cap."""

from __future__ import annotations

import math

import numpy as np
import pytest

YAW = math.pi / 2


def test_a_stalled_omnidirectional_gait_is_refused_not_repeated():
    """omni.Stall: half cycles advancing less than STALL_FRACTION of the step asked, in a row,
    refuse the gait after MAX_STALLED_HALF_CYCLES (mantis before a 0.2625 m gap ran 4,700
    half cycles of 0.1-12 mm in 100 s towards the 10,000 cap); a short step that was asked
    for (the last one onto a waypoint) is not stalled, and a good step resets the count."""
    from planner.errors import PlanningError
    from planner.gaits.omni import MAX_STALLED_HALF_CYCLES, Stall

    class Builder:
        def error(self, reason):
            return PlanningError(reason)

    stall = Stall()
    for _ in range(3 * MAX_STALLED_HALF_CYCLES):
        stall.record(0.001, 0.001, Builder())  # short, as asked
    for _ in range(MAX_STALLED_HALF_CYCLES - 1):
        stall.record(0.001, 0.15, Builder())
    stall.record(0.15, 0.15, Builder())  # progress: the count starts again
    for _ in range(MAX_STALLED_HALF_CYCLES - 1):
        stall.record(0.001, 0.15, Builder())
    with pytest.raises(PlanningError, match="makes no progress"):
        stall.record(0.0005, 0.15, Builder())


def test_mantis_before_a_wide_gap_gets_an_answer_in_seconds():
    """bench_capability.py's 0.2625 m gap for mantis at h 0.35 m: the omnidirectional gait
    stalled (steps halved towards 0) and the plan ran for more than 12 minutes; now the
    stall refuses that gait and gait auto answers (a plan or a named refusal)."""
    import sys
    from pathlib import Path

    from planner import plan_path
    from planner.terrain import terrain_from_document
    from silo4kin import load_robot
    from silo4kin.errors import Silo4Error

    bench = str(Path(__file__).resolve().parents[1] / "benchmarks")
    sys.path.insert(0, bench)
    try:
        import bench_capability
        from bench_terrain import HEIGHTS_M, ROBOTS, layout_for
    finally:
        sys.path.remove(bench)
    robot = load_robot(ROBOTS["mantis"])
    layout = layout_for(robot, HEIGHTS_M["mantis"])
    document, goal_y = bench_capability.gap(layout, 0.2625)
    terrain = terrain_from_document(document, name="gap")
    try:
        plan = plan_path(
            robot,
            np.array([[0.0, goal_y]]),
            HEIGHTS_M["mantis"],
            start_heading=YAW,
            terrain=terrain,
            samples_per_unit=5,
        )
    except Silo4Error as refused:
        assert "gap" in str(refused)
    else:
        assert plan.n_creep_half_cycles > 0
