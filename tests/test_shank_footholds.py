"""The foothold search on surfaces knows the shank (planner/gaits/shank_clearance.py): a
candidate keeps its leg's tibia capsule, the one the physics replay collides and the run
checks, MIN_TIBIA_CLEARANCE_M + TIBIA_SEARCH_MARGIN_M off the terrain at touch-down and over
the body step that follows. Checked on go2 stepping down off bench_capability.py's blocks
(h 0.28 m), where the shank leans back from the foot over the block's far edge: before, the
0.07 m block's LH capsule came -6.7 mm (into the block) and the run refused every block from
0.06 m up."""

from __future__ import annotations

import numpy as np
import pytest

from planner.terrain.capsule_distance import capsule_clearance, capsule_clears
from planner.terrain.heightmap import HeightMap
from planner.terrain.shapes import Box, Cylinder
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.clearance import MIN_TIBIA_CLEARANCE_M

#: bench_capability.py's block for go2 at h 0.28 m (its centre y and footprint), the goal.
BLOCK_CENTER_Y_M, BLOCK_SIZE_XY_M, GOAL_Y_M = 0.71222, (0.917, 0.4602), 1.3522
#: LH's step down off the 0.077 m block (the builder's pose before it: the base, heading
#: +y, the feet, the last body step), and a nominal foothold 0.109 m past the far edge.
BASE = np.array([0.0, 1.074, 0.318])
YAW = np.pi / 2
MOTION_XY = np.array([0.0, 0.153])
NOMINAL_XY = np.array([-0.199, 1.051])
LH = 2


def _block(rise_m: float):
    from planner.terrain import terrain_from_document

    box = {
        "center": [0.0, BLOCK_CENTER_Y_M, rise_m / 2],
        "size": [*BLOCK_SIZE_XY_M, rise_m],
    }
    return terrain_from_document({"floor": 0.0, "boxes": [box]}, name=f"block {rise_m} m")


@pytest.fixture(scope="module")
def go2(go2):
    """The planning model of the session's go2 (tests/conftest.py)."""
    from planner.model import planning_model

    return planning_model(go2)


def test_capsule_clears_answers_as_capsule_clearance():
    """The pruned yes/no measure is the full measure compared with the threshold, on random
    capsules over a floor, a height map, boxes and cylinders."""
    rng = np.random.default_rng(7)
    heights = rng.uniform(0.0, 0.03, size=(12, 16))
    terrain = TerrainMap(
        floor_z=0.0,
        heightmap=HeightMap(heights, 0.05, np.array([-0.4, -0.3]), base_z=0.0),
        boxes=(Box(np.array([0.3, 0.2, 0.04]), np.array([0.2, 0.3, 0.08])),),
        cylinders=(Cylinder(np.array([-0.2, 0.1, 0.05]), 0.06, 0.1),),
    )
    start = rng.uniform([-0.5, -0.4, 0.0], [0.5, 0.5, 0.2], size=(1000, 3))
    end = start + rng.normal(0.0, 0.1, size=(1000, 3))
    for threshold in (0.003, 0.02):
        clearance = capsule_clearance(terrain, start, end, 0.015)
        clears = capsule_clears(terrain, start, end, 0.015, threshold)
        assert np.array_equal(clears, clearance >= threshold)
        assert clears.any() and (~clears).any()


def test_no_shank_check_on_a_level_floor(go2):
    """The search asks the capsule only where the run measures it (a terrain with obstacles),
    so plans on a level floor stay as they were."""
    from planner.gaits.shank_clearance import shank_clearance_for

    legs = go2.planning_robot.legs
    assert shank_clearance_for(go2.robot, legs, TerrainMap(floor_z=0.0)) is None
    assert shank_clearance_for(go2.robot, legs, None) is None
    assert shank_clearance_for(go2.robot, legs, _block(0.05)) is not None


