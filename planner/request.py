"""What ``plan_path`` accepts: argument types and ranges, and the work budget.

:func:`check_plan_inputs` runs first in :func:`planner.path.plan_path`, before any step is
built, so bad input costs nothing and fails with :class:`PlannerInputError` naming the value
(never a numpy TypeError, never a silently truncated complex number).

The work budget bounds one plan: at most MAX_WAYPOINTS waypoints and MAX_TOTAL_SAMPLES
samples. The sample count is estimated in O(K) from the path before planning: creeping
covers a distance d in ``8 d / λ`` time units (thesis §5.5: 8 units per cycle of stride λ,
eq 4.5) and a turn ψ costs ``6 ceil(|ψ| / ψ_max)`` units (β = 5/6 spinning cycles, §4.3);
times ``samples_per_unit``. A far waypoint (``1e9, 0``) is refused in microseconds, with
the numbers and what to do: fewer samples per unit, or split the path into several runs.
Measured (benchmarks/bench_budget.py, SILO4, h = 0.4 m): docs/errors.md "Work budget".
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Any

import numpy as np

from planner.budget import (  # noqa: F401 (re-exported: the limits live in a numpy-free module)
    MAX_COORDINATE_M,
    MAX_SAMPLES_PER_UNIT,
    MAX_TOTAL_SAMPLES,
    MAX_WAYPOINTS,
    UNIT_TIME_RANGE_S,
)
from planner.errors import PlannerInputError
from planner.presets import PRESETS, Preset, preset_for

#: Default lateral / reach tolerance [m]: "distance in x equal to zero" with 1 cm slack.
DEFAULT_TOLERANCE_M = 0.01

#: The height value that asks for the least-time height (planner/path/height.py).
AUTO_HEIGHT = "auto"

_UNITS_PER_CREEP_CYCLE = 8.0  # thesis §4.2: β = 7/8, 8 units per stride λ
_UNITS_PER_SPIN_CYCLE = 6.0  # thesis §4.3: β = 5/6, 6 units per spinning cycle


#: Heights above this [m] are taken for centimetres or millimetres typed for metres and
#: refused with a suggestion, before any planning work (no legged robot stands 10 m tall).
MAX_PLAUSIBLE_HEIGHT_M = 10.0
#: A suggestion (the value read as cm or mm) is offered only inside this range [m].
_SUGGESTED_HEIGHT_RANGE_M = (0.05, 3.0)


def check_height_scale(name: str, height_m: float) -> None:
    """Refuse a height above MAX_PLAUSIBLE_HEIGHT_M as a unit slip: ``--height 40`` ->
    "did you mean 0.40 m?" (40 cm), ``400`` -> 0.400 m (mm). Costs nothing: no robot, no
    workspace.

    Raises:
        PlannerInputError: ``height_m`` > MAX_PLAUSIBLE_HEIGHT_M [m].
    """
    if not height_m > MAX_PLAUSIBLE_HEIGHT_M:
        return
    lo, hi = _SUGGESTED_HEIGHT_RANGE_M
    guesses = [
        f"{height_m / scale:.{digits}f} m ({unit})"
        for scale, digits, unit in ((100.0, 2, "cm"), (1000.0, 3, "mm"))
        if lo <= height_m / scale <= hi
    ]
    hint = f": did you mean {' or '.join(guesses)}?" if guesses else ""
    raise PlannerInputError(
        f"{name} {height_m:g} m is not a plausible body height (at most "
        f"{MAX_PLAUSIBLE_HEIGHT_M:g} m){hint} heights are in metres"
    )


def _real(name: str, value: Any, unit: str, *, optional: bool = False) -> float | None:
    """``value`` as a finite float, or PlannerInputError naming it (bools and text refused)."""
    if value is None and optional:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise PlannerInputError(
            f"{name} must be a real number{unit}, got {value!r} ({type(value).__name__})"
        )
    number = float(value)
    if not math.isfinite(number):
        raise PlannerInputError(f"{name} must be a finite number{unit}, got {value!r}")
    return number


@dataclass(frozen=True)
class Height:
    """The body CoG height above the ground a plan walks at: ``fixed_m`` [m], or None for
    "auto" (the height of the feasible range that walks the path in the least time,
    planner/path/height.py)."""

    fixed_m: float | None

    @classmethod
    def fixed(cls, height_m: float) -> Height:
        """A fixed height [m] (range-checked against the preset's workspace when planned)."""
        value = _real("height", height_m, " [m]")
        check_height_scale("height", value)  # type: ignore[arg-type]
        return cls(value)

    @classmethod
    def auto(cls) -> Height:
        """The least-time height."""
        return cls(None)

    @property
    def is_auto(self) -> bool:
        return self.fixed_m is None

    def __str__(self) -> str:
        return AUTO_HEIGHT if self.fixed_m is None else f"{self.fixed_m:g} m"


def as_height(height: Any) -> Height:
    """``height`` (a number [m], "auto" or a :class:`Height`) as a Height; PlannerInputError
    for anything else."""
    if isinstance(height, Height):
        return height if height.fixed_m is None else Height.fixed(height.fixed_m)
    if isinstance(height, str):
        if height == AUTO_HEIGHT:
            return Height.auto()
        raise PlannerInputError(f"height must be a number [m] or 'auto', got {height[:40]!r}")
    return Height.fixed(height)


def waypoints_array(waypoints_in_world: Any) -> np.ndarray:
    """Waypoints as a (K, 2) float array [m]; refuses text, None, complex and ragged input."""
    try:
        wp = np.asarray(waypoints_in_world)
    except (TypeError, ValueError) as exc:  # ragged nesting, unconvertible objects
        raise PlannerInputError(f"waypoints must be numbers, shape (K, 2): {exc}") from None
    if wp.dtype.kind not in "iuf":
        what = {"c": "complex numbers", "b": "booleans", "U": "text", "S": "bytes"}.get(
            wp.dtype.kind, f"{wp.dtype} values"
        )
        raise PlannerInputError(f"waypoints must be real numbers [m], shape (K, 2); got {what}")
    wp = wp.astype(float)
    if wp.ndim == 1 and wp.size == 2:
        wp = wp[None]
    if wp.ndim != 2 or wp.shape[1] != 2 or wp.shape[0] < 1:
        raise PlannerInputError(f"waypoints must have shape (K, 2) with K >= 1, got {wp.shape}")
    if wp.shape[0] > MAX_WAYPOINTS:
        raise PlannerInputError(
            f"{wp.shape[0]} waypoints exceed the budget of {MAX_WAYPOINTS} per plan; "
            "split the path into several runs"
        )
    bad = np.flatnonzero(~np.all(np.isfinite(wp), axis=1))
    if bad.size:
        raise PlannerInputError(f"waypoint {bad[0]} is not finite: {wp[bad[0]].tolist()}")
    far = np.flatnonzero(np.any(np.abs(wp) > MAX_COORDINATE_M, axis=1))
    if far.size:
        raise PlannerInputError(
            f"waypoint {far[0]} {wp[far[0]].tolist()} is more than "
            f"{MAX_COORDINATE_M:g} m away; split the path into several runs"
        )
    return wp


def estimate_time_units(
    waypoints_in_world: np.ndarray, start_heading: float, stride_m: float, psi_max_rad: float
) -> float:
    """Time units t_l to walk from (0, 0) through the waypoints (module docstring): creeping
    ``8 d / λ`` per path leg plus ``6 ceil(|ψ| / ψ_max)`` per turn ψ between path legs."""
    points = np.vstack([np.zeros((1, 2)), waypoints_in_world])
    legs = np.diff(points, axis=0)
    lengths = np.hypot(legs[:, 0], legs[:, 1])
    creep = _UNITS_PER_CREEP_CYCLE * float(lengths.sum()) / stride_m
    moving = legs[lengths > 0]
    headings = np.concatenate([[start_heading], np.arctan2(moving[:, 1], moving[:, 0])])
    turns = np.abs((np.diff(headings) + np.pi) % (2.0 * np.pi) - np.pi)
    cycles = np.ceil(turns / psi_max_rad - 1e-12).sum() if psi_max_rad > 0 else 0.0  # no spin
    spin = _UNITS_PER_SPIN_CYCLE * float(cycles)
    return creep + spin


def check_work_budget(
    n_samples: float, samples_per_unit: int, units: float, distance_m: float
) -> None:
    """Refuse a plan estimated above MAX_TOTAL_SAMPLES, saying how to make it fit."""
    if n_samples <= MAX_TOTAL_SAMPLES:
        return
    fit = int(MAX_TOTAL_SAMPLES // max(units, 1.0))
    advice = (
        f"use at most {fit} samples per unit" if fit >= 1 else "even 1 sample per unit is too many"
    )
    raise PlannerInputError(
        f"the path ({distance_m:.4g} m of waypoints, about {units:.4g} time units) needs about "
        f"{n_samples:.3g} samples at {samples_per_unit} per unit, over the budget of "
        f"{MAX_TOTAL_SAMPLES:,} per plan: {advice}, or split the path into several runs"
    )


def check_plan_inputs(
    robot: Any,
    waypoints_in_world: Any,
    height: Any,
    start_heading: Any,
    workspace: Any,
    tolerance: Any,
    samples_per_unit: Any,
    unit_time_s: Any,
    stability_threshold: Any,
) -> None:
    """Validate every argument of ``plan_path`` and the work budget (module docstring).

    Raises:
        PlannerInputError: a value of the wrong type or out of range (named, with what is
            allowed), or a plan over the work budget.
    """
    from planner.model import as_planning_model
    from planner.workspace.layout import workspace_for
    from planner.workspace.spin import turn_per_cycle_rad
    from silo4kin.robot import Robot

    if isinstance(robot, Robot):
        planning_robot = as_planning_model(robot).planning_robot
    elif isinstance(getattr(robot, "planning_robot", None), Robot):
        planning_robot = robot.planning_robot  # a planning model that owns the frame already
    else:
        raise PlannerInputError(
            f"robot must be a silo4kin Robot (silo4kin.load_robot()), got {type(robot).__name__}"
        )
    wp = waypoints_array(waypoints_in_world)
    h = as_height(height).fixed_m  # None: "auto" (planner/path/height.py)
    heading = _real("start_heading", start_heading, " [rad]")
    if not isinstance(workspace, (str, Preset)):
        raise PlannerInputError(
            f"workspace must be a preset name {list(PRESETS)} or a Preset, got {workspace!r}"
        )
    preset = preset_for(workspace).name
    for name, value in (("tolerance", tolerance), ("stability_threshold", stability_threshold)):
        v = _real(name, value, " [m]", optional=True)
        if v is not None and not 0.0 <= v <= MAX_COORDINATE_M:
            raise PlannerInputError(f"{name} must be in [0, {MAX_COORDINATE_M:g}] m, got {v!r}")
    if (
        isinstance(samples_per_unit, (bool, np.bool_))
        or not isinstance(samples_per_unit, numbers.Integral)
        or not 1 <= int(samples_per_unit) <= MAX_SAMPLES_PER_UNIT
    ):
        raise PlannerInputError(
            f"samples_per_unit must be an integer in [1, "
            f"{MAX_SAMPLES_PER_UNIT}], got {samples_per_unit!r}"
        )
    t = _real("unit_time_s", unit_time_s, " [s]")
    lo, hi = UNIT_TIME_RANGE_S
    if not lo <= t <= hi:  # type: ignore[operator]
        raise PlannerInputError(f"unit_time_s must be in [{lo:g}, {hi:g}] s, got {unit_time_s!r}")

    if h is None:  # "auto": the budget at the lowest feasible height (shortest stride)
        from planner.workspace.layout import feasible_height_range

        h = feasible_height_range(planning_robot, preset)[0]
    ws = workspace_for(planning_robot, h, preset)  # range-checks h
    if not ws.stride_m > 0.0:  # e.g. HyQ near the bottom of its range: no budget to estimate
        from planner.errors import PlanningError

        raise PlanningError(
            f"at h = {h:g} m the {preset} workspace leaves no stride "
            f"(stride {ws.stride_m:g} m): choose another height"
        )
    units = estimate_time_units(wp, heading, ws.stride_m, turn_per_cycle_rad(ws))  # type: ignore[arg-type]
    distance = float(np.hypot(*np.diff(np.vstack([[0.0, 0.0], wp]), axis=0).T).sum())
    check_work_budget(units * int(samples_per_unit) + 1, int(samples_per_unit), units, distance)
