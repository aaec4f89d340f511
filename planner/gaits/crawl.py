"""The continuous crawl: a wave gait whose body moves while a leg swings.

Same frame and footholds as the omnidirectional gait (planner/gaits/omni.py): the body keeps its
heading, travel direction u (unit, base frame B) at any angle, each foot inside the ellipse
of semi-axes λ_x/2, λ_y/2 around its position 2. What changes:

- **Leg order.** One leg at a time, the creeping order of the nearest body axis
  (gaits.creep_pairs: the pair on the right of u rear leg first, then the other pair; for
  +x RH, RF, LH, LF), the crawl of a wave gait (thesis §4.2: the creeping gait is its
  special case with the body still during swings).
- **Staggered footholds.** Each swing lands its foot at the front of its ellipse, r u from
  position 2 (r = the ellipse radius along u) relative to the nominal CoG at touch-down.
  The body advances ``a`` during each swing and ``c = d a`` during each four-foot phase of
  d units (two per cycle: after each pair), so in the steady state consecutive feet of the
  order are a, a + c, a apart along u (a quarter stride for c = 0): the stroke is
  R = 2r = 3a + 2c (each foot moves back by the body's advance outside its own swing), the
  cycle takes T = 4 + 2d units and the nominal CoG advances 4a + 2c = R (4 + 2d)/(3 + 2d)
  per cycle. Each step's advance is capped by the stance feet's ellipse (omni's closed
  form) and by reach (halved until every foot is reachable with the shift reserve), so
  the ramp from any start stance needs no special case.
- **Sway.** A foot lifts only with the whole-body CoM inside the triangle of the other three
  by the threshold (0.02 m) over its swing. Two legs swinging one after the other on the
  same side share the triangle side away from them, so the body sways to the other side
  while they swing; between the pairs the swinging side changes and the CoM must cross the
  diagonal joining the next pair's front leg and the last pair's rear leg: that is what the
  four-foot phase is for (with d = 0 the CoM would sit on the diagonal, margin 0, the
  classic β = 3/4 limit of the quadruped wave gait). Each step's end base is the point
  nearest the nominal CoG with margin >= threshold + the CoM's spread over the swing +
  SHIFT_EXTRA_M in the triangle of the lift it ends and of the lift it starts
  (shifts.closest_point_with_margin, the builder's fold); the base moves on a straight
  line between those points, along which the margin of a fixed point offset is concave,
  so the ends bound it; the samples are verified anyway (planner/trajectory/verify.py).
- **Duty factor** β = (T - 1)/T = (3 + 2d)/(4 + 2d): 0.8 for d = 1/2.

Every step keeps the quintic of eq 5.16 (base and swing x, y) and the smooth lift, so q̇ and
q̈ are zero at every phase boundary as in the omni gait. Arriving: each advance is capped by
the distance left, so the nominal CoG lands on the waypoint; a pair that ends there gets no
four-foot sway (the arrival would undo it, and the next segment's first swing sways from the
waypoint). A four-foot body move lasts d units, or longer where the joints cannot carry its
acceleration within their effort budget (StepBuilder.four_foot_units, sway_timing.py).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from planner.errors import PlanningError
from planner.gaits.builder import StepBuilder
from planner.gaits.crawl_reach import REACH_HALVINGS, reachable_advance
from planner.gaits.creep_spin import creep_pairs
from planner.gaits.foothold_ellipse import ellipse_radius, offsets_in_base
from planner.gaits.moving_transfer import moving_lift_margin, moving_transfer
from planner.gaits.omni import MIN_STEP_M, nearest_axis
from planner.gaits.steps import Phase, StepKind
from planner.gaits.sway import capped_sway_end, sway_point, swept_reach_ok
from planner.gaits.tibia_reach import tibias_clear
from planner.stability.margin import MARGIN_TOLERANCE
from planner.ties import tie_key
from planner.trajectory.samples import LEGS
from planner.workspace.layout import Workspace
from silo4kin.frames import rotation_z

#: Duration d of each of the two four-foot phases per cycle [time units t_l] (module
#: docstring: the CoM crosses a diagonal of the support there).
FOUR_FOOT_UNITS = 0.5
#: Steps in a row without progress before the crawl gives up.
MAX_IDLE_STEPS = 8


def leg_order(ws: Workspace, u: np.ndarray) -> tuple[int, int, int, int]:
    """Swing order of the crawl along unit u (2,) in B: the two creeping pairs of the
    nearest body axis, rear leg first in each (module docstring)."""
    first, second = creep_pairs(ws, nearest_axis(u))
    return first + second


def duty_factor(four_foot_units: float = FOUR_FOOT_UNITS) -> float:
    """β of the steady crawl: (3 + 2d) / (4 + 2d) (module docstring)."""
    return (3.0 + 2.0 * four_foot_units) / (4.0 + 2.0 * four_foot_units)


class Crawl:
    """The crawl's state across segments: which leg of the order swings next."""

    def __init__(self, four_foot_units: float = FOUR_FOOT_UNITS) -> None:
        self.four_foot_units = float(four_foot_units)
        self.next_index = 0
        self.order: tuple[int, int, int, int] | None = None
        #: With a foothold check: (builder state, swings, distance [m]) before the step
        #: being made (CrawlOrCreep goes back there when the check refuses its foothold).
        self.resume: tuple[dict, int, float] | None = None

    def to(
        self, b: StepBuilder, ws: Workspace, target_xy_in_world: np.ndarray, legs=None
    ) -> tuple[int, float]:
        """Walk the nominal CoG to ``target_xy_in_world`` (2,) [m] without turning; returns
        the swings made and the nominal distance walked [m]."""
        rot = rotation_z(b.nominal_yaw)
        target = np.asarray(target_xy_in_world, float)
        n_swings, walked, idle = 0, 0.0, 0
        while True:
            rel = rot[:2, :2].T @ (target - b.nominal_base[:2])
            dist = float(np.hypot(*rel))
            if dist <= 1e-9:
                if float(np.hypot(*(b.base[:2] - b.nominal_base[:2]))) > 1e-9:
                    # swayed off the waypoint: the CoG as walked lands on it (E_n, eq 6.1)
                    b.body(
                        b.nominal_base,
                        b.nominal_yaw,
                        b.four_foot_units(b.nominal_base, self.four_foot_units),
                        StepKind.BODY,
                        "crawl arrive",
                        Phase.CREEP,
                    )
                b.fold_fence = len(b.steps)
                return n_swings, walked
            if b.foothold_check is not None:
                self.resume = (b.snapshot(), n_swings, walked)
            u = rel / dist
            order = leg_order(ws, u)
            starts = [self.next_index]
            if order != self.order:  # new axis: start with the pair furthest behind
                off = offsets_in_base(b, ws)
                pairs = (order[:2], order[2:])
                rear = min(pairs, key=lambda p: tie_key(off[list(p)] @ u @ np.ones(2)))
                self.order = order
                starts = [0 if rear == pairs[0] else 2]
            if n_swings == 0:  # a new segment: any leg of the order may start
                starts += [i for i in (0, 2, 1, 3) if i not in starts]
            radius = ellipse_radius(ws, u)
            if radius < MIN_STEP_M:
                raise b.error("the crawl has no stride along a body axis here")
            d = self.four_foot_units
            a_nom = 2.0 * radius / (3.0 + 2.0 * d)
            first_error = None
            for i in starts:
                try:
                    step = self._swing(
                        b,
                        ws,
                        u,
                        self.order[i],
                        self.order[(i + 1) % 4] if i % 2 == 0 else None,
                        dist,
                        min(a_nom, dist),
                        legs,
                    )
                    break
                except PlanningError as exc:
                    first_error = first_error or exc
            else:
                assert first_error is not None
                raise first_error
            n_swings += 1
            self.next_index = (i + 1) % 4
            dist_left = float(np.hypot(*(rot[:2, :2].T @ (target - b.nominal_base[:2]))))
            if i % 2 == 1 and dist_left > 1e-9:  # pair done: four-foot phase (crosses a diagonal)
                # (not on the waypoint: a sway there towards the next lift would be undone
                # by the arrival, and the next segment's first swing sways again)
                step += self._four_foot(
                    b,
                    ws,
                    u,
                    self.order[self.next_index],
                    min(d * a_nom, dist_left),
                    legs,
                    min(a_nom, max(dist_left - d * a_nom, 0.0)),
                )
            walked += step
            idle = idle + 1 if step < MIN_STEP_M else 0
            if idle > MAX_IDLE_STEPS:
                raise b.error("the crawl makes no progress")
            if n_swings > 40_000:
                raise b.error("the crawl makes no progress")

    def _swing(
        self,
        b: StepBuilder,
        ws: Workspace,
        u: np.ndarray,
        leg: int,
        next_leg: int | None,
        dist: float,
        t_want: float,
        legs,
    ) -> float:
        """Swing ``leg`` while the body advances (module docstring); the step ends where the
        next lift (``next_leg``, None when a four-foot phase follows) can start too, or on
        the waypoint when the advance reaches it (``dist`` [m] left). The
        advance is halved while a foot leaves its reach with the base where the sway puts
        it (the workspace's shift reserve, SHIFT_RESERVE_M, covers 5 cm; a sway may go further)."""
        rot = rotation_z(b.nominal_yaw)
        off = offsets_in_base(b, ws)
        for _ in range(REACH_HALVINGS):
            try:
                t, r = reachable_advance(legs, ws, leg, off, u, t_want)
            except ValueError:
                raise b.error(f"the crawl finds no reachable foothold for {LEGS[leg]}") from None
            nominal_end = b.nominal_base + rot @ np.array([t * u[0], t * u[1], 0.0])
            foothold = ws.position_mid_in_base[leg].copy()
            foothold[:2] += r * u
            target = nominal_end + rot @ foothold
            lifts: list[tuple[Any, ...]] = [(leg, b.feet.copy(), target)]
            if next_leg is not None:
                feet_after = b.feet.copy()
                feet_after[leg] = target
                nxt = ws.position_mid_in_base[next_leg].copy()
                nxt[:2] += r * u
                adv = rot @ np.array([t * u[0], t * u[1], 0.0])
                lifts.append((next_leg, feet_after, nominal_end + adv + rot @ nxt, adv))
            start: np.ndarray | None = None
            base_end = nominal_end  # (set again before the loop breaks)
            for start in (
                None,
                sway_point(b, [lifts[0] + (nominal_end - b.nominal_base,)], b.base),
            ):
                # the swing starts where the last step ended if its end can be placed; else
                # a sway step first (a new segment: the last step did not aim at this lift)
                b0 = b.base if start is None else start
                try:
                    if (
                        t >= dist - 1e-12
                        and moving_lift_margin(b, leg, target, nominal_end, b.feet, b0)
                        >= b.threshold - MARGIN_TOLERANCE
                    ):
                        base_end = nominal_end  # arriving on the waypoint, no sway needed
                    else:
                        base_end = sway_point(b, lifts, nominal_end, b0)
                    break
                except PlanningError:
                    if start is not None:
                        raise
            if legs is None or swept_reach_ok(
                legs, ws, b, start, base_end, leg, target, ws.swing_height_m
            ):
                break
            if t < MIN_STEP_M:
                raise b.error(f"the crawl's sway takes a foot out of reach lifting {LEGS[leg]}")
            t_want = 0.5 * t
        else:
            raise b.error(f"the crawl's sway takes a foot out of reach lifting {LEGS[leg]}")
        label = f"crawl transfer {LEGS[leg]}"
        base_end = capped_sway_end(legs, ws, b, lifts, start, base_end, label)
        if start is not None:
            b.body(
                start,
                b.nominal_yaw,
                b.four_foot_units(start, self.four_foot_units),
                StepKind.BODY,
                "crawl sway",
                Phase.SHIFT,
            )
            b.n_shifts += 1
        moving_transfer(b, leg, target, base_end, label, Phase.CREEP)
        b.nominal_base = nominal_end
        return t

    def _four_foot(
        self,
        b: StepBuilder,
        ws: Workspace,
        u: np.ndarray,
        next_leg: int,
        t_want: float,
        legs,
        a_next: float,
    ) -> float:
        """All four feet down for d units while the CoM crosses to the next lift's side
        (whose swing advances about ``a_next`` [m])."""
        rot = rotation_z(b.nominal_yaw)
        off = offsets_in_base(b, ws)
        try:
            t, _ = reachable_advance(legs, ws, None, off, u, t_want)
        except ValueError:
            t = 0.0
        nominal_end = b.nominal_base + rot @ np.array([t * u[0], t * u[1], 0.0])
        nxt = ws.position_mid_in_base[next_leg].copy()
        nxt[:2] += ellipse_radius(ws, u) * u
        adv = rot @ np.array([a_next * u[0], a_next * u[1], 0.0])
        base_end = sway_point(
            b, [(next_leg, b.feet.copy(), nominal_end + adv + rot @ nxt, adv)], nominal_end
        )
        if legs is not None:  # the feet seen from the base along its move (tibia_reach.py)
            bases = [b.base, 0.5 * (b.base + base_end), base_end]
            feet = [rot.T @ (b.feet[k] - base) for base in bases for k in range(4)]
            if not tibias_clear(legs, ws, np.tile(np.arange(4), len(bases)), np.array(feet)).all():
                raise b.error("the crawl's four-foot sway brings a tibia to the ground")
        b.body(
            base_end,
            b.nominal_yaw,
            b.four_foot_units(base_end, self.four_foot_units),
            StepKind.BODY,
            "crawl sway",
            Phase.CREEP,
        )
        b.nominal_base = nominal_end
        return t
