"""When the animation's keys fall: the playback times of a plan [s] (its inputs checked) and
the samples kept for playback, about ``fps`` per second of animation time, at most
``max_frames``."""

from __future__ import annotations

import math

import numpy as np

from planner.trajectory.samples import Trajectory
from silo4kin.errors import Silo4Error
from silo4kin.robot import Robot

#: Playback key rate [frames per second of animation time]. three.js interpolates linearly
#: between keys; joint motions of a 1 s leg transfer are smooth at 25 keys per second.
DEFAULT_FPS = 25.0
#: Cap on animation keys: ~171 bytes per frame (17 float32 values + 15 key-time arrays,
#: base64) -> 12000 frames ~ 2.1 MB, plus ~0.85 MB of viewer JavaScript: < 4 MB.
DEFAULT_MAX_FRAMES = 12000


def playback_frame_indices(
    t_s: np.ndarray, fps: float = DEFAULT_FPS, max_frames: int = DEFAULT_MAX_FRAMES
) -> np.ndarray:
    """Sample indices to keep for playback: about ``fps`` per second, at most ``max_frames``.

    Args:
        t_s: playback times [s], shape (N,), strictly increasing.

    Returns:
        indices into t_s, shape (K,), strictly increasing, first 0 and last N - 1,
        K <= min(N, max_frames); the kept samples are the nearest to a uniform time grid.
    """
    n = t_s.shape[0]
    duration = float(t_s[-1] - t_s[0])
    k = int(min(n, max_frames, math.ceil(duration * fps) + 1))
    k = max(k, 2)
    grid = np.linspace(t_s[0], t_s[-1], k)
    right = np.clip(np.searchsorted(t_s, grid), 1, n - 1)
    nearer_left = (grid - t_s[right - 1]) <= (t_s[right] - grid)
    idx = np.where(nearer_left, right - 1, right)
    idx[0], idx[-1] = 0, n - 1
    return np.unique(idx)


def playback_times(
    robot: Robot, trajectory: Trajectory, unit_time_s: float | None, max_frames: int, fps: float
) -> np.ndarray:
    """Check the inputs; return the playback times [s], shape (N,)."""
    if len(trajectory) < 1:
        raise Silo4Error("an animation needs at least 1 sample, the trajectory has none")
    missing = sorted(set(robot.joint_names) - set(trajectory.joint_names))
    if missing:
        raise Silo4Error(
            f"the trajectory does not belong to robot {robot.name!r}: its joints "
            f"{list(trajectory.joint_names)} lack {missing}"
        )
    if not (isinstance(max_frames, int) and max_frames >= 2):
        raise Silo4Error(f"max_frames={max_frames!r}; it must be an integer >= 2")
    if not (math.isfinite(fps) and fps > 0):
        raise Silo4Error(f"fps={fps!r}; it must be a positive number of frames per second")
    if unit_time_s is None:
        t_s = np.asarray(trajectory.t, dtype=float)
    else:
        if not (
            isinstance(unit_time_s, (int, float)) and math.isfinite(unit_time_s) and unit_time_s > 0
        ):
            raise Silo4Error(
                f"unit_time_s={unit_time_s!r}; it must be a positive number of "
                "seconds per time unit"
            )
        t_s = np.asarray(trajectory.time_units, dtype=float) * float(unit_time_s)
    for name in ("q", "position_base_in_world", "yaw_base_in_world", "position_foot_in_world"):
        if not np.all(np.isfinite(getattr(trajectory, name))):
            raise Silo4Error(f"trajectory.{name} holds NaN or infinite values")
    if not np.all(np.isfinite(t_s)) or np.any(np.diff(t_s) <= 0):
        raise Silo4Error("trajectory times must be finite and strictly increasing")
    return t_s - t_s[0]
