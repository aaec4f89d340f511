"""Footholds on the surfaces of a terrain file: the nearest valid point to a gait's nominal
foothold (docs/terrain.md, "Footholds on surfaces").

A point (x, y) is a valid foothold of a leg when

- there is ground under it and its normal is within ``max_tilt_deg`` of vertical;
- the ground is the same part of the terrain (TerrainMap.part_at: the floor, one box, one
  post; the floor and the height map on it count as one part, the ground) and keeps to the
  plane of that surface (within SURFACE_TOLERANCE_M; on the ground of a terrain with a
  height map within HEIGHTMAP_STEP_M, the height map's analogue of an edge) over a disc of
  radius ``edge_margin_m`` around it: no edge, wall, step or void nearer than the margin
  (sampled on rings of rays: planner/gaits/search_offsets.py, so that a straight edge
  nearer than the margin is always met; on a height map also every grid sample within the
  margin, where its piecewise-linear ground has its extremes), and no ground rises
  above that plane (by more than the same tolerance) within ``wall_margin_m`` (a riser or a
  wall in front of the foot: the shank, which leans from the foot towards the hip, would
  meet it; the same rings at that radius);
- it is outside every forbidden polygon by the terrain's clearance (TerrainMap.allows_footholds);
- the leg reaches it at the surface height (planner.workspace.reach_check
  reachable_in_limits_of_legs) from the base where the transfer places it;
- given the other feet's footholds at that step, it is at least ``clearance_m`` (the leg
  interference clearance, planner/workspace/interference.py LEG_CLEARANCE_M) from each of
  them in 3-D: a hind foot does not land on the stone its front foot stands on;
- with ``shank`` (a terrain with obstacles, planner/gaits/shank_clearance.py), the leg's tibia
  capsule, posed with the foot on it and the base where the transfer places it, keeps
  MIN_TIBIA_CLEARANCE_M + TIBIA_SEARCH_MARGIN_M from the terrain: stepping down past an
  edge, the shank leaning from the foot back towards the hip over the higher surface would
  lie on the edge (go2 on examples/terrain/stairs.yaml), and the foothold moves farther on.

Candidates are the nominal point and a grid of SEARCH_STEP_M around it out to
``search_radius_m``, tried nearest first (points of contact); the foothold is the foot frame
over it: the contact point plus the foot's contact offset along the surface normal
(:meth:`SurfaceFootholds.foot_frames`: a ball's centre).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from planner.errors import FootholdRefused
from planner.gaits.ball_stance import body_height, foot_frames_on_surface
from planner.gaits.search_offsets import EDGE_DIRECTIONS, disc_offsets, ring_offsets
from planner.gaits.shank_clearance import ShankClearance
from planner.gaits.stance_torque import StanceTorque
from planner.terrain.refusals import slope_clause, stance_out_of_reach
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.samples import LEGS
from planner.workspace.interference import LEG_CLEARANCE_M
from planner.workspace.reach_check import reachable_in_limits_of_legs
from silo4kin.frames import rotation_z

#: The foot sphere's radius assumed when none is given [m] (SILO4's foot, 0.025 m).
DEFAULT_FOOT_RADIUS_M = 0.025
#: Added to the foot radius for the default edge margin [m] (docs/terrain.md).
EDGE_EXTRA_M = 0.02
#: How far a foothold keeps from ground that rises above its surface [m] (module docstring):
#: SILO4 at h = 0.4 m put its LH tibia on a 0.08 m block's edge from 0.048 m in physics.
WALL_MARGIN_M = 0.1
#: Steepest surface a foot stands on: angle of its normal from vertical [deg].
MAX_TILT_DEG = 20.0
#: How far the ground may leave the foothold's plane within the edge margin [m].
SURFACE_TOLERANCE_M = 1e-3
#: How far the ground of a height map may rise above or drop below the foothold's plane
#: within the edge margin, and rise above it within the wall margin [m]: a step the foot
#: sphere (radius 0.025 m) rolls over, not an edge it sits on.
HEIGHTMAP_STEP_M = 0.01
#: Spacing of the candidate grid [m] and its default reach around the nominal point [m]. The
#: reach check bounds a candidate anyway; the radius only caps the grid. At 0.12 m SILO4
#: (h 0.4 m) was refused at a 0.25 m gap whose near edge lay 0.13 m behind a nominal
#: foothold; at 0.2 m (about half SILO4's stride, 2/3 of go2's) it walks it.
SEARCH_STEP_M = 0.005
SEARCH_RADIUS_M = 0.2
#: Candidates judged per vectorised pass.
CANDIDATE_CHUNK = 256
#: Candidates whose stance torques are computed per pass (planner/gaits/stance_torque.py),
#: nearest first: the first that keeps the budget is usually among the first few.
TORQUE_BATCH = 32


@dataclass(frozen=True, eq=False)
class SurfaceFootholds:
    """The foothold search on a terrain file's surfaces (module docstring).

    Attributes:
        terrain: the ground.
        legs: the planning robot's legs (LegGeometry in B), for the reach check.
        height_m: the body height above the stance feet's mean height [m].
        edge_margin_m: least distance of a foothold from a surface's edges [m].
        wall_margin_m: least distance of a foothold from ground rising above it [m].
        max_tilt_deg: steepest surface normal from vertical [deg].
        search_radius_m: how far from the nominal point a foothold may move [m].
        friction: the friction coefficient a plan may use (mu_plan) [-]; None: no limit.
        clearance_m: least 3-D distance of a foothold from the other feet's footholds [m].
        foot_offset_m: how far a standing foot frame is above its contact point [m]
            (silo4kin.foot_contact.foot_contact_offset_m: 0 for point feet, r - o_z for a
            ball). The builder's feet are foot frames, so a foothold is its contact point on
            the ground plus this along the surface normal (:meth:`foot_frames`), and the body
            stands ``height_m`` above the contact points' mean.
        shank: None, or the tibia capsule check of a candidate (module docstring).
        roll_m: how far a stance contact point of a ball foot rolls from where it touches
            down [m] (planner/gaits/stance_roll.py; 0 for point feet), along the body's
            motion over it: the point that far on along that motion must be valid too
            (:meth:`place`), so the edge margin and the forbidden polygons' clearance hold
            at both ends of the roll.
        torque: None, or the static torque preference of a candidate's stances
            (planner/gaits/stance_torque.py): the nearest candidate whose stances keep the
            effort budget is taken, else the nearest the other rules allow.
    """

    terrain: TerrainMap
    legs: tuple
    height_m: float
    edge_margin_m: float = DEFAULT_FOOT_RADIUS_M + EDGE_EXTRA_M
    max_tilt_deg: float = MAX_TILT_DEG
    wall_margin_m: float = WALL_MARGIN_M
    search_radius_m: float = SEARCH_RADIUS_M
    friction: float | None = None
    clearance_m: float = LEG_CLEARANCE_M
    foot_offset_m: float = 0.0
    shank: ShankClearance | None = None
    roll_m: float = 0.0
    torque: StanceTorque | None = None
    _offsets: np.ndarray = field(init=False, repr=False)
    _stages: tuple[tuple[np.ndarray, bool], ...] = field(init=False, repr=False)
    _group: np.ndarray = field(init=False, repr=False)
    _tolerance: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_offsets", disc_offsets(SEARCH_STEP_M, self.search_radius_m))
        edge, wall = ring_offsets(self.edge_margin_m), ring_offsets(self.wall_margin_m)
        outer = slice(-EDGE_DIRECTIONS, None)
        inner = slice(None, -EDGE_DIRECTIONS)
        stages = ((edge[outer], False), (wall[outer], True), (edge[inner], False))
        object.__setattr__(self, "_stages", (*stages, (wall[inner], True)))
        names = self.terrain.part_names()
        group = np.arange(len(names) + 1)  # the last entry: a void (part -1)
        tolerance = np.full(len(names) + 1, SURFACE_TOLERANCE_M)
        if self.terrain.heightmap is not None:
            ground = [names.index("height map")] + (
                [names.index("floor")] if "floor" in names else []
            )
            group[ground] = ground[0]
            tolerance[ground] = HEIGHTMAP_STEP_M
        object.__setattr__(self, "_group", group)
        object.__setattr__(self, "_tolerance", tolerance)

    def valid(self, xy_in_world: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(valid (N,) bool, z (N,) [m]) of candidate footholds (N, 2) [m] on the terrain:
        ground, tilt, edge and wall margins and forbidden polygons (module docstring), not
        reach. The rings are asked outermost first, each of the candidates left, then a
        height map's grid samples within the edge margin."""
        xy = np.asarray(xy_in_world, dtype=float).reshape(-1, 2)
        z, n, part = self.terrain.ground_at(xy)
        with np.errstate(invalid="ignore"):
            ok = np.isfinite(z) & (n[:, 2] >= np.cos(np.radians(self.max_tilt_deg)))
            if self.friction is not None:
                ok &= np.hypot(n[:, 0], n[:, 1]) <= self.friction * n[:, 2]
        ok &= self.terrain.allows_footholds(xy)
        for ring, is_wall in self._stages:
            idx = np.flatnonzero(ok)
            if not idx.size:
                break
            points = xy[idx, None, :] + ring[None]
            ok[idx] = self._keeps(xy[idx], z[idx], n[idx], part[idx], points, is_wall)
        idx = np.flatnonzero(ok)
        if self.terrain.heightmap is not None and idx.size:
            points, near = self.terrain.heightmap.samples_near(xy[idx], self.edge_margin_m)
            ok[idx] = self._keeps(xy[idx], z[idx], n[idx], part[idx], points, False, near)
        return ok, z

    def _keeps(
        self,
        xy: np.ndarray,
        z: np.ndarray,
        normal: np.ndarray,
        part: np.ndarray,
        points: np.ndarray,
        is_wall: bool,
        asked: np.ndarray | None = None,
    ) -> np.ndarray:
        """Whether the ground under ``points`` (M, R, 2) around each point (M, 2) at z (M,)
        with ``normal`` (M, 3) on ``part`` (M,) keeps the rule, (M,): no rise above the
        plane through the point (``is_wall``), else the same part (the floor and a height
        map one) near that plane, by the part's tolerance (module docstring); only the
        points ``asked`` (M, R) when given."""
        ground, _, on = self.terrain.ground_at(points.reshape(-1, 2))
        ground, on = ground.reshape(points.shape[:2]), on.reshape(points.shape[:2])
        d = points - xy[:, None, :]
        plane = (
            z[:, None]
            - (normal[:, None, 0] * d[..., 0] + normal[:, None, 1] * d[..., 1]) / normal[:, None, 2]
        )
        tolerance = self._tolerance[part][:, None]
        with np.errstate(invalid="ignore"):
            if is_wall:
                keeps = ground - plane <= tolerance
            else:
                same = self._group[on] == self._group[part][:, None]
                keeps = (np.abs(ground - plane) <= tolerance) & same
        if asked is not None:
            keeps |= ~asked
        return np.all(keeps, axis=1)

    def place(
        self,
        leg: int,
        nominal_in_world: np.ndarray,
        base_in_world: np.ndarray,
        yaw: float,
        position_feet_in_world: np.ndarray | None = None,
        stance_motion_xy: np.ndarray | None = None,
        settles: bool = False,
        next_leg: int | None = None,
    ) -> np.ndarray:
        """The foothold (3,) in W [m] of ``leg`` nearest ``nominal_in_world`` (3,) [m]: valid,
        reached with the base at ``base_in_world`` (3,) [m], heading ``yaw`` [rad], and, given
        the feet (4, 3) [m] at that step, ``clearance_m`` from each other foot; with
        ``shank``, its tibia capsule clear of the terrain at touch-down and, given the body's
        predicted motion ``stance_motion_xy`` (2,) [m] after it, over that motion
        (:meth:`_stance_end`); ``settles``: the base is at the stance feet's height at
        touch-down already (a transfer whose base moves, the crawl), not ``base_in_world``'s;
        ``next_leg``: the leg the gait swings next (StepBuilder.next_swing_leg), whose support
        the torque preference weighs (None: each three feet holding ``leg``).

        Raises:
            FootholdRefused: no valid foothold within ``search_radius_m``.
        """
        nominal = np.asarray(nominal_in_world, dtype=float)
        base = np.asarray(base_in_world, dtype=float)
        rot_t = rotation_z(float(yaw)).T
        others = np.zeros((0, 3))
        feet = None
        if position_feet_in_world is not None:
            feet = np.asarray(position_feet_in_world, dtype=float)
            others = feet[[k for k in range(len(feet)) if k != leg]]
        roll = self._roll_xy(leg, nominal, feet, stance_motion_xy)
        bounds = [0, *range(1, len(self._offsets), CANDIDATE_CHUNK), len(self._offsets)]
        blocked = None  # the nearest candidate the shank alone refused, for the refusal
        nearest = None  # the nearest candidate valid but for the torque preference
        for lo, hi in zip(bounds[:-1], bounds[1:]):  # the nominal point alone first
            xy = nominal[:2] + self._offsets[lo:hi]
            ok, z = self.valid(xy)
            if roll is not None and ok.any():  # where the contact point rolls to, too
                ok[ok] = self.valid(xy[ok] + roll)[0]
            idx = np.flatnonzero(ok)
            if not idx.size:
                continue
            points = self.foot_frames(np.column_stack([xy[idx], z[idx]]))
            ground = z[idx]
            if others.size:
                apart = np.all(
                    np.linalg.norm(points[:, None, :] - others[None], axis=2) >= self.clearance_m,
                    axis=1,
                )
                points, ground = points[apart], ground[apart]
                if not len(points):
                    continue
            in_base = (rot_t @ (points - base).T).T
            reach = reachable_in_limits_of_legs(self.legs, np.full(len(points), leg), in_base)
            hit = np.flatnonzero(reach)
            if not hit.size:
                continue
            touchdown, end = self._stance_end(
                leg, points[hit], ground[hit], base, feet, stance_motion_xy, settles
            )
            after = 0  # candidates of this chunk after the nearest valid one
            if nearest is None:  # the foothold the rules give without the torque preference
                first = self._first_shank_clear(leg, points[hit], touchdown, end, yaw)
                if first is None and blocked is None and self.shank is not None:
                    blocked = (points[hit[0]], touchdown[0], None if end is None else end[0])
                if first is None:
                    continue
                nearest, after = points[hit[first]], first + 1
                if self.torque is None or feet is None or lo == 0:
                    return nearest  # the gait's own foothold is not weighed (stance_torque.py)
                if (
                    self._within_budget(
                        leg,
                        points[hit[first : first + 1]],
                        touchdown[first : first + 1],
                        None if end is None else end[first : first + 1],
                        yaw,
                        feet,
                        next_leg,
                    )
                    == 0
                ):
                    return nearest
            assert feet is not None  # a nearest foothold is kept only with the feet known
            first = self._within_budget(
                leg,
                points[hit[after:]],
                touchdown[after:],
                None if end is None else end[after:],
                yaw,
                feet,
                next_leg,
            )
            if first is not None:
                return points[hit[after + first]]
        if nearest is not None:  # none keeps the torque budget: the run's check decides
            return nearest
        reason = self._refusal(leg, nominal)
        if blocked is not None and self.shank is not None:
            point = blocked[0]
            reason += (
                f"; the nearest point otherwise valid, ({point[0]:.4g}, {point[1]:.4g}, "
                f"{point[2]:.4g}) m, {self.shank.describe(leg, point, *blocked[1:], yaw)}"
            )
        raise FootholdRefused(nominal, reason)

    def _within_budget(
        self,
        leg: int,
        points: np.ndarray,
        touchdown: np.ndarray,
        end: np.ndarray | None,
        yaw: float,
        feet: np.ndarray,
        next_leg: int | None = None,
    ) -> int | None:
        """The index of the first of ``points`` (M, 3) [m] whose stances keep the torque
        budget (StanceTorque.keeps at touch-down ``touchdown`` (M, 3) and at the body step's
        end ``end`` (M, 3) or None [m], the other feet at ``feet`` (4, 3) [m], ``next_leg``
        swinging next) and whose
        tibia capsule clears; None when none does. TORQUE_BATCH candidates at a time, in
        order."""
        assert self.torque is not None
        for lo in range(0, len(points), TORQUE_BATCH):
            rows = slice(lo, lo + TORQUE_BATCH)
            poses = (
                touchdown[rows, None]
                if end is None
                else np.stack([touchdown[rows], end[rows]], axis=1)
            )
            keeps = np.flatnonzero(self.torque.keeps(leg, points[rows], poses, yaw, feet, next_leg))
            if not keeps.size:
                continue
            kept = keeps + lo
            first = self._first_shank_clear(
                leg, points[kept], touchdown[kept], None if end is None else end[kept], yaw
            )
            if first is not None:
                return int(kept[first])
        return None

    def _first_shank_clear(
        self,
        leg: int,
        points: np.ndarray,
        touchdown: np.ndarray,
        end: np.ndarray | None,
        yaw: float,
    ) -> int | None:
        """The index of the first of ``points`` (M, 3) [m] whose tibia capsule clears
        (ShankClearance.first_clear, the base at ``touchdown`` (M, 3) and over the motion on
        to ``end`` (M, 3) or None [m]); 0 without a shank check."""
        if self.shank is None:
            return 0
        return self.shank.first_clear(leg, points, touchdown, end, yaw)

    def _roll_xy(
        self,
        leg: int,
        nominal: np.ndarray,
        feet: np.ndarray | None,
        motion_xy: np.ndarray | None,
    ) -> np.ndarray | None:
        """Where a ball foot's contact point rolls over its stance, (2,) [m] from where it
        touches down: ``roll_m`` along the body's predicted motion ``motion_xy`` (the ball
        rolls forward as the body passes over it), else along the swing (from the foot's
        last foothold to ``nominal``); None for a point foot or no direction known."""
        if self.roll_m <= 0.0:
            return None
        for direction in (
            None if motion_xy is None else np.asarray(motion_xy, dtype=float)[:2],
            None if feet is None else nominal[:2] - feet[leg, :2],
        ):
            if direction is not None and np.hypot(*direction) > 1e-9:
                return self.roll_m * direction / np.hypot(*direction)
        return None

    def _stance_end(
        self,
        leg: int,
        points: np.ndarray,
        ground: np.ndarray,
        base: np.ndarray,
        feet: np.ndarray | None,
        motion_xy: np.ndarray | None,
        settles: bool,
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """(base at touch-down (M, 3), base at the end of the body motion that follows (M, 3)
        or None) [m] for ``leg``'s foot frames ``points`` (M, 3) on ground at z ``ground``
        (M,) [m], the base at ``base`` (3,) [m] and the feet (4, 3) [m] (None: unknown). The
        motion ends ``motion_xy`` (2,) [m] on (None: no motion asked) at the height the feet
        with the candidate ask (:meth:`body_z`): a foot stepping down lowers the body, which
        brings the shank down on the edge it stepped past. With ``settles`` the base is at
        that height at touch-down already."""
        touchdown = np.tile(base, (len(points), 1))
        if feet is None:
            return touchdown, None
        with_first = feet.copy()
        with_first[leg] = points[0]
        settled = self.body_z(with_first) + (ground - ground[0]) / len(feet)
        if settles:
            touchdown[:, 2] = settled
        if motion_xy is None:
            return touchdown, None
        end = touchdown.copy()
        end[:, :2] += np.asarray(motion_xy, dtype=float)[:2]
        end[:, 2] = settled
        return touchdown, end

    def _refusal(self, leg: int, nominal_in_world: np.ndarray) -> str:
        """Why no foothold of ``leg`` was found near ``nominal_in_world`` (3,) [m]: what
        lies under it, its slope when that is too steep, and the rules."""
        xy = nominal_in_world[:2]
        limits = [(self.max_tilt_deg, "the steepest a foot stands on")]
        if self.friction is not None:
            why = f"atan(mu_plan {self.friction:g}), the friction a standing foot needs"
            limits.insert(0, (float(np.degrees(np.arctan(self.friction))), why))
        under = self.terrain.describe_at(xy) + slope_clause(self.terrain, xy, limits)
        step = ""
        if self.terrain.heightmap is not None:
            step = f" (on the height map: no step over {HEIGHTMAP_STEP_M:.3g} m)"
        return (
            f"{self.terrain.label()}: leg {LEGS[leg]}'s nominal foothold is over {under}, and "
            f"no point "
            f"within {self.search_radius_m:.3g} m of it is on a surface flat to "
            f"{self.max_tilt_deg:.3g} deg, {self.edge_margin_m:.3g} m from its edges{step}, "
            f"{self.wall_margin_m:.3g} m from any rise, {self.clearance_m:.3g} m from the "
            f"other feet and in the leg's reach"
            + (
                f", its tibia capsule {1e3 * self.shank.min_clearance_m:.3g} mm off the terrain"
                if self.shank is not None
                else ""
            )
            + (
                f", both where its ball touches down and {self.roll_m:.3g} m on, where it rolls"
                if self.roll_m > 0.0
                else ""
            )
        )

    def step_end(
        self,
        body_step: bool,
        leg: int | None,
        base_start_in_world: np.ndarray,
        base_end_in_world: np.ndarray,
        yaw_end: float,
        position_feet_in_world: np.ndarray,
        foot_end_in_world: np.ndarray | None,
        stance_motion_xy: np.ndarray | None = None,
        next_leg: int | None = None,
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """(base end (3,), foothold (3,) or None) [m] of a step from feet (4, 3) [m]: the
        foothold of ``leg`` placed (:meth:`place`, the base at its end; unchanged when it is
        valid already), and the base z over the stance feet (:meth:`body_z`) for a body step
        or a transfer whose base moves in xy, every stance foot then checked in reach
        (:meth:`check_stance`). The stance motion the shank is measured over: the step's own
        for a transfer whose base moves (the next one is like it), else
        ``stance_motion_xy`` (2,) [m] (StepBuilder: its last body step's); ``next_leg`` as
        :meth:`place`."""
        base_end = np.array(base_end_in_world, dtype=float)
        feet = np.array(position_feet_in_world, dtype=float)
        foot_end = foot_end_in_world
        moves = bool(np.any(base_end[:2] != np.asarray(base_start_in_world)[:2]))
        if leg is not None and foot_end is not None:
            motion = stance_motion_xy
            if moves:
                motion = base_end[:2] - np.asarray(base_start_in_world, dtype=float)[:2]
            foot_end = self.place(leg, foot_end, base_end, yaw_end, feet, motion, moves, next_leg)
            feet[leg] = foot_end
        if body_step or moves:
            base_end[2] = self.body_z(feet)
            self.check_stance(base_end, yaw_end, feet)
        return base_end, foot_end

    def check_stance(
        self, base_in_world: np.ndarray, yaw: float, position_feet_in_world: np.ndarray
    ) -> None:
        """Refuse a body pose (base (3,) [m], heading ``yaw`` [rad]) from which a stance foot
        (4, 3) [m] is out of its leg's reach, naming the foot, the part of the terrain it
        stands on and the highest and lowest feet (the body follows their mean height).

        Raises:
            FootholdRefused: a foot out of reach.
        """
        feet = np.asarray(position_feet_in_world, dtype=float)
        in_base = (rotation_z(float(yaw)).T @ (feet - base_in_world).T).T
        reach = reachable_in_limits_of_legs(self.legs, np.arange(len(feet)), in_base)
        if np.all(reach):
            return
        leg = int(np.flatnonzero(~reach)[0])
        raise FootholdRefused(
            feet[leg], stance_out_of_reach(self.terrain, feet, self.height_m, leg, LEGS)
        )

    def start_pose(
        self, base_in_world: np.ndarray, position_feet_in_world: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """(base (3,), feet (4, 3)) [m] of the start stance on the terrain: each foot on the
        ground under it and the base :meth:`body_z` over them; unchanged when every foot is
        on the ground already (the start over level ground).

        Raises:
            FootholdRefused: a start foot over a void.
        """
        feet = np.array(position_feet_in_world, dtype=float)
        ground = self.terrain.height_at(feet[:, :2])
        normal_z = self.terrain.normal_at(feet[:, :2])[:, 2]
        if np.array_equal(ground + self.foot_offset_m, feet[:, 2]) and np.all(normal_z == 1.0):
            return np.asarray(base_in_world, dtype=float), feet
        void = np.flatnonzero(~np.isfinite(ground))
        if void.size:
            what = self.terrain.label()
            raise FootholdRefused(
                feet[void[0]],
                f"{what}: leg {LEGS[int(void[0])]}'s start foothold is over a void",
            )
        feet = self.foot_frames(np.column_stack([feet[:, :2], ground]))
        base = np.array(base_in_world, dtype=float)
        base[2] = self.body_z(feet)
        return base, feet

    def body_z(self, position_feet_in_world: np.ndarray) -> float:
        """The base height [m] over the stance feet (4, 3) [m, foot frames]: their contact
        points' mean z + height_m (planner/gaits/ball_stance.py)."""
        return body_height(self.terrain, position_feet_in_world, self.foot_offset_m, self.height_m)

    def foot_frames(self, position_contact_in_world: np.ndarray) -> np.ndarray:
        """The foot frames (N, 3) [m] in W of feet touching the ground at the contact points
        (N, 3) [m] on it: contact point + foot_offset_m n (planner/gaits/ball_stance.py)."""
        return foot_frames_on_surface(self.terrain, position_contact_in_world, self.foot_offset_m)


def surface_footholds_for(
    terrain,
    legs,
    height_m: float,
    friction: float | None = None,
    foot_offset_m: float = 0.0,
    shank: ShankClearance | None = None,
    roll_m: float = 0.0,
    torque: StanceTorque | None = None,
) -> SurfaceFootholds | None:
    """The foothold search of a gait on ``terrain``: None unless it is a :class:`TerrainMap`
    (what :func:`planner.terrain.terrain_map.gait_terrain` hands the gaits only for ground
    that is not a level floor), whose footholds then go on its surfaces; ``friction``:
    mu_plan (None: slopes limited by the tilt alone); ``foot_offset_m``: the foot frame's
    height above its contact point [m] (SurfaceFootholds); ``shank``: the tibia capsule check
    (planner/gaits/shank_clearance.py shank_clearance_for), None to not ask it; ``roll_m``:
    how far a stance contact point rolls [m] (planner/gaits/stance_roll.py); ``torque``: the
    static torque preference (planner/gaits/stance_torque.py stance_torque_for)."""
    if not isinstance(terrain, TerrainMap):
        return None
    return SurfaceFootholds(
        terrain,
        tuple(legs),
        float(height_m),
        friction=friction,
        foot_offset_m=float(foot_offset_m),
        shank=shank,
        roll_m=float(roll_m),
        torque=torque,
    )
