"""Where a stability shift may put the CoM so that the three stance legs keep their effort
budget: load-share caps, half-planes in the CoM plane (issue 21).

A stance foot's static joint torque is τ = G(q) - F J_z(q)ᵀ (silo4kin.joint_torques: its
links' gravity with the hip fixed, eq A.14, plus the support part Jᵀ(-F), eq A.34), F the
foot's upward reaction. With the budget b (the preset's headroom x URDF effort) each joint
bounds F to an interval, and so the foot's share s = F / (m g) of the whole robot's weight;
on three feet the share is the CoM's barycentric coordinate of that foot, affine in the CoM:
s_i(p) = d_i(p) / h_i, d_i the distance of p from the edge of the other two feet and h_i the
foot's own distance from it. So at given joint values "foot i keeps its budget" is a pair of
half-planes parallel to the opposite edge (:meth:`LoadCaps.keeps` tests them, the CoM's
spread r over the swing, the builder's com_spread, kept inside).

The builder's shift (planner/gaits/builder.py _shifted_base) took the point nearest the CoM
with the margin: near the edge of the two feet it approaches, each carrying half the weight
on its lever, which is where SILO4's plans broke the budget (a rear foot a half stride
behind its centre, RH_hip_pitch 1.16 x its budget at h 0.22 m). Now, where the stance legs
break it there (or a lift that needs no shift would), it takes the point nearest the CoM,
among rings around that one with the margin (StepBuilder._capped), whose own base keeps
them: the levers move with the body (the joint values are those of the stance feet seen
from each candidate base), so the caps are taken per candidate, not once. Where the base so
found still breaks the budget at a point of the swing's CoM (:meth:`LoadCaps.stance_torques`,
the split the run's check makes), the whole support triangle is searched
(StepBuilder._capped_base), and where no point keeps both the margin and the budget the
builder refuses naming the joint and the step (OverBudget). The other gaits choosing a CoM
point keep the budget too: a fold (planner/gaits/fold.py), a spin's leg order
(planner/gaits/creep_spin.py) and the crawl's moving transfers (planner/gaits/sway.py
capped_sway_end).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from planner.gaits.tibia_reach import tibias_clear
from planner.trajectory.limits import urdf_limits
from planner.trajectory.profiles import cosine_blend, lift
from planner.workspace.reach_check import joint_values_of_legs, reachable_in_limits_of_legs
from silo4kin.frames import rotation_z
from silo4kin.joint_torques import motion_torques
from silo4kin.legs import jacobian
from silo4kin.robot import STANDARD_GRAVITY

#: Points of a swing's path :meth:`LoadCaps.placeable` checks, τ evenly spaced in [0, 1].
SWING_PATH_POINTS = 9


def share_bounds(
    gravity_nm: np.ndarray, jz: np.ndarray, budget_nm: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(F_lo, F_hi) (N,) [N]: the reactions F of one foot whose joints keep |G - F J_z| <=
    b, from the leg's gravity torques G (N, 3) [N m], J's z row (N, 3) [m] and budget b (3,)
    [N m]; F_lo > F_hi where none does."""
    g, j = np.atleast_2d(gravity_nm), np.atleast_2d(jz)
    b = np.asarray(budget_nm, dtype=float)[None]
    tiny = np.abs(j) < 1e-12
    safe = np.where(tiny, 1.0, j)
    a, c = (g - b) / safe, (g + b) / safe
    lo = np.where(tiny, np.where(np.abs(g) > b, np.inf, -np.inf), np.minimum(a, c))
    hi = np.where(tiny, np.where(np.abs(g) > b, -np.inf, np.inf), np.maximum(a, c))
    return np.maximum(lo.max(axis=1), 0.0), hi.min(axis=1)


