"""Issue 12, the planner part: mammal legs (hip ab/adduction first) plan like insect legs.

Robots from example-robot-data: go2 and solo12 run the planner's property tests
(tests/test_planner_invariants.py's checks, generalised to either leg family and to ball
feet; hyq has no height within its effort budget). The mammal reachable set
(planner/workspace/reach_mammal.py) is checked against forward kinematics of the joint
space; the whole-body CoM in the planning frame against pin.centerOfMass; the contact
convention against the URDFs.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_planner_invariants import SETTINGS, check_finite_differences, check_invariants

from planner import PlannerInputError, plan_path
from planner.gaits.creep_spin import (
    CRAB_MAX_RAD,
    CRAB_STEP_RAD,
    crab_limit_rad,
    crab_stances_clear,
    foothold_in_base,
)
from planner.model import planning_model
from planner.outputs.pipeline import RunRequest, plan_run
from planner.presets import MIN_GROUND_CLEARANCE_M
from planner.trajectory.clearance import clearance_of_poses, ground_clearance
from planner.workspace.layout import (
    DEFAULT_KNEE_MARGIN,
    feasible_height_range,
    planning_robot,
    workspace_for,
)
from planner.workspace.reach_mammal import knee_angle, reachable_mask_at, reachable_set
from silo4kin import load_robot
from silo4kin.foot_contact import contact_offset_from_urdf, foot_contact_offset_m
from silo4kin.legs import forward_kinematics, inverse_kinematics
from silo4kin.mammal import branch_of

PROPERTY_ROBOTS = ("go2", "solo12")


@pytest.fixture(scope="module", params=PROPERTY_ROBOTS)
def mammal(request):
    """go2 or solo12: the session's robot (tests/conftest.py), the same go2 as ``go2``."""
    return request.getfixturevalue(request.param)


def test_contact_offset_is_read_from_the_foot_sphere():
    """Ball radius minus the sphere's height in the foot frame; a mesh ball its depth; points 0."""
    assert foot_contact_offset_m(load_robot("a1")) == pytest.approx(0.02)
    assert foot_contact_offset_m(load_robot("hyq")) == pytest.approx(0.02175)
    assert foot_contact_offset_m(load_robot("anymal")) == pytest.approx(0.031 - 0.02325)
    assert foot_contact_offset_m(load_robot("go2")) == pytest.approx(0.0229, abs=1e-4)  # mesh
    assert foot_contact_offset_m(load_robot()) == 0.0  # SILO4: point foot
    xml = (
        '<robot name="r"><link name="foot"><collision><origin xyz="0 0 0.01"/>'
        '<geometry><sphere radius="0.03"/></geometry></collision></link></robot>'
    )
    assert contact_offset_from_urdf(xml, "foot") == pytest.approx(0.02)
    assert contact_offset_from_urdf(xml, "other") == 0.0


def test_whole_body_com_in_the_planning_frame_equals_pinocchio(mammal):
    """PlanningModel.com_offset_in_base (mammal link moments with hips, pitch and knee points
    and link CMs moved to the body-CoG frame) + the body CoG = pin.centerOfMass."""
    model = planning_model(mammal)
    rng = np.random.default_rng(3)
    lo = np.concatenate([leg.q_lower for leg in mammal.legs])
    hi = np.concatenate([leg.q_upper for leg in mammal.legs])
    q = rng.uniform(np.maximum(lo, -3.0), np.minimum(hi, 3.0), size=(20, 12))
    com = model.com_offset_in_base(q) + model.position_body_com_in_root
    ff = mammal.model_free_flyer  # the fixed-base model leaves out the body
    data = ff.createData()
    base = np.array([0, 0, 0, 0, 0, 0, 1.0])
    for i in range(len(q)):
        ref = pin.centerOfMass(ff, data, np.concatenate([base, mammal.to_pinocchio_q(q[i])]))
        np.testing.assert_allclose(com[i], ref, atol=1e-10)


def test_swing_com_of_a_mammal_equals_the_com_of_its_ik(go2):
    """The step builder's swing CoM (family dispatch) equals com_in_world of the legs' IK."""
    model = planning_model(go2)
    ws = workspace_for(go2, 0.28)
    base = np.array([0.1, -0.05, 0.28])
    yaw = 0.3
    c, s = np.cos(yaw), np.sin(yaw)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    feet = base + ws.position_mid_in_base @ rot.T
    end = feet[2] + np.array([0.1, 0.0, 0.0])
    got = model.swing_com_in_world(base, yaw, feet, 2, end, ws.swing_height_m, n=5)
    tau = np.linspace(0.0, 1.0, 5)
    blend = 0.5 * (1 - np.cos(np.pi * tau))
    q = np.empty((5, 12))
    for k, leg in enumerate(model.legs):
        target = np.repeat(feet[k][None], 5, axis=0)
        if k == 2:
            target = feet[2] + blend[:, None] * (end - feet[2])
            target[:, 2] += _lift(tau, ws.swing_height_m)
        q[:, 3 * k : 3 * k + 3] = inverse_kinematics(leg, (target - base) @ rot).q
    ref = model.com_in_world(q, np.repeat(base[None], 5, axis=0), np.full(5, yaw))
    np.testing.assert_allclose(got, ref[:, :2], atol=1e-12)


