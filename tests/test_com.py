"""Whole-robot CoM: the closed form (silo4kin/com.py) against pin.centerOfMass."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from silo4kin import load_robot
from silo4kin.check import random_states
from silo4kin.com import center_of_mass_closed_form, legs_com_offset
from silo4kin.joint_torques import free_flyer_q_index

#: Closed form vs Pinocchio [m]: both sum ~13 products of O(1) numbers; rounding ~1e-16.
COM_TOLERANCE_M = 1e-12
MANTIS = Path(__file__).parent / "robots" / "mantis.urdf"


def _pinocchio_com(robot, q: np.ndarray) -> np.ndarray:
    """pin.centerOfMass of the free-flyer model at the identity base pose (the fixed-base
    model's centerOfMass leaves out the root link: it is part of the universe)."""
    model = robot.model_free_flyer
    data = model.createData()
    q_ff = np.zeros((q.shape[0], model.nq))
    q_ff[:, 6] = 1.0
    q_ff[:, free_flyer_q_index(robot)] = q
    return np.array([pin.centerOfMass(model, data, qi) for qi in q_ff])


@pytest.mark.parametrize("which", ["silo4", "mantis", "variant"])
def test_closed_form_com_matches_pinocchio(which: str, silo4) -> None:
    """The whole-robot CoM of the closed form equals pin.centerOfMass on random states."""
    robot = {
        "silo4": lambda: silo4,
        "mantis": lambda: load_robot(MANTIS),
        "variant": lambda: load_robot(xacro_args={"L2": 0.3, "L3": 0.35}),
    }[which]()
    q, _, _ = random_states(robot, 300, seed=7)
    err = np.abs(center_of_mass_closed_form(robot, q) - _pinocchio_com(robot, q)).max()
    assert err < COM_TOLERANCE_M, err


def test_planning_frame_offset_is_com_minus_body_com(silo4) -> None:
    """legs_com_offset on hips measured from the body CoM is CoM - body CoM (mantis: off-centre
    body CoM), so the planner may work in the body-CoG frame."""
    from planner.path.plan_path import robot_in_body_com_frame

    robot = load_robot(MANTIS)
    framed = robot_in_body_com_frame(robot)
    q, _, _ = random_states(robot, 50, seed=3)
    offset = legs_com_offset(framed.legs, q, robot.total_mass)
    expected = _pinocchio_com(robot, q) - robot.position_body_com_in_base
    assert np.abs(offset - expected).max() < COM_TOLERANCE_M


def test_a_wrong_link_mass_is_seen(silo4) -> None:
    """The check can fail: the femur CM moved 1 cm along the link changes the CoM by > 1e-5 m."""
    from dataclasses import replace

    leg = silo4.legs[0]
    femur = leg.links[1]
    moved = replace(femur, com=femur.com + np.array([0.01, 0.0, 0.0]))
    bad = replace(
        silo4, legs=(replace(leg, links=(leg.links[0], moved, leg.links[2])),) + silo4.legs[1:]
    )
    q, _, _ = random_states(silo4, 20, seed=1)
    err = np.abs(center_of_mass_closed_form(bad, q) - _pinocchio_com(silo4, q)).max()
    assert err > 1e-5


@pytest.mark.parametrize("which", ["silo4", "mantis"])
def test_swing_com_fast_path_equals_ik_and_closed_form(which: str, silo4) -> None:
    """PlanningModel.swing_com_in_world (one fused IK + CoM pass over legs and samples) equals
    silo4kin's IK (inverse_kinematics_masked) followed by legs_com_offset, on random stances
    and swings with the base displaced and yawed."""
    from planner.model import planning_model
    from planner.trajectory.profiles import cosine_blend, lift
    from silo4kin.kinematics import forward_kinematics, inverse_kinematics_masked

    robot = silo4 if which == "silo4" else load_robot(MANTIS)
    model = planning_model(robot)
    rng = np.random.default_rng(5)
    q, _, _ = random_states(robot, 40, seed=11)
    n_checked = 0
    for i in range(0, 40, 2):
        feet_b = np.array(
            [forward_kinematics(g, q[i, 3 * k : 3 * k + 3]) for k, g in enumerate(model.legs)]
        )
        end_b = np.array(forward_kinematics(model.legs[0], q[i + 1, :3]))
        yaw = rng.uniform(-np.pi, np.pi)
        base = np.array([*rng.uniform(-2, 2, 2), 0.4])
        c, s = np.cos(yaw), np.sin(yaw)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        feet_w = base + feet_b @ rot.T
        end_w = base + rot @ end_b
        leg = int(rng.integers(4))
        end_w = base + rot @ np.array(
            forward_kinematics(model.legs[leg], q[i + 1, 3 * leg : 3 * leg + 3])
        )
        got = model.swing_com_in_world(base, yaw, feet_w, leg, end_w, 0.05, n=11)
        tau = np.linspace(0.0, 1.0, 11)
        path = feet_w[leg] + (end_w - feet_w[leg]) * cosine_blend(tau, 1.0).s[:, None]
        path[:, 2] += lift(tau, 1.0, 0.05).s
        q_ref = np.tile(
            np.concatenate(
                [inverse_kinematics_masked(g, feet_b[k]).q for k, g in enumerate(model.legs)]
            ),
            (11, 1),
        )
        q_ref[:, 3 * leg : 3 * leg + 3] = inverse_kinematics_masked(
            model.legs[leg], (path - base) @ rot
        ).q
        ref = base[:2] + (model.com_offset_in_base(q_ref) @ rot.T)[:, :2]
        ok = np.all(np.isfinite(ref), axis=1)
        np.testing.assert_array_equal(ok, np.all(np.isfinite(got), axis=1))
        n_checked += int(ok.sum())
        if ok.any():
            assert np.abs(got[ok] - ref[ok]).max() < COM_TOLERANCE_M
    assert n_checked > 100


def test_the_builders_swing_com_follows_the_gaits_profiles(silo4) -> None:
    """The whole-body CoM the step builder checks over a still-base swing is the CoM of the
    plan's samples over that swing: a smooth gait (the default's creep) is sampled on the
    quintic and the smooth lift, and its lifts are checked on them (they were checked on the
    thesis's cosine blends, up to ~1 mm away)."""
    from planner import plan_path
    from planner.model import planning_model

    plan = plan_path(silo4, np.array([[0.0, 1.0], [0.0, 2.0]]), 0.4, gait="creep")
    model, traj = planning_model(silo4), plan.trajectory
    spu = round(1.0 / (traj.time_units[1] - traj.time_units[0]))
    checked = 0
    for step in plan.steps:
        start, end = step.position_base_start_in_world, step.position_base_end_in_world
        if step.leg is None or not np.array_equal(start, end):
            continue
        rows = np.arange(round(step.t_start * spu), round(step.t_end * spu) + 1)
        sampled = model.com_in_world(
            traj.q[rows], traj.position_base_in_world[rows], traj.yaw_base_in_world[rows]
        )[:, :2]
        leg = ("LF", "RF", "LH", "RH").index(step.leg)
        args = (start, step.yaw_base_start, step.position_feet_in_world, leg)
        end_w, h = step.foothold_end_in_world, plan.workspace.swing_height_m
        got = model.swing_com_in_world(*args, end_w, h, n=len(rows), smooth=True)
        assert np.abs(got - sampled).max() < 1e-9
        cosine = model.swing_com_in_world(*args, end_w, h, n=len(rows))
        assert np.abs(cosine - sampled).max() > 1e-5  # the control: the profiles differ
        checked += 1
    assert checked >= 4
