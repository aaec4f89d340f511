"""The builder that checks every step (planner/gaits/steps.py) before it is accepted.

Stability (thesis §5.1, checked before any joint value exists): a transfer is accepted only if
the CoG projection is inside the support triangle of the other three feet with S_m >=
threshold. When it is not, :class:`StepBuilder` inserts one "shift" body step that moves the
CoG the shortest way towards the triangle's incenter until S_m = threshold + SHIFT_EXTRA_M
(the thesis instead accepts S_m = 0; see workspace.py, preset "thesis"). If even the incenter
is too close to an edge, :class:`PlanningError` names the waypoint and the margin.

With ``fold_shifts`` (default preset) the shift costs no time when it can be folded into the
last body or rotate step (planner/gaits/fold.py); only when it cannot is a 1-unit shift step
inserted. A transfer while the base moves (the crawl) is planner/gaits/moving_transfer.py.

With ``swing_com`` (the default preset) the point kept inside is the whole-robot CoM at every
checked configuration of the swing (planner/model.py) instead of the body CoG.

With ``surface_footholds`` (a terrain file's surfaces, planner/gaits/surface_footholds.py) every
placed foothold is first moved to the nearest valid point on a surface (its z the surface
height) and the checks above run on that foothold; a body step's base z, and that of a
transfer whose base moves (the crawl), is the stance feet's mean height plus the body height.
The margins stay those of the xy projection (the support polygon projected along gravity).
A crawl transfer (planner/gaits/moving_transfer.py) checks its margins at the gait's nominal
foothold before :meth:`StepBuilder.append_step` moves it; the verification of the samples
(planner/trajectory/verify.py) checks the margins of the moved one.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from planner.errors import PlanningError
from planner.gaits.body_pace import body_units
from planner.gaits.fold import fold_shift
from planner.gaits.rolled_contacts import RolledContacts
from planner.gaits.steps import (
    COM_SHIFT_ROUNDS,
    SHIFT_EXTRA_M,
    SHIFT_UNITS,
    TRANSFER_UNITS,
    Phase,
    Step,
    StepKind,
)
from planner.gaits.surface_footholds import SurfaceFootholds
from planner.gaits.swing_pace import transfer_units

if TYPE_CHECKING:
    from planner.gaits.load_caps import LoadCaps
    from planner.gaits.sway_timing import SwayTiming
from planner.stability.margin import (
    MARGIN_TOLERANCE,
    support_margin,
    triangle_margin_xy,
    triangle_margins,
)
from planner.stability.shifts import shift_for_margin
from planner.trajectory.samples import LEGS

#: Points tried for a shift whose nearest point breaks a stance leg's effort budget
#: (StepBuilder._capped): offsets (K, 2) [m] from it, rings CAP_RING_M apart out to
#: CAP_REACH_M, 32 directions each.
CAP_RING_M = 0.005
CAP_REACH_M = 0.15
#: The base's step [m] over which StepBuilder._offset_gain measures how the swing CoM's
#: offset from the base moves with the base.
CAP_PROBE_M = 0.01
#: Points of the support triangle StepBuilder._capped_base checks at a time, nearest first.
CAP_BATCH = 1024
#: Candidate bases keeping the budget that StepBuilder._first_reachable tries (each costs
#: the swing's whole-body CoM) before the caps give up on a batch.
CAP_REACH_TRIES = 16
CAP_CANDIDATES = np.array(
    [[0.0, 0.0]]
    + [
        [r * np.cos(a), r * np.sin(a)]
        for r in np.arange(CAP_RING_M, CAP_REACH_M + 1e-9, CAP_RING_M)
        for a in np.linspace(0.0, 2.0 * np.pi, 32, endpoint=False)
    ]
)

#: The terrain's foothold rule (planner/terrain/base.py foothold_rule): called with every
#: foothold (3,) in W [m] as a transfer places it; it raises FootholdRefused to abandon the
#: gait there (the ditch, planner/studies/ditch.py), or a crawl attempt (planner/gaits/crawl.py).
#: A pure function of the foothold: a memoised first segment (planner/gaits/first_walk.py)
#: asks it again about the footholds it placed.
FootholdCheck = Callable[[np.ndarray], None]

#: Whole-body CoM (x, y) in W [m], (K, 2), over the swing of a leg: (base (3,) [m], yaw
#: [rad], feet (4, 3) [m], leg index, foothold end (3,) [m]) -> points (PlanningModel).
SwingCom = Callable[[np.ndarray, float, np.ndarray, int, np.ndarray], np.ndarray]


class OverBudget(PlanningError):
    """No shift lets a leg lift with the stance legs within both the margin and their effort
    budget (StepBuilder._refuse_over_budget names the joint and the step)."""


class TimeLimitReached(Exception):
    """The plan cannot end before StepBuilder.time_limit: a step ended at or after it, or the
    time so far and the bound on the rest reach it (the argument: the least time [units] the
    plan can take, at least the limit)."""


class StepBuilder:
    """Accumulates checked steps from a start pose (see module docstring).

    Attributes:
        t: current time [units]; base: CoG (3,) [m]; yaw: heading [rad];
        feet: feet in W (4, 3) [m]; nominal_base / nominal_yaw: the gait's reference pose
        (the base without stability shifts); threshold: minimum S_m on a lift [m];
        swing_com: None to keep the body CoG inside the support triangle (thesis §5.1), or
        the whole-body CoM over a swing (:data:`SwingCom`) to keep that inside instead, at
        every checked configuration of the swing; foothold_check: None, or a
        :data:`FootholdCheck` called with every foothold placed; surface_footholds: None
        (level ground), or the foothold search on a terrain's surfaces (module docstring);
        rolled_contacts: None (point feet: the contact points are the footholds), or the
        predictor of where ball feet touch the ground after rolling since touchdown
        (planner/gaits/rolled_contacts.py), which every lift and shift is checked on.
    """

    def __init__(
        self,
        position_base_in_world: np.ndarray,
        yaw: float,
        position_feet_in_world: np.ndarray,
        threshold: float,
        *,
        fold_shifts: bool = False,
        swing_com: SwingCom | None = None,
        foothold_check: FootholdCheck | None = None,
        surface_footholds: SurfaceFootholds | None = None,
        rolled_contacts: RolledContacts | None = None,
    ) -> None:
        self.t = 0.0
        self.base = np.array(position_base_in_world, dtype=float)
        self.yaw = float(yaw)
        self.feet = np.array(position_feet_in_world, dtype=float)
        self.nominal_base = self.base.copy()
        self.nominal_yaw = self.yaw
        #: The base pose (x, y, z [m], yaw [rad]) before the first step: the ball feet roll
        #: from it on the first base move (planner/gaits/rolled_contacts.py).
        self.start_pose = np.append(self.base, self.yaw)
        self.threshold = float(threshold)
        self.steps: list[Step] = []
        self.waypoint_index: int | None = None
        self.waypoint: tuple[float, float] | None = None
        self.n_shifts = 0
        self.fold_shifts = bool(fold_shifts)
        self.n_folded = 0
        #: Steps before this index keep their end pose (no fold moves them: a body step that
        #: arrived at a waypoint, planner/gaits/omni.py).
        self.fold_fence = 0
        self.swing_com = swing_com
        self.foothold_check = foothold_check
        self.surface_footholds = surface_footholds
        self.rolled_contacts = rolled_contacts
        #: (base start, base end, yaw, feet, leg, foothold end) -> (CoM (K, 2), base (K, 2))
        #: in W [m] over a swing whose base moves (the crawl; PlanningModel), or None.
        self.moving_swing_com: Callable[..., tuple[np.ndarray, np.ndarray]] | None = None
        self._com_cache: dict[bytes, np.ndarray] = {}
        #: With a value [units], a step ending at or after it raises :class:`TimeLimitReached`
        #: (plan_path's gait "auto" stops building a gait that cannot be the faster one).
        self.time_limit: float | None = None
        #: None, or the duration rule of the crawl's four-foot body moves
        #: (planner/gaits/sway_timing.py: long enough for the joints to carry the move's
        #: acceleration within their effort budget).
        self.sway_timing: SwayTiming | None = None
        #: The four-foot stand [units] a plan whose first step is a transfer starts with
        #: (planner/gaits/walk.py start_stand_units; 0: none), and the one this plan has
        #: (set by its first step).
        self.stand_units = 0.0
        self.lead_units = 0.0
        #: The four-foot stand [units] between a touchdown and the next lift-off where the
        #: gait swings two legs back to back (planner/gaits/walk.py swap_stand_units; 0:
        #: none): :meth:`append_step` leaves that much time before a transfer that follows a
        #: transfer, and the plan fills it with a stand (walk.py ``_with_swap_stands``).
        self.swap_stand_units = 0.0
        #: None, or a lower bound [units] on the time the rest of the walk takes from the
        #: nominal CoG (x, y) [m] (set by the gait for the segment it walks:
        #: planner/gaits/without_turning.py); :meth:`check_time_limit` adds it.
        self.rest_units: Callable[[np.ndarray], float] | None = None
        #: None, or the zero-moment point (x, y) in W [m] (K, 2) over a still-base swing
        #: (:data:`SwingCom`'s arguments; PlanningModel.swing_zmp_in_world): with
        #: ``swing_com``, a lift is also checked for the ZMP at least :attr:`zmp_least` [m]
        #: inside the other feet (the contact-force rule the pipeline checks on the samples,
        #: planner/stability/contact_forces.py), and shifted until it is.
        self.swing_zmp: SwingCom | None = None
        self.zmp_least = 0.0
        #: None, or the zero-moment point's largest distance [m] from the whole-robot CoM over
        #: a still-base swing lasting ``units`` at 1 s a unit (base, yaw, feet, leg, target,
        #: units): a transfer then lasts as long as planner/gaits/swing_pace.py asks.
        self.swing_excursion: Callable[..., float] | None = None
        #: None, or the load-share caps a lift's shift keeps (planner/gaits/load_caps.py:
        #: the stance legs within their effort budget while the leg swings).
        self.load_caps: LoadCaps | None = None

    @property
    def t_plan(self) -> float:
        """The plan's time [units] at :attr:`t`: the steps' time and the four-foot stand the
        plan will start with (:attr:`lead_units`)."""
        return self.t + self.lead_units

    def _swing_com_points(
        self, base: np.ndarray, feet: np.ndarray, leg: int, target: np.ndarray
    ) -> np.ndarray:
        """``swing_com`` memoised: the fold re-checks the lifts since the last body step at
        the base they were accepted at (cleared at every body or rotate step)."""
        key = b"".join(
            (
                np.asarray(base, float).tobytes(),
                np.float64(self.yaw).tobytes(),
                np.asarray(feet, float).tobytes(),
                bytes([leg]),
                np.asarray(target, float).tobytes(),
            )
        )
        points = self._com_cache.get(key)
        if points is None:
            if self.swing_com is None:
                raise TypeError("StepBuilder has no swing_com to check the whole-body CoM")
            points = self._com_cache[key] = self.swing_com(base, self.yaw, feet, leg, target)
        return points

    def _swing_zmp_points(
        self, base: np.ndarray, feet: np.ndarray, leg: int, target: np.ndarray
    ) -> np.ndarray:
        """``swing_zmp``'s points (memoised by the model)."""
        assert self.swing_zmp is not None
        return self.swing_zmp(base, self.yaw, feet, leg, target)

    #: The mutable fields :meth:`snapshot` copies and :meth:`restore` sets.
    SNAPSHOT_FIELDS = (
        "t",
        "base",
        "yaw",
        "feet",
        "nominal_base",
        "nominal_yaw",
        "steps",
        "n_shifts",
        "n_folded",
        "fold_fence",
        "lead_units",
    )

    def snapshot(self) -> dict:
        """A copy of the builder's mutable fields (SNAPSHOT_FIELDS: the steps, the pose, the
        counters): the crawl rolls back a segment it cannot walk (planner/gaits/crawl.py),
        and a plan's first segment is replayed from a memo (planner/gaits/first_walk.py)."""
        return {name: _copied(getattr(self, name)) for name in self.SNAPSHOT_FIELDS}

    def restore(self, snapshot: dict) -> None:
        """Set the fields saved by :meth:`snapshot` (copied again: it can be restored
        twice)."""
        for name in self.SNAPSHOT_FIELDS:
            setattr(self, name, _copied(snapshot[name]))
        self.clear_com_cache()

    def clear_com_cache(self) -> None:
        """Forget the memoised whole-body CoM points (the base moved)."""
        self._com_cache.clear()

    def error(self, reason: str) -> PlanningError:
        """A :class:`PlanningError` naming the current waypoint."""
        return PlanningError(reason, self.waypoint_index, self.waypoint)

    def append_step(
        self,
        kind: StepKind,
        leg: int | None,
        duration: float,
        base_end: np.ndarray,
        yaw_end: float,
        foot_end: np.ndarray | None,
        label: str,
        phase: Phase,
    ) -> None:
        """Add a step from the current pose, unchecked (callers check its stability first),
        and move the pose to its end; ask ``foothold_check`` about a placed foothold. With
        ``surface_footholds`` the foothold is put on a surface (unchanged when
        :meth:`transfer` placed it already) and the base z follows the feet (module
        docstring). A transfer right after a transfer starts :attr:`swap_stand_units`
        after it (the stand of the load transfer)."""
        if StepKind(kind) == StepKind.TRANSFER and self.steps and self.steps[-1].kind == kind:
            self.t += self.swap_stand_units
        if self.surface_footholds is not None:
            base_end, foot_end = self.surface_footholds.step_end(
                StepKind(kind) != StepKind.TRANSFER,
                leg,
                self.base,
                base_end,
                yaw_end,
                self.feet,
                foot_end,
                self.stance_motion_xy(),
                None if leg is None else self.next_swing_leg(leg),
            )
        self.steps.append(
            Step(
                kind=StepKind(kind),
                leg=None if leg is None else LEGS[leg],
                t_start=self.t,
                t_end=self.t + duration,
                position_base_start_in_world=self.base.copy(),
                position_base_end_in_world=np.array(base_end, dtype=float),
                yaw_base_start=self.yaw,
                yaw_base_end=float(yaw_end),
                foothold_start_in_world=None if leg is None else self.feet[leg].copy(),
                foothold_end_in_world=None if foot_end is None else np.array(foot_end, float),
                label=label,
                waypoint_index=self.waypoint_index,
                position_feet_in_world=self.feet.copy(),
                phase=Phase(phase),
            )
        )
        if len(self.steps) == 1:
            self.lead_units = self.stand_units if StepKind(kind) == StepKind.TRANSFER else 0.0
        self.t += duration
        if self.time_limit is not None and self.t_plan >= self.time_limit:
            raise TimeLimitReached(self.t_plan)
        self.base = np.array(base_end, dtype=float)
        self.yaw = float(yaw_end)
        if leg is not None and foot_end is not None:
            self.feet[leg] = foot_end
            if self.foothold_check is not None:
                self.foothold_check(self.feet[leg].copy())

    def check_time_limit(self) -> None:
        """TimeLimitReached when the plan's time so far and :attr:`rest_units`' bound on the
        rest reach :attr:`time_limit`: the plan cannot end before it. The gaits call it
        where no step built since could be rolled back (a segment's start, a crawl's
        attempt: planner/gaits/crawl_or_creep.py, a creeping half cycle: omni.omni_to)."""
        if self.time_limit is None or self.rest_units is None:
            return
        least_units = self.t_plan + self.rest_units(self.nominal_base[:2])
        if least_units >= self.time_limit:
            raise TimeLimitReached(least_units)

    def next_swing_leg(self, leg: int) -> int | None:
        """The leg that swung right after ``leg``'s last swing (the gaits repeat their swing
        order: the leg whose swing the stance of ``leg`` carries next), or None before that is
        known. The foothold search on surfaces weighs that support's torques
        (planner/gaits/stance_torque.py)."""
        name, later = LEGS[leg], None
        for step in reversed(self.steps):
            if step.leg is None:
                continue
            if step.leg == name and later is not None:
                return LEGS.index(later)
            later = step.leg
        return None

    def stance_motion_xy(self) -> np.ndarray | None:
        """The body's xy motion [m] (2,) expected after a foot touches down: that of the last
        body step (the gaits repeat their body steps; a shift, which moves the body towards a
        support triangle, and a rotate are not asked), or None before the first. The foothold
        search on surfaces measures the shank over it (SurfaceFootholds.place)."""
        for step in reversed(self.steps):
            if step.kind is StepKind.BODY and step.phase is not Phase.SHIFT:
                return (step.position_base_end_in_world - step.position_base_start_in_world)[:2]
        return None

    def lift_margin(
        self,
        leg: int,
        target_in_world: np.ndarray | None = None,
        base: np.ndarray | None = None,
        feet: np.ndarray | None = None,
        steps: Sequence[Step] | None = None,
    ) -> float:
        """S_m [m] of lifting ``leg`` with the base at ``base`` (default: where it is now)
        and the feet on the footholds ``feet`` (default: now), on their contact points
        (:meth:`contact_points` after ``steps``, default the steps so far): of the body CoG,
        or with ``swing_com`` the smallest of the whole-body CoM over the swing to
        ``target_in_world``. -inf where a foot is out of reach on the swing (its CoM has NaN
        rows): such a lift keeps no margin. A NaN margin passed every ``margin < threshold``
        test, so the transfer was built without a shift and refused by its own sample
        verification ("a foot target is out of reach", issue 21: the SILO4 variant L2 0.3,
        L3 0.35, Lb 0.25 m at h 0.2148 m, (1, 1), creep transfer RF of the plain gait)."""
        base = self.base if base is None else base
        feet = self.contact_points(self.feet if feet is None else feet, base, steps)
        a, b, c = (tuple(feet[k, :2]) for k in range(4) if k != leg)
        if self.swing_com is None or target_in_world is None:
            return triangle_margin_xy(a, b, c, (base[0], base[1]))
        points = self._swing_com_points(base, feet, leg, target_in_world)
        if not np.all(np.isfinite(points)):
            return -np.inf  # a foot out of reach on the swing
        margin = float(np.min(triangle_margins(np.array([a, b, c]), points)))
        if self.swing_zmp is None:
            return margin
        # the ZMP's own rule, on the same scale: its margin less zmp_least against 0
        zmp = self._swing_zmp_points(base, feet, leg, target_in_world)
        if not np.all(np.isfinite(zmp)):
            return -np.inf
        zmp_margin = float(np.min(triangle_margins(np.array([a, b, c]), zmp)))
        return min(margin, zmp_margin - self.zmp_least + self.threshold)

    def contact_points(
        self, feet: np.ndarray, base: np.ndarray, steps: Sequence[Step] | None = None
    ) -> np.ndarray:
        """Where the feet standing on the footholds ``feet`` (4, 3) [m] touch the ground
        when the base, after ``steps`` (default: the steps so far), has moved straight on to
        ``base`` (3,) [m]: ``feet`` itself for point feet, else rolled
        (planner/gaits/rolled_contacts.py); PlanningError when a stance foot is out of
        reach on the way."""
        if self.rolled_contacts is None:
            return feet
        steps = self.steps if steps is None else steps
        rolled = self.rolled_contacts.contact_points(steps, feet, base, self.yaw, self.start_pose)
        if not np.all(np.isfinite(rolled)):
            raise self.error("a stance foot is out of reach on the base path of a lift")
        return rolled

    def com_spread(
        self,
        leg: int,
        target: np.ndarray,
        base: np.ndarray,
        feet: np.ndarray,
        steps: Sequence[Step] | None = None,
    ) -> tuple[np.ndarray, float]:
        """(c, r): the whole-body CoM over the swing stays within r [m] of base + c (c (2,)
        [m], the middle of its bounding box), so S_m(base + c) >= threshold + r is enough."""
        if self.swing_com is None:
            return np.zeros(2), 0.0
        feet = self.contact_points(feet, base, steps)
        com = self._swing_com_points(base, feet, leg, target)
        off = com - base[:2]
        if self.swing_zmp is not None:
            # each ZMP moved towards its CoM by the threshold less zmp_least (at most that
            # far: its margin changes by no more): S_m >= threshold of that point is enough
            # for the ZMP's zmp_least
            away = self._swing_zmp_points(base, feet, leg, target) - com
            length = np.hypot(*away.T)[:, None]
            slack = self.threshold - self.zmp_least
            with np.errstate(invalid="ignore", divide="ignore"):
                keep = np.clip(1.0 - slack / length, 0.0, None) if slack > 0 else 1.0
            off = np.vstack([off, off + away * keep])
        if not np.all(np.isfinite(off)):
            raise self.error(f"a foot of the lift of leg {LEGS[leg]} is out of reach")
        centre = 0.5 * (off.min(axis=0) + off.max(axis=0))
        return centre, float(np.max(np.hypot(*(off - centre).T)))

    def transfer(
        self, leg: int, target_in_world: np.ndarray, label: str, phase: Phase = Phase.CREEP
    ) -> None:
        """Swing ``leg`` to ``target_in_world`` (3,) [m], shifting the CoG first if needed
        (folded into the last body phase when ``fold_shifts`` and possible:
        planner/gaits/fold.py)."""
        target_in_world = np.asarray(target_in_world, dtype=float)
        if self.surface_footholds is not None:
            target_in_world = self.surface_footholds.place(
                leg,
                target_in_world,
                self.base,
                self.yaw,
                self.feet,
                self.stance_motion_xy(),
                next_leg=self.next_swing_leg(leg),
            )
        if (
            self.lift_margin(leg, target_in_world) < self.threshold - MARGIN_TOLERANCE
            and not (self.fold_shifts and fold_shift(self, leg, target_in_world))
        ) or self._caps_broken(leg, target_in_world):
            shifted = self._shifted_base(leg, target_in_world, label)
            self.body(
                shifted,
                self.yaw,
                # as long as the ZMP's excursion asks (planner/gaits/body_pace.py)
                body_units(
                    float(np.hypot(*(shifted[:2] - self.base[:2]))),
                    self.cog_height(),
                    self.threshold,
                    SHIFT_UNITS,
                ),
                StepKind.BODY,
                "shift",
                Phase.SHIFT,
            )
            self.n_shifts += 1
        self.append_step(
            StepKind.TRANSFER,
            leg,
            self.transfer_units(leg, target_in_world),
            self.base,
            self.yaw,
            target_in_world,
            label,
            phase,
        )

    def transfer_units(self, leg: int, target_in_world: np.ndarray) -> float:
        """Time units of ``leg``'s transfer to ``target_in_world`` from where the base and
        feet are now: TRANSFER_UNITS, or as long as the swing's ZMP excursion asks
        (planner/gaits/swing_pace.py) with :attr:`swing_excursion`."""
        if self.swing_excursion is None:
            return TRANSFER_UNITS
        excursion = self.swing_excursion
        feet = self.contact_points(self.feet, self.base)
        base, yaw = self.base.copy(), self.yaw
        return transfer_units(
            lambda units: excursion(base, yaw, feet, leg, target_in_world, units),
            self.threshold,
            TRANSFER_UNITS,
        )

    def cog_height(self) -> float:
        """Height of the CoG over the mean of the feet's ground contacts [m] (a ball foot's
        frame is its rolling radius above the ground)."""
        radius = 0.0 if self.rolled_contacts is None else self.rolled_contacts.ball.rolling_radius_m
        return float(self.base[2] - (self.feet[:, 2].mean() - radius))

    def _shifted_base(self, leg: int, target: np.ndarray, label: str) -> np.ndarray:
        """The base after a shift step that lets ``leg`` lift (:meth:`_shifted_base_with`).
        Where no base keeps the swing's zero-moment point inside at the request's unit time
        (a unit time short enough for the legs' accelerations to throw it metres out), the
        shift keeps the whole-body CoM's margin alone and the run's contact-force check on
        the samples decides (refuses, reports, or with ``--unit-time auto`` slows the plan
        until it holds), as it did before the builder checked the ZMP."""
        try:
            return self._shifted_base_with(leg, target, label)
        except PlanningError:
            if self.swing_zmp is None:
                raise
        zmp, self.swing_zmp = self.swing_zmp, None
        try:
            return self._shifted_base_with(leg, target, label)
        finally:
            self.swing_zmp = zmp

    def _shifted_base_with(self, leg: int, target: np.ndarray, label: str) -> np.ndarray:
        """The base after a shift step that lets ``leg`` lift: the CoG moved the shortest way
        towards the incenter of the other feet until S_m = threshold + SHIFT_EXTRA_M (else
        = threshold); with ``swing_com`` the whole-body CoM over the swing, the base moved
        again until it holds (COM_SHIFT_ROUNDS). With :attr:`load_caps`, a point near it
        whose stance legs keep their effort budget (:meth:`_capped`); where the base found
        so still breaks it at a point of the swing's CoM (:meth:`over_budget`), the whole
        support triangle searched again (:meth:`_capped_base`), and OverBudget naming the
        joint and the step where no point keeps both the margin and the budget."""
        base = self._shift_rounds(leg, target, label, whole_triangle=False)
        assert base is not None  # (None only from the whole triangle's search)
        if self.load_caps is None or self.over_budget(leg, target, base) is None:
            return base
        try:
            searched = self._shift_rounds(leg, target, label, whole_triangle=True)
        except PlanningError:  # no base settles there: the first one's joint is named
            searched = None
        if searched is not None:
            base = searched
        self._refuse_over_budget(leg, target, base, label)
        return base

    def _shift_rounds(
        self, leg: int, target: np.ndarray, label: str, whole_triangle: bool
    ) -> np.ndarray | None:
        """The rounds of :meth:`_shifted_base_with` from the base where it is, the caps' point
        by :meth:`_capped` or, ``whole_triangle``, by :meth:`_capped_base` (kept when its
        base keeps the budget at every point of the swing's CoM; None where no point of the
        triangle keeps it). Where the swing is out of reach from where the base stands
        (earlier shifts for the budget can leave it far from the nominal CoG: the SILO4
        variant L2 0.3, L3 0.35, Lb 0.25 m at h 0.2148 m stood 0.26 m behind it when RF was
        to swing to its front foothold), the rounds start from the nominal CoG instead, where
        the workspace keeps the footholds in reach (planner/workspace/foothold_layout.py)."""
        base = self.base.copy()
        if not self.reaches(leg, target, base):
            nominal = np.array([self.nominal_base[0], self.nominal_base[1], base[2]])
            if self.reaches(leg, target, nominal):
                base = nominal
        rounds = 1 if self.swing_com is None and self.rolled_contacts is None else COM_SHIFT_ROUNDS
        for k in range(rounds):
            last = k == rounds - 1
            feet = self.contact_points(self.feet, base)
            support = np.array([feet[k, :2] for k in range(4) if k != leg])
            centre, radius = self.com_spread(leg, target, base, self.feet)
            point = base[:2] + centre
            cog = shift_for_margin(support, point, self.threshold + radius + SHIFT_EXTRA_M)
            capped = None
            if cog is not None and self.load_caps is not None:
                if whole_triangle:
                    capped = self._capped_base(leg, target, base, feet, support, point, radius)
                    if capped is None:
                        return None
                else:
                    cog = self._capped(leg, target, base, feet, support, point, radius, cog)
            if cog is None:
                cog = shift_for_margin(support, point, self.threshold + radius)
            if cog is None:
                raise self.error(
                    f"no stable lift of leg {LEGS[leg]} ({label}): the support triangle of the "
                    f"other feet has no point with margin >= {self.threshold + radius:.4g} m"
                )
            if capped is not None:
                base = capped
            else:
                base = np.array([base[0] + cog[0] - point[0], base[1] + cog[1] - point[1], base[2]])
            if (
                rounds == 1
                or self.lift_margin(leg, target, base) >= self.threshold - MARGIN_TOLERANCE
            ) and (last or self._kept(leg, target, base, whole_triangle)):
                return base
        raise self.error(
            f"no stable lift of leg {LEGS[leg]} ({label}): the whole-body CoM "
            f"does not settle with margin >= {self.threshold:.4g} m"
        )

    def _kept(self, leg: int, target: np.ndarray, base: np.ndarray, whole_triangle: bool) -> bool:
        """Whether a shift round's ``base`` keeps the budget for the lift of ``leg`` (with
        ``whole_triangle`` at every point of the swing's CoM, :meth:`over_budget`, else over
        its disc, :meth:`_caps_broken`); False where a foot is out of reach there (the next
        round moves the base again, as it does where the margin is short)."""
        if not self.reaches(leg, target, base):
            return False
        try:
            if whole_triangle:
                return self.over_budget(leg, target, base) is None
            return not self._caps_broken(leg, target, base)
        except PlanningError:
            return False

    def _caps_broken(self, leg: int, target: np.ndarray, base: np.ndarray | None = None) -> bool:
        """Whether lifting ``leg`` with the base at ``base`` (default: where it is) breaks a
        stance leg's effort budget (:attr:`load_caps`; False without them, and where a foot
        is out of reach there: the reach checks refuse that, not the caps)."""
        if self.load_caps is None:
            return False
        base = self.base if base is None else base
        try:
            feet = self.contact_points(self.feet, base)
            centre, radius = self.com_spread(leg, target, base, self.feet)
        except PlanningError:
            return False
        point = base[:2] + centre
        return not bool(self.load_caps.keeps(leg, base, self.yaw, feet, point[None], radius)[0])

    def _capped(
        self,
        leg: int,
        target: np.ndarray,
        base: np.ndarray,
        feet: np.ndarray,
        support: np.ndarray,
        point: np.ndarray,
        radius: float,
        nearest: np.ndarray,
    ) -> np.ndarray:
        """The shift's CoM point: ``nearest`` (shift_for_margin's) when the three stance legs
        keep their budget there (:attr:`load_caps`), else the nearest to ``point`` of the
        CAP_CANDIDATES points around ``nearest`` (rings CAP_RING_M apart) with the margin
        whose base keeps it, every foot placeable and ``leg``'s swing path to ``target`` within
        its joint limits (LoadCaps.placeable: reach, joint limits, tibias); ``nearest`` when
        none does (:meth:`_shifted_base_with` then searches the whole triangle)."""
        assert self.load_caps is not None
        cand = nearest + CAP_CANDIDATES
        margin = self.threshold + radius + SHIFT_EXTRA_M
        tri = np.repeat(support[None], len(cand), axis=0)
        cand = cand[support_margin(tri, np.ones((len(cand), 3), bool), cand) >= margin]
        cand = cand[np.argsort(np.hypot(*(cand - point).T), kind="stable")]
        bases = np.column_stack(
            [base[0] + cand[:, 0] - point[0], base[1] + cand[:, 1] - point[1]]
            + [np.full(len(cand), base[2])]
        )
        ok = self.load_caps.keeps(leg, bases, self.yaw, feet, cand, radius)
        ok[ok] = self.load_caps.placeable(bases[ok], self.yaw, self.feet, (leg, target))
        first = self._first_reachable(leg, target, bases, ok)
        return nearest if first is None else cand[first]

    def _first_reachable(
        self, leg: int, target: np.ndarray, bases: np.ndarray, ok: np.ndarray
    ) -> int | None:
        """The index of the first of ``bases`` (N, 3) [m] marked ``ok`` (N,) from which the
        lift of ``leg`` to ``target`` keeps every foot in reach (:meth:`reaches`), at most
        CAP_REACH_TRIES of them tried; None when none does. LoadCaps.placeable checks the
        feet and a cosine swing path, not the swing's whole-body CoM (:meth:`com_spread`,
        its own path and rolled contacts): on the SILO4 xacro variant (L2 0.3, L3 0.35,
        Lb 0.25 m, h 0.4 m, facing (0, 1) -> (1, 1)) a base placeable there put LH's swing
        out of reach, and the next shift round refused the walk main plans."""
        for index in np.flatnonzero(ok)[:CAP_REACH_TRIES]:
            if self.reaches(leg, target, bases[index]):
                return int(index)
        return None

    def reaches(self, leg: int, target: np.ndarray, base: np.ndarray) -> bool:
        """Whether the lift of ``leg`` to ``target`` (3,) [m] with the base at ``base`` (3,)
        [m] keeps every foot in reach: the stance feet's contact points and the swing's
        whole-body CoM exist (:meth:`contact_points`, :meth:`com_spread`, which raise
        "out of reach" otherwise)."""
        try:
            self.com_spread(leg, target, np.asarray(base, dtype=float), self.feet)
        except PlanningError:
            return False
        return True

    def _capped_base(
        self,
        leg: int,
        target: np.ndarray,
        base: np.ndarray,
        feet: np.ndarray,
        support: np.ndarray,
        point: np.ndarray,
        radius: float,
    ) -> np.ndarray | None:
        """The base (3,) [m] of the point of the support triangle nearest to ``point``
        (CAP_RING_M apart) with the margin (threshold + ``radius`` [m], and SHIFT_EXTRA_M
        more where a point keeps it), whose base keeps the three stance legs within their
        budget (:attr:`load_caps`), every foot placeable and ``leg``'s swing path within its
        joint limits (LoadCaps.placeable); None when none does.

        The CoM's offset c from the base moves with the base: the stance legs stay behind
        (the CoM follows the base with a gain of ~0.9, steps.COM_SHIFT_ROUNDS). A base
        moved by Δ puts the CoM near point + (I + K) Δ, K = ∂c/∂base (2, 2) measured by
        moving the base CAP_PROBE_M along each axis (:meth:`_offset_gain`), so the base of a
        point p is base + (I + K)⁻¹ (p - point). :meth:`_capped` takes K = 0 and looks
        within CAP_REACH_M of the nearest point: on mantis at h 0.2055 m (the corpus's case
        1, seed 20261202: a 0.13 m shift before LF's spin transfer) its point kept the
        budget but its base put the CoM 7 mm away, where arm3_lift needed 35.03 N m (budget
        34.00 N m), and the points that keep it lie 0.2 m off, across the triangle."""
        assert self.load_caps is not None
        lo, hi = support.min(axis=0), support.max(axis=0)
        xs, ys = (np.arange(a, b + CAP_RING_M, CAP_RING_M) for a, b in zip(lo, hi))
        cand = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
        margins = triangle_margins(support, cand)
        inside = margins >= self.threshold + radius
        cand, margins = cand[inside], margins[inside]
        order = np.argsort(np.hypot(*(cand - point).T), kind="stable")
        cand, margins = cand[order], margins[order]
        gain = np.eye(2) + self._offset_gain(leg, target, base, point)
        moves = np.linalg.solve(gain, (cand - point).T).T
        bases = np.column_stack([base[:2] + moves, np.full(len(cand), base[2])])
        # SHIFT_EXTRA_M to spare where a point keeps it (as shift_for_margin's), else the
        # margin alone; nearest first, CAP_BATCH points at a time
        for least in (self.threshold + radius + SHIFT_EXTRA_M, self.threshold + radius):
            rows = np.flatnonzero(margins >= least)
            for start in range(0, len(rows), CAP_BATCH):
                batch = rows[start : start + CAP_BATCH]
                ok = self.load_caps.keeps(leg, bases[batch], self.yaw, feet, cand[batch], radius)
                ok[ok] = self.load_caps.placeable(
                    bases[batch][ok], self.yaw, self.feet, (leg, target)
                )
                first = self._first_reachable(leg, target, bases[batch], ok)
                if first is not None:
                    return bases[batch[first]]
        return None

    def _offset_gain(
        self, leg: int, target: np.ndarray, base: np.ndarray, point: np.ndarray
    ) -> np.ndarray:
        """K = ∂c/∂base (2, 2): how the swing CoM's offset c = point - base (com_spread's
        centre) moves with the base, by differences over CAP_PROBE_M [m] along x and y
        (:meth:`_capped`); zeros where a probe takes a foot out of reach."""
        gain = np.zeros((2, 2))
        for axis in range(2):
            probe = np.array(base, dtype=float)
            probe[axis] += CAP_PROBE_M
            try:
                centre, _ = self.com_spread(leg, target, probe, self.feet)
            except PlanningError:
                return np.zeros((2, 2))
            gain[:, axis] = (centre - (point - base[:2])) / CAP_PROBE_M
        return gain

    def over_budget(
        self,
        leg: int,
        target: np.ndarray,
        base: np.ndarray,
        feet: np.ndarray | None = None,
        steps: Sequence[Step] | None = None,
    ) -> tuple[str, float, float] | None:
        """(joint, static torque [N m], budget [N m]) of the stance joint furthest over its
        effort budget when ``leg`` lifts with the base at ``base`` and the feet on the
        footholds ``feet`` (default: now; contact points after ``steps``, as
        :meth:`contact_points`), at a point of the swing's whole-body CoM
        (LoadCaps.stance_torques: the three-foot split the run's check makes, at the CoM
        itself, not the disc :meth:`_caps_broken` bounds it by), or None when every stance
        joint keeps its budget (or there are no :attr:`load_caps`)."""
        if self.load_caps is None:
            return None
        footholds = self.feet if feet is None else feet
        contacts = self.contact_points(footholds, base, steps)
        if self.swing_com is None:
            points = np.asarray(base[:2], dtype=float)[None]
        else:
            points = self._swing_com_points(base, contacts, leg, target)
        tau = self.load_caps.stance_torques(leg, base, self.yaw, contacts, points)
        ratio = np.abs(tau) / self.load_caps.budget_nm[None]
        if not np.any(ratio > 1.0):
            return None
        row, joint = np.unravel_index(int(np.nanargmax(ratio)), ratio.shape)
        budget = float(self.load_caps.budget_nm[joint])
        return self.load_caps.robot.joint_names[joint], float(abs(tau[row, joint])), budget

    def _refuse_over_budget(
        self, leg: int, target: np.ndarray, base: np.ndarray, label: str
    ) -> None:
        """Raise OverBudget naming the stance joint and the step when the lift of ``leg``
        with the base at ``base`` breaks its effort budget (:meth:`over_budget`): no point
        the shift found keeps both the margin and the budget. Returns when none breaks it."""
        over = self.over_budget(leg, target, base)
        if over is None:
            return
        name, torque, budget = over
        raise OverBudget(
            f"no lift of leg {LEGS[leg]} ({label}) keeps both the margin "
            f">= {self.threshold:.4g} m and the effort budget: joint {name} needs "
            f"{torque:.2f} N m standing still, above its budget {budget:.2f} N m",
            self.waypoint_index,
            self.waypoint,
        )

    def four_foot_units(self, base_end: np.ndarray, nominal_units: float) -> float:
        """The duration [units] of a four-foot body move from the base to ``base_end`` (3,)
        [m]: ``nominal_units``, or longer where :attr:`sway_timing` asks it."""
        if self.sway_timing is None:
            return nominal_units
        return self.sway_timing.units(self.base, base_end, self.yaw, self.feet, nominal_units)

    def body(
        self,
        base_end: np.ndarray,
        yaw_end: float,
        duration: float,
        kind: str,
        label: str,
        phase: Phase = Phase.CREEP,
    ) -> None:
        """A four-foot body step (kind "body" or "rotate") to the given pose."""
        self.append_step(StepKind(kind), None, duration, base_end, yaw_end, None, label, phase)
        self.clear_com_cache()


def _copied(value):
    """A copy of a state value: arrays and the list of (immutable) steps are copied."""
    if isinstance(value, np.ndarray):
        return value.copy()
    return list(value) if isinstance(value, list) else value
