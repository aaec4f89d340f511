"""Swing apexes raised over a terrain file's ground, and the clearance of the sampled robot
above it (docs/terrain.md, "Swing and clearance").

A swing foot moves as z(τ) = z_o + (z_f - z_o) s(τ) + h w(τ) (planner/trajectory/sampling.py;
s the x, y blend, w the lift profile normalised to 1 at its apex). Over a terrain that is not
level, each transfer's apex h is the least value >= the workspace's swing height for which
z(τ) >= H(x(τ), y(τ)) + clearance_m w(τ) on APEX_SAMPLES phases of the swing where
w >= MIN_LIFT_FRACTION (H the ground height under the foot): full clearance at the apex,
none at lift-off and touch-down, where the foot stands on its surface.

:func:`terrain_violation` checks every sample of a trajectory: no foot in the ground (a
point foot's contact point not below it, a ball foot's ball not in it:
planner/trajectory/ball_clearance.py),
every insect tibia capsule above it (planner/trajectory/clearance.py: spheres of the
capsule's radius along its axis, measured by TerrainMap.sphere_clearance, which sees the
side faces of boxes and cylinders), and the body's base point and hips at least CLEARANCE_M
from the terrain's solids (the same measure: a hip beside a riser is as close as one above
it).
"""

from __future__ import annotations

import numpy as np

from planner.gaits.steps import Step, StepKind
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.ball_clearance import foot_violation
from planner.trajectory.clearance import tibia_violation
from planner.trajectory.clearance_text import mm_down
from planner.trajectory.profiles import cosine_blend, lift, quintic_blend, smooth_lift
from silo4kin.frames import rotation_z

#: Least clearance of a swing foot at its apex, and of the body, over the ground [m].
CLEARANCE_M = 0.02
#: Phases of a swing where the apex condition is asked.
APEX_SAMPLES = 201
#: The condition is asked where the lift profile is at least this fraction of its apex.
MIN_LIFT_FRACTION = 0.05


def step_swing_heights(
    terrain, steps: tuple[Step, ...], swing_height_m: float, *, smooth: bool
) -> float | np.ndarray:
    """The swing height of each step (S,) [m] over a :class:`TerrainMap` (module
    docstring); ``swing_height_m`` itself, unchanged, over any other terrain."""
    if not isinstance(terrain, TerrainMap):
        return swing_height_m
    tau = np.linspace(0.0, 1.0, APEX_SAMPLES)
    s = (quintic_blend if smooth else cosine_blend)(tau, 1.0).s
    w = (smooth_lift if smooth else lift)(tau, 1.0, 1.0).s
    asked = w >= MIN_LIFT_FRACTION
    s, w = s[asked], w[asked]
    heights = np.full(len(steps), float(swing_height_m))
    for i, step in enumerate(steps):
        f0, f1 = step.foothold_start_in_world, step.foothold_end_in_world
        if step.kind != StepKind.TRANSFER or f0 is None or f1 is None:
            continue
        path = f0[None, :] + (f1 - f0)[None, :] * s[:, None]
        ground = terrain.height_at(path[:, :2])
        with np.errstate(invalid="ignore"):
            need = np.max(np.where(np.isfinite(ground), (ground - path[:, 2]) / w, -np.inf))
        heights[i] = max(float(swing_height_m), float(need) + CLEARANCE_M)
    return heights


def swing_height_at(swing_height_m: float | np.ndarray, step_index: np.ndarray):
    """The swing height [m] of the steps ``step_index``: a number for every step, or the
    per-step heights of :func:`step_swing_heights` picked out."""
    if np.ndim(swing_height_m) == 0:
        return swing_height_m
    return np.asarray(swing_height_m)[step_index]


def terrain_violation(
    legs,
    trajectory,
    terrain,
    position_hip_in_base: np.ndarray,
    *,
    foot_radius_m: float = 0.0,
) -> str | None:
    """The first breach of the module docstring's clearances on ``trajectory`` over a
    :class:`TerrainMap`, in words; None when every sample keeps them (or the terrain is
    not a TerrainMap). ``foot_radius_m``: the radius [m] of the ball centred on each foot
    frame (silo4kin.foot_contact.FootBall.rolling_radius_m; 0: point feet)."""
    if not isinstance(terrain, TerrainMap):
        return None
    reason = foot_violation(legs, trajectory, terrain, foot_radius_m)
    if reason is not None:
        return reason
    reason = tibia_violation(legs, trajectory, terrain)
    if reason is not None:
        return reason
    base = trajectory.position_base_in_world
    yaw = trajectory.yaw_base_in_world
    points = [base]
    for hip in np.asarray(position_hip_in_base, dtype=float):
        points.append(base + np.einsum("nij,j->ni", rotation_z(yaw), hip * [1.0, 1.0, 0.0]))
    body = np.stack(points, axis=1)  # (N, 5, 3)
    above = terrain.sphere_clearance(body.reshape(-1, 3)).reshape(body.shape[:2])
    bad = np.argwhere(above < CLEARANCE_M)
    if bad.size:
        i, _ = bad[0]
        return (
            f"the body is {mm_down(above[i].min())} mm above the terrain (< "
            f"{1e3 * CLEARANCE_M:.0f} mm) at t = {trajectory.t[i]:.2f} s"
        )
    return None
