"""What every gait's plan shares (planner/gaits/base.py): the step builder at the start pose,
and, once the gait has walked the waypoints, the dense samples, their verification and the
:class:`~planner.plan.Plan`."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from planner.errors import GaitRefused, PlannerInputError, PlanningError
from planner.gaits.base import NotFaster, PlanRequest
from planner.gaits.builder import StepBuilder, TimeLimitReached
from planner.gaits.creep_spin import creep_stance_in_base
from planner.gaits.load_caps import load_caps_for
from planner.gaits.rolled_contacts import rolled_contacts_for
from planner.gaits.shank_clearance import shank_clearance_for
from planner.gaits.stance_roll import stance_roll_m
from planner.gaits.stance_torque import stance_torque_for
from planner.gaits.steps import Phase, Step, StepKind
from planner.gaits.surface_footholds import surface_footholds_for
from planner.gaits.sway_timing import sway_timing_for
from planner.plan import Plan, SpinRecord
from planner.presets import StabilityPoint
from planner.stability.swing_com import SwingTiming
from planner.terrain.base import ground_height_at
from planner.trajectory.samples import Trajectory
from planner.trajectory.sampling import sample_steps
from planner.trajectory.terrain_clearance import step_swing_heights, terrain_violation
from planner.trajectory.verify import SAMPLE_MARGIN_SLACK_M, verify_samples
from planner.workspace.heights import feasible_height_range
from planner.workspace.interference import check_interference
from planner.workspace.spin import MIN_DEFAULT_SPIN_RAD, stance_turns
from silo4kin.foot_contact import foot_ball
from silo4kin.frames import rotation_z
from silo4kin.robot import STANDARD_GRAVITY

#: The four-foot stand [units] before a plan whose first step is a transfer
#: (:func:`start_stand_units`, which adds a sample): at the default unit time of 1 s the
#: lifting foot hands its load over through it (LOAD_TRANSFER_S = 0.2 s) and the first sample
#: carries the four-foot split. In units, as every step: a plan retimed (or planned) at a
#: shorter unit time starts its load transfer before its first sample, where the lifting
#: foot's share is already falling. (It was 0.5 unit, the crawl's four-foot time, until the
#: Chapter 6 straight path at h 0.2 m came to 92.5 units against the 0.7 x 132 the default
#: must stay within.)
START_STAND_UNITS = 0.2
#: The four-foot stand [units] between two transfers back to back (:func:`swap_stand_units`):
#: the load passes from the lifting foot to the landed one over 0.15 s at 1 s a unit (in one
#: 10 ms sample without it). Shorter than LOAD_TRANSFER_S: 0.2 unit and a sample put the
#: default's straight path at h 0.6 m at 175.3 units against the 0.7 x 246 = 172.2 of the
#: thesis's time it must keep (tests/test_omni_targets.py).
SWAP_STAND_UNITS = 0.15


@dataclass
class Walked:
    """What a gait's walk records besides the steps (filled in by the gait).

    Attributes:
        reached: nominal CoG (x, y) [m] when each waypoint was done, one (2,) per waypoint.
        t_reached: time [units] of each.
        passed: waypoint index -> (t0, t1) [units]: walked past it in that window (the
            gaits without turning: E_n where the samples came nearest).
        spins: the turns made.
        n_half_cycles: creeping half cycles.
        nominal_distance_m: length of the nominal CoG path [m] where the steps vary in
            length, else None.
        n_crawl_swings: swings of the continuous crawl.
    """

    reached: list[np.ndarray] = field(default_factory=list)
    t_reached: list[float] = field(default_factory=list)
    passed: dict[int, tuple[float, float]] = field(default_factory=dict)
    spins: list[SpinRecord] = field(default_factory=list)
    n_half_cycles: int = 0
    nominal_distance_m: float | None = None
    n_crawl_swings: int = 0


def walk_plan(
    request: PlanRequest,
    name: str,
    walk: Callable[[StepBuilder, Walked], None],
    *,
    fold_shifts: bool,
    smooth: bool,
    slower_than: float | None,
) -> Plan:
    """The plan of a gait called ``name`` whose ``walk(builder, record)`` walks the waypoints
    from the start pose: folded shifts (StepBuilder) with ``fold_shifts``, quintic profiles
    with ``smooth``; with ``slower_than`` [units], NotFaster as soon as the steps take at
    least that long (the rest is not built)."""
    b = start_builder(request, fold_shifts=fold_shifts, smooth=smooth)
    b.time_limit = slower_than
    b.stand_units = start_stand_units(request)
    b.swap_stand_units = swap_stand_units(request)
    walked = Walked()
    try:
        walk(b, walked)
    except TimeLimitReached as exc:
        raise NotFaster(exc.args[0]) from None
    if walked.spins:
        check_can_spin(request, name)
    if slower_than is not None and b.t_plan >= slower_than:
        raise NotFaster(b.t_plan)
    return finish_plan(request, name, b, walked, smooth=smooth)


def check_can_spin(
    request: PlanRequest, name: str, waypoint_index: int | None = None, waypoint=None
) -> None:
    """PlanningError when gait ``name`` turns the stance (towards waypoint ``waypoint_index``
    (x, y) [m], when given) and the default workspace turns it less than MIN_DEFAULT_SPIN_RAD
    per cycle at the request's height. The default's feasible heights do not ask for a spin
    (planner/workspace/heights.py: feasibility follows the path); the refusal names the
    heights at which the robot walks any direction, and says that at this one it walks
    along its body axis (facing the path walks such a path forwards and backwards,
    planner/gaits/facing.py)."""
    if can_turn(request):
        return
    ws = request.workspace
    raise PlanningError(
        f"the path needs a turn of the stance here (the {name} gait's), and at "
        f"h = {float(ws.height):.4g} m it turns {np.rad2deg(ws.psi_max_rad):.2f} deg per cycle, "
        "under the "
        f"{np.rad2deg(MIN_DEFAULT_SPIN_RAD):.0f} deg a turn needs; " + _where_it_turns(request),
        waypoint_index,
        None if waypoint is None else (float(waypoint[0]), float(waypoint[1])),
    )


def can_turn(request: PlanRequest) -> bool:
    """Whether a plan of ``request`` may turn its stance (spin.stance_turns of its
    workspace)."""
    return stance_turns(request.workspace)


def _where_it_turns(request: PlanRequest) -> str:
    """The clause of check_can_spin's refusal naming the heights at which the robot walks a
    path in every direction, and what it walks at the request's height."""
    robot = request.model.planning_robot
    heading = np.rad2deg(float(request.start_heading))
    along = (
        f"at this height it walks only along its body axis (heading {heading:.4g} deg, "
        "forwards or backwards, within its crab angle)"
    )
    try:
        lo, hi = feasible_height_range(robot, request.preset.name, any_direction=True)
    except PlannerInputError:
        return f"it walks no path in every direction at any height; {along}"
    return f"it walks a path in every direction at {lo:.4g}-{hi:.4g} m; {along}"


