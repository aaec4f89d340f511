"""How far the continuous crawl's body may advance in one step (planner/gaits/crawl.py):
every foot stays reachable within the joint limits, with the workspace's shift reserve, while
the body advances along the travel direction u and the swing foot moves to its foothold.

The advance is the stance feet's ellipse limit (foothold_ellipse.stance_step_limit)
halved until every foot is reachable; the swing foot's foothold distance r from its position
2 along u is the first of REACH_FACTORS times the ellipse radius that has such an advance.
"""

from __future__ import annotations

import numpy as np

from planner.gaits.foothold_ellipse import ellipse_radius, stance_step_limit
from planner.workspace.layout import (
    RESERVE_DIRECTIONS,
    SHIFT_RESERVE_M,
    Workspace,
    reachable_in_limits_of_legs,
)

#: Factors tried on the foothold distance r when the front of the ellipse is out of reach.
REACH_FACTORS = (1.0, 0.75, 0.5, 0.25, 0.0)
#: Bisection halvings of a body advance whose feet leave the reachable set.
REACH_HALVINGS = 12

#: The body displacements each reach check holds a foot to: none and the shift reserve in
#: 8 directions, (9, 3) [m].
_RESERVE_SHIFTS = np.vstack([np.zeros(3), SHIFT_RESERVE_M * RESERVE_DIRECTIONS])


def feet_reachable(
    legs,
    ws: Workspace,
    leg: int | None,
    off: np.ndarray,
    u: np.ndarray,
    advances: list[float],
    r: float,
) -> np.ndarray:
    """Whether every foot stays reachable (joint limits, the shift reserve in 8 directions)
    when the body advances t [m] along u, for each t of ``advances``, (T,) bool: stance feet
    at advance 0, t/2 and t; the swing foot (``leg``, None for a four-foot phase) at r u
    from position 2 after the advance, on the ground and lifted, and lifted half-way from
    its start offset. All candidates and legs go through one IK pass (the same values as
    one reachable_in_limits call per leg and advance: the IK is elementwise)."""
    t = np.asarray(advances, dtype=float)
    s = np.stack([np.zeros_like(t), 0.5 * t, t], axis=1)  # (T, 3) [m]
    rows, targets, stance = [], [], []
    for k in range(len(legs)):
        mid = ws.position_mid_in_base[k]
        if k == leg:
            # base and foot follow the same blend, so seen from the base the foot moves on
            # the line from its start offset to its foothold, lifted (independent of t)
            p = mid + np.array([r * u[0], r * u[1], 0.0])
            start = mid + np.array([off[k, 0], off[k, 1], 0.0])
            lift = np.array([0.0, 0.0, ws.swing_height_m])
            pts = np.array([p, p + lift, 0.5 * (start + p) + lift])[None]  # (1, 3, 3)
        else:
            pts = np.empty((len(t), 3, 3))
            pts[..., 0] = off[k, 0] - s * u[0]
            pts[..., 1] = off[k, 1] - s * u[1]
            pts[..., 2] = 0.0
            pts = mid + pts  # (T, 3, 3)
            stance.append(k)
        targets.append((pts[:, :, None, :] + _RESERVE_SHIFTS).reshape(-1, 3))
        rows.append(np.full(len(targets[-1]), k))
    ok = np.asarray(reachable_in_limits_of_legs(legs, np.concatenate(rows), np.vstack(targets)))
    out = np.ones(len(t), dtype=bool)
    at = 0
    for k, target in enumerate(targets):
        each = np.asarray(ok[at : at + len(target)].reshape(len(target) // 27, 27).all(axis=1))
        out &= each if k in stance else each[0]
        at += len(target)
    return out


def reachable_advance(
    legs, ws: Workspace, leg: int | None, off: np.ndarray, u: np.ndarray, t_want: float
) -> tuple[float, float]:
    """(t, r): the body advance [m] (<= t_want, stance feet in their ellipses, reachable)
    and the swing foot's distance from position 2 along u [m] (module docstring): the first
    of the foothold factors, and for it the first of t_cap halved up to REACH_HALVINGS - 1
    times, then 0, that keeps every foot reachable (the first candidate alone, the rest of
    a factor in one pass)."""
    stance = [k for k in range(4) if k != leg]
    t_cap = min(t_want, stance_step_limit(ws, off[stance], u))
    radius = ellipse_radius(ws, u)
    advances = [t_cap]
    for _ in range(REACH_HALVINGS - 1):
        advances.append(advances[-1] * 0.5)
    advances.append(0.0)
    for factor in REACH_FACTORS if leg is not None else (0.0,):
        r = factor * radius
        if legs is None:
            return t_cap, r
        if feet_reachable(legs, ws, leg, off, u, advances[:1], r)[0]:
            return t_cap, r
        ok = feet_reachable(legs, ws, leg, off, u, advances[1:], r)
        if ok.any():
            return advances[1 + int(np.argmax(ok))], r
    raise ValueError("no reachable foothold")
