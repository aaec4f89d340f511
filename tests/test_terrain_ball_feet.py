"""Ball feet on a terrain file: the step builder's feet are foot frames, which stand the
ball's contact offset above the ground (silo4kin/foot_contact.py), so a foothold placed on a
surface, the start stance and the body height add it; the contact points the trajectory
carries then lie on the surfaces. Checked on go2 (a 22.9 mm contact offset) over a low block,
from the terrain geometry alone: before, the start feet's frames were put on the ground and
the contact points 22.9 mm under it, and every go2 plan on a terrain was refused."""

from __future__ import annotations

import numpy as np
import pytest

BLOCK_TOP_M = 0.007


@pytest.fixture(scope="module")
def go2_on_block(go2):
    from planner import plan_path
    from planner.terrain import terrain_from_document
    from silo4kin.foot_contact import foot_contact_offset_m

    robot = go2
    assert foot_contact_offset_m(robot) > 0.02  # a ball foot: the case this file is about
    document = {
        "floor": 0.0,
        "boxes": [{"center": [0.0, 1.5, BLOCK_TOP_M / 2], "size": [1.2, 0.6, BLOCK_TOP_M]}],
    }
    terrain = terrain_from_document(document, name="low block")
    plan = plan_path(robot, np.array([[0.0, 3.0]]), 0.3, start_heading=np.pi / 2, terrain=terrain)
    return plan


def _ground(xy: np.ndarray) -> np.ndarray:
    on_block = (np.abs(xy[:, 0]) <= 0.6) & (np.abs(xy[:, 1] - 1.5) <= 0.3)
    return np.where(on_block, BLOCK_TOP_M, 0.0)


def test_every_stance_contact_point_of_go2_lies_on_the_ground_under_it(go2_on_block):
    trajectory = go2_on_block.trajectory
    feet = trajectory.position_foot_in_world  # contact points (N, 4, 3)
    stance = feet[trajectory.contact]
    assert len(stance) > 0
    assert np.abs(stance[:, 2] - _ground(stance[:, :2])).max() < 1e-3
    on_block = np.isclose(_ground(stance[:, :2]), BLOCK_TOP_M)
    assert on_block.any() and (~on_block).any()  # it stepped onto the block and off it


def test_go2_body_stands_its_height_over_the_stance_contact_points(go2_on_block):
    trajectory = go2_on_block.trajectory
    first = trajectory.position_foot_in_world[0]
    base_z = trajectory.position_base_in_world[0, 2]
    assert base_z == pytest.approx(np.mean(first[:, 2]) + 0.3, abs=1e-9)
