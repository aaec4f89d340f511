"""ROS 2 export: the rosbag2 (MCAP) and the FollowJointTrajectory goal read back exactly.

Read back with the same pure-Python ``rosbags`` library (its MCAP reader and CDR
deserialiser), and the goal YAML with PyYAML: independent of our writers' code paths.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from test_animation import synthetic_trajectory  # tests/ is on sys.path (pytest rootdir)

from planner.outputs.root_pose import root_pose_in_world
from planner.trajectory.samples import Trajectory
from silo4kin import Robot
from viz.cli.main import main
from viz.export.ros2 import (
    JOINT_TOPIC,
    PATH_TOPIC,
    ROS_DISTRO,
    write_joint_trajectory_goal,
    write_ros2_bag,
)

rosbag2 = pytest.importorskip("rosbags.rosbag2")
typesys = pytest.importorskip("rosbags.typesys")


@pytest.fixture(scope="module")
def walk(silo4: Robot) -> Trajectory:
    """A 6-unit synthetic walk with torques, 0.5 s per unit (times not in whole seconds)."""
    trajectory = synthetic_trajectory(silo4, n_units=6.0, samples_per_unit=20, unit_time_s=0.5)
    return trajectory.with_torques(np.sin(trajectory.q) * 3.0)


def read_bag(path: Path) -> dict[str, list]:
    """topic -> [(bag time [ns], message)] via rosbags' own reader and deserialiser."""
    store = typesys.get_typestore(getattr(typesys.Stores, ROS_DISTRO))
    out: dict[str, list] = {}
    with rosbag2.Reader(path) as reader:
        for connection, timestamp, raw in reader.messages():
            message = store.deserialize_cdr(raw, connection.msgtype)
            out.setdefault(connection.topic, []).append((timestamp, message))
    return out


def test_bag_round_trip_joint_trajectory(walk: Trajectory, tmp_path: Path) -> None:
    """The bag is MCAP; /joint_trajectory holds every sample's q, qd, qdd, tau and time,
    bit for bit, under the URDF joint names."""
    bag = write_ros2_bag(tmp_path / "run.bag", walk, root_pose_in_world(walk, np.zeros(3)))
    assert (bag / "metadata.yaml").is_file() and list(bag.glob("*.mcap"))
    assert "storage_identifier: mcap" in (bag / "metadata.yaml").read_text()
    messages = read_bag(bag)
    [(stamp, msg)] = messages[JOINT_TOPIC]
    assert stamp == 0 and msg.__msgtype__ == "trajectory_msgs/msg/JointTrajectory"
    assert list(msg.joint_names) == list(walk.joint_names)
    assert len(msg.points) == len(walk)
    for name, field in (("q", "positions"), ("qd", "velocities"), ("qdd", "accelerations"),
                        ("tau", "effort")):
        got = np.array([getattr(p, field) for p in msg.points])
        np.testing.assert_array_equal(got, getattr(walk, name), err_msg=name)
    t = np.array([p.time_from_start.sec + 1e-9 * p.time_from_start.nanosec for p in msg.points])
    np.testing.assert_allclose(t, walk.t - walk.t[0], rtol=0, atol=0.5e-9)  # ns resolution
    assert all(0 <= p.time_from_start.nanosec < 1_000_000_000 for p in msg.points)


#: A root link 3 cm behind, 1 cm left of and 2 cm below the body CoG (root to B_c) [m].
POSITION_BODY_COM_IN_ROOT = np.array([0.03, -0.01, 0.02])


