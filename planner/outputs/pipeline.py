"""One plan pipeline: plan -> URDF limits -> torques -> metrics, for every caller.

    run = plan_run(robot, waypoints, 0.4, RunRequest(unit_time=1.0, gearing=gearing),
                   start_heading=math.pi / 2, workspace="default")
    run.plan, run.metrics, run.limits

``silo4 plan``, ``silo4 cases`` and the sweep (silo4sweep/task.py) all call :func:`plan_run`, so
they retime and check a plan against the URDF velocity and effort limits the same way
(planner.trajectory.limits), compute the torques with the same load (planner.trajectory.
torques) and report the same metrics (planner.path.metrics). What differs is what a limit
violation does (:class:`OnLimitViolation`): ``silo4 plan`` refuses the plan, ``silo4 cases``
and the sweep report it.

metrics (planner.path.metrics.compute_metrics) gain ``joint_limits`` (LimitCheck.to_dict()
where the limits refuse or the unit time is "auto"; where a violation is reported,
``unit_time_s`` and ``violation``: the line naming joint, value, limit and time, or None),
and with torques ``torque_load`` and ``motor_sizing`` (silo4kin.motors.sizing_table,
eq A.35-A.36).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np

from planner.errors import PlanningError
from planner.model import planning_model
from planner.path.metrics import compute_metrics
from planner.path.plan_path import plan_path
from planner.plan import Plan
from planner.presets import CRAWL_BY_DEFAULT_FAMILIES, Preset, preset_for
from planner.stability.contact_forces import ContactForceCheck
from planner.trajectory.clearance import ground_contact_violations
from planner.trajectory.limits import (
    UNIT_TIME_RESOLUTION_S,
    JointLimitError,
    LimitCheck,
    limit_plan,
    limit_violation,
    motion_share,
    retime,
    urdf_limits,
)
from planner.trajectory.torques import add_torques, transfer_time_s
from planner.trajectory.verify import contact_force_violation
from silo4kin.errors import Silo4Error
from silo4kin.motors import Gearing, sizing_table
from silo4kin.robot import STANDARD_GRAVITY

Load = Literal["body", "total"]


class OnLimitViolation(enum.Enum):
    """What a plan that breaks a URDF velocity or effort limit at its unit time becomes."""

    #: JointLimitError naming joint, value, limit and time (``silo4 plan``).
    REFUSE = "refuse"
    #: kept at its unit time; the violation is metrics["joint_limits"]["violation"] and a
    #: line of metrics["warnings"] (``silo4 cases``, sweeps).
    REPORT = "report"


@dataclass(frozen=True)
class RunRequest:
    """What the pipeline does with a plan after planning it.

    Attributes:
        unit_time: the duration of one time unit t_l [s], or "auto": the shortest unit time
            within the URDF limits (planner.trajectory.limits.shortest_unit_time).
        load: the mass the feet carry for the limits and the torques, "body" or "total";
            None: the plan's preset's (Plan.preset.load).
        gearing: the motors' gearing for the sizing table; None: no torques in the
            trajectory nor sizing in the metrics.
        on_limit_violation: refuse or report a plan that breaks a URDF limit.
        torque_headroom: the fraction of each URDF effort limit the plan's torques may use
            (1: the limit itself); None: the plan's preset's (Preset.torque_headroom: 0.85,
            the thesis preset 1.0).
        ground_clearance_m: the least height above the ground of every non-foot collision
            shape [m] (planner/trajectory/clearance.py); None: the preset's
            (Preset.ground_clearance_m, 1 cm). A plan under it is reported (a warning in
            the metrics); one that puts a non-foot shape on the ground (clearance < 0) is
            refused or reported as ``on_limit_violation`` says. The margin is not a refusal:
            the crawl keeps SILO4's tibia capsules MIN_TIBIA_CLEARANCE_M (2 mm, measured in
            physics) off the ground, and the thesis straight path at h 0.4 m comes 9.9 mm.
        terrain: the terrain the plan walks (None: flat ground at z = 0), for the clearance.
    """

    unit_time: float | Literal["auto"] = 1.0
    load: Load | None = None
    gearing: Gearing | None = None
    on_limit_violation: OnLimitViolation = OnLimitViolation.REFUSE
    torque_headroom: float | None = None
    ground_clearance_m: float | None = None
    terrain: Any = None


@dataclass(frozen=True)
class PlannedRun:
    """A planned run: the plan (torques in its trajectory when asked), its metrics, and its
    LimitCheck at the plan's unit time (None where a violation is reported at a fixed unit
    time: :func:`finish_plan`)."""

    plan: Plan
    metrics: dict[str, Any]
    limits: LimitCheck | None


#: The default's two gaits without turning (planner/gaits/registry.py, "auto"): where the one
#: "auto" chose breaks a rule the pipeline checks, :func:`plan_run` plans the other.
OTHER_GAIT_WITHOUT_TURNING = {"crawl": "creep", "creep": "crawl"}
#: Plans a run makes at most when its motion breaks the effort budget (plan_run): each
#: lowers the step builder's share of the effort by what the last one's motion added.
MOTION_REPLANS = 4
#: How fallback reasons name them (the gaits' own labels, planner/gaits/without_turning.py,
#: which this layer does not import).
GAIT_LABELS = {"crawl": "continuous crawl", "creep": "omnidirectional gait"}


def plan_load(plan: Plan, request: RunRequest) -> Load:
    """The load the limits and the torques use: the request's, else the plan's preset's."""
    chosen = request.load or str(plan.preset.load)
    return "body" if chosen == "body" else "total"


