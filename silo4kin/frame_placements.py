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


class FrameHeights(NamedTuple):
    """What a frame's height needs: ``z_axis_row`` (F, N, 3), row 2 of each frame's rotation
    in the model root frame (a point p of the frame is at z = z_axis_row . p + ``z`` in
    the root frame), and ``z`` (F, N) [m], the frame origin's height, for the F frames and
    N configurations asked."""

    z_axis_row: np.ndarray
    z: np.ndarray


def frame_heights(
    model: pin.Model, axes: np.ndarray, q: np.ndarray, frame_ids: list[int]
) -> FrameHeights:
    """Row 2 of the rotations and the z of the translations of :func:`frame_placements`,
    without the other rows: row 2 of a joint's rotation is its parent's row 2 times the
    joint placement's rotation and its turn, and v R(a, q) = v + sin q (v x a) + (1 - cos q)
    ((v x a) x a), elementwise on (N,) arrays (no (N, 3, 3) products). Equal to
    :func:`frame_placements` to rounding (tests/test_clearance_urdf.py)."""
    q = np.asarray(q, dtype=float).reshape(-1, model.nq)
    n = len(q)
    rows: list[np.ndarray] = [np.broadcast_to(np.array([0.0, 0.0, 1.0]), (n, 3))]
    heights: list[np.ndarray] = [np.zeros(n)]
    for j in range(1, model.njoints):
        a0, a1, a2 = axes[j]
        placement = model.jointPlacements[j]
        parent = rows[model.parents[j]]
        heights.append(heights[model.parents[j]] + parent @ placement.translation)
        v = parent @ placement.rotation  # (N, 3)
        v0, v1, v2 = v[:, 0], v[:, 1], v[:, 2]
        w0, w1, w2 = v1 * a2 - v2 * a1, v2 * a0 - v0 * a2, v0 * a1 - v1 * a0  # v x a
        u0, u1, u2 = w1 * a2 - w2 * a1, w2 * a0 - w0 * a2, w0 * a1 - w1 * a0  # (v x a) x a
        angle = q[:, model.joints[j].idx_q]
        s, c1 = np.sin(angle), 1.0 - np.cos(angle)
        row = np.empty((n, 3))
        row[:, 0] = v0 + s * w0 + c1 * u0
        row[:, 1] = v1 + s * w1 + c1 * u1
        row[:, 2] = v2 + s * w2 + c1 * u2
        rows.append(row)
    z_axis_row = np.empty((len(frame_ids), n, 3))
    z = np.empty((len(frame_ids), n))
    for i, fid in enumerate(frame_ids):
        frame = model.frames[fid]
        j = frame.parentJoint
        z_axis_row[i] = rows[j] @ frame.placement.rotation
        z[i] = heights[j] + rows[j] @ frame.placement.translation
    return FrameHeights(z_axis_row, z)
