"""The feasible height range is the longest run of feasible grid heights for every leg family,
and the height check's shortcut (_inside_feasible_run) agrees with it (issue 21).

The control: the 100 N m SILO4 xacro variant (L2 0.3, L3 0.35, Lb 0.25 m). With the layout's
feet lifted by the plans' 5 cm swing (planner/workspace/foothold_layout.py swing_height_m) its
grid's lowest height, 0.2 m, plans with a stride cut to 0.44 m, but from 0.204 m the longer
stride's creeping stance brings the tibias within 9.2 mm of the ground (holes at 0.204-0.205
and 0.207-0.210 m): the first run was the sliver [0.2, 0.2035] m, and the test of its walk at
0.4 m (tests/test_sim_walks.py) was refused.
"""

from __future__ import annotations

import numpy as np
import pytest

import planner.workspace.heights as heights
from planner.model import planning_robot
from silo4kin import load_robot


@pytest.fixture(scope="module")
def silo4():  # noqa: ANN201
    return planning_robot(load_robot())


def test_the_100_nm_variant_range_is_its_long_run_not_the_low_sliver():
    robot = load_robot(xacro_args={"L2": 0.3, "L3": 0.35, "Lb": 0.25, "joint_effort": 100.0})
    lo, hi = heights.feasible_height_range(robot)
    assert heights._height_ok(planning_robot(robot), 0.2, "default")  # the sliver plans
    assert lo > 0.21 and hi > 0.77  # measured [0.211, 0.7777] m
    assert not heights._inside_feasible_run(planning_robot(robot), 0.201, "default")
    assert heights._inside_feasible_run(planning_robot(robot), 0.4, "default")


def _fake_ok(runs: list[tuple[float, float]]):  # noqa: ANN202
    def ok(robot, height: float, preset: str, clear_stance: bool = True) -> bool:  # noqa: ANN001
        return any(a <= height <= b for a, b in runs)

    return ok


def test_the_shortcut_says_true_only_inside_the_longest_run(silo4, monkeypatch):
    """Random feasible sets (1-4 runs of heights over SILO4's grid): the range is the longest
    grid run, and _inside_feasible_run is True only inside the range; where the grid after
    the range's run is too short to hold a longer one, True for every grid height of the
    run past its first (the run is then known to be the range's without reading on)."""
    lowest, highest, grid = heights._height_grid(silo4, "default")

    def whole(robot, preset):  # noqa: ANN001, ANN202 (the range computed, not memoised)
        return heights._feasible_height_range.__wrapped__(robot, preset, True, False)

    rng = np.random.default_rng(21)
    for _ in range(60):
        ends = np.sort(rng.uniform(lowest - 0.02, highest, 2 * int(rng.integers(1, 5))))
        runs = list(zip(ends[::2], ends[1::2]))
        monkeypatch.setattr(heights, "_height_ok", _fake_ok(runs))
        on_grid = np.array([any(a <= h <= b for a, b in runs) for h in grid])
        if not on_grid.any():
            continue
        lo, hi = whole(silo4, "default")
        first, last = heights._longest_run(on_grid)
        assert grid[first] - 0.01 <= lo <= grid[first] + 1e-4 and grid[last] - 1e-4 <= hi
        probes = np.concatenate([np.linspace(lowest - 0.01, highest + 0.01, 49), grid])
        for h in probes:
            if heights._inside_feasible_run(silo4, float(h), "default"):
                assert lo <= h <= hi, (runs, h, lo, hi)
        if last - first + 1 < grid.size - last - 2:
            continue
        for h in grid[first + 1 : last + 1]:
            assert heights._inside_feasible_run(silo4, float(h) - 1e-6, "default"), (runs, h)


def test_a_low_sliver_does_not_make_the_range(silo4, monkeypatch):
    """A sliver on the grid's lowest height, a hole, then a long run: the long run (the
    first-run rule returned the sliver)."""
    lowest, highest, _ = heights._height_grid(silo4, "default")
    runs = [(lowest, lowest + 0.0035), (lowest + 0.011, highest - 0.05)]
    monkeypatch.setattr(heights, "_height_ok", _fake_ok(runs))
    lo, hi = heights._feasible_height_range.__wrapped__(silo4, "default", True, False)
    assert abs(lo - (lowest + 0.011)) < 1e-4 and abs(hi - (highest - 0.05)) < 1e-4
    assert not heights._inside_feasible_run(silo4, lowest + 0.001, "default")
    assert heights._inside_feasible_run(silo4, lowest + 0.1, "default")
