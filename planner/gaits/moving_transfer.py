"""A swing while the base moves in a straight line: the continuous crawl's step
(planner/gaits/crawl.py, planner/gaits/sway.py), added to a
:class:`planner.gaits.builder.StepBuilder` after its stability check.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from planner.gaits.steps import TRANSFER_UNITS, Phase, StepKind
from planner.stability.margin import MARGIN_TOLERANCE, triangle_margin_xy, triangle_margins
from planner.trajectory.samples import LEGS

if TYPE_CHECKING:
    from planner.gaits.builder import StepBuilder


def moving_lift_margin(
    builder: StepBuilder,
    leg: int,
    target_in_world: np.ndarray,
    base_end: np.ndarray,
    feet: np.ndarray,
    base_start: np.ndarray | None = None,
) -> float:
    """S_m [m] of lifting ``leg`` while the base moves from ``base_start`` to
    ``base_end`` (a still base when ``base_start`` is None, :meth:`StepBuilder.lift_margin`): the
    body CoG at both ends (S_m is concave along the straight move), or with
    ``moving_swing_com`` the smallest of the whole-body CoM over the moving swing."""
    if base_start is None:
        return builder.lift_margin(leg, target_in_world, base_end, feet)
    ends = (base_start, base_end)
    contacts = [builder.contact_points(feet, p) for p in ends]
    triangles = [np.array([c[k, :2] for k in range(4) if k != leg]) for c in contacts]
    if builder.moving_swing_com is None:
        return min(
            triangle_margin_xy(tuple(tri[0]), tuple(tri[1]), tuple(tri[2]), (p[0], p[1]))
            for tri, p in zip(triangles, ends)
        )
    com, _ = builder.moving_swing_com(
        base_start, base_end, builder.yaw, contacts[-1], leg, target_in_world
    )
    if not np.all(np.isfinite(com)):
        return -np.inf
    return float(min(np.min(triangle_margins(tri, com)) for tri in triangles))


#: Points of the moving swing (of the model's SWING_CHECK_SAMPLES) at which
#: :func:`moving_over_budget` takes the stance legs' static torques.
BUDGET_POINTS = 21


def moving_over_budget(
    builder: StepBuilder,
    leg: int,
    target_in_world: np.ndarray,
    base_end: np.ndarray,
    feet: np.ndarray,
    base_start: np.ndarray,
) -> tuple[str, float, float] | None:
    """(joint, static torque [N m], budget [N m]) of the stance joint furthest over its
    effort budget while ``leg`` swings to ``target_in_world`` and the base moves from
    ``base_start`` to ``base_end`` (3,) [m], the feet on ``feet`` (4, 3) [m]: the three-foot
    split at the whole-body CoM (LoadCaps.stance_torques, the run's check's split) at
    BUDGET_POINTS points of the moving swing, each with the base where it is then; None
    when every stance joint keeps its budget (or without ``load_caps`` or
    ``moving_swing_com``)."""
    caps = builder.load_caps
    if caps is None or builder.moving_swing_com is None:
        return None
    start, end = np.asarray(base_start, dtype=float), np.asarray(base_end, dtype=float)
    contacts = builder.contact_points(feet, end)
    com, path = builder.moving_swing_com(start, end, builder.yaw, contacts, leg, target_in_world)
    if not np.all(np.isfinite(com)):
        return None  # out of reach: the margin check refuses it
    rows = np.unique(np.linspace(0, len(com) - 1, BUDGET_POINTS).round().astype(int))
    span = float(np.hypot(*(end[:2] - start[:2])))
    along = np.hypot(*(path[rows] - start[:2]).T) / span if span > 0 else np.zeros(len(rows))
    bases = np.column_stack([path[rows, 0], path[rows, 1], start[2] + along * (end[2] - start[2])])
    tau = caps.stance_torques_along(leg, bases, builder.yaw, contacts, com[rows])
    ratio = np.abs(tau) / caps.budget_nm
    ratio[~np.isfinite(ratio)] = -np.inf  # a stance foot out of reach: the margin refuses it
    # the first largest in swing order, then joint order (row-major argmax)
    i, j = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
    if not ratio[i, j] > 1.0:
        return None
    return caps.robot.joint_names[j], float(abs(tau[i, j])), float(caps.budget_nm[j])


def moving_transfer(
    builder: StepBuilder,
    leg: int,
    target_in_world: np.ndarray,
    base_end_in_world: np.ndarray,
    label: str,
    phase: Phase = Phase.CREEP,
) -> None:
    """Swing ``leg`` to ``target_in_world`` (3,) [m] while the base moves in a straight
    line to ``base_end_in_world`` (3,) [m] (the continuous crawl, planner/gaits/crawl.py).
    Accepted only if the lift has S_m >= threshold with the base at both ends (the
    margin of a point moving on a line is concave, so the ends bound the body CoG's;
    the whole-body CoM is checked at both ends and verified on every sample)."""
    target_in_world = np.asarray(target_in_world, dtype=float)
    base_end = np.asarray(base_end_in_world, dtype=float)
    margin = moving_lift_margin(builder, leg, target_in_world, base_end, builder.feet, builder.base)
    if margin < builder.threshold - MARGIN_TOLERANCE:
        raise builder.error(
            f"lift of leg {LEGS[leg]} ({label}) has margin {margin:.4f} m < "
            f"{builder.threshold:.4g} m with the base moving"
        )
    builder.append_step(
        StepKind.TRANSFER,
        leg,
        TRANSFER_UNITS,
        base_end,
        builder.yaw,
        target_in_world,
        label,
        phase,
    )
    builder.clear_com_cache()
