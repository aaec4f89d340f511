"""Where the stance balls touch the ground when the step builder checks a lift.

A ball foot rolls while its link turns in stance (planner/trajectory/rolling_feet.py): its
contact point moves from the foothold by the rolling displacement d, the integral of
r ω × n since touchdown (n the normal of the surface under the foothold, ẑ on level
ground). The samples stand on those contact points, so the step builder
(planner/gaits/builder.py) checks every lift and every shift on them too: for each stance
foot, :class:`RolledContacts` takes the base path since the foot touched down (the base
poses at the starts of the steps since, then the pose the check is made at), samples each
straight segment of it (base position and yaw blended together, as the sampler does) and
calls :func:`~planner.trajectory.rolling_feet.roll_feet` on those samples, segment after
segment from where the foot has rolled to (each path's d is memoised, so a new check rolls
only its last segment). d depends on the
path only, not on how fast it is walked (ω dt is a change of joint angle), so the samples
need no profile; SEGMENT_SAMPLES of them per segment bring the trapezoid within ~3e-6 m of
the sampler's.

Point feet never reach this module (:func:`rolled_contacts_for` returns None).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from planner.gaits.steps import Step, StepKind
from planner.trajectory.heightmap_rest import heightmap_ground
from planner.trajectory.rolling_feet import (
    MAX_ROLL_PASSES,
    SampledFeet,
    mammal_omega_in_base,
    roll_feet,
    rolling_velocity_in_world,
)
from planner.trajectory.samples import LEGS
from planner.trajectory.sampling import _foot_in_base, joint_motion
from silo4kin.foot_contact import FootBall
from silo4kin.mammal import MammalLegGeometry, joint_rates, joint_rates_of_rows
from silo4kin.mammal_constants import MammalConstants

#: Samples per straight segment of the base path (module docstring).
SEGMENT_SAMPLES = 16
#: Convergence of the rolling fixed point for a prediction [m]: far below the margins' 1e-4 m.
PREDICTION_TOLERANCE_M = 1e-7


class RolledContacts:
    """The contact points of a robot's ball feet at a lift (module docstring).

    Attributes:
        legs: the four leg geometries in B; ball: the foot ball (it rolls); terrain: the
            ground (a TerrainMap: each ball rolls on the plane of the surface under its
            foothold) or None (level).
    """

    def __init__(self, legs: Sequence, ball: FootBall, terrain=None) -> None:
        self.legs = tuple(legs)
        self.ball = ball
        self.terrain = terrain
        self._memo: dict[bytes, np.ndarray] = {}
        self._normals: dict[bytes, np.ndarray | None] = {}

    def contact_points(
        self,
        steps: Sequence[Step],
        feet_in_world: np.ndarray,
        base_in_world: np.ndarray,
        yaw: float,
        start_pose: np.ndarray | None = None,
    ) -> np.ndarray:
        """The feet (4, 3) [m] in W moved by the rolling since each touched down at its
        foothold ``feet_in_world`` (4, 3), after ``steps`` and then a straight base move to
        ``base_in_world`` (3,) [m], ``yaw`` [rad]; NaN where a stance foot is out of reach
        on that path. ``start_pose`` (x, y, z [m], yaw [rad]): where the base stands before
        the first step (the plan's start), from which the move starts when ``steps`` is
        empty; None: from ``base_in_world`` itself (no move, no rolling)."""
        feet = np.asarray(feet_in_world, dtype=float)
        poses, touch = _base_path(
            steps, feet, np.asarray(base_in_world, float), float(yaw), start_pose
        )
        rolled = feet.copy()
        # a check at a new pose adds the same last segment to every stance foot's path:
        # those are rolled together (_segments_together); the rest come from the memo
        new = [
            j
            for j in range(4)
            if len(poses) - touch[j] >= 2 and _key(j, feet[j], poses[touch[j] :]) not in self._memo
        ]
        if len(new) > 1 and self._together(new, feet):
            before = [self._offset(j, poses[touch[j] : -1], feet[j]) for j in new]
            starts = np.array([feet[j] + b for j, b in zip(new, before)])
            for j, b, seg in zip(
                new, before, self._segments_together(new, poses[-2], poses[-1], starts)
            ):
                self._memo[_key(j, feet[j], poses[touch[j] :])] = b + seg
        for j in range(4):
            rolled[j] += self._offset(j, poses[touch[j] :], feet[j])
        return rolled

    def _offset(self, leg: int, poses: np.ndarray, foothold: np.ndarray) -> np.ndarray:
        """d (3,) [m] of foot ``leg`` standing on ``foothold`` (3,) [m] in W while the base
        walks the path ``poses`` (M, 4: x, y, z [m], yaw [rad]) from its touchdown: the d of
        the path but its last segment (memoised), plus the rolling over that segment from
        where the foot has rolled to."""
        if len(poses) < 2:
            return np.zeros(3)
        key = _key(leg, foothold, poses)
        d = self._memo.get(key)
        if d is None:
            before = self._offset(leg, poses[:-1], foothold)
            start = foothold + before
            normal = self._normal(foothold)
            d = self._memo[key] = before + self._segment(leg, poses[-2], poses[-1], start, normal)
        return d

    def _together(self, legs: list[int], feet: np.ndarray) -> bool:
        """Whether :meth:`_segments_together` rolls these legs: mammal legs on level ground
        (no terrain normal under any of their footholds, no height map); the others roll
        one at a time (:meth:`_segment`)."""
        if heightmap_ground(self.terrain, self.ball.rolling_radius_m) is not None:
            return False
        return all(
            isinstance(self.legs[j], MammalLegGeometry) and self._normal(feet[j]) is None
            for j in legs
        )

    def _segments_together(
        self, legs: list[int], pose_start: np.ndarray, pose_end: np.ndarray, feet: np.ndarray
    ) -> list[np.ndarray]:
        """:meth:`_segment` of each of ``legs`` (L mammal legs on level ground, their foot
        frames at ``feet`` (L, 3) [m] in W) over the same straight base move, in one pass of
        the fixed point for all of them: each leg's d follows the same passes with the same
        operations as roll_feet's (its targets, the joint rates of its rows, ω, r ω × ẑ, the
        trapezoid), and stops changing at the pass its own converges at, so each is what
        :meth:`_segment` returns (tests/test_rolled_contacts.py); a singular pose falls back
        to one leg at a time."""
        k = SEGMENT_SAMPLES
        frac = np.linspace(0.0, 1.0, k + 1)
        n, count = len(frac), len(legs)
        rate = np.broadcast_to(pose_end - pose_start, (n, 4))
        path = pose_start + rate * frac[:, None]
        tile = lambda a: np.tile(a, (count,) + (1,) * (a.ndim - 1))  # noqa: E731
        base, base_d, zero3 = tile(path[:, :3]), tile(rate[:, :3]), np.zeros((n * count, 3))
        yaw, yaw_d, zero_n = tile(path[:, 3]), tile(rate[:, 3]), np.zeros(n * count)
        rows_leg = np.repeat(np.asarray(legs), n)
        consts = MammalConstants.of_rows(self.legs, rows_leg)
        foot = np.repeat(np.asarray(feet, dtype=float), n, axis=0)  # (L n, 3)
        d, v, v_d = np.zeros((count, n, 3)), np.zeros((count, n, 3)), np.zeros((count, n, 3))
        target = np.empty((count, n, 3))
        active = np.ones(count, dtype=bool)
        with np.errstate(invalid="ignore"):
            for _ in range(MAX_ROLL_PASSES):
                rows = np.repeat(active, n)
                target[active] = (foot[rows] + d[active].reshape(-1, 3)).reshape(-1, n, 3)
                u = _foot_in_base(
                    target[active].reshape(-1, 3), 0.0 + v[active].reshape(-1, 3),
                    0.0 + v_d[active].reshape(-1, 3), base[rows], base_d[rows], zero3[rows],
                    yaw[rows], yaw_d[rows], zero_n[rows],
                )  # fmt: skip
                sub = consts if rows.all() else MammalConstants(*(c[rows] for c in consts))
                try:
                    q, qd, _ = joint_rates_of_rows(
                        sub, np.column_stack(u[0]), np.column_stack(u[1])
                    )
                except np.linalg.LinAlgError:
                    return [
                        self._segment(j, pose_start, pose_end, feet[i], None)
                        for i, j in enumerate(legs)
                    ]
                omega, omega_d = mammal_omega_in_base(sub, q, qd, zero3[rows])
                vel, vel_d = rolling_velocity_in_world(
                    self.ball.rolling_radius_m, omega, omega_d, yaw[rows], yaw_d[rows]
                )
                vel, vel_d = np.nan_to_num(vel), np.nan_to_num(vel_d)
                vel, vel_d = vel.reshape(-1, n, 3), vel_d.reshape(-1, n, 3)
                inc = np.zeros_like(vel)
                inc[:, 1:] = 0.5 * (vel[:, 1:] + vel[:, :-1]) * (1.0 / k)
                total = np.cumsum(inc, axis=1)
                d_new = total - total[:, :1]  # stance_integral of one stance run
                change = np.max(np.abs(d_new - d[active]), axis=(1, 2))
                idx = np.flatnonzero(active)
                d[idx], v[idx], v_d[idx] = d_new, vel, vel_d
                active[idx[change < PREDICTION_TOLERANCE_M]] = False
                if not active.any():
                    break
        return [target[i, -1] - feet[i] for i in range(count)]

    def _normal(self, foothold: np.ndarray) -> np.ndarray | None:
        """The unit normal (3,) in W of the surface under ``foothold`` (3,) [m], which the
        ball rolls on for the whole stance; None on level ground or without a terrain (the
        level formula, bit for bit). Memoised: one terrain query per foothold."""
        if not hasattr(self.terrain, "normal_at"):
            return None
        key = foothold.tobytes()
        if key not in self._normals:
            n = self.terrain.normal_at(foothold[None, :2])[0]
            level = not np.all(np.isfinite(n)) or (n[0] == 0.0 and n[1] == 0.0)
            self._normals[key] = None if level else n
        return self._normals[key]

    def _segment(
        self,
        leg: int,
        pose_start: np.ndarray,
        pose_end: np.ndarray,
        foot: np.ndarray,
        normal: np.ndarray | None,
    ) -> np.ndarray:
        """d (3,) [m] of foot ``leg``, its foot frame at ``foot`` (3,) [m] in W, over a straight
        base move from ``pose_start`` to ``pose_end`` (4,: x, y, z [m], yaw [rad]), rolling on
        the plane of unit normal ``normal`` (3,) (None: level, d_z = 0), along which d runs."""
        k = SEGMENT_SAMPLES
        frac = np.linspace(0.0, 1.0, k + 1)
        n = len(frac)
        rate = np.broadcast_to(pose_end - pose_start, (n, 4))  # per unit of the parameter
        path = pose_start + rate * frac[:, None]
        base, base_d, zero = path[:, :3], rate[:, :3], np.zeros((n, 3))
        yaw, yaw_d, zero_n = path[:, 3], rate[:, 3], np.zeros(n)
        # roll_feet treats each leg on its own (its columns only), so the leg that stands
        # here is rolled alone: the other three, which nothing rolls, cost a pass each
        contact = np.ones((n, 1), dtype=bool)
        feet = np.zeros((n, 1, 3))
        feet[:, 0] = foot
        geometry = self.legs[leg]

        def solve(j: int, target, target_d, target_dd):
            u = _foot_in_base(target, target_d, target_dd, base, base_d, zero, yaw, yaw_d, zero_n)
            if isinstance(geometry, MammalLegGeometry):
                # d integrates v = r ω × n, and ω is q̇ along the joint axes at q: q̈ enters
                # only ω̇ and v̇, which d and the targets returned never read, so the
                # mammal's J̇q̇ and second solve (a third of its joint_motion) are skipped
                q, qd, _ = joint_rates(geometry, np.column_stack(u[0]), np.column_stack(u[1]))
                return q, qd, zero
            motion = joint_motion(geometry, *u)
            return motion[0], motion[1], motion[2]

        sampled = SampledFeet(
            feet=feet,
            feet_d=np.zeros((n, 1, 3)),
            feet_dd=np.zeros((n, 1, 3)),
            swing_s=zero_n,
            swing_ds=zero_n,
            swing_dds=zero_n,
            yaw=yaw,
            yaw_d=yaw_d,
            contact=contact,
            dt_units=1.0 / k,
            normal=None if normal is None else np.broadcast_to(normal, (n, 1, 3)),
            ground=heightmap_ground(self.terrain, self.ball.rolling_radius_m),
        )
        with np.errstate(invalid="ignore"):
            try:
                _, _, _, targets = roll_feet(
                    (geometry,), self.ball, sampled, solve, PREDICTION_TOLERANCE_M
                )
            except np.linalg.LinAlgError:  # the foot out of reach on the segment
                return np.full(3, np.nan)
        return targets[-1, 0] - foot


_Z_HAT = np.array([0.0, 0.0, 1.0])


def _key(leg: int, foothold: np.ndarray, poses: np.ndarray) -> bytes:
    """The memo key of foot ``leg``'s d on ``foothold`` along the base path ``poses``."""
    return b"".join((bytes([leg]), foothold.tobytes(), poses.tobytes()))


