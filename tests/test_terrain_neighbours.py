"""The foothold search keeps clear of the other feet, and a step rise beyond the legs is
refused naming the terrain (planner/gaits/surface_footholds.py; docs/terrain.md, "Walking a
terrain")."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from benchmark_scripts import load_benchmark

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples" / "terrain"


def test_a_hind_foot_never_lands_within_the_clearance_of_another_foot(silo4):
    """On the stones field, LH's nominal foothold is the middle of the post (radius 0.08 m)
    LF stands on 0.03 m ahead of it: the search alone would keep it there; given the feet it
    moves at least the interference clearance from every other foot, still on a valid
    surface."""
    from planner.gaits.surface_footholds import SurfaceFootholds
    from planner.model import as_planning_model
    from planner.terrain import load_terrain
    from planner.workspace.interference import LEG_CLEARANCE_M

    terrain = load_terrain(EXAMPLES / "stones.yaml")
    search = SurfaceFootholds(terrain, tuple(as_planning_model(silo4).planning_robot.legs), 0.4)
    base = np.array([0.0, 1.25, 0.4])
    feet = np.array([[-0.3, 1.03, 0.0], [0.3, 1.5, 0.0], [-0.3, 0.75, 0.0], [0.3, 1.0, 0.0]])
    nominal = np.array([-0.3, 1.0, 0.0])
    alone = search.place(2, nominal, base, np.pi / 2)
    np.testing.assert_allclose(alone, nominal, atol=1e-12)  # valid, were LF not on it
    moved = search.place(2, nominal, base, np.pi / 2, feet)
    others = np.delete(feet, 2, axis=0)
    assert np.min(np.linalg.norm(others - moved, axis=1)) >= LEG_CLEARANCE_M
    ok, z = search.valid(moved[:2].reshape(1, 2))
    assert ok[0] and z[0] == pytest.approx(moved[2], abs=1e-12)


def _capability():
    return load_benchmark("bench_capability")


@pytest.mark.parametrize(
    ("rise_m", "why"),
    [
        (0.2, "out of reach"),  # the body over the stance feet leaves a hind foot on the floor
        # LF stepping down off it: the point nearest its nominal foothold puts its shank on
        # the edge, and the search (0.2 m around it) finds one farther that clears the edge
        # but leaves the stance out of reach (with a 0.12 m search: refused for the capsule;
        # the capsule's refusal: tests/test_terrain_walk.py, a 0.4 m block)
        (0.16, "out of reach"),
    ],
)
def test_silo4_refuses_a_block_beyond_its_legs_naming_it(silo4, rise_m, why):
    """SILO4 at h = 0.4 m on the capability benchmark's block: refused in one line that
    names the terrain file, the block and the reason: the foot out of reach (0.2 m, and 0.16 m
    where the search moves the foot stepping down off the block clear of its edge). The
    0.14 m block this test refused before for reach now plans and walks: the foothold search
    moves LF clear of the edge it steps past (docs/terrain.md, Capability)."""
    from planner.errors import FootholdRefused
    from planner.path.plan_path import plan_path
    from planner.terrain import terrain_from_document

    bench = _capability()
    layout = bench.layout_for(silo4, 0.4)
    document, goal = bench.OBSTACLES["block"].scenario(layout, rise_m)
    terrain = terrain_from_document(document, name="blockN")
    with pytest.raises(FootholdRefused) as info:
        plan_path(
            silo4,
            np.array([[0.0, goal]]),
            0.4,
            samples_per_unit=2,
            start_heading=math.pi / 2,
            terrain=terrain,
        )
    message = str(info.value)
    assert "terrain file blockN" in message and "\n" not in message
    assert "box 0" in message and why in message
