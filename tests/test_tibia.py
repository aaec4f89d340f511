"""The tibia capsule's clearance above the ground (planner/trajectory/clearance.py): closed form
against Pinocchio's frame placements, the constants against the physics model, and the crawl keeping
it on a sweep of directions and heights."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest

from planner import plan_path
from planner.errors import PlanningError
from planner.trajectory.clearance import (
    MIN_TIBIA_CLEARANCE_M,
    TIBIA_FOOT_GAP_M,
    tibia_clearance,
    tibia_low,
    tibia_violation,
)
from planner.trajectory.verify import verify_samples
from silo4sim.settings import SimSettings
from silo4sim.urdf_collisions import prepare_urdf

#: closed form vs Pinocchio: the same lengths, float round-off only [m]
FK_TOL_M = 1e-12


def test_clearance_matches_pinocchio_frame_placements(silo4):
    """The lowest point of each capsule (knee joint placement to TIBIA_FOOT_GAP_M short of
    the foot frame, minus the radius) from Pinocchio equals the closed form, level body."""
    rng = np.random.default_rng(7)
    n = 200
    lower = np.concatenate([leg.q_lower for leg in silo4.legs])
    upper = np.concatenate([leg.q_upper for leg in silo4.legs])
    q = rng.uniform(lower, upper, size=(n, 12))
    height = rng.uniform(0.1, 0.7, size=n)
    model = silo4.model_free_flyer
    data = model.createData()
    expected = np.empty((n, 4))
    for i in range(n):
        q_ff = np.r_[0.3, -0.2, height[i], 0, 0, 0, 1, silo4.to_pinocchio_q(q[i])]
        pin.forwardKinematics(model, data, q_ff)
        for k, leg in enumerate(silo4.legs):
            frame = model.frames[model.getFrameId(leg.foot_frame)]
            knee = data.oMi[frame.parentJoint]
            foot = frame.placement.translation
            end = knee.act(foot * (1 - TIBIA_FOOT_GAP_M / np.linalg.norm(foot)))
            expected[i, k] = min(knee.translation[2], end[2]) - leg.tibia_radius_m
    got = tibia_clearance(silo4.legs, q, height)
    assert np.max(np.abs(got - expected)) < FK_TOL_M


@pytest.mark.parametrize("robot_file", [None, "mantis.urdf", "phasmid.urdf.xacro"])
def test_capsule_is_the_physics_model(robot_file):
    """The planner's capsule is the one silo4sim/model.py builds, per robot (the URDF's own tibia
    radius: SILO4 20 mm, mantis 12 mm, phasmid 18 mm)."""
    from pathlib import Path

    from silo4kin import load_robot

    source = None if robot_file is None else Path(__file__).parent / "robots" / robot_file
    robot = load_robot(source)
    _, radius = prepare_urdf(robot.urdf_xml, [leg.joint_names[2] for leg in robot.legs])
    assert [radius[leg.joint_names[2]] for leg in robot.legs] == [
        leg.tibia_radius_m for leg in robot.legs
    ]
    assert len({leg.tibia_radius_m for leg in robot.legs}) == 1
    assert SimSettings().tibia_clearance_m == TIBIA_FOOT_GAP_M


def test_verify_refuses_a_low_tibia(silo4):
    """verify_samples (hold_tibias) raises at the first sample where a capsule comes within
    the margin of the ground, with the body lowered under a plan that clears it; the thesis
    preset's call (hold_tibias=False) does not look."""
    plan = plan_path(silo4, [[0.5, 0.0]], 0.4, start_heading=0.0, samples_per_unit=10)
    traj = plan.trajectory
    assert tibia_violation(silo4.legs, traj) is None
    clearance = tibia_clearance(silo4.legs, traj.q, traj.position_base_in_world[:, 2])
    drop = clearance[0].min() - MIN_TIBIA_CLEARANCE_M + 1e-3  # clears only at the start
    drops = np.r_[0.0, np.full(len(traj) - 1, drop)]  # (N,) [m]
    lowered = replace(
        traj,
        position_base_in_world=traj.position_base_in_world
        - drops[:, None] * np.array([0.0, 0.0, 1.0]),
    )
    low = tibia_low(silo4.legs, lowered)
    first = int(np.flatnonzero(low.any(axis=1))[0])
    expected = clearance - drops[:, None]
    assert np.array_equal(low, expected < MIN_TIBIA_CLEARANCE_M)
    wp = np.array([[0.5, 0.0]])
    verify_samples(silo4.legs, lowered, plan.steps, 0.0, wp)  # not held: no error
    with pytest.raises(PlanningError, match="tibia") as err:
        verify_samples(silo4.legs, lowered, plan.steps, 0.0, wp, hold_tibias=True)
    assert f"t = {lowered.time_units[first]:.2f} units" in str(err.value)