def _lift(tau, h):
    from planner.trajectory.profiles import lift

    return lift(tau, 1.0, h).s


def test_reachable_mask_agrees_with_forward_kinematics(go2):
    """Every FK sample of the joint space on the rest branch, within limits and with the knee
    20°+ from stretched, lies in the mask at its own height (completeness); every node of a
    mask goes back through FK(IK) to itself within limits (soundness)."""
    leg = planning_robot(go2).legs[0]
    rng = np.random.default_rng(0)
    q = rng.uniform(leg.q_lower, leg.q_upper, size=(4000, 3))
    keep = (branch_of(leg, q[:, 2]) == leg.knee_branch) & (
        knee_angle(leg, q) >= DEFAULT_KNEE_MARGIN + 1e-6
    )
    p = forward_kinematics(leg, q[keep])
    below = p[:, 2] < leg.position_hip_in_base[2] - 0.05  # foot under the HAA axis
    p = p[below]
    assert len(p) > 200
    ok = np.array(
        [reachable_mask_at(leg, pt[None, :2], pt[2], DEFAULT_KNEE_MARGIN)[0] for pt in p[:300]]
    )
    assert ok.mean() > 0.99, ok.mean()  # the rest: foot above the HAA axis side
    sets = reachable_set(leg, (-0.28,), DEFAULT_KNEE_MARGIN)
    nodes = sets.nodes_in_base
    targets = np.column_stack([nodes, np.full(len(nodes), -0.28)])
    q_ik = inverse_kinematics(leg, targets).q
    np.testing.assert_allclose(forward_kinematics(leg, q_ik), targets, atol=1e-9)
    assert np.all(q_ik >= leg.q_lower - 1e-9) and np.all(q_ik <= leg.q_upper + 1e-9)
    # erosion: a point inside the eroded set has its whole disc in the set
    inside = nodes[sets.contains(nodes, 0.03)]
    a = rng.uniform(0, 2 * np.pi, len(inside))
    ring = inside + 0.029 * np.column_stack([np.cos(a), np.sin(a)])
    assert sets.contains(ring).all()


def test_mammal_robots_have_a_height_range(mammal):
    lo, hi = feasible_height_range(mammal)
    assert 0.0 < lo < hi
    assert workspace_for(mammal, 0.5 * (lo + hi)).stride_m >= 0.1


def test_hyq_has_no_height_within_its_effort_budget(hyq):
    """HyQ's creeping stances break 0.85 x its URDF effort at every height but a sliver
    near 0.634 m (planner/workspace/stance_budget.py): the range is refused naming the
    budget (it came out inverted, [0.6386, 0.6352] m, before)."""
    with pytest.raises(PlannerInputError, match="effort budget"):
        feasible_height_range(hyq)


@settings(max_examples=6, **SETTINGS)
@given(data=st.data())
def test_mammal_plans_satisfy_every_invariant(mammal, data):
    """Stance feet fixed in W, margin >= threshold on every lift, limits, no NaN, feet on
    the ground (ball contact), swing legs at rest at lift-off and touch-down: random paths
    (with turns) and heights on go2 and solo12."""
    lo, hi = feasible_height_range(mammal)
    height = data.draw(st.floats(lo + 0.2 * (hi - lo), hi - 0.2 * (hi - lo)))
    point = st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0))
    waypoints = np.array(data.draw(st.lists(point, min_size=1, max_size=2)))
    plan = plan_path(mammal, waypoints, height, samples_per_unit=10)
    check_invariants(planning_robot(mammal), plan)


def test_crab_stances_at_the_crab_limit_keep_the_calves_off_the_ground(mammal):
    """The crab limit (planner/gaits/creep_spin.py crab_limit_rad) admits a crab angle only
    where the turned footholds keep every non-foot shape MIN_GROUND_CLEARANCE_M above the
    ground, measured as the run's check measures it (clearance_of_poses on the URDF robot,
    the base at its nominal pose); low in the range, where the legs fold, the limit is tight:
    one CRAB_STEP_RAD more fails. go2 at 0.1852 m crabbed at 10° with LF's calf 6.7 mm into
    the ground (the 200-case corpus's #3)."""
    model = planning_model(mammal)
    robot = model.planning_robot
    lo, _ = feasible_height_range(mammal)
    tight = 0
    for height in (lo, lo + 0.005, lo + 0.01, lo + 0.02):
        ws = workspace_for(robot, height)
        limit = crab_limit_rad(robot, ws)
        for angle in (-limit, limit):
            for which in ("front", "rear"):
                feet = np.array([foothold_in_base(ws, k, "+x", which, angle) for k in range(4)])
                q = np.concatenate(
                    [
                        inverse_kinematics(leg, feet[k][None]).q[0]
                        for k, leg in enumerate(robot.legs)
                    ]
                )
                clearance = clearance_of_poses(
                    model.robot, q[None], np.array([[0.0, 0.0, height]]), np.zeros(1)
                )
                assert clearance.min() >= MIN_GROUND_CLEARANCE_M, (height, np.degrees(angle), which)
        if limit < CRAB_MAX_RAD - 1e-9:
            tight += 1
            past = limit + CRAB_STEP_RAD
            assert not crab_stances_clear(robot, ws, np.array([past]))[0]
    assert tight  # the low end folds the calves: the clearance, not the reach, bounds the crab