def test_bag_round_trip_body_path(walk: Trajectory, tmp_path: Path) -> None:
    """/body_path: one pose per sample, the URDF root link in the world frame (the body CoG
    frame moved by the offset turned with the yaw), the yaw recovered from the quaternion
    (atan2 of 2 z w, w^2 - z^2), stamped at t."""
    pose = root_pose_in_world(walk, POSITION_BODY_COM_IN_ROOT)
    messages = read_bag(write_ros2_bag(tmp_path / "run.bag", walk, pose,
                                       start_time_ns=5 * 10**9))
    [(stamp, path)] = messages[PATH_TOPIC]
    assert stamp == 5 * 10**9 and path.header.frame_id == "world"
    xyz = np.array([[p.pose.position.x, p.pose.position.y, p.pose.position.z]
                    for p in path.poses])
    np.testing.assert_array_equal(xyz, pose.position_root_in_world)
    yaw = walk.yaw_base_in_world  # the CoG = root + R_z(yaw) @ offset, to rounding
    turned = np.column_stack([np.cos(yaw) * 0.03 + np.sin(yaw) * 0.01,
                              np.sin(yaw) * 0.03 - np.cos(yaw) * 0.01, np.full_like(yaw, 0.02)])
    np.testing.assert_allclose(xyz + turned, walk.position_base_in_world, rtol=0, atol=1e-12)
    quat = np.array([[p.pose.orientation.x, p.pose.orientation.y, p.pose.orientation.z,
                      p.pose.orientation.w] for p in path.poses])
    np.testing.assert_allclose(np.linalg.norm(quat, axis=1), 1.0, atol=1e-15)
    assert np.all(quat[:, :2] == 0.0)
    yaw = np.arctan2(2 * quat[:, 2] * quat[:, 3], quat[:, 3] ** 2 - quat[:, 2] ** 2)
    wrapped = np.angle(np.exp(1j * (yaw - walk.yaw_base_in_world)))
    np.testing.assert_allclose(wrapped, 0.0, atol=1e-12)
    stamps = np.array([p.header.stamp.sec + 1e-9 * p.header.stamp.nanosec for p in path.poses])
    np.testing.assert_allclose(stamps, 5.0 + walk.t, atol=1e-9)


def test_goal_yaml_reads_back_exactly(walk: Trajectory, tmp_path: Path) -> None:
    """The FollowJointTrajectory goal parses as YAML into the same numbers, bit for bit."""
    goal = yaml.safe_load(write_joint_trajectory_goal(tmp_path / "goal.yaml", walk).read_text())
    trajectory = goal["trajectory"]
    assert trajectory["joint_names"] == list(walk.joint_names)
    points = trajectory["points"]
    assert len(points) == len(walk)
    np.testing.assert_array_equal([p["positions"] for p in points], walk.q)
    np.testing.assert_array_equal([p["velocities"] for p in points], walk.qd)
    np.testing.assert_array_equal([p["accelerations"] for p in points], walk.qdd)
    np.testing.assert_array_equal([p["effort"] for p in points], walk.tau)
    t = [p["time_from_start"]["sec"] + 1e-9 * p["time_from_start"]["nanosec"] for p in points]
    np.testing.assert_allclose(t, walk.t - walk.t[0], atol=0.5e-9)


def test_cli_export_and_refusals(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """silo4 export writes bag and goal from a plan folder; an existing bag is kept unless
    --force; no output asked for, or a missing run, is exit 2 with one line."""
    run = tmp_path / "run"
    assert main(["plan", "--waypoints", "0,0.6", "--height", "0.4", "--out", str(run),
                 "--samples-per-unit", "4", "--no-html", "--no-plots"]) == 0
    bag, goal = tmp_path / "b.bag", tmp_path / "goal.yaml"
    assert main(["export", str(run), "--ros2", str(bag), "--goal-yaml", str(goal)]) == 0
    joint = read_bag(bag)[JOINT_TOPIC][0][1]
    from planner.outputs.export import read_trajectory_npz
    np.testing.assert_array_equal([p.positions for p in joint.points],
                                  read_trajectory_npz(run / "trajectory.npz").q)
    before = sorted(p.name for p in bag.iterdir())
    capsys.readouterr()
    assert main(["export", str(run), "--ros2", str(bag)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--force" in err
    assert sorted(p.name for p in bag.iterdir()) == before
    assert main(["export", str(run), "--ros2", str(bag), "--force"]) == 0
    # no temp left; .silo4-files records goal.yaml as silo4's (docs/errors.md)
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == [".silo4-files"]
    assert main(["export", str(run)]) == 2
    assert main(["export", str(tmp_path / "missing"), "--ros2", str(tmp_path / "x")]) == 2
    assert not (tmp_path / "x").exists()
