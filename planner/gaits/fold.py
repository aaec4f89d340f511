"""Shifts folded into the last body phase (the default preset's ``fold_shifts``).

When a lift lacks margin, :func:`fold_shift` moves the end of the last body (or rotate)
step, and the CoG of the transfers since, to the point nearest it where every one of those
lifts and this one keep S_m >= threshold + SHIFT_EXTRA_M (else >= threshold;
planner/stability/shifts.py closest_point_with_margin): the body phase does the shift at no
extra time. :class:`planner.gaits.builder.StepBuilder` inserts a shift step only when this
returns False.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from planner.errors import PlanningError
from planner.gaits.body_pace import CREEP_BODY_LABEL, body_units
from planner.gaits.steps import COM_SHIFT_ROUNDS, SHIFT_EXTRA_M, Step, StepKind
from planner.stability.margin import MARGIN_TOLERANCE
from planner.stability.shifts import closest_point_with_margin
from planner.trajectory.samples import LEGS

if TYPE_CHECKING:
    from planner.gaits.builder import StepBuilder


def lift_group(b: StepBuilder) -> tuple[tuple[tuple[float, float], ...], ...] | None:
    """Support triangles ((x, y) of the three stance feet [m]) of the lifts since the
    last body or rotate step, oldest first; None when there is no such step yet."""
    last = last_body_index(b)
    if last is None:
        return None
    return tuple(
        tuple((float(f[k, 0]), float(f[k, 1])) for k in range(4) if k != LEGS.index(s.leg))
        for s in b.steps[last + 1 :]
        for f in (s.position_feet_in_world,)
        if s.leg is not None and f is not None
    )


def last_body_index(b: StepBuilder) -> int | None:
    return next(
        (i for i in range(len(b.steps) - 1, -1, -1) if b.steps[i].kind != StepKind.TRANSFER),
        None,
    )


def folded_steps(steps: list[Step], last: int, base: np.ndarray) -> list[Step]:
    """``steps`` with the end of step ``last`` (a body or rotate step) and the CoG of the
    transfers after it moved to ``base`` (3,) [m]."""
    out = list(steps[:last])
    out.append(replace(steps[last], position_base_end_in_world=base.copy()))
    out.extend(
        replace(s, position_base_start_in_world=base.copy(), position_base_end_in_world=base.copy())
        for s in steps[last + 1 :]
    )
    return out


def _trial(b: StepBuilder, last: int, base: np.ndarray) -> list[Step] | None:
    """The steps a fold to ``base`` would leave, for the contact points of ball feet (they
    roll along the base path); None (the steps so far) for point feet."""
    return None if b.rolled_contacts is None else folded_steps(b.steps, last, base)


def fold_shift(b: StepBuilder, leg: int, target: np.ndarray) -> bool:
    """Move the end of the last body (or rotate) step, and the CoG of the transfers since,
    to the point nearest it with S_m >= threshold + SHIFT_EXTRA_M (else >= threshold) for
    every lift since that step and for lifting ``leg`` now; False (nothing changed) when
    there is no body step yet, no such point, or the step is a creeping gait's body phase
    that would move further than its time lets the zero-moment point stay within the
    threshold (planner/gaits/body_pace.py). The body phase then does the shift: no
    extra step, no extra time. With ``swing_com`` the triangles are moved by each lift's
    CoM offset and the threshold raised by its spread (:meth:`StepBuilder.com_spread`), then every
    lift is checked again at the new base (COM_SHIFT_ROUNDS). False too where the point
    breaks a stance leg's effort budget on one of the earlier lifts (StepBuilder.over_budget,
    planner/gaits/load_caps.py): the fold moved a shift step that kept the budget for LF's
    lift to the nearest point for the next lift, where LF's lift then needed 34.26 N m of
    mantis's arm3_lift (budget 34.00 N m, h 0.2718 m)."""
    last = last_body_index(b)
    if last is None or last < b.fold_fence:
        return False
    lifts = [
        (LEGS.index(s.leg), s.position_feet_in_world, s.foothold_end_in_world)
        for s in b.steps[last + 1 :]
        if s.leg is not None
        and s.position_feet_in_world is not None
        and s.foothold_end_in_world is not None
    ]
    lifts.append((leg, b.feet.copy(), target))
    start = (float(b.base[0]), float(b.base[1]))
    base = b.base.copy()
    rounds = 1 if b.swing_com is None and b.rolled_contacts is None else COM_SHIFT_ROUNDS
    for _ in range(rounds):
        triangles, spread = [], 0.0
        folded = _trial(b, last, base)
        for j, f, end in lifts:
            try:
                centre, radius = b.com_spread(j, end, base, f, folded)
                c = b.contact_points(f, base, folded)
            except PlanningError:
                # the base of the previous round takes a foot of an earlier lift out of
                # reach: no fold here (a shift step may still place the CoG)
                return False
            triangles.append(
                tuple(
                    (float(c[k, 0] - centre[0]), float(c[k, 1] - centre[1]))
                    for k in range(4)
                    if k != j
                )
            )
            spread = max(spread, radius)
        cog = closest_point_with_margin(triangles, start, b.threshold + spread + SHIFT_EXTRA_M)
        if cog is None:
            cog = closest_point_with_margin(triangles, start, b.threshold + spread)
        if cog is None:
            return False
        base = np.array([cog[0], cog[1], b.base[2]])
        folded = _trial(b, last, base)
        try:
            if rounds == 1 or all(
                b.lift_margin(j, end, base, f, folded) >= b.threshold - MARGIN_TOLERANCE
                for j, f, end in lifts
            ):
                break
        except PlanningError:  # a stance foot out of reach at that base
            return False
    else:
        return False
    try:
        if any(b.over_budget(j, end, base, f, folded) is not None for j, f, end in lifts[:-1]):
            # the point breaks a stance leg's effort budget on a lift the fold moves
            # (planner/gaits/load_caps.py): a shift step instead (the lift of ``leg`` is the
            # builder's: it shifts again where the fold breaks the budget for it)
            return False
    except PlanningError:
        return False
    body = b.steps[last]
    if (
        body.label == CREEP_BODY_LABEL
        and body.duration
        < body_units(
            float(np.hypot(*(base[:2] - body.position_base_start_in_world[:2]))),
            b.cog_height(),
            b.threshold,
            0.0,
        )
        - 1e-9
    ):
        # the creeping gait's body phase would move further than its time lets the ZMP
        # stay within the margin (planner/gaits/body_pace.py): a shift step instead
        return False
    b.steps[:] = folded_steps(b.steps, last, base)
    b.base = base
    b.n_folded += 1
    return True
