"""What every gait's plan shares (planner/gaits/base.py): the step builder at the start pose,
and, once the gait has walked the waypoints, the dense samples, their verification and the
:class:`~planner.plan.Plan`."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from planner.errors import GaitRefused, PlanningError
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
from planner.presets import FootholdRule, StabilityPoint, footholds_of
from planner.terrain.base import ground_height_at
from planner.trajectory.samples import Trajectory
from planner.trajectory.sampling import sample_steps
from planner.trajectory.terrain_clearance import step_swing_heights, terrain_violation
from planner.trajectory.verify import SAMPLE_MARGIN_SLACK_M, verify_samples
from planner.workspace.interference import check_interference
from planner.workspace.spin import MIN_DEFAULT_SPIN_RAD
from silo4kin.foot_contact import foot_ball
from silo4kin.frames import rotation_z


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
    b = start_builder(request, fold_shifts=fold_shifts)
    b.time_limit = slower_than
    walked = Walked()
    try:
        walk(b, walked)
    except TimeLimitReached as exc:
        raise NotFaster(exc.args[0]) from None
    if walked.spins:
        check_can_spin(request, name)
    if slower_than is not None and b.t >= slower_than:
        raise NotFaster(b.t)
    return finish_plan(request, name, b, walked, smooth=smooth)


def check_can_spin(request: PlanRequest, name: str) -> None:
    """PlanningError when gait ``name`` turns the stance and the default workspace turns it
    less than MIN_DEFAULT_SPIN_RAD per cycle at the request's height (the default's
    feasible heights do not ask for a spin: planner/workspace/heights.py)."""
    ws = request.workspace
    if footholds_of(request.preset.name) is not FootholdRule.REACHABLE_SETS:
        return
    if ws.psi_max_rad < MIN_DEFAULT_SPIN_RAD:
        raise PlanningError(
            f"the {name} gait turns the stance, and at h = {float(ws.height):.4g} m it turns "
            f"{np.rad2deg(ws.psi_max_rad):.2f} deg per cycle, under the "
            f"{np.rad2deg(MIN_DEFAULT_SPIN_RAD):.0f} deg a turn needs"
        )


def start_builder(request: PlanRequest, *, fold_shifts: bool) -> StepBuilder:
    """The step builder at the start pose: CoG at the height above the terrain under (0, 0),
    heading ``start_heading``, the forward creeping stance; the preset's stability point;
    the terrain's foothold rule; ball feet checked on their rolled contact points."""
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
            request.preset.torque_headroom,
            "body" if str(request.preset.load) == "body" else "total",
        ),
    )
    if surface is not None:  # each start foot on the ground under it
        base0, feet0 = surface.start_pose(base0, feet0)
    swing_com = None
    if request.preset.stability_point == StabilityPoint.WHOLE_BODY_COM:

        def swing_com(base, yaw, feet, leg, target):
            return model.swing_com_in_world(base, yaw, feet, leg, target, ws.swing_height_m)

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
    b.sway_timing = sway_timing_for(model, request.preset.torque_headroom, request.unit_time_s)
    if str(request.preset.load) == "total" and not request.preset.follows_thesis:
        b.load_caps = load_caps_for(model, request.preset.torque_headroom)
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
    steps = tuple(b.steps)
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
