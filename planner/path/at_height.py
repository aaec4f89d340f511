"""Planning at one body height: checked inputs -> the preset's gait -> its plan.

:func:`plan_at_height` is what :func:`planner.path.plan_path.plan_path` runs for a fixed
height, and what the height search (planner/path/height.py) runs for every candidate.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from planner.errors import PlannerInputError, PlanningError
from planner.gaits.base import Gait, NotFaster, PlanRequest, fewest_units
from planner.gaits.combinators import Fallback
from planner.gaits.facing import FacingPath
from planner.gaits.first_walk import FirstWalkMemo
from planner.gaits.registry import gait_for
from planner.model import PlanningModel, as_planning_model
from planner.plan import Plan
from planner.presets import Preset, preset_for
from planner.request import (
    DEFAULT_TOLERANCE_M,
    Height,
    as_height,
    check_plan_inputs,
    waypoints_array,
)
from planner.terrain.base import FlatGround, Terrain
from planner.terrain.forbidden import CheckedFootholds
from planner.terrain.terrain_map import gait_terrain
from planner.trajectory.continuity import qdd_jump
from planner.workspace.layout import workspace_for
from silo4kin.robot import Robot


def plan_at_height(
    robot: Robot | PlanningModel,
    waypoints_in_world,
    height: float | Height,
    *,
    start_heading: float = np.pi / 2,
    workspace: str | Preset = "default",
    tolerance: float | None = None,
    samples_per_unit: int = 100,
    unit_time_s: float = 1.0,
    stability_threshold: float | None = None,
    swing_height_m: float | None = None,
    face_path: bool = False,
    gait: str = "auto",
    terrain: Terrain | None = None,
    foothold_check: Callable[[np.ndarray], None] | None = None,
    first_walk_memo: FirstWalkMemo | None = None,
    slower_than: float | None = None,
    strict: bool = False,
) -> Plan:
    """Plan at one body height ``height`` [m] (a number or a fixed
    :class:`~planner.request.Height`): the inputs checked (planner/request.py), the preset's
    gait for the asked name (planner/gaits/registry.py) walking the request. The arguments are
    :func:`planner.path.plan_path.plan_path`'s, without "auto".

    ``strict`` (off by default, see below): no degraded fallback. The preset's default gait
    (gait "auto" of a preset that arrives, Preset.arrives) and the gaits it is made of
    ("creep", "crawl") are held to the tolerance and to a continuous q̈: where the first
    choice finds no stable, reachable step, "auto" faces the path on the quintic profiles
    (``FacingPath(smooth=True)``, planner/gaits/facing.py), not the plain creeping and
    spinning gait (cosine blends); the plan that walked is refused with PlanningError when
    its E_n (eq 6.1, as walked) exceeds the tolerance or its q̈ jumps (measured on the
    samples, planner/trajectory/continuity.py), naming the waypoint or the step (and why
    the first choice did not walk), and where both gaits fail GaitRefused names each
    reason. Gaits asked for by name that the default does not walk ("facing", "plain") and
    the thesis preset (§5.5 misses by design) are not held to it. Off by default because
    facing the path on the quintic profiles still breaks joint limits in spin transfers
    that the cosine blends keep (SILO4 at (-0.75, 0.75), phasmid across its range:
    docs/gaits.md); ``strict=False``: facing (cosine blends) then plain, the tolerance
    warned about in the metrics.

    Raises:
        PlannerInputError: bad waypoints, height, preset, gait or parameters.
        PlanningError: no stable or reachable step for a waypoint (named in the message).
        FootholdRefused: the terrain refused a foothold of every gait tried.
    """
    check_plan_inputs(
        robot,
        waypoints_in_world,
        height,
        start_heading,
        workspace,
        tolerance,
        samples_per_unit,
        unit_time_s,
        stability_threshold,
    )  # planner/request.py
    preset = preset_for(workspace)
    if not isinstance(gait, str):
        raise PlannerInputError(f"gait must be one of {list(preset.gaits)}, got {gait!r}")
    walker = gait_for(preset, gait, face_path=bool(face_path))
    held = strict and holds_strictly(preset, walker)
    if held and isinstance(walker, Fallback):
        # the default's fallback faces the path (quintic profiles, planner/gaits/facing.py),
        # held to the same tolerance and continuous q'' below; not the plain creeping and
        # spinning gait after it (the thesis's cosine blends: q'' jumps at every step)
        walker = Fallback(walker.first, FacingPath(smooth=True), all_reasons=True)
    wp = waypoints_array(waypoints_in_world)
    if foothold_check is not None and not callable(foothold_check):
        raise PlannerInputError(
            f"foothold_check must be a function of a foothold (3,) [m] or "
            f"None, got {type(foothold_check).__name__}"
        )
    ground = FlatGround() if terrain is None else terrain
    if not all(
        callable(getattr(ground, name, None))
        for name in ("height_at", "normal_at", "allows_foothold")
    ):
        raise PlannerInputError(
            f"terrain must be a Terrain (planner/terrain/), got {type(terrain).__name__}"
        )
    ground = gait_terrain(ground)  # a terrain file's map: what the gaits walk, or refused
    if foothold_check is not None:
        ground = CheckedFootholds(foothold_check, ground)
    height_m = as_height(height).fixed_m
    if height_m is None:
        raise PlannerInputError(
            "plan_at_height needs a fixed height [m]; plan_path plans height 'auto'"
        )
    if swing_height_m is not None and (
        isinstance(swing_height_m, bool)
        or not isinstance(swing_height_m, (int, float, np.floating))
        or not 0 < swing_height_m < np.inf
    ):
        raise PlannerInputError(
            f"swing_height_m must be a finite number > 0 [m], got {swing_height_m!r}"
        )
    model = as_planning_model(robot)
    ws = workspace_for(model.planning_robot, height_m, preset.name)
    ws = replace(ws, swing_height_m=preset.swing_height(ws.swing_height_m, swing_height_m))
    request = PlanRequest(
        model=model,
        preset=preset,
        workspace=ws,
        waypoints_in_world=wp,
        start_heading=start_heading,
        tolerance=DEFAULT_TOLERANCE_M if tolerance is None else float(tolerance),
        threshold=ws.stability_threshold_m
        if stability_threshold is None
        else float(stability_threshold),
        samples_per_unit=samples_per_unit,
        unit_time_s=unit_time_s,
        terrain=ground,
        first_walk_memo=first_walk_memo,
    )
    if slower_than is not None:
        bound = fewest_units(walker, request)
        if bound >= slower_than:
            # every plan the gait could make takes at least that long: NotFaster without a
            # step built (a gait refused on the way would end as slow, or refused)
            raise NotFaster(bound)
    plan = walker.plan(request, slower_than=slower_than)  # NotFaster at >= slower_than [units]
    if held:
        check_tolerance(plan)
        check_continuous_qdd(plan)
    return plan


#: The gaits strict planning holds to the tolerance and to a continuous q̈: the default
#: preset's "auto" (named by its first choice, planner/gaits/registry.py) and its parts.
SMOOTH_GAITS = ("crawl", "creep")


def holds_strictly(preset: Preset, walker: Gait) -> bool:
    """Whether strict planning holds ``walker``'s plan to its tolerance and a continuous q̈:
    a preset that arrives (Preset.arrives) walking its default gait or one of its parts
    (:data:`SMOOTH_GAITS`; a Fallback or Fastest named "crawl|creep" by its first choice)."""
    names = set(walker.name.split("|"))
    return bool(preset.arrives) and names <= set(SMOOTH_GAITS)


def check_continuous_qdd(plan: Plan) -> None:
    """PlanningError when the plan's q̈ jumps at a step boundary
    (planner/trajectory/continuity.py), naming the step's waypoint."""
    jump = qdd_jump(plan.trajectory, plan.steps)
    if jump is None:
        return
    k = plan.steps[jump.step_index].waypoint_index
    wp = plan.waypoints_in_world
    at = None if k is None else (float(wp[k, 0]), float(wp[k, 1]))
    raise PlanningError(f"gait {plan.gait}: {jump.reason}{_because(plan)}", k, at)


def _because(plan: Plan) -> str:
    """Why the plan's gait walked and not the one preferred to it ("" if it was the first)."""
    return f" (walked because {plan.fallback_reason})" if plan.fallback_reason else ""


def check_tolerance(plan: Plan) -> None:
    """PlanningError when the plan's E_n (eq 6.1, the mean distance of the CoG as walked
    from each waypoint) [m] exceeds its tolerance, naming the worst waypoint."""
    walked = plan.position_walked_in_world
    if not len(walked):
        return
    errors = np.hypot(*(walked - plan.waypoints_in_world).T)
    if float(errors.mean()) <= plan.tolerance:
        return
    k = int(np.argmax(errors))
    raise PlanningError(
        f"gait {plan.gait} misses its tolerance: E_n {1e3 * errors.mean():.1f} mm > "
        f"{1e3 * plan.tolerance:.0f} mm (waypoint {k} "
        f"({plan.waypoints_in_world[k, 0]:.4g}, {plan.waypoints_in_world[k, 1]:.4g}) m "
        f"missed by {1e3 * errors[k]:.1f} mm){_because(plan)}"
    )
