"""One candidate gait's plan (planner/path/plan_path.py chooses among them, module docstring there):
the step builder walked through the waypoints by that gait, then the dense samples and
their verification. :func:`build_plan` is what plan_path calls once per candidate."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from planner.gaits.builder import FootholdCheck, StepBuilder, TimeLimitReached
from planner.gaits.crawl import CrawlOrCreep
from planner.gaits.creep_spin import (
    creep_half_cycle,
    creep_stance_in_base,
    rotation_z,
    spin,
    thesis_spin_cycles,
    transition_from_spin,
    transition_to_spin,
)
from planner.gaits.facing import crab_limit, lookahead_turn
from planner.gaits.omni import line_of_sight, nearest_on_segment, omni_to
from planner.gaits.steps import Phase, Step, StepKind
from planner.model import PlanningModel
from planner.path.first_walk import walk_first_segment, workspace_key
from planner.path.plan import Plan, SpinRecord
from planner.presets import Policy, StabilityPoint
from planner.trajectory.samples import Trajectory
from planner.trajectory.sampling import sample_steps
from planner.trajectory.verify import SAMPLE_MARGIN_SLACK_M, verify_samples
from planner.workspace.interference import check_interference
from planner.workspace.layout import Workspace


class NotFaster(Exception):
    """A gait's steps take longer than the plan already in hand (plan_path, gait "auto")."""


def build_plan(model: PlanningModel, policy: Policy, ws: Workspace, wp: np.ndarray,
               start_heading: float, tol: float, thr: float, samples_per_unit: int,
               unit_time_s: float, foothold_check: FootholdCheck | None, *, fast: bool,
               omni: bool = False, crawl: bool = False, slower_than: float | None = None
               ) -> Plan:
    """Steps, samples and verification of planner.path.plan_path for one gait; ``fast``
    enables the default preset's crab gait, lookahead turns, spins without transitions and
    folded shifts (planner/path/plan_path.py's docstring); ``omni`` walks without turning, by the
    continuous crawl with ``crawl``. With ``slower_than`` [units], :class:`NotFaster` is
    raised as soon as the steps take at least that long (the builder's time limit: the rest
    is not built)."""
    base0 = np.array([0.0, 0.0, float(ws.height)])
    feet0 = base0 + (rotation_z(start_heading) @ creep_stance_in_base(ws, "+x", 0).T).T
    swing_com = None
    if policy.stability_point == StabilityPoint.WHOLE_BODY_COM:
        def swing_com(base, yaw, feet, leg, target):
            return model.swing_com_in_world(base, yaw, feet, leg, target, ws.swing_height_m)
    b = StepBuilder(base0, float(start_heading), feet0, thr, fold_shifts=fast,
                    swing_com=swing_com, foothold_check=foothold_check)
    if swing_com is not None:
        def moving_swing_com(base_start, base_end, yaw, feet, leg, target, **kw):
            return model.moving_swing_com_in_world(base_start, base_end, yaw, feet, leg,
                                                   target, ws.swing_height_m, **kw)
        b.moving_swing_com = moving_swing_com
    b.time_limit = slower_than
    try:
        return _walk_and_sample(model, policy, ws, wp, start_heading, tol, thr,
                                samples_per_unit, unit_time_s, b, fast=fast, omni=omni,
                                crawl=crawl, slower_than=slower_than)
    except TimeLimitReached as exc:
        raise NotFaster(exc.args[0]) from None