def start_builder(request: PlanRequest, *, fold_shifts: bool, smooth: bool = False) -> StepBuilder:
    """The step builder at the start pose: CoG at the height above the terrain under (0, 0),
    heading ``start_heading``, the forward creeping stance; the preset's stability point;
    the terrain's foothold rule; ball feet checked on their rolled contact points; with the
    whole-body CoM and a preset's zero-moment-point rule, every still-base lift also checked
    for its ZMP (the gait's profiles, ``smooth``, at the request's unit time) and each
    transfer as long as its ZMP excursion asks (planner/gaits/swing_pace.py)."""
    model, ws = request.model, request.workspace
    robot = model.planning_robot
    ground_z = ground_height_at(request.terrain, np.zeros(2))
    base0 = np.array([0.0, 0.0, ground_z + float(ws.height)])
    feet0 = base0 + (rotation_z(request.start_heading) @ creep_stance_in_base(ws, "+x", 0).T).T
    surface = surface_footholds_for(
        request.terrain,
        robot.legs,
        ws.height,
        request.preset.contact_forces.friction,
        foot_ball(robot).contact_offset_m,
        shank_clearance_for(model.robot, robot.legs, request.terrain),
        stance_roll_m(robot, ws, request.terrain),
        stance_torque_for(
            model.robot,
            robot.legs,
            request.terrain,
            request.preset.builder_torque_headroom,
            "body" if str(request.preset.load) == "body" else "total",
        ),
    )
    if surface is not None:  # each start foot on the ground under it
        base0, feet0 = surface.start_pose(base0, feet0)
    swing_com = None
    if request.preset.stability_point == StabilityPoint.WHOLE_BODY_COM:

        def swing_com(base, yaw, feet, leg, target):
            # on the gait's own profiles: the samples' swing path (planner/trajectory/sampling.py)
            return model.swing_com_in_world(
                base, yaw, feet, leg, target, ws.swing_height_m, smooth=bool(smooth)
            )

    b = StepBuilder(
        base0,
        float(request.start_heading),
        feet0,
        request.threshold,
        fold_shifts=fold_shifts,
        swing_com=swing_com,
        foothold_check=request.foothold_rule(),
        surface_footholds=surface,
        rolled_contacts=rolled_contacts_for(robot.legs, foot_ball(robot), request.terrain),
    )
    b.sway_timing = sway_timing_for(
        model, request.preset.builder_torque_headroom, request.unit_time_s, request.threshold
    )
    zmp_least = request.preset.contact_forces.min_zmp_margin_m
    if swing_com is not None and zmp_least is not None and surface is None:
        timing = SwingTiming(
            float(ws.swing_height_m),
            bool(smooth),
            float(request.unit_time_s),
            float(foot_ball(robot).contact_offset_m),
            STANDARD_GRAVITY,
        )

        def swing_zmp(base, yaw, feet, leg, target):
            return model.swing_zmp_in_world(base, yaw, feet, leg, target, timing)

        b.swing_zmp, b.zmp_least = swing_zmp, float(zmp_least)

        def swing_excursion(base, yaw, feet, leg, target, units):
            # the swing lasting ``units`` at 1 s a unit (planner/gaits/swing_pace.py)
            paced = timing._replace(unit_time_s=float(units))
            return model.swing_zmp_excursion_m(base, yaw, feet, leg, target, paced)

        b.swing_excursion = swing_excursion
    if str(request.preset.load) == "total" and not request.preset.follows_thesis:
        b.load_caps = load_caps_for(model, request.preset.builder_torque_headroom, ws)
    if swing_com is not None:

        def moving_swing_com(base_start, base_end, yaw, feet, leg, target, **kw):
            return model.moving_swing_com_in_world(
                base_start, base_end, yaw, feet, leg, target, ws.swing_height_m, **kw
            )

        b.moving_swing_com = moving_swing_com
    return b


