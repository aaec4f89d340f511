"""Where the continuous crawl puts the body (planner/gaits/crawl.py): the sway point of each step
and the checks on it.

A foot lifts only with the whole-body CoM at least the threshold inside the triangle of the
other three over its swing, the base moving on a straight line (the model's moving swing,
PlanningModel.moving_swing_com_in_world). :func:`sway_point` finds the base nearest the
nominal CoG that keeps the lift it ends and the lift it starts inside
(shifts.closest_point_with_margin on the triangles moved by the CoM's offset and shrunk by
its spread); :func:`swept_reach_ok` checks that every foot stays reachable, inside its
ellipse grown by the shift reserve, and (SILO4's legs) with its shank clear of the ground;
:func:`shank_violation` checks the last on a sampled plan.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from planner.errors import PlanningError
from planner.gaits.builder import OverBudget, StepBuilder
from planner.gaits.foothold_ellipse import ellipse_semi_axes
from planner.gaits.moving_transfer import moving_lift_margin, moving_over_budget
from planner.gaits.steps import SHIFT_EXTRA_M
from planner.gaits.tibia_reach import tibias_clear_at, with_positions_2
from planner.stability.margin import MARGIN_TOLERANCE, triangle_margin_xy
from planner.stability.shifts import closest_point_with_margin
from planner.trajectory.samples import LEGS
from planner.workspace.layout import SHIFT_RESERVE_M, Workspace
from planner.workspace.reach_check import joint_values_in_limits_of_legs
from silo4kin.frames import rotation_z
from silo4kin.leg_family import INSECT, family_of

#: Rounds of "choose the base, recompute the whole-body CoM spread there".
SWAY_ROUNDS = 3
#: Smallest slope of an insect leg's shank (tibia) below the horizontal with its foot on the
#: ground [rad]. Measured (planner at 20 samples per unit, `silo4 simulate`): the creeping
#: gait keeps >= 33 deg on every Chapter 6 case and walks; a crawl on the circle at h = 0.2 m
#: reached 23.6 deg and put three shanks on the ground in physics (drift 32 mm, slip 48 mm).
#: Below this the crawl halves its advance, and where that does not help the creeping gait
#: takes the half cycle; plan_path drops a crawl whose samples go below it (shank_violation).
#: Held only for legs whose shank is steeper at position 2 / the start (SILO4's; mantis's
#: shank stands near horizontal and is not held to it). A shank folded past the vertical
#: passes this rule: the tibia capsule's own clearance is held too
#: (planner/trajectory/clearance.py).
MIN_SHANK_SLOPE_RAD = math.radians(30.0)
#: How far from the sway point :func:`capped_sway_end` looks for a base that keeps the
#: stance legs' effort budget [m] (the workspace's shift reserve, SHIFT_RESERVE_M, covers
#: 5 cm of sway).
SWAY_CAP_REACH_M = 0.05
#: The points :func:`capped_sway_end` tries, offsets (K, 2) [m] from the sway point: rings
#: SWAY_CAP_RING_M apart out to SWAY_CAP_REACH_M, 16 directions each, nearest first (each
#: costs a moving swing's CoM: 80 of them, where 320 at 5 mm made a refused crawl 30 s).
SWAY_CAP_RING_M = 0.01
SWAY_CAP_CANDIDATES = np.array(
    [
        [r * np.cos(a), r * np.sin(a)]
        for r in np.arange(SWAY_CAP_RING_M, SWAY_CAP_REACH_M + 1e-9, SWAY_CAP_RING_M)
        for a in np.linspace(0.0, 2.0 * np.pi, 16, endpoint=False)
    ]
)


def shank_violation(legs, trajectory) -> str | None:
    """One line for the first sample where an insect leg's foot is on the ground with its
    shank less than MIN_SHANK_SLOPE_RAD below the horizontal, or None (the sampled joints
    q, in legs order LF, RF, LH, RH; plan_path drops such a crawl)."""
    q = trajectory.q.reshape(len(trajectory), -1, 3)
    slope = -(q[..., 1] + q[..., 2])
    # legs whose shank stands steeper than the floor at the start (SILO4's; a leg built
    # otherwise, e.g. mantis's near-horizontal shank, is not held to it)
    held = np.array([family_of(geo) is INSECT for geo in legs]) & (slope[0] >= MIN_SHANK_SLOPE_RAD)
    low = (slope < MIN_SHANK_SLOPE_RAD) & trajectory.contact & held
    rows = np.flatnonzero(low.any(axis=1))
    if not rows.size:
        return None
    i, k = int(rows[0]), int(np.argmax(low[rows[0]]))
    return (
        f"the shank of {LEGS[k]} is {math.degrees(-(q[i, k, 1] + q[i, k, 2])):.1f} deg "
        f"below the horizontal at t = {trajectory.time_units[i]:.2f} units, under the "
        f"{math.degrees(MIN_SHANK_SLOPE_RAD):.0f} deg that keep it off the ground"
    )


def swept_reach_ok(
    legs,
    ws: Workspace,
    b: StepBuilder,
    start: np.ndarray | None,
    end: np.ndarray,
    leg: int,
    target: np.ndarray,
    swing_height_m: float,
) -> bool:
    """Whether every foot is reachable within the joint limits with the base where the crawl
    puts it: stance feet with the base at the start, half-way and the end of its straight
    move (and at a sway step's end, ``start``, when there is one), the swing foot at its
    foothold (ground and lifted) and lifted half-way (seen from the moving base, the foot
    moves on the line between its offsets); and every foot on the ground inside its ellipse
    grown by the shift reserve, seen from the base where it is, with an insect leg's shank
    at least MIN_SHANK_SLOPE_RAD below the horizontal (θ2 + θ3, eq 3.10-3.24) when it is
    so at position 2; every held tibia clear of the ground (planner/gaits/tibia_reach.py)."""
    rot_t = rotation_z(b.nominal_yaw).T
    b0 = b.base if start is None else start
    bases = [b.base, b0, 0.5 * (b0 + end), end]
    lift = np.array([0.0, 0.0, swing_height_m])
    rows, reach_targets, down = [], [], []  # down: the rows of feet on the ground
    for k in range(len(legs)):
        if k == leg:
            rel0 = rot_t @ (b.feet[k] - b0)
            rel1 = rot_t @ (target - end)
            pts = [rel0, rel1, rel1 + lift, 0.5 * (rel0 + rel1) + lift]
            down += [False, True, False, False]
        else:
            pts = [rot_t @ (b.feet[k] - base) for base in bases]
            down += [True] * len(pts)
        rows += [k] * len(pts)
        reach_targets += pts
    idx, targets, on_ground = np.array(rows), np.array(reach_targets), np.array(down)
    # a foot down stays where the workspace checked the legs (its ellipse grown by the
    # shift reserve): a sway beyond would bring a shank near the ground at low heights
    off = (targets[on_ground, :2] - ws.position_mid_in_base[idx[on_ground], :2]) / (
        ellipse_semi_axes(ws) + SHIFT_RESERVE_M
    )
    if np.any(np.einsum("ij,ij->i", off, off) > 1.0 + 1e-9):
        return False
    # every leg and check in one IK pass: each leg's position 2 (the shank and tibia rules
    # hold a leg by its pose there), then the targets (the IK is elementwise: the values of
    # one reachable_in_limits / IK call per leg and check)
    rows_with_mid, with_mid = with_positions_2(legs, ws, idx, targets)
    q, in_limits = joint_values_in_limits_of_legs(legs, rows_with_mid, with_mid)
    n_legs = len(legs)
    if not in_limits[n_legs:].all():
        return False
    slope = -(q[:, 1] + q[:, 2])
    insect = np.array([family_of(geo) is INSECT for geo in legs])
    held = insect & (slope[:n_legs] >= MIN_SHANK_SLOPE_RAD)
    if np.any(held[idx] & on_ground & (slope[n_legs:] < MIN_SHANK_SLOPE_RAD)):
        return False
    return bool(tibias_clear_at(legs, ws, rows_with_mid, q).all())


def _lift_region(
    b: StepBuilder,
    leg: int,
    feet: np.ndarray,
    target: np.ndarray,
    base: np.ndarray,
    base_start: np.ndarray | None = None,
    advance: np.ndarray | None = None,
) -> tuple[tuple[tuple[float, float], ...], float]:
    """The support triangle of lifting ``leg`` (feet (4, 3) [m]) moved by the whole-body
    CoM's offset from the base (centre c of the offsets' bounding box), and the offsets'
    spread r [m] about c. With ``base_start``: over the swing to ``target`` while the base
    moves from there to ``base`` (the model's moving swing); without, for the next lift
    (whose own step sways its end): over its swing with the base moving from ``base`` by
    ``advance`` (3,) [m] (an estimate), or where that leaves the reach, at the lift-off
    only. A base path whose points
    all have S_m >= threshold + r in the moved triangle keeps the CoM inside by the
    threshold; on a straight base path the ends bound it (S_m is concave along a line)."""
    if b.moving_swing_com is None:
        centre, radius = (
            b.com_spread(leg, target, base, feet) if base_start is not None else (np.zeros(2), 0.0)
        )
    else:
        com: np.ndarray | None = None
        path: np.ndarray | None = None
        if base_start is None and advance is not None:
            com, path = b.moving_swing_com(base, base + advance, b.yaw, feet, leg, target)
            if not np.all(np.isfinite(com)):
                com = None
        if base_start is None and com is None:
            com, path = b.moving_swing_com(base, base, b.yaw, feet, leg, feet[leg], n=1)
        elif base_start is not None:
            com, path = b.moving_swing_com(base_start, base, b.yaw, feet, leg, target)
        off = np.asarray(com) - np.asarray(path)  # (set on every branch above)
        if not np.all(np.isfinite(off)):
            raise b.error(f"a foot of the crawl's lift of {LEGS[leg]} is out of reach")
        centre = 0.5 * (off.min(axis=0) + off.max(axis=0))
        radius = float(np.max(np.hypot(*(off - centre).T)))
    tri = tuple(
        (float(feet[k, 0] - centre[0]), float(feet[k, 1] - centre[1])) for k in range(4) if k != leg
    )
    return tri, radius


def sway_point(
    b: StepBuilder,
    lifts: list[tuple[Any, ...]],
    nominal: np.ndarray,
    base_start: np.ndarray | None = None,
) -> np.ndarray:
    """The base (3,) [m] nearest ``nominal`` with the whole-body CoM inside by the threshold
    for each lift (leg, feet (4, 3), target (3,)[, advance (3,)]) in ``lifts`` (module
    docstring, sway).
    With ``base_start`` the first lift swings while the base moves from there to the point
    (moving_transfer checks it); the others lift off at the point (their own
    steps sway their ends), with SHIFT_EXTRA_M to spare."""
    base = np.array(nominal, dtype=float)
    if not lifts:
        return base
    extra = SHIFT_EXTRA_M
    for _ in range(SWAY_ROUNDS):
        regions = [
            _lift_region(b, leg, feet, target, base, base_start if i == 0 else None, advance)
            for i, (leg, feet, target, *advance_) in enumerate(lifts)
            for advance in (advance_[0] if advance_ else None,)
        ]
        spread = max(r for _, r in regions)
        tris = [t for t, _ in regions]
        point = (float(nominal[0]), float(nominal[1]))
        xy = closest_point_with_margin(tris, point, b.threshold + spread + extra)
        if xy is None:
            xy = closest_point_with_margin(tris, point, b.threshold + spread)
        if xy is None:
            raise b.error(
                f"the crawl finds no sway for lifting {', '.join(LEGS[x[0]] for x in lifts)}"
                f" with margin {b.threshold + spread:.4g} m"
            )
        base = np.array([xy[0], xy[1], nominal[2]])
        worst = min(
            _lift_off_margin(b, j, tgt, base, f, base_start if i == 0 else None)
            for i, (j, f, tgt, *_) in enumerate(lifts)
        )
        if worst >= b.threshold - MARGIN_TOLERANCE:
            return base
        extra += b.threshold - worst
    raise b.error("the crawl's sway does not settle with the whole-body CoM inside")


def _lift_off_margin(
    b: StepBuilder,
    leg: int,
    target: np.ndarray,
    base: np.ndarray,
    feet: np.ndarray,
    base_start: np.ndarray | None,
) -> float:
    """S_m [m] of the lift: over the moving swing (``base_start`` to ``base``), or at the
    lift-off with the base at ``base`` (:func:`_lift_region`)."""
    if base_start is not None or b.moving_swing_com is None:
        return moving_lift_margin(b, leg, target, base, feet, base_start)
    com, _ = b.moving_swing_com(base, base, b.yaw, feet, leg, feet[leg], n=1)
    if not np.all(np.isfinite(com)):
        return -np.inf
    # one point: the scalar form of triangle_margins (the same operations on floats)
    a, b_, c = (tuple(feet[k, :2].tolist()) for k in range(4) if k != leg)
    return triangle_margin_xy(a, b_, c, (float(com[0, 0]), float(com[0, 1])))


def capped_sway_end(
    legs,
    ws: Workspace,
    b: StepBuilder,
    lifts: list[tuple[Any, ...]],
    start: np.ndarray | None,
    base_end: np.ndarray,
    label: str,
) -> np.ndarray:
    """The end (3,) [m] of the crawl's moving transfer of the first of ``lifts`` (as
    :func:`sway_point`), the base moving from ``start`` (None: where it is): ``base_end``
    where the stance legs keep their effort budget over the swing (moving_over_budget:
    the run's three-foot split at the whole-body CoM, planner/gaits/load_caps.py), else the
    nearest to it of the SWAY_CAP_CANDIDATES points whose swing keeps
    the margins :func:`sway_point` keeps, the budget and :func:`swept_reach_ok`'s rules;
    OverBudget naming the joint and the step where none does. The sway point is the nearest
    with the margin: on phasmid at h 0.3337 m (corpus seed 20261202, case #14) LH's swing
    then needed 36.7 N m of RH_hip_pitch (budget 34.0 N m) and the run refused the crawl."""
    leg, feet, target = lifts[0][:3]
    b0 = b.base if start is None else start
    over = moving_over_budget(b, leg, target, base_end, feet, b0)
    if over is None:
        return base_end
    least = b.threshold - MARGIN_TOLERANCE
    for offset in SWAY_CAP_CANDIDATES:
        end = np.array([base_end[0] + offset[0], base_end[1] + offset[1], base_end[2]])
        try:
            if moving_lift_margin(b, leg, target, end, feet, b0) < least or any(
                _lift_off_margin(b, j, tgt, end, f, None) < least for j, f, tgt, *_ in lifts[1:]
            ):
                continue
        except PlanningError:
            continue
        if moving_over_budget(b, leg, target, end, feet, b0) is not None:
            continue
        if legs is None or swept_reach_ok(legs, ws, b, start, end, leg, target, ws.swing_height_m):
            return end
    name, torque, budget = over
    raise OverBudget(
        f"no sway of the crawl lets {LEGS[leg]} lift ({label}) within both the margin "
        f">= {b.threshold:.4g} m and the effort budget: joint {name} needs {torque:.2f} N m "
        f"standing still, above its budget {budget:.2f} N m",
        b.waypoint_index,
        b.waypoint,
    )
