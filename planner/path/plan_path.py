"""Path following (thesis §5.4-5.5): waypoints in W -> checked steps -> dense samples.

The robot starts at (0, 0) with the CoG at height h, heading ``start_heading`` (thesis: facing
its +y, i.e. π/2 in a REP-103 world), in the forward creeping stance. For each waypoint, in the
base frame (eq 5.29-5.30: p_CoG = Qᵀ(p_W - p_o), from the nominal CoG, i.e. without stability
shifts):

1. n = round(d / (λ/2)) half cycles for the straight-line distance d (default preset; the
   thesis preset rounds d/λ to whole cycles, §5.5). d <= tolerance: reached; n = 0:
   reached for the default preset, while the thesis preset still spins to face a waypoint
   off its axis (step 2) and then creeps its n = 0 cycles: §5.5 spins towards every
   waypoint that is off the body's axis (issue 11; with it the circle of Table 6.2 lands
   within 3 %, docs/results.md). On its axis the thesis preset creeps only when the
   waypoint is more than the tolerance ahead (§6.3).
2. Spin to face it (transition, ceil(|ψ|/ψ_max) spinning cycles, transition) when its lateral
   offset exceeds the tolerance or it lies behind by more than the tolerance (§5.5 case 2;
   the thesis's "distance in x equal to zero" needs a tolerance).
3. Creep forward n half cycles; the nominal CoG is tracked in W (eq 5.31-5.32).

The default preset walks in any direction without turning the body (planner/gaits/omni.py,
docs/gaits.md): straight to each waypoint (past the ones the line passes within half the
tolerance), equal steps so the CoG lands on it, 1-unit body phases, quintic profiles (q̈
continuous). If that plan fails (no reachable or stable step), or with ``face_path``, it
faces each segment as below, and ``Plan.fallback_reason`` says why.

Facing the path, the default preset is faster with the same checks (the thesis preset keeps
the rules above):
- ceil(d / (λ/2)) half cycles, the last one shortened, so the nominal CoG lands on the
  waypoint (metrics.tolerance_warning says so if a default plan still misses it);
- a waypoint needing a turn but at most gaits.crab_limit_rad off the heading is walked to at
  that crab angle (thesis §4.1), without a spin;
- a turn only brings the waypoint within the crab range: of the turns with the fewest
  spinning cycles, the one keeping the most following path legs in range
  (:func:`_lookahead_turn`);
- no transitions: the first spinning cycle starts from the creeping stance and the creep
  starts from the spin stance (its first pair swings from position 2 to the front);
- stability shifts are folded into the last body phase or spin rotation (StepBuilder).
If that plan fails its verification (these moves go beyond the workspace's checked reserves
on some robots), the path is planned again without them, and the plan says so
(``Plan.gait`` = "plain", ``Plan.fallback_reason``): no silent fallback.

Stability point and swing height come from the preset's policy (planner/presets.py): the
default keeps the whole-robot CoM (legs included, as they move; planner/model.py) at least
the threshold inside the support triangle at every checked configuration of every swing,
and lifts the feet by at least policy.MIN_SWING_HEIGHT_M; the thesis keeps the body CoG
and eq 5.12. Every trajectory carries both margins (margin_com, margin_body).

``tolerance`` [m] defaults to DEFAULT_TOLERANCE_M; 0.15 m is the reduced-accuracy run of
Table 6.3. Then the samples are verified (IK reachable, joints within limits, no NaN, margin
>= threshold on every lift); any failure raises PlanningError naming the waypoint.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from planner.errors import PlannerInputError, PlanningError
from planner.gaits.builder import FootholdCheck
from planner.gaits.sway import shank_violation
from planner.model import PlanningModel, as_planning_model
from planner.path.follower import NotFaster, build_plan
from planner.path.plan import Plan, SpinRecord
from planner.presets import policy_for
from planner.request import check_plan_inputs, waypoints_array
from planner.trajectory.limits import limit_violation
from planner.workspace.layout import workspace_for
from silo4kin.robot import Robot

__all__ = ["DEFAULT_TOLERANCE_M", "GAITS", "Plan", "SpinRecord", "plan_path",
           "robot_in_body_com_frame"]

#: Default lateral / reach tolerance [m]: "distance in x equal to zero" with 1 cm slack.
DEFAULT_TOLERANCE_M = 0.01
#: The default preset's gaits without turning (plan_path's ``gait``).
GAITS = ("auto", "crawl", "creep")


def robot_in_body_com_frame(robot: Robot) -> Robot:
    """The robot with its hips measured from the body CoG, the frame B the planner works in
    (planner/model.py); cached per robot object. For SILO4 the URDF root is the CoG and the
    robot is returned unchanged."""
    return as_planning_model(robot).planning_robot


def plan_path(robot: Robot | PlanningModel, waypoints_in_world, height: float | str, *,
              start_heading: float = np.pi / 2, workspace: str = "default",
              tolerance: float | None = None, samples_per_unit: int = 100,
              unit_time_s: float = 1.0, stability_threshold: float | None = None,
              swing_height_m: float | None = None, face_path: bool = False,
              foothold_check: FootholdCheck | None = None, gait: str = "auto") -> Plan:
    """Plan statically stable walking through ``waypoints_in_world`` (K, 2) [m] at CoG height
    ``height`` [m] (module docstring), or ``height="auto"``: the height in the feasible range
    that walks the path in the least time (planner/path/height.py, thesis §7.2), recorded in
    ``Plan.height_search``. ``swing_height_m`` [m] overrides the policy's swing
    height (default: eq 5.12, at least policy.MIN_SWING_HEIGHT_M for the default preset).
    ``face_path`` keeps the thesis's habit of facing each segment (spin, then creep forward)
    in the default preset instead of walking in any direction without turning
    (planner/gaits/omni.py). ``gait`` picks the default preset's gait without turning: "crawl"
    (the continuous crawl, planner/gaits/crawl.py), "creep" (the omnidirectional creeping gait,
    planner/gaits/omni.py) or "auto" (both, the one that takes less time; the crawl on a tie);
    ``Plan.gait`` says which walked ("crawl" or "omni"). The thesis preset ignores it.
    ``foothold_check`` is called with every foothold (3,) in W [m] as a step places it
    (planner/gaits/builder.py; a pure function of the foothold: it may see one twice). An
    exception it raises abandons the candidate gait being built (gait "auto" tries the
    other; the last one's exception propagates), except inside the continuous crawl, which
    undoes the swing that placed the foothold and walks a creeping half cycle from there,
    its footholds checked too (planner/gaits/crawl.py CrawlOrCreep). The
    ditch's route search rejects a gait at its first foothold in the ditch (planner/studies/ditch.py).

    Raises:
        PlannerInputError: bad waypoints, height, preset or parameters.
        PlanningError: no stable or reachable step for a waypoint (named in the message).
    """
    check_plan_inputs(robot, waypoints_in_world, height, start_heading, workspace, tolerance,
                      samples_per_unit, unit_time_s, stability_threshold)  # planner/request.py
    if gait not in GAITS:
        raise PlannerInputError(f"gait must be one of {list(GAITS)}, got {gait!r}")
    wp = waypoints_array(waypoints_in_world)
    if foothold_check is not None and not callable(foothold_check):
        raise PlannerInputError(f"foothold_check must be a function of a foothold (3,) [m] or "
                                f"None, got {type(foothold_check).__name__}")
    if isinstance(height, str):
        if height != "auto":
            raise PlannerInputError(f"height must be a number [m] or 'auto', got {height!r}")
        from planner.path.height import best_height

        options: dict[str, Any] = dict(
            start_heading=start_heading, workspace=workspace, tolerance=tolerance,
            unit_time_s=unit_time_s, stability_threshold=stability_threshold,
            swing_height_m=swing_height_m, face_path=face_path, foothold_check=foothold_check,
            gait=gait)
        choice = best_height(robot, wp, **options)
        plan = plan_path(robot, wp, choice.height_m, samples_per_unit=samples_per_unit,
                         **options)
        return replace(plan, height_search=choice.to_json())
    if swing_height_m is not None and (isinstance(swing_height_m, bool) or not isinstance(
            swing_height_m, (int, float, np.floating)) or not 0 < swing_height_m < np.inf):
        raise PlannerInputError(f"swing_height_m must be a finite number > 0 [m], got "
                                f"{swing_height_m!r}")
    policy = policy_for(workspace)
    model = as_planning_model(robot)
    ws = workspace_for(model.planning_robot, height, workspace)
    ws = replace(ws, swing_height_m=policy.swing_height(ws.swing_height_m, swing_height_m))
    tol = DEFAULT_TOLERANCE_M if tolerance is None else float(tolerance)
    thr = ws.stability_threshold_m if stability_threshold is None else float(stability_threshold)
    args = (model, policy, ws, wp, start_heading, tol, thr, samples_per_unit, unit_time_s,
            foothold_check)
    robot = model.planning_robot
    if not policy.fast_gait:
        return build_plan(*args, fast=False)
    omni_reason = None
    if not face_path:
        # a foothold_check rejection rules out one candidate gait, not the plan: the check
        # applies to the plan that is returned (the ditch route search, planner/studies/ditch.py)
        cargs = args if foothold_check is None else (*args[:-1], _candidate(foothold_check))
        crawl, crawl_reason = None, None
        if gait == "auto" and model.family != "insect":
            # the crawl is checked in physics on insect legs only: a mammal's crawl slipped
            # and drifted where its creeping gait walks (docs/robots.md); ask with gait="crawl"
            crawl_reason = (f"continuous crawl: not the default for {model.family} legs "
                            f"(not validated in physics; gait='crawl' plans it)")
        elif gait in ("auto", "crawl"):
            try:
                crawl = build_plan(*cargs, fast=True, omni=True, crawl=True)
                # the crawl moves body and swing leg together: it may need more speed or
                # torque than the creeping gait, so it is kept only within the URDF limits
                # at this unit time (planner/trajectory/limits.py; `silo4 plan` checks every plan),
                # and its sway may flatten a shank: kept only with every shank clear
                # (sway.MIN_SHANK_SLOPE_RAD)
                violation = (shank_violation(robot.legs, crawl.trajectory)
                             or limit_violation(model.robot, crawl.trajectory,
                                                str(policy.load)))
                if violation is not None:
                    crawl = None
                    crawl_reason = f"continuous crawl: {violation}"
            except PlanningError as exc:
                crawl_reason = f"continuous crawl: {exc}"
            except _FootholdRejected as exc:
                crawl_reason = f"continuous crawl: foothold rejected ({exc.cause!r})"
        if crawl is not None and gait == "crawl":
            return crawl
        crawl_units = crawl.steps[-1].t_end if crawl is not None and crawl.steps else 0.0
        try:
            # with a crawl in hand, the creeping gait is sampled only if it is faster
            creep = build_plan(*cargs, fast=True, omni=True,
                          slower_than=None if crawl is None else crawl_units)
            return replace(creep, fallback_reason=crawl_reason)
        except NotFaster:
            assert crawl is not None
            return crawl
        except _FootholdRejected as exc:
            if crawl is not None:
                return crawl
            raise exc.cause from None
        except PlanningError as exc:
            if crawl is not None:
                return crawl
            # neither omnidirectional gait found a stable or reachable step: face the path
            # instead, and say so in the plan
            omni_reason = "; ".join(filter(None, (crawl_reason,
                                                  f"omnidirectional gait: {exc}")))
    try:
        return replace(build_plan(*args, fast=True), fallback_reason=omni_reason)
    except PlanningError as exc:
        # the faster gait left the checked reserves (e.g. a swing straight from a creeping
        # foothold to a rotated one on a robot with other leg lengths): plan as before, and
        # say so in the plan
        reason = str(exc) if omni_reason is None else f"{omni_reason}; fast gait: {exc}"
        return replace(build_plan(*args, fast=False), fallback_reason=reason)


class _FootholdRejected(Exception):
    """plan_path's foothold_check raised ``cause`` while one candidate gait was built."""

    def __init__(self, cause: BaseException) -> None:
        super().__init__(str(cause))
        self.cause = cause


def _candidate(check: FootholdCheck) -> FootholdCheck:
    """``check``, its exception wrapped in :class:`_FootholdRejected`."""
    def wrapped(position_foot_in_world: np.ndarray) -> None:
        try:
            check(position_foot_in_world)
        except Exception as exc:  # noqa: BLE001 - any rejection; re-raised as it came
            raise _FootholdRejected(exc) from exc
    return wrapped
