"""Walking in any direction without turning the body, and arriving exactly.

The default preset's gait ``creep`` (planner/gaits/without_turning.py) walks to each
waypoint with the body's heading unchanged: a creeping gait (thesis §4.2.1: two transfers,
then a body phase, 4 units per half cycle) whose travel direction u (unit, base frame B) is
the waypoint's direction, at any angle to the body axes — the crab gait of §4.1 (eq 4.1-4.2)
without its angle limit.

Footholds. Each leg's allowed foot region is the ellipse of planner/gaits/foothold_ellipse.py
(semi-axes λ_x/2 and λ_y/2 around its position 2). A half cycle with body step
t along u swings the pair whose feet lie furthest behind (along u) to ``mid + t u`` and then
moves the body by t u: the swung feet are back at position 2, the other pair at its old offset
minus t u. t is the largest step (at most the ellipse radius along u) that keeps the other
pair inside its ellipse; of the two leg pairs of the nearest body-axis direction
(gaits.creep_pairs, the thesis's pairing) the one allowing the larger step swings, rear leg
first. Where neither can step (from the +x creeping stance towards a direction whose
nearest axis is ±y, each such pair keeps a foot on the rear edge of its ellipse), the pairs
of the axis across u, shorter steps, or a step of 0 bringing a pair back to position 2
(:func:`step_candidates`), each rolled back if the builder refuses it and the next one
tried (docs/gaits.md, "Which pair swings").

Arriving: a segment of length d takes n = ceil(d / t_max) half cycles of equal steps d / n,
so the nominal CoG lands on the waypoint (E_n, eq 6.1, is then set by the stability shifts
alone; planner/gaits/waypoint_passing.py walks past waypoints within the tolerance).
Stability: every lift is checked by the StepBuilder (whole-body CoM over the swing,
threshold, shifts folded into the last body phase where possible, else a 1-unit shift).
"""

from __future__ import annotations

import math

import numpy as np

from planner.errors import PlanningError
from planner.gaits.body_pace import CREEP_BODY_LABEL, body_units
from planner.gaits.builder import StepBuilder
from planner.gaits.creep_spin import DIRECTIONS, creep_pairs
from planner.gaits.foothold_ellipse import ellipse_radius, offsets_in_base, stance_step_limit
from planner.gaits.foothold_replacement import FootholdReplacements
from planner.gaits.steps import Phase, StepKind
from planner.gaits.tibia_reach import tibias_clear
from planner.ties import tie_key
from planner.trajectory.samples import LEGS
from planner.workspace.layout import (
    RESERVE_DIRECTIONS,
    SHIFT_RESERVE_M,
    Workspace,
    reachable_in_limits_of_legs,
)
from silo4kin.frames import rotation_z
from silo4kin.memo import memo_of

#: Steps shorter than this [m] count as no progress (the stance pair is at its ellipse edge).
MIN_STEP_M = 1e-4
#: A half cycle advancing the body by less than this fraction of the step asked is stalled,
#: and this many stalled ones in a row refuse the gait (:class:`Stall`).
STALL_FRACTION = 0.1
MAX_STALLED_HALF_CYCLES = 8
#: Duration of the omnidirectional gait's body phase [time units t_l]: the body moves at most
#: λ/2 in one unit, no faster than a swing foot (λ in one unit); the thesis's creeping gait
#: takes 2 (steps.BODY_UNITS). URDF velocity and effort limits are checked on every plan
#: (planner/trajectory/limits.py) and the Chapter 6 cases walk in physics (docs/gaits.md).
OMNI_BODY_UNITS = 1.0
#: Bisection halvings of a step whose footholds leave the reachable set (1/2^20 of λ/2).
REACH_HALVINGS = 20
#: Factors on a step the builder refused, tried before a step of 0 (step_candidates).
SHORTER_STEP_FACTORS = (0.5, 0.25)


#: The order in which :func:`nearest_axis` breaks a tie (u on a diagonal, planner/ties.py):
#: the body's y axis first (the side pairs walk a diagonal). A convention, measured: with +x
#: first anymal's creeping gait on the thesis straight path at h = 0.49 m drifted 46.9 mm in
#: physics (65 units), with +y first 6.8 mm (68 units); SILO4's Chapter 6 plans walk either way.
AXIS_TIE_ORDER = ("+y", "-y", "+x", "-x")


def nearest_axis(u: np.ndarray) -> str:
    """The body-axis direction ("+x", "-x", "+y", "-y") nearest to unit u (2,); on a tie
    the first in AXIS_TIE_ORDER."""
    return max(AXIS_TIE_ORDER, key=lambda name: tie_key(DIRECTIONS[name] @ u))


