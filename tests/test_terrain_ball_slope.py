"""Ball feet on a ramp: a ball of radius r resting on a plane of unit normal n touches it at
centre - r n (planner/gaits/ball_stance.py), and rolls along the plane while its link turns
(planner/trajectory/rolling_feet.py: v = r ω × n).

The references are independent of the planner: the ramp's plane from the terrain document's
geometry (a plank rolled ``RAMP_DEG`` about x, its top's lower edge on the floor at
``RAMP_START_Y_M``), the ball centres from Pinocchio's forward kinematics of the planned
joints, and MuJoCo's replay for the walk. Before, go2 was refused on every ramp down to
1.25 deg: its contact points stood r straight under the centres, inside the ramp.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np
import pytest
from benchmark_scripts import load_benchmark

RAMP_DEG = 5.0
RAMP_START_Y_M = 0.48
RAMP_LENGTH_M = 1.15
PLANK_THICKNESS_M = 0.02
WIDTH_M = 0.92
HEIGHT_M = 0.28
#: The fixed point of the rolling converges to 1e-12 m; Pinocchio and the closed forms
#: agree to ~1e-13 m (tests/test_round_feet.py).
ON_PLANE_M = 1e-9
#: A go2 stance rolls its ball by millimetres; one that rolls < 1 mm is not rolling.
MIN_ROLL_PER_STANCE_M = 1e-3


def _ramp_document() -> tuple[dict, float]:
    """The ramp, a flat box at its top, and the goal y [m] past it."""
    a, t, length = math.radians(RAMP_DEG), PLANK_THICKNESS_M, RAMP_LENGTH_M
    y0 = RAMP_START_Y_M
    centre = [
        0.0,
        y0 + 0.5 * length * math.cos(a) + 0.5 * t * math.sin(a),
        0.5 * length * math.sin(a) - 0.5 * t * math.cos(a),
    ]
    top_z, y1 = length * math.sin(a), y0 + length * math.cos(a)
    boxes = [
        {"center": centre, "size": [WIDTH_M, length, t], "rpy": [RAMP_DEG, 0.0, 0.0]},
        {"center": [0.0, y1 + 0.6, 0.5 * top_z], "size": [WIDTH_M, 1.2, top_z]},
    ]
    return {"floor": 0.0, "boxes": boxes}, y1 + 0.45


def _plane_normal() -> np.ndarray:
    a = math.radians(RAMP_DEG)
    return np.array([0.0, -math.sin(a), math.cos(a)])


def _distance_to_ramp_plane(points: np.ndarray) -> np.ndarray:
    """Signed distance [m] of points (..., 3) from the plane of the ramp's top."""
    return (points - np.array([0.0, RAMP_START_Y_M, 0.0])) @ _plane_normal()


def _on_ramp(xy: np.ndarray) -> np.ndarray:
    """Points (..., 2) well inside the ramp's top (3 cm from its ends)."""
    a = math.radians(RAMP_DEG)
    along = xy[..., 1] - RAMP_START_Y_M
    return (along > 0.03) & (along < RAMP_LENGTH_M * math.cos(a) - 0.03)


@pytest.fixture(scope="module")
def ramp_terrain():
    from planner.terrain import terrain_from_document

    return terrain_from_document(_ramp_document()[0], name="ramp")


@pytest.fixture(scope="module")
def go2_on_ramp(go2, ramp_terrain):
    from planner import plan_path

    goal = _ramp_document()[1]
    return plan_path(
        go2, np.array([[0.0, goal]]), HEIGHT_M, start_heading=np.pi / 2, terrain=ramp_terrain
    )