def _walk_and_sample(model: PlanningModel, policy: Policy, ws: Workspace, wp: np.ndarray,
                     start_heading: float, tol: float, thr: float, samples_per_unit: int,
                     unit_time_s: float, b: StepBuilder, *, fast: bool, omni: bool,
                     crawl: bool, slower_than: float | None) -> Plan:
    """The body of :func:`build_plan`, from the builder ``b`` at the start pose."""
    robot = model.planning_robot
    height = ws.height
    direction = "+x"
    crab_max = crab_limit(robot, float(height)) if fast else 0.0
    parity, n_half_total, spins, reached, t_reached = 0, 0, [], [], []
    half = ws.stride_m / 2.0
    passed: dict[int, tuple[float, float]] = {}    # omni: waypoint -> time window passing it
    aim = 0                                         # omni: the waypoint walked to next
    omni_distance = 0.0                             # omni: nominal CoG path [m]
    fast_distance = 0.0                             # facing the path: the same [m]
    crawler = CrawlOrCreep() if crawl else None
    walk_to = omni_to if crawler is None else crawler.to   # omni: crawl or creeping gait
    for k, target in enumerate(wp):
        b.waypoint_index, b.waypoint = k, (float(target[0]), float(target[1]))
        rel = rotation_z(-b.nominal_yaw)[:2, :2] @ (target - b.nominal_base[:2])   # eq 5.30
        dist = float(np.hypot(*rel))
        n_half = round(dist / half) if ws.half_cycles else 2 * round(dist / ws.stride_m)
        if omni:
            if k >= aim:
                aim = line_of_sight(wp, k, b.nominal_base[:2], tol)
                t0 = b.t
                if aim > k or dist > tol:
                    b.waypoint_index = aim
                    b.waypoint = (float(wp[aim, 0]), float(wp[aim, 1]))
                    def walk(aim=aim):
                        return walk_to(b, ws, wp[aim], robot.legs)
                    # the first segment is the same on many ditch routes (memoised)
                    n_half, walked = walk_first_segment(model, (
                        workspace_key(ws), thr, float(start_heading), crawl, aim,
                        wp[aim].tobytes(), b.swing_com is not None), b, crawler, walk)
                    n_half_total += n_half
                    omni_distance += walked
                passed.update({i: (t0, b.t) for i in range(k, aim)})
            if k in passed:                          # walked past: E_n where it came nearest
                reached.append(nearest_on_segment(wp[k], *passed[k], b))
                t_reached.append(passed[k][0])
                continue
        elif not fast:
            # §5.5 as written (issue 11): spin towards every waypoint off the body's axis
            # (more than the tolerance to the side or behind), then creep round(d / λ)
            # cycles, even zero; on the axis, creep only when it is more than the tolerance
            # ahead (§6.3: "a forward walk if the waypoint was more than 0.15 m away")
            def face_and_creep(k=k, rel=rel, n_half=n_half, parity=parity):
                """(parity, the turn or None, half cycles) of walking to waypoint k."""
                off_axis = abs(rel[1]) > tol or rel[0] < -tol
                turn = None
                if off_axis:
                    psi = math.atan2(rel[1], rel[0])
                    transition_to_spin(b, ws, direction, parity)
                    orders = spin(b, ws, psi)
                    parity = transition_from_spin(b, ws, direction)
                    turn = SpinRecord(k, psi, len(orders), thesis_spin_cycles(psi), tuple(
                        tuple(("LF", "RF", "LH", "RH")[i] for i in o) for o in orders))
                if not (off_axis or rel[0] > tol):
                    return parity, turn, 0
                for _ in range(n_half):
                    parity = creep_half_cycle(b, ws, direction, parity, 0.0)
                return parity, turn, n_half
            parity, turn, n_done = walk_first_segment(model, (   # (memoised from the start)
                workspace_key(ws), thr, float(start_heading), "plain", k, wp[k].tobytes(),
                tol, b.swing_com is not None), b, None, face_and_creep)
            spins += [turn] if turn is not None else []
            n_half_total += n_done
        elif dist > tol:
            # facing the path (default preset): ceil(d / (λ/2)) half cycles, the last one
            # shortened so the nominal CoG lands on the waypoint (docs/gaits.md)
            n_half = math.ceil(dist / half - 1e-9)
            last_m = dist - (n_half - 1) * half
            crab = 0.0
            angle = math.atan2(rel[1], rel[0])
            if fast and (abs(rel[1]) > tol or rel[0] < -tol) and abs(angle) <= crab_max:
                crab = angle
            elif abs(rel[1]) > tol or rel[0] < -tol:
                psi = angle if not fast else lookahead_turn(ws, wp, k, b.nominal_yaw, angle,
                                                            crab_max)
                crab = angle - psi if fast else 0.0
                if not fast:
                    transition_to_spin(b, ws, direction, parity)
                orders = spin(b, ws, psi)
                parity = 0 if fast else transition_from_spin(b, ws, direction)
                spins.append(SpinRecord(k, psi, len(orders), thesis_spin_cycles(psi), tuple(
                    tuple(("LF", "RF", "LH", "RH")[i] for i in o) for o in orders)))
            for i in range(n_half):
                short = i == n_half - 1 and last_m < half - 1e-12
                parity = creep_half_cycle(b, ws, direction, parity, crab,
                                          last_m if short else None)
                fast_distance += last_m if short else half
            n_half_total += n_half
        reached.append(b.nominal_base[:2].copy())
        t_reached.append(b.t)
    steps = tuple(b.steps)
    if slower_than is not None and b.t >= slower_than:
        raise NotFaster(b.t)
    if steps:
        traj = sample_steps(robot, steps, ws.swing_height_m, samples_per_unit, unit_time_s,
                            model=model, stability_point=policy.stability_point, smooth=omni)
        slack = SAMPLE_MARGIN_SLACK_M if b.swing_com is not None else 0.0
        verify_samples(robot.legs, traj, steps, thr, wp, slack_m=slack,
                       hold_tibias=policy.fast_gait)     # planner/trajectory/clearance.py
        check_interference(traj)                    # thesis §3.6 (planner/workspace/interference.py)
    else:
        traj = _standing(model, b, ws, unit_time_s, policy)
    t_reached_units = np.array(t_reached, dtype=float)
    rows = np.clip(np.round(t_reached_units * samples_per_unit).astype(int), 0, len(traj) - 1)
    for k, (t0, t1) in passed.items():       # the sample nearest the waypoint in its window
        lo, hi = (int(round(t * samples_per_unit)) for t in (t0, t1))
        hi = min(hi, len(traj) - 1)
        near = lo + int(np.argmin(np.hypot(*(traj.position_base_in_world[lo:hi + 1, :2]
                                             - wp[k]).T)))
        rows[k], t_reached_units[k] = near, near / samples_per_unit
    return Plan(waypoints_in_world=wp, height=float(height), workspace=ws, steps=steps,
                trajectory=traj, start_heading=float(start_heading), tolerance=tol,
                stability_threshold=thr, position_reached_in_world=np.array(reached),
                spins=tuple(spins), n_creep_half_cycles=n_half_total, n_shifts=b.n_shifts,
                n_folded_shifts=b.n_folded,
                policy=policy,
                gait=("crawl" if crawl else "omni") if omni else "fast" if fast else "plain",
                time_reached_units=t_reached_units,
                n_crawl_swings=0 if crawler is None else crawler.n_swings,
                nominal_distance_m=(omni_distance if omni else fast_distance if fast
                                    else None),
                position_walked_in_world=traj.position_base_in_world[rows, :2].copy())


def _standing(model: PlanningModel, b: StepBuilder, ws: Workspace, unit_time_s: float,
              policy: Policy) -> Trajectory:
    """One sample of the start pose when no step is needed."""
    still = Step(StepKind.BODY, None, 0.0, 1.0, b.base.copy(), b.base.copy(), b.yaw, b.yaw,
                 label="stand", position_feet_in_world=b.feet.copy(), phase=Phase.STAND)
    tr = sample_steps(model.planning_robot, (still,), ws.swing_height_m, 1, unit_time_s,
                      model=model, stability_point=policy.stability_point)
    return replace(tr, **{name: getattr(tr, name)[:1] for name in (
        "t", "position_base_in_world", "yaw_base_in_world", "q", "qd", "qdd",
        "position_foot_in_world", "contact", "margin", "margin_com", "margin_body", "phase")})