def finish_plan(
    request: PlanRequest, name: str, b: StepBuilder, walked: Walked, *, smooth: bool
) -> Plan:
    """Samples of the builder's steps, verified (IK, limits, margins on every lift, the
    preset's tibia clearance, interference), and the Plan of gait ``name``."""
    model, ws, wp = request.model, request.workspace, request.waypoints_in_world
    preset, spu = request.preset, request.samples_per_unit
    robot = model.planning_robot
    steps = _with_swap_stands(tuple(b.steps))
    if b.lead_units and steps:
        steps, walked = _after_stand(steps, walked, b.lead_units)
    steps = on_sample_grid(steps, spu)
    if steps:
        traj = sample_steps(
            robot,
            steps,
            step_swing_heights(request.terrain, steps, ws.swing_height_m, smooth=smooth),
            spu,
            request.unit_time_s,
            model=model,
            stability_point=preset.stability_point,
            smooth=smooth,
            terrain=request.terrain,
        )
        slack = SAMPLE_MARGIN_SLACK_M if b.swing_com is not None else 0.0
        verify_samples(
            robot.legs,
            traj,
            steps,
            request.threshold,
            wp,
            slack_m=slack,
            hold_tibias=preset.holds_tibias,  # planner/trajectory/clearance.py
            terrain=request.terrain,
        )
        check_interference(traj, steps=steps, waypoints_in_world=wp)  # thesis §3.6
        reason = terrain_violation(
            robot.legs,
            traj,
            request.terrain,
            ws.position_hip_in_base,
            foot_radius_m=foot_ball(robot).rolling_radius_m,
        )
        if reason is not None:
            raise GaitRefused(f"{name}: {reason}")
    else:
        traj = _standing(request, b)
    t_reached_units = np.array(walked.t_reached, dtype=float)
    rows = np.clip(np.round(t_reached_units * spu).astype(int), 0, len(traj) - 1)
    for k, (t0, t1) in walked.passed.items():  # the sample nearest the waypoint in its window
        lo, hi = (int(round(t * spu)) for t in (t0, t1))
        hi = min(hi, len(traj) - 1)
        near = lo + int(
            np.argmin(np.hypot(*(traj.position_base_in_world[lo : hi + 1, :2] - wp[k]).T))
        )
        rows[k], t_reached_units[k] = near, near / spu
    return Plan(
        waypoints_in_world=wp,
        height=float(ws.height),
        workspace=ws,
        steps=steps,
        trajectory=traj,
        start_heading=float(request.start_heading),
        tolerance=request.tolerance,
        stability_threshold=request.threshold,
        position_reached_in_world=np.array(walked.reached),
        spins=tuple(walked.spins),
        n_creep_half_cycles=walked.n_half_cycles,
        n_shifts=b.n_shifts,
        n_folded_shifts=b.n_folded,
        preset=preset,
        gait=name,
        time_reached_units=t_reached_units,
        n_crawl_swings=walked.n_crawl_swings,
        nominal_distance_m=walked.nominal_distance_m,
        position_walked_in_world=traj.position_base_in_world[rows, :2].copy(),
    )


