"""Issue 6 end to end: robots other than SILO4 plan, pass every planner invariant, carry
torques and animate correctly.

Robots: tests/robots/mantis.urdf (every convention differs from SILO4's, body CoG 4.5 cm
ahead of and 4.2 cm above the URDF root) and a SILO4 xacro variant with other lengths.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_animation import SCENE_FK_TOLERANCE, _decode, scene_foot_in_world
from test_planner_invariants import SETTINGS, check_finite_differences, check_invariants

from planner import PlanningError, plan_path
from planner.gaits.builder import OverBudget
from planner.path.plan_path import robot_in_body_com_frame
from planner.trajectory.samples import LEGS
from planner.trajectory.torques import add_torques
from planner.workspace.layout import feasible_height_range, walks_any_direction
from silo4kin import load_robot
from viz.animation.page import build_scene
from viz.animation.playback import playback_frame_indices


@pytest.fixture(scope="module")
def variant():
    return load_robot(xacro_args={"L2": 0.3, "L3": 0.35, "Lb": 0.25})


@pytest.fixture(scope="module", params=["mantis", "variant", "phasmid"])
def robot(request, mantis, variant, phasmid):
    return {"mantis": mantis, "variant": variant, "phasmid": phasmid}[request.param]


def test_mantis_body_cog_is_not_its_root(mantis):
    """The stability point is the body CoG: mantis's differs from its URDF root frame."""
    assert np.linalg.norm(mantis.position_body_com_in_base) > 0.04
    shifted = robot_in_body_com_frame(mantis)
    for leg, moved in zip(mantis.legs, shifted.legs):
        np.testing.assert_allclose(
            moved.position_hip_in_base,
            leg.position_hip_in_base - mantis.position_body_com_in_base,
            rtol=0,
            atol=1e-15,
        )


@pytest.mark.parametrize("preset", ["default", "thesis"])
def test_robot_has_a_feasible_height_range(robot, preset):
    lo, hi = feasible_height_range(robot_in_body_com_frame(robot), preset)
    assert 0.1 < lo < hi


@settings(max_examples=25, **SETTINGS)
@given(data=st.data())
def test_plans_of_other_robots_satisfy_every_invariant(robot, data):
    """Stance feet fixed in W, margin >= threshold on every lift, joints in limits, no NaN,
    feet never below ground: for mantis and the xacro variant, random paths and heights,
    default preset (its reserves make room for the stability shifts these robots need).

    The xacro variant (longer legs on SILO4's 60 N m joints) may be refused, only with
    OverBudget naming the joint: where no shift keeps its stance legs within the default's
    effort budget (0.85 x 60 = 51 N m, planner/gaits/load_caps.py). At (0.3826, 0.0313) m,
    h 0.3503 m the plan before the caps was a creep whose RH_hip_pitch needed 65.6 N m
    standing still, past even the URDF effort; mantis and phasmid always plan where they
    walk any direction. Above that (mantis over 0.5041 m, phasmid over 0.5173 m: no stride
    across the body, no spin) a path that needs a turn is refused naming the heights where
    the robot turns (planner/gaits/walk.py check_can_spin); one along the body plans
    (test_walks_along_its_body_where_it_cannot_turn)."""
    preset = "default"
    planning = robot_in_body_com_frame(robot)
    lo, hi = feasible_height_range(planning, preset)
    height = data.draw(st.floats(lo, hi))
    point = st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0))
    waypoints = np.array(data.draw(st.lists(point, min_size=1, max_size=2)))
    try:
        plan = plan_path(robot, waypoints, height, workspace=preset, samples_per_unit=10)
    except OverBudget as exc:
        assert robot.xacro_args, exc  # the variant only
        assert re.search(
            r"joint (LF|RF|LH|RH)_\w+ needs [\d.]+ N m standing still, above its budget",
            str(exc),
        ), exc
        return
    except PlanningError as exc:
        if walks_any_direction(planning, height):
            raise
        turns_at = feasible_height_range(planning, preset, any_direction=True)
        assert f"walks a path in every direction at {turns_at[0]:.4g}-{turns_at[1]:.4g} m" in str(
            exc
        ), exc
        return
    check_invariants(planning, plan)


@settings(max_examples=15, **SETTINGS)
@given(data=st.data())
def test_thesis_preset_on_another_robot_plans_validly_or_refuses(mantis, data):
    """The thesis preset reproduces SILO4's Chapter 6 (no reserves, threshold 0). On mantis,
    whose CoG is off-centre, it must shift the body and may run into a joint limit: then it
    refuses with a PlanningError naming the waypoint; it never emits an invalid plan."""
    planning = robot_in_body_com_frame(mantis)
    lo, hi = feasible_height_range(planning, "thesis")
    height = data.draw(st.floats(lo, hi))
    target = data.draw(st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0)))
    try:
        plan = plan_path(
            mantis, np.array([target]), height, workspace="thesis", samples_per_unit=10
        )
    except PlanningError as exc:
        assert "waypoint 0" in str(exc)
        return
    check_invariants(planning, plan)


def test_other_robot_velocities_match_finite_differences(mantis):
    plan = plan_path(mantis, np.array([[0.3, 0.4]]), 0.3, samples_per_unit=10)
    check_finite_differences(robot_in_body_com_frame(mantis), plan)


def test_torques_of_another_robot_carry_its_body(mantis):
    """Support reactions computed about mantis's body CoG, not its root: no foot pulls,
    and the torques exist for every sample."""
    plan = plan_path(mantis, np.array([[0.0, 0.6]]), 0.3, samples_per_unit=10)
    traj = add_torques(mantis, plan.trajectory)
    assert traj.tau is not None and np.all(np.isfinite(traj.tau))


def test_animation_places_another_robot_at_its_cog(mantis):
    """Chaining the scene's transforms puts mantis's feet where the plan says, although its
    URDF root is not at the CoG (the scene inserts the root offset)."""
    plan = plan_path(mantis, np.array([[0.0, 0.4]]), 0.3, samples_per_unit=10)
    traj = plan.trajectory
    rec, _ = build_scene(mantis, traj)
    statics, clips = _decode(rec)
    idx = playback_frame_indices(traj.t - traj.t[0], 25.0)
    for k in (0, len(idx) // 2, len(idx) - 1):
        for leg_index, leg in enumerate(LEGS):
            expected = traj.position_foot_in_world[idx[k], leg_index]
            foot = scene_foot_in_world(statics, clips, leg, k)
            assert np.max(np.abs(foot - expected)) < SCENE_FK_TOLERANCE
