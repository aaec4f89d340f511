"""The URDF root link's pose in trajectory.csv / .npz is the floating base a user gives
Pinocchio: the feet it puts, from the CSV's root and q columns alone, are where the CSV's
foot columns (and the planner) put them.

Three robots whose body CoG sits differently from the root link: SILO4 (root = CoG), go2
(2 cm off), tests/robots/mantis.urdf (4.5 cm behind and 4.2 cm below the CoG). The joints
are mapped into Pinocchio's configuration BY NAME, as a user's code would.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from planner.model import as_planning_model
from planner.outputs.export import (
    read_root_pose_npz,
    read_trajectory_csv,
    read_trajectory_npz,
    root_pose_in_world,
    write_run,
)
from planner.path.metrics import compute_metrics
from planner.path.plan_path import plan_path
from planner.trajectory.samples import LEGS
from silo4kin.foot_contact import foot_contact_offset_m
from silo4kin.robot import load_robot

ROBOTS = Path(__file__).parent / "robots"
#: How far Pinocchio's feet may be from the CSV's [m]: CSV numbers carry 10 significant
#: digits (~1e-10 m here); 1e-6 m is far below any planning tolerance.
FOOT_TOLERANCE_M = 1e-6

#: robot -> (how to load it, from the test's request: go2 and mantis are the session's,
#: tests/conftest.py; a short path (K, 2) [m], height [m], preset)
CASES = {
    "silo4": (lambda request: load_robot(), [[0.0, 0.15]], 0.4, "default"),
    "go2": (lambda request: request.getfixturevalue("go2"), [[0.0, 0.15]], 0.28, "default"),
    "mantis": (
        lambda request: request.getfixturevalue("mantis"),
        [[0.1, 0.1]],
        0.33,
        "default",
    ),
}


def feet_from_csv(robot, table: dict[str, np.ndarray]) -> np.ndarray:
    """Foot frames in W, (N, 4, 3) [m], by Pinocchio FK on the free-flyer model with
    q = [root xyz, root quaternion xyzw, joints by name] read from the CSV columns."""
    model = robot.model_free_flyer
    data = model.createData()
    n = len(table["t"])
    root = np.column_stack(
        [
            table[c]
            for c in ("root_x", "root_y", "root_z", "root_qx", "root_qy", "root_qz", "root_qw")
        ]
    )
    joints = [name for name in model.names[2:]]  # universe, root_joint, then the joints
    feet_frames = [model.getFrameId(leg.foot_frame) for leg in robot.legs]
    out = np.empty((n, len(LEGS), 3))
    for k in range(n):
        q = pin.neutral(model)
        q[:7] = root[k]
        for name in joints:
            q[model.joints[model.getJointId(name)].idx_q] = table[f"q_{name}"][k]
        pin.framesForwardKinematics(model, data, q)
        out[k] = [data.oMf[f].translation for f in feet_frames]
    return out


@pytest.mark.parametrize("name", sorted(CASES))
def test_pinocchio_puts_the_feet_where_the_csv_does(name: str, tmp_path: Path, request) -> None:
    """Free-flyer FK from root_* and q_* columns gives foot_*_x/y/z within 1e-6 m."""
    load, waypoints, height, preset = CASES[name]
    robot = load(request)
    plan = plan_path(
        robot, np.array(waypoints, dtype=float), height, workspace=preset, samples_per_unit=10
    )
    offset = as_planning_model(robot).position_body_com_in_root
    files = write_run(
        tmp_path / "run",
        plan,
        compute_metrics(plan),
        robot_name=name,
        position_body_com_in_root=offset,
    )
    table = read_trajectory_csv(files["trajectory.csv"])
    feet_csv = np.stack(
        [np.column_stack([table[f"foot_{leg}_{a}"] for a in "xyz"]) for leg in LEGS], axis=1
    )
    feet = feet_from_csv(robot, table)  # foot frames: a ball's centre stands r above its
    feet[..., 2] -= foot_contact_offset_m(robot)  # contact point, the CSV's foot (0 for points)
    np.testing.assert_allclose(feet, feet_csv, rtol=0, atol=FOOT_TOLERANCE_M)
    np.testing.assert_allclose(
        feet, plan.trajectory.position_foot_in_world, rtol=0, atol=FOOT_TOLERANCE_M
    )
    # the npz holds the same pose, exactly
    pose = read_root_pose_npz(files["trajectory.npz"])
    assert pose is not None
    expected = root_pose_in_world(read_trajectory_npz(files["trajectory.npz"]), offset)
    np.testing.assert_array_equal(pose.position_root_in_world, expected.position_root_in_world)
    np.testing.assert_array_equal(
        pose.orientation_root_in_world_xyzw, expected.orientation_root_in_world_xyzw
    )


def test_the_offsets_the_robots_have() -> None:
    """SILO4's root link is its body CoG; go2's is 2 cm off; mantis's 4.5 cm behind and
    4.2 cm below it (so the test above checks a real offset)."""
    np.testing.assert_allclose(
        as_planning_model(load_robot()).position_body_com_in_root, 0.0, atol=1e-12
    )
    go2 = as_planning_model(load_robot("go2")).position_body_com_in_root
    assert 0.015 < np.linalg.norm(go2) < 0.03
    mantis = as_planning_model(load_robot(ROBOTS / "mantis.urdf")).position_body_com_in_root
    np.testing.assert_allclose(mantis[[0, 2]], [0.045, 0.042], atol=1e-3)


def test_old_npz_without_root_pose_reads_as_none(tmp_path: Path) -> None:
    """A trajectory.npz written before the root pose was recorded still reads, without it."""
    from planner.outputs.trajectory_npz import write_trajectory_npz

    robot = load_robot()
    plan = plan_path(robot, np.array([[0.0, 0.15]]), 0.4, samples_per_unit=10)
    write_trajectory_npz(tmp_path / "old.npz", plan.trajectory)
    assert read_root_pose_npz(tmp_path / "old.npz") is None
    assert len(read_trajectory_npz(tmp_path / "old.npz")) == len(plan.trajectory)
