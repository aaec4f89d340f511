"""The step list of a plan and the builder that checks every step before it is accepted.

A plan is a sequence of steps, each of whole time units t_l (thesis §4.2):

    transfer  one leg swings from its foothold to a new one; the base stands still (1 unit).
    body      all four feet stand; the CoG translates (creeping body phase: 2 units, λ/2;
              a stability "shift" before a lift: 1 unit, label "shift").
    rotate    all four feet stand; the base turns about the vertical (spinning gait's body
              rotation, 2 units), returning the CoG to the spin centre if it was shifted.

Stability (thesis §5.1, checked before any joint value exists): a transfer is accepted only if
the CoG projection is inside the support triangle of the other three feet with S_m >=
threshold. When it is not, :class:`StepBuilder` inserts one "shift" body step that moves the
CoG the shortest way towards the triangle's incenter until S_m = threshold + SHIFT_EXTRA_M
(the thesis instead accepts S_m = 0; see workspace.py, preset "thesis"). If even the incenter
is too close to an edge, :class:`PlanningError` names the waypoint and the margin.

With ``fold_shifts`` (default preset) the shift costs no time when it can be folded: the last
body or rotate step is made to end at the point nearest its end where every lift since then,
and this one, has S_m >= threshold + SHIFT_EXTRA_M (else >= threshold;
stability.closest_point_with_margin); the transfers in between keep that CoG. Only when no
such point exists (or there is no body step yet) is a 1-unit shift step inserted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .errors import PlanningError
from .stability import MARGIN_TOLERANCE, closest_point_with_margin, shift_for_margin
from .trajectory import LEGS

#: Durations [time units t_l] (thesis §4.2.1, §4.2.2).
TRANSFER_UNITS = 1.0
BODY_UNITS = 2.0
ROTATE_UNITS = 2.0
SHIFT_UNITS = 1.0
#: A shift aims this far above the threshold [m], so the lift never sits exactly on it.
SHIFT_EXTRA_M = 0.005


@dataclass(frozen=True, eq=False)
class Step:
    """One step of a plan (times in units t_l, positions in the world frame W [m]).

    Attributes:
        kind: "transfer", "body" or "rotate".
        leg: swinging leg name for transfers, else None.
        t_start, t_end: start and end time [units].
        position_base_start_in_world, position_base_end_in_world: CoG (3,) [m].
        yaw_base_start, yaw_base_end: heading of the base x axis [rad].
        foothold_start_in_world, foothold_end_in_world: swing foot (3,) [m], transfers only.
        label: phase label, e.g. "creep transfer RH", "spin rotate", "shift".
        waypoint_index: the waypoint this step works towards (0-based), or None.
        position_feet_in_world: all four feet at the step start (4, 3) [m].
    """

    kind: str
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

    @property
    def duration(self) -> float:
        """t_end - t_start [units]."""
        return self.t_end - self.t_start

    def to_dict(self) -> dict[str, object]:
        """JSON-able dict (lists and floats) for plan.json."""
        def vec(v: np.ndarray | None) -> list[float] | None:
            return None if v is None else [float(x) for x in v]
        return {
            "kind": self.kind, "leg": self.leg, "label": self.label,
            "t_start": float(self.t_start), "t_end": float(self.t_end),
            "position_base_start_in_world": vec(self.position_base_start_in_world),
            "position_base_end_in_world": vec(self.position_base_end_in_world),
            "yaw_base_start": float(self.yaw_base_start),
            "yaw_base_end": float(self.yaw_base_end),
            "foothold_start_in_world": vec(self.foothold_start_in_world),
            "foothold_end_in_world": vec(self.foothold_end_in_world),
            "waypoint_index": self.waypoint_index,
        }


def triangle_margin_xy(a: tuple[float, float], b: tuple[float, float],
                       c: tuple[float, float], p: tuple[float, float]) -> float:
    """S_m of point p in triangle abc (floats, [m]); -inf for a degenerate triangle."""
    area2 = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
    if abs(area2) < 1e-15:
        return -math.inf
    sign = 1.0 if area2 > 0 else -1.0
    m = math.inf
    for u, v in ((a, b), (b, c), (c, a)):
        ex, ey = v[0] - u[0], v[1] - u[1]
        d = sign * (ex * (p[1] - u[1]) - ey * (p[0] - u[0])) / math.hypot(ex, ey)
        m = min(m, d)
    return m


class StepBuilder:
    """Accumulates checked steps from a start pose (see module docstring).

    Attributes:
        t: current time [units]; base: CoG (3,) [m]; yaw: heading [rad];
        feet: feet in W (4, 3) [m]; nominal_base / nominal_yaw: the gait's reference pose
        (the base without stability shifts); threshold: minimum S_m on a lift [m].
    """

    def __init__(self, position_base_in_world: np.ndarray, yaw: float,
                 position_feet_in_world: np.ndarray, threshold: float, *,
                 fold_shifts: bool = False) -> None:
        self.t = 0.0
        self.base = np.array(position_base_in_world, dtype=float)
        self.yaw = float(yaw)
        self.feet = np.array(position_feet_in_world, dtype=float)
        self.nominal_base = self.base.copy()
        self.nominal_yaw = self.yaw
        self.threshold = float(threshold)
        self.steps: list[Step] = []
        self.waypoint_index: int | None = None
        self.waypoint: tuple[float, float] | None = None
        self.n_shifts = 0
        self.fold_shifts = bool(fold_shifts)
        self.n_folded = 0

    def error(self, reason: str) -> PlanningError:
        """A :class:`PlanningError` naming the current waypoint."""
        return PlanningError(reason, self.waypoint_index, self.waypoint)

    def _append(self, kind: str, leg: int | None, duration: float, base_end: np.ndarray,
                yaw_end: float, foot_end: np.ndarray | None, label: str) -> None:
        self.steps.append(Step(
            kind=kind, leg=None if leg is None else LEGS[leg], t_start=self.t,
            t_end=self.t + duration, position_base_start_in_world=self.base.copy(),
            position_base_end_in_world=np.array(base_end, dtype=float),
            yaw_base_start=self.yaw, yaw_base_end=float(yaw_end),
            foothold_start_in_world=None if leg is None else self.feet[leg].copy(),
            foothold_end_in_world=None if foot_end is None else np.array(foot_end, float),
            label=label, waypoint_index=self.waypoint_index,
            position_feet_in_world=self.feet.copy()))
        self.t += duration
        self.base = np.array(base_end, dtype=float)
        self.yaw = float(yaw_end)
        if leg is not None and foot_end is not None:
            self.feet[leg] = foot_end

    def lift_margin(self, leg: int) -> float:
        """S_m of the three other feet with the CoG where it is now [m]."""
        a, b, c = (tuple(self.feet[k, :2]) for k in range(4) if k != leg)
        return triangle_margin_xy(a, b, c, (self.base[0], self.base[1]))

    def transfer(self, leg: int, target_in_world: np.ndarray, label: str) -> None:
        """Swing ``leg`` to ``target_in_world`` (3,) [m], shifting the CoG first if needed
        (folded into the last body phase when ``fold_shifts`` and possible, :meth:`_fold`)."""
        if self.lift_margin(leg) < self.threshold - MARGIN_TOLERANCE and not (
                self.fold_shifts and self._fold(leg)):
            support = np.array([self.feet[k, :2] for k in range(4) if k != leg])
            target = self.threshold + SHIFT_EXTRA_M
            cog = shift_for_margin(support, self.base[:2], target)
            if cog is None:
                cog = shift_for_margin(support, self.base[:2], self.threshold)
            if cog is None:
                raise self.error(
                    f"no stable lift of leg {LEGS[leg]} ({label}): the support triangle of the "
                    f"other feet has no point with margin >= {self.threshold:.4g} m")
            self.body(np.array([cog[0], cog[1], self.base[2]]), self.yaw, SHIFT_UNITS,
                      "body", "shift")
            self.n_shifts += 1
        self._append("transfer", leg, TRANSFER_UNITS, self.base, self.yaw,
                     np.asarray(target_in_world, dtype=float), label)

    def lift_group(self) -> tuple[tuple[tuple[float, float], ...], ...] | None:
        """Support triangles ((x, y) of the three stance feet [m]) of the lifts since the
        last body or rotate step, oldest first; None when there is no such step yet."""
        last = next((i for i in range(len(self.steps) - 1, -1, -1)
                     if self.steps[i].kind != "transfer"), None)
        if last is None:
            return None
        legs = ("LF", "RF", "LH", "RH")
        return tuple(
            tuple((float(f[k, 0]), float(f[k, 1])) for k in range(4) if k != legs.index(s.leg))
            for s in self.steps[last + 1:] for f in (s.position_feet_in_world,)
            if s.leg is not None and f is not None)

    def _fold(self, leg: int) -> bool:
        """Move the end of the last body (or rotate) step, and the CoG of the transfers since,
        to the point nearest it with S_m >= threshold + SHIFT_EXTRA_M (else >= threshold) for
        every lift since that step and for lifting ``leg`` now; False (nothing changed) when
        there is no body step yet or no such point. The body phase then does the shift: no
        extra step, no extra time."""
        last = next((i for i in range(len(self.steps) - 1, -1, -1)
                     if self.steps[i].kind != "transfer"), None)
        if last is None:
            return False
        legs = ("LF", "RF", "LH", "RH")
        lifts = [(legs.index(s.leg), s.position_feet_in_world) for s in self.steps[last + 1:]
                 if s.leg is not None and s.position_feet_in_world is not None]
        lifts.append((leg, self.feet))
        triangles = [tuple((float(f[k, 0]), float(f[k, 1])) for k in range(4) if k != j)
                     for j, f in lifts]
        start = (float(self.base[0]), float(self.base[1]))
        cog = closest_point_with_margin(triangles, start, self.threshold + SHIFT_EXTRA_M)
        if cog is None:
            cog = closest_point_with_margin(triangles, start, self.threshold)
        if cog is None:
            return False
        new = np.array([cog[0], cog[1], self.base[2]])
        self.steps[last] = replace(self.steps[last], position_base_end_in_world=new.copy())
        for i in range(last + 1, len(self.steps)):
            self.steps[i] = replace(self.steps[i], position_base_start_in_world=new.copy(),
                                    position_base_end_in_world=new.copy())
        self.base = new
        self.n_folded += 1
        return True

    def body(self, base_end: np.ndarray, yaw_end: float, duration: float, kind: str,
             label: str) -> None:
        """A four-foot body step (kind "body" or "rotate") to the given pose."""
        self._append(kind, None, duration, base_end, yaw_end, None, label)