def swing_pairs(ws: Workspace, u: np.ndarray) -> list[tuple[int, int]]:
    """Leg pairs the omnidirectional gait may swing along unit u (2,) in B: the two creeping
    pairs of the nearest body axis (gaits.creep_pairs, the thesis's pairing), then those of
    the axis across it (the other two sides of the body). Near a diagonal both axes'
    pairings are the thesis's crab gait for one of them; which one can step depends on the
    stance left by the previous half cycle: from the +x creeping stance (a right foot at
    the rear end of each ±y pair's stance) neither ±y pair can step along u with u_x > 0,
    so a direction whose nearest axis is ±y found no step (docs/gaits.md)."""
    near = nearest_axis(u)
    across = "+y" if near in ("+x", "-x") else "+x"
    return [*creep_pairs(ws, near), *creep_pairs(ws, across)]


def _reachable(
    legs, ws: Workspace, pair: tuple[int, int], off: np.ndarray, u: np.ndarray, t: float
) -> bool:
    """Whether the half cycle with step t [m] keeps every foot reachable within the joint
    limits with the body displaced by SHIFT_RESERVE_M in 8 directions (the reserve the
    workspace keeps for stability shifts): the swing feet at their targets (ground and swing
    height), the stance feet before, half-way and after the body move; with the body where the
    step puts it, every held tibia clear of the ground (planner/gaits/tibia_reach.py). All
    legs in one IK pass (workspace.reachable_in_limits_of_legs: the same values as one call
    per leg), and memoised on the exact inputs in the first leg's memo (silo4kin.memo): the
    ditch's route search (planner/studies/ditch.py) plans the
    same approach for each of its crossing angles."""
    key = (
        tuple(id(leg) for leg in legs),
        ws.position_mid_in_base.tobytes(),
        float(ws.swing_height_m),
        tuple(pair),
        np.asarray(off, float).tobytes(),
        np.asarray(u, float).tobytes(),
        float(t),
    )
    answers = memo_of(legs[0]).setdefault("omni_reachable", {})
    hit = answers.get(key)
    if hit is not None and all(a is b for a, b in zip(hit[0], legs)):  # ids reused
        return hit[1]
    shifts = np.vstack([np.zeros(3), SHIFT_RESERVE_M * RESERVE_DIRECTIONS])
    mid = ws.position_mid_in_base
    swing = [k for k in range(len(legs)) if k in pair]
    stance = [k for k in range(len(legs)) if k not in pair]
    p = mid[swing] + np.array([t * u[0], t * u[1], 0.0])  # (2, 3)
    swing_pts = np.stack([p, p + np.array([0.0, 0.0, ws.swing_height_m])], axis=1)
    steps = np.array([0.0, 0.5 * t, t])
    stance_pts = mid[stance][:, None, :] + np.stack(
        [
            off[stance, 0][:, None] - steps[None] * u[0],
            off[stance, 1][:, None] - steps[None] * u[1],
            np.zeros((len(stance), 3)),
        ],
        axis=2,
    )
    targets = np.concatenate(
        [
            (swing_pts[:, :, None, :] + shifts).reshape(-1, 3),
            (stance_pts[:, :, None, :] + shifts).reshape(-1, 3),
        ]
    )
    rows = np.concatenate([np.repeat(swing, 2 * len(shifts)), np.repeat(stance, 3 * len(shifts))])
    # the tibia rule at the step's own footholds and body positions, not at the reserve's
    # hypothetical shifts (a shift the builder makes is checked on the samples)
    ground = np.concatenate([swing_pts[:, 0], stance_pts.reshape(-1, 3)])
    ground_rows = np.concatenate([swing, np.repeat(stance, 3)])
    ok = bool(reachable_in_limits_of_legs(legs, rows, targets).all()) and bool(
        tibias_clear(legs, ws, ground_rows, ground).all()
    )
    if len(answers) >= REACHABLE_MEMO_SIZE:
        answers.clear()
    answers[key] = (tuple(legs), ok)
    return ok


#: Entries of :func:`_reachable`'s memo, kept in the first leg's memo (~0.5 kB each).
REACHABLE_MEMO_SIZE = 8192


def _pair_step(
    legs, ws: Workspace, off: np.ndarray, pair: tuple[int, int], u: np.ndarray, t_cap: float
) -> float:
    """The largest body step t <= ``t_cap`` [m] of swinging ``pair`` along u with its
    footholds reachable (halved while not, :func:`_reachable`); 0 when none is."""
    t = t_cap
    if legs is None:
        return t
    for _ in range(REACH_HALVINGS):
        if t < MIN_STEP_M or _reachable(legs, ws, pair, off, u, t):
            return t
        t *= 0.5
    return 0.0


