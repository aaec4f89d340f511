"""Path following (thesis §5.4-5.5): waypoints in W -> checked steps -> dense samples.

:func:`plan_path` checks its inputs (planner/request.py), takes the preset
(planner/presets.py), the gait the preset walks for the asked name (planner/gaits/registry.py)
and lets it plan (planner/gaits/base.py). The robot starts at (0, 0) with the CoG at height h
above the terrain, heading ``start_heading`` (thesis: facing its +y, i.e. π/2 in a REP-103
world), in the forward creeping stance. The gaits (docs/gaits.md):

- ``thesis`` (the thesis preset): §5.5 as written, spin to face each waypoint off the body's
  axis and creep round(d / λ) cycles (planner/gaits/thesis_walk.py);
- ``auto`` (the default preset): the faster of the continuous crawl (``crawl``, insect legs)
  and the omnidirectional creeping gait (``creep``), walking in any direction without
  turning and arriving exactly (planner/gaits/without_turning.py); if neither finds a
  stable, reachable step, ``facing``: facing each segment with crab angles, look-ahead turns
  and folded shifts (planner/gaits/facing.py), and if that fails its checks, ``plain``
  (the creeping and spinning gait in the default workspace). With ``strict=True`` (no
  degraded fallback) facing walks the quintic profiles, no plain follows, and the plan is
  held to the tolerance and a continuous q̈ or refused naming the reason.
  ``Plan.gait`` names the gait that walked and ``Plan.fallback_reason`` why a
  gait preferred to it was not used.

Stability point and swing height come from the preset: the default keeps the whole-robot
CoM (legs included, as they move; planner/model.py) at least the threshold inside the
support triangle at every checked configuration of every swing, and lifts the feet by at
least presets.MIN_SWING_HEIGHT_M; the thesis keeps the body CoG and eq 5.12. Every
trajectory carries both margins (margin_com, margin_body).

``tolerance`` [m] defaults to DEFAULT_TOLERANCE_M; 0.15 m is the reduced-accuracy run of
Table 6.3. Then the samples are verified (IK reachable, joints within limits, no NaN, margin
>= threshold on every lift); any failure raises PlanningError naming the waypoint.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from planner.gaits.first_walk import FirstWalkMemo
from planner.model import PlanningModel, as_planning_model
from planner.path.at_height import plan_at_height
from planner.path.height import best_height
from planner.plan import Plan, SpinRecord
from planner.presets import Preset
from planner.request import (
    DEFAULT_TOLERANCE_M,
    Height,
    as_height,
    check_plan_inputs,
    waypoints_array,
)
from planner.terrain.base import Terrain
from silo4kin.robot import Robot

__all__ = ["DEFAULT_TOLERANCE_M", "Plan", "SpinRecord", "plan_path", "robot_in_body_com_frame"]


def robot_in_body_com_frame(robot: Robot) -> Robot:
    """The robot with its hips measured from the body CoG, the frame B the planner works in
    (planner/model.py); cached per robot object. For SILO4 the URDF root is the CoG and the
    robot is returned unchanged."""
    return as_planning_model(robot).planning_robot


def plan_path(
    robot: Robot | PlanningModel,
    waypoints_in_world,
    height: float | str | Height,
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
    on_height_candidate: Callable[[int, int], object] | None = None,
    strict: bool = False,
) -> Plan:
    """Plan statically stable walking through ``waypoints_in_world`` (K, 2) [m] at CoG height
    ``height`` [m] above the ground (module docstring), or ``height="auto"`` (or a
    :class:`~planner.request.Height`): the height in the feasible range that walks the path
    in the least time (planner/path/height.py, thesis §7.2), recorded in
    ``Plan.height_search``.

    ``workspace``: the preset, by name or as a :class:`~planner.presets.Preset`.
    ``gait``: a gait the preset offers (Preset.gaits; "auto": its default), reported by
    ``Plan.gait`` as it is named here; a gait asked for by name walks or fails with its
    reason. ``face_path`` is gait "facing" (the thesis's habit of facing each segment,
    default preset only). ``swing_height_m`` [m] overrides the preset's swing height
    (default: eq 5.12, at least presets.MIN_SWING_HEIGHT_M for the default preset).
    ``terrain``: the ground (planner/terrain/; default flat ground at z = 0); every foothold
    a step places is asked about as it is placed (a refused one raises FootholdRefused,
    which abandons the gait being built: "auto" tries the other, the continuous crawl
    undoes the swing that placed it and walks a creeping half cycle from there).
    ``foothold_check``: a function of a foothold (3,) in W [m] that raises to refuse it,
    the same as ``terrain=CheckedFootholds(check, terrain)``. ``first_walk_memo``: shared by
    plans that start alike (planner/gaits/first_walk.py; the ditch's route search).
    ``on_height_candidate``: the height search's progress (planner/path/height.py).
    ``strict``: no degraded fallback: the default gait (its first choice or facing the path
    on quintic profiles) walks within the tolerance (E_n) and with q̈ continuous, or
    PlanningError names the waypoint or step and the reason (planner/path/at_height.py;
    off by default: facing's spin transfers on quintic profiles still break joint limits
    the cosine blends keep).

    Raises:
        PlannerInputError: bad waypoints, height, preset, gait or parameters.
        PlanningError: no stable or reachable step for a waypoint (named in the message).
        FootholdRefused: the terrain refused a foothold of every gait tried.
    """
    options: dict[str, Any] = dict(
        start_heading=start_heading,
        workspace=workspace,
        tolerance=tolerance,
        unit_time_s=unit_time_s,
        stability_threshold=stability_threshold,
        swing_height_m=swing_height_m,
        face_path=face_path,
        gait=gait,
        terrain=terrain,
        foothold_check=foothold_check,
        first_walk_memo=first_walk_memo,
        strict=strict,
    )
    requested = as_height(height)
    if requested.fixed_m is not None:
        return plan_at_height(
            robot, waypoints_in_world, requested, samples_per_unit=samples_per_unit, **options
        )
    # "auto": the inputs and the work budget checked once, then the least-time height
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
    )
    wp = waypoints_array(waypoints_in_world)
    choice = best_height(robot, wp, on_candidate=on_height_candidate, **options)
    plan = plan_at_height(robot, wp, choice.height_m, samples_per_unit=samples_per_unit, **options)
    return replace(plan, height_search=choice.to_json())