def _pinocchio_centres(robot, trajectory) -> tuple[np.ndarray, np.ndarray]:
    """Ball centres (N, 4, 3) [m] in W and the foot links' angular velocities (N, 4, 3)
    [rad/s] in W, by Pinocchio (the body level, turned by its yaw)."""
    import pinocchio as pin

    model, data = robot.model, robot.model.createData()
    q_pin = robot.to_pinocchio_q(trajectory.q)
    v_pin = robot.to_pinocchio_q(trajectory.qd)
    root = robot.position_body_com_in_base
    c, s = np.cos(trajectory.yaw_base_in_world), np.sin(trajectory.yaw_base_in_world)
    n = len(trajectory)
    centres, omegas = np.empty((n, 4, 3)), np.empty((n, 4, 3))
    for j, leg in enumerate(robot.legs):
        fid = model.getFrameId(leg.foot_frame)
        for i in range(n):
            pin.forwardKinematics(model, data, q_pin[i], v_pin[i])
            centres[i, j] = pin.updateFramePlacement(model, data, fid).translation - root
            omegas[i, j] = pin.getFrameVelocity(
                model, data, fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
            ).angular
    rot = np.zeros((n, 3, 3))
    rot[:, 0, 0], rot[:, 0, 1], rot[:, 1, 0], rot[:, 1, 1], rot[:, 2, 2] = c, -s, s, c, 1.0
    centres = trajectory.position_base_in_world[:, None] + np.einsum("nij,nkj->nki", rot, centres)
    return centres, np.einsum("nij,nkj->nki", rot, omegas)


def test_stance_balls_rest_on_the_ramp_and_roll_along_it(go2, go2_on_ramp):
    """On the ramp, every stance ball's centre (Pinocchio) is r from the ramp's plane, the
    planned contact point is the centre - r n and lies on the plane; minus the rolling
    integral of r ω × n (Pinocchio's foot angular velocity), the contact point is the
    touchdown point for the whole stance: the ball rolls on the plane without slipping."""
    from silo4kin.foot_contact import foot_ball

    tr, r = go2_on_ramp.trajectory, foot_ball(go2).rolling_radius_m
    assert np.ptp(tr.yaw_base_in_world) == 0.0  # a straight walk: no body yaw rate to add
    centres, omega = _pinocchio_centres(go2, tr)
    contact_points = tr.position_foot_in_world
    n = _plane_normal()
    dt = tr.t[1] - tr.t[0]
    rolled, checked = 0, 0
    for j in range(4):
        stance = tr.contact[:, j]
        edges = np.flatnonzero(np.diff(np.concatenate([[0], stance.astype(int), [0]])))
        for a, b in zip(edges[::2], edges[1::2]):
            if not np.all(_on_ramp(contact_points[a:b, j, :2])):
                continue
            checked += 1
            centre, contact = centres[a:b, j], contact_points[a:b, j]
            np.testing.assert_allclose(_distance_to_ramp_plane(centre), r, atol=ON_PLANE_M)
            np.testing.assert_allclose(contact, centre - r * n, atol=ON_PLANE_M)
            np.testing.assert_allclose(_distance_to_ramp_plane(contact), 0.0, atol=ON_PLANE_M)
            v = r * np.cross(omega[a:b, j], n)
            d = np.vstack([np.zeros(3), np.cumsum(0.5 * (v[1:] + v[:-1]) * dt, axis=0)])
            np.testing.assert_allclose(contact - d - contact[0], 0.0, atol=ON_PLANE_M)
            rolled += np.linalg.norm(d[-1]) > MIN_ROLL_PER_STANCE_M
    assert checked >= 4 and rolled >= 4, "the feet should stand and roll on the ramp"


def test_foot_frames_stand_r_along_the_normal_and_the_body_h_over_the_contacts(go2, ramp_terrain):
    """A foothold's foot frame is its contact point + r n: r from the ramp's plane, r n_xy
    aside of the contact point; on the floor r straight above it, bit for bit. The body
    stands h above the mean z of the four contact points, foot frames - r n."""
    from planner.gaits.surface_footholds import SurfaceFootholds
    from silo4kin.foot_contact import foot_ball

    r = foot_ball(go2).rolling_radius_m
    search = SurfaceFootholds(ramp_terrain, tuple(go2.legs), HEIGHT_M, foot_offset_m=r)
    xy = np.array([[-0.16, 0.8], [0.16, 0.9], [-0.16, 1.1], [0.16, 0.2]])  # the last: floor
    contact = np.column_stack([xy, ramp_terrain.height_at(xy)])
    np.testing.assert_allclose(_distance_to_ramp_plane(contact[:3]), 0.0, atol=1e-12)
    frames = search.foot_frames(contact)
    np.testing.assert_allclose(_distance_to_ramp_plane(frames[:3]), r, atol=1e-12)
    np.testing.assert_allclose(
        frames[:3] - contact[:3], np.tile(r * _plane_normal(), (3, 1)), atol=1e-12
    )
    assert np.array_equal(frames[3], contact[3] + [0.0, 0.0, r])
    expected = np.mean(contact[:, 2]) + HEIGHT_M
    assert search.body_z(frames) == pytest.approx(expected, abs=1e-12)
    level = frames.copy()
    level[:3] = contact[3] + [0.0, 0.0, r]
    assert search.body_z(level) == float(np.mean(level[:, 2])) - r + HEIGHT_M