def plan_run(
    robot: Any,
    waypoints_in_world: Any,
    height: float | str,
    request: RunRequest,
    **plan_options: Any,
) -> PlannedRun:
    """Plan (planner.path.plan_path.plan_path with ``plan_options``), retime and check the
    URDF limits, add the torques, compute the metrics (module docstring). Where gait "auto"
    chose one of its gaits without turning and that plan breaks a rule checked here (an
    effort limit standing still, the contact forces, a non-foot ground touch), the other
    one is planned at the same height (OTHER_GAIT_WITHOUT_TURNING; ``Plan.fallback_reason``
    says why); if it fails too, the first refusal is raised.

    A plan whose torques standing still keep the effort budget but whose motion breaks it at
    the unit time asked for (the floating robot's torques: the stance legs also carry the
    base's acceleration and the swinging legs' reactions, planner/trajectory/floating_torques.py)
    is planned again with the step builder's share of each joint's effort that broke the
    budget lowered by what the motion added to it there (Preset.step_torque_headroom, per
    joint: its headroom - max (|τ| - |τ_static|) / URDF effort over the samples where the
    joint broke it, JointLimitError.motion_share), so that its stances leave the motion that
    room; the joints that break it in the next plan are lowered too, at most MOTION_REPLANS
    plans in all; if none keeps the budget (or a later plan finds no step) the first refusal
    is raised. A run that reports a limit violation instead (``on_limit_violation`` REPORT:
    ``silo4 cases``, sweeps) is planned again alike, and the last plan that planned is
    reported.
    (mantis at h 0.1927 m, 200-case corpus #7: the load caps held arm3_lift at 33.85 of its
    34.00 N m standing still, and its motion asked 34.01; SILO4's crawl to (-0.3, 0.2) at
    0.4 m: RH_knee 48.63 N m standing still, 51.48 in the moving transfer, budget 51.00.)

    Raises:
        PlannerInputError, PlanningError: as plan_path.
        planner.trajectory.limits.JointLimitError: a limit is broken and
            ``request.on_limit_violation`` is REFUSE.
    """
    options = dict(plan_options)
    first: JointLimitError | None = None  # the first plan's refusal, raised if no plan does better
    reported: PlannedRun | None = None  # the last plan whose violation was reported
    for attempt in range(1, MOTION_REPLANS + 1):
        last = attempt == MOTION_REPLANS
        try:
            run = _planned_and_finished(
                robot, waypoints_in_world, height, request, options, replans=not last
            )
        except JointLimitError as refused:
            first = first or refused
            lowered = (
                None if refused.motion_share is None else _lowered(options, refused.motion_share)
            )
            if last or lowered is None:
                raise first from None
            options["workspace"] = lowered
            continue
        except PlanningError:
            # a plan with less of the effort for its stances found no step: the first
            # plan's outcome stands
            if first is not None:
                raise first from None
            if reported is not None:
                return reported
            raise
        # a violation reported (not refused) at a fixed unit time: the same second plan
        if last or run.limits is not None or not run.metrics["joint_limits"].get("violation"):
            return run
        share = motion_share(
            robot, run.plan.trajectory, plan_load(run.plan, request), _headroom(run.plan, request)
        )
        lowered = None if share is None else _lowered(options, share)
        if lowered is None:
            return run
        reported = run
        options["workspace"] = lowered
    raise AssertionError("unreachable: the last attempt returns or raises")