def test_go2_low_in_its_range_turns_rather_than_crab_its_calves_into_the_ground(go2):
    """go2 at h 0.1852 m to (0.6, -0.1) from heading 0: 9.5° off the heading, which facing the
    path crabbed (crab limit 10°, from the reach alone) with LH's front foothold 26 mm in
    under the body, and the run refused the plan (RL_calf -0.5 mm at t 5.28 units, in LH's
    swing down to it; the 200-case corpus's #3 the same way). The crab limit at this height
    is now 0 (the crab stances' clearance): it turns to face the waypoint, and every sample
    keeps every non-foot shape MIN_GROUND_CLEARANCE_M off the ground (no warning)."""
    run = plan_run(go2, np.array([[0.6, -0.1]]), 0.1852, RunRequest(), start_heading=0.0)
    assert run.plan.spins
    clearance = ground_clearance(planning_model(go2).robot, run.plan.trajectory)
    assert clearance.min() >= MIN_GROUND_CLEARANCE_M
    assert not any("ground clearance" in w for w in run.metrics.get("warnings", []))


def test_mammal_velocities_match_finite_differences(go2):
    plan = plan_path(go2, np.array([[0.3, 0.4]]), 0.28, samples_per_unit=10, face_path=True)
    assert any(s.kind == "rotate" for s in plan.steps)  # it turns
    check_finite_differences(planning_robot(go2), plan)


def test_go2_animation_draws_simplified_meshes_and_puts_its_feet_on_the_plan(go2):
    """Go2's 5.3 MB of COLLADA exceed the mesh budget: its meshes are embedded simplified (as
    STL, not its files, no stick figure), and the scene's feet are where the plan says (foot
    frames chained through the scene's transforms, as tests/test_animation.py does for
    SILO4)."""
    import umsgpack
    from test_animation import SCENE_FK_TOLERANCE, _decode, scene_foot_in_world

    from planner.trajectory.samples import LEGS
    from viz.animation.mesh_budget import MESH_BUDGET_BYTES, mesh_bytes
    from viz.animation.page import build_scene
    from viz.animation.playback import playback_frame_indices

    assert mesh_bytes(go2) > MESH_BUDGET_BYTES
    plan = plan_path(go2, np.array([[0.0, 0.3]]), 0.28, samples_per_unit=10)
    traj = plan.trajectory
    rec, _ = build_scene(go2, traj)
    objects = [umsgpack.unpackb(b) for b in rec.commands()]
    paths = [c["path"] for c in objects if c["type"] == "set_object"]
    assert not any("stick_" in p for p in paths)
    formats = [
        g["format"]
        for c in objects
        if c["type"] == "set_object"
        for g in c["object"].get("geometries", ())
        if g.get("type") == "_meshfile_geometry"
    ]
    assert formats and set(formats) == {"stl"}
    statics, clips = _decode(rec)
    idx = playback_frame_indices(traj.t - traj.t[0], 25.0)
    for k in (0, len(idx) // 2, len(idx) - 1):
        for leg_index, leg in enumerate(LEGS):
            foot = scene_foot_in_world(statics, clips, leg, k)
            expected = traj.position_foot_in_world[idx[k], leg_index].copy()
            expected[2] += foot_contact_offset_m(go2)  # the plan's feet are contact points
            assert np.max(np.abs(foot - expected)) < SCENE_FK_TOLERANCE


def test_silo4_robots_lists_rows_and_refuses_unknown_names(capsys):
    from viz.cli.main import main

    assert main(["robots", "--only", "nosuchrobot"]) == 2
    assert "known: silo4, go2" in capsys.readouterr().err
    assert main(["robots", "--only", "silo4"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].split()[:2] == ["robot", "family"]
    name, family, mass, rng, stride, any_direction = out[1].split()
    assert (name, family) == ("silo4", "insect") and float(mass) == pytest.approx(42.44, abs=0.01)
    lo, hi = (float(v) for v in rng.split("-"))
    assert 0.1 < lo < hi and float(stride) > 0.1
    assert any_direction == rng  # SILO4's diagonal legs step across the body at every height
