"""The omnidirectional creeping gait (planner/gaits/omni.py, `gait="creep"`; the continuous crawl is
tests/test_crawl.py): its closed forms against brute force,
and property tests on random paths on SILO4, mantis and phasmid (the body keeps its heading,
every waypoint is reached, every planner invariant holds, q̇ and q̈ are continuous: zero at
every phase boundary, where the profiles meet)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_planner_invariants import SETTINGS, check_invariants, heights, waypoints

from planner import plan_path
from planner.errors import PlanningError
from planner.gaits.foothold_ellipse import ellipse_radius, ellipse_semi_axes, stance_step_limit
from planner.gaits.omni import nearest_axis
from planner.path.plan_path import robot_in_body_com_frame
from planner.workspace.layout import workspace_for

#: |q̈| at a phase boundary [rad/s²]: every smooth profile has zero velocity and
#: acceleration at both ends of its step, so q̈ is exactly 0 there, on both sides (rounding
#: through J⁻¹ only); the thesis's cosine blends give π²/2 (Δ/t_f²), ~25 rad/s² at
#: touch-down, then 0 in the next step: a jump in q̈.
QDD_AT_BOUNDARY = 1e-8
#: Largest q̇ jump between consecutive samples at 100 samples per unit [rad/unit]: a
#: continuous q̇ changes by at most max|q̈| dt (~ 50 rad/unit² x 0.01); a jump at a phase
#: boundary would show as the full rate (~1 rad/unit).
QD_JUMP = 0.6


@pytest.fixture(scope="module")
def ws(silo4):
    return workspace_for(robot_in_body_com_frame(silo4), 0.4, "default")


def _inside(ws, r):
    a = ellipse_semi_axes(ws)
    return ((r / a) ** 2).sum(axis=-1) <= 1.0 + 1e-12


@pytest.mark.parametrize("angle_deg", [0.0, 17.0, 45.0, 90.0, 133.0, 200.0, 311.0])
def test_ellipse_radius_and_stance_limit_match_brute_force(ws, angle_deg):
    u = np.array([np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))])
    r = ellipse_radius(ws, u)
    assert _inside(ws, r * u) and not _inside(ws, (r + 1e-6) * u)
    rng = np.random.default_rng(int(angle_deg))
    offsets = rng.uniform(-1, 1, (2, 2)) * ellipse_semi_axes(ws) * 0.6
    t = stance_step_limit(ws, offsets, u)
    grid = np.linspace(0.0, 1.0, 20001)
    ok = np.all(_inside(ws, offsets[None] - grid[:, None, None] * u), axis=1)
    brute = grid[np.argmin(ok)] if not ok.all() else 1.0
    assert t == pytest.approx(brute, abs=1e-4)


def test_stance_limit_is_zero_outside_and_axis_names():
    class W:
        stride_m, stride_lateral_m = 0.2, 0.4

    assert stance_step_limit(W, np.array([[0.2, 0.0]]), np.array([1.0, 0.0])) == 0.0
    assert nearest_axis(np.array([0.6, -0.8])) == "-y"
    assert nearest_axis(np.array([-0.9, 0.1])) == "-x"


def creep_or_refusal(robot, wp, h, **options):
    """plan_path(gait="creep"): the creeping gait, or a PlanningError naming why (never
    another gait); where refused, gait "facing" plans it (checked by the caller)."""
    try:
        plan = plan_path(robot, wp, h, gait="creep", **options)
    except PlanningError as exc:
        assert str(exc)
        return plan_path(robot, wp, h, gait="facing", **options)
    assert plan.gait == "creep"
    return plan


def _check_omni(robot, plan, wp):
    planning = robot_in_body_com_frame(robot)
    # where the omnidirectional gait finds no reachable step (seen near the ends of the
    # height range, where the shift reserve leaves almost no room) the plan faces the path
    # and says why: no silent fallback
    if plan.gait == "creep":
        assert not plan.spins
        np.testing.assert_allclose(
            plan.trajectory.yaw_base_in_world, plan.start_heading, atol=1e-12
        )
        err = np.hypot(*(plan.position_walked_in_world - np.asarray(wp, float)).T)
        assert err.max() <= plan.tolerance + 1e-9
    check_invariants(planning, plan)
    if len(plan.trajectory) > 1 and plan.gait == "creep":
        # smoothness is the omnidirectional gait's property; the face-the-path fallback keeps
        # the older profiles (q̈ up to ~68 rad/s² in its spin swings: a 0.62 rad/s jump per
        # sample at 100 samples per unit, seen at h = 0.5 m, heading 0, (0, 1) (0, 0))
        assert np.abs(np.diff(plan.trajectory.qd, axis=0)).max() <= QD_JUMP
        spu = round((len(plan.trajectory) - 1) / plan.trajectory.time_units[-1])
        rows = np.array([int(round(s.t_start * spu)) for s in plan.steps])
        assert np.abs(plan.trajectory.qdd[rows]).max() <= QDD_AT_BOUNDARY
        assert np.abs(plan.trajectory.qd[rows]).max() <= QDD_AT_BOUNDARY


@settings(max_examples=12, **SETTINGS)
@given(data=st.data())
def test_silo4_random_paths_walk_without_turning(silo4, data):
    h = data.draw(heights(silo4, "default"))
    heading = data.draw(st.floats(-np.pi, np.pi))
    wp = data.draw(waypoints())
    plan = creep_or_refusal(silo4, wp, h, start_heading=heading, samples_per_unit=100)
    _check_omni(silo4, plan, wp)


@pytest.fixture(scope="module", params=["mantis", "phasmid"])
def other(request):
    """tests/robots/mantis.urdf or phasmid.urdf.xacro: the session's (tests/conftest.py)."""
    return request.getfixturevalue(request.param)


@settings(max_examples=4, **SETTINGS)
@given(data=st.data())
def test_other_robots_random_paths_walk_without_turning(other, data):
    h = data.draw(heights(robot_in_body_com_frame(other), "default"))
    wp = data.draw(waypoints(max_points=2, radius=0.8))
    plan = creep_or_refusal(other, wp, h, samples_per_unit=100)
    _check_omni(other, plan, wp)
