"""The URDF root link's pose in the world along a trajectory, from the planner's body frame.

The planner walks the body frame B_c: origin at the body (base link) CoG, axes those of the
URDF root link, the body level (roll = pitch = 0) and turned by the yaw about world z
(``Trajectory.position_base_in_world``, ``yaw_base_in_world``). The URDF root link (the
floating base of Pinocchio, MuJoCo or ROS) sits ``position_body_com_in_root`` (the origin of
B_c in the root frame, (3,) [m], ``planner.model.PlanningModel``) away from it, so

    position_root_in_world = position_base_in_world - R_z(yaw) @ position_body_com_in_root
    orientation_root_in_world = R_z(yaw)   (quaternion x, y, z, w = 0, 0, sin(yaw/2), cos(yaw/2))

:func:`root_pose_in_world` is the one implementation; trajectory.csv (``root_*`` columns),
trajectory.npz and the ROS 2 export read it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from planner.trajectory.samples import Trajectory


class RootPose(NamedTuple):
    """The URDF root link's pose in the world frame W, one row per sample.

    Attributes:
        position_root_in_world: (N, 3) [m].
        orientation_root_in_world_xyzw: (N, 4) unit quaternions, scalar last.
    """

    position_root_in_world: np.ndarray
    orientation_root_in_world_xyzw: np.ndarray


def root_pose_in_world(trajectory: Trajectory, position_body_com_in_root: np.ndarray) -> RootPose:
    """The root link's pose along ``trajectory`` (module docstring, level body).

    Args:
        trajectory: samples of the body frame B_c (``position_base_in_world`` (N, 3) [m],
            ``yaw_base_in_world`` (N,) [rad]).
        position_body_com_in_root: the origin of B_c in the URDF root frame, (3,) [m].
    """
    offset = np.asarray(position_body_com_in_root, dtype=float).reshape(3)
    yaw = np.asarray(trajectory.yaw_base_in_world, dtype=float)
    cos, sin = np.cos(yaw), np.sin(yaw)
    # R_z(yaw) @ offset, row by row; z is unchanged by a turn about z
    offset_in_world = np.column_stack(
        [
            cos * offset[0] - sin * offset[1],
            sin * offset[0] + cos * offset[1],
            np.full_like(yaw, offset[2]),
        ]
    )
    position = np.asarray(trajectory.position_base_in_world, dtype=float) - offset_in_world
    zeros = np.zeros_like(yaw)
    quaternion = np.column_stack([zeros, zeros, np.sin(yaw / 2.0), np.cos(yaw / 2.0)])
    return RootPose(position, quaternion)
