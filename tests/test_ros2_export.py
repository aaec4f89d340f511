"""ROS 2 export: the rosbag2 (MCAP) RViz replays and the FollowJointTrajectory goal, read back.

The bag is read with rosbags' own MCAP reader and CDR deserialiser (the ``mcap`` package is
not a dependency), the goal YAML with PyYAML and then built into a FollowJointTrajectory
goal message of the official definition: independent of our writers' code paths. One tiny
plan (``silo4 plan``, with torques) made once for the module.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
import yaml

from planner.outputs.trajectory_npz import read_root_pose_npz, read_trajectory_npz
from planner.trajectory.samples import Trajectory
from silo4kin import Robot
from viz.cli.main import main
from viz.export.robot_frames import RobotFrames
from viz.export.ros2 import write_ros2_bag
from viz.export.ros2_messages import (
    DEFAULT_START_TIME_NS,
    ODOM_FRAME,
    ROS_DISTRO,
    typestore,
)

rosbag2 = pytest.importorskip("rosbags.rosbag2")
typesys = pytest.importorskip("rosbags.typesys")

ONE_SHOT = {"/robot_description", "/tf_static", "/joint_trajectory", "/body_path"}
STREAMS = {"/joint_states", "/tf"}


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 0.3 m straight walk at 100 samples per unit (100 Hz), torques on (the default)."""
    out = tmp_path_factory.mktemp("ros2") / "run"
    assert (
        main(
            [
                "plan",
                "--waypoints",
                "0,0.3",
                "--height",
                "0.4",
                "--out",
                str(out),
                "--samples-per-unit",
                "100",
                "--no-html",
                "--no-plots",
            ]
        )
        == 0
    )
    return out


@pytest.fixture(scope="module")
def walk(run: Path) -> Trajectory:
    return read_trajectory_npz(run / "trajectory.npz")


