"""The random-terrain benchmark (benchmarks/bench_terrain.py), a 3-case subset: SILO4 at
h = 0.4 m on the seeded benchmark's first stone field over a void, its first on a floor and
its first height map. All three plan and walk in `silo4 simulate`'s default replay (they
did when the test was last measured: docs/terrain.md, "Benchmark").
"""

from __future__ import annotations

import numpy as np
import pytest
from benchmark_scripts import load_benchmark

pytest.importorskip("mujoco")


def _bench():
    return load_benchmark("bench_terrain")


@pytest.fixture(scope="module")
def cases(silo4):
    bench = _bench()
    layouts = {"silo4": bench.layout_for(silo4, bench.HEIGHTS_M["silo4"])}
    return bench, bench.terrain_cases(3, bench.DEFAULT_SEED, ["silo4"], layouts)


def test_the_fields_hold_the_feet_at_the_start_and_at_the_goal(cases):
    """A stone field's start platform is under the four standing feet and its end platform
    under them at the goal (tops at z = 0); the stones are posts between the two; a height
    map lies on the floor (heights >= 0)."""
    from planner.terrain import terrain_from_document

    bench, made = cases
    layout_feet = np.array([[-0.312, 0.312], [0.312, 0.312], [-0.312, -0.312], [0.312, -0.312]])
    for case in made[:2]:
        terrain = terrain_from_document(case.field.document)
        at_goal = layout_feet + [0.0, case.field.goal_y_m]
        np.testing.assert_allclose(terrain.height_at(layout_feet), 0.0, atol=1e-12)
        np.testing.assert_allclose(terrain.height_at(at_goal), 0.0, atol=1e-12)
        posts_y = [c["center"][1] for c in case.field.document["cylinders"]]
        assert 0.312 < min(posts_y) and max(posts_y) < case.field.goal_y_m - 0.312
    heights = np.array(made[2].field.document["heightmap"]["heights"])
    assert made[2].field.kind == bench.FIELDS[2] and heights.min() >= 0.0 < heights.max()


def test_the_subset_plans_and_walks(cases, silo4):
    """The stone fields and the height map plan and walk."""
    bench, made = cases
    kinds = [case.field.kind for case in made]
    assert kinds == list(bench.FIELDS)
    for case in made:
        outcome = bench.run_case(silo4, case)
        assert outcome.planned and outcome.walks, (case.describe(), outcome.reasons)
        assert outcome.transfers > 0 and outcome.plan_s > 0
