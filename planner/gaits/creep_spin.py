"""Creeping and spinning gaits (thesis §4.2) on top of :class:`~planner.gaits.builder.StepBuilder`.

Creeping gait 4-2-B-3-1-B (§4.2.1, β = 7/8): thesis legs 1-4 are LF, RF, LH, RH; thesis +y
(forward) is base +x. For travel along a base axis d, the first pair to swing is the two legs
on the right of d, the one further back first (d = +x: RH, RF = legs 4, 2; d = -x: LF, LH =
1, 3; d = -y (thesis +x): LH, RH = 3, 4; d = +y: RF, LF = 2, 1, as printed in §4.2.1). Each
swinging leg goes from its rear foothold to its front foothold (workspace.py), then the body
moves λ/2 along d over 2 units; half a cycle is 4 units and flips the parity (which pair is
at the rear). A whole cycle is 8 units and moves the CoG λ.

Spinning gait (§4.2.2, consistent version; docs/thesis-notes.md): from the spin stance (all feet at
position 2), the four feet move one at a time to the stance rotated by ψ about the spin
centre (the nominal CoG), then the base turns by ψ (2 units, quintic 5.16-5.28) with IK for
every stance leg, so no stance foot slides. |ψ| per cycle <= Workspace.psi_max_rad (θ1
limits); a turn takes ceil(|ψ| / ψ_max) equal cycles, either direction. The leg order is
chosen among the 24 permutations: fewest stability shifts, then shortest total shift, then
largest smallest margin. Transitions (2 units): before a spin the two legs at their rear
footholds move to position 2 (thesis: legs 4, 2); after it, the first pair of the forward
gait moves back to its rear footholds (thesis: legs 2, 4). The default preset's path
follower skips both transitions (planner/path/plan_path.py).

Crab gait (§4.1, eq 4.1-4.2): the creeping gait of "+x" with the travel direction turned by a
crab angle α: same legs and order, footholds on the turned line through position 2, body
λ/2 along the turned direction. |α| <= crab_limit_rad keeps the footholds within the
default workspace's shift reserve, and their stances' non-foot shapes off the ground.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from planner.errors import PlanningError
from planner.gaits.builder import OverBudget, StepBuilder
from planner.gaits.fold import lift_group
from planner.gaits.steps import BODY_UNITS, ROTATE_UNITS, SHIFT_EXTRA_M, Phase, StepKind
from planner.presets import MIN_GROUND_CLEARANCE_M, FootholdRule, footholds_of
from planner.stability.margin import MARGIN_TOLERANCE, triangle_margin_xy
from planner.stability.shifts import closest_point_with_margin, shift_for_margin_xy
from planner.ties import tie_key
from planner.trajectory.samples import LEGS
from planner.workspace.footholds import creep_pairs_from_hips
from planner.workspace.heights import stance_clearance
from planner.workspace.layout import (
    RESERVE_DIRECTIONS,
    SHIFT_RESERVE_M,
    Workspace,
    reachable_in_limits,
)
from silo4kin.frames import rotation_z

#: Travel directions along the base axes (REP-103: +x forward, +y left).
DIRECTIONS: dict[str, np.ndarray] = {
    "+x": np.array([1.0, 0.0]),
    "-x": np.array([-1.0, 0.0]),
    "+y": np.array([0.0, 1.0]),
    "-y": np.array([0.0, -1.0]),
}
#: Largest crab angle tried by the default preset's path follower [rad] (CRAB_STEP_RAD grid).
CRAB_MAX_RAD = math.radians(10.0)
CRAB_STEP_RAD = math.radians(1.0)
#: Foothold offsets along d from position 2, in strides λ.
_OFFSET = {"front": 0.5, "mid": 0.0, "rear": -0.5}


def creep_pairs(ws: Workspace, direction: str) -> tuple[tuple[int, int], tuple[int, int]]:
    """(first pair, second pair) of leg indices for travel along ``direction``, rear first."""
    return creep_pairs_from_hips(ws.position_hip_in_base, DIRECTIONS[direction])


def crab_direction(direction: str, crab_rad: float = 0.0) -> np.ndarray:
    """Unit travel direction (2,) in B: the base axis ``direction`` turned by the crab angle
    ``crab_rad`` [rad] (thesis §4.1, eq 4.1-4.2: a crab gait walks at an angle to the body
    axis); the axis itself, bit for bit, when the angle is 0."""
    d = DIRECTIONS[direction]
    if crab_rad == 0.0:
        return d
    return rotation_z(crab_rad)[:2, :2] @ d


def foothold_in_base(
    ws: Workspace, leg: int, direction: str, which: str, crab_rad: float = 0.0
) -> np.ndarray:
    """Foothold ("front" = position 1 of a front leg, "mid" = 2, "rear") in B, (3,) [m]; with
    a crab angle the three footholds lie on the line through position 2 along
    :func:`crab_direction`, ±λ/2 apart as along the axis (inside the workspace square for
    |crab| <= 45°)."""
    d = DIRECTIONS[direction]
    p = ws.position_mid_in_base[leg].copy()
    p[:2] += crab_direction(direction, crab_rad) * _OFFSET[which] * ws.stride_along(d)
    return p


def crab_limit_rad(robot, ws: Workspace, max_rad: float = CRAB_MAX_RAD) -> float:
    """Largest crab angle α <= max_rad [rad] on the CRAB_STEP_RAD grid such that for every
    |α'| <= α the crab footholds of "+x" (front, rear and position 2, on the ground and
    lifted by the swing height) stay reachable within the joint limits with the body
    displaced by SHIFT_RESERVE_M in 8 directions: the reserve the default workspace keeps
    for the axis footholds (workspace.py). 0 when no angle passes.

    With the default's footholds (the reachable sets) the crab stances must also keep every
    shape of the robot but its feet MIN_GROUND_CLEARANCE_M above the ground, as the
    feasible height range asks of the axis stance (planner/workspace/heights.py
    stance_clear): the four feet on their front footholds, and on their rear ones, turned by
    ±α', the base at its nominal pose (the URDF's collision shapes, the run's check,
    planner/trajectory/clearance.py). A crab turns the front footholds of one side's legs in
    under the body: go2 at h 0.1852 m (the 200-case corpus's #3) crabbing at -10° put its LF
    and LH feet 27 mm inwards of the axis ones, and their calves 6.7 and 4.4 mm into the
    ground at touch-down (straight ahead: 11.6 mm above it); the clearance falls ~1.8 mm per
    degree there, so its crab limit is now 0 and facing the path turns to face each segment
    instead."""
    angles = np.arange(CRAB_STEP_RAD, max_rad + 1e-12, CRAB_STEP_RAD)
    ok = np.ones(angles.size, dtype=bool)
    offsets = np.vstack([np.zeros(3), SHIFT_RESERVE_M * RESERVE_DIRECTIONS])
    for leg, geo in enumerate(robot.legs):
        pts = []
        for a in angles:
            for sign in (1.0, -1.0):
                for which in ("front", "rear", "mid"):
                    p = foothold_in_base(ws, leg, "+x", which, sign * float(a))
                    for dz in (0.0, ws.swing_height_m):
                        pts.append(p + np.array([0.0, 0.0, dz]) + offsets)
        reach = reachable_in_limits(geo, np.concatenate(pts)).reshape(angles.size, -1)
        ok &= reach.all(axis=1)
    if footholds_of(ws.preset) is FootholdRule.REACHABLE_SETS:
        ok &= crab_stances_clear(robot, ws, angles)
    n = int(np.argmin(np.append(ok, False)))  # leading run of passing angles
    return float(angles[n - 1]) if n else 0.0


def crab_stances_clear(robot, ws: Workspace, angles: np.ndarray) -> np.ndarray:
    """(A,) bool: whether the stances with every foot on its crab foothold of "+x" turned by
    +a and by -a, front and rear (:func:`foothold_in_base`), keep every shape of ``robot``
    (planning frame) but its feet at least MIN_GROUND_CLEARANCE_M above flat ground, for
    each of ``angles`` (A,) [rad] (:func:`crab_limit_rad`); a stance with a foot out of
    reach does not."""
    stances = np.array(
        [
            [foothold_in_base(ws, k, "+x", which, sign * float(a)) for k in range(len(robot.legs))]
            for a in angles
            for sign in (1.0, -1.0)
            for which in ("front", "rear")
        ]
    )
    clearance = stance_clearance(robot, ws.height, stances).reshape(len(angles), -1)
    return np.all(clearance >= MIN_GROUND_CLEARANCE_M, axis=1)  # NaN: out of reach


def creep_stance_in_base(ws: Workspace, direction: str, parity: int) -> np.ndarray:
    """Feet (4, 3) [m] in B between half cycles: the pair about to swing is at the rear."""
    first, second = creep_pairs(ws, direction)
    rear = first if parity == 0 else second
    return np.array(
        [foothold_in_base(ws, k, direction, "rear" if k in rear else "mid") for k in range(4)]
    )


def _to_world(b: StepBuilder, p_in_base: np.ndarray, yaw: float | None = None) -> np.ndarray:
    y = b.nominal_yaw if yaw is None else yaw
    return b.nominal_base + rotation_z(y) @ p_in_base


def creep_half_cycle(
    b: StepBuilder,
    ws: Workspace,
    direction: str,
    parity: int,
    crab_rad: float = 0.0,
    step_m: float | None = None,
) -> int:
    """Two transfers and one body phase (4 units); returns the new parity. ``crab_rad``
    [rad] turns the travel direction off the base axis (the legs, their order and λ/2 per
    body phase stay those of the axis; the swinging pair lands on the turned front
    footholds, wherever its feet stood). ``step_m`` [m] (0 < step_m <= λ/2; None: λ/2)
    shortens the body phase, and the swinging pair lands step_m ahead of position 2 instead
    of λ/2, so it stands at position 2 afterwards as after a full half cycle (the default
    preset's last half cycle of a segment facing the path lands on the waypoint)."""
    first, second = creep_pairs(ws, direction)
    d = crab_direction(direction, crab_rad)
    for leg in first if parity == 0 else second:
        if step_m is None:
            foothold = foothold_in_base(ws, leg, direction, "front", crab_rad)
        else:
            foothold = ws.position_mid_in_base[leg].copy()
            foothold[:2] += d * step_m
        b.transfer(leg, _to_world(b, foothold), f"creep transfer {LEGS[leg]}", Phase.CREEP)
    length = ws.stride_along(DIRECTIONS[direction]) / 2 if step_m is None else step_m
    step = rotation_z(b.nominal_yaw) @ np.array([d[0], d[1], 0.0]) * length
    b.nominal_base = b.nominal_base + step
    b.body(b.nominal_base, b.nominal_yaw, BODY_UNITS, StepKind.BODY, "creep body", Phase.CREEP)
    return 1 - parity


def transition_to_spin(b: StepBuilder, ws: Workspace, direction: str, parity: int) -> None:
    """Move the two legs at their rear footholds to position 2 (rear one first)."""
    first, second = creep_pairs(ws, direction)
    for leg in first if parity == 0 else second:
        b.transfer(
            leg,
            _to_world(b, ws.position_mid_in_base[leg]),
            f"transition transfer {LEGS[leg]}",
            Phase.TRANSITION,
        )


def transition_from_spin(b: StepBuilder, ws: Workspace, direction: str) -> int:
    """Move the forward gait's first pair back to its rear footholds; returns parity 0."""
    first, _ = creep_pairs(ws, direction)
    for leg in reversed(first):
        b.transfer(
            leg,
            _to_world(b, foothold_in_base(ws, leg, direction, "rear")),
            f"transition transfer {LEGS[leg]}",
            Phase.TRANSITION,
        )
    return 0


#: Spin search state after lifting the legs of an order prefix: (feet (x, y) per leg [m],
#: CoG (x, y) [m], n_shifts, total shift [m], smallest lift margin [m], support triangles
#: of the lifts since the last body step, or None when shifts are not folded or there is no
#: body step to fold into (StepBuilder.fold_shifts)).
_Triangle = tuple[tuple[float, float], ...]
_SpinState = tuple[
    tuple[tuple[float, float], ...],
    tuple[float, float],
    int,
    float,
    float,
    tuple[_Triangle, ...] | None,
]


def _lift(
    state: _SpinState,
    leg: int,
    targets: list[tuple[float, float]],
    threshold: float,
    fold: bool = False,
) -> _SpinState | None:
    """Lift ``leg`` (shifting the CoG first if S_m < threshold, §5.1: folded into the last
    body step when the group allows it, as StepBuilder does, else a shift step) and place it
    on its target; None when no shift reaches the threshold."""
    feet, cog, n, dist, worst, group = state
    tri = tuple(feet[k] for k in range(4) if k != leg)
    m = triangle_margin_xy(tri[0], tri[1], tri[2], cog)
    if m < threshold - MARGIN_TOLERANCE:
        new = None
        if group is not None:
            both = list(group) + [tri]
            new = closest_point_with_margin(both, cog, threshold + SHIFT_EXTRA_M)
            if new is None:
                new = closest_point_with_margin(both, cog, threshold)
        if new is not None and group is not None:
            group = group + (tri,)
        else:
            new = shift_for_margin_xy(tri[0], tri[1], tri[2], cog, threshold + SHIFT_EXTRA_M)
            if new is None:
                new = shift_for_margin_xy(tri[0], tri[1], tri[2], cog, threshold)
            if new is None:
                return None
            n += 1
            group = (tri,) if fold else None
        dist += math.hypot(new[0] - cog[0], new[1] - cog[1])
        cog = new
        m = triangle_margin_xy(tri[0], tri[1], tri[2], cog)
    elif group is not None:
        group = group + (tri,)
    moved = feet[:leg] + (targets[leg],) + feet[leg + 1 :]
    return moved, cog, n, dist, min(worst, m), group


def _key(state: _SpinState) -> tuple[int, float, float]:
    """Ranking of a (partial) order: fewest shifts, shortest total shift, largest margin."""
    return state[2], tie_key(state[3]), -tie_key(state[4])


def _spin_start(
    feet_xy: np.ndarray,
    targets_xy: np.ndarray,
    cog_xy: np.ndarray,
    group: tuple[_Triangle, ...] | None,
    fold: bool,
) -> tuple[_SpinState, list[tuple[float, float]]]:
    """The state before any lift (no shift yet, margin +inf) and the targets as tuples."""
    feet = tuple((float(f[0]), float(f[1])) for f in feet_xy)
    targets = [(float(f[0]), float(f[1])) for f in targets_xy]
    start: _SpinState = (
        feet,
        (float(cog_xy[0]), float(cog_xy[1])),
        0,
        0.0,
        math.inf,
        group if fold else None,
    )
    return start, targets


def choose_spin_order(
    feet_xy: np.ndarray,
    targets_xy: np.ndarray,
    cog_xy: np.ndarray,
    threshold: float,
    group: tuple[_Triangle, ...] | None = None,
    fold: bool = False,
) -> tuple[int, ...]:
    """Best of the 24 leg orders (module docstring); arrays (4, 2) and (2,) [m]. With
    ``fold`` the shifts are simulated as StepBuilder folds them, ``group`` being the support
    triangles of the lifts since the last body step (None: no body step yet).

    Orders sharing a prefix share its simulation, and a prefix whose key already ties or
    loses to the best complete order is dropped (every key component only grows along an
    order). The first order in lexicographic order wins ties, as in a plain scan.
    """
    start, targets = _spin_start(feet_xy, targets_xy, cog_xy, group, fold)
    best: tuple[int, ...] | None = None
    best_key: tuple[int, float, float] | None = None

    def search(prefix: tuple[int, ...], state: _SpinState) -> None:
        nonlocal best, best_key
        if best_key is not None and _key(state) >= best_key:
            return
        if len(prefix) == 4:
            best, best_key = prefix, _key(state)
            return
        for leg in range(4):
            if leg not in prefix:
                child = _lift(state, leg, targets, threshold, fold)
                if child is not None:
                    search(prefix + (leg,), child)

    search((), start)
    if best is None:
        raise ValueError("no leg order")
    return best


def ranked_spin_orders(
    feet_xy: np.ndarray,
    targets_xy: np.ndarray,
    cog_xy: np.ndarray,
    threshold: float,
    group: tuple[_Triangle, ...] | None = None,
    fold: bool = False,
) -> list[tuple[int, ...]]:
    """Every leg order with a stable lift for each leg, ranked as :func:`choose_spin_order`
    ranks them (its choice first: the key, then lexicographic order), for a spin whose
    chosen order no shift keeps within the effort budget (:func:`spin`)."""
    start, targets = _spin_start(feet_xy, targets_xy, cog_xy, group, fold)
    ranked = []
    for order in itertools.permutations(range(4)):
        state: _SpinState | None = start
        for leg in order:
            state = _lift(state, leg, targets, threshold, fold) if state is not None else None
        if state is not None:
            ranked.append((_key(state), order))
    ranked.sort(key=lambda item: item[0])  # stable: lexicographic among equal keys
    return [order for _, order in ranked]


def spin_cycles(ws: Workspace, psi: float) -> int:
    """ceil(|ψ| / ψ_max) spinning cycles for a turn ψ [rad] (0 for no turn)."""
    if psi != 0.0 and ws.psi_max_rad <= 0.0:
        raise PlanningError(f"the stance cannot turn at h = {float(ws.height):.4g} m (ψ_max = 0)")
    return int(math.ceil(abs(psi) / ws.psi_max_rad - 1e-12)) if psi != 0.0 else 0


def thesis_spin_cycles(psi: float) -> int:
    """The thesis's count (§5.5): halve ψ until it is below π/2; 2^halvings cycles."""
    n, a = 1, abs(psi)
    while a > math.pi / 2:
        a /= 2.0
        n *= 2
    return n


def spin(b: StepBuilder, ws: Workspace, psi: float) -> list[tuple[int, ...]]:
    """Spinning cycles turning the base by ψ [rad] about the nominal CoG, from and back to
    the spin stance; returns the leg order of each cycle."""
    n = spin_cycles(ws, psi)
    orders = []
    for _ in range(n):
        dpsi = psi / n
        yaw_new = b.nominal_yaw + dpsi
        targets = np.array([_to_world(b, ws.position_mid_in_base[k], yaw_new) for k in range(4)])
        try:
            order = choose_spin_order(
                b.feet[:, :2],
                targets[:, :2],
                b.base[:2],
                b.threshold,
                lift_group(b),
                b.fold_shifts,
            )
        except ValueError:
            raise b.error(
                f"no leg order of the spinning gait (ψ = "
                f"{math.degrees(dpsi):.1f}° per cycle) keeps margin >= "
                f"{b.threshold:.4g} m"
            ) from None
        order = _spin_transfers(b, order, targets)
        b.nominal_yaw = yaw_new
        b.body(b.nominal_base, yaw_new, ROTATE_UNITS, StepKind.ROTATE, "spin rotate", Phase.SPIN)
        orders.append(order)
    return orders


def _spin_transfers(b: StepBuilder, order: tuple[int, ...], targets: np.ndarray) -> tuple[int, ...]:
    """The spin's transfers in ``order`` (each to ``targets`` (4, 3) [m]); where one has no
    shift that keeps both the margin and the stance legs' effort budget (OverBudget,
    planner/gaits/load_caps.py), the other orders in :func:`ranked_spin_orders`'s rank
    from the same state, the first that does; returns the order walked. The order search
    sees the margins alone: mantis at h 0.2055 m (the corpus's case 1, seed 20261202)
    found no base keeping arm3_lift within its 34 N m for LF's lift in the order chosen."""
    state = b.snapshot()
    # with the caps, a refused order is retried whatever refused it: a shift that keeps
    # the budget moves the base, and a later lift of that order may then find a foot out of
    # reach (the SILO4 xacro variant's spin at (1, 1), L2 0.3, L3 0.35, Lb 0.25 m, h 0.4 m)
    retried: type[PlanningError] = OverBudget if b.load_caps is None else PlanningError
    try:
        for leg in order:
            b.transfer(leg, targets[leg], f"spin transfer {LEGS[leg]}", Phase.SPIN)
        return order
    except retried as refused:
        first = refused
    b.restore(state)
    group = lift_group(b)
    for other in ranked_spin_orders(
        b.feet[:, :2], targets[:, :2], b.base[:2], b.threshold, group, b.fold_shifts
    ):
        if other == order:
            continue
        b.restore(state)
        try:
            for leg in other:
                b.transfer(leg, targets[leg], f"spin transfer {LEGS[leg]}", Phase.SPIN)
        except retried as refused:
            if isinstance(refused, OverBudget) and not isinstance(first, OverBudget):
                first = refused  # the budget, not the reach, is what no order keeps
            continue
        return other
    b.restore(state)
    raise first
