"""The ditch crossing of Fig 6.30 (§6.4): a straight ditch across the path (the strip y_near
<= y <= y_near + width in W, all x), crossed walking +y with no foothold inside it (nor
closer than the foot radius to its edges). The creeping gait puts the front feet of the two
sides lambda/2 apart and the rear feet likewise, so the footholds near the ditch form two
lattices of period lambda/2: a ditch is crossable only if it is narrower than lambda/2
(thesis: "less than lambda/2"), and only if the lattices fall on both sides of it. Walking
straight across, SILO4's widest gap is 0.139 m (thesis preset) / 0.131 m (default), so even
the thesis's 0.15 m ditch is not crossable head-on. The ditch is a terrain that forbids its
strip (:meth:`Ditch.terrain`, planner/terrain/forbidden.py): the planner refuses a gait at
its first foothold in it, and this module routes the approach: crossing angles up to ±30 deg
to the ditch normal (CROSSING_ANGLES_DEG) with the approach shifted sideways up to ±0.4 m
(APPROACH_OFFSETS_M); at 15 deg the four feet's lattices line up and open ~0.30 m gaps. A
ditch as wide as the stride λ (plus the clearance) is refused outright, naming λ; a narrower
one that no tried route clears is refused with a DitchNotCrossableError. What the planner
would need to do this without a route search: footholds placed around the forbidden region
and a shortened last stride (a fractional cycle) before the obstacle.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any

import numpy as np

from planner.budget import MAX_COORDINATE_M
from planner.gaits.first_walk import FirstWalkMemo
from planner.studies.cases import PRESETS, START_HEADING_RAD
from planner.terrain.forbidden import ForbiddenPolygons
from silo4kin.errors import Silo4Error

#: Fig 6.30: body height [m] and ditch width [m].
DITCH_HEIGHT_M = 0.3
DITCH_WIDTH_M = 0.15
#: Where our ditch starts along +y [m] (the thesis does not say).
DITCH_NEAR_EDGE_M = 1.5
#: Safety distance of a foothold (the foot sphere's ground contact point, below its centre)
#: from the ditch edge [m].
FOOT_CLEARANCE_M = 0.01
#: The approach ends this far before the ditch [m]: the front feet reach ~0.5 m ahead.
APPROACH_BEFORE_DITCH_M = 0.6
#: Crossing angles to the ditch normal [deg], tried in this order: straight across first.
CROSSING_ANGLES_DEG: tuple[float, ...] = (
    0.0,
    15.0,
    -15.0,
    10.0,
    -10.0,
    20.0,
    -20.0,
    5.0,
    -5.0,
    25.0,
    -25.0,
    30.0,
    -30.0,
)
#: Lateral offsets of the approach waypoint [m] (shift where the foothold lattice falls).
APPROACH_OFFSETS_M: tuple[float, ...] = (0.0,) + tuple(
    s * k * 0.05 for k in range(1, 9) for s in (1.0, -1.0)
)
#: Samples per unit while searching routes (only the footholds matter there).
ROUTE_SEARCH_SAMPLES_PER_UNIT = 1


class DitchNotCrossableError(Silo4Error):
    """A ditch that the creeping gait cannot cross without a foothold inside it."""


@dataclass(frozen=True)
class Ditch:
    """A ditch across the path: the strip y_near_m <= y <= y_near_m + width_m of W (all x)."""

    y_near_m: float
    width_m: float

    @property
    def y_far_m(self) -> float:
        return self.y_near_m + self.width_m

    def terrain(self, foot_clearance_m: float = 0.0) -> ForbiddenPolygons:
        """Flat ground without a foothold in the strip or nearer than ``foot_clearance_m``
        [m] to its edges (the strip as a rectangle 20 MAX_COORDINATE_M long in x)."""
        x = 10.0 * MAX_COORDINATE_M
        strip = np.array(
            [[-x, self.y_near_m], [x, self.y_near_m], [x, self.y_far_m], [-x, self.y_far_m]]
        )
        return ForbiddenPolygons((strip,), clearance_m=foot_clearance_m)

    def clearance(self, points_in_world: np.ndarray) -> np.ndarray:
        """Distance of points (M, 2) [m] to the strip, negative inside, shape (M,)."""
        y = np.asarray(points_in_world, dtype=float)[:, 1]
        return np.maximum(self.y_near_m - y, y - self.y_far_m)


def footholds_in_world(trajectory: Any) -> np.ndarray:
    """Every distinct foot position in contact with the ground (x, y) [m], shape (M, 2)."""
    feet = trajectory.position_foot_in_world[:, :, :2][trajectory.contact]
    return np.unique(np.round(feet, 9), axis=0)


@dataclass(frozen=True, eq=False)
class DitchOutcome:
    """Result of a ditch case: crossed (plan, route, footholds) or refused (reason)."""

    ditch: Ditch
    height_m: float
    workspace: str
    stride_m: float
    crossed: bool
    reason: str = ""
    route_in_world: np.ndarray | None = None
    crossing_angle_deg: float | None = None
    plan: Any = None
    footholds_in_world: np.ndarray | None = None
    clearance_m: float | None = None
    routes_tried: int = 0
    straight_gap_m: float | None = None

    def summary(self) -> str:
        """One line for the console and the results page."""
        gap = (
            ""
            if self.straight_gap_m is None
            else f", widest foothold gap walking straight across {self.straight_gap_m:.3f} m"
        )
        head = (
            f"ditch {self.ditch.width_m:.3f} m wide, h = {self.height_m:g} m, "
            f"`{self.workspace}` (lambda = {self.stride_m:.3f} m, lambda/2 = "
            f"{self.stride_m / 2:.3f} m{gap}): "
        )
        if not self.crossed or self.route_in_world is None or self.footholds_in_world is None:
            return head + "refused: " + self.reason
        route = " ".join(f"({x:.2f}, {y:.2f})" for x, y in self.route_in_world)
        return (
            head + f"crossed at {self.crossing_angle_deg:g} deg to the ditch normal via "
            f"{route} (route {self.routes_tried} tried); {len(self.footholds_in_world)} "
            f"footholds, nearest {self.clearance_m:.3f} m from an edge"
        )


def _stride(robot: Any, height_m: float, workspace: str) -> float:
    from planner.workspace.layout import workspace_for

    return float(workspace_for(robot, height_m, workspace).stride_m)


def _candidate_routes(ditch: Ditch, stride: float) -> list[tuple[float, np.ndarray]]:
    """(crossing angle [deg], waypoints (2, 2) [m]): approach point, then across."""
    approach_y = ditch.y_near_m - APPROACH_BEFORE_DITCH_M
    beyond = ditch.y_far_m + APPROACH_BEFORE_DITCH_M + stride - approach_y
    routes = []
    for angle in CROSSING_ANGLES_DEG:
        a = math.radians(angle)
        for offset in APPROACH_OFFSETS_M:
            goal = (offset - beyond * math.tan(a), approach_y + beyond)
            routes.append((angle, np.array([[offset, approach_y], goal])))
    return routes


def straight_foothold_gap(robot: Any, height_m: float, workspace: str) -> float:
    """Widest gap between successive footholds along a long straight creep [m].

    A ditch straight across the path must fit in such a gap. With the thesis's footholds the
    front feet of both sides form a lattice of period lambda/2 and so do the rear feet,
    offset by (front-rear hip distance) mod lambda/2, so the gap is below lambda/2.
    """
    return _straight_foothold_gap(robot, float(height_m), workspace)


@lru_cache(maxsize=32)
def _straight_foothold_gap(robot: Any, height_m: float, workspace: str) -> float:
    """straight_foothold_gap, planned once per (robot, height, preset): plan_ditch_cases asks
    for it for each of its three ditches."""
    from planner.path.plan_path import plan_path

    plan = plan_path(
        robot,
        np.array([[0.0, 4.0]]),
        height_m,
        start_heading=START_HEADING_RAD,
        workspace=workspace,
        samples_per_unit=ROUTE_SEARCH_SAMPLES_PER_UNIT,
    )
    y = np.unique(footholds_in_world(plan.trajectory)[:, 1])
    steady = y[(y > 1.0) & (y < 3.0)]  # away from the start and end stances
    return float(np.max(np.diff(steady)))


def _route_clears(trajectory: Any, ditch: Ditch, foot_clearance_m: float) -> bool:
    footholds = footholds_in_world(trajectory)
    across = trajectory.position_foot_in_world[-1, :, 1] > ditch.y_far_m
    return bool(np.min(ditch.clearance(footholds)) >= foot_clearance_m and np.all(across))


def plan_ditch_crossing(
    robot: Any,
    ditch: Ditch,
    height_m: float = DITCH_HEIGHT_M,
    *,
    workspace: str = "default",
    samples_per_unit: int = 100,
    foot_clearance_m: float = FOOT_CLEARANCE_M,
    first_walk_memo: FirstWalkMemo | None = None,
) -> DitchOutcome:
    """Plan a crossing of ``ditch`` from (0, 0) heading +y; refuse if it cannot be done.

    Tries the routes of :func:`_candidate_routes` in order (straight across first) and keeps
    the first whose footholds all stay ``foot_clearance_m`` outside the strip and whose final
    stance is entirely across. Every foothold is checked as it is placed (the ditch's
    terrain, :meth:`Ditch.terrain`): a gait is abandoned at its first foothold in the
    strip (the rest of its plan is not built; gait "auto" then tries the creeping gait),
    except in the crawl, which undoes the swing that placed it and walks a creeping half
    cycle from there (so a refused route costs a fraction of a finished one, and the crawl
    crosses ditches it could not cross if only its finished attempts were checked). The
    final stance is checked on the finished plan. The routes share their first walked
    segment through ``first_walk_memo`` (a new one when None).

    Raises:
        DitchNotCrossableError: the ditch (plus the clearance on both edges) is not narrower
            than the stride lambda (no leg can step over it), or no tried route clears it.
    """
    from planner.path.plan_path import plan_path

    stride = _stride(robot, height_m, workspace)
    needed = ditch.width_m + 2.0 * foot_clearance_m
    where = f"at h = {height_m:g} m with the {workspace!r} workspace"
    if needed >= stride:
        raise DitchNotCrossableError(
            f"ditch {ditch.width_m:.3f} m wide (+ {foot_clearance_m} m clearance on each edge "
            f"= {needed:.3f} m) is not narrower than the stride lambda = {stride:.3f} m {where}:"
            " no leg can step over it"
        )
    routes = _candidate_routes(ditch, stride)
    terrain = ditch.terrain(foot_clearance_m)
    memo = FirstWalkMemo() if first_walk_memo is None else first_walk_memo

    def plan_checked(route: np.ndarray, samples: int) -> Any:
        """The route's plan on the ditch terrain, or None when refused or not clearing it."""
        try:
            plan = plan_path(
                robot,
                route,
                height_m,
                start_heading=START_HEADING_RAD,
                workspace=workspace,
                samples_per_unit=samples,
                terrain=terrain,
                first_walk_memo=memo,
            )
        except Silo4Error:  # FootholdRefused, PlanningError
            return None
        return plan if _route_clears(plan.trajectory, ditch, foot_clearance_m) else None

    for tried, (angle, route) in enumerate(routes, start=1):
        # the trial is cheap (few samples); the returned plan is planned on the ditch
        # again: the terrain may rule out a faster gait (the crawl) on this route, and the
        # plan we return must be the one that was checked
        if plan_checked(route, ROUTE_SEARCH_SAMPLES_PER_UNIT) is not None:
            plan = plan_checked(route, samples_per_unit)
            if plan is None:
                continue
            footholds = footholds_in_world(plan.trajectory)
            return DitchOutcome(
                ditch,
                height_m,
                workspace,
                stride,
                True,
                "",
                route,
                angle,
                plan,
                footholds,
                float(np.min(ditch.clearance(footholds))),
                tried,
            )
    raise DitchNotCrossableError(
        f"ditch {ditch.width_m:.3f} m wide: none of the {len(routes)} tried routes (crossing "
        f"angles {min(CROSSING_ANGLES_DEG):g}..{max(CROSSING_ANGLES_DEG):g} deg, approach "
        f"offsets up to {max(APPROACH_OFFSETS_M):g} m) keeps every foothold "
        f"{foot_clearance_m} m outside it {where}"
    )


