"""Mammal legs (hip ab/adduction first): closed form vs Pinocchio, finite differences, numeric IK.

Every example-robot-data quadruped the toolkit supports is loaded by name; its legs are found
from the geometry (discovery.discover_mammal_legs) and checked like SILO4's (check.py).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from silo4kin import kinematics, mammal
from silo4kin.check import cross_check
from silo4kin.discovery import NotInsectLegError
from silo4kin.errors import RobotDescriptionError
from silo4kin.numeric_ik import dls_inverse_kinematics
from silo4kin.robot import load_robot
from silo4kin.robot_library import EXAMPLE_QUADRUPEDS

#: Finite-difference step [rad] and tolerance of central differences (error ~ h² x |p'''|).
FD_STEP = 1e-6
FD_TOLERANCE = 1e-8
#: Numeric IK agrees with a closed form to this [rad] (it stops at 1e-11 m foot error).
DLS_AGREEMENT = 1e-7


@pytest.fixture(scope="module", params=EXAMPLE_QUADRUPEDS)
def quadruped(request):
    return load_robot(request.param)


def _in_limit_states(leg, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    mid = 0.5 * (leg.q_lower + leg.q_upper)
    lo = np.maximum(leg.q_lower, mid - np.pi)
    hi = np.minimum(leg.q_upper, mid + np.pi)
    return rng.uniform(lo, hi, (n, 3)), rng.standard_normal((n, 3))


def test_every_example_quadruped_is_a_mammal_whose_closed_form_matches_pinocchio(quadruped):
    """silo4 check's rows (fk, J, J̇q̇, IK on the sample's branch) pass on every leg."""
    assert quadruped.family == "mammal"
    assert [leg.name for leg in quadruped.legs] == ["LF", "RF", "LH", "RH"]
    rows = cross_check(quadruped, n=200, seed=3)
    assert {r.quantity for r in rows} == {"fk", "jacobian", "jdot_qd", "ik"}
    bad = [r for r in rows if not r.ok]
    assert not bad, bad


def test_a_perturbed_thigh_fails_the_check():
    """The check can fail: 0.1 mm on RF's thigh shows in fk, jacobian and ik."""
    robot = load_robot("go2")
    legs = list(robot.legs)
    thigh = legs[1].thigh_in_plane + np.array([0.0, -1e-4])
    legs[1] = dataclasses.replace(legs[1], thigh_in_plane=thigh)
    failed = {(r.quantity, r.leg) for r in cross_check(robot, n=100, seed=0, legs=legs) if not r.ok}
    assert {("fk", "RF"), ("jacobian", "RF")} <= failed
    assert all(leg == "RF" for _, leg in failed)


def test_jacobian_and_jdot_match_finite_differences_of_the_closed_form(quadruped):
    """J = ∂p/∂q and J̇q̇ = d/dt(J q̇) at q̈ = 0, by central differences (no Pinocchio)."""
    for leg in quadruped.legs:
        q, qd = _in_limit_states(leg, 50, seed=7)
        jac = mammal.jacobian(leg, q)
        for j in range(3):
            dq = np.zeros(3)
            dq[j] = FD_STEP
            fd = (
                mammal.forward_kinematics(leg, q + dq) - mammal.forward_kinematics(leg, q - dq)
            ) / (2 * FD_STEP)
            assert np.abs(fd - jac[..., j]).max() < FD_TOLERANCE
        fd_jdqd = (
            np.einsum("nij,nj->ni", mammal.jacobian(leg, q + FD_STEP * qd), qd)
            - np.einsum("nij,nj->ni", mammal.jacobian(leg, q - FD_STEP * qd), qd)
        ) / (2 * FD_STEP)
        jdqd = mammal.jacobian_derivative_times_velocity(leg, q, qd)
        assert np.abs(fd_jdqd - jdqd).max() < 1e3 * FD_TOLERANCE


def test_every_ik_solution_reaches_the_target(quadruped):
    """The sample's own knee branch and foot side always solve; every other (branch, side)
    that the geometry allows puts the foot back where FK had it too."""
    for leg in quadruped.legs:
        q, _ = _in_limit_states(leg, 200, seed=11)
        target = mammal.forward_kinematics(leg, q)
        own = mammal.inverse_kinematics(
            leg, target, mammal.branch_of(leg, q[:, 2]), mammal.foot_side_of(leg, q)
        )
        assert own.reachable.all()
        for branch in (1, -1):
            for side in (1.0, -1.0):
                ik = mammal.inverse_kinematics(leg, target, branch, side)
                back = mammal.forward_kinematics(leg, ik.q[ik.reachable])
                assert np.abs(back - target[ik.reachable]).max(initial=0.0) < 1e-12