def _lowered(options: dict[str, Any], share: np.ndarray) -> Preset | None:
    """The plan's preset with the step builder's share of each joint's effort lowered by
    ``share`` (12,) (plan_run), or None where a share would reach 0."""
    preset = preset_for(options.get("workspace", "default"))
    lowered = np.asarray(preset.builder_torque_headroom, dtype=float) - share
    if np.any(lowered <= 0.0):
        return None
    return preset._replace(
        step_torque_headroom=tuple(float(x) for x in np.broadcast_to(lowered, (12,)))
    )


def _headroom(plan: Plan, request: RunRequest) -> float:
    """The run's effort budget as a fraction of the URDF effort: the request's, else the
    plan's preset's."""
    if request.torque_headroom is None:
        return plan.preset.torque_headroom
    return request.torque_headroom


def _planned_and_finished(
    robot: Any,
    waypoints_in_world: Any,
    height: float | str,
    request: RunRequest,
    plan_options: dict[str, Any],
    replans: bool,
) -> PlannedRun:
    """plan_run's plan, limits and outputs, and its other gait without turning; with
    ``replans``, a refusal of the plan's motion alone (JointLimitError.motion_share) is
    raised to plan_run, which plans the same gait again, before the other gait is tried."""
    unit_time_s = 1.0 if request.unit_time == "auto" else float(request.unit_time)
    plan = plan_path(robot, waypoints_in_world, height, unit_time_s=unit_time_s, **plan_options)
    if request.terrain is None and plan_options.get("terrain") is not None:
        request = replace(request, terrain=plan_options["terrain"])
    try:
        return finish_plan(robot, plan, request)
    except PlanningError as refused:
        if replans and getattr(refused, "motion_share", None) is not None:
            raise
        other = OTHER_GAIT_WITHOUT_TURNING.get(plan.gait)
        if other is None or plan_options.get("gait", "auto") != "auto":
            raise
        if other == "crawl" and planning_model(robot).family not in CRAWL_BY_DEFAULT_FAMILIES:
            raise  # gait auto does not crawl on these legs
        # the faster gait without turning breaks a rule checked on its samples (an effort,
        # the contact forces, a non-foot touch): the other one, at the height chosen
        options = dict(plan_options, gait=other)
        options.pop("on_height_candidate", None)
        try:
            alternative = plan_path(
                robot, waypoints_in_world, plan.height, unit_time_s=unit_time_s, **options
            )
            reason = f"{GAIT_LABELS[plan.gait]}: {refused}"
            alternative = replace(
                alternative,
                gait=other,
                fallback_reason=reason
                if alternative.fallback_reason is None
                else f"{reason}; {alternative.fallback_reason}",
                height_search=plan.height_search,
            )
            return finish_plan(robot, alternative, request)
        except PlanningError:
            raise refused from None


