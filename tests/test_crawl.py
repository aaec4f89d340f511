"""The continuous crawl (planner/gaits/crawl.py): the moving-base whole-body CoM against the CoM of
the sampled joints, the duty factor against its closed form, the body moving while a leg
swings, and property tests on random paths on SILO4 and mantis (stance feet fixed, margin
held, joint and URDF limits, q̇ and q̈ continuous: zero at every phase boundary)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_omni import QDD_AT_BOUNDARY
from test_planner_invariants import (
    SETTINGS,
    check_finite_differences,
    check_invariants,
    heights,
    waypoints,
)

from planner import plan_path
from planner.errors import PlannerInputError, PlanningError
from planner.gaits.crawl import FOUR_FOOT_UNITS, duty_factor, leg_order
from planner.model import as_planning_model
from planner.path.plan_path import robot_in_body_com_frame
from planner.trajectory.limits import check_limits
from planner.trajectory.verify import SAMPLE_MARGIN_SLACK_M
from planner.workspace.layout import workspace_for
from silo4kin.robot import load_robot

#: A long straight crawl along the body x axis (start heading 0): 2 m at h = 0.6 m.
STRAIGHT_2M = [(2.0, 0.0)]
#: Duty factor of a finite crawl vs the steady state's: the start (a sway step, the first
#: swing from the creeping stance) and the arrival add four-foot time, so it is a little
#: higher; 0.02 is ~4 swings' worth over the ~70 swings of 2 m.
DUTY_SLACK = 0.02


def _transfers(plan):
    return [s for s in plan.steps if s.kind == "transfer"]


@pytest.fixture(scope="module")
def straight(silo4):
    return plan_path(silo4, STRAIGHT_2M, 0.6, start_heading=0.0, gait="crawl")


def test_duty_factor_closed_form_and_measured(straight):
    # β = (T - 1) / T with T = 4 + 2d units per cycle (module docstring)
    d = FOUR_FOOT_UNITS
    assert duty_factor(d) == pytest.approx(1.0 - 1.0 / (4.0 + 2.0 * d))
    assert duty_factor(0.0) == 0.75
    assert straight.gait == "crawl" and straight.fallback_reason is None
    measured = float(straight.trajectory.contact.mean())
    assert duty_factor() <= measured <= duty_factor() + DUTY_SLACK


def test_body_moves_while_a_leg_swings(straight):
    """Most swings move the base (the crawl), and the legs swing one at a time in the
    creeping order of the body axis (RH, RF, LH, LF along +x)."""
    moving = [
        s
        for s in _transfers(straight)
        if np.hypot(*(s.position_base_end_in_world - s.position_base_start_in_world)[:2]) > 1e-3
    ]
    assert len(moving) >= 0.9 * len(_transfers(straight))
    ws = workspace_for(robot_in_body_com_frame(load_robot()), 0.6, "default")
    names = ("LF", "RF", "LH", "RH")
    assert [names[k] for k in leg_order(ws, np.array([1.0, 0.0]))] == ["RH", "RF", "LH", "LF"]
    legs = [s.leg for s in _transfers(straight)]
    cycle = ["RH", "RF", "LH", "LF"]
    assert all(cycle[(cycle.index(a) + 1) % 4] == b for a, b in zip(legs, legs[1:]))


def test_crawl_is_faster_than_creeping_at_h_0_6(silo4, straight):
    creep = plan_path(silo4, STRAIGHT_2M, 0.6, start_heading=0.0, gait="creep")
    assert creep.gait == "creep"
    # steady state: 4a + 2c = R (4 + 2d) / (3 + 2d) per 4 + 2d units for the crawl, R per
    # 4 + 2b units for the creeping gait whose body phases last b (1 unit, longer where
    # planner/gaits/body_pace.py paces them): (4 + 2b) / (3 + 2d) = 1.5x faster at b = 1,
    # d = 1/2
    body = [s.t_end - s.t_start for s in creep.steps if s.label == "creep body"]
    b = float(np.mean(body))
    assert b >= 1.0
    ratio = creep.trajectory.time_units[-1] / straight.trajectory.time_units[-1]
    assert 1.3 <= ratio <= (4.0 + 2.0 * b) / (3.0 + 2.0 * FOUR_FOOT_UNITS) + 0.05
    auto = plan_path(silo4, STRAIGHT_2M, 0.6, start_heading=0.0)
    assert auto.gait == "crawl"


def test_moving_swing_com_matches_the_sampled_joints(silo4, straight):
    """PlanningModel.moving_swing_com_in_world (what the crawl checks) equals the whole-body
    CoM of the joint values the sampler writes, on every sample of a moving swing."""
    model = as_planning_model(silo4)
    tr = straight.trajectory
    com = model.com_in_world(tr.q, tr.position_base_in_world, tr.yaw_base_in_world)
    spu = round((len(tr) - 1) / tr.time_units[-1])
    names = ("LF", "RF", "LH", "RH")
    checked = 0
    for s in _transfers(straight)[10:14]:
        points, base = model.moving_swing_com_in_world(
            s.position_base_start_in_world,
            s.position_base_end_in_world,
            s.yaw_base_start,
            s.position_feet_in_world,
            names.index(s.leg),
            s.foothold_end_in_world,
            straight.workspace.swing_height_m,
            n=spu + 1,
        )
        rows = slice(int(round(s.t_start * spu)), int(round(s.t_end * spu)) + 1)
        np.testing.assert_allclose(base, tr.position_base_in_world[rows, :2], atol=1e-12)
        # the last sample belongs to the next step (the foot down): same configuration
        np.testing.assert_allclose(points, com[rows, :2], atol=1e-9)
        checked += 1
    assert checked == 4


def test_gait_option_is_checked(silo4):
    with pytest.raises(PlannerInputError, match="gait"):
        plan_path(silo4, [(0.0, 0.3)], 0.4, gait="trot")


def crawl_or_refusal(robot, wp, h, **options):
    """plan_path(gait="crawl"): a crawl, or a PlanningError naming why (never a creeping
    plan); where refused, gait "auto" still plans (checked by the caller)."""
    try:
        plan = plan_path(robot, wp, h, gait="crawl", **options)
    except PlanningError as exc:
        assert str(exc)
        return plan_path(robot, wp, h, **options)
    assert plan.gait == "crawl"
    return plan


def _check_crawl(robot, plan, wp):
    """The plan walks without turning, reaches every waypoint, keeps every invariant and
    the URDF limits at unit time 1 s, and is smooth."""
    planning = robot_in_body_com_frame(robot)
    check_invariants(planning, plan)
    if plan.gait != "crawl":
        return
    assert not plan.spins
    np.testing.assert_allclose(plan.trajectory.yaw_base_in_world, plan.start_heading, atol=1e-12)
    err = np.hypot(*(plan.position_walked_in_world - np.asarray(wp, float)).T)
    assert err.max() <= plan.tolerance + 1e-9
    tr = plan.trajectory
    lifted = ~np.all(tr.contact, axis=1)
    if lifted.any():
        assert tr.margin_com[lifted].min() >= plan.stability_threshold - SAMPLE_MARGIN_SLACK_M
    limits = check_limits(robot, tr, "total")
    assert limits.violation is None, limits.violation
    if len(tr) > 1:
        # q̇ continuous: between samples it changes by at most max|q̈| dt (mean value
        # theorem, 10 % for the peak between samples); a jump would show as the full rate
        dt = tr.t[1] - tr.t[0]
        assert np.abs(np.diff(tr.qd, axis=0)).max() <= 1.1 * np.abs(tr.qdd).max() * dt + 1e-9
        spu = round((len(tr) - 1) / tr.time_units[-1])
        rows = np.array([int(round(s.t_start * spu)) for s in plan.steps])
        assert np.abs(tr.qdd[rows]).max() <= QDD_AT_BOUNDARY
        assert np.abs(tr.qd[rows]).max() <= QDD_AT_BOUNDARY


@settings(max_examples=10, **SETTINGS)
@given(data=st.data())
def test_silo4_random_paths_crawl(silo4, data):
    h = data.draw(heights(silo4, "default"))
    heading = data.draw(st.floats(-np.pi, np.pi))
    wp = data.draw(waypoints())
    plan = crawl_or_refusal(silo4, wp, h, start_heading=heading, samples_per_unit=100)
    _check_crawl(silo4, plan, wp)


@settings(max_examples=4, **SETTINGS)
@given(data=st.data())
def test_crawl_finite_differences(silo4, data):
    """q̇ and q̈ equal central differences of q on a crawl (body and swing foot moving
    together: the u̇, ü terms of the base enter every leg)."""
    h = data.draw(heights(silo4, "default"))
    wp = data.draw(waypoints(max_points=1, radius=0.5))
    plan = crawl_or_refusal(silo4, wp, h)
    if plan.steps:  # a waypoint at the start: no step
        check_finite_differences(robot_in_body_com_frame(silo4), plan)


@settings(max_examples=4, **SETTINGS)
@given(data=st.data())
def test_mantis_random_paths_crawl(mantis, data):
    h = data.draw(heights(robot_in_body_com_frame(mantis), "default"))
    wp = data.draw(waypoints(max_points=2, radius=0.8))
    plan = crawl_or_refusal(mantis, wp, h, samples_per_unit=100)
    _check_crawl(mantis, plan, wp)


def test_mantis_crawls_faster_than_it_creeps(mantis):
    """Another robot (hips off the CoG, other legs): the crawl walks a path the creeping
    gait walks too, in less time, with every check of :func:`_check_crawl`."""
    wp = [(0.0, 1.2)]  # 1.2 m ahead
    crawl = plan_path(mantis, wp, 0.4, samples_per_unit=50, gait="crawl")
    creep = plan_path(mantis, wp, 0.4, samples_per_unit=50, gait="creep")
    assert crawl.gait == "crawl" and creep.gait == "creep"
    assert crawl.trajectory.time_units[-1] < creep.trajectory.time_units[-1]
    _check_crawl(mantis, crawl, wp)


@pytest.mark.parametrize("gait,walked", [("crawl", "crawl"), ("creep", "creep")])
def test_cli_gait_option_is_recorded(tmp_path, gait, walked):
    """`silo4 plan --gait` reaches the planner; plan.json and metrics.json say which gait
    walked."""
    import json

    from viz.cli.main import main

    out = tmp_path / gait
    assert (
        main(
            [
                "plan",
                "--waypoints",
                "0,0.5",
                "--height",
                "0.5",
                "--gait",
                gait,
                "--samples-per-unit",
                "5",
                "--out",
                str(out),
                "--no-html",
                "--no-plots",
                "--no-csv",
            ]
        )
        == 0
    )
    for name in ("plan.json", "metrics.json"):
        doc = json.loads((out / name).read_text())
        assert doc["gait"] == walked and doc["fallback_reason"] is None


def test_a_refused_foothold_undoes_that_swing_and_the_creep_takes_over(silo4) -> None:
    """A foothold check refusing one foothold of a crawl: the plan is the unchecked crawl up
    to the swing that placed it (the same steps), then a creeping half cycle starts there,
    and the refused foothold is nowhere in the plan (every foothold was checked)."""
    waypoints = [[0.0, 1.6]]
    free = plan_path(silo4, waypoints, 0.3, gait="crawl", samples_per_unit=10)
    assert free.gait == "crawl" and free.n_creep_half_cycles == 0
    placed = [s for s in free.steps if s.foothold_end_in_world is not None]
    banned = placed[6].foothold_end_in_world
    seen: list[np.ndarray] = []

    def check(foot: np.ndarray) -> None:
        seen.append(np.array(foot))
        if np.array_equal(foot, banned):
            raise ValueError("refused")

    plan = plan_path(silo4, waypoints, 0.3, gait="crawl", foothold_check=check, samples_per_unit=10)
    assert plan.gait == "crawl" and plan.n_creep_half_cycles >= 1
    cut = free.steps.index(placed[6])
    for mine, theirs in zip(plan.steps[:cut], free.steps[:cut]):
        assert mine.label == theirs.label and mine.t_end == theirs.t_end
        assert np.array_equal(mine.position_base_end_in_world, theirs.position_base_end_in_world)
    assert not plan.steps[cut].label.startswith("crawl transfer")
    assert any(np.array_equal(f, banned) for f in seen)
    assert not any(
        s.foothold_end_in_world is not None and np.array_equal(s.foothold_end_in_world, banned)
        for s in plan.steps
    )
    check_invariants(robot_in_body_com_frame(silo4), plan)