def test_defect_path_default_gait_keeps_the_tibias_up(silo4):
    """silo4 plan --waypoints -1,-1 --height 0.3 --start-heading 0 (gait auto): walked with
    the front/rear pairs, the crawl and the omnidirectional creeping gait folded a shank under
    the body (capsule within 5 mm of the ground; physics put LF and RH tibias on the floor).
    The diagonal now goes to the side pairs (planner/gaits/omni.py AXIS_TIE_ORDER); whatever
    the gait, every tibia stays clear, the plan arrives within its tolerance, and a plan that
    faces the path says it was for a tibia."""
    plan = plan_path(silo4, [[-1.0, -1.0]], 0.3, start_heading=0.0, samples_per_unit=20)
    assert tibia_violation(silo4.legs, plan.trajectory) is None
    assert plan.gait in ("crawl", "creep") or "tibia" in (plan.fallback_reason or "")
    errors = np.hypot(*(plan.position_walked_in_world - plan.waypoints_in_world).T)
    assert errors.mean() <= plan.tolerance


@pytest.mark.parametrize("height", [0.25, 0.3, 0.4])
@pytest.mark.parametrize("direction_deg", [-135, -45, 45, 135])
def test_default_plans_keep_the_tibias_up(silo4, height, direction_deg):
    """Every default plan (gait auto) keeps every tibia capsule MIN_TIBIA_CLEARANCE_M above
    the ground on every sample, stance and swing."""
    a = np.radians(direction_deg)
    plan = plan_path(
        silo4, [[np.cos(a), np.sin(a)]], height, start_heading=0.0, samples_per_unit=10
    )
    traj = plan.trajectory
    clearance = tibia_clearance(silo4.legs, traj.q, traj.position_base_in_world[:, 2])
    assert clearance.min() >= MIN_TIBIA_CLEARANCE_M


def test_tibia_radius_rule_of_silo4kin_shapes():
    """The one reader of the shank shape: the first cylinder or capsule of the tibia's
    collision shapes, else of its visuals (fixed-joint children included), else the default;
    the physics model's capsule uses it."""
    from silo4kin.shapes import DEFAULT_TIBIA_RADIUS_M, tibia_radii_m

    def urdf(tibia: str, tip: str = "") -> str:
        return (
            f'<robot name="r"><link name="femur"/><link name="tibia">{tibia}</link>'
            f'<link name="tip">{tip}</link>'
            '<joint name="knee" type="revolute"><parent link="femur"/>'
            '<child link="tibia"/></joint>'
            '<joint name="weld" type="fixed"><parent link="tibia"/>'
            '<child link="tip"/></joint></robot>'
        )

    def shape(kind: str, tag: str, radius: float) -> str:
        return f'<{kind}><geometry><{tag} radius="{radius}" length="0.1"/></geometry></{kind}>'

    both = shape("visual", "cylinder", 0.03) + shape("collision", "cylinder", 0.01)
    assert tibia_radii_m(urdf(both), ["knee"]) == {"knee": 0.01}
    assert tibia_radii_m(urdf(shape("visual", "cylinder", 0.03)), ["knee"]) == {"knee": 0.03}
    assert tibia_radii_m(urdf("", shape("collision", "capsule", 0.02)), ["knee"]) == {"knee": 0.02}
    assert tibia_radii_m(urdf(shape("visual", "box", 0.02)), ["knee"]) == {
        "knee": DEFAULT_TIBIA_RADIUS_M
    }
    _, radius = prepare_urdf(urdf(both), ["knee"])
    assert radius == {"knee": 0.01}


class _LevelButAsked:
    """Level ground at z0 that does not say so: its heights are asked point by point."""

    def __init__(self, z0: float) -> None:
        self.z0 = z0

    def height_at(self, xy_in_world):
        return np.full(len(np.asarray(xy_in_world).reshape(-1, 2)), self.z0)


