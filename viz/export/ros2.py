"""A plan for a ROS 2 robot: a rosbag2 (MCAP) and a ros2_control goal, without a ROS install.

    write_ros2_bag("out/run.bag", trajectory, root_pose)   # folder: metadata.yaml + *.mcap
    write_joint_trajectory_goal("out/goal.yaml", trajectory)

The bag (pure-Python ``rosbags`` library, ROS 2 Humble message definitions) holds:

    /joint_trajectory  trajectory_msgs/msg/JointTrajectory   one message, every sample:
                       positions [rad], velocities [rad/s], accelerations [rad/s^2],
                       effort [N m] (when the plan has torques), time_from_start [s]
    /body_path         nav_msgs/msg/Path                      one message, a PoseStamped per
                       sample: the URDF root link (the robot's base, the floating base of
                       its URDF) in the world frame W, orientation the yaw about z as a
                       quaternion (x, y, z, w) = (0, 0, sin ψ/2, cos ψ/2)
                       (planner.outputs.root_pose: the planner's body frame B_c at the body
                       CoG, moved to the root link)

Both are stamped at ``start_time_ns`` (default 0); path poses at start + t. Frame ids:
``world`` for the path (W of docs/notation.md: z up, ground z = 0). Joint names are the URDF
names, so a controller of the same URDF takes the trajectory as it is.

The goal YAML is a ``control_msgs/action/FollowJointTrajectory`` goal, the form
``ros2 action send_goal /joint_trajectory_controller/follow_joint_trajectory
control_msgs/action/FollowJointTrajectory "$(cat goal.yaml)"`` takes. Every number is
written with ``repr`` (shortest exact round trip): the file reads back bit for bit.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from planner.outputs.files import (
    OutputFolderError,
    check_target,
    record_written,
    replace_folder_atomically,
    write_atomic,
)
from planner.outputs.root_pose import RootPose
from planner.trajectory.samples import Trajectory
from silo4kin.errors import Silo4Error

JOINT_TOPIC = "/joint_trajectory"
PATH_TOPIC = "/body_path"
WORLD_FRAME = "world"
#: ROS 2 distribution whose message definitions the bag records.
ROS_DISTRO = "ROS2_HUMBLE"


def _stamp(seconds: float) -> tuple[int, int]:
    """(sec, nanosec) of a non-negative time [s], nanosec in [0, 1e9)."""
    ns = int(round(seconds * 1e9))
    return ns // 1_000_000_000, ns % 1_000_000_000


def _typestore():  # noqa: ANN202
    try:
        from rosbags.typesys import Stores, get_typestore
    except ImportError as exc:  # declared dependency; a broken install gets one clear line
        raise Silo4Error(f"the ROS 2 export needs the 'rosbags' package ({exc})") from exc
    return get_typestore(getattr(Stores, ROS_DISTRO))


def joint_trajectory_message(trajectory: Trajectory, start_time_ns: int = 0):  # noqa: ANN201
    """trajectory_msgs/msg/JointTrajectory with one point per sample (module docstring)."""
    store = _typestore()
    Time = store.types["builtin_interfaces/msg/Time"]
    Duration = store.types["builtin_interfaces/msg/Duration"]
    Header = store.types["std_msgs/msg/Header"]
    Point = store.types["trajectory_msgs/msg/JointTrajectoryPoint"]
    JointTrajectory = store.types["trajectory_msgs/msg/JointTrajectory"]
    t = np.asarray(trajectory.t, dtype=float) - float(trajectory.t[0])
    effort = (np.asarray(trajectory.tau, dtype=float) if trajectory.tau is not None
              else np.empty((len(t), 0)))
    points = [Point(positions=np.ascontiguousarray(trajectory.q[k], dtype=np.float64),
                    velocities=np.ascontiguousarray(trajectory.qd[k], dtype=np.float64),
                    accelerations=np.ascontiguousarray(trajectory.qdd[k], dtype=np.float64),
                    effort=np.ascontiguousarray(effort[k], dtype=np.float64),
                    time_from_start=Duration(*_stamp(t[k])))
              for k in range(len(t))]
    sec, nanosec = divmod(int(start_time_ns), 1_000_000_000)
    return JointTrajectory(header=Header(stamp=Time(sec=sec, nanosec=nanosec), frame_id=""),
                           joint_names=list(trajectory.joint_names), points=points)


def body_path_message(trajectory: Trajectory, root_pose: RootPose,  # noqa: ANN201
                      start_time_ns: int = 0):
    """nav_msgs/msg/Path of the URDF root link in W, one PoseStamped per sample (module
    docstring); ``root_pose`` from planner.outputs.root_pose (trajectory.npz holds it)."""
    store = _typestore()
    types = store.types
    Time, Header = types["builtin_interfaces/msg/Time"], types["std_msgs/msg/Header"]
    Pose, PoseStamped = types["geometry_msgs/msg/Pose"], types["geometry_msgs/msg/PoseStamped"]
    Point, Quaternion = types["geometry_msgs/msg/Point"], types["geometry_msgs/msg/Quaternion"]
    t = np.asarray(trajectory.t, dtype=float) - float(trajectory.t[0])
    position = np.asarray(root_pose.position_root_in_world, dtype=float)
    quaternion = np.asarray(root_pose.orientation_root_in_world_xyzw, dtype=float)
    if position.shape != (len(t), 3) or quaternion.shape != (len(t), 4):
        raise Silo4Error(f"root pose of {len(position)} samples for a trajectory of {len(t)}")
    start_s = int(start_time_ns) * 1e-9
    poses = [PoseStamped(header=Header(stamp=Time(*_stamp(start_s + t[k])), frame_id=WORLD_FRAME),
                         pose=Pose(position=Point(x=float(position[k, 0]),
                                                  y=float(position[k, 1]),
                                                  z=float(position[k, 2])),
                                   orientation=Quaternion(x=float(quaternion[k, 0]),
                                                          y=float(quaternion[k, 1]),
                                                          z=float(quaternion[k, 2]),
                                                          w=float(quaternion[k, 3]))))
             for k in range(len(t))]
    sec, nanosec = divmod(int(start_time_ns), 1_000_000_000)
    return types["nav_msgs/msg/Path"](
        header=Header(stamp=Time(sec=sec, nanosec=nanosec), frame_id=WORLD_FRAME), poses=poses)


def check_bag_target(path: str | Path, *, force: bool = False,
                     inputs: Iterable[str | Path] = ()) -> Path:
    """Whether the bag folder ``path`` may be written: the output-safety rule
    (planner.outputs.files.check_target: only a bag silo4 wrote, never an input such as the run
    folder itself), then ``--force`` to replace an existing bag of ours."""
    path = Path(path)
    check_target(path, folder=True, inputs=inputs, what="--ros2")
    if os.path.lexists(path) and not force:
        raise OutputFolderError(f"{path} exists; use --force to replace it", path)
    return path


def write_ros2_bag(path: str | Path, trajectory: Trajectory, root_pose: RootPose, *,
                   start_time_ns: int = 0, force: bool = False,
                   inputs: Iterable[str | Path] = ()) -> Path:
    """Write the rosbag2 folder ``path`` (MCAP storage), atomically.

    The folder gets a ``.silo4-files`` manifest (planner/outputs/files.py), so a rerun with
    ``force`` may replace it; ros2 bag ignores files its metadata.yaml does not list.

    Args:
        path: the bag folder to create (rosbag2 bags are folders: metadata.yaml + .mcap).
        trajectory: the plan (N >= 1 samples).
        root_pose: the URDF root link's pose along it (/body_path).
        start_time_ns: bag time of the messages' stamps [ns].
        force: replace an existing bag folder silo4 wrote.
        inputs: the files the command reads (never replaced: :func:`check_bag_target`).

    Returns:
        the bag folder.

    Raises:
        Silo4Error: ``path`` exists (without force), holds files silo4 did not write,
            holds an input, or cannot be written.
    """
    from rosbags.rosbag2 import StoragePlugin, Writer

    path = Path(path).absolute()
    store = _typestore()
    messages = [(JOINT_TOPIC, "trajectory_msgs/msg/JointTrajectory",
                 joint_trajectory_message(trajectory, start_time_ns)),
                (PATH_TOPIC, "nav_msgs/msg/Path",
                 body_path_message(trajectory, root_pose, start_time_ns))]

    def fill(tmp: Path) -> None:
        bag = tmp / ".bag" / path.name  # the .mcap file is named after the bag folder
        bag.parent.mkdir()
        with Writer(bag, version=8, storage_plugin=StoragePlugin.MCAP) as writer:
            for topic, msgtype, message in messages:
                connection = writer.add_connection(topic, msgtype, typestore=store)
                writer.write(connection, int(start_time_ns),
                             store.serialize_cdr(message, msgtype))
        for entry in bag.iterdir():
            entry.rename(tmp / entry.name)
        bag.rmdir()
        bag.parent.rmdir()

    def check(out: Path) -> None:  # again under the folder lock
        check_bag_target(out, force=force, inputs=inputs)

    return replace_folder_atomically(path, fill, check=check)


def _flow(values: np.ndarray) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def joint_trajectory_goal_yaml(trajectory: Trajectory) -> str:
    """A FollowJointTrajectory goal (module docstring) as YAML text."""
    t = np.asarray(trajectory.t, dtype=float) - float(trajectory.t[0])
    lines = ["# control_msgs/action/FollowJointTrajectory goal written by silo4 export",
             "# positions [rad], velocities [rad/s], accelerations [rad/s^2], effort [N m]",
             "trajectory:",
             "  header: {stamp: {sec: 0, nanosec: 0}, frame_id: ''}",
             "  joint_names: [" + ", ".join(trajectory.joint_names) + "]",
             "  points:"]
    for k in range(len(t)):
        sec, nanosec = _stamp(t[k])
        lines.append(f"    - positions: {_flow(trajectory.q[k])}")
        lines.append(f"      velocities: {_flow(trajectory.qd[k])}")
        lines.append(f"      accelerations: {_flow(trajectory.qdd[k])}")
        if trajectory.tau is not None:
            lines.append(f"      effort: {_flow(trajectory.tau[k])}")
        lines.append(f"      time_from_start: {{sec: {sec}, nanosec: {nanosec}}}")
    return "\n".join(lines) + "\n"


def write_joint_trajectory_goal(path: str | Path, trajectory: Trajectory, *,
                                inputs: Iterable[str | Path] = ()) -> Path:
    """Write the goal YAML atomically and record it in the ``.silo4-files`` of its folder
    (so a rerun may replace it); a file silo4 did not write, or an input, is refused
    (planner.outputs.files.check_target). Returns the path."""
    if not all(math.isfinite(float(x)) for x in (trajectory.t[0], trajectory.t[-1])):
        raise Silo4Error("trajectory times must be finite")
    check_target(path, inputs=inputs, what="--goal-yaml")
    text = joint_trajectory_goal_yaml(trajectory)
    written = write_atomic(Path(path), lambda tmp: tmp.write_text(text), make_parents=True)
    record_written([written])
    return written
