"""Walking in every direction without turning (planner/gaits/omni.py, planner/gaits/crawl.py):
a sweep of segment directions 0..345 deg in 15-deg steps at heights across SILO4's feasible range,
top included, where every plan walks without turning, arrives within the tolerance
(E_n, eq 6.1) and keeps the invariants of every plan (tests/test_planner_invariants.py).

Before the fix (docs/gaits.md, "Which pair swings"), a direction whose nearest body axis
is ±y found no step from the +x creeping stance (each ±y pair's stance keeps a foot on the
rear edge of its ellipse), e.g. `--waypoints "-1,1 -1,2.5"` at h 0.5 (45 deg in the body
frame): the plan faced the path and arrived only within 0.037 m of the 0.01 m tolerance.
Where no gait without turning exists at all (mantis at heights without a lateral stride),
the face-path gait shortens its last half cycle and still arrives within the tolerance.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from test_planner_invariants import check_invariants

from planner import plan_path
from planner.errors import PlanningError
from planner.gaits.creep_spin import creep_stance_in_base
from planner.gaits.foothold_ellipse import stance_step_limit
from planner.gaits.omni import step_candidates, swing_pairs
from planner.path.metrics import compute_metrics, tolerance_warning
from planner.path.plan_path import robot_in_body_com_frame
from planner.trajectory.clearance import tibia_violation
from planner.workspace.layout import feasible_height_range, workspace_for

#: Segment directions of the sweep, in the body frame [deg] (start heading 0: world = body).
DIRECTIONS_DEG = tuple(range(0, 360, 15))
#: Length of the swept segment [m]: two to five half cycles at SILO4's heights.
SEGMENT_M = 0.6
#: Samples per time unit: 20 puts a sample on every phase boundary (the crawl's four-foot
#: phases last 0.5 units) and keeps the sweep to ~10 s.
SAMPLES_PER_UNIT = 20
#: SILO4 heights [m] of the sweep; the top of the feasible range is added (fixture).
SILO4_HEIGHTS_M = (0.2, 0.3, 0.4, 0.5, 0.55)
#: mantis heights [m]: 0.35 has a lateral stride (gaits without turning); 0.25 and 0.45 have
#: none (workspace λ_y = 0: the plan faces the path).
MANTIS_HEIGHTS_M = (0.25, 0.35, 0.45)


def _segment(angle_deg: float) -> list[tuple[float, float]]:
    a = math.radians(angle_deg)
    return [(SEGMENT_M * math.cos(a), SEGMENT_M * math.sin(a))]


def _check_arrives(robot, plan, wp, gaits=("crawl", "creep")) -> None:
    """The plan walks with one of ``gaits`` (or, where the omnidirectional gaits fold a shank
    under the body, faces the path and says so: planner/trajectory/clearance.py), lands within the
    tolerance of every waypoint (the CoG as walked), says nothing about missing it, keeps
    every tibia clear and every invariant."""
    if plan.gait == "facing" and "facing" not in gaits:
        reason = plan.fallback_reason or ""
        assert "omnidirectional gait" in reason and "tibia" in reason, reason
    else:
        assert plan.gait in gaits, (plan.gait, plan.fallback_reason)
    assert tibia_violation(robot.legs, plan.trajectory) is None
    err = np.hypot(*(plan.position_walked_in_world - np.asarray(wp, float)).T)
    assert err.max() <= plan.tolerance + 1e-9, (plan.gait, err.max())
    assert compute_metrics(plan)["warnings"] == []
    check_invariants(robot_in_body_com_frame(robot), plan)


@pytest.fixture(scope="module")
def top_height(silo4) -> float:
    return feasible_height_range(robot_in_body_com_frame(silo4))[1]


def test_blocked_nearest_axis_pairs_leave_a_step(silo4):
    """The root cause, measured: at h 0.5 from the +x creeping stance, towards 90 deg, both
    pairs of the nearest axis (+y) have a stance foot on the rear edge of its ellipse (no
    step: stance_step_limit 0), and the candidates still hold a step of the pair across."""
    ws = workspace_for(robot_in_body_com_frame(silo4), 0.5)
    off = creep_stance_in_base(ws, "+x", 0)[:, :2] - ws.position_mid_in_base[:, :2]
    u = np.array([0.0, 1.0])
    pairs = swing_pairs(ws, u)
    for pair in pairs[:2]:
        rest = [k for k in range(4) if k not in pair]
        assert stance_step_limit(ws, off[rest], u) == 0.0
    legs = robot_in_body_com_frame(silo4).legs
    t, pair = step_candidates(ws, off, u, 0.3, legs)[0]
    assert pair in pairs[2:] and t > 0.05


@pytest.mark.parametrize("height", (0.5, 0.55))
def test_the_45_degree_path_walks_without_turning(silo4, height):
    """The outside check's path: a 45-deg first segment in the body frame."""
    wp = [(-1.0, 1.0), (-1.0, 2.5)]
    plan = plan_path(silo4, wp, height, samples_per_unit=SAMPLES_PER_UNIT)
    _check_arrives(silo4, plan, wp)
    assert plan.fallback_reason is None


