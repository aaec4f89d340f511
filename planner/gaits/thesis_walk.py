"""The creeping and spinning gait of thesis §5.5 as written, as a gait (planner/gaits/base.py).

For each waypoint, in the base frame (eq 5.29-5.30: p_CoG = Qᵀ(p_W - p_o), from the nominal
CoG, i.e. without stability shifts): n = round(d / (λ/2)) half cycles where the workspace
walks half cycles (default preset), else 2 round(d / λ) (the thesis preset: whole cycles);
spin towards every waypoint off the body's axis (more than the tolerance to the side or
behind: transition, spinning cycles, transition) and then creep those n half cycles, even
zero; on the axis, creep only when it is more than the tolerance ahead (§6.3: "a forward
walk if the waypoint was more than 0.15 m away"). The nominal CoG is tracked in W
(eq 5.31-5.32).

Named ``thesis`` in the thesis preset and ``plain`` in the default one (where it is the
last fallback of facing the path, planner/gaits/facing.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.gaits.base import PlanRequest
from planner.gaits.builder import StepBuilder
from planner.gaits.creep_spin import (
    creep_half_cycle,
    spin,
    thesis_spin_cycles,
    transition_from_spin,
    transition_to_spin,
)
from planner.gaits.creep_spin_duration import fewest_creep_spin_units
from planner.gaits.first_walk import walk_first_segment, workspace_key
from planner.gaits.walk import Walked, check_can_spin, walk_plan
from planner.plan import Plan, SpinRecord
from planner.trajectory.samples import LEGS
from silo4kin.frames import rotation_z


def spin_record(k: int, psi: float, orders: list) -> SpinRecord:
    """The SpinRecord of a turn ψ [rad] before waypoint k walked in the leg ``orders``."""
    return SpinRecord(
        k,
        psi,
        len(orders),
        thesis_spin_cycles(psi),
        tuple(tuple(LEGS[i] for i in o) for o in orders),
    )


@dataclass(frozen=True)
class CreepSpin:
    """Spin to face each waypoint off the body's axis, then creep to it (module docstring)."""

    name: str = "thesis"
    label: str = "creeping and spinning gait"

    def plan(self, request: PlanRequest, slower_than: float | None = None) -> Plan:
        return walk_plan(
            request,
            self.name,
            lambda b, w: self._walk(request, b, w),
            fold_shifts=False,
            smooth=False,
            slower_than=slower_than,
        )

    def fewest_units(self, request: PlanRequest) -> float:
        """A lower bound [units] on the duration of this gait's plan of ``request``, found
        without building a step (planner/gaits/creep_spin_duration.py)."""
        return fewest_creep_spin_units(
            request.workspace, request.waypoints_in_world, request.tolerance
        )

    def _walk(self, request: PlanRequest, b: StepBuilder, walked: Walked) -> None:
        ws, wp, tol = request.workspace, request.waypoints_in_world, request.tolerance
        direction, parity = "+x", 0
        for k, target in enumerate(wp):
            b.waypoint_index, b.waypoint = k, (float(target[0]), float(target[1]))
            rel = rotation_z(-b.nominal_yaw)[:2, :2] @ (target - b.nominal_base[:2])  # eq 5.30
            dist = float(np.hypot(*rel))
            n_half = (
                round(dist / (ws.stride_m / 2.0))
                if ws.half_cycles
                else 2 * round(dist / ws.stride_m)
            )

            def face_and_creep(k=k, rel=rel, n_half=n_half, parity=parity):
                """(parity, the turn or None, half cycles) of walking to waypoint k."""
                off_axis = abs(rel[1]) > tol or rel[0] < -tol
                turn = None
                if off_axis:
                    check_can_spin(request, self.name, k, wp[k])
                    psi = math.atan2(rel[1], rel[0])
                    transition_to_spin(b, ws, direction, parity)
                    orders = spin(b, ws, psi)
                    parity = transition_from_spin(b, ws, direction)
                    turn = spin_record(k, psi, orders)
                if not (off_axis or rel[0] > tol):
                    return parity, turn, 0
                for _ in range(n_half):
                    parity = creep_half_cycle(b, ws, direction, parity, 0.0)
                return parity, turn, n_half

            parity, turn, n_done = walk_first_segment(
                request.first_walk_memo,
                request.model,
                (
                    self.name,
                    workspace_key(ws),
                    request.threshold,
                    float(request.start_heading),
                    k,
                    wp[k].tobytes(),
                    tol,
                    b.swing_com is not None,
                ),
                b,
                None,
                face_and_creep,
            )
            walked.spins += [turn] if turn is not None else []
            walked.n_half_cycles += n_done
            walked.reached.append(b.nominal_base[:2].copy())
            walked.t_reached.append(b.t)
