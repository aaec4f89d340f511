"""Facing the path, the default preset's gait ``facing`` (planner/gaits/base.py): spin to face
each segment, then creep, faster than §5.5 with the same checks:

- ceil(d / (λ/2)) half cycles, the last one shortened, so the nominal CoG lands on the
  waypoint (metrics.tolerance_warning says so if a plan still misses it);
- a waypoint needing a turn but at most :func:`crab_limit` off the heading is walked to at
  that crab angle (thesis §4.1), without a spin;
- a turn only brings the waypoint within the crab range: of the turns with the fewest
  spinning cycles, the one keeping the most following path legs in range
  (:func:`lookahead_turn`);
- no transitions: the first spinning cycle starts from the creeping stance and the creep
  starts from the spin stance (its first pair swings from position 2 to the front);
- stability shifts are folded into the last body phase or spin rotation (StepBuilder).

These moves go beyond the workspace's checked reserves on some robots; the registry's
"facing" falls back to the plain creeping and spinning gait then (``plain``,
planner/gaits/thesis_walk.py), and the plan says why (``Plan.fallback_reason``).

Where the stance turns less than MIN_DEFAULT_SPIN_RAD per cycle (walk.can_turn: the
feasible heights do not ask for a spin, planner/workspace/heights.py), the heading stays the
start heading: a waypoint within the crab range behind is walked to backwards (:func:`reverse`:
the creeping gait along -x, entered through the stances of the one along +x), and one that
needs a turn is refused naming the heights where the robot turns (walk.check_can_spin).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from planner.errors import FootholdRefused
from planner.gaits.base import PlanRequest
from planner.gaits.builder import StepBuilder
from planner.gaits.creep_spin import (
    _to_world,
    crab_limit_rad,
    creep_half_cycle,
    creep_pairs,
    foothold_in_base,
    spin,
    spin_cycles,
)
from planner.gaits.creep_spin_duration import fewest_facing_units
from planner.gaits.steps import SHIFT_UNITS, Phase, StepKind
from planner.gaits.thesis_walk import spin_record
from planner.gaits.walk import Walked, can_turn, check_can_spin, walk_plan
from planner.plan import Plan
from planner.trajectory.samples import LEGS
from planner.workspace.layout import Workspace, workspace_for
from silo4kin.frames import rotation_z
from silo4kin.robot import Robot

#: On a terrain file's surfaces, the fractions of a refused half cycle's body phase tried
#: instead, longest first (:func:`creep_on_surfaces`).
SHORTER_STEP_FRACTIONS = (0.75, 0.5, 0.25)
#: Turns tried between the two ends of the crab range, and the slack kept on the following
#: path legs (their actual start is the reached CoG, up to λ/4 off the waypoint) [rad].
LOOKAHEAD_SAMPLES = 61
LOOKAHEAD_SLACK_RAD = math.radians(5.0)
#: The other creeping direction along the body axis (walking backwards where the stance
#: cannot turn, :meth:`FacingPath._walk`).
REVERSE = {"+x": "-x", "-x": "+x"}


@lru_cache(maxsize=64)
def crab_limit(robot: Robot, height: float, preset: str = "default") -> float:
    """gaits.crab_limit_rad of the preset's workspace, cached per robot, height and preset
    name [rad]."""
    return crab_limit_rad(robot, workspace_for(robot, height, preset))


def wrap(angle: float) -> float:
    """angle [rad] wrapped to (-π, π]."""
    return math.pi - (math.pi - angle) % (2.0 * math.pi)


def lookahead_turn(
    ws: Workspace, wp: np.ndarray, k: int, yaw: float, angle: float, crab_max: float
) -> float:
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
            if abs(wrap(h - yaw - psi)) > crab_max - LOOKAHEAD_SLACK_RAD:
                break
            run += 1
        runs.append(run)
    if max(runs) == 0:
        return float(grid[np.argmin(np.abs(grid - angle))])
    best = grid[np.array(runs) == max(runs)]
    return float(best[len(best) // 2])


@dataclass(frozen=True)
class FacingPath:
    """Face each segment: crab angles, look-ahead turns, no transitions, folded shifts
    (module docstring)."""

    name: str = "facing"
    label: str = "fast gait"
    #: quintic profiles of eq 5.16 and the smooth lift (q̈ continuous: the default's
    #: fallback under strict planning, planner/path/at_height.py) instead of the thesis's
    #: cosine blends (gait "facing" asked for by name)
    smooth: bool = False

    def plan(self, request: PlanRequest, slower_than: float | None = None) -> Plan:
        return walk_plan(
            request,
            self.name,
            lambda b, w: self._walk(request, b, w),
            fold_shifts=True,
            smooth=self.smooth,
            slower_than=slower_than,
        )

    def fewest_units(self, request: PlanRequest) -> float:
        """A lower bound [units] on the duration of this gait's plan of ``request``, found
        without building a step (planner/gaits/creep_spin_duration.py)."""
        return fewest_facing_units(request.workspace, request.waypoints_in_world, request.tolerance)

    def _walk(self, request: PlanRequest, b: StepBuilder, walked: Walked) -> None:
        ws, wp, tol = request.workspace, request.waypoints_in_world, request.tolerance
        crab_max = crab_limit(request.model.planning_robot, float(ws.height), request.preset.name)
        half = ws.stride_m / 2.0
        direction, parity = "+x", 0
        turns = can_turn(request)
        walked.nominal_distance_m = 0.0
        for k, target in enumerate(wp):
            b.waypoint_index, b.waypoint = k, (float(target[0]), float(target[1]))
            rel = rotation_z(-b.nominal_yaw)[:2, :2] @ (target - b.nominal_base[:2])  # eq 5.30
            dist = float(np.hypot(*rel))
            if dist > tol:
                n_half = math.ceil(dist / half - 1e-9)
                last_m = dist - (n_half - 1) * half
                crab = 0.0
                ahead = rel if direction == "+x" else -rel  # along the walking direction
                angle = math.atan2(ahead[1], ahead[0])
                off_axis = abs(ahead[1]) > tol or ahead[0] < -tol
                if off_axis and abs(angle) <= crab_max:
                    crab = angle
                elif off_axis and not turns:
                    # behind: walk backwards, at a crab angle off the other direction, or
                    # straight where the waypoint is within the tolerance of its axis
                    crab = wrap(angle - math.pi)
                    if abs(crab) > crab_max:
                        if abs(ahead[1]) > tol:
                            check_can_spin(request, self.name, k, target)  # refuses
                        crab = 0.0
                    direction, parity = reverse(b, ws, direction, parity)
                elif off_axis:
                    check_can_spin(request, self.name, k, target)
                    psi = lookahead_turn(ws, wp, k, b.nominal_yaw, angle, crab_max)
                    crab = angle - psi
                    orders = spin(b, ws, psi)
                    parity = 0
                    walked.spins.append(spin_record(k, psi, orders))
                if b.surface_footholds is None:
                    for i in range(n_half):
                        short = i == n_half - 1 and last_m < half - 1e-12
                        parity = creep_half_cycle(
                            b, ws, direction, parity, crab, last_m if short else None
                        )
                        walked.nominal_distance_m += last_m if short else half
                    walked.n_half_cycles += n_half
                else:
                    parity = creep_on_surfaces(b, ws, direction, parity, crab, dist, walked)
                if not turns:
                    arrive(b)
            walked.reached.append(b.nominal_base[:2].copy())
            walked.t_reached.append(b.t)
        # folded shifts leave the body off the nominal CoG when a waypoint is reached; it
        # comes back to it on the next base move (a spin's rotation or the next segment's
        # first body phase): E_n (eq 6.1) takes where the CoG as walked comes nearest each
        # waypoint between its arrival and the next one's
        for k in range(len(wp) - 1):
            walked.passed[k] = (walked.t_reached[k], walked.t_reached[k + 1])


def arrive(b: StepBuilder) -> None:
    """The body back on the nominal CoG (the waypoint just reached) where the last body phase
    carried a folded stability shift, and kept there: no later shift folds into that move
    (StepBuilder.fold_fence). Where the stance cannot turn the heading never changes, and
    the walk on may start backwards or at a crab angle from the shifted body without passing
    the waypoint (mantis at 0.5374 m, walking back along its body: 42 mm, E_n eq 6.1)."""
    if float(np.hypot(*(b.base[:2] - b.nominal_base[:2]))) > 1e-9:
        b.body(
            b.nominal_base,
            b.nominal_yaw,
            b.four_foot_units(b.nominal_base, SHIFT_UNITS),
            StepKind.BODY,
            "arrive",
            Phase.CREEP,
        )
    b.fold_fence = len(b.steps)


def reverse(b: StepBuilder, ws: Workspace, direction: str, parity: int) -> tuple[str, int]:
    """Turn the creeping gait along ``direction`` into the one along the other direction of
    the same axis, without turning the stance; returns the new (direction, parity). The body
    first on the nominal CoG (:func:`arrive`); then the pair at its rear footholds swings to
    its front ones, as the next half cycle would, and the body stays: the pair now stands at
    the rear footholds of the other direction, the other pair at position 2, which is that
    direction's creeping stance with this pair about to swing. Every stance on the way is
    one of the creeping gait's own along ``direction`` (the thesis's transitions through
    position 2, §5.5, are not: phasmid at 0.5303 m took LF_hip_pitch past its limit in
    them, walking back along its body)."""
    arrive(b)
    first, second = creep_pairs(ws, direction)
    pair = first if parity == 0 else second
    for leg in pair:
        foothold = foothold_in_base(ws, leg, direction, "front")
        b.transfer(leg, _to_world(b, foothold), f"reverse transfer {LEGS[leg]}", Phase.TRANSITION)
    other = REVERSE[direction]
    first, _ = creep_pairs(ws, other)
    return other, 0 if set(first) == set(pair) else 1


def creep_on_surfaces(
    b: StepBuilder,
    ws: Workspace,
    direction: str,
    parity: int,
    crab: float,
    distance_m: float,
    walked: Walked,
) -> int:
    """Creep ``distance_m`` [m] in half cycles of λ/2 on a terrain file's surfaces, the last
    one shortened to land on the waypoint, as over flat ground; returns the new parity.

    A half cycle the terrain refuses (FootholdRefused: no foothold near the nominal one, or
    a stance foot out of reach after the body phase) is tried again, from the same state,
    with its body phase shortened to SHORTER_STEP_FRACTIONS of its length, longest first:
    a foothold the search moved back from an edge (before a gap, a block, a riser) leaves
    its leg less travel than a stride, and the next body phase of λ/2 carries it out of
    reach; a shorter one keeps it in reach and moves the following footholds against the
    terrain. The distance left is then walked as before (half cycles of λ/2, the last one
    shortened). When every fraction is refused too, the first refusal is raised.
    """
    half = ws.stride_m / 2.0
    left = float(distance_m)
    while left > 1e-12:
        step = min(half, left)
        state = b.snapshot()
        try:
            parity = creep_half_cycle(
                b, ws, direction, parity, crab, step if step < half - 1e-12 else None
            )
        except FootholdRefused as refused:
            for fraction in SHORTER_STEP_FRACTIONS:
                b.restore(state)
                try:
                    parity = creep_half_cycle(b, ws, direction, parity, crab, fraction * step)
                except FootholdRefused:
                    continue
                step = fraction * step
                break
            else:
                raise refused
        left -= step
        walked.nominal_distance_m = (walked.nominal_distance_m or 0.0) + step
        walked.n_half_cycles += 1
    return parity
