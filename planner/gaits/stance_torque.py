"""Whether a foothold the search on a terrain file's surfaces moved lets its leg stand within
the joints' effort budget: the static torques (q̇ = q̈ = 0, eq A.14 + A.34) of the stance
poses the candidate makes, computed as the run's limit check computes them.

Why the foothold search asks it: the run refuses a plan whose static torque breaks the effort
budget (headroom x URDF effort, planner/trajectory/limits.py: "no unit time helps"), but the
search on surfaces knew the ground, the reach and the shank, not the load. go2 at h 0.28 m
before a 0.05 m block 0.6 m deep (examples/terrain/block.yaml lowered, then go2's
scenario): RH's nominal foothold lay at the block's near edge; the nearest valid point was
on the block, 0.215 m ahead of the hip and crowding RF's foot, and while RF swung RH carried
62 % of the weight on that lever: RR_thigh_joint 22.03 N m standing still against a budget
of 20.14 N m (0.85 x 23.7), the plan refused. A point 0.12 m back, on the floor, carries half
the weight under the hip.

The poses: at touch-down (the base where the transfer places it) and at the end of the body
motion the builder predicts after it (planner/gaits/surface_footholds.py _stance_end), every
foot at its foothold, each leg's joints from its IK (the solution the samples take). At each
pose, the supports the candidate's leg can be part of: all four feet, and each three of them
with the candidate (while the fourth swings) whose load stays inside the support triangle;
a triangle the load leaves is a support no statically stable swing uses. The torques are
silo4kin.joint_torques.joint_torques with the preset's load (the legs' own weight in the
motion part, the reactions of eq A.30-A.33 in the support part; equal to the run's to 1e-6
N m at a real plan's three-foot samples, tests/test_stance_torque.py): a candidate keeps
the budget when its own leg's joints do in every such support at both poses.

Where it applies, and why only there: a preference among the candidates the other rules
allow, asked only of a foothold the search moves (the gait's nominal foothold, when valid,
is taken as before: the workspace placed it, and the run checks it), nearest first. It is
not a rule, because the body shifts before each swing and the gait swings the other legs
one at a time, at bases this prediction does not know: the three triangles at touch-down
overstate the load (SILO4 at h 0.4 m on gap.yaml: 15,600 of 16,200 candidates over its
hip-pitch budget in some triangle, where its plan keeps 0.85 of the effort on every
sample). So when no candidate keeps the budget the nearest valid one is taken, and the
run's check, on every sample, decides.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import Any

import numpy as np

from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.limits import urdf_limits
from planner.workspace.reach_check import joint_values_of_legs
from silo4kin.errors import Silo4Error
from silo4kin.frames import rotation_z
from silo4kin.joint_torques import joint_torques


def supports_with(leg: int, n_legs: int = 4, swinging: int | None = None) -> np.ndarray:
    """Stance flags (S, n_legs) of the supports ``leg`` can be part of: all feet, then each
    set of n_legs - 1 feet holding ``leg`` (the others' swings), in leg order; with
    ``swinging``, only the set without that leg after all feet."""
    rows = [np.ones(n_legs, dtype=bool)]
    for kept in combinations(range(n_legs), n_legs - 1):
        if leg in kept and (swinging is None or swinging not in kept):
            row = np.zeros(n_legs, dtype=bool)
            row[list(kept)] = True
            rows.append(row)
    return np.array(rows)


@dataclass(frozen=True, eq=False)
class StanceTorque:
    """The static torques of the stances a candidate foothold makes (module docstring).

    Attributes:
        robot: the robot in its URDF frame (planner.model.PlanningModel.robot: what the
            run's torques use).
        legs: the planning robot's legs (LegGeometry in B, B at the body CoG), for the IK.
        budget_nm: the effort budget of the robot's joints, (12,) [N m] in its joint order.
        load: the load the feet carry ("body" or "total", the preset's).
    """

    robot: Any
    legs: tuple
    budget_nm: np.ndarray
    load: str = "total"

    def torques(
        self,
        leg: int,
        position_feet_in_world: np.ndarray,
        bases_in_world: np.ndarray,
        yaw: float,
        feet_in_world: np.ndarray,
        next_leg: int | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """(static torques (M, P, S, 12) [N m], used (M, P, S) bool) of ``leg``'s foot frame at
        each of ``position_feet_in_world`` (M, 3) [m] with the other feet at
        ``feet_in_world`` (4, 3) [m], the base at each of ``bases_in_world`` (M, P, 3) [m]
        (the poses), heading ``yaw`` [rad], for the S supports of :func:`supports_with`
        (``next_leg``: the leg the gait swings next, when known); ``used`` is False where the
        load leaves the support or a leg does not reach."""
        cand = np.asarray(position_feet_in_world, dtype=float).reshape(-1, 3)
        bases = np.asarray(bases_in_world, dtype=float).reshape(len(cand), -1, 3)
        m, p = bases.shape[:2]
        n_legs = len(self.legs)
        feet = np.broadcast_to(np.asarray(feet_in_world, dtype=float), (m, p, n_legs, 3)).copy()
        feet[:, :, leg] = cand[:, None, :]
        rel_world = feet - bases[:, :, None, :]
        in_base = rel_world @ rotation_z(float(yaw))  # R^T v for row vectors: v R
        flat = in_base.reshape(-1, 3)
        q_legs, reached = joint_values_of_legs(self.legs, np.tile(np.arange(n_legs), m * p), flat)
        reached = reached.reshape(m * p, n_legs).all(axis=1) & np.all(
            np.isfinite(q_legs.reshape(m * p, -1)), axis=1
        )
        supports = supports_with(leg, n_legs, next_leg)
        s = len(supports)
        tau = np.full((m * p, s, 3 * n_legs), np.nan)
        used = np.zeros((m * p, s), dtype=bool)
        rows = np.flatnonzero(reached)
        if rows.size:
            q = np.repeat(q_legs.reshape(m * p, 3 * n_legs)[rows], s, axis=0)
            at = np.repeat(in_base.reshape(m * p, n_legs, 3)[rows], s, axis=0)
            contact = np.tile(supports, (rows.size, 1))
            zeros = np.zeros_like(q)
            try:
                jt = joint_torques(
                    self.robot,
                    q,
                    zeros,
                    zeros,
                    contact,
                    position_foot_in_base=at + self.robot.position_body_com_in_base,
                    load=self.load,  # type: ignore[arg-type]
                )
            except Silo4Error:  # collinear feet: no support to judge
                return tau.reshape(m, p, s, -1), used.reshape(m, p, s)
            tau[rows] = jt.total.reshape(rows.size, s, -1)
            used[rows] = ~jt.unloadable.reshape(rows.size, s)
        return tau.reshape(m, p, s, -1), used.reshape(m, p, s)

    def keeps(
        self,
        leg: int,
        position_feet_in_world: np.ndarray,
        bases_in_world: np.ndarray,
        yaw: float,
        feet_in_world: np.ndarray,
        next_leg: int | None = None,
    ) -> np.ndarray:
        """(M,) bool: whether the joints of ``leg`` keep their budget in every support
        :meth:`torques` uses at every pose (``next_leg`` as there; True where no support is
        used: the other rules answer)."""
        tau, used = self.torques(
            leg, position_feet_in_world, bases_in_world, yaw, feet_in_world, next_leg
        )
        joints = slice(3 * leg, 3 * leg + 3)
        over = np.any(np.abs(tau[..., joints]) > self.budget_nm[joints], axis=-1) & used
        return ~np.any(over, axis=(1, 2))


def stance_torque_for(  # noqa: ANN001
    robot, legs, terrain, headroom: float | tuple[float, ...], load: str
) -> StanceTorque | None:
    """The torque preference of the foothold search on ``terrain`` (a TerrainMap: the
    terrains whose footholds are searched; None otherwise), the budget ``headroom`` x URDF
    effort (the preset's torque headroom) under the preset's ``load`` ("body" or
    "total")."""
    if not isinstance(terrain, TerrainMap):
        return None
    _, effort = urdf_limits(robot)
    return StanceTorque(robot, tuple(legs), effort * np.asarray(headroom, dtype=float), str(load))
