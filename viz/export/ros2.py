"""A plan as a rosbag2 (MCAP) that RViz replays, written without a ROS install.

    write_ros2_bag("out/run.bag", trajectory, root_pose, RobotFrames(urdf_xml, names),
                   urdf_xml)   # folder: metadata.yaml + run.bag.mcap

The bag (pure-Python ``rosbags`` library, message definitions of ROS 2
:data:`~viz.export.ros2_messages.ROS_DISTRO`) holds, for N samples at bag times
``start + (t_k - t_0)`` (viz/export/ros2_messages.py: frames, stamps, QoS):

    /robot_description  std_msgs/msg/String          once: the URDF the run used
    /tf_static          tf2_msgs/msg/TFMessage       once: the URDF's fixed joints
    /joint_trajectory   trajectory_msgs/msg/JointTrajectory  once: every sample
    /body_path          nav_msgs/msg/Path            once: the root link's pose per sample
    /joint_states       sensor_msgs/msg/JointState   N: position, velocity, effort
    /tf                 tf2_msgs/msg/TFMessage       N: odom -> root link (trajectory.npz's
                        root pose) and every moving joint's parent -> child link
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from planner.outputs.files import OutputFolderError, check_target, replace_folder_atomically
from planner.outputs.root_pose import RootPose
from planner.trajectory.samples import Trajectory
from silo4kin.errors import Silo4Error
from viz.export.robot_frames import RobotFrames
from viz.export.ros2_messages import (
    BAG_VERSION,
    BODY_PATH,
    DEFAULT_START_TIME_NS,
    JOINT_STATES,
    JOINT_TRAJECTORY,
    ODOM_FRAME,
    ROBOT_DESCRIPTION,
    ROS_DISTRO,
    TF,
    TF_STATIC,
    Messages,
    Topic,
    sample_times_ns,
    typestore,
)


def check_bag_target(
    path: str | Path, *, force: bool = False, inputs: Iterable[str | Path] = ()
) -> Path:
    """Whether the bag folder ``path`` may be written: the output-safety rule
    (planner.outputs.files.check_target: only a bag silo4 wrote, never an input such as the run
    folder itself), then ``--force`` to replace an existing bag of ours."""
    path = Path(path)
    check_target(path, folder=True, inputs=inputs, what="--ros2")
    if os.path.lexists(path) and not force:
        raise OutputFolderError(f"{path} exists; use --force to replace it", path)
    return path


def bag_messages(
    trajectory: Trajectory,
    root_pose: RootPose,
    frames: RobotFrames,
    urdf_xml: str,
    start_time_ns: int,
) -> list[tuple[Topic, int, Any]]:
    """Every (topic, bag time [ns], message) of the bag, in time order (module docstring)."""
    build = Messages(typestore())
    stamps = sample_times_ns(trajectory, start_time_ns)
    position = np.asarray(root_pose.position_root_in_world, dtype=float)
    orientation = np.asarray(root_pose.orientation_root_in_world_xyzw, dtype=float)
    start = int(stamps[0])
    static = frames.transforms(trajectory.q[:1], fixed=True)
    moving = frames.transforms(trajectory.q, fixed=False)
    out: list[tuple[Topic, int, Any]] = [
        (ROBOT_DESCRIPTION, start, build.string(urdf_xml)),
        (TF_STATIC, start, build.tf_message(build.link_transforms(start, static, 0))),
        (JOINT_TRAJECTORY, start, build.joint_trajectory(trajectory)),
        (BODY_PATH, start, build.body_path(stamps, root_pose)),
    ]
    names = list(trajectory.joint_names)
    tau = trajectory.tau
    for k, ns in enumerate(int(s) for s in stamps):
        out.append(
            (
                JOINT_STATES,
                ns,
                build.joint_state(
                    ns, names, trajectory.q[k], trajectory.qd[k], None if tau is None else tau[k]
                ),
            )
        )
        root = build.transform(ns, ODOM_FRAME, frames.root_link, position[k], orientation[k])
        out.append((TF, ns, build.tf_message([root, *build.link_transforms(ns, moving, k)])))
    return out


_ROSBAGS_DISTRO = "ros_distro: rosbags"


def _writer_class() -> type:
    """rosbags' rosbag2 Writer naming :data:`ROS_DISTRO` (rosbags writes ``ros_distro:
    rosbags``) in metadata.yaml and in the copy the MCAP file keeps."""
    from rosbags.rosbag2 import Writer

    class DistroWriter(Writer):
        def close(self) -> None:
            storage = self.storage
            if storage is not None:
                close = storage.close
                storage.close = lambda version, metadata: close(  # type: ignore[method-assign]
                    version, metadata.replace(_ROSBAGS_DISTRO, f"ros_distro: {ROS_DISTRO}")
                )
            super().close()
            text = self.metapath.read_text(encoding="utf-8")
            if _ROSBAGS_DISTRO not in text:
                raise Silo4Error(f"{self.metapath}: no ros_distro to set (rosbags changed)")
            self.metapath.write_text(
                text.replace(_ROSBAGS_DISTRO, f"ros_distro: {ROS_DISTRO}"), encoding="utf-8"
            )

    return DistroWriter


def write_ros2_bag(
    path: str | Path,
    trajectory: Trajectory,
    root_pose: RootPose,
    frames: RobotFrames,
    urdf_xml: str,
    *,
    start_time_ns: int = DEFAULT_START_TIME_NS,
    force: bool = False,
    inputs: Iterable[str | Path] = (),
) -> Path:
    """Write the rosbag2 folder ``path`` (MCAP storage), atomically.

    The folder gets a ``.silo4-files`` manifest (planner/outputs/files.py), so a rerun with
    ``force`` may replace it; ros2 bag ignores files its metadata.yaml does not list.

    Args:
        path: the bag folder to create (rosbag2 bags are folders: metadata.yaml + .mcap).
        trajectory: the plan (N >= 1 samples).
        root_pose: the URDF root link's pose in W along it (trajectory.npz).
        frames: the robot's link transforms (:class:`RobotFrames` of ``urdf_xml``).
        urdf_xml: the URDF text the run used (/robot_description).
        start_time_ns: bag time of the first sample [ns], > 0.
        force: replace an existing bag folder silo4 wrote.
        inputs: the files the command reads (never replaced: :func:`check_bag_target`).

    Returns:
        the bag folder.

    Raises:
        Silo4Error: ``path`` exists (without force), holds files silo4 did not write,
            holds an input, or cannot be written; ``start_time_ns`` not > 0.
    """
    from rosbags.rosbag2 import StoragePlugin

    if int(start_time_ns) <= 0:
        raise Silo4Error(f"start time {start_time_ns} ns: must be > 0 (ROS reads 0 as no time)")
    path = Path(path).absolute()
    store = typestore()
    messages = bag_messages(trajectory, root_pose, frames, urdf_xml, int(start_time_ns))

    def fill(tmp: Path) -> None:
        bag = tmp / ".bag" / path.name  # the .mcap file is named after the bag folder
        bag.parent.mkdir()
        with _writer_class()(bag, version=BAG_VERSION, storage_plugin=StoragePlugin.MCAP) as writer:
            topics = (ROBOT_DESCRIPTION, TF_STATIC, JOINT_TRAJECTORY, BODY_PATH, JOINT_STATES, TF)
            connections = {
                topic: writer.add_connection(
                    topic.name, topic.msgtype, typestore=store, offered_qos_profiles=[topic.qos()]
                )
                for topic in topics
            }
            for topic, ns, message in messages:
                writer.write(connections[topic], ns, store.serialize_cdr(message, topic.msgtype))
        for entry in bag.iterdir():
            entry.rename(tmp / entry.name)
        bag.rmdir()
        bag.parent.rmdir()

    def check(out: Path) -> None:  # again under the folder lock
        check_bag_target(out, force=force, inputs=inputs)

    return replace_folder_atomically(path, fill, check=check)
