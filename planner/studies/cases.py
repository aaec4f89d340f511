"""The thesis's case studies (Chapter 6) as data, and a runner that plans them.

Paths (world frame W, REP-103, the robot starts at (0, 0) facing +y, heading 90 deg, as in
the thesis whose robot starts facing its own +y):

- straight (Table 6.1): waypoints (0,1) (1,1) (0,2) (0,3); 4.41 m from the start.
- circle (Table 6.2): radius 1 m, 6.28 m long. The thesis gives neither the centre nor the
  sampling. Decision: the circle passes through the start, tangent to the start heading,
  centred at (-1, 0) (counter-clockwise). Why: the thesis's circle is 6.28 m long from the
  start, so the start lies on it; its first spin is "less than ten degrees" (Fig 6.15), so the
  start heading is the tangent; and its spin leg order 1-3-4-2 is the reverse of the
  straight path's 1-2-4-3 (a clockwise first turn), so the circle turns the other way.
  Sampling: CIRCLE_WAYPOINT_COUNT = 32 points every 11.25 deg, the last one back at the
  start; chords of 0.196 m, heading change 11.25 deg per waypoint (5.6 deg at the first
  one). Why 32: the thesis gives no sampling, and the time of its planner depends on it
  (every waypoint off the body's axis costs a spin, §5.5). With §5.5 as written (the
  ``thesis`` preset), 31 or 32 waypoints reproduce Table 6.2 within 3 % in time and 0.01 m
  in E_n at all three heights; every other count from 16 to 72 misses by more than 3 % at
  one height or more (36 points: +14 % at h = 0.2 m). docs/results.md gives the numbers.
- circle with reduced accuracy (Table 6.3): the same circle with tolerance 0.15 m.
- each at h = 0.2, 0.4, 0.6 m and for both workspace presets ("thesis", "default").

The ditch crossing of Fig 6.30 is in planner/studies/ditch.py.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from planner import presets as preset_registry
from silo4kin.errors import Silo4Error

#: Body heights of Chapter 6 [m].
THESIS_HEIGHTS_M: tuple[float, ...] = (0.2, 0.4, 0.6)
#: Workspace presets every case is run with (the registry, planner/presets.py).
PRESETS: tuple[str, ...] = tuple(preset_registry.PRESETS)  # thesis first
#: The thesis's reduced-accuracy run (§6.3, Table 6.3) [m].
REDUCED_TOLERANCE_M = 0.15
#: Start heading of every case: facing world +y [rad].
START_HEADING_RAD = math.pi / 2

STRAIGHT_WAYPOINTS_IN_WORLD = np.array([[0.0, 1.0], [1.0, 1.0], [0.0, 2.0], [0.0, 3.0]])
CIRCLE_RADIUS_M = 1.0
CIRCLE_CENTRE_IN_WORLD = np.array([-1.0, 0.0])
CIRCLE_WAYPOINT_COUNT = 32


def circle_waypoints(
    radius_m: float = CIRCLE_RADIUS_M,
    count: int = CIRCLE_WAYPOINT_COUNT,
    centre_in_world: Iterable[float] = tuple(CIRCLE_CENTRE_IN_WORLD),
) -> np.ndarray:
    """Waypoints on a circle through the start (0, 0), counter-clockwise, shape (count, 2) [m].

    Point k (k = 1..count) sits at angle 2 pi k / count from the start, seen from the centre;
    the last waypoint is the start itself.
    """
    centre = np.asarray(tuple(centre_in_world), dtype=float)
    angle_start = math.atan2(-centre[1], -centre[0])
    angles = angle_start + 2.0 * np.pi * np.arange(1, count + 1) / count
    points = centre + radius_m * np.column_stack([np.cos(angles), np.sin(angles)])
    points[-1] = (0.0, 0.0)  # exactly back at the start, not 1e-16 off
    return points


@dataclass(frozen=True)
class ThesisRow:
    """One column of thesis Tables 6.1-6.3 (printed values, 2-3 significant digits)."""

    time_units: float
    distance_m: float
    average_speed: float  # [m / time unit]
    normalized_error_m: float  # eq 6.1


#: Published numbers, keyed by (path, height [m]) (thesis Tables 6.1, 6.2, 6.3).
THESIS_TABLES: Mapping[tuple[str, float], ThesisRow] = {
    ("straight", 0.2): ThesisRow(132, 4.54, 0.034, 0.11),
    ("straight", 0.4): ThesisRow(140, 4.33, 0.031, 0.04),
    ("straight", 0.6): ThesisRow(246, 4.36, 0.018, 0.03),
    ("circle", 0.2): ThesisRow(418, 6.06, 0.014, 0.10),
    ("circle", 0.4): ThesisRow(462, 6.32, 0.014, 0.09),
    ("circle", 0.6): ThesisRow(618, 6.13, 0.010, 0.04),
    ("circle-reduced", 0.2): ThesisRow(252, 5.68, 0.023, 0.24),
    ("circle-reduced", 0.4): ThesisRow(266, 5.99, 0.023, 0.16),
    ("circle-reduced", 0.6): ThesisRow(434, 6.13, 0.014, 0.17),
}
#: Which table each path belongs to.
THESIS_TABLE_OF_PATH: Mapping[str, str] = {
    "straight": "6.1",
    "circle": "6.2",
    "circle-reduced": "6.3",
}
#: Strides the thesis used in Chapter 6 [m] (§6 intro).
THESIS_STRIDES_M: Mapping[float, float] = {0.2: 0.3787, 0.4: 0.3328, 0.6: 0.1613}
#: Thesis time counts [time units] (§4.2, §6.5).
THESIS_UNITS_PER_CREEP_CYCLE = 8
THESIS_UNITS_PER_SPIN_CYCLE = 6
THESIS_UNITS_PER_SPIN_TRANSITIONS = 2 + 2


@dataclass(frozen=True)
class PathCase:
    """One planning case.

    Attributes:
        path: "straight", "circle" or "circle-reduced".
        height_m: CoG height [m].
        workspace: workspace preset, "thesis" or "default".
        waypoints_in_world: (K, 2) [m].
        tolerance_m: path-following tolerance [m], None for the planner's default.
        start_heading_rad: heading of the base x axis at the start [rad].
    """

    path: str
    height_m: float
    workspace: str
    waypoints_in_world: np.ndarray = field(repr=False)
    tolerance_m: float | None = None
    start_heading_rad: float = START_HEADING_RAD

    @property
    def name(self) -> str:
        """Folder-safe name, e.g. ``circle-reduced_h0.4_thesis``."""
        return f"{self.path}_h{self.height_m:.1f}_{self.workspace}"

    @property
    def thesis(self) -> ThesisRow | None:
        """The published row for this case, if any."""
        return THESIS_TABLES.get((self.path, self.height_m))


def path_waypoints(path: str) -> tuple[np.ndarray, float | None]:
    """Waypoints (K, 2) [m] and tolerance [m] of a named thesis path."""
    if path == "straight":
        return STRAIGHT_WAYPOINTS_IN_WORLD.copy(), None
    if path == "circle":
        return circle_waypoints(), None
    if path == "circle-reduced":
        return circle_waypoints(), REDUCED_TOLERANCE_M
    raise Silo4Error(f"unknown case path {path!r}; known: straight, circle, circle-reduced")


def thesis_cases(
    paths: Iterable[str] = ("straight", "circle", "circle-reduced"),
    heights_m: Iterable[float] = THESIS_HEIGHTS_M,
    presets: Iterable[str] = PRESETS,
) -> tuple[PathCase, ...]:
    """Every (path, height, preset) combination of Chapter 6, table order."""
    cases = []
    for path in paths:
        waypoints, tolerance = path_waypoints(path)
        for preset in presets:
            for h in heights_m:
                cases.append(PathCase(path, float(h), preset, waypoints, tolerance))
    return tuple(cases)


@dataclass(frozen=True, eq=False)
class CaseResult:
    """A planned case: the plan (planner.path.plan_path.Plan), its metrics and the wall time [s]."""

    case: PathCase
    plan: Any
    metrics: Mapping[str, Any]
    wall_time_s: float


def run_case(
    robot: Any, case: PathCase, *, samples_per_unit: int = 100, unit_time_s: float = 1.0
) -> CaseResult:
    """Plan one case as ``silo4 cases`` does (planner.outputs.pipeline.plan_run: the plan, its
    URDF limits, a violation reported rather than refused, and a run whose motion breaks the
    effort budget planned again) and compute its metrics; ``unit_time_s`` [s] is the
    duration of one time unit t_l."""
    from planner.outputs.pipeline import OnLimitViolation, RunRequest, plan_run

    start = time.perf_counter()
    run = plan_run(
        robot,
        case.waypoints_in_world,
        case.height_m,
        RunRequest(unit_time=unit_time_s, on_limit_violation=OnLimitViolation.REPORT),
        start_heading=case.start_heading_rad,
        workspace=case.workspace,
        tolerance=case.tolerance_m,
        samples_per_unit=samples_per_unit,
    )
    wall = time.perf_counter() - start
    return CaseResult(case, run.plan, run.metrics, wall)


def run_cases(
    robot: Any,
    cases: Iterable[PathCase] | None = None,
    *,
    samples_per_unit: int = 100,
    on_result: Callable[[CaseResult], None] | None = None,
) -> list[CaseResult]:
    """Plan every case in order; ``on_result`` is called after each (progress, writing)."""
    results = []
    for case in thesis_cases() if cases is None else cases:
        result = run_case(robot, case, samples_per_unit=samples_per_unit)
        if on_result is not None:
            on_result(result)
        results.append(result)
    return results