def test_the_default_branch_is_the_standing_pose():
    """IK of the SRDF standing pose's feet returns the standing pose (knee branch, side)."""
    import pinocchio as pin

    for name in ("go2", "solo12", "anymal", "hyq"):
        robot = load_robot(name)
        rest = None
        for leg in robot.legs:
            idx = [robot.model.joints[robot.model.getJointId(n)].idx_q for n in leg.joint_names]
            from silo4kin.robot import _reference_posture
            from silo4kin.robot_library import resolve_example_robot

            rest = _reference_posture(robot.model, resolve_example_robot(name))
            assert rest is not None
            q_rest = rest[idx]
            ik = mammal.inverse_kinematics(leg, mammal.forward_kinematics(leg, q_rest))
            assert ik.within_limits
            assert np.abs(ik.q - q_rest).max() < 1e-9, (name, leg.name)
        assert pin is not None


def test_numeric_ik_agrees_with_the_mammal_closed_form():
    """Pinocchio DLS IK (any 3-DoF leg) lands on one of the closed form's solutions."""
    robot = load_robot("anymal")
    for k, leg in enumerate(robot.legs[:2]):
        q, _ = _in_limit_states(leg, 30, seed=5)
        target = mammal.forward_kinematics(leg, q)
        dls = dls_inverse_kinematics(robot, k, target, 0.5 * (leg.q_lower + leg.q_upper))
        assert dls.converged.all()
        closed = mammal.inverse_kinematics(
            leg, target, mammal.branch_of(leg, dls.q[:, 2]), mammal.foot_side_of(leg, dls.q)
        ).q
        unique = mammal.ik_is_unique(leg, target)
        diff = np.abs(np.angle(np.exp(1j * (closed - dls.q))))[unique]
        assert diff.max() < DLS_AGREEMENT


def test_numeric_ik_agrees_with_the_insect_closed_form():
    """On SILO4, DLS IK from the knee-down middle of the limits = eq 3.10-3.24's solution."""
    robot = load_robot()
    for k, leg in enumerate(robot.legs):
        rng = np.random.default_rng(k)
        q = rng.uniform(leg.q_lower, leg.q_upper, (30, 3))
        target = kinematics.forward_kinematics(leg, q)
        dls = dls_inverse_kinematics(robot, k, target, 0.5 * (leg.q_lower + leg.q_upper))
        assert dls.converged.mean() > 0.9
        dist = kinematics.singularity_distance(leg, dls.q)
        ok = dls.converged & (dist.knee_rad > 1e-3) & (dist.radial_m > 1e-3)
        closed = kinematics.inverse_kinematics_masked(leg, target).q
        knee_down = np.isfinite(closed).all(axis=1)
        same = ok & knee_down & (np.abs(closed - dls.q).max(axis=1) < 1e-6)
        # the DLS solution is knee-down (SILO4's limits allow nothing else) and is eq 3.10-3.24's
        assert same.sum() >= 0.9 * ok.sum()


def test_two_dof_legs_and_unknown_names_are_refused_with_the_reason():
    with pytest.raises(NotInsectLegError, match=r"has 2 joints; a supported leg has 3"):
        load_robot("solo8")
    with pytest.raises(RobotDescriptionError, match=r"not a quadruped: found 1 leg chain"):
        load_robot("ur5")
    with pytest.raises(RobotDescriptionError, match=r"unknown robot 'go3'.*did you mean go2"):
        load_robot("go3")


def test_a_leg_of_another_family_among_mammal_legs_is_refused():
    """One leg of go2 turned into a yaw joint: refused naming that leg and joint."""
    robot = load_robot("go2")
    text = robot.urdf_xml
    start = text.index('name="RR_hip_joint"')
    axis = text.index("<axis", start)
    end = text.index("/>", axis)
    mutated = text[:axis] + '<axis xyz="0 0 1"' + text[end:]
    import pinocchio as pin

    from silo4kin.discovery import discover_mammal_legs

    with pytest.raises(NotInsectLegError, match=r"RH chain: first joint 'RR_hip_joint'.*not along"):
        discover_mammal_legs(pin.buildModelFromXML(mutated))