def finish_plan(robot: Any, plan: Plan, request: RunRequest) -> PlannedRun:
    """The pipeline after planning: limits, contact forces (an "auto" unit time grows to
    keep the friction demand within mu_plan and the zero-moment point inside the support),
    metrics, torques (:func:`plan_run`).

    Refused violations and "auto" unit times get the full LimitCheck (velocity and effort
    ratios, the shortest allowed unit time: four torque computations); a reported violation
    at a fixed unit time gets the same check of the same limits at that unit time
    (planner.trajectory.limits.limit_violation: one torque computation, which the torques
    then reuse), so a sweep or ``silo4 cases`` costs what it did without the limits.
    """
    load = plan_load(plan, request)
    headroom = _headroom(plan, request)
    limits: LimitCheck | None = None
    violation: str | None = None
    if request.on_limit_violation is OnLimitViolation.REFUSE or request.unit_time == "auto":
        plan, limits = limit_plan(robot, plan, request.unit_time, load=load, headroom=headroom)
        joint_limits = limits.to_dict()
    else:
        unit_time_s = float(request.unit_time)
        if plan.trajectory.unit_time_s != unit_time_s:
            plan = replace(plan, trajectory=retime(plan.trajectory, unit_time_s))
        violation = limit_violation(robot, plan.trajectory, load, headroom)
        joint_limits = {"unit_time_s": unit_time_s, "violation": violation}
    contact = ContactForceCheck(
        plan.preset.contact_forces,
        planning_model(robot),
        STANDARD_GRAVITY,
        request.terrain,
        transfer_time_s(load),
    )
    if request.unit_time == "auto":  # slower where the friction or the ZMP asks for it
        t_contact = max(
            contact.unit_time_for_friction(plan.trajectory, UNIT_TIME_RESOLUTION_S),
            contact.unit_time_for_zmp(plan.trajectory, UNIT_TIME_RESOLUTION_S),
        )
        if t_contact > plan.trajectory.unit_time_s:
            plan, limits = limit_plan(robot, plan, t_contact, load=load, headroom=headroom)
            joint_limits = limits.to_dict()
    forces = contact_force_violation(plan.trajectory, plan.steps, plan.waypoints_in_world, contact)
    if forces is not None and request.on_limit_violation is OnLimitViolation.REFUSE:
        raise forces
    touch, clearance = ground_contact_violations(
        planning_model(robot).robot,
        plan.trajectory,
        request.terrain,
        (
            0.0,
            plan.preset.ground_clearance_m
            if request.ground_clearance_m is None
            else request.ground_clearance_m,
        ),
    )
    if touch is not None and request.on_limit_violation is OnLimitViolation.REFUSE:
        raise PlanningError(touch)
    metrics = compute_metrics(plan)
    metrics["joint_limits"] = joint_limits
    if clearance is not None:
        warnings = metrics.get("warnings")
        metrics["warnings"] = [
            *(warnings if isinstance(warnings, list) else []),
            f"ground clearance: {clearance}",
        ]
    if forces is not None:
        warnings = metrics.get("warnings")
        metrics["warnings"] = [
            *(warnings if isinstance(warnings, list) else []),
            f"contact forces: {forces}",
        ]
    if violation is not None:
        warnings = metrics.get("warnings")
        metrics["warnings"] = [
            *(warnings if isinstance(warnings, list) else []),
            f"URDF joint limit: {violation} (unit time {unit_time_s:g} s)",
        ]
    if request.gearing is not None:
        trajectory = add_torques(robot, plan.trajectory, load=load)
        if trajectory.tau is None:  # add_torques always sets it; keeps the type checker honest
            raise Silo4Error("planner.trajectory.torques.add_torques returned no torques")
        metrics["torque_load"] = load
        metrics["motor_sizing"] = sizing_table(
            trajectory.joint_names,
            trajectory.tau,
            trajectory.qd,
            request.gearing,
            t=trajectory.t,
            urdf_limits=urdf_limits(robot),
        )
        plan = replace(plan, trajectory=trajectory)
    return PlannedRun(plan, metrics, limits)