def _placed(step: Step, leg: int, foothold: np.ndarray) -> bool:
    """``step`` is the transfer that put ``leg`` on ``foothold`` (3,) [m]."""
    end = step.foothold_end_in_world
    return (
        step.kind == StepKind.TRANSFER
        and step.leg == LEGS[leg]
        and end is not None
        and np.array_equal(end, foothold)
    )


def _base_path(
    steps: Sequence[Step],
    feet: np.ndarray,
    base: np.ndarray,
    yaw: float,
    start_pose: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The base poses (M, 4: x, y, z [m], yaw [rad]) since the earliest touchdown of the
    feet ``feet`` (4, 3) (the start of the steps for a foot no transfer placed), ending at
    (``base``, ``yaw``), without repeats; and the path point each foot stands from (4,).
    Without steps the path starts at ``start_pose`` (4,) where given: a first shift rolls
    the feet as any later one does (solo12 of the corpus, seed 20261202 #22 of 200: its
    first shift was checked on unrolled contacts, 22.8 mm of margin, and the samples stood
    on rolled ones, 18.3 mm, under the 20 mm threshold)."""
    first = []
    for j in range(4):
        placed = next(
            (i for i in range(len(steps) - 1, -1, -1) if _placed(steps[i], j, feet[j])),
            -1,
        )
        first.append(placed + 1)  # the foot stands from the start of this step
    start = min(first)
    poses: list[np.ndarray] = []
    touch_pose = [0] * 4
    for i in range(start, len(steps) + 1):
        if i < len(steps):
            st = steps[i]
            pose = np.append(st.position_base_start_in_world, st.yaw_base_start)
        elif steps:
            pose = np.append(steps[-1].position_base_end_in_world, steps[-1].yaw_base_end)
        else:
            pose = np.append(base, yaw) if start_pose is None else np.asarray(start_pose, float)
        if not poses or not np.array_equal(poses[-1], pose):
            poses.append(pose)
        for j in range(4):
            if first[j] == i:
                touch_pose[j] = len(poses) - 1
    end = np.append(base, yaw)
    if not np.array_equal(poses[-1], end):
        poses.append(end)
    return np.array(poses), np.array(touch_pose)


def rolled_contacts_for(legs: Sequence, ball: FootBall, terrain=None) -> RolledContacts | None:
    """The contact predictor of ``ball`` feet on ``terrain`` (None: level), or None for point
    feet (they do not roll)."""
    return RolledContacts(legs, ball, terrain) if ball.rolls else None
