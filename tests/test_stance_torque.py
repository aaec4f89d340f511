"""The foothold search on surfaces weighs the static torque of the stances a candidate makes
(planner/gaits/stance_torque.py), and the facing gait shortens a half cycle the terrain
refuses (planner/gaits/facing.py creep_on_surfaces).

Before: go2 (h 0.28 m) on examples/terrain/block.yaml and gap.yaml, and its scaled block and
0.15 m gap, were refused: a hind thigh needing 22.03 N m standing still (budget 20.14) on a
foothold the search had moved onto the block's edge ahead of the hip, or a stance foot left
out of reach after a foothold moved back from the gap's edge. Both walk in physics now
(tests/test_terrain_scenarios.py with SILO4_HEAVY=1)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.gaits.stance_torque import StanceTorque, supports_with
from planner.terrain.terrain_map import TerrainMap

H_M = 0.28
YAW = math.pi / 2
RH = 3


@pytest.fixture(scope="module")
def go2(go2):
    """The planning model of the session's go2 (tests/conftest.py)."""
    from planner.model import planning_model

    return planning_model(go2)


@pytest.fixture(scope="module")
def go2_walk(go2):
    """A default plan of go2 on flat ground, heading +y (the terrain scenarios' heading)."""
    from planner import plan_path

    return plan_path(go2.robot, np.array([[0.0, 0.9]]), H_M, start_heading=YAW, samples_per_unit=10)


def test_supports_are_all_feet_and_each_triangle_holding_the_leg():
    rows = supports_with(RH)
    assert rows.shape == (4, 4)
    assert rows[0].all()
    assert all(r[RH] and r.sum() == 3 for r in rows[1:])
    assert len({tuple(r) for r in rows[1:]}) == 3


