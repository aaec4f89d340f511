"""Placements of a fixed-base robot's frames in the model root frame for a batch of joint
configurations, in one vectorised pass over the kinematic tree (no Python loop over samples).

Each joint j of the Pinocchio model is a revolute joint about a constant unit axis a_j in its
own frame: its placement in its parent's is ``jointPlacements[j] * (R(a_j, q_j), 0)`` with
R by Rodrigues' formula, R = I + sin q [a]x + (1 - cos q) [a]x²; the world placement of a
joint is its parent's composed with it, and a frame's is its parent joint's composed with the
frame's placement. The axis of every joint is read once from Pinocchio (the rotation of
``data.liMi`` at q_j = 1 rad). tests/test_clearance_urdf.py checks the result against
``pin.framesForwardKinematics`` for every frame of every robot it loads.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pinocchio as pin

from .errors import RobotDescriptionError


class FramePlacements(NamedTuple):
    """Frames in the model root frame: ``rotation`` (N, F, 3, 3), ``translation`` (N, F, 3)
    [m] for the N configurations and F frames asked."""

    rotation: np.ndarray
    translation: np.ndarray


def joint_axes(model: pin.Model) -> np.ndarray:
    """The unit axis of every joint in its own frame, (njoints, 3) (row 0: the universe,
    zero). Raises RobotDescriptionError for a joint that is not a 1-DoF rotation."""
    data = model.createData()
    axes = np.zeros((model.njoints, 3))
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.nq != 1 or joint.nv != 1:
            raise RobotDescriptionError(
                f"joint {model.names[j]!r} ({joint.shortname()}) is not a 1-DoF revolute joint"
            )
        q = pin.neutral(model)
        q[joint.idx_q] = 1.0
        pin.forwardKinematics(model, data, q)
        motion = model.jointPlacements[j].actInv(data.liMi[j])
        axis = pin.log3(motion.rotation)
        if np.linalg.norm(motion.translation) > 1e-12 or abs(np.linalg.norm(axis) - 1) > 1e-9:
            raise RobotDescriptionError(
                f"joint {model.names[j]!r} ({joint.shortname()}) is not a revolute joint"
            )
        axes[j] = axis
    return axes


def frame_placements(
    model: pin.Model, axes: np.ndarray, q: np.ndarray, frame_ids: list[int]
) -> FramePlacements:
    """The placements in the model root frame of ``frame_ids`` at configurations q (N, nq)
    [rad], for the joint ``axes`` of :func:`joint_axes` (module docstring)."""
    q = np.asarray(q, dtype=float).reshape(-1, model.nq)
    n = len(q)
    rot = np.empty((model.njoints, n, 3, 3))
    pos = np.empty((model.njoints, n, 3))
    rot[0], pos[0] = np.eye(3), 0.0
    for j in range(1, model.njoints):
        a = axes[j]
        k = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
        angle = q[:, model.joints[j].idx_q]
        turn = (
            np.eye(3)
            + np.sin(angle)[:, None, None] * k
            + (1.0 - np.cos(angle))[:, None, None] * (k @ k)
        )  # (N, 3, 3)
        placement = model.jointPlacements[j]
        parent = model.parents[j]
        rot[j] = rot[parent] @ placement.rotation @ turn
        pos[j] = pos[parent] + rot[parent] @ placement.translation
    rotation = np.empty((n, len(frame_ids), 3, 3))
    translation = np.empty((n, len(frame_ids), 3))
    for i, fid in enumerate(frame_ids):
        frame = model.frames[fid]
        j = frame.parentJoint
        rotation[:, i] = rot[j] @ frame.placement.rotation
        translation[:, i] = pos[j] + rot[j] @ frame.placement.translation
    return FramePlacements(rotation, translation)