def test_a_foothold_past_an_edge_moves_on_until_the_shank_clears(go2):
    """LH steps down off a 0.077 m block. Without the shank the nominal point is valid and its
    capsule lies in the block (-6 mm); at touch-down alone the search moves it 15 mm out and
    10 mm on (4.6 mm at touch-down, 1.0 mm into the body step, measured densely here); with
    the stance 5 mm farther on, clear over the whole body step."""
    from planner.gaits.shank_clearance import SHANK_SEARCH_CLEARANCE_M, shank_clearance_for
    from planner.gaits.surface_footholds import surface_footholds_for
    from silo4kin.foot_contact import foot_ball

    rise = 0.077
    terrain = _block(rise)
    legs = go2.planning_robot.legs
    offset = foot_ball(go2.planning_robot).contact_offset_m
    shank = shank_clearance_for(go2.robot, legs, terrain)
    plain = surface_footholds_for(terrain, legs, 0.28, 0.5, offset)
    held = surface_footholds_for(terrain, legs, 0.28, 0.5, offset, shank)
    feet = np.array(
        [
            [-0.159, 1.096, offset],
            [0.158, 1.249, offset],
            [-0.159, 0.709, rise + offset],
            [0.153, 0.832, rise + offset],
        ]
    )
    nominal = np.array([*NOMINAL_XY, offset])

    def stance(point: np.ndarray) -> np.ndarray:
        """The capsule's clearance [m] at 41 poses along the body step after touch-down."""
        end = np.array(
            [*(BASE[:2] + MOTION_XY), plain.body_z(np.vstack([point, *feet[[0, 1, 3]]]))]
        )
        f = np.linspace(0.0, 1.0, 41)[:, None]
        bases = BASE + f * (end - BASE)
        return shank.clearance(LH, np.tile(point, (len(f), 1)), bases, YAW)

    nearest = plain.place(LH, nominal, BASE, YAW, feet)
    assert np.allclose(nearest, nominal)
    assert shank.clearance(LH, nearest[None], BASE, YAW)[0] < 0.0
    touchdown = held.place(LH, nominal, BASE, YAW, feet)
    assert shank.clearance(LH, touchdown[None], BASE, YAW)[0] >= SHANK_SEARCH_CLEARANCE_M
    assert stance(touchdown).min() < MIN_TIBIA_CLEARANCE_M  # the body step lowers the knee
    placed = held.place(LH, nominal, BASE, YAW, feet, MOTION_XY)
    assert placed[1] > touchdown[1] > nominal[1]  # farther past the edge
    assert np.isfinite(stance(placed)).all()
    assert stance(placed).min() >= MIN_TIBIA_CLEARANCE_M


@pytest.mark.parametrize("rise_m", [0.06, 0.07])
def test_go2_steps_off_a_block_with_every_tibia_capsule_clear(go2, rise_m):
    """The walk over bench_capability.py's block plans with every capsule at least
    MIN_TIBIA_CLEARANCE_M off the terrain at every sample (measured on the trajectory, as the
    run does): before, the LH capsule came -0.3 mm (0.06 m) and -6.7 mm (0.07 m)."""
    from planner import plan_path
    from planner.trajectory.tibia_capsules import tibia_capsule_clearance

    terrain = _block(rise_m)
    plan = plan_path(
        go2.robot,
        np.array([[0.0, GOAL_Y_M]]),
        0.28,
        start_heading=np.pi / 2,
        terrain=terrain,
        samples_per_unit=5,
    )
    clearance = tibia_capsule_clearance(go2.robot, plan.trajectory, terrain)
    assert clearance.min() >= MIN_TIBIA_CLEARANCE_M
    lh_on_floor = plan.trajectory.contact[:, LH] & (
        plan.trajectory.position_foot_in_world[:, LH, 1] > BLOCK_CENTER_Y_M + BLOCK_SIZE_XY_M[1] / 2
    )
    assert lh_on_floor.any()  # it stepped down past the far edge
