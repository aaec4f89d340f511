"""Leg interference (thesis §3.6): neighbouring feet keep a clearance on every plan."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from planner import PlanningError, plan_path
from planner.workspace.interference import LEG_CLEARANCE_M, check_interference, neighbour_distances
from silo4kin import load_robot

ROBOTS_DIR = Path(__file__).resolve().parent / "robots"


@pytest.mark.parametrize("robot_file", [None, "mantis.urdf", "phasmid.urdf.xacro"])
def test_plans_keep_neighbouring_feet_apart(robot_file):
    robot = load_robot(None if robot_file is None else ROBOTS_DIR / robot_file)
    plan = plan_path(robot, [(0.5, 0.5), (0.0, 1.0)], 0.3, samples_per_unit=10)
    d = neighbour_distances(plan.trajectory)
    assert d.min() >= LEG_CLEARANCE_M
    assert check_interference(plan.trajectory) == pytest.approx(d.min())


def test_interference_is_refused_naming_the_legs_and_the_time(silo4):
    """A trajectory whose LH foot passes within 1 cm of LF's at one sample is refused with
    both legs and that sample's time; a clearance wider than the stance is refused too."""
    traj = plan_path(silo4, [(0.0, 0.5)], 0.4, samples_per_unit=10).trajectory
    feet = traj.position_foot_in_world.copy()
    k = 37
    feet[k, 2] = feet[k, 0] + np.array([0.01, 0.0, 0.0])
    bad = replace(traj, position_foot_in_world=feet)
    with pytest.raises(
        PlanningError,
        match=rf"legs LH and LF interfere: feet 0\.010 m apart "
        rf".* at t = {traj.time_units[k]:.2f} units",
    ):
        check_interference(bad)
    with pytest.raises(PlanningError, match="interfere"):
        check_interference(traj, clearance_m=1.0)
