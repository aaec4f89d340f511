"""Ground clearance from the URDF's own shapes: meshes of every format, the batched frame
placements against Pinocchio, and the clearance against a per-sample Pinocchio reference."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from silo4kin import load_robot
from silo4kin.collision_shapes import collision_points
from silo4kin.frame_placements import frame_heights, frame_placements, joint_axes

ROBOTS = Path(__file__).with_name("robots")
#: Agreement of the batched placements with Pinocchio's [m, -]: round-off of ~10 products.
PLACEMENT_TOL = 1e-12


@pytest.mark.parametrize("which", [None, str(ROBOTS / "mantis.urdf"), "go2"])
def test_frame_placements_match_pinocchio(which):
    """Every frame's placement from the batched tree pass equals framesForwardKinematics's
    at random configurations."""
    if which == "go2":
        pytest.importorskip("example_robot_data")
    robot = load_robot(which)
    model = robot.model
    rng = np.random.default_rng(7)
    q = rng.uniform(-2.0, 2.0, size=(5, model.nq))
    ids = list(range(model.nframes))
    got = frame_placements(model, joint_axes(model), q, ids)
    data = model.createData()
    for i, qi in enumerate(q):
        pin.framesForwardKinematics(model, data, qi)
        for k, fid in enumerate(ids):
            np.testing.assert_allclose(
                got.rotation[i, k], data.oMf[fid].rotation, atol=PLACEMENT_TOL
            )
            np.testing.assert_allclose(
                got.translation[i, k], data.oMf[fid].translation, atol=PLACEMENT_TOL
            )


@pytest.mark.parametrize("which", [None, str(ROBOTS / "mantis.urdf"), "go2"])
def test_frame_heights_match_frame_placements(which):
    """frame_heights (row 2 of each rotation and the z of each translation, elementwise) is
    frame_placements's to round-off, on every frame at random configurations."""
    if which == "go2":
        pytest.importorskip("example_robot_data")
    model = load_robot(which).model
    q = np.random.default_rng(11).uniform(-2.0, 2.0, size=(7, model.nq))
    ids = list(range(model.nframes))
    axes = joint_axes(model)
    full = frame_placements(model, axes, q, ids)
    got = frame_heights(model, axes, q, ids)
    np.testing.assert_allclose(
        got.z_axis_row, np.moveaxis(full.rotation[:, :, 2, :], 0, 1), atol=PLACEMENT_TOL
    )
    np.testing.assert_allclose(got.z, full.translation[:, :, 2].T, atol=PLACEMENT_TOL)


def test_go2_dae_hips_are_read(go2):
    """go2's front hips have only COLLADA visuals: they are read (nothing skipped), and their
    points span the hip mesh (about 12 cm along x)."""
    shapes = collision_points(go2)
    assert shapes.skipped == ()
    hips = {link.link: link for link in shapes.links if link.link in ("FL_hip", "FR_hip")}
    assert set(hips) == {"FL_hip", "FR_hip"}
    span = np.ptp(hips["FL_hip"].points_in_link, axis=0)
    assert 0.08 < span[0] < 0.2


def test_clearance_matches_a_per_sample_reference(go2):
    """clearance_of_poses (one batched pass) equals the lowest shape point found with
    Pinocchio sample by sample, for poses of the go2 standing at 0.25 m with its joints
    perturbed."""
    from planner.model import planning_robot
    from planner.trajectory.clearance import clearance_of_poses
    from planner.workspace.foothold_layout import foothold_layout
    from silo4kin.leg_family import family_of

    robot = planning_robot(go2)
    _, mid, _ = foothold_layout(robot, 0.25, "default")
    q0 = np.concatenate(
        [
            family_of(leg).inverse_kinematics(leg, mid[k][None]).q[0]
            for k, leg in enumerate(robot.legs)
        ]
    )
    rng = np.random.default_rng(3)
    q = q0 + rng.uniform(-0.2, 0.2, size=(6, 12))
    base = np.tile([0.1, -0.2, 0.25], (6, 1))
    got = clearance_of_poses(robot, q, base, np.zeros(6))
    shapes = collision_points(robot).links
    model, data = robot.model, robot.model.createData()
    from planner.outputs.root_pose import root_pose_in_world
    from planner.trajectory.clearance import _BodyPose

    root = root_pose_in_world(
        _BodyPose(base, np.zeros(6)), np.asarray(robot.position_body_com_in_base)
    ).position_root_in_world
    for i in range(6):
        q_full = np.zeros(model.nq)
        q_full[robot.q_index] = q[i]
        pin.framesForwardKinematics(model, data, q_full)
        for k, link in enumerate(shapes):
            pose = data.oMf[link.frame_id]
            z = (link.points_in_link @ pose.rotation.T + pose.translation)[:, 2] + root[i, 2]
            assert got[i, k] == pytest.approx(float(np.min(z - link.inflation_m)), abs=1e-12)


def test_a_run_under_its_ground_clearance_is_reported_and_one_touching_is_refused(silo4):
    """The run pipeline measures every sample's non-foot clearance: SILO4's short straight
    plan at 0.4 m keeps its default 1 cm; asked for more than it keeps, the plan gets a
    warning naming the link, the distance and the time; with its base lowered until a
    non-foot shape is under the ground, it is refused naming them (reported, a warning)."""
    from dataclasses import replace

    from planner.errors import PlanningError
    from planner.outputs.pipeline import OnLimitViolation, RunRequest, finish_plan, plan_run
    from planner.trajectory.clearance import ground_clearance

    kept = plan_run(silo4, np.array([[0.0, 0.6]]), 0.4, RunRequest(), start_heading=np.pi / 2)
    lowest = float(ground_clearance(silo4, kept.plan.trajectory).min())
    assert lowest >= kept.plan.preset.ground_clearance_m == 0.01
    assert not any(w.startswith("ground clearance") for w in kept.metrics.get("warnings", []))
    asked = round(lowest + 0.005, 4)
    margin = plan_run(
        silo4,
        np.array([[0.0, 0.6]]),
        0.4,
        RunRequest(ground_clearance_m=asked),
        start_heading=np.pi / 2,
    )
    line = next(w for w in margin.metrics["warnings"] if w.startswith("ground clearance: "))
    assert re.search(r"link \w+ comes [\d.]+ mm above the ground at t = ", line)
    trajectory = kept.plan.trajectory
    base = trajectory.position_base_in_world.copy()
    base[:, 2] -= lowest + 0.002  # the lowest non-foot point 2 mm under the floor
    sunk = replace(kept.plan, trajectory=replace(trajectory, position_base_in_world=base))
    with pytest.raises(PlanningError, match=r"link \w+ comes -[\d.]+ mm above the ground at t = "):
        finish_plan(silo4, sunk, RunRequest())
    reported = finish_plan(silo4, sunk, RunRequest(on_limit_violation=OnLimitViolation.REPORT))
    assert any(w.startswith("ground clearance: link ") for w in reported.metrics["warnings"])
