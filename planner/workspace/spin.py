"""The spin angle per cycle ψ_max (thesis §4.2.2): how far the stance turns about the CoG.

:func:`psi_max` bisects the largest ψ <= π/2 with every rotated foothold reachable within the
joint limits (planner/workspace/reach_check.py, one vectorised IK pass per probe); the default
preset keeps a θ1 reserve (per leg family, planner/workspace/families.py), a body shift
reserve and the swings from the creeping stance.
"""

from __future__ import annotations

import numpy as np

from planner.presets import FootholdRule, footholds_of
from planner.workspace.families import workspace_family
from planner.workspace.foothold_layout import (
    RESERVE_DIRECTIONS,
    SHIFT_RESERVE_M,
    foothold_layout,
    swing_height_m,
)
from planner.workspace.reach_check import reachable_in_limits_of_legs
from silo4kin.frames import rotation_z
from silo4kin.memo import cached_on_first_argument

#: Smallest spin angle per cycle a default-preset plan that turns its stance accepts [rad]
#: (planner/gaits/walk.py check_can_spin); a height whose stride across the body is too
#: short to walk sideways needs it (planner/workspace/heights.py): 2° is ~45 cycles for a
#: quarter turn.
MIN_DEFAULT_SPIN_RAD = np.deg2rad(2.0)


def psi_max(
    robot,
    mid: np.ndarray,
    reserve: float,
    shift: float,
    starts: np.ndarray | None = None,
    swing_m: float = 0.0,
    decided_at: float | None = None,
) -> float:
    """Largest ψ <= π/2 with the spin stance rotated by ±ψ about the CoG reachable with θ1
    narrowed by ``reserve`` [rad] and the body displaced by up to ``shift`` [m]
    (thesis-notes.md: acos(Lb / |p2|) for SILO4 without reserves). With ``starts`` (4, K, 3)
    [m], the swings from those footholds to the rotated stance (straight in x, y, lifted by
    ``swing_m`` sin(πs) [m], as the default's first spin cycle from the creeping stance,
    planner/path/plan_path.py) must be reachable too: their chords pass nearer the hip.

    With ``decided_at`` [rad] the bisection stops as soon as its result is known to be
    >= decided_at or < decided_at, and returns a value on that same side (the bisection's
    probes are the same, so the answer is that of the full bisection, monotone or not)."""
    offsets = np.vstack([np.zeros(3), shift * RESERVE_DIRECTIONS])
    s = np.linspace(0.1, 0.9, 5)[:, None]

    lift_m = swing_m * np.sin(np.pi * s[:, 0])  # (5,) the chords' lift [m]
    n_legs = len(robot.legs)
    # (leg, sign) pairs in the order leg 0 +ψ, leg 0 -ψ, leg 1 +ψ, ...
    starts2 = None if starts is None else np.repeat(np.asarray(starts, float), 2, axis=0)
    per_pair = 1 if starts2 is None else 1 + 5 * starts2.shape[1]
    idx = np.repeat(np.arange(n_legs).repeat(2), per_pair * len(offsets))

    def ok(psi: float) -> bool:  # every leg, both signs, in one vectorised IK pass
        targets = np.array(
            [rotation_z(sign * psi) @ mid[i] for i in range(n_legs) for sign in (1.0, -1.0)]
        )  # (2L, 3)
        if starts2 is None:
            pts = targets[:, None, :]
        else:  # the chords from each start to the rotated foothold
            chords = (
                starts2[:, :, None, :]
                + s[None, None] * (targets[:, None, :] - starts2)[:, :, None, :]
            )  # (2L, K, 5, 3)
            chords[..., 2] += lift_m
            pts = np.concatenate([targets[:, None, :], chords.reshape(len(targets), -1, 3)], axis=1)
        pts = (pts[:, :, None, :] + offsets[None, None]).reshape(-1, 3)
        return bool(np.all(reachable_in_limits_of_legs(robot.legs, idx, pts, reserve)))

    if ok(np.pi / 2):
        return float(np.pi / 2)
    lo, hi = 0.0, np.pi / 2
    for _ in range(24):  # π/2 / 2^24 < 1e-7 rad
        if decided_at is not None and (lo >= decided_at or hi <= decided_at):
            break  # lo only grows and the result stays below hi: its side is known
        m = 0.5 * (lo + hi)
        lo, hi = (m, hi) if ok(m) else (lo, m)
    return float(lo)


@cached_on_first_argument(512)
def default_psi_max(robot, height: float) -> float:
    """ψ_max of the default workspace [rad]: θ1 reserve, shift reserve, and the swings from
    the creeping footholds to the rotated stance (psi_max). A mammal leg has no hip yaw: its
    yaw comes from HAA and the two pitches, so no θ1 reserve (the shift reserve stays)."""
    _, mid, lam, starts, reserve, swing = _default_psi_inputs(robot, height)
    return psi_max(robot, mid, reserve, SHIFT_RESERVE_M, starts=starts, swing_m=swing)


def _default_psi_inputs(robot, height: float) -> tuple:
    """(ρ, mid, λ, starts, θ1 reserve, swing height) of :func:`default_psi_max`."""
    rho, mid, lam = foothold_layout(robot, height, "default")
    starts = mid[:, None, :] + np.array([[-lam[0] / 2, 0, 0], [0, 0, 0], [lam[0] / 2, 0, 0]])
    reserve = workspace_family(robot).spin_theta1_reserve_rad
    return rho, mid, lam, starts, reserve, swing_height_m(robot, height, "default")


@cached_on_first_argument(512)
def default_spin_suffices(robot, height: float) -> bool:
    """``default_psi_max(robot, height) >= MIN_DEFAULT_SPIN_RAD``, by a bisection that stops
    once the answer is known (feasible_height_range asks this at ~70 heights; the full ψ_max
    takes 25 IK passes, the answer mostly one)."""
    _, mid, lam, starts, reserve, swing = _default_psi_inputs(robot, height)
    return (
        psi_max(
            robot,
            mid,
            reserve,
            SHIFT_RESERVE_M,
            starts=starts,
            swing_m=swing,
            decided_at=float(MIN_DEFAULT_SPIN_RAD),
        )
        >= MIN_DEFAULT_SPIN_RAD
    )


def stance_turns(ws) -> bool:
    """Whether the plans in workspace ``ws`` (planner.workspace.layout.Workspace) may turn
    their stance: the thesis preset always (§5.5), the default where it turns at least
    MIN_DEFAULT_SPIN_RAD per cycle (elsewhere its plans walk without turning, or are
    refused: planner/gaits/walk.py check_can_spin)."""
    if footholds_of(ws.preset) is not FootholdRule.REACHABLE_SETS:
        return True
    return bool(ws.psi_max_rad >= MIN_DEFAULT_SPIN_RAD)


def turn_per_cycle_rad(ws) -> float:
    """The turn per spinning cycle [rad] of the plans in workspace ``ws``: ψ_max where they
    may turn (:func:`stance_turns`), else 0."""
    return float(ws.psi_max_rad) if stance_turns(ws) else 0.0