def start_stand_units(request: PlanRequest) -> float:
    """How long [units] a plan whose first step is a transfer stands on its four feet first
    (StepBuilder.stand_units): START_STAND_UNITS on the sample grid and one sample, the
    same at every unit time (a plan retimed equals the plan planned at that unit time); 0
    for a preset that follows the thesis (its plans start with the thesis's first step).

    A plan whose first step lifts a foot has that foot in swing on its very first sample
    (a transfer's window [t_start, t_end) is out of contact): its first posture, the one
    the robot is put down in and stands in before the plan starts (the sim's calibration
    and settling, silo4sim/replay.py), is a three-foot support whose torques give the
    fourth foot none of the load, although that foot stands on the ground. The stand puts
    the load on four feet first and lets the lifting foot give its share away over the load
    transfer (silo4kin/load_transfer.py) before it lifts."""
    if request.preset.follows_thesis:
        return 0.0
    spu = request.samples_per_unit
    # one sample more: the load transfer ends on the foot's last sample in contact
    return float((np.ceil(START_STAND_UNITS * spu - 1e-9) + 1.0) / spu)


def swap_stand_units(request: PlanRequest) -> float:
    """How long [units] the feet stand on four between two transfers back to back
    (StepBuilder.swap_stand_units): SWAP_STAND_UNITS on the sample grid; 0 for a preset that
    follows the thesis. The reason is the start's stand's (:func:`start_stand_units`).

    Where a gait swings one leg right after another (the creep's two transfers, the crawl's
    pairs, the spin's transfers) one foot lands on the sample the other lifts: there is no
    four-foot time, so the landing foot takes its share of the three-foot support on that
    sample (silo4kin/load_transfer.py can ramp nothing within 0 s). Measured on solo12
    (corpus case 16 of seed 20261202, docs/physics.md "The swing is paced"): RF, planned
    to carry 0.35 W from the sample it lands on, chattered on the floor (sim force 0 /
    0.42 W every ~50 ms) and slid 5.7 mm; with this stand the lifting foot hands its load
    to the landed one before it lifts (silo4kin/load_transfer.py: its share falls to 0 at
    the lift-off), and no foot slides more than 0.2 mm."""
    if request.preset.follows_thesis:
        return 0.0
    spu = request.samples_per_unit
    return float(np.ceil(SWAP_STAND_UNITS * spu - 1e-9) / spu)