def ditch_outcome(
    robot: Any,
    ditch: Ditch,
    height_m: float,
    workspace: str,
    *,
    samples_per_unit: int = 100,
    first_walk_memo: FirstWalkMemo | None = None,
) -> DitchOutcome:
    """Like plan_ditch_crossing, but a refusal becomes an outcome with its reason."""
    gap = straight_foothold_gap(robot, height_m, workspace)
    try:
        outcome = plan_ditch_crossing(
            robot,
            ditch,
            height_m,
            workspace=workspace,
            samples_per_unit=samples_per_unit,
            first_walk_memo=first_walk_memo,
        )
    except DitchNotCrossableError as exc:
        return DitchOutcome(
            ditch,
            height_m,
            workspace,
            _stride(robot, height_m, workspace),
            False,
            str(exc),
            straight_gap_m=gap,
        )
    return replace(outcome, straight_gap_m=gap)


def plan_ditch_cases(
    robot: Any, presets: Iterable[str] = PRESETS, *, samples_per_unit: int = 100
) -> list[DitchOutcome]:
    """Per preset at h = 0.3 m: Fig 6.30's 0.15 m ditch, one 0.25 m wide (wider than
    lambda/2), and one as wide as the stride lambda (refused)."""
    outcomes = []
    memo = FirstWalkMemo()  # the ditches of one height share their approaches
    for preset in presets:
        stride = _stride(robot, DITCH_HEIGHT_M, preset)
        for width in (DITCH_WIDTH_M, 0.25, stride):
            outcomes.append(
                ditch_outcome(
                    robot,
                    Ditch(DITCH_NEAR_EDGE_M, width),
                    DITCH_HEIGHT_M,
                    preset,
                    samples_per_unit=samples_per_unit,
                    first_walk_memo=memo,
                )
            )
    return outcomes