@pytest.fixture(scope="module")
def bag(run: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The bag ``silo4 export`` writes for the run."""
    path = tmp_path_factory.mktemp("bag") / "run.bag"
    assert main(["export", str(run), "--ros2", str(path)]) == 0
    return path


def read_bag(path: Path) -> tuple[dict[str, list], dict[str, Any]]:
    """(topic -> [(bag time [ns], message)], topic -> connection) via rosbags' reader."""
    store = typestore()
    out: dict[str, list] = {}
    with rosbag2.Reader(path) as reader:
        connections = {c.topic: c for c in reader.connections}
        for connection, timestamp, raw in reader.messages():
            message = store.deserialize_cdr(raw, connection.msgtype)
            out.setdefault(connection.topic, []).append((timestamp, message))
    return out, connections


def stamp_ns(stamp: Any) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def test_bag_metadata_topics_and_qos(bag: Path) -> None:
    """The bag is MCAP of rosbag2 metadata version 9 (Jazzy's), names the distro, and offers
    reliable QoS on every topic: transient local for what is published once, volatile for
    the streams."""
    from rosbags.interfaces import QosDurability, QosReliability

    metadata = yaml.safe_load((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    assert metadata["ros_distro"] == ROS_DISTRO == "jazzy" and metadata["version"] == 9
    assert metadata["storage_identifier"] == "mcap"
    assert b"ros_distro: jazzy" in next(bag.glob("*.mcap")).read_bytes()
    messages, connections = read_bag(bag)
    assert set(connections) == ONE_SHOT | STREAMS
    for topic, connection in connections.items():
        [qos] = connection.ext.offered_qos_profiles
        assert qos.reliability == QosReliability.RELIABLE, topic
        durability = QosDurability.TRANSIENT_LOCAL if topic in ONE_SHOT else QosDurability.VOLATILE
        assert qos.durability == durability, topic
    for topic in ONE_SHOT:
        [(stamp, _)] = messages[topic]
        assert stamp == DEFAULT_START_TIME_NS, topic


def test_joint_states_are_the_npz(bag: Path, walk: Trajectory) -> None:
    """/joint_states: one message per sample at start + t, strictly increasing, header stamp
    equal to the bag time; positions, velocities and efforts the npz's, bit for bit."""
    records = read_bag(bag)[0]["/joint_states"]
    times = np.array([t for t, _ in records])
    states = [m for _, m in records]
    assert len(times) == len(walk) and np.all(np.diff(times) > 0)
    np.testing.assert_array_equal(
        times, DEFAULT_START_TIME_NS + np.round((walk.t - walk.t[0]) * 1e9).astype(np.int64)
    )
    assert [stamp_ns(m.header.stamp) for m in states] == list(times)
    assert all(list(m.name) == list(walk.joint_names) for m in states)
    np.testing.assert_array_equal([m.position for m in states], walk.q)
    np.testing.assert_array_equal([m.velocity for m in states], walk.qd)
    np.testing.assert_array_equal([m.effort for m in states], walk.tau)


def test_tf_root_pose_is_the_npz(bag: Path, run: Path, walk: Trajectory, silo4: Robot) -> None:
    """/tf: per sample, odom -> the URDF root link equal to trajectory.npz's root pose bit for
    bit, stamps monotonic; the link transforms of /tf and /tf_static composed from the root
    to each foot give the foot where Pinocchio's forward kinematics puts it."""
    messages, _ = read_bag(bag)
    tf = [m for _, m in messages["/tf"]]
    stamps = [stamp_ns(m.transforms[0].header.stamp) for m in tf]
    assert np.all(np.diff(stamps) > 0)
    root = RobotFrames(silo4.urdf_xml, walk.joint_names).root_link
    assert {(m.transforms[0].header.frame_id, m.transforms[0].child_frame_id) for m in tf} == {
        (ODOM_FRAME, root)
    }
    pose = read_root_pose_npz(run / "trajectory.npz")
    assert pose is not None
    xyz = [
        [
            t.transforms[0].transform.translation.x,
            t.transforms[0].transform.translation.y,
            t.transforms[0].transform.translation.z,
        ]
        for t in tf
    ]
    np.testing.assert_array_equal(xyz, pose.position_root_in_world)
    r = [t.transforms[0].transform.rotation for t in tf]
    np.testing.assert_array_equal(
        [[q.x, q.y, q.z, q.w] for q in r], pose.orientation_root_in_world_xyzw
    )
    [(_, static)] = messages["/tf_static"]
    data = silo4.model.createData()
    for k in (0, len(tf) // 2, len(tf) - 1):
        parent_of = {t.child_frame_id: t for t in [*tf[k].transforms[1:], *static.transforms]}
        pin.framesForwardKinematics(silo4.model, data, silo4.to_pinocchio_q(walk.q[k]))
        for leg in silo4.legs:
            link, placement = leg.foot_frame, pin.SE3.Identity()
            while link != root:
                t = parent_of[link].transform
                q = pin.Quaternion(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z)
                placement = (
                    pin.SE3(
                        q.matrix(), np.array([t.translation.x, t.translation.y, t.translation.z])
                    )
                    * placement
                )
                link = parent_of[link].header.frame_id
            expected = data.oMf[silo4.model.getFrameId(leg.foot_frame)]
            np.testing.assert_allclose(placement.translation, expected.translation, atol=1e-12)


def test_one_shot_messages(bag: Path, walk: Trajectory, silo4: Robot) -> None:
    """/robot_description is the URDF the run used; /joint_trajectory every sample bit for
    bit; /body_path the root link in odom at each sample's time."""
    messages, _ = read_bag(bag)
    [(_, description)] = messages["/robot_description"]
    assert description.data == silo4.urdf_xml
    [(_, joint)] = messages["/joint_trajectory"]
    assert list(joint.joint_names) == list(walk.joint_names) and len(joint.points) == len(walk)
    for name, field in (
        ("q", "positions"),
        ("qd", "velocities"),
        ("qdd", "accelerations"),
        ("tau", "effort"),
    ):
        np.testing.assert_array_equal(
            [getattr(p, field) for p in joint.points], getattr(walk, name), err_msg=name
        )
    t = np.array([stamp_ns(p.time_from_start) for p in joint.points]) * 1e-9
    np.testing.assert_allclose(t, walk.t - walk.t[0], rtol=0, atol=0.5e-9)  # ns resolution
    [(_, path)] = messages["/body_path"]
    assert path.header.frame_id == ODOM_FRAME and len(path.poses) == len(walk)
    stamps = [stamp_ns(p.header.stamp) for p in path.poses]
    assert stamps == [t for t, _ in messages["/joint_states"]]


def test_bag_start_time_and_determinism(walk: Trajectory, silo4: Robot, tmp_path: Path) -> None:
    """``start_time_ns`` moves every stamp; the same inputs give the same bag, byte for byte;
    a start time of 0 is refused."""
    from planner.outputs.root_pose import root_pose_in_world
    from silo4kin.errors import Silo4Error

    frames = RobotFrames(silo4.urdf_xml, walk.joint_names)
    pose = root_pose_in_world(walk, np.zeros(3))
    path = write_ros2_bag(
        tmp_path / "b.bag", walk, pose, frames, silo4.urdf_xml, start_time_ns=5 * 10**9
    )
    assert read_bag(path)[0]["/joint_states"][0][0] == 5 * 10**9
    again = write_ros2_bag(
        tmp_path / "again" / "b.bag", walk, pose, frames, silo4.urdf_xml, start_time_ns=5 * 10**9
    )  # the same inputs give the same bytes
    assert (again / "b.bag.mcap").read_bytes() == (path / "b.bag.mcap").read_bytes()
    assert (again / "metadata.yaml").read_text() == (path / "metadata.yaml").read_text()
    with pytest.raises(Silo4Error, match="must be > 0"):
        write_ros2_bag(tmp_path / "c.bag", walk, pose, frames, silo4.urdf_xml, start_time_ns=0)


def test_root_link_is_the_urdfs_own() -> None:
    """The root link is the one link no joint has as child, whatever its name."""
    from silo4kin.errors import Silo4Error
    from viz.export.robot_frames import root_link_name

    urdf = (
        '<robot name="r"><link name="torso"/><link name="leg"/>'
        '<joint name="j" type="revolute"><parent link="torso"/><child link="leg"/></joint>'
        "</robot>"
    )
    assert root_link_name(urdf) == "torso"
    with pytest.raises(Silo4Error, match="one root link"):
        root_link_name('<robot name="r"><link name="a"/><link name="b"/></robot>')
