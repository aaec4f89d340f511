"""The default preset's gaits that keep the body's heading: ``creep``, the omnidirectional
creeping gait (planner/gaits/omni.py), and ``crawl``, the continuous crawl
(planner/gaits/crawl.py), as gaits (planner/gaits/base.py).

Both walk straight to each waypoint, past the ones the line passes within half the
tolerance (waypoint_passing.line_of_sight; E_n is taken where the CoG as walked comes nearest), with
equal steps so the nominal CoG lands on it, 1-unit body phases and quintic profiles (q̈
continuous). The crawl is kept only within the URDF velocity and effort limits at the unit
time and with every shank clear of the ground (sway.MIN_SHANK_SLOPE_RAD): it moves body and
swing leg together, so it may need more speed or torque than the creeping gait.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from planner.errors import GaitRefused, PlanningError
from planner.gaits.base import PlanRequest
from planner.gaits.builder import StepBuilder
from planner.gaits.crawl_duration import crawl_walk_bound
from planner.gaits.crawl_or_creep import CrawlOrCreep
from planner.gaits.creep_duration import WalkBound, creep_walk_bound
from planner.gaits.first_walk import walk_first_segment, workspace_key
from planner.gaits.foothold_replacement import OFFSETS_M, FootholdReplacements
from planner.gaits.omni import omni_to
from planner.gaits.sway import shank_violation
from planner.gaits.walk import Walked, walk_plan
from planner.gaits.waypoint_passing import line_of_sight, nearest_on_segment
from planner.plan import Plan
from planner.trajectory.limits import limit_violation
from planner.workspace.layout import Workspace
from silo4kin.frames import rotation_z

#: walk_to(builder, workspace, target (2,) [m], legs) -> (half cycles, nominal distance [m]).
WalkTo = Callable[[StepBuilder, Workspace, np.ndarray, object], tuple[int, float]]


def walk_without_turning(
    request: PlanRequest,
    name: str,
    b: StepBuilder,
    walked: Walked,
    walk_to: WalkTo,
    crawler: CrawlOrCreep | None,
    bound: WalkBound | None = None,
) -> None:
    """Walk the waypoints by ``walk_to`` (module docstring); ``crawler`` is the CrawlOrCreep
    behind it, or None (its state is memoised with the builder's, planner/gaits/first_walk.py).
    With ``bound`` (the gait's lower bound on a walk's time, planner/gaits/creep_duration.py)
    and a time limit, each segment starts only while the time so far and the bound on the
    rest are below the limit (StepBuilder.check_time_limit)."""
    ws, wp, tol = request.workspace, request.waypoints_in_world, request.tolerance
    legs = request.model.planning_robot.legs
    aim = 0  # the waypoint walked to next
    walked.nominal_distance_m = 0.0
    for k, target in enumerate(wp):
        b.waypoint_index, b.waypoint = k, (float(target[0]), float(target[1]))
        rel = rotation_z(-b.nominal_yaw)[:2, :2] @ (target - b.nominal_base[:2])  # eq 5.30
        dist = float(np.hypot(*rel))
        if k >= aim:
            aim = line_of_sight(wp, k, b.nominal_base[:2], tol)
            t0 = b.t
            if aim > k or dist > tol:
                b.waypoint_index = aim
                b.waypoint = (float(wp[aim, 0]), float(wp[aim, 1]))
                if bound is not None:
                    b.rest_units = partial(bound.rest_units, aim=aim)
                    b.check_time_limit()

                def walk(aim=aim):
                    return walk_to(b, ws, wp[aim], legs)

                # the first segment is the same on many ditch routes (memoised)
                n_half, distance = walk_first_segment(
                    request.first_walk_memo,
                    request.model,
                    (
                        name,
                        workspace_key(ws),
                        request.threshold,
                        float(request.start_heading),
                        aim,
                        wp[aim].tobytes(),
                        b.swing_com is not None,
                    ),
                    b,
                    crawler,
                    walk,
                )
                walked.n_half_cycles += n_half
                walked.nominal_distance_m += distance
            walked.passed.update({i: (t0, b.t) for i in range(k, aim)})
        if k in walked.passed:  # walked past: E_n where it came nearest
            walked.reached.append(nearest_on_segment(wp[k], *walked.passed[k], b))
            walked.t_reached.append(walked.passed[k][0])
            continue
        walked.reached.append(b.nominal_base[:2].copy())
        walked.t_reached.append(b.t)
    if crawler is not None:
        walked.n_crawl_swings = crawler.n_swings


@dataclass(frozen=True)
class OmniCreep:
    """The omnidirectional creeping gait: body still while a leg swings (omni.py). Where
    the samples refuse a swing (its stability or a tibia's clearance), its foothold is
    replaced from the reach set and the walk made again
    (planner/gaits/foothold_replacement.py) before the gait is refused."""

    name: str = "creep"
    label: str = "omnidirectional gait"

    def plan(self, request: PlanRequest, slower_than: float | None = None) -> Plan:
        replacements = FootholdReplacements()
        walk_to = partial(omni_to, replacements=replacements)
        bound = _walk_bound(creep_walk_bound, request) if slower_than is not None else None

        def walk(b: StepBuilder, walked: Walked) -> None:
            walk_without_turning(request, self.name, b, walked, walk_to, None, bound)

        first: PlanningError | None = None
        last: PlanningError | None = None
        legs = request.model.planning_robot.legs
        while True:
            # a replaced foothold changes the first segment: not replayed from a memo
            asked = request if not replacements.offsets else replace(request, first_walk_memo=None)
            try:
                return walk_plan(
                    asked, self.name, walk, fold_shifts=True, smooth=True, slower_than=slower_than
                )
            except PlanningError as exc:
                first, last = first or exc, exc
                if not replacements.replace_at(exc.step_start_units, legs):
                    break
        assert first is not None and last is not None
        if not replacements.walks:
            raise first
        reach_mm = 1e3 * float(np.hypot(*OFFSETS_M.T).max())
        raise PlanningError(
            f"{first.reason}; no foothold within {reach_mm:.0f} mm of the refused one walks "
            f"({replacements.walks} tried, the last: {last})",
            first.waypoint_index,
            first.waypoint,
        )

    def fewest_units(self, request: PlanRequest) -> float:
        """A lower bound [units] on the duration of this gait's plan of ``request``, found
        without building a step (planner/gaits/creep_duration.py)."""
        return _walk_bound(creep_walk_bound, request).total()


@dataclass(frozen=True)
class ContinuousCrawl:
    """The continuous crawl: body moving while a leg swings, a creeping half cycle where it
    finds no step (crawl.py CrawlOrCreep); refused beyond the URDF limits or with a shank
    too flat (module docstring)."""

    name: str = "crawl"
    label: str = "continuous crawl"

    def plan(self, request: PlanRequest, slower_than: float | None = None) -> Plan:
        crawler = CrawlOrCreep()
        bound = _walk_bound(crawl_walk_bound, request) if slower_than is not None else None

        def walk(b: StepBuilder, walked: Walked) -> None:
            walk_without_turning(request, self.name, b, walked, crawler.to, crawler, bound)

        plan = walk_plan(
            request, self.name, walk, fold_shifts=True, smooth=True, slower_than=slower_than
        )
        model = request.model
        violation = shank_violation(model.planning_robot.legs, plan.trajectory) or limit_violation(
            model.robot, plan.trajectory, str(request.preset.load)
        )
        if violation is not None:
            raise GaitRefused(violation)
        return plan

    def fewest_units(self, request: PlanRequest) -> float:
        """A lower bound [units] on the duration of this gait's plan of ``request``, found
        without building a step (planner/gaits/crawl_duration.py)."""
        return _walk_bound(crawl_walk_bound, request).total()


def _walk_bound(make: Callable[..., WalkBound], request: PlanRequest) -> WalkBound:
    """The gait's WalkBound (``make``: creep_walk_bound or crawl_walk_bound) of ``request``."""
    return make(
        request.workspace,
        request.waypoints_in_world,
        float(request.start_heading),
        request.tolerance,
    )
