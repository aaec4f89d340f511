"""Whether a foothold on a terrain file's surfaces keeps its leg's shank off the terrain: the
tibia capsule the physics replay collides (planner/trajectory/tibia_capsules.py) posed with
the foot on the candidate and the body where the transfer places it, measured against the
terrain as a whole capsule (planner/terrain/capsule_distance.py).

Why the foothold search asks it: the run refuses a plan whose capsule comes nearer than
MIN_TIBIA_CLEARANCE_M to a part of a terrain with obstacles (planner/trajectory/clearance.py
ground_contact_violations), but the search on surfaces knew only the edge and wall margins,
which do not know the shank. go2 at h 0.28 m stepping down off the landing of
examples/terrain/stairs.yaml put its RH foot 0.103 m past the landing's edge, on the tread
below; its calf capsule, leaning back from the foot to the knee above the landing, came
0.68 mm from the edge at touch-down and the plan was refused at the end. Asked here, the
search moves the foothold farther past the edge, to the nearest point whose capsule clears.

The capsule is measured at touch-down and over the stance that follows. At touch-down: the
foot on the candidate, the base at the pose the transfer ends at (its z the base's, or for a
transfer whose base moves, the crawl, the height the stance feet with the candidate ask),
each joint from the leg's IK (planner.workspace.reach_check joint_values_of_legs, the
solution the samples take). Over the stance: the body step after a foot steps down lowers the
base by a quarter of the drop (the body follows the stance feet's mean height), and the knee
comes down with it; go2 on a 0.07 m block (benchmarks/bench_capability.py) with the
touch-down check alone put its LH foot where the capsule cleared the block's edge by 3.53 mm
at touch-down and 1.39 mm 1.6 units later, in the body step (the body 31 mm on, 4 mm
lower). Where the builder gives the body's predicted motion (StepBuilder.stance_motion_xy:
its last body step, or the moving transfer's own), the candidate is measured at
STANCE_POSES base poses along the straight line from touch-down to that motion's end at the
height the feet with the candidate ask (a body step's base moves on a straight line; its
profile only times it). A candidate is kept when every pose clears by
MIN_TIBIA_CLEARANCE_M + TIBIA_SEARCH_MARGIN_M (planner/gaits/tibia_reach.py): the swing's end
and the samples between the poses are not measured. Poses out of the leg's reach count as
clear (the search's reach check answers at touch-down, the builder's at each body step).

The run's check (planner/trajectory/clearance.py) still measures every sample: a stance that
differs from the prediction (a last body step shorter than the one before, another foot
stepping down before the body moves) is refused there, naming the leg and the part.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from planner.gaits.tibia_reach import TIBIA_SEARCH_MARGIN_M
from planner.terrain.capsule_distance import (
    capsule_clearance,
    capsule_clearance_by_part,
    capsule_clears,
)
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.clearance import MIN_TIBIA_CLEARANCE_M
from planner.trajectory.clearance_text import mm_down
from planner.trajectory.tibia_capsules import posed_tibia_capsules
from planner.workspace.reach_check import joint_values_of_legs
from silo4kin.frames import rotation_z

#: Least clearance of a searched foothold's tibia capsule from the terrain [m] (module
#: docstring).
SHANK_SEARCH_CLEARANCE_M = MIN_TIBIA_CLEARANCE_M + TIBIA_SEARCH_MARGIN_M
#: Base poses of the stance after touch-down at which a candidate is measured: along the
#: predicted body step, the last at its end (module docstring).
STANCE_POSES = 8
#: Candidates measured (at touch-down and over the stance) per vectorised pass.
STANCE_BATCH = 16


@dataclass(frozen=True, eq=False)
class ShankClearance:
    """The tibia capsule of a leg standing on candidate footholds (module docstring).

    Attributes:
        robot: the robot in its URDF frame (planner.model.PlanningModel.robot: what
            posed_tibia_capsules poses, as the run's check does).
        legs: the planning robot's legs (LegGeometry in B), for the IK.
        terrain: the ground the capsule is measured against.
        min_clearance_m: least clearance a candidate keeps [m].
    """

    robot: Any
    legs: tuple
    terrain: TerrainMap
    min_clearance_m: float = SHANK_SEARCH_CLEARANCE_M

    def clearance(
        self,
        leg: int,
        position_feet_in_world: np.ndarray,
        base_in_world: np.ndarray,
        yaw: float,
    ) -> np.ndarray:
        """Signed clearance (M,) [m] of ``leg``'s tibia capsule from the terrain with its foot
        frame at each of ``position_feet_in_world`` (M, 3) [m] and the base at
        ``base_in_world`` (3,) or one per foot (M, 3) [m], heading ``yaw`` [rad]; NaN where
        the leg does not reach."""
        start, end, radius, rows = self._capsules(leg, position_feet_in_world, base_in_world, yaw)
        out = np.full(len(np.reshape(position_feet_in_world, (-1, 3))), np.nan)
        if rows.size:
            out[rows] = capsule_clearance(self.terrain, start, end, radius)
        return out

    def clear(
        self,
        leg: int,
        position_feet_in_world: np.ndarray,
        base_in_world: np.ndarray,
        yaw: float,
    ) -> np.ndarray:
        """(M,) bool: whether :meth:`clearance` is at least ``min_clearance_m`` (the same
        answer, by planner/terrain/capsule_distance.py capsule_clears); True where the leg
        does not reach (the reach checks answer for those: the search's at touch-down, the
        builder's at each body step)."""
        start, end, radius, rows = self._capsules(leg, position_feet_in_world, base_in_world, yaw)
        out = np.ones(len(np.reshape(position_feet_in_world, (-1, 3))), dtype=bool)
        if rows.size:
            out[rows] = capsule_clears(self.terrain, start, end, radius, self.min_clearance_m)
        return out

    def first_clear(
        self,
        leg: int,
        position_feet_in_world: np.ndarray,
        touchdown_in_world: np.ndarray,
        stance_end_in_world: np.ndarray | None,
        yaw: float,
    ) -> int | None:
        """The index of the first foothold of ``position_feet_in_world`` (M, 3) [m] whose
        capsule clears at touch-down, the base at ``touchdown_in_world`` (M, 3) [m], and, with
        ``stance_end_in_world`` (M, 3) [m], at STANCE_POSES poses evenly along the straight
        line on to it (the body step that follows); None when none does. Asked of
        STANCE_BATCH candidates at a time, in order."""
        feet = np.asarray(position_feet_in_world, dtype=float).reshape(-1, 3)
        touchdown = np.asarray(touchdown_in_world, dtype=float).reshape(-1, 3)
        f = np.zeros(1)
        end = touchdown
        if stance_end_in_world is not None:
            f = np.arange(STANCE_POSES + 1) / STANCE_POSES
            end = np.asarray(stance_end_in_world, dtype=float).reshape(-1, 3)
        for lo in range(0, len(feet), STANCE_BATCH):
            a, b = touchdown[lo : lo + STANCE_BATCH], end[lo : lo + STANCE_BATCH]
            bases = a[:, None, :] + f[None, :, None] * (b - a)[:, None, :]  # (R, K, 3)
            at = np.repeat(feet[lo : lo + STANCE_BATCH], len(f), axis=0)
            clear = self.clear(leg, at, bases.reshape(-1, 3), yaw).reshape(len(a), len(f))
            good = np.flatnonzero(np.all(clear, axis=1))
            if good.size:
                return lo + int(good[0])
        return None

    def describe(
        self,
        leg: int,
        position_foot_in_world: np.ndarray,
        touchdown_in_world: np.ndarray,
        stance_end_in_world: np.ndarray | None,
        yaw: float,
    ) -> str:
        """Where the capsule of ``leg`` with its foot at ``position_foot_in_world`` (3,) [m]
        comes nearest the terrain over the poses :meth:`first_clear` measures (touch-down
        ``touchdown_in_world`` (3,), the body step on to ``stance_end_in_world`` (3,) or
        None [m]), for a refusal: "brings its tibia capsule -5.3 mm from box 0 at
        touch-down"."""
        touchdown = np.asarray(touchdown_in_world, dtype=float)
        end = touchdown if stance_end_in_world is None else np.asarray(stance_end_in_world)
        f = np.arange(STANCE_POSES + 1) / STANCE_POSES if stance_end_in_world is not None else [0]
        bases = touchdown + np.asarray(f, dtype=float)[:, None] * (end - touchdown)
        foot = np.tile(np.asarray(position_foot_in_world, dtype=float), (len(bases), 1))
        clearance = self.clearance(leg, foot, bases, yaw)
        if not np.isfinite(clearance).any():
            return "leaves its leg's reach in the body step after touch-down"
        k = int(np.nanargmin(clearance))
        start, stop, radius, _ = self._capsules(leg, foot[k : k + 1], bases[k], yaw)
        part = self.terrain.part_names()[
            int(np.argmin(capsule_clearance_by_part(self.terrain, start, stop, radius)[:, 0]))
        ]
        when = "at touch-down" if k == 0 else "in the body step after touch-down"
        return f"brings its tibia capsule {mm_down(clearance[k])} mm from {part} {when}"

    def _capsules(self, leg, position_feet_in_world, base_in_world, yaw) -> tuple:  # noqa: ANN001
        """(start (R, 3), end (R, 3), radius (R,) [m], rows (R,)): ``leg``'s tibia capsule
        for the rows of the feet (M, 3) [m] (bases (3,) or (M, 3) [m]) the leg reaches."""
        feet = np.asarray(position_feet_in_world, dtype=float).reshape(-1, 3)
        base = np.broadcast_to(np.asarray(base_in_world, dtype=float), feet.shape)
        in_base = (rotation_z(float(yaw)).T @ (feet - base).T).T
        q_leg, reached = joint_values_of_legs(self.legs, np.full(len(feet), leg), in_base)
        rows = np.flatnonzero(reached & np.all(np.isfinite(q_leg), axis=1))
        if not rows.size:
            return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), rows
        n_legs = len(self.legs)
        q = np.zeros((rows.size, n_legs, 3))
        q[:, leg] = q_leg[rows]
        start, end, radius = posed_tibia_capsules(
            self.robot, q.reshape(rows.size, 3 * n_legs), base[rows], np.full(rows.size, float(yaw))
        )
        return start[:, leg], end[:, leg], np.full(rows.size, radius[leg]), rows


def shank_clearance_for(robot, legs, terrain) -> ShankClearance | None:  # noqa: ANN001
    """The shank check of the foothold search on ``terrain``: None unless it is a
    :class:`TerrainMap` with obstacles (boxes, cylinders, a height map), the terrains the
    run's capsule check measures (planner/trajectory/tibia_capsules.py)."""
    if not isinstance(terrain, TerrainMap) or not terrain.obstacles():
        return None
    return ShankClearance(robot, tuple(legs), terrain)