def test_the_ball_check_measures_the_ball_not_the_point_under_its_centre(
    go2, go2_on_ramp, ramp_terrain
):
    """The plan keeps every ball out of the terrain (FK centres: Pinocchio's); a stance ball
    on the ramp touches it, its point r straight under the centre r / cos(a) - r above the
    surface; a centre r straight above its contact point (the model of before, which the
    point check passed) puts the ball r (1 - cos a) into the ramp; lowering
    one sample's base by 0.1 mm puts its stance balls 0.1 mm cos(a) into the ramp, which the
    check reports naming the terrain file and the part."""
    from planner.model import planning_robot
    from planner.trajectory.ball_clearance import (
        BELOW_TOLERANCE_M,
        ball_centres_in_world,
        foot_violation,
    )
    from silo4kin.foot_contact import foot_ball

    tr, r = go2_on_ramp.trajectory, foot_ball(go2).rolling_radius_m
    legs = planning_robot(go2).legs  # in B, the body CoG frame the plan's joints are for
    assert foot_violation(legs, tr, ramp_terrain, r) is None
    centres = ball_centres_in_world(legs, tr)
    np.testing.assert_allclose(centres, _pinocchio_centres(go2, tr)[0], atol=1e-9)
    on = tr.contact & _on_ramp(centres[..., :2])
    a = math.radians(RAMP_DEG)
    resting = ramp_terrain.sphere_clearance(centres[on], r)
    np.testing.assert_allclose(resting, 0.0, atol=1e-9)  # touching, not entering
    under = ramp_terrain.lowest_clearance(centres[on] - [0.0, 0.0, r])
    np.testing.assert_allclose(under, r / math.cos(a) - r, atol=1e-9)  # r / cos(a) up
    # the model of before: the centre r straight above the contact point, which the point
    # check passed; the ball then enters the ramp by r (1 - cos a)
    before = tr.position_foot_in_world[on] + [0.0, 0.0, r]
    np.testing.assert_allclose(ramp_terrain.lowest_clearance(before - [0, 0, r]), 0, atol=1e-9)
    entered = ramp_terrain.sphere_clearance(before, r)
    np.testing.assert_allclose(entered, r * math.cos(a) - r, atol=1e-9)
    assert r * math.cos(a) - r < -BELOW_TOLERANCE_M

    i = int(np.flatnonzero(np.all(on | ~tr.contact, axis=1) & on.any(axis=1))[0])
    base = tr.position_base_in_world.copy()
    base[i, 2] -= 1e-4
    reason = foot_violation(legs, replace(tr, position_base_in_world=base), ramp_terrain, r)
    assert reason is not None and reason.startswith("terrain file ramp: ")
    assert "over box 0" in reason  # the plank
    depth_mm = float(re.search(r"is ([0-9.e-]+) mm inside", reason).group(1))
    assert depth_mm == pytest.approx(0.1 * math.cos(math.radians(RAMP_DEG)), rel=1e-3)


def _bench():
    return load_benchmark("bench_terrain")


def test_go2_walks_the_ramp_in_physics(go2):
    """The plan walks in `silo4 simulate`'s default replay on the same terrain (MuJoCo)."""
    pytest.importorskip("mujoco")
    document, goal = _ramp_document()
    planned, walks, _, _, reasons = _bench().plan_and_walk(
        go2, np.array([[0.0, goal]]), HEIGHT_M, document
    )
    assert planned and walks, reasons
