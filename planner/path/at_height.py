"""Planning at one body height: checked inputs -> the preset's gait -> its plan.

:func:`plan_at_height` is what :func:`planner.path.plan_path.plan_path` runs for a fixed
height, and what the height search (planner/path/height.py) runs for every candidate.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from planner.errors import PlannerInputError
from planner.gaits.base import PlanRequest
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
) -> Plan:
    """Plan at one body height ``height`` [m] (a number or a fixed
    :class:`~planner.request.Height`): the inputs checked (planner/request.py), the preset's
    gait for the asked name (planner/gaits/registry.py) walking the request. The arguments are
    :func:`planner.path.plan_path.plan_path`'s, without "auto".

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
    return walker.plan(request, slower_than=slower_than)  # NotFaster at >= slower_than [units]