def _ranked(
    ws: Workspace, off: np.ndarray, u: np.ndarray, t_want: float, legs, pairs: list[tuple[int, int]]
) -> list[tuple[float, tuple[int, int]]]:
    """(largest step t [m], pair) of each of ``pairs`` (one axis's), the larger step first,
    on a tie the pair further behind along u (step_candidates, 1. and 2.)."""
    radius = ellipse_radius(ws, u)
    ranked = []
    for pair in pairs:
        rest = [k for k in range(4) if k not in pair]
        # rounded to 1 nm: a step that only rounding makes longer does not win a tie
        t = round(
            _pair_step(
                legs, ws, off, pair, u, min(t_want, radius, stance_step_limit(ws, off[rest], u))
            ),
            9,
        )
        behind = tie_key(off[list(pair)] @ u @ np.ones(2))
        ranked.append(((-t, behind), t, pair))
    ranked.sort(key=lambda row: row[0])
    return [(t, pair) for _, t, pair in ranked]


def step_candidates(
    ws: Workspace,
    off: np.ndarray,
    u: np.ndarray,
    t_want: float,
    legs=None,
    near: list[tuple[float, tuple[int, int]]] | None = None,
) -> list[tuple[float, tuple[int, int]]]:
    """The half cycles (step t [m], swing pair) :func:`omni_half_cycle` tries along unit u
    (2,) in B from the feet at offsets ``off`` (4, 2) [m] from position 2, in order:

    1. the pairs of the nearest body axis, each with its largest step (<= ``t_want``, stance
       feet in their ellipses, footholds reachable); the larger step first, on a tie the
       pair further behind along u (the thesis's pairing: the plan as before this list);
    2. the pairs of the axis across u, in the same order (:func:`swing_pairs`);
    3. each of those with its step halved, then quartered (a shorter step rather than none:
       the builder may find a step unstable or its shift out of reach);
    4. a step of 0 for each pair not at position 2 yet (it swings back there and the body
       stays: the next half cycle starts from a stance its pairs can step from).

    ``near``: 1. already ranked (:func:`_ranked` of the nearest axis's pairs), not again.
    """
    pairs = swing_pairs(ws, u)
    if near is None:
        near = _ranked(ws, off, u, t_want, legs, pairs[:2])
    ranked = near + _ranked(ws, off, u, t_want, legs, pairs[2:])
    moving = [(t, pair) for t, pair in ranked if t >= MIN_STEP_M]
    shorter = [
        (_pair_step(legs, ws, off, pair, u, t * f), pair)
        for f in SHORTER_STEP_FACTORS
        for t, pair in moving
    ]
    back = [
        (0.0, pair)
        for _, pair in ranked
        if np.hypot(*off[list(pair)].T).max() > MIN_STEP_M
        and (legs is None or _reachable(legs, ws, pair, off, u, 0.0))
    ]
    return moving + [c for c in shorter if c[0] >= MIN_STEP_M] + back


class Stall:
    """Half cycles that advance the body by less than STALL_FRACTION of the step they were
    asked for (:func:`omni_half_cycle` halves a step until its footholds are reachable):
    after MAX_STALLED_HALF_CYCLES of them in a row the gait makes no progress, and is
    refused naming it. Without this a step halved towards zero repeated itself: mantis at
    h 0.35 m before a 0.2625 m gap (benchmarks/bench_capability.py) took steps of 12, 7, 1,
    0.1 mm ... and ran 4,700 half cycles in 100 s towards the 10,000 cap."""

    def __init__(self) -> None:
        self.steps_m: list[float] = []
        self.stalled = 0

    def record(self, step_m: float, asked_m: float, b: StepBuilder) -> None:
        """Count a half cycle that advanced ``step_m`` [m] of ``asked_m`` [m]; refuse
        (PlanningError via ``b``) after MAX_STALLED_HALF_CYCLES stalled ones in a row."""
        self.steps_m.append(float(step_m))
        self.stalled = self.stalled + 1 if step_m < STALL_FRACTION * asked_m else 0
        if self.stalled >= MAX_STALLED_HALF_CYCLES:
            last = self.steps_m[-MAX_STALLED_HALF_CYCLES:]
            raise b.error(
                f"the omnidirectional gait makes no progress: {len(last)} half cycles in a "
                f"row advanced {1e3 * sum(last):.2f} mm in all, under "
                f"{STALL_FRACTION:g} of the steps asked (footholds out of reach or refused "
                "farther on)"
            )


