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
    robot = {"silo4": lambda: silo4, "mantis": lambda: load_robot(MANTIS),
             "variant": lambda: load_robot(xacro_args={"L2": 0.3, "L3": 0.35})}[which]()
    q, _, _ = random_states(robot, 300, seed=7)
    err = np.abs(center_of_mass_closed_form(robot, q) - _pinocchio_com(robot, q)).max()
    assert err < COM_TOLERANCE_M, err


def test_planning_frame_offset_is_com_minus_body_com(silo4) -> None:
    """legs_com_offset on hips measured from the body CoM is CoM - body CoM (mantis: off-centre
    body CoM), so the planner may work in the body-CoG frame."""
    from planner.path import robot_in_body_com_frame
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
    bad = replace(silo4, legs=(replace(leg, links=(leg.links[0], moved, leg.links[2])),)
                  + silo4.legs[1:])
    q, _, _ = random_states(silo4, 20, seed=1)
    err = np.abs(center_of_mass_closed_form(bad, q) - _pinocchio_com(silo4, q)).max()
    assert err > 1e-5
