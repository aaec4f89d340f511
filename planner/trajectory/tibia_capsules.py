"""Every leg's tibia capsule, the shape the physics replay collides (silo4sim/model.py, from
silo4kin.collision_shapes.tibia_capsules), posed along a plan and measured against a
terrain map as a whole capsule (planner/terrain/capsule_distance.py).

Why a check of its own: the URDF-shape clearance (planner/trajectory/clearance.py
``clearance_of_poses``) measures a link's own collision shapes, but MuJoCo replaces every
tibia's URDF shapes by this capsule (silo4sim/urdf_collisions.py); and the insect capsule
rule (``tibia_clearance``) holds insect legs only. go2 at h 0.28 m on a 0.07 m block
(benchmarks/bench_capability.py) planned its LH foot 0.104 m past the block's far edge: the
calf meshes cleared the block by 19.9 mm, while the capsule lay on the edge in stance from
t = 28.86 s to 31.21 s and MuJoCo put RL_calf on the block (slip 5.3 mm). Over level ground
the check is not asked, so flat-ground plans are judged exactly as before: the insect rule
holds insect tibias there; a mammal's capsule on level ground is not held (not measured yet).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from planner.terrain.capsule_distance import capsule_clearance, capsule_clearance_by_part
from planner.trajectory.clearance_text import mm_down

#: The capsule stops this far short of the foot frame [m] (SimSettings.tibia_clearance_m;
#: planner/trajectory/clearance.py TIBIA_FOOT_GAP_M, which imports this module: tested equal).
TIBIA_FOOT_GAP_M = 0.05


class _BodyPose(NamedTuple):
    """The two fields of a Trajectory that root_pose_in_world reads."""

    position_base_in_world: np.ndarray
    yaw_base_in_world: np.ndarray


def posed_tibia_capsules(robot, q, position_base_in_world, yaw_base_in_world):  # noqa: ANN001, ANN201
    """(start (N, 4, 3), end (N, 4, 3) [m] in W, radius (4,) [m]) of each leg's tibia capsule
    at joints q (N, 12) [rad], the planning frame's position (N, 3) [m] and yaw (N,) [rad],
    the body level (the URDF root's pose: planner.outputs.root_pose, as clearance_of_poses)."""
    from planner.outputs.root_pose import root_pose_in_world
    from silo4kin.collision_shapes import tibia_capsules
    from silo4kin.frame_placements import frame_placements, joint_axes

    memo = robot._memo
    if "tibia_capsules" not in memo:
        memo["tibia_capsules"] = tibia_capsules(robot, TIBIA_FOOT_GAP_M)
    if "joint_axes" not in memo:
        memo["joint_axes"] = joint_axes(robot.model)
    capsules = memo["tibia_capsules"]
    yaw = np.asarray(yaw_base_in_world, dtype=float).reshape(-1)
    base = np.asarray(position_base_in_world, dtype=float).reshape(-1, 3)
    com_in_root = np.asarray(robot.position_body_com_in_base, dtype=float)
    root = root_pose_in_world(_BodyPose(base, yaw), com_in_root).position_root_in_world
    q_full = np.zeros((len(yaw), robot.model.nq))
    q_full[:, robot.q_index] = np.asarray(q, dtype=float).reshape(len(yaw), -1)
    rotation, translation = frame_placements(
        robot.model, memo["joint_axes"], q_full, [c.frame_id for c in capsules]
    )
    c, s = np.cos(yaw), np.sin(yaw)
    turn = np.zeros((len(yaw), 3, 3))  # R_z(yaw): the root frame's heading in W
    turn[:, 0, 0], turn[:, 0, 1], turn[:, 1, 0], turn[:, 1, 1], turn[:, 2, 2] = c, -s, s, c, 1.0
    ends = []
    for name in ("start_in_link", "end_in_link"):
        local = np.stack([getattr(cap, name) for cap in capsules])  # (4, 3)
        in_root = np.einsum("nkij,kj->nki", rotation, local) + translation
        ends.append(root[:, None, :] + np.einsum("nij,nkj->nki", turn, in_root))
    return ends[0], ends[1], np.array([cap.radius_m for cap in capsules])


def tibia_capsule_clearance(robot, trajectory, terrain) -> np.ndarray:  # noqa: ANN001
    """Signed clearance [m] of each leg's tibia capsule from the TerrainMap ``terrain`` (the
    least over its parts) at every sample of ``trajectory``, shape (N, 4)."""
    start, end, radius = posed_tibia_capsules(
        robot, trajectory.q, trajectory.position_base_in_world, trajectory.yaw_base_in_world
    )
    n, legs = start.shape[:2]
    flat = capsule_clearance(terrain, start.reshape(-1, 3), end.reshape(-1, 3), np.tile(radius, n))
    return flat.reshape(n, legs)


def tibia_capsule_violation(
    robot,  # noqa: ANN001
    trajectory,  # noqa: ANN001
    terrain,  # noqa: ANN001
    min_clearance_m: float,
) -> str | None:
    """One line naming the leg, its tibia link, the terrain part, stance or swing and the time
    of the first sample where a tibia capsule comes nearer than ``min_clearance_m`` [m] to a
    part of the TerrainMap ``terrain``; None when none does, or on
    a terrain that is not a TerrainMap or has only a floor (module docstring)."""
    from planner.terrain.terrain_map import TerrainMap
    from silo4kin.collision_shapes import tibia_capsules

    if not isinstance(terrain, TerrainMap) or not terrain.obstacles():
        return None
    clearance = tibia_capsule_clearance(robot, trajectory, terrain)  # (N, 4)
    low = np.argwhere(clearance < min_clearance_m)
    if not low.size:
        return None
    i, k = (int(v) for v in low[0])
    worst = int(np.argmin(clearance[:, k]))
    start, end, radius = posed_tibia_capsules(
        robot,
        trajectory.q[i : i + 1],
        trajectory.position_base_in_world[i : i + 1],
        trajectory.yaw_base_in_world[i : i + 1],
    )
    by_part = capsule_clearance_by_part(terrain, start[0, k], end[0, k], radius[k])[:, 0]
    part = terrain.part_names()[int(np.argmin(by_part))]
    capsule = tibia_capsules(robot, TIBIA_FOOT_GAP_M)[k]

    def state(row: int) -> str:
        return "stance" if trajectory.contact[row, k] else "swing"

    return (
        f"{terrain.label()}: the tibia of {capsule.leg} ({capsule.link}, the physics model's "
        f"capsule) comes within {1e3 * min_clearance_m:g} mm of {part} at t = "
        f"{trajectory.time_units[i]:.2f} units ({state(i)}), least "
        f"{mm_down(clearance[worst, k])} mm at t = {trajectory.time_units[worst]:.2f} units "
        f"({state(worst)})"
    )