@dataclass(frozen=True, eq=False)
class LoadCaps:
    """The load-share caps of a robot (module docstring).

    Attributes:
        robot: the robot in the planning frame (legs in B; its Pinocchio model for G).
        budget_nm: the joints' effort budget (12,) [N m].
        weight_n: the whole robot's weight [N] (load "total": the feet carry everything).
        workspace: the plan's Workspace, for the tibia rule of :meth:`placeable` (None:
            reach and joint limits only).
    """

    robot: Any
    budget_nm: np.ndarray
    weight_n: float
    workspace: Any = None

    def placeable(
        self,
        bases: np.ndarray,
        yaw: float,
        feet_in_world: np.ndarray,
        swing: tuple[int, np.ndarray] | None = None,
    ) -> np.ndarray:
        """(N,) bool: whether every foot at ``feet_in_world`` (4, 3) [m] stays reachable
        within its joint limits, and an insect leg's tibia clear of the ground
        (planner/gaits/tibia_reach.py), with the base at each of ``bases`` (N, 3) [m] and
        heading ``yaw`` [rad]: a base the shift may move to for the caps keeps the rules the
        nearest shift keeps (a base chosen for the torques alone put a hip yaw 3 mrad past
        its limit and a tibia 1.8 mm above the ground). With ``swing`` (leg, foothold (3,)
        [m]) and a workspace, that leg's swing path from its foot in ``feet_in_world`` too,
        at SWING_PATH_POINTS points (the cosine blend and eq 5.4 lift by the workspace's
        swing height, planner/trajectory/sampling.py) within its joint limits: a base 0.2 m
        from the nearest put mantis's lifted LF foot past its arm2_lift limit (1.2308 rad,
        limit 1.2217 rad)."""
        legs = tuple(self.robot.legs)
        bases = np.atleast_2d(np.asarray(bases, dtype=float))
        n_legs = len(legs)
        feet = np.asarray(feet_in_world, dtype=float)
        rot = rotation_z(float(yaw))
        rel = (feet[None] - bases[:, None, :]) @ rot
        idx = np.tile(np.arange(n_legs), len(bases))
        pts = rel.reshape(-1, 3)
        ok = np.asarray(reachable_in_limits_of_legs(legs, idx, pts), dtype=bool)
        if self.workspace is not None:
            ok &= np.asarray(tibias_clear(legs, self.workspace, idx, pts), dtype=bool)
        out = np.asarray(ok.reshape(len(bases), n_legs).all(axis=1), dtype=bool)
        if swing is None or self.workspace is None:
            return out
        leg, foothold = swing
        tau = np.linspace(0.0, 1.0, SWING_PATH_POINTS)
        start = feet[leg]
        path = (
            start + (np.asarray(foothold, dtype=float) - start) * cosine_blend(tau, 1.0).s[:, None]
        )
        path[:, 2] += lift(tau, 1.0, float(self.workspace.swing_height_m)).s
        rel = (path[None] - bases[:, None, :]) @ rot  # (N, M, 3)
        ok = reachable_in_limits_of_legs(
            legs, np.full(rel.shape[0] * rel.shape[1], leg), rel.reshape(-1, 3)
        )
        return out & np.asarray(ok, dtype=bool).reshape(rel.shape[:2]).all(axis=1)

    def gravity_torques(self, q: np.ndarray) -> np.ndarray:
        """The legs' gravity torques G(q) (N, 12) [N m], hips fixed (eq A.14 at rest:
        silo4kin.joint_torques.motion_torques at q̇ = q̈ = 0), for q (N, 12) [rad]."""
        q = np.atleast_2d(np.asarray(q, dtype=float))
        zeros = np.zeros_like(q)
        return motion_torques(self.robot, q, zeros, zeros)

    def keeps(
        self,
        leg: int,
        bases: np.ndarray,
        yaw: float,
        feet_in_world: np.ndarray,
        points: np.ndarray,
        radius_m: float,
    ) -> np.ndarray:
        """(N,) bool: whether the three stance legs keep their budget while ``leg`` swings,
        the base at each of ``bases`` (N, 3) [m] (heading ``yaw`` [rad]) and the whole-robot
        CoM anywhere within ``radius_m`` [m] of each of ``points`` (N, 2) [m] in W, the feet
        at ``feet_in_world`` (4, 3) [m]; False where a stance foot is out of reach."""
        stance = [k for k in range(4) if k != leg]
        feet = np.asarray(feet_in_world, dtype=float)
        gravity, jz, reached = self._stance_statics(leg, bases, yaw, feet)
        support = feet[stance, :2]
        out = reached.copy()
        for i, k in enumerate(stance):
            joints = slice(3 * k, 3 * k + 3)
            f_lo, f_hi = share_bounds(gravity[:, joints], jz[:, joints], self.budget_nm[joints])
            # the foot's share at the CoM p: its barycentric coordinate d(p) / h
            b, c = support[(i + 1) % 3], support[(i + 2) % 3]
            e = c - b
            nrm = np.array([-e[1], e[0]]) / float(np.hypot(*e))
            if nrm @ (support[i] - b) < 0:
                nrm = -nrm
            h = float(nrm @ (support[i] - b))
            d = (np.asarray(points, dtype=float) - b) @ nrm
            share_hi = (d + radius_m) / h
            share_lo = (d - radius_m) / h
            out &= (share_hi * self.weight_n <= f_hi) & (share_lo * self.weight_n >= f_lo)
        return out

    def stance_torques(
        self, leg: int, base: np.ndarray, yaw: float, feet_in_world: np.ndarray, points: np.ndarray
    ) -> np.ndarray:
        """The three stance legs' static torques τ = G(q) - F J_z(q)ᵀ (eq A.14 + A.34) (K, 12)
        [N m] while ``leg`` swings (its own columns 0), the base at ``base`` (3,) [m] heading
        ``yaw`` [rad], the feet at ``feet_in_world`` (4, 3) [m] and the whole-robot CoM at each
        of ``points`` (K, 2) [m] in W: each foot's reaction F its barycentric share of the
        weight (module docstring), the split the run's check makes on three feet. NaN where a
        stance foot is out of reach."""
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        feet = np.asarray(feet_in_world, dtype=float)
        gravity, jz, reached = self._stance_statics(leg, np.asarray(base, float)[None], yaw, feet)
        if not reached[0]:
            return np.full((len(pts), 12), np.nan)
        rows = np.zeros(len(pts), dtype=int)
        return self._split(leg, gravity[rows], jz[rows], feet, pts)

    def stance_torques_along(
        self, leg: int, bases: np.ndarray, yaw: float, feet_in_world: np.ndarray, points: np.ndarray
    ) -> np.ndarray:
        """:meth:`stance_torques` for N bases at once (one IK, one RNEA batch and one
        Jacobian pass for all): (N, 12) [N m], row i with the base at ``bases[i]`` (N, 3)
        [m] and the CoM at ``points[i]`` (N, 2) [m]; NaN rows where a stance foot is out of
        reach."""
        feet = np.asarray(feet_in_world, dtype=float)
        gravity, jz, reached = self._stance_statics(leg, bases, yaw, feet)
        tau = self._split(leg, gravity, jz, feet, np.atleast_2d(np.asarray(points, dtype=float)))
        tau[~reached] = np.nan
        return tau

    def _stance_statics(
        self, leg: int, bases: np.ndarray, yaw: float, feet: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(G (N, 12) [N m], J's z rows (N, 12) [m], reached (N,)) of the three stance legs
        while ``leg`` swings (its columns 0), the base at each of ``bases`` (N, 3) [m] heading
        ``yaw`` [rad], the feet at ``feet`` (4, 3) [m]: one IK, one RNEA batch and one
        Jacobian pass per stance leg for all N; a row where a stance foot is out of reach has
        its joints at 0 and reached False."""
        stance = [k for k in range(4) if k != leg]
        legs = tuple(self.robot.legs)
        bases = np.atleast_2d(np.asarray(bases, dtype=float))
        n = len(bases)
        rel = (feet[stance][None] - bases[:, None, :]) @ rotation_z(float(yaw))  # (N, 3, 3)
        q_legs, ok = joint_values_of_legs(legs, np.tile(stance, n), rel.reshape(-1, 3))
        q_legs = q_legs.reshape(n, 3, 3)
        reached = ok.reshape(n, 3).all(axis=1) & np.all(np.isfinite(q_legs), axis=(1, 2))
        q = np.zeros((n, 12))
        for i, k in enumerate(stance):
            q[:, 3 * k : 3 * k + 3] = np.where(reached[:, None], q_legs[:, i], 0.0)
        jz = np.zeros((n, 12))
        for k in stance:
            joints = slice(3 * k, 3 * k + 3)
            jz[:, joints] = jacobian(legs[k], q[:, joints])[:, 2, :]
        return self.gravity_torques(q), jz, reached

    def _split(
        self, leg: int, gravity: np.ndarray, jz: np.ndarray, feet: np.ndarray, points: np.ndarray
    ) -> np.ndarray:
        """τ = G - F J_z (N, 12) [N m], row by row, each stance foot's F its barycentric share
        of the weight at the CoM ``points`` (N, 2) [m] (module docstring)."""
        stance = [k for k in range(4) if k != leg]
        support = feet[stance, :2]
        tau = np.zeros((len(points), 12))
        for i, k in enumerate(stance):
            joints = slice(3 * k, 3 * k + 3)
            b, c = support[(i + 1) % 3], support[(i + 2) % 3]
            e = c - b
            nrm = np.array([-e[1], e[0]])
            share = ((points - b) @ nrm) / float(nrm @ (support[i] - b))
            tau[:, joints] = gravity[:, joints] - (share * self.weight_n)[:, None] * jz[:, joints]
        return tau


def load_caps_for(
    model: Any, headroom: float | tuple[float, ...], workspace: Any = None
) -> LoadCaps:
    """The caps of a PlanningModel at the preset's torque ``headroom`` (fraction of the
    URDF effort, or one per joint: Preset.builder_torque_headroom), the whole robot carried
    (load "total"); ``workspace``: the plan's, for the tibia rule of
    :meth:`LoadCaps.placeable`."""
    _, effort = urdf_limits(model.robot)
    return LoadCaps(
        model.planning_robot,
        effort * np.asarray(headroom, dtype=float),
        float(model.total_mass) * STANDARD_GRAVITY,
        workspace,
    )