def test_clearance_over_a_terrain_is_the_closed_form_on_level_ground(silo4):
    """The capsule sampled over a terrain (world points, the terrain asked under each) gives
    the closed form's clearance on level ground, for a plan that turns; a FlatGround at z0
    lowers every clearance by exactly z0."""
    from planner.terrain.base import FlatGround
    from planner.trajectory.clearance import trajectory_tibia_clearance

    plan = plan_path(silo4, [[0.6, 0.4], [0.2, 1.0]], 0.4, start_heading=0.3, samples_per_unit=10)
    traj = plan.trajectory
    closed = tibia_clearance(silo4.legs, traj.q, traj.position_base_in_world[:, 2])
    asked = trajectory_tibia_clearance(silo4.legs, traj, _LevelButAsked(0.0))
    assert np.max(np.abs(asked - closed)) < FK_TOL_M
    shifted = trajectory_tibia_clearance(silo4.legs, traj, FlatGround(0.05))
    assert np.array_equal(shifted, closed - 0.05)


def test_clearance_sees_a_bump_under_the_shank(silo4):
    """A terrain raised under the middle of one tibia (and nowhere else) lowers that leg's
    clearance, and only that leg's: the capsule's inside points are asked, not only its
    ends."""
    from planner.trajectory.clearance import trajectory_tibia_clearance

    plan = plan_path(silo4, [[0.5, 0.0]], 0.4, start_heading=0.0, samples_per_unit=10)
    traj = plan.trajectory
    flat = trajectory_tibia_clearance(silo4.legs, traj, _LevelButAsked(0.0))
    leg = silo4.legs[0]
    theta = leg.joint_to_dh(traj.q[:1, :3])[0]
    hip = leg.position_hip_in_base
    knee_r = leg.L1 + leg.L2 * np.cos(theta[1])
    end_r = knee_r + (leg.L3 - TIBIA_FOOT_GAP_M) * np.cos(theta[1] + theta[2])
    phi = leg.theta_b + theta[0] + traj.yaw_base_in_world[0]
    mid = (
        traj.position_base_in_world[0, :2]
        + hip[:2]
        + 0.5 * (knee_r + end_r) * np.array([np.cos(phi), np.sin(phi)])
    )

    class Bump:
        def height_at(self, xy_in_world):
            xy = np.asarray(xy_in_world).reshape(-1, 2)
            return np.where(np.hypot(*(xy - mid).T) < 0.01, 0.1, 0.0)

    bumped = trajectory_tibia_clearance(silo4.legs, traj, Bump())
    assert bumped[0, 0] < flat[0, 0] - 0.01
    assert np.array_equal(bumped[0, 1:], flat[0, 1:])


def test_a_joint_limit_refusal_on_a_terrain_names_what_is_under_the_foot(silo4):
    """Beyond a robot's reach on a terrain file (go2 on the capability benchmark's 12.5 deg
    ramp: a calf joint left its limit in a creep transfer) the refusal names the part under
    the leg's foot and its slope, as the foothold refusals do; on level ground it does not."""
    from planner.terrain import terrain_from_document

    plan = plan_path(silo4, [[0.5, 0.0]], 0.4, start_heading=0.0, samples_per_unit=10)
    traj = plan.trajectory
    q = traj.q.copy()
    i = len(q) // 2
    q[i, 2] = silo4.legs[0].q_upper[2] + 0.01  # LF's third joint past its upper limit
    off = replace(traj, q=q)
    wp = np.array([[0.5, 0.0]])
    foot = traj.position_foot_in_world[i, 0]
    box = {"center": [foot[0], foot[1], -0.05], "size": [0.3, 0.3, 0.1], "rpy": [8.0, 0, 0]}
    terrain = terrain_from_document({"floor": None, "boxes": [box]}, name="tilted")
    with pytest.raises(PlanningError) as err:
        verify_samples(silo4.legs, off, plan.steps, 0.0, wp, terrain=terrain)
    assert "leaves" in str(err.value)
    assert "foot LF over box 0 of terrain file tilted, 8.0 deg from level" in str(err.value)
    with pytest.raises(PlanningError) as err:
        verify_samples(silo4.legs, off, plan.steps, 0.0, wp)
    assert "over" not in str(err.value)
