"""Feasibility follows the path (issue 21): an insect robot that cannot turn its stance plans
and walks along its body at every height its legs reach.

tests/robots/mantis.urdf (legs sideways, hip yaw +-60 deg) has no stride across its body
above ~0.48 m (workspace lambda_y = 0) and its stance turns 0 deg per cycle above 0.5041 m,
while its legs give the default a stride along the body up to 0.5704 m. The feasible range
no longer asks for a spin (planner/workspace/heights.py); a path along the body is walked
forwards and backwards without a turn (planner/gaits/facing.py reverse), and a path that
needs a turn is refused naming the heights where the robot turns
(planner/gaits/walk.py check_can_spin). The physics replay is bench_corpus's (friction 0.8,
the URDF's feet).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from benchmark_scripts import load_benchmark
from test_planner_invariants import check_invariants

from planner import PlanningError, plan_path
from planner.errors import PlannerInputError
from planner.path.metrics import compute_metrics
from planner.path.plan_path import robot_in_body_com_frame
from planner.stability.shifts import SHIFT_EXTRA_M
from planner.workspace.families import workspace_family
from planner.workspace.foothold_layout import (
    AXIS_DIRECTIONS,
    DEFAULT_KNEE_MARGIN,
    MIN_DEFAULT_STRIDE_M,
    SHIFT_RESERVE_M,
    default_layout,
    foot_levels,
    foothold_layout,
)
from planner.workspace.footholds import stable_stride
from planner.workspace.layout import feasible_height_range, walks_any_direction, workspace_for
from planner.workspace.spin import MIN_DEFAULT_SPIN_RAD

#: A path along the start heading (0): forwards 0.8 m, back past the start, forwards again
#: (two reversals), each waypoint 4 mm to the side (within the 0.01 m tolerance).
ALONG_BODY = np.array([[0.8, 0.004], [-0.4, -0.004], [0.2, 0.0]])


def _mantis_heights(planning) -> tuple[float, ...]:
    """Heights [m] of the feasible range where mantis walks only along its body: its low
    end, the middle of the part above its any-direction range, and its top."""
    lo, hi = feasible_height_range(planning)
    _, turn_hi = feasible_height_range(planning, any_direction=True)
    return (lo, round(0.5 * (turn_hi + hi), 4), hi)


def test_the_range_is_the_legs_not_the_spin(mantis):
    """The feasible range reaches past the any-direction range; outside it mantis has neither
    a stride across its body nor a spin (measured on the workspace itself), and the range's
    top is where the stride along the body falls under the shortest (not a spin rule)."""
    planning = robot_in_body_com_frame(mantis)
    lo, hi = feasible_height_range(planning)
    turn_lo, turn_hi = feasible_height_range(planning, any_direction=True)
    assert lo <= turn_lo and turn_hi + 0.05 < hi
    for h in _mantis_heights(planning):
        if turn_lo <= h <= turn_hi:
            continue
        ws = workspace_for(planning, h)
        assert not walks_any_direction(planning, h)
        assert ws.stride_lateral_m < MIN_DEFAULT_STRIDE_M and ws.psi_max_rad < MIN_DEFAULT_SPIN_RAD
        assert ws.stride_m >= MIN_DEFAULT_STRIDE_M
    assert foothold_layout(planning, hi + 2e-4, "default")[2][0] < MIN_DEFAULT_STRIDE_M
    for h in np.linspace(turn_lo, turn_hi, 5):
        assert walks_any_direction(planning, float(h))


@pytest.mark.parametrize("which", [0, 1, 2])
def test_walks_along_its_body_where_it_cannot_turn(mantis, which):
    """Forwards, backwards and forwards again along its body: no turn, the reversals' own
    transfers, every waypoint within the tolerance, every invariant."""
    planning = robot_in_body_com_frame(mantis)
    h = _mantis_heights(planning)[which]
    plan = plan_path(mantis, ALONG_BODY, h, start_heading=0.0, samples_per_unit=20)
    assert plan.gait == "facing" and plan.spins == ()
    assert np.ptp(plan.trajectory.yaw_base_in_world) == 0.0
    assert sum(s.label.startswith("reverse transfer") for s in plan.steps) == 4
    err = np.hypot(*(plan.position_walked_in_world - ALONG_BODY).T)
    assert err.max() <= plan.tolerance, err
    assert compute_metrics(plan)["warnings"] == []
    check_invariants(planning, plan)


def test_phasmid_walks_back_along_its_body_above_its_turning_heights(phasmid):
    """phasmid above its any-direction range (0.5173 m): back along its body (the thesis's
    transitions through position 2 took LF_hip_pitch past its limit here)."""
    planning = robot_in_body_com_frame(phasmid)
    _, hi = feasible_height_range(planning)
    _, turn_hi = feasible_height_range(planning, any_direction=True)
    h = round(0.5 * (turn_hi + hi), 4)
    assert not walks_any_direction(planning, h)
    wp = np.array([[0.0, -1.2], [0.0, -0.5], [0.0, -1.5]])
    plan = plan_path(phasmid, wp, h, start_heading=math.radians(89.0), samples_per_unit=20)
    assert plan.spins == ()
    err = np.hypot(*(plan.position_walked_in_world - wp).T)
    assert err.max() <= plan.tolerance, err
    check_invariants(planning, plan)


def test_a_turn_it_cannot_make_is_refused_naming_where_it_turns(mantis):
    """Across its body at a height where it cannot turn: refused, naming the height, its
    spin, the heights where it walks any direction, and what it walks here."""
    planning = robot_in_body_com_frame(mantis)
    h = _mantis_heights(planning)[1]
    turn_lo, turn_hi = feasible_height_range(planning, any_direction=True)
    with pytest.raises(PlanningError) as refused:
        plan_path(mantis, np.array([[0.0, 1.0]]), h, start_heading=0.0)
    text = str(refused.value)
    assert f"at h = {h:.4g} m it turns 0.00 deg per cycle" in text, text
    assert f"walks a path in every direction at {turn_lo:.4g}-{turn_hi:.4g} m" in text, text
    assert "only along its body axis" in text and refused.value.waypoint_index == 0
    # the same path planned at a height where it turns
    plan = plan_path(mantis, np.array([[0.0, 1.0]]), turn_hi, start_heading=0.0)
    assert np.hypot(*(plan.position_walked_in_world[0] - [0.0, 1.0])) <= plan.tolerance


@pytest.mark.parametrize("which", [0, 1, 2])
def test_walks_in_physics_where_it_cannot_turn(mantis, which):
    """The along-body plans walk in MuJoCo (bench_corpus's replay: friction 0.8, the URDF's
    feet; no fall, drift <= 20 mm, slip <= 5 mm, feet only on the ground) with the pipeline's
    limits and full-load torques."""
    pytest.importorskip("mujoco")
    bench = load_benchmark("bench_corpus")
    h = _mantis_heights(robot_in_body_com_frame(mantis))[which]
    outcome = bench.run_case(mantis, bench.Case(0, "mantis", ALONG_BODY, 0.0, h, "along body"))
    assert outcome.walks, outcome.reasons


def test_the_workspace_figure_says_along_the_body_only(mantis):
    """``silo4 workspace``'s title at a height where mantis cannot turn: feasible, along the
    body only; at one where it turns, feasible without that clause."""
    import matplotlib.pyplot as plt

    from viz.plots.workspace import workspace_figure

    planning = robot_in_body_com_frame(mantis)
    h = _mantis_heights(planning)[1]
    _, turn_hi = feasible_height_range(planning, any_direction=True)
    titles = []
    for height in (h, turn_hi):
        fig = workspace_figure(mantis, height)
        titles.append(fig.axes[0].get_title())
        plt.close(fig)
    assert "\nfeasible; along the body only: stride y 0.000 m < 0.10 m" in titles[0], titles[0]
    assert "(a path across the body is refused)" in titles[0]
    assert "\nfeasible\n" in titles[1] and "along the body only" not in titles[1], titles[1]


def test_above_the_range_the_refusal_names_the_stability_threshold(mantis):
    """Above mantis's range (0.5704 m) its legs still reach footholds a stride apart, but no
    stride keeps the 2 cm threshold on every creeping lift: the refusal says so (and the
    same stances with a threshold of 0 do have a stride: it is the threshold that binds)."""
    planning = robot_in_body_com_frame(mantis)
    _, hi = feasible_height_range(planning)
    h = round(hi + 0.008, 4)
    with pytest.raises(PlannerInputError) as refused:
        plan_path(mantis, np.array([[0.5, 0.0]]), h, start_heading=0.0)
    text = str(refused.value)
    assert "keeps the stability threshold of 0.02 m on every creeping lift" in text, text
    assert foothold_layout(planning, h, "default")[2][0] < MIN_DEFAULT_STRIDE_M
    assert default_layout(planning, h, "default")[3] == "stability"
    # the threshold binds: position 2 as the layout chooses it, a stride without a margin
    family = workspace_family(planning)
    levels = foot_levels(planning, h)
    sets = family.reachable_sets(tuple(planning.legs), levels, DEFAULT_KNEE_MARGIN)
    centres, extents = family.choose_centres(tuple(planning.legs), sets, SHIFT_RESERVE_M)
    hips = np.array([leg.position_hip_in_base for leg in planning.legs])
    mid = np.column_stack([centres, np.full(4, levels[0])])
    longest = float(extents[:, 0].min())
    along_x = AXIS_DIRECTIONS[0][1]
    assert stable_stride(hips, mid, longest, along_x, SHIFT_EXTRA_M) >= MIN_DEFAULT_STRIDE_M
    assert stable_stride(hips, mid, longest, along_x, 0.02 + SHIFT_EXTRA_M) == 0.0