@pytest.mark.parametrize("height", (*SILO4_HEIGHTS_M, "top"))
def test_silo4_every_direction_arrives(silo4, top_height, height):
    """Default gait (crawl or creeping, the faster): every direction, no turn, E_n <= tol."""
    h = top_height if height == "top" else height
    for angle in DIRECTIONS_DEG:
        wp = _segment(angle)
        plan = plan_path(silo4, wp, h, start_heading=0.0, samples_per_unit=SAMPLES_PER_UNIT)
        _check_arrives(silo4, plan, wp)


@pytest.mark.parametrize("height", (0.2, 0.5, "top"))
def test_silo4_creeping_gait_every_direction(silo4, top_height, height):
    """The omnidirectional creeping gait alone (gait="creep") walks every direction, or is
    refused naming why (a folded shank: planner/trajectory/clearance.py), where facing the
    path walks it."""
    h = top_height if height == "top" else height
    for angle in DIRECTIONS_DEG:
        wp = _segment(angle)
        try:
            plan = plan_path(
                silo4, wp, h, start_heading=0.0, samples_per_unit=SAMPLES_PER_UNIT, gait="creep"
            )
        except PlanningError as exc:
            assert "tibia" in str(exc), str(exc)
            plan = plan_path(
                silo4, wp, h, start_heading=0.0, samples_per_unit=SAMPLES_PER_UNIT, gait="facing"
            )
            _check_arrives(silo4, plan, wp, gaits=("facing",))
            continue
        _check_arrives(silo4, plan, wp, gaits=("creep",))


@pytest.mark.parametrize("height", MANTIS_HEIGHTS_M)
def test_mantis_every_direction_arrives(mantis, height):
    """mantis: without turning where its workspace has strides along both axes; else facing
    the path (the fallback says why), still within the tolerance (shortened last half
    cycle, planner/path/plan_path.py)."""
    ws = workspace_for(robot_in_body_com_frame(mantis), height)
    lateral = ws.stride_lateral_m > 0
    for angle in DIRECTIONS_DEG:
        wp = _segment(angle)
        plan = plan_path(mantis, wp, height, start_heading=0.0, samples_per_unit=SAMPLES_PER_UNIT)
        _check_arrives(mantis, plan, wp, gaits=("crawl", "creep") if lateral else ("facing",))
        if not lateral:
            assert "no stride along a body axis" in plan.fallback_reason


@pytest.mark.parametrize("angle", (0, 45, 90, 200))
@pytest.mark.parametrize("length", (0.05, SEGMENT_M))
def test_face_path_arrives_within_the_tolerance(silo4, angle, length):
    """Facing the path (face_path, and the fallback where no gait without turning steps):
    ceil(d / (λ/2)) half cycles, the last shortened, so the CoG lands on the waypoint; before,
    round(d / (λ/2)) whole half cycles missed it by up to λ/4 (a 0.05 m segment not at all)."""
    a = math.radians(angle)
    wp = [(length * math.cos(a), length * math.sin(a))]
    plan = plan_path(
        silo4, wp, 0.5, start_heading=0.0, samples_per_unit=SAMPLES_PER_UNIT, face_path=True
    )
    _check_arrives(silo4, plan, wp, gaits=("facing",))
    half = plan.workspace.stride_m / 2
    assert plan.n_creep_half_cycles == math.ceil(length / half)
    assert compute_metrics(plan)["distance_m"] == pytest.approx(length, abs=1e-9)


def test_missing_the_tolerance_is_said(silo4):
    """A default-preset plan that leaves a waypoint further than the tolerance says so in
    one warning line (metrics.tolerance_warning); the thesis preset walks whole cycles and
    is not held to it."""
    wp = [(0.4, 0.0)]
    plan = plan_path(silo4, wp, 0.4, start_heading=0.0, samples_per_unit=10)
    assert tolerance_warning(plan, np.array([plan.tolerance])) == []
    off = replace(
        plan, position_walked_in_world=plan.position_walked_in_world + np.array([0.0, 0.03])
    )
    lines = compute_metrics(off)["warnings"]
    assert len(lines) == 1 and "waypoint 0" in lines[0] and "0.030 m" in lines[0]
    thesis = plan_path(silo4, wp, 0.4, workspace="thesis", samples_per_unit=10)
    assert tolerance_warning(thesis, np.array([1.0])) == []
