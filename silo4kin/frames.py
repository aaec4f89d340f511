"""Rotations about the vertical axis: the one R_z of the toolkit (eq 4.3 / 5.29).

The body stays level in every plan, so a change between the world frame W and the base
frame B is a yaw about z (docs/notation.md).
"""

from __future__ import annotations

import numpy as np


def rotation_z(yaw: float | np.ndarray) -> np.ndarray:
    """Rotation about z by ``yaw`` [rad]: (3, 3) for a scalar, (N, 3, 3) for yaw (N,).

    Maps a vector in B to W for ``yaw = yaw_base_in_world``; its transpose maps W to B.
    """
    yaw_arr = np.asarray(yaw, dtype=float)
    if yaw_arr.ndim == 0:
        c, s = float(np.cos(yaw_arr)), float(np.sin(yaw_arr))
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    c, s = np.cos(yaw_arr), np.sin(yaw_arr)
    out = np.zeros(yaw_arr.shape + (3, 3))
    out[..., 0, 0], out[..., 0, 1] = c, -s
    out[..., 1, 0], out[..., 1, 1] = s, c
    out[..., 2, 2] = 1.0
    return out


def homogeneous(rotation: np.ndarray, translation=(0.0, 0.0, 0.0)) -> np.ndarray:
    """The 4x4 transform of ``rotation`` (3, 3) and ``translation`` (3,) [m]."""
    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b of 3-vectors along the last axis, broadcast like ``np.cross`` and equal to it
    bit for bit (the same products and differences, cp0 = a1 b2 - a2 b1 ...), without its
    axis moves: ~5x faster on the few rows the mammal legs' kinematics pass (go2's height
    search called np.cross 465 k times)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out