def test_joint_motion_rates_match_finite_differences_along_a_foot_path():
    """legs.joint_motion on a mammal leg: q̇ and q̈ equal central differences of q(t)."""
    from silo4kin import legs as leg_api

    robot = load_robot("go2")
    leg = robot.legs[0]
    rest = mammal.forward_kinematics(leg, np.array([0.0, 0.8, -1.5]))
    t = np.linspace(0.0, 1.0, 2001)
    dt = t[1] - t[0]
    amplitude = np.array([0.05, 0.02, 0.04])
    w = 2 * np.pi
    p = rest + amplitude * np.sin(w * t)[:, None]
    pd = amplitude * w * np.cos(w * t)[:, None]
    pdd = -amplitude * w * w * np.sin(w * t)[:, None]
    motion = leg_api.joint_motion(leg, p, pd, pdd)
    assert motion.reachable.all()
    assert np.abs(leg_api.forward_kinematics(leg, motion.q) - p).max() < 1e-12
    fd_qd = (motion.q[2:] - motion.q[:-2]) / (2 * dt)
    fd_qdd = (motion.qd[2:] - motion.qd[:-2]) / (2 * dt)
    assert np.abs(fd_qd - motion.qd[1:-1]).max() < 1e-4
    assert np.abs(fd_qdd - motion.qdd[1:-1]).max() < 1e-2


def test_leg_mass_moments_give_pinocchios_centre_of_mass():
    """Body CoM + Σ legs' m_i c_i (mammal.leg_mass_moment_in_base) = pin.centerOfMass of the
    free-flyer model at the identity base pose (the fixed-base model leaves out the body)."""
    import pinocchio as pin

    for name in ("go2", "anymal_c", "hyq"):
        robot = load_robot(name)
        model = robot.model_free_flyer
        data = model.createData()
        rng = np.random.default_rng(2)
        q = np.concatenate(
            [_in_limit_states(leg, 20, seed=k)[0] for k, leg in enumerate(robot.legs)], axis=1
        )
        moment = robot.body_mass * robot.position_body_com_in_base + np.zeros((20, 3))
        for k, leg in enumerate(robot.legs):
            moment += mammal.leg_mass_moment_in_base(leg, q[:, 3 * k : 3 * k + 3])
        com = moment / robot.total_mass
        for i in range(20):
            base = np.array([0, 0, 0, 0, 0, 0, 1.0])
            ref = pin.centerOfMass(model, data, np.concatenate([base, robot.to_pinocchio_q(q[i])]))
            assert np.abs(com[i] - ref).max() < 1e-10, name
        assert rng is not None


def test_thesis_workspace_is_refused_for_mammal_legs_with_the_reason():
    """The thesis's square workspace needs a hip-yaw reference pose: refused by name, exit 2
    (the default workspace plans mammal legs, tests/test_mammal_planning.py)."""
    from planner.errors import PlannerInputError
    from planner.path.plan_path import plan_path

    with pytest.raises(PlannerInputError, match=r"mammal legs.*'default' workspace"):
        plan_path(load_robot("go2"), np.array([[0.0, 1.0]]), height=0.3, workspace="thesis")


def test_a_robot_name_beside_a_folder_of_that_name(tmp_path, monkeypatch, capsys):
    """``silo4 plan --robot go2 --out go2`` makes a folder go2 in the working folder; the
    name still means the robot go2 afterwards (a second plan, as a file it would be refused
    as "a folder"), while a file of that name is read as a robot file."""
    pytest.importorskip("example_robot_data")
    from silo4kin.robot_library import looks_like_name
    from viz.cli.main import main

    monkeypatch.chdir(tmp_path)
    plan = [
        "plan",
        "--robot",
        "go2",
        "--height",
        "0.28",
        "--waypoints",
        "0,0.3",
        "--out",
        "go2",
        "--samples-per-unit",
        "5",
        "--no-html",
        "--no-plots",
        "--no-csv",
    ]
    assert main(plan) == 0
    assert (tmp_path / "go2").is_dir() and looks_like_name("go2")
    assert main(plan) == 0, capsys.readouterr().err
    (tmp_path / "a1").write_text("<robot/>")
    assert not looks_like_name("a1")
