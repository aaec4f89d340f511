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

The default preset walks in any direction without turning the body (planner/omni.py,
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

Stability point and swing height come from the preset's policy (planner/policy.py): the
default keeps the whole-robot CoM (legs included, as they move; planner/model.py) at least
the threshold inside the support triangle at every checked configuration of every swing,
and lifts the feet by at least policy.MIN_SWING_HEIGHT_M; the thesis keeps the body CoG
and eq 5.12. Every trajectory carries both margins (margin_com, margin_body).

``tolerance`` [m] defaults to DEFAULT_TOLERANCE_M; 0.15 m is the reduced-accuracy run of
Table 6.3. Then the samples are verified (IK reachable, joints within limits, no NaN, margin
>= threshold on every lift); any failure raises PlanningError naming the waypoint.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from silo4kin.robot import Robot

from .builder import FootholdCheck, StepBuilder, TimeLimitReached
from .crawl import CrawlOrCreep
from .errors import PlannerInputError, PlanningError
from .first_walk import walk_first_segment, workspace_key
from .gaits import (
    creep_half_cycle,
    creep_stance_in_base,
    rotation_z,
    spin,
    thesis_spin_cycles,
    transition_from_spin,
    transition_to_spin,
)
from .inputs import check_plan_inputs, waypoints_array
from .interference import check_interference
from .limits import limit_violation
from .model import PlanningModel, as_planning_model
from .omni import line_of_sight, nearest_on_segment, omni_to
from .policy import Policy, StabilityPoint, policy_for
from .sampling import sample_steps
from .steps import Phase, Step, StepKind
from .sway import shank_violation
from .trajectory import Trajectory
from .turns import crab_limit, lookahead_turn
from .verify import SAMPLE_MARGIN_SLACK_M, verify_samples
from .workspace import Workspace, workspace_for

#: Default lateral / reach tolerance [m]: "distance in x equal to zero" with 1 cm slack.
DEFAULT_TOLERANCE_M = 0.01
#: The default preset's gaits without turning (plan_path's ``gait``).
GAITS = ("auto", "crawl", "creep")


class _NotFaster(Exception):
    """A gait's steps take longer than the plan already in hand (plan_path, gait "auto")."""


@dataclass(frozen=True)
class SpinRecord:
    """One turn: waypoint index, total angle ψ [rad], cycles (ours and the thesis's count),
    leg order per cycle (leg names)."""

    waypoint_index: int
    psi_rad: float
    cycles: int
    thesis_cycles: int
    orders: tuple[tuple[str, ...], ...]


@dataclass(frozen=True, eq=False)
class Plan:
    """A planned path.

    Attributes:
        waypoints_in_world: (K, 2) [m], as given.
        height: body CoG height h [m].
        workspace: the :class:`~planner.workspace.Workspace` used.
        steps: the step list (planner/steps.py).
        trajectory: dense samples (planner/trajectory.py).
        start_heading: world yaw of the base x axis at t = 0 [rad].
        tolerance: [m] (module docstring).
        stability_threshold: minimum S_m required on every lift [m].
        position_reached_in_world: nominal CoG (x, y) when each waypoint was done, (K, 2) [m].
        spins: the turns made.
        n_creep_half_cycles: number of creeping half cycles (4 units each).
        n_shifts: stability shifts inserted (1 unit each).
        n_folded_shifts: stability shifts folded into a body phase (no time).
        policy: the preset's :class:`~planner.policy.Policy`.
        gait: "crawl" (the continuous crawl, planner/crawl.py), "omni" (the omnidirectional
            creeping gait, planner/omni.py), "fast" (facing the path,
            crab and look-ahead turns) or "plain" (§5.5 as written).
        fallback_reason: why a faster gait was not used (its PlanningError), or None.
        time_reached_units: time [units] when each waypoint was done, (K,).
        position_walked_in_world: the sampled CoG (x, y) at those times, (K, 2) [m] (what
            E_n measures: the CoG as walked, shifts included).
        height_search: with ``height="auto"``, how the height was chosen
            (:meth:`planner.height.HeightChoice.to_json`), else None.
        nominal_distance_m: length of the nominal CoG path [m] where the steps vary in length
            (omni gait); None where it is the count of creeping body phases x λ/2.
        n_crawl_swings: swings of the continuous crawl (body moving); its creeping half
            cycles (planner/crawl.py, CrawlOrCreep) are in n_creep_half_cycles.
    """

    waypoints_in_world: np.ndarray
    height: float
    workspace: Workspace
    steps: tuple[Step, ...]
    trajectory: Trajectory
    start_heading: float
    tolerance: float
    stability_threshold: float
    position_reached_in_world: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    spins: tuple[SpinRecord, ...] = ()
    n_creep_half_cycles: int = 0
    n_shifts: int = 0
    n_folded_shifts: int = 0
    policy: Policy = field(default_factory=lambda: policy_for("default"))
    gait: str = "plain"
    fallback_reason: str | None = None
    time_reached_units: np.ndarray = field(default_factory=lambda: np.zeros(0))
    position_walked_in_world: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    height_search: dict | None = None
    nominal_distance_m: float | None = None
    n_crawl_swings: int = 0


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
    that walks the path in the least time (planner/height.py, thesis §7.2), recorded in
    ``Plan.height_search``. ``swing_height_m`` [m] overrides the policy's swing
    height (default: eq 5.12, at least policy.MIN_SWING_HEIGHT_M for the default preset).
    ``face_path`` keeps the thesis's habit of facing each segment (spin, then creep forward)
    in the default preset instead of walking in any direction without turning
    (planner/omni.py). ``gait`` picks the default preset's gait without turning: "crawl"
    (the continuous crawl, planner/crawl.py), "creep" (the omnidirectional creeping gait,
    planner/omni.py) or "auto" (both, the one that takes less time; the crawl on a tie);
    ``Plan.gait`` says which walked ("crawl" or "omni"). The thesis preset ignores it.
    ``foothold_check`` is called with every foothold (3,) in W [m] as a step places it
    (planner/builder.py; a pure function of the foothold: it may see one twice). An
    exception it raises abandons the candidate gait being built (gait "auto" tries the
    other; the last one's exception propagates), except inside the continuous crawl, which
    undoes the swing that placed the foothold and walks a creeping half cycle from there,
    its footholds checked too (planner/crawl.py CrawlOrCreep). The
    ditch's route search rejects a gait at its first foothold in the ditch (planner/ditch.py).

    Raises:
        PlannerInputError: bad waypoints, height, preset or parameters.
        PlanningError: no stable or reachable step for a waypoint (named in the message).
    """
    check_plan_inputs(robot, waypoints_in_world, height, start_heading, workspace, tolerance,
                      samples_per_unit, unit_time_s, stability_threshold)  # planner/inputs.py
    if gait not in GAITS:
        raise PlannerInputError(f"gait must be one of {list(GAITS)}, got {gait!r}")
    wp = waypoints_array(waypoints_in_world)
    if foothold_check is not None and not callable(foothold_check):
        raise PlannerInputError(f"foothold_check must be a function of a foothold (3,) [m] or "
                                f"None, got {type(foothold_check).__name__}")
    if isinstance(height, str):
        if height != "auto":
            raise PlannerInputError(f"height must be a number [m] or 'auto', got {height!r}")
        from .height import best_height

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
        return _plan(*args, fast=False)
    omni_reason = None
    if not face_path:
        # a foothold_check rejection rules out one candidate gait, not the plan: the check
        # applies to the plan that is returned (the ditch route search, planner/ditch.py)
        cargs = args if foothold_check is None else (*args[:-1], _candidate(foothold_check))
        crawl, crawl_reason = None, None
        if gait == "auto" and model.family != "insect":
            # the crawl is checked in physics on insect legs only: a mammal's crawl slipped
            # and drifted where its creeping gait walks (docs/robots.md); ask with gait="crawl"
            crawl_reason = (f"continuous crawl: not the default for {model.family} legs "
                            f"(not validated in physics; gait='crawl' plans it)")
        elif gait in ("auto", "crawl"):
            try:
                crawl = _plan(*cargs, fast=True, omni=True, crawl=True)
                # the crawl moves body and swing leg together: it may need more speed or
                # torque than the creeping gait, so it is kept only within the URDF limits
                # at this unit time (planner/limits.py; `silo4 plan` checks every plan),
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
            creep = _plan(*cargs, fast=True, omni=True,
                          slower_than=None if crawl is None else crawl_units)
            return replace(creep, fallback_reason=crawl_reason)
        except _NotFaster:
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
        return replace(_plan(*args, fast=True), fallback_reason=omni_reason)
    except PlanningError as exc:
        # the faster gait left the checked reserves (e.g. a swing straight from a creeping
        # foothold to a rotated one on a robot with other leg lengths): plan as before, and
        # say so in the plan
        reason = str(exc) if omni_reason is None else f"{omni_reason}; fast gait: {exc}"
        return replace(_plan(*args, fast=False), fallback_reason=reason)


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


def _plan(model: PlanningModel, policy: Policy, ws: Workspace, wp: np.ndarray,
          start_heading: float, tol: float, thr: float, samples_per_unit: int,
          unit_time_s: float, foothold_check: FootholdCheck | None, *, fast: bool,
          omni: bool = False, crawl: bool = False, slower_than: float | None = None) -> Plan:
    """Steps, samples and verification of :func:`plan_path`; ``fast`` enables the default
    preset's crab gait, lookahead turns, spins without transitions and folded shifts
    (module docstring); ``omni`` walks without turning, by the continuous crawl with
    ``crawl``. With ``slower_than`` [units], :class:`_NotFaster` is raised as soon as the
    steps take at least that long (the builder's time limit: the rest is not built)."""
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
        raise _NotFaster(exc.args[0]) from None


def _walk_and_sample(model: PlanningModel, policy: Policy, ws: Workspace, wp: np.ndarray,
                     start_heading: float, tol: float, thr: float, samples_per_unit: int,
                     unit_time_s: float, b: StepBuilder, *, fast: bool, omni: bool,
                     crawl: bool, slower_than: float | None) -> Plan:
    """The body of :func:`_plan`, from the builder ``b`` at the start pose."""
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
                    if not b.steps:     # the first segment: the same on many ditch routes
                        n_half, walked = walk_first_segment(model, (
                            workspace_key(ws), thr, float(start_heading), crawl, aim,
                            wp[aim].tobytes(), b.swing_com is not None), b, crawler, walk)
                    else:
                        n_half, walked = walk()
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
            off_axis = abs(rel[1]) > tol or rel[0] < -tol
            if off_axis:
                psi = math.atan2(rel[1], rel[0])
                transition_to_spin(b, ws, direction, parity)
                orders = spin(b, ws, psi)
                parity = transition_from_spin(b, ws, direction)
                spins.append(SpinRecord(k, psi, len(orders), thesis_spin_cycles(psi), tuple(
                    tuple(("LF", "RF", "LH", "RH")[i] for i in o) for o in orders)))
            if off_axis or rel[0] > tol:
                for _ in range(n_half):
                    parity = creep_half_cycle(b, ws, direction, parity, 0.0)
                n_half_total += n_half
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
        raise _NotFaster(b.t)
    if steps:
        traj = sample_steps(robot, steps, ws.swing_height_m, samples_per_unit, unit_time_s,
                            model=model, stability_point=policy.stability_point, smooth=omni)
        slack = SAMPLE_MARGIN_SLACK_M if b.swing_com is not None else 0.0
        verify_samples(robot.legs, traj, steps, thr, wp, slack_m=slack)
        check_interference(traj)                    # thesis §3.6 (planner/interference.py)
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