def _with_swap_stands(steps: tuple[Step, ...]) -> tuple[Step, ...]:
    """``steps`` with a four-foot stand in every gap the builder left between two steps
    (StepBuilder.swap_stand_units: before a transfer that follows a transfer)."""
    out: list[Step] = []
    for step in steps:
        if out and step.t_start > out[-1].t_end + 1e-9:
            out.append(_stand(step, out[-1].t_end, step.t_start))
        out.append(step)
    return tuple(out)


def on_sample_grid(steps: tuple[Step, ...], samples_per_unit: int) -> tuple[Step, ...]:
    """``steps`` with every start and end time [units] within 1e-6 sample of the sample grid
    put on it exactly (k / samples_per_unit): the stands' 0.15 and 0.21 unit, added to times
    on the 0.5-unit grid, leave sums one ulp off it (1.21 + 0.15 = 1.3599999999999999), and
    a step starting one ulp after its sample labelled that sample with the step before
    (the sampler's searchsorted), one sample off the motion."""

    def snap(t: float) -> float:
        k = round(t * samples_per_unit)
        return k / samples_per_unit if abs(t * samples_per_unit - k) < 1e-6 else t

    return tuple(replace(s, t_start=snap(s.t_start), t_end=snap(s.t_end)) for s in steps)


def _stand(step: Step, t_start: float, t_end: float) -> Step:
    """A four-foot stand from ``t_start`` to ``t_end`` [units] at the start pose of
    ``step``."""
    return Step(
        StepKind.BODY,
        None,
        t_start,
        t_end,
        step.position_base_start_in_world.copy(),
        step.position_base_start_in_world.copy(),
        step.yaw_base_start,
        step.yaw_base_start,
        label="stand",
        waypoint_index=step.waypoint_index,
        position_feet_in_world=None
        if step.position_feet_in_world is None
        else step.position_feet_in_world.copy(),
        phase=Phase.STAND,
    )


def _after_stand(
    steps: tuple[Step, ...], walked: Walked, lead: float
) -> tuple[tuple[Step, ...], Walked]:
    """``steps`` and ``walked`` ``lead`` units later, after a four-foot stand at the start
    pose (:func:`start_stand_units`)."""
    stand = _stand(steps[0], 0.0, lead)
    later = tuple(replace(s, t_start=s.t_start + lead, t_end=s.t_end + lead) for s in steps)
    shifted = replace(
        walked,
        t_reached=[t + lead for t in walked.t_reached],
        passed={k: (t0 + lead, t1 + lead) for k, (t0, t1) in walked.passed.items()},
    )
    return (stand, *later), shifted


def _standing(request: PlanRequest, b: StepBuilder) -> Trajectory:
    """One sample of the start pose when no step is needed."""
    model, ws = request.model, request.workspace
    still = Step(
        StepKind.BODY,
        None,
        0.0,
        1.0,
        b.base.copy(),
        b.base.copy(),
        b.yaw,
        b.yaw,
        label="stand",
        position_feet_in_world=b.feet.copy(),
        phase=Phase.STAND,
    )
    tr = sample_steps(
        model.planning_robot,
        (still,),
        ws.swing_height_m,
        1,
        request.unit_time_s,
        model=model,
        stability_point=request.preset.stability_point,
        terrain=request.terrain,
    )
    return tr.head(1)