def omni_half_cycle(
    b: StepBuilder,
    ws: Workspace,
    u: np.ndarray,
    t_want: float,
    legs=None,
    replacements: FootholdReplacements | None = None,
) -> float:
    """One half cycle along unit u (2,) in B with a body step of at most ``t_want`` [m]
    (module docstring); returns the step taken [m]. With ``legs`` (the planning robot's
    LegGeometry per leg) a step whose footholds leave the reachable set is halved until
    they are in (:func:`_reachable`). Where a pair of the nearest axis steps, the first
    candidate of :func:`step_candidates` is that step (the thesis's pairing, as before);
    else the candidates are tried in turn, and one the builder refuses (no stable lift, a
    foot out of reach after a shift) is rolled back (StepBuilder.snapshot / restore)
    and the next one tried."""
    off = offsets_in_base(b, ws)
    heading = math.degrees(math.atan2(u[1], u[0]))
    # the nearest axis's best pair first: where it steps, it is the only candidate taken
    # (below), and the rest of step_candidates is not computed
    near = _ranked(ws, off, u, t_want, legs, swing_pairs(ws, u)[:2])
    candidates = (
        near[:1]
        if near and near[0][0] >= MIN_STEP_M
        else step_candidates(ws, off, u, t_want, legs, near)
    )
    if not candidates:
        raise b.error(
            f"the omnidirectional gait finds no step towards heading "
            f"{heading:.1f} deg in the body frame"
        )
    # where the thesis's pairing (the nearest axis's pairs) steps, that step is taken as
    # before, and a refusal of the builder fails the half cycle as before: the crawl then
    # stays dropped where it was (the reduced circle at h = 0.4 m, whose crawl with the
    # fallbacks below slips 6.0 mm > 5 mm in physics, docs/gaits.md)
    thesis_pairing = candidates[0][0] >= MIN_STEP_M and candidates[0][1] in swing_pairs(ws, u)[:2]
    state = None if thesis_pairing else b.snapshot()
    first_error: PlanningError | None = None
    rot = rotation_z(b.nominal_yaw)
    for t, pair in candidates[:1] if thesis_pairing else candidates:
        try:
            for leg in sorted(pair, key=lambda k: tie_key(ws.position_hip_in_base[k, :2] @ u)):
                target = ws.position_mid_in_base[leg].copy()
                target[:2] += t * u
                nominal, ordinal = target.copy(), _n_transfers(b)
                if replacements is not None:
                    target[:2] += replacements.offset(ordinal)
                b.transfer(
                    leg, b.nominal_base + rot @ target, f"omni transfer {LEGS[leg]}", Phase.CREEP
                )
                if replacements is not None:
                    replacements.record(b.steps[-1].t_start, ordinal, leg, nominal, ws)
        except PlanningError as exc:
            if thesis_pairing:
                raise
            first_error = first_error or exc
            assert state is not None
            b.restore(state)
            continue
        b.nominal_base = b.nominal_base + rot @ np.array([t * u[0], t * u[1], 0.0])
        # as long as the ZMP's excursion asks (planner/gaits/body_pace.py)
        units = body_units(
            float(np.hypot(*(b.nominal_base[:2] - b.base[:2]))),
            b.cog_height(),
            b.threshold,
            OMNI_BODY_UNITS,
        )
        b.body(b.nominal_base, b.nominal_yaw, units, StepKind.BODY, CREEP_BODY_LABEL, Phase.CREEP)
        return t
    assert first_error is not None
    raise b.error(
        f"the omnidirectional gait finds no stable step towards heading "
        f"{heading:.1f} deg in the body frame ({first_error.reason})"
    )


def _n_transfers(b: StepBuilder) -> int:
    """Swings the builder has made so far (the ordinal of the next one)."""
    return sum(1 for s in b.steps if s.kind is StepKind.TRANSFER)


def omni_to(
    b: StepBuilder,
    ws: Workspace,
    target_xy_in_world: np.ndarray,
    legs=None,
    replacements: FootholdReplacements | None = None,
) -> tuple[int, float]:
    """Walk the nominal CoG to ``target_xy_in_world`` (2,) [m] without turning (module
    docstring: equal steps, the last lands on the target); returns the half cycles used and
    the nominal distance walked [m]. ``replacements``: :func:`omni_half_cycle`'s."""
    n_done, walked = 0, 0.0
    stall = Stall()
    while True:
        b.check_time_limit()  # the half cycles so far stay: the bound on the rest holds
        rel = rotation_z(-b.nominal_yaw)[:2, :2] @ (
            np.asarray(target_xy_in_world, float) - b.nominal_base[:2]
        )
        dist = float(np.hypot(*rel))
        if dist <= 1e-9:
            b.fold_fence = len(b.steps)  # the CoG stays on the waypoint (E_n, eq 6.1)
            return n_done, walked
        u = rel / dist
        radius = ellipse_radius(ws, u)
        if radius < MIN_STEP_M:
            raise b.error("the omnidirectional gait has no stride along a body axis here")
        n = int(math.ceil(dist / radius - 1e-9))
        stall.record(omni_half_cycle(b, ws, u, dist / n, legs, replacements), dist / n, b)
        walked += stall.steps_m[-1]
        n_done += 1
        if n_done > 10_000:
            raise b.error("the omnidirectional gait makes no progress")
