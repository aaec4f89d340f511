"""A plan starts at rest on four loaded feet (issue 21).

Where a gait's first step is a transfer, its first sample used to have the swing foot out of
contact while it stood on the ground: the torques of that first posture were the three-foot
support's, and the sim's calibration, which holds the first posture, stood the robot on
three loaded feet and one unloaded one (go2 corpus case 27: that foot rose 1.8 mm and
another slid 11.8 mm; docs/physics.md). The default preset now stands on four feet first
(planner/gaits/walk.py start_stand_units); the thesis preset keeps the thesis's first step.
"""

from __future__ import annotations

import numpy as np
import pytest

from planner.gaits.steps import Phase, StepKind
from planner.gaits.walk import START_STAND_UNITS
from planner.path.plan_path import plan_path
from planner.trajectory.torques import add_torques
from silo4kin.load_transfer import LOAD_TRANSFER_S, load_shares
from silo4kin.robot import load_robot

pytest.importorskip("example_robot_data")

PATH = np.array([[0.0, 0.6]])


@pytest.fixture(scope="module")
def go2_plan(go2):  # noqa: ANN201
    return go2, plan_path(go2, PATH, 0.28)


def test_a_plan_whose_first_step_lifts_a_foot_stands_on_four_feet_first(go2_plan) -> None:
    _, plan = go2_plan
    stand, first = plan.steps[0], plan.steps[1]
    assert stand.phase == Phase.STAND and stand.kind == StepKind.BODY
    assert first.kind == StepKind.TRANSFER
    assert stand.duration == pytest.approx(START_STAND_UNITS + 0.01)  # 100 samples a unit
    assert first.t_start == pytest.approx(stand.t_end)
    tr = plan.trajectory
    assert tr.contact[0].all()
    still = tr.time_units < stand.t_end
    assert np.ptp(tr.q[still], axis=0).max() == 0.0  # at rest
    # the first posture carries the four-foot split; the lifting foot gives its load away
    # before it lifts
    shares = load_shares(tr.contact, tr.t, LOAD_TRANSFER_S)
    assert np.all(shares[0] == 1.0)
    lifts = np.flatnonzero(~tr.contact.all(axis=1))[0]
    assert shares[lifts - 1].min() < 0.01


def test_the_first_posture_is_held_on_four_loaded_feet(go2_plan) -> None:
    """The calibration's feed-forward is the four-foot stance's: every foot carries a share
    of the weight (three-foot torques left one at 0 N and slid another)."""
    pytest.importorskip("mujoco")
    from silo4sim.metrics import measure_standing
    from silo4sim.model import build_sim_model
    from silo4sim.replay import stand_still
    from silo4sim.settings import SimSettings

    robot, plan = go2_plan
    traj = add_torques(robot, plan.trajectory, load="total")
    sm = build_sim_model(robot, SimSettings(friction=0.8, ball_feet=True))
    rec = stand_still(sm, traj, 1.0)
    force = rec.get("foot_force", sm)[-1]
    weight = robot.total_mass * 9.81
    assert force.min() > 0.1 * weight
    assert measure_standing(sm, rec)["ok"]


def test_the_thesis_preset_keeps_the_thesis_first_step() -> None:
    plan = plan_path(load_robot(None), np.array([[0.0, 1.0]]), 0.4, workspace="thesis")
    assert plan.steps[0].kind == StepKind.TRANSFER
    assert plan.steps[0].t_start == 0.0
