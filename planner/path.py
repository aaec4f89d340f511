"""Path following (thesis §5.4-5.5): waypoints in W -> checked steps -> dense samples.

The robot starts at (0, 0) with the CoG at height h, heading ``start_heading`` (thesis: facing
its +y, i.e. π/2 in a REP-103 world), in the forward creeping stance. For each waypoint, in the
base frame (eq 5.29-5.30: p_CoG = Qᵀ(p_W - p_o), from the nominal CoG, i.e. without stability
shifts):

1. n = round(d / (λ/2)) half cycles for the straight-line distance d (default preset; the
   thesis preset rounds d/λ to whole cycles, §5.5). n = 0 or d <= tolerance: reached.
2. Spin to face it (transition, ceil(|ψ|/ψ_max) spinning cycles, transition) when its lateral
   offset exceeds the tolerance or it lies behind by more than the tolerance (§5.5 case 2;
   the thesis's "distance in x equal to zero" needs a tolerance).
3. Creep forward n half cycles; the nominal CoG is tracked in W (eq 5.31-5.32).

The default preset is faster with the same checks (the thesis preset keeps the rules above):
- a waypoint needing a turn but at most gaits.crab_limit_rad off the heading is walked to at
  that crab angle (thesis §4.1), without a spin;
- a turn only brings the waypoint within the crab range: of the turns with the fewest
  spinning cycles, the one keeping the most following path legs in range
  (:func:`_lookahead_turn`);
- no transitions: the first spinning cycle starts from the creeping stance and the creep
  starts from the spin stance (its first pair swings from position 2 to the front);
- stability shifts are folded into the last body phase or spin rotation (StepBuilder).
If that plan fails its verification (these moves go beyond the workspace's checked reserves
on some robots), the path is planned again without them, as before.

``tolerance`` [m] defaults to DEFAULT_TOLERANCE_M; 0.15 m is the reduced-accuracy run of
Table 6.3. Then the samples are verified (IK reachable, joints within limits, no NaN, margin
>= threshold on every lift); any failure raises PlanningError naming the waypoint.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import lru_cache

import numpy as np

from silo4kin.discovery import legs_in_body_com_frame
from silo4kin.robot import Robot

from .errors import PlannerInputError, PlanningError
from .gaits import (
    crab_limit_rad,
    creep_half_cycle,
    creep_stance_in_base,
    rotation_z,
    spin,
    spin_cycles,
    transition_from_spin,
    transition_to_spin,
)
from .inputs import check_plan_inputs
from .sampling import sample_steps
from .stability import MARGIN_TOLERANCE
from .steps import Step, StepBuilder
from .trajectory import Trajectory
from .workspace import JOINT_LIMIT_TOLERANCE, Workspace, workspace_for

#: Default lateral / reach tolerance [m]: "distance in x equal to zero" with 1 cm slack.
DEFAULT_TOLERANCE_M = 0.01
#: Turns tried between the two ends of the crab range, and the slack kept on the following
#: path legs (their actual start is the reached CoG, up to λ/4 off the waypoint) [rad].
LOOKAHEAD_SAMPLES = 61
LOOKAHEAD_SLACK_RAD = math.radians(5.0)
#: Most samples per time unit accepted (memory guard: 10 000 units x 1000 = 1e7 rows).
MAX_SAMPLES_PER_UNIT = 1000


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


def _validate(waypoints, samples_per_unit, unit_time_s, tolerance, start_heading,
              stability_threshold) -> np.ndarray:
    try:
        wp = np.array(waypoints, dtype=float)
    except (TypeError, ValueError) as exc:
        raise PlannerInputError(f"waypoints must be numbers, shape (K, 2): {exc}") from None
    if wp.ndim == 1 and wp.size == 2:
        wp = wp[None]
    if wp.ndim != 2 or wp.shape[1] != 2 or wp.shape[0] < 1:
        raise PlannerInputError(f"waypoints must have shape (K, 2) with K >= 1, got {wp.shape}")
    bad = np.flatnonzero(~np.all(np.isfinite(wp), axis=1))
    if bad.size:
        raise PlannerInputError(f"waypoint {bad[0]} is not finite: {wp[bad[0]].tolist()}")
    if (isinstance(samples_per_unit, bool) or not isinstance(samples_per_unit, (int, np.integer))
            or not 1 <= samples_per_unit <= MAX_SAMPLES_PER_UNIT):
        raise PlannerInputError(f"samples_per_unit must be an integer in [1, "
                                f"{MAX_SAMPLES_PER_UNIT}], got {samples_per_unit!r}")
    for name, v, lo_ok in (("unit_time_s", unit_time_s, False), ("tolerance", tolerance, True),
                           ("stability_threshold", stability_threshold, True)):
        if v is None:
            continue
        if not isinstance(v, (int, float, np.floating)) or not np.isfinite(v) or v < 0 or (
                v == 0 and not lo_ok):
            allowed = "a finite number >= 0" if lo_ok else "a finite number > 0"
            raise PlannerInputError(f"{name} must be {allowed}, got {v!r}")
    if not np.isfinite(start_heading):
        raise PlannerInputError(f"start_heading must be finite [rad], got {start_heading!r}")
    return wp


@lru_cache(maxsize=16)
def robot_in_body_com_frame(robot: Robot) -> Robot:
    """The robot with its hips measured from the body CoG, the frame B the planner works in
    (design.md). For SILO4 the URDF root is the CoG and the robot is returned unchanged; for
    another URDF (tests/robots/mantis.urdf: CoG 4.5 cm ahead of and 4.2 cm above the root)
    only ``LegGeometry.position_hip_in_base`` moves, joint values are unaffected. Cached per
    robot object, so the workspace caches keyed on it stay warm across plans."""
    com = np.asarray(robot.position_body_com_in_base, dtype=float)
    if not np.any(com):
        return robot
    return replace(robot, legs=legs_in_body_com_frame(robot.legs, com))


def plan_path(robot, waypoints_in_world, height: float, *, start_heading: float = np.pi / 2,
              workspace: str = "default", tolerance: float | None = None,
              samples_per_unit: int = 100, unit_time_s: float = 1.0,
              stability_threshold: float | None = None) -> Plan:
    """Plan statically stable walking through ``waypoints_in_world`` (K, 2) [m] at CoG height
    ``height`` [m] (module docstring).

    Raises:
        PlannerInputError: bad waypoints, height, preset or parameters.
        PlanningError: no stable or reachable step for a waypoint (named in the message).
    """
    check_plan_inputs(robot, waypoints_in_world, height, start_heading, workspace, tolerance,
                      samples_per_unit, unit_time_s, stability_threshold)  # planner/inputs.py
    wp = _validate(waypoints_in_world, samples_per_unit, unit_time_s, tolerance,
                   start_heading, stability_threshold)
    robot = robot_in_body_com_frame(robot)
    ws = workspace_for(robot, height, workspace)
    tol = DEFAULT_TOLERANCE_M if tolerance is None else float(tolerance)
    thr = ws.stability_threshold_m if stability_threshold is None else float(stability_threshold)
    if ws.preset == "thesis":
        return _plan(robot, ws, wp, start_heading, tol, thr, samples_per_unit, unit_time_s,
                     fast=False)
    try:
        return _plan(robot, ws, wp, start_heading, tol, thr, samples_per_unit, unit_time_s,
                     fast=True)
    except PlanningError:
        # the faster gait left the checked reserves (e.g. a swing straight from a creeping
        # foothold to a rotated one on a robot with other leg lengths): plan as before
        return _plan(robot, ws, wp, start_heading, tol, thr, samples_per_unit, unit_time_s,
                     fast=False)


def _plan(robot, ws: Workspace, wp: np.ndarray, start_heading: float, tol: float,
          thr: float, samples_per_unit: int, unit_time_s: float, *, fast: bool) -> Plan:
    """Steps, samples and verification of :func:`plan_path`; ``fast`` enables the default
    preset's crab gait, lookahead turns, spins without transitions and folded shifts
    (module docstring)."""
    height = ws.height
    direction = "+x"
    base0 = np.array([0.0, 0.0, float(height)])
    feet0 = base0 + (rotation_z(start_heading) @ creep_stance_in_base(ws, direction, 0).T).T
    crab_max = _crab_limit(robot, float(height)) if fast else 0.0
    b = StepBuilder(base0, float(start_heading), feet0, thr, fold_shifts=fast)
    parity, n_half_total, spins, reached = 0, 0, [], []
    half = ws.stride_m / 2.0
    for k, target in enumerate(wp):
        b.waypoint_index, b.waypoint = k, (float(target[0]), float(target[1]))
        rel = rotation_z(-b.nominal_yaw)[:2, :2] @ (target - b.nominal_base[:2])   # eq 5.30
        dist = float(np.hypot(*rel))
        n_half = round(dist / half) if ws.half_cycles else 2 * round(dist / ws.stride_m)
        if n_half > 0 and dist > tol:
            crab = 0.0
            angle = math.atan2(rel[1], rel[0])
            if fast and (abs(rel[1]) > tol or rel[0] < -tol) and abs(angle) <= crab_max:
                crab = angle
            elif abs(rel[1]) > tol or rel[0] < -tol:
                psi = angle if not fast else _lookahead_turn(ws, wp, k, b.nominal_yaw, angle,
                                                             crab_max)
                crab = angle - psi if fast else 0.0
                if not fast:
                    transition_to_spin(b, ws, direction, parity)
                orders = spin(b, ws, psi)
                parity = 0 if fast else transition_from_spin(b, ws, direction)
                spins.append(SpinRecord(k, psi, len(orders), _thesis_cycles(psi), tuple(
                    tuple(("LF", "RF", "LH", "RH")[i] for i in o) for o in orders)))
            for _ in range(n_half):
                parity = creep_half_cycle(b, ws, direction, parity, crab)
            n_half_total += n_half
        reached.append(b.nominal_base[:2].copy())
    steps = tuple(b.steps)
    if steps:
        traj = sample_steps(robot, steps, ws.swing_height_m, samples_per_unit, unit_time_s)
        _verify(robot, traj, steps, thr, wp, samples_per_unit)
    else:
        traj = _standing(robot, b, ws, unit_time_s)
    return Plan(waypoints_in_world=wp, height=float(height), workspace=ws, steps=steps,
                trajectory=traj, start_heading=float(start_heading), tolerance=tol,
                stability_threshold=thr, position_reached_in_world=np.array(reached),
                spins=tuple(spins), n_creep_half_cycles=n_half_total, n_shifts=b.n_shifts)


@lru_cache(maxsize=64)
def _crab_limit(robot: Robot, height: float) -> float:
    """gaits.crab_limit_rad of the default workspace, cached per robot and height [rad]."""
    return crab_limit_rad(robot, workspace_for(robot, height, "default"))


def _wrap(angle: float) -> float:
    """angle [rad] wrapped to (-π, π]."""
    return math.pi - (math.pi - angle) % (2.0 * math.pi)


def _lookahead_turn(ws: Workspace, wp: np.ndarray, k: int, yaw: float, angle: float,
                    crab_max: float) -> float:
    """The turn ψ [rad] before walking to waypoint k, which lies ``angle`` [rad] off the
    heading ``yaw``: any ψ leaving it within ±``crab_max`` [rad] of the new heading will do, so
    among those needing the fewest spinning cycles take the ones under which the most of the
    following path legs (waypoint to waypoint, in order) stay within the crab range less
    LOOKAHEAD_SLACK_RAD, and of those the middle one (when no leg stays in range: the one
    nearest ψ = angle, facing the waypoint)."""
    grid = np.linspace(angle - crab_max, angle + crab_max, LOOKAHEAD_SAMPLES)
    cycles = np.array([spin_cycles(ws, float(psi)) for psi in grid])
    grid = grid[cycles == cycles.min()]
    legs = np.diff(wp[k:], axis=0)
    headings = [math.atan2(v[1], v[0]) for v in legs if math.hypot(v[0], v[1]) > 1e-9]
    runs = []
    for psi in grid:
        run = 0
        for h in headings:
            if abs(_wrap(h - yaw - psi)) > crab_max - LOOKAHEAD_SLACK_RAD:
                break
            run += 1
        runs.append(run)
    if max(runs) == 0:
        return float(grid[np.argmin(np.abs(grid - angle))])
    best = grid[np.array(runs) == max(runs)]
    return float(best[len(best) // 2])


def _thesis_cycles(psi: float) -> int:
    from .gaits import thesis_spin_cycles
    return thesis_spin_cycles(psi)


def _standing(robot, b: StepBuilder, ws: Workspace, unit_time_s: float) -> Trajectory:
    """One sample of the start pose when no step is needed."""
    still = Step("body", None, 0.0, 1.0, b.base.copy(), b.base.copy(), b.yaw, b.yaw,
                 label="stand", position_feet_in_world=b.feet.copy())
    tr = sample_steps(robot, (still,), ws.swing_height_m, 1, unit_time_s)
    return replace(tr, **{name: getattr(tr, name)[:1] for name in (
        "t", "position_base_in_world", "yaw_base_in_world", "q", "qd", "qdd",
        "position_foot_in_world", "contact", "margin", "phase")})


def _verify(robot, traj: Trajectory, steps: tuple[Step, ...], threshold: float,
            wp: np.ndarray, samples_per_unit: int) -> None:
    """Raise PlanningError at the first sample that is unreachable, off limits, or unstable."""
    lower = np.concatenate([leg.q_lower for leg in robot.legs]) - JOINT_LIMIT_TOLERANCE
    upper = np.concatenate([leg.q_upper for leg in robot.legs]) + JOINT_LIMIT_TOLERANCE
    q = traj.q
    finite = np.all(np.isfinite(q) & np.isfinite(traj.qd) & np.isfinite(traj.qdd), axis=1)
    within = np.all((q >= lower) & (q <= upper), axis=1)
    lifted = ~np.all(traj.contact, axis=1)
    stable = ~lifted | (traj.margin >= threshold - MARGIN_TOLERANCE)
    bad = np.flatnonzero(~(finite & within & stable))
    if not bad.size:
        return
    i = int(bad[0])
    t_units = traj.time_units[i]
    starts = np.array([s.t_start for s in steps])
    step = steps[int(np.clip(np.searchsorted(starts, t_units, side="right") - 1, 0,
                             len(steps) - 1))]
    if not finite[i]:
        reason = f"a foot target is out of reach or singular at t = {t_units:.2f} units"
    elif not within[i]:
        j = int(np.flatnonzero((q[i] < lower) | (q[i] > upper))[0])
        reason = (f"joint {traj.joint_names[j]} = {q[i, j]:.4f} rad leaves "
                  f"[{lower[j]:.4f}, {upper[j]:.4f}] at t = {t_units:.2f} units")
    else:
        reason = (f"stability margin {traj.margin[i]:.4f} m < threshold {threshold:.4f} m "
                  f"at t = {t_units:.2f} units")
    k = step.waypoint_index
    raise PlanningError(f"{reason} ({step.label})", k,
                        None if k is None else (float(wp[k, 0]), float(wp[k, 1])))