def test_the_stance_torques_are_the_run_checks_at_rest(go2, go2_walk):
    """At three-foot samples of a real plan, the candidate's stance torques for the support
    the plan stands on equal the run's static torques (planner/trajectory/torques.py, the
    plan at rest, the whole robot carried, no load transfer) to 1e-6 N m: same IK, same
    reactions; the triangles the whole-robot CoM leaves are marked unused."""

    from planner.trajectory.limits import at_rest, urdf_limits
    from planner.trajectory.torques import trajectory_torques
    from silo4kin.frames import rotation_z
    from silo4kin.legs import forward_kinematics

    trajectory = go2_walk.trajectory
    tau_run = trajectory_torques(go2.robot, at_rest(trajectory), load="total", transfer_s=0.0).total
    three = np.flatnonzero(trajectory.contact.sum(axis=1) == 3)
    assert three.size > 100
    _, effort = urdf_limits(go2.robot)
    torque = StanceTorque(go2.robot, tuple(go2.planning_robot.legs), effort, "total")
    for i in three[:: max(1, three.size // 12)]:
        contact = trajectory.contact[i]
        leg = int(np.flatnonzero(contact)[0])
        q = trajectory.q[i].reshape(4, 3)
        feet = trajectory.position_base_in_world[i] + np.array(
            [
                rotation_z(float(trajectory.yaw_base_in_world[i])) @ forward_kinematics(g, q[k])
                for k, g in enumerate(go2.planning_robot.legs)
            ]
        )  # the foot frames, from the plan's own joints
        tau, used = torque.torques(
            leg,
            feet[leg][None],
            trajectory.position_base_in_world[i][None, None],
            float(trajectory.yaw_base_in_world[i]),
            feet,
        )
        row = int(np.flatnonzero((supports_with(leg) == contact).all(axis=1))[0])
        assert used[0, 0, row]  # the plan stands on it: the CoM is inside
        assert np.allclose(tau[0, 0, row], tau_run[i], atol=1e-6)


def _standing(go2):
    """(base (3,), feet (4, 3) foot frames) [m] of go2's start stance on a level floor."""
    from planner.gaits.ball_stance import foot_frames_on_surface
    from planner.gaits.creep_spin import creep_stance_in_base
    from planner.workspace.layout import workspace_for
    from silo4kin.foot_contact import foot_ball
    from silo4kin.frames import rotation_z

    robot = go2.planning_robot
    ws = workspace_for(robot, H_M, "default")
    base = np.array([0.0, 0.0, H_M])
    feet = base + (rotation_z(YAW) @ creep_stance_in_base(ws, "+x", 0).T).T
    feet[:, 2] = 0.0
    offset = foot_ball(robot).contact_offset_m
    return base, foot_frames_on_surface(TerrainMap(floor_z=0.0), feet, offset), offset


def test_the_search_takes_the_nearest_foothold_within_the_budget(go2):
    """RH's nominal foothold a stride ahead lies in a forbidden square, so the search moves
    it; the nearest valid point needs more than a budget set just under its own worst stance
    torque. The search then takes the nearest candidate whose stances keep the budget (every
    nearer valid, reachable candidate breaks it); with a budget nothing keeps, the nearest
    valid point (the run's check decides); without the preference, the nearest valid point;
    and a valid nominal foothold is taken as it is, whatever the budget."""
    from planner.gaits.search_offsets import disc_offsets
    from planner.gaits.surface_footholds import SEARCH_STEP_M, SurfaceFootholds
    from planner.terrain import terrain_from_document
    from planner.trajectory.limits import urdf_limits
    from planner.workspace.reach_check import reachable_in_limits_of_legs
    from silo4kin.frames import rotation_z

    base, feet, offset = _standing(go2)
    legs = tuple(go2.planning_robot.legs)
    _, effort = urdf_limits(go2.robot)
    nominal = feet[RH] + np.array([0.0, 0.08, 0.0])  # a stride ahead: a long lever
    x, y, r = nominal[0], nominal[1], 0.02
    square = [[x - r, y - r], [x + r, y - r], [x + r, y + r], [x - r, y + r]]
    ground = terrain_from_document({"floor": 0.0, "forbidden": [square]}, name="square")

    def search(torque, terrain=ground):
        return SurfaceFootholds(terrain, legs, H_M, foot_offset_m=offset, torque=torque)

    nearest = search(None).place(RH, nominal, base, YAW, feet)
    assert np.hypot(*(nearest - nominal)[:2]) > r
    loose = StanceTorque(go2.robot, legs, effort * 10.0, "total")
    tau, used = loose.torques(RH, nearest[None], base[None, None], YAW, feet)
    worst = np.nanmax(np.where(used[..., None], np.abs(tau), 0.0), axis=(0, 1, 2))
    joint = int(np.argmax(worst[3 * RH : 3 * RH + 3])) + 3 * RH
    budget = effort * 10.0
    budget[joint] = worst[joint] - 0.5
    tight = StanceTorque(go2.robot, legs, budget, "total")

    placed = search(tight).place(RH, nominal, base, YAW, feet)
    assert np.hypot(*(placed - nominal)[:2]) > np.hypot(*(nearest - nominal)[:2])
    assert tight.keeps(RH, placed[None], base[None, None], YAW, feet)[0]
    moved = np.hypot(*(placed - nominal)[:2])
    candidates = nominal[:2] + disc_offsets(SEARCH_STEP_M, 0.2)
    ok, z = search(None).valid(candidates)
    nearer = ok & (np.hypot(*(candidates - nominal[:2]).T) < moved - 1e-9)
    points = np.column_stack([candidates[nearer], z[nearer] + offset])
    reach = reachable_in_limits_of_legs(
        legs, np.full(len(points), RH), (points - base) @ rotation_z(YAW)
    )
    assert reach.sum() > 0  # the nearer candidates the preference passed over
    bases = np.tile(base, (int(reach.sum()), 1, 1))
    assert not tight.keeps(RH, points[reach], bases, YAW, feet).any()
    nothing = StanceTorque(go2.robot, legs, effort * 1e-3, "total")
    assert np.allclose(search(nothing).place(RH, nominal, base, YAW, feet), nearest)
    floor = TerrainMap(floor_z=0.0)
    assert np.allclose(search(nothing, floor).place(RH, nominal, base, YAW, feet), nominal)


def test_the_next_swing_is_the_one_after_the_legs_last(go2):
    """StepBuilder.next_swing_leg reads the gait's swing order from its steps: the leg that
    swung right after the given leg's last swing; None before that is known."""
    from planner.gaits.builder import StepBuilder

    base, feet, _ = _standing(go2)
    b = StepBuilder(base, YAW, feet, 0.03)
    assert b.next_swing_leg(RH) is None
    for leg in (3, 1, 2, 0, 3):  # RH, RF, LH, LF, RH
        b.append_step("transfer", leg, 1.0, b.base, b.yaw, b.feet[leg], "t", "creep")
    assert b.next_swing_leg(RH) == 1
    assert b.next_swing_leg(1) == 2
    assert b.next_swing_leg(0) == 3
    assert supports_with(RH, swinging=1).tolist() == [
        [True, True, True, True],
        [True, False, True, True],
    ]


def test_silo4_crosses_a_wider_gap_by_shortening_a_half_cycle(monkeypatch):
    """SILO4 at h 0.4 m before a 0.3 m gap with no floor (platforms ending at y = 1.4 m): the
    half cycles of λ/2 leave a foothold the search cannot place, and the plan is refused;
    the facing gait's shortened half cycles cross it (more half cycles than λ/2 steps)."""
    import planner.gaits.facing as facing
    from planner import plan_path
    from planner.errors import FootholdRefused
    from planner.terrain import terrain_from_document
    from silo4kin import load_robot

    robot = load_robot()
    near_end, width = 1.4, 0.3
    boxes = [
        {"center": [0.0, near_end - 1.75, -0.25], "size": [2.0, 3.5, 0.5]},
        {"center": [0.0, near_end + width + 1.75, -0.25], "size": [2.0, 3.5, 0.5]},
    ]
    terrain = terrain_from_document({"floor": None, "boxes": boxes}, name="gap 0.3 m")
    goal = np.array([[0.0, 3.0]])

    def plan():
        return plan_path(robot, goal, 0.4, start_heading=YAW, terrain=terrain, samples_per_unit=5)

    crossed = plan()
    assert crossed.gait == "facing"
    half = crossed.workspace.stride_m / 2.0
    assert crossed.n_creep_half_cycles > math.ceil(3.0 / half)
    feet = crossed.trajectory.position_foot_in_world
    stance = crossed.trajectory.contact
    in_gap = (feet[..., 1] > near_end) & (feet[..., 1] < near_end + width)
    assert not np.any(in_gap & stance)
    monkeypatch.setattr(facing, "SHORTER_STEP_FRACTIONS", ())
    with pytest.raises(FootholdRefused):
        plan()
