"""A ball foot's roll over a stance (planner/gaits/stance_roll.py) and the foothold rules held
along it (planner/gaits/surface_footholds.py ``roll_m``).

- The bound r ∫|ω_h| over a leg's stroke equals r times the angle between the foot link's
  orientations at the stroke's two ends, read from Pinocchio's forward kinematics of the
  URDF (go2's pitch joints are parallel and turn one way along the stroke, so the integral
  of |ω| is that angle); a point foot (SILO4) does not roll.
- On a forbidden strip a foothold whose contact point would roll into it (the body moving
  towards the strip) moves back until the point it rolls to keeps the clearance too.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner.gaits.stance_roll import STROKE_SAMPLES, stance_roll_bound_m
from planner.gaits.surface_footholds import SurfaceFootholds
from planner.model import planning_model
from planner.terrain import terrain_from_document
from planner.workspace.foothold_layout import SHIFT_RESERVE_M
from planner.workspace.layout import workspace_for
from silo4kin.foot_contact import foot_ball
from silo4kin.legs import joint_motion


@pytest.fixture(scope="module")
def go2(go2):
    """(robot, planning model, workspace at 0.28 m) of the session's go2 (tests/conftest.py)."""
    return go2, planning_model(go2), workspace_for(go2, 0.28)


def _foot_rotation(robot, leg_index: int, q_leg: np.ndarray) -> np.ndarray:
    """The foot frame's rotation in the URDF root, Pinocchio's FK, the other legs at 0."""
    q = np.zeros(12)
    q[3 * leg_index : 3 * leg_index + 3] = q_leg
    model = robot.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, robot.to_pinocchio_q(q))
    return data.oMf[model.getFrameId(robot.legs[leg_index].foot_frame)].rotation.copy()


def test_the_roll_bound_is_the_ball_radius_times_the_foot_link_turn(go2):
    robot, model, ws = go2
    legs = model.planning_robot.legs
    radius = foot_ball(model.planning_robot).rolling_radius_m
    stroke = ws.stride_m + 2.0 * SHIFT_RESERVE_M
    turns = []
    for k, leg in enumerate(legs):
        ends = np.tile(ws.position_mid_in_base[k], (2, 1))
        ends[:, 0] += np.array([-0.5, 0.5]) * stroke
        q = joint_motion(leg, ends, np.zeros((2, 3)), np.zeros((2, 3)))[0]
        r0, r1 = (_foot_rotation(robot, k, q[i]) for i in range(2))
        turns.append(np.linalg.norm(pin.log3(r0.T @ r1)))
    assert ws.stride_lateral_m == 0.0  # go2 at 0.28 m strides along x only
    bound = stance_roll_bound_m(legs, ws, radius)
    assert bound == pytest.approx(radius * max(turns), rel=2.0 / STROKE_SAMPLES)
    assert 0.02 < bound < 0.04  # ~23 mm rolled per stance was measured on its plans
    assert stance_roll_bound_m(legs, ws, 0.0) == 0.0


def test_a_foothold_keeps_the_forbidden_clearance_where_its_ball_rolls_to(go2):
    _, model, ws = go2
    terrain = terrain_from_document(
        {"floor": 0.0, "forbidden": [[[-5, 1.5], [5, 1.5], [5, 1.65], [-5, 1.65]]]}
    )
    legs = tuple(model.planning_robot.legs)
    base = np.array([-0.17, 1.30, 0.28])  # facing +x, the front left foot near y = 1.5
    nominal = base + np.array([0.17, 0.16 + 0.02, -0.28])  # 2 cm before the strip's 1 cm
    nominal[1] = 1.5 - 0.012
    toward = np.array([0.0, 0.1])  # the body moves towards the strip over the stance
    plain = SurfaceFootholds(terrain, legs, 0.28)
    rolling = SurfaceFootholds(terrain, legs, 0.28, roll_m=0.025)
    kept = plain.place(0, nominal, base, 0.0, stance_motion_xy=toward)
    moved = rolling.place(0, nominal, base, 0.0, stance_motion_xy=toward)
    assert kept[1] == pytest.approx(nominal[1])  # valid where it touches down
    clearance = terrain.forbidden_clearance_m
    assert 1.5 - (moved[1] + 0.025) >= clearance - 1e-9  # and where it rolls to
    assert 1.5 - (moved[1] + 0.025) <= clearance + 0.006  # the nearest such point (5 mm grid)
    away = rolling.place(0, nominal, base, 0.0, stance_motion_xy=-toward)
    assert away[1] == pytest.approx(nominal[1])  # rolling away from the strip: unchanged
