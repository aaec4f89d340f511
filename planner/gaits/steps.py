"""The step list of a plan: what each step is (thesis §4.2), as data.

A plan is a sequence of steps, each of whole time units t_l (thesis §4.2):

    transfer  one leg swings from its foothold to a new one; the base stands still (1 unit).
    body      all four feet stand; the CoG translates (creeping body phase: 2 units, λ/2;
              a stability "shift" before a lift: 1 unit, label "shift").
    rotate    all four feet stand; the base turns about the vertical (spinning gait's body
              rotation, 2 units), returning the CoG to the spin centre if it was shifted.

:class:`StepKind` says what moves, :class:`Phase` which part of the gait a step belongs to
(metrics count by it, not by labels). The builder that checks every step before accepting it
is planner/gaits/builder.py.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.presets import StrEnum
from planner.stability.shifts import SHIFT_EXTRA_M  # noqa: F401 (re-exported for the gaits)

#: Durations [time units t_l] (thesis §4.2.1, §4.2.2).
TRANSFER_UNITS = 1.0
BODY_UNITS = 2.0
ROTATE_UNITS = 2.0
SHIFT_UNITS = 1.0

#: Rounds of "move the base, recompute the whole-body CoM" a CoM shift may take (a shift
#: step, planner/gaits/builder.py, or a fold, planner/gaits/fold.py): the CoM follows the
#: base with a gain of ~0.9 (stance legs stay behind), so each round shrinks the shortfall
#: ~10x; 6 rounds leave < 1e-6 of it.
COM_SHIFT_ROUNDS = 6


class StepKind(StrEnum):
    """What moves in a step (module docstring)."""

    TRANSFER = "transfer"
    BODY = "body"
    ROTATE = "rotate"


class Phase(StrEnum):
    """Which part of the gait a step belongs to (metrics count time and distance by it)."""

    CREEP = "creep"  # creeping gait: transfers and body phases (λ/2 each)
    SPIN = "spin"  # spinning gait: transfers and the base rotation
    TRANSITION = "transition"  # creep <-> spin stance changes (thesis preset)
    SHIFT = "shift"  # a stability shift (1 unit body step)
    STAND = "stand"  # a plan with no step: the start pose


@dataclass(frozen=True, eq=False)
class Step:
    """One step of a plan (times in units t_l, positions in the world frame W [m]).

    Attributes:
        kind: StepKind (a str: "transfer", "body" or "rotate").
        leg: swinging leg name for transfers, else None.
        t_start, t_end: start and end time [units].
        position_base_start_in_world, position_base_end_in_world: CoG (3,) [m].
        yaw_base_start, yaw_base_end: heading of the base x axis [rad].
        foothold_start_in_world, foothold_end_in_world: swing foot (3,) [m], transfers only.
        label: phase label, e.g. "creep transfer RH", "spin rotate", "shift".
        waypoint_index: the waypoint this step works towards (0-based), or None.
        position_feet_in_world: all four feet at the step start (4, 3) [m].
        phase: the gait phase (:class:`Phase`).
    """

    kind: StepKind
    leg: str | None
    t_start: float
    t_end: float
    position_base_start_in_world: np.ndarray
    position_base_end_in_world: np.ndarray
    yaw_base_start: float
    yaw_base_end: float
    foothold_start_in_world: np.ndarray | None = None
    foothold_end_in_world: np.ndarray | None = None
    label: str = ""
    waypoint_index: int | None = None
    position_feet_in_world: np.ndarray | None = None
    phase: Phase = Phase.CREEP

    @property
    def duration(self) -> float:
        """t_end - t_start [units]."""
        return self.t_end - self.t_start

    def to_dict(self) -> dict[str, object]:
        """JSON-able dict (lists and floats) for plan.json."""

        def vec(v: np.ndarray | None) -> list[float] | None:
            return None if v is None else [float(x) for x in v]

        return {
            "kind": str(self.kind),
            "phase": str(self.phase),
            "leg": self.leg,
            "label": self.label,
            "t_start": float(self.t_start),
            "t_end": float(self.t_end),
            "position_base_start_in_world": vec(self.position_base_start_in_world),
            "position_base_end_in_world": vec(self.position_base_end_in_world),
            "yaw_base_start": float(self.yaw_base_start),
            "yaw_base_end": float(self.yaw_base_end),
            "foothold_start_in_world": vec(self.foothold_start_in_world),
            "foothold_end_in_world": vec(self.foothold_end_in_world),
            "waypoint_index": self.waypoint_index,
        }
