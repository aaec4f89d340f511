"""The body height that walks a path fastest (thesis §7.2: "a height chosen per path").

The time of a plan is a step function of the height h: the stride λ(h) changes smoothly, but
the creep counts round(d / λ) and the spin counts ceil(|ψ| / ψ_max(h)) jump, so the objective
has flat plateaus and is not unimodal (the thesis preset's stride even jumps at h = 0.39 m,
docs/results.md). Golden section would stop on whichever plateau it happens to bracket, so
the search is a grid:

1. coarse: every COARSE_STEP_M over :func:`~planner.workspace.layout.feasible_height_range`
   (the same range ``silo4 plan`` and ``plan_path`` accept, URDF joint limits included),
   both ends included;
2. refine: every FINE_STEP_M within one coarse step of each of the REFINE_COUNT best coarse
   heights (a plateau narrower than a coarse step is still found if a neighbour is good).

The coarse heights are planned from the middle of the range outwards (the ends, where the
stride or the spin angle shrinks, are rarely the fastest): the order changes only how soon
the bound below is tight, not what is chosen.

Each candidate is planned at SEARCH_SAMPLES_PER_UNIT samples per unit (the time in units does
not depend on the sampling; every step is still checked for stability and reach, and the
samples verified), and the winner is planned again by the caller at full resolution.

A candidate that cannot change the outcome is not built to its end: its gait is told the
time it has to beat (``slower_than``, planner/gaits/base.py NotFaster), the REFINE_COUNT-th
best coarse time while the coarse grid is planned and the best time during the refinement,
and stops at the first step that reaches it, or sooner where a lower bound on the time says
it cannot end below it: a candidate whose gait's bound on its whole plan reaches the time
is not built at all (plan_at_height, base.fewest_units: the least of the bounds of the
gaits "auto" may walk, crawl_duration.py, creep_duration.py, creep_spin_duration.py), and
the crawl and the creeping gait stop at a segment's start, the crawl at each attempt's
start and the creeping gait at each half cycle's, once the time built plus their bound on
the rest of the walk reaches it
(StepBuilder.check_time_limit). A candidate stopped so takes at least that
time, so it would rank after the heights that set the bound (ties are built: the bound is
the next float above the time): the choice, its time, E_n and the refined heights are those
of planning every candidate in full. While fewer than REFINE_COUNT coarse times are known, a
coarse candidate is stopped at PROVISIONAL_FACTOR times the best time so far instead of
being planned in full (a height whose gait falls back to a slow one can take 6x the best:
go2 at 0.28 m, 824 units against 135; the factor lets the heights about as fast as the best
finish at once: SILO4 on (0.5, 0.5) m plans 34 candidates instead of 47). A candidate
stopped at a bound below the final REFINE_COUNT-th coarse time is planned again with that
time as its bound, so the refined heights are the same. Those are planned again one at a
time, best first: the one whose gaits stopped at the least time (NotFaster's value:
Fastest's is the least of its gaits' stops, a lower bound on each one's time) first, since
the time it finishes with is the bound the others are planned again against (go2 with a
factor of 1: 0.3218 m, 151.7 units, before 0.2818 m, whose facing gait walks 870 units);
and a candidate whose gaits stopped at or beyond the new bound is not planned again (a
limit up to that value stops the same gaits at the same steps; not with no bound, where the
gaits are built to where they may be refused). One case is not covered: gait "auto" falls
back to the facing gait only when the crawl and the creep are both refused, and a gait
stopped at the bound is not built to where it might have been refused, so a height where
both would have been refused late and the facing gait would have been faster than the
bound is passed over
(tests/test_speed_cache.py compares both searches; tests/test_height_exact.py compares the
search with the grid written out on its own, every candidate planned in full, on SILO4 and
mantis).
Ranking: least time [units], then least E_n [m], then the lower height; all candidates are
evaluated in a fixed order, so the result is deterministic. A height whose plan is refused
(PlanningError), or whose plan needs more than its preset's effort budget standing still
(torque_headroom x URDF effort; no unit time helps: planner/trajectory/limits.py, HyQ's HAA
joints at some heights), is skipped: the run (planner/outputs/pipeline.py) refuses such a
plan, so the search must not pick it. If every height is refused the lowest height's refusal
is re-raised.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from planner.budget import MAX_HEIGHT_SEARCH_UNITS
from planner.errors import PlannerInputError, PlanningError
from planner.gaits.base import NotFaster
from planner.gaits.combinators import stop_units
from planner.model import as_planning_model
from planner.path.at_height import plan_at_height
from planner.presets import Preset, preset_for
from planner.request import estimate_time_units
from planner.trajectory.clearance import check_ground_clearance
from planner.trajectory.limits import check_static_effort
from planner.workspace.layout import feasible_height_range, workspace_for
from planner.workspace.spin import turn_per_cycle_rad

#: Coarse grid spacing [m]: 2 cm gives 24 plans over SILO4's 0.17-0.63 m.
COARSE_STEP_M = 0.02
#: Fine grid spacing [m] (a quarter of the coarse step).
FINE_STEP_M = 0.005
#: How many of the best coarse heights are refined.
REFINE_COUNT = 2
#: Sampling of the candidate plans [samples per time unit]: enough to verify the samples,
#: ten times cheaper than the default 100.
SEARCH_SAMPLES_PER_UNIT = 10
#: While fewer than REFINE_COUNT coarse times are known, a coarse candidate is stopped at
#: this times the best time so far: one about as fast as it finishes at once instead of
#: being stopped and planned again once the REFINE_COUNT-th time is known (the work only).
PROVISIONAL_FACTOR = 1.25


@dataclass(frozen=True)
class HeightChoice:
    """The outcome of :func:`best_height`.

    Attributes:
        height_m: the chosen CoG height [m].
        time_units: plan time at that height [thesis time units].
        normalized_error_m: E_n at that height [m] (eq 6.1).
        feasible_range_m: (min, max) height searched [m].
        evaluated: (height [m], time [units] or inf when refused or stopped) of every
            candidate, in the order planned, shape (N, 2).
        stopped_m: the candidates stopped once as slow as the bound (module docstring) [m].
    """

    height_m: float
    time_units: float
    normalized_error_m: float
    feasible_range_m: tuple[float, float]
    evaluated: np.ndarray
    stopped_m: tuple[float, ...] = ()

    def to_json(self) -> dict:
        """The record written to plan.json / metrics.json (``height_search``)."""
        finite = np.isfinite(self.evaluated[:, 1])
        return {
            "height_m": self.height_m,
            "time_units": self.time_units,
            "normalized_error_m": self.normalized_error_m,
            "feasible_range_m": list(self.feasible_range_m),
            "method": f"grid {COARSE_STEP_M} m, then {FINE_STEP_M} m around the "
            f"{REFINE_COUNT} best",
            "n_evaluated": int(len(self.evaluated)),
            "n_refused": int((~finite).sum()) - len(self.stopped_m),
            "n_stopped": len(self.stopped_m),
        }


def candidate_count(lo: float, hi: float) -> int:
    """The most heights the search plans over [lo, hi] [m]: the coarse grid and, around each
    of the REFINE_COUNT best, the fine grid of two coarse steps."""
    fine = int(np.floor(2 * COARSE_STEP_M / FINE_STEP_M + 1e-9)) + 1
    return len(_grid(lo, hi, COARSE_STEP_M)) + REFINE_COUNT * fine


def check_search_budget(
    model, waypoints_in_world, lo: float, hi: float, workspace: str | Preset, start_heading: float
) -> None:
    """Refuse a search whose candidates would plan more than MAX_HEIGHT_SEARCH_UNITS time
    units in all, before any is planned, saying what to do instead: the path's estimated
    units (planner/request.py) at every coarse height, plus the refinement's heights at the
    fewest of them."""
    preset = preset_for(workspace).name
    wp = np.asarray(waypoints_in_world, dtype=float).reshape(-1, 2)
    units = []
    for h in _grid(lo, hi, COARSE_STEP_M):
        ws = workspace_for(model.planning_robot, float(h), preset)
        if ws.stride_m > 0:
            units.append(
                estimate_time_units(wp, start_heading, ws.stride_m, turn_per_cycle_rad(ws))
            )
    if not units:
        return
    fine = candidate_count(lo, hi) - len(_grid(lo, hi, COARSE_STEP_M))
    total = float(sum(units) + fine * min(units))
    if total > MAX_HEIGHT_SEARCH_UNITS:
        raise PlannerInputError(
            f"--height auto would plan {candidate_count(lo, hi)} heights of this path, about "
            f"{total:,.0f} time units in all (at most {MAX_HEIGHT_SEARCH_UNITS:,}): give a "
            "height in metres, or split the path"
        )


def _grid(lo: float, hi: float, step: float) -> np.ndarray:
    n = max(1, int(np.floor((hi - lo) / step + 1e-9)))
    heights = lo + step * np.arange(n + 1)
    heights = heights[heights <= hi + 1e-12]
    if hi - heights[-1] > 1e-6:
        heights = np.append(heights, hi)
    return np.round(heights, 6)


def best_height(
    robot,
    waypoints_in_world,
    *,
    workspace: str | Preset = "default",
    on_candidate: Callable[[int, int], object] | None = None,
    **plan_kwargs,
) -> HeightChoice:
    """The height in the preset's feasible range that walks ``waypoints_in_world`` (K, 2) [m]
    in the least time (module docstring). ``plan_kwargs`` go to
    :func:`planner.path.plan_path` (start_heading, tolerance, ...; not samples_per_unit).
    ``on_candidate(done, most)`` is called after each height is planned (progress: ``most``
    is :func:`candidate_count`, the search may plan fewer).

    Raises:
        PlannerInputError: bad waypoints or options (from plan_path).
        PlanningError: no height in the range gives a plan.
    """
    plan_kwargs.pop("samples_per_unit", None)
    model = as_planning_model(robot)
    lo, hi = feasible_height_range(model.planning_robot, preset_for(workspace).name)
    check_search_budget(
        model,
        waypoints_in_world,
        lo,
        hi,
        workspace,
        float(plan_kwargs.get("start_heading", np.pi / 2)),
    )
    scores: dict[float, tuple[float, float]] = {}
    errors: dict[float, PlanningError] = {}
    stopped: list[float] = []
    least: dict[float, float] = {}  # stopped height -> the time its gait stopped at [units]

    def evaluate(h: float, bound_units: float) -> None:
        if h in scores:
            return
        limit = float(np.nextafter(bound_units, np.inf)) if np.isfinite(bound_units) else None
        try:
            plan = plan_at_height(
                model,
                waypoints_in_world,
                h,
                workspace=workspace,
                samples_per_unit=SEARCH_SAMPLES_PER_UNIT,
                slower_than=limit,
                **plan_kwargs,
            )
            check_static_effort(
                model.robot, plan.trajectory, plan.preset.load, plan.preset.torque_headroom
            )
            check_ground_clearance(
                model.robot,
                plan.trajectory,
                plan_kwargs.get("terrain"),
                min_clearance_m=plan.preset.ground_clearance_m,
            )
        except NotFaster as exc:
            scores[h] = (np.inf, np.inf)
            stopped.append(h)
            least[h] = stop_units(exc)
            return
        except PlanningError as exc:
            scores[h] = (np.inf, np.inf)
            errors[h] = exc
            return
        walked_error_m = np.hypot(
            *(plan.position_walked_in_world - plan.waypoints_in_world).T
        )  # eq 6.1
        scores[h] = (float(plan.trajectory.time_units[-1]), float(walked_error_m.mean()))

    def kth_best_units(k: int) -> float:
        """The k-th least finite time planned so far [units] (inf with fewer than k)."""
        times = sorted(t for t, _ in scores.values() if np.isfinite(t))
        return times[k - 1] if len(times) >= k else np.inf

    def evaluate_and_report(h: float, slower_than: float) -> None:
        evaluate(h, slower_than)
        if on_candidate is not None:
            on_candidate(len(scores), most)

    most = candidate_count(lo, hi)
    coarse = _grid(lo, hi, COARSE_STEP_M)
    middle = 0.5 * (lo + hi)
    stopped_at: dict[float, float] = {}  # coarse height -> the bound it was stopped at [units]
    for h in sorted(coarse.tolist(), key=lambda h: (abs(h - middle), h)):
        bound = kth_best_units(REFINE_COUNT)
        if not np.isfinite(bound):
            # provisional: planned again below if too low
            bound = kth_best_units(1) * PROVISIONAL_FACTOR
        evaluate_and_report(float(h), bound)
        if h in stopped:
            stopped_at[float(h)] = bound
    while True:  # a height stopped below the final REFINE_COUNT-th time may rank before it
        again = [h for h, b in stopped_at.items() if b < kth_best_units(REFINE_COUNT)]
        if not again:
            break
        # the one whose gaits stopped soonest first: a time it finishes with stops the others
        h = min(again, key=lambda h: (least[h], h))
        bound = kth_best_units(REFINE_COUNT)
        if np.isfinite(bound) and least[h] >= np.nextafter(bound, np.inf):
            # its gaits stopped at or beyond the new limit: they would stop at the same steps
            # (Fastest's value); with no limit a gait is built to where it might be refused
            stopped_at[h] = bound
            continue
        del scores[h], stopped_at[h], least[h]
        stopped.remove(h)
        evaluate_and_report(h, bound)
        if h in stopped:
            stopped_at[h] = bound
    ranked = sorted(scores, key=lambda h: (*scores[h], h))
    for h0 in ranked[:REFINE_COUNT]:
        if not np.isfinite(scores[h0][0]):
            continue
        for h in _grid(max(lo, h0 - COARSE_STEP_M), min(hi, h0 + COARSE_STEP_M), FINE_STEP_M):
            evaluate_and_report(float(h), kth_best_units(1))
    best = min(scores, key=lambda h: (*scores[h], h))
    if not np.isfinite(scores[best][0]):
        raise errors[min(errors)]  # the lowest height's reason
    return HeightChoice(
        height_m=best,
        time_units=scores[best][0],
        normalized_error_m=scores[best][1],
        feasible_range_m=(lo, hi),
        evaluated=np.array([[h, s[0]] for h, s in scores.items()]),
        stopped_m=tuple(stopped),
    )
