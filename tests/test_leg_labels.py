"""The robot's own leg and joint names, from its joint names (planner/outputs/leg_labels.py)."""

from __future__ import annotations

from planner.outputs.leg_labels import LegLabels
from planner.trajectory.samples import LEGS


def _names(legs: tuple[str, ...], joints: tuple[str, ...]) -> list[str]:
    return [f"{leg}_{j}" for leg in legs for j in joints]


def test_silo4_names_are_the_planner_s() -> None:
    labels = LegLabels.from_joint_names(_names(LEGS, ("hip_yaw", "hip_pitch", "knee")))
    assert labels == LegLabels(LEGS, ("hip yaw", "hip pitch", "knee"))


def test_go2_and_solo12_legs_and_joints() -> None:
    go2 = LegLabels.from_joint_names(
        _names(("FL", "FR", "RL", "RR"), ("hip_joint", "thigh_joint", "calf_joint"))
    )
    assert go2 == LegLabels(("FL", "FR", "RL", "RR"), ("hip", "thigh", "calf"))
    assert go2.leg("LH") == "RL"
    solo = LegLabels.from_joint_names(_names(("FL", "FR", "HL", "HR"), ("HAA", "HFE", "KFE")))
    assert solo == LegLabels(("FL", "FR", "HL", "HR"), ("HAA", "HFE", "KFE"))


def test_names_without_a_shared_prefix_fall_back() -> None:
    """No prefix shared by a leg's joints (or the same prefix on two legs): the planner's
    leg names; legs whose joints differ: generic joint labels."""
    flat = LegLabels.from_joint_names([f"j{k}" for k in range(12)])
    assert flat == LegLabels(LEGS, ("joint 1", "joint 2", "joint 3"))
    same = LegLabels.from_joint_names(_names(("L", "L", "R", "R"), ("a", "b", "c")))
    assert same.legs == LEGS
    mixed = _names(("FL", "FR", "RL", "RR"), ("a", "b", "c"))
    mixed[0] = "FL_z"
    assert LegLabels.from_joint_names(mixed) == LegLabels(
        ("FL", "FR", "RL", "RR"), ("joint 1", "joint 2", "joint 3")
    )
