"""Replacement footholds of the omnidirectional creeping gait (planner/gaits/omni.py): where
the verification of the samples (planner/trajectory/verify.py) refuses a swing of the plan,
the swing foot's foothold is moved within its reach set and the plan walked again, before
another gait is tried (issue 21 item 6, "no degraded fallback").

The gait puts a swing foot at position 2 + t u (its ellipse, planner/gaits/foothold_ellipse.py).
The builder checks each lift on SWING_CHECK_SAMPLES configurations of the whole-body CoM
(planner/model.py); the samples can still dip under the threshold between them, or a
tibia come nearer the ground than the rule allows. The foothold of the refused swing is one
input of both: the swing leg's share of the CoM over the swing (its mass moves with the foot)
and the leg's pose at touchdown. The candidates are the nominal foothold plus the offsets of
:data:`OFFSETS_M` (rings of RING_DIRECTIONS directions, nearest first), kept where the foot
stays inside its ellipse and reachable within the joint limits with the body displaced by
the workspace's shift reserve as it lands and after the body phase, its tibia clear (the
checks of omni._reachable for one foot).
Each candidate replays the walk from the start (the same steps up to the replaced swing:
the walk is deterministic), at most MAX_REPLACEMENTS walks per plan.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from planner.gaits.foothold_ellipse import ellipse_semi_axes
from planner.gaits.tibia_reach import tibias_clear
from planner.workspace.layout import (
    RESERVE_DIRECTIONS,
    SHIFT_RESERVE_M,
    Workspace,
    reachable_in_limits_of_legs,
)

#: Radii of the candidate rings around the nominal foothold [m] and directions per ring.
RING_RADII_M = (0.005, 0.01, 0.02)
RING_DIRECTIONS = 8
#: Walks of one plan with replaced footholds, at most (each costs a whole plan).
MAX_REPLACEMENTS = 12


def _offsets() -> np.ndarray:
    angles = 2.0 * np.pi * np.arange(RING_DIRECTIONS) / RING_DIRECTIONS
    rays = np.column_stack([np.cos(angles), np.sin(angles)])
    return np.vstack([r * rays for r in RING_RADII_M])


#: Candidate offsets (K, 2) in B [m] from a nominal foothold, nearest first.
OFFSETS_M = _offsets()


@dataclass
class FootholdReplacements:
    """The footholds a plan's walk replaces, kept across its walks (module docstring).

    Attributes:
        offsets: transfer ordinal (the how-many-th swing of the walk, from 0) -> offset
            (2,) in B [m] added to the gait's nominal foothold.
        swings: start time [units] of each swing of the last walk -> (ordinal, leg, nominal
            foothold (3,) in B [m] relative to the nominal CoG, workspace).
        tried: ordinal -> candidates of OFFSETS_M tried so far.
        walks: walks made with a replaced foothold.
    """

    offsets: dict[int, np.ndarray] = field(default_factory=dict)
    swings: dict[float, tuple[int, int, np.ndarray, Workspace]] = field(default_factory=dict)
    tried: dict[int, int] = field(default_factory=dict)
    walks: int = 0

    def offset(self, ordinal: int) -> np.ndarray:
        """The offset (2,) [m] of swing ``ordinal`` (zero where none is replaced)."""
        return self.offsets.get(ordinal, np.zeros(2))

    def record(
        self, t_start: float, ordinal: int, leg: int, nominal_in_base: np.ndarray, ws: Workspace
    ) -> None:
        """Remember swing ``ordinal`` of ``leg`` starting at ``t_start`` [units]."""
        self.swings[round(float(t_start), 6)] = (ordinal, leg, np.array(nominal_in_base), ws)

    def replace_at(self, t_start: float | None, legs) -> bool:  # noqa: ANN001
        """Move the foothold of the swing that started at ``t_start`` [units] to its next
        valid candidate (module docstring); False when there is no such swing, no candidate
        is left, or MAX_REPLACEMENTS walks are spent. Swings after it are walked anew."""
        if t_start is None or self.walks >= MAX_REPLACEMENTS:
            return False
        hit = self.swings.get(round(float(t_start), 6))
        if hit is None:
            return False
        ordinal, leg, nominal, ws = hit
        self.offsets = {k: v for k, v in self.offsets.items() if k <= ordinal}
        self.tried = {k: v for k, v in self.tried.items() if k <= ordinal}
        for i in range(self.tried.get(ordinal, 0), len(OFFSETS_M)):
            self.tried[ordinal] = i + 1
            if _placeable(legs, ws, leg, nominal, OFFSETS_M[i]):
                self.offsets[ordinal] = OFFSETS_M[i]
                self.walks += 1
                return True
        return False


def _placeable(legs, ws: Workspace, leg: int, nominal: np.ndarray, off: np.ndarray) -> bool:  # noqa: ANN001
    """Whether ``leg``'s foot at ``nominal`` (3,) in B [m] moved by ``off`` (2,) [m] stays
    in its ellipse and is reachable within the joint limits, at ground and swing height,
    with the body displaced by the shift reserve, its tibia clear (module docstring)."""
    a = ellipse_semi_axes(ws)
    mid = ws.position_mid_in_base[leg]
    before = nominal[:2] + off - mid[:2]  # from position 2 as it lands
    if np.any(a <= 0.0) or max(np.sum((before / a) ** 2), np.sum((off / a) ** 2)) > 1.0:
        return False  # and after the body phase, which brings position 2 over it
    p = nominal.copy()
    p[:2] += off
    after = mid.copy()
    after[:2] += off
    shifts = np.vstack([np.zeros(3), SHIFT_RESERVE_M * RESERVE_DIRECTIONS])
    pts = np.vstack(
        [p + shifts, p + np.array([0.0, 0.0, ws.swing_height_m]) + shifts, after + shifts]
    )
    rows = np.full(len(pts), leg)
    return bool(reachable_in_limits_of_legs(legs, rows, pts).all()) and bool(
        tibias_clear(legs, ws, np.array([leg, leg]), np.vstack([p, after])).all()
    )
