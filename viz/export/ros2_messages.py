"""The messages of the ROS 2 bag, built with the ``rosbags`` typestore of :data:`ROS_DISTRO`.

Frames (REP 105): ``odom`` is the plan's world frame W (docs/notation.md: z up, ground
z = 0); the robot's frames are the URDF's links, its root link (``base_link`` for most robots;
whatever the URDF names it) moving in ``odom``. Stamps are bag times [ns]: the bag starts at
``start_time_ns`` and sample k is at ``start_time_ns + (t_k - t_0)`` (docs/outputs.md).

Each topic is a :class:`Topic`: its name, type and the QoS profile the bag records as offered
(``ros2 bag play`` publishes with it): reliable, keep last; durability transient local for
what is published once (a late subscriber such as RViz still gets it), volatile for streams.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from rosbags.interfaces import (
    Qos,
    QosDurability,
    QosHistory,
    QosLiveliness,
    QosReliability,
    QosTime,
)

from planner.outputs.root_pose import RootPose
from planner.trajectory.samples import Trajectory
from silo4kin.errors import Silo4Error
from viz.export.robot_frames import LinkTransforms

#: ROS 2 distribution whose message definitions (and rosbag2 metadata format) the bag
#: records: Jazzy, the LTS whose ``ros2 bag`` writes metadata version 9 (QoS profiles as YAML
#: with policy names) and MCAP by default; the message types used are the same in Humble.
ROS_DISTRO = "jazzy"
#: The bag's metadata version (rosbag2 of Jazzy).
BAG_VERSION = 9
#: The frame of the plan's world W.
ODOM_FRAME = "odom"
#: Default bag time of the first sample [ns]: 2000-01-01T00:00:00Z, a fixed epoch so that the
#: same run gives the same bag; ROS reads time 0 as "no time", so the default is not 0.
DEFAULT_START_TIME_NS = 946_684_800 * 10**9

_NS = 1_000_000_000


class Topic(NamedTuple):
    """One topic of the bag: name, message type, offered QoS durability and history depth."""

    name: str
    msgtype: str
    durability: QosDurability
    depth: int

    def qos(self) -> Qos:
        """The offered QoS profile: reliable, keep last ``depth``, :attr:`durability`, no
        deadline, lifespan or lease (rosbag2's "infinite": 9223372036 s 854775807 ns)."""
        never = QosTime(9223372036, 854775807)
        return Qos(
            QosHistory.KEEP_LAST,
            self.depth,
            QosReliability.RELIABLE,
            self.durability,
            never,
            never,
            QosLiveliness.AUTOMATIC,
            never,
            False,
        )


_ONCE, _STREAM = QosDurability.TRANSIENT_LOCAL, QosDurability.VOLATILE
JOINT_STATES = Topic("/joint_states", "sensor_msgs/msg/JointState", _STREAM, 10)
TF = Topic("/tf", "tf2_msgs/msg/TFMessage", _STREAM, 100)
TF_STATIC = Topic("/tf_static", "tf2_msgs/msg/TFMessage", _ONCE, 1)
ROBOT_DESCRIPTION = Topic("/robot_description", "std_msgs/msg/String", _ONCE, 1)
JOINT_TRAJECTORY = Topic("/joint_trajectory", "trajectory_msgs/msg/JointTrajectory", _ONCE, 1)
BODY_PATH = Topic("/body_path", "nav_msgs/msg/Path", _ONCE, 1)


def typestore() -> Any:
    """The rosbags typestore of :data:`ROS_DISTRO`."""
    try:
        from rosbags.typesys import Stores, get_typestore
    except ImportError as exc:  # declared dependency; a broken install gets one clear line
        raise Silo4Error(f"the ROS 2 export needs the 'rosbags' package ({exc})") from exc
    return get_typestore(getattr(Stores, f"ROS2_{ROS_DISTRO.upper()}"))


def sample_times_ns(trajectory: Trajectory, start_time_ns: int) -> np.ndarray:
    """Bag time of each sample, (N,) int [ns]: start + (t - t_0), rounded to ns."""
    t = np.asarray(trajectory.t, dtype=float) - float(trajectory.t[0])
    return int(start_time_ns) + np.round(t * 1e9).astype(np.int64)


class Messages:
    """Builds the bag's messages from one typestore (module docstring)."""

    def __init__(self, store: Any) -> None:
        self.store = store
        self.types = store.types

    def time(self, ns: int) -> Any:
        """builtin_interfaces/msg/Time of a bag time [ns]."""
        return self.types["builtin_interfaces/msg/Time"](sec=int(ns) // _NS, nanosec=int(ns) % _NS)

    def header(self, ns: int, frame_id: str) -> Any:
        return self.types["std_msgs/msg/Header"](stamp=self.time(ns), frame_id=frame_id)

    def joint_state(
        self, ns: int, names: list[str], q: np.ndarray, qd: np.ndarray, tau: np.ndarray | None
    ) -> Any:
        """sensor_msgs/msg/JointState: position [rad], velocity [rad/s], effort [N m] or
        empty (no torques)."""
        f64 = np.float64
        return self.types["sensor_msgs/msg/JointState"](
            header=self.header(ns, ""),
            name=names,
            position=np.ascontiguousarray(q, dtype=f64),
            velocity=np.ascontiguousarray(qd, dtype=f64),
            effort=np.ascontiguousarray(tau if tau is not None else [], dtype=f64),
        )

    def transform(
        self, ns: int, parent: str, child: str, position: np.ndarray, orientation_xyzw: np.ndarray
    ) -> Any:
        """geometry_msgs/msg/TransformStamped of ``child`` in ``parent``."""
        t = self.types
        return t["geometry_msgs/msg/TransformStamped"](
            header=self.header(ns, parent),
            child_frame_id=child,
            transform=t["geometry_msgs/msg/Transform"](
                translation=t["geometry_msgs/msg/Vector3"](*(float(x) for x in position)),
                rotation=t["geometry_msgs/msg/Quaternion"](*(float(x) for x in orientation_xyzw)),
            ),
        )

    def tf_message(self, transforms: list[Any]) -> Any:
        return self.types["tf2_msgs/msg/TFMessage"](transforms=transforms)

    def link_transforms(self, ns: int, links: LinkTransforms, k: int) -> list[Any]:
        """Sample ``k`` of ``links`` as TransformStamped messages stamped ``ns``."""
        return [
            self.transform(
                ns,
                parent,
                child,
                links.position_child_in_parent[k, i],
                links.orientation_child_in_parent_xyzw[k, i],
            )
            for i, (parent, child) in enumerate(zip(links.parent_links, links.child_links))
        ]

    def string(self, text: str) -> Any:
        return self.types["std_msgs/msg/String"](data=text)

    def joint_trajectory(self, trajectory: Trajectory) -> Any:
        """trajectory_msgs/msg/JointTrajectory, one point per sample: positions [rad],
        velocities [rad/s], accelerations [rad/s^2], effort [N m] (when the plan has torques),
        time_from_start = t - t_0; header stamp 0 ("start on receipt", the ROS convention)."""
        t = self.types
        Duration, Point = (
            t["builtin_interfaces/msg/Duration"],
            t["trajectory_msgs/msg/JointTrajectoryPoint"],
        )
        offsets = sample_times_ns(trajectory, 0)
        effort = (
            np.asarray(trajectory.tau, dtype=float)
            if trajectory.tau is not None
            else np.empty((len(trajectory), 0))
        )
        f64 = np.float64
        points = [
            Point(
                positions=np.ascontiguousarray(trajectory.q[k], dtype=f64),
                velocities=np.ascontiguousarray(trajectory.qd[k], dtype=f64),
                accelerations=np.ascontiguousarray(trajectory.qdd[k], dtype=f64),
                effort=np.ascontiguousarray(effort[k], dtype=f64),
                time_from_start=Duration(sec=int(offsets[k]) // _NS, nanosec=int(offsets[k]) % _NS),
            )
            for k in range(len(trajectory))
        ]
        return t["trajectory_msgs/msg/JointTrajectory"](
            header=self.header(0, ""), joint_names=list(trajectory.joint_names), points=points
        )

    def body_path(self, stamps_ns: np.ndarray, root_pose: RootPose) -> Any:
        """nav_msgs/msg/Path in ``odom``: the URDF root link's pose at every sample (the
        npz's root pose: planner.outputs.root_pose), each PoseStamped at its sample's time."""
        t = self.types
        position = np.asarray(root_pose.position_root_in_world, dtype=float)
        quaternion = np.asarray(root_pose.orientation_root_in_world_xyzw, dtype=float)
        if position.shape != (len(stamps_ns), 3) or quaternion.shape != (len(stamps_ns), 4):
            raise Silo4Error(
                f"root pose of {len(position)} samples for a trajectory of {len(stamps_ns)}"
            )
        poses = [
            t["geometry_msgs/msg/PoseStamped"](
                header=self.header(int(stamps_ns[k]), ODOM_FRAME),
                pose=t["geometry_msgs/msg/Pose"](
                    position=t["geometry_msgs/msg/Point"](*(float(x) for x in position[k])),
                    orientation=t["geometry_msgs/msg/Quaternion"](
                        *(float(x) for x in quaternion[k])
                    ),
                ),
            )
            for k in range(len(stamps_ns))
        ]
        return t["nav_msgs/msg/Path"](
            header=self.header(int(stamps_ns[0]), ODOM_FRAME), poses=poses
        )
