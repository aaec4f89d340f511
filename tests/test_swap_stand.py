"""Two transfers back to back stand on four feet between them for the load transfer
(planner/gaits/walk.py swap_stand_units, docs/physics.md "Two swings back to back stand
for the load transfer").

Without the stand one foot lands on the sample the other lifts, and the landing foot takes its
share of the three-foot support on that sample. solo12's corpus case 16 (seed 20261202) is the
measured case: its RF, planned to carry 0.35 W from the sample it lands on, chattered on the
floor (sim force 0 / 0.42 W every ~50 ms) and slid 5.7 mm, over the sim's 5 mm; with the
stand the plan's loads step by at most 0.004 W in a sample where a foot lands or lifts
(0.575 W before) and no foot slides more than 0.2 mm.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from planner.gaits.walk import SWAP_STAND_UNITS
from planner.model import planning_model
from planner.outputs.pipeline import RunRequest, plan_run
from planner.stability.contact_forces import ContactForceCheck
from planner.stability.contact_rule import ContactForceRule
from planner.trajectory.torques import add_torques, transfer_time_s

pytest.importorskip("example_robot_data")

#: benchmarks/bench_corpus.py case 16 of seed 20261202 (30 cases): solo12 at h 0.2552 m.
WAYPOINTS = np.array([[0.36, -0.58], [0.21, -1.21]])
HEIGHT_M = 0.2552
HEADING_RAD = np.radians(-155.0)


@pytest.fixture(scope="module")
def solo12_case(solo12):
    robot = solo12
    plan = plan_run(robot, WAYPOINTS, HEIGHT_M, RunRequest(), start_heading=float(HEADING_RAD)).plan
    return robot, plan, add_torques(robot, plan.trajectory, load="total")


def test_a_transfer_after_a_transfer_waits_for_the_load_transfer(solo12_case) -> None:
    robot, plan, traj = solo12_case
    steps = plan.steps
    stands = 0
    for a, b in zip(steps, steps[1:], strict=False):
        assert a.t_end == pytest.approx(b.t_start)
        assert not (a.kind == "transfer" and b.kind == "transfer")
    for a, stand, b in zip(steps, steps[1:], steps[2:], strict=False):
        if a.kind == "transfer" == b.kind and stand.phase == "stand":
            assert stand.duration >= SWAP_STAND_UNITS - 1e-9
            stands += 1
    assert stands, "the creep swings two legs back to back"
    # the loads the torques were computed with change smoothly through every contact change
    check = ContactForceCheck(
        ContactForceRule(), planning_model(robot), 9.80665, transfer_s=transfer_time_s("total")
    )
    forces = check.forces(traj)
    share = forces.normal_n / forces.weight_n
    contact = np.asarray(traj.contact, dtype=bool)
    change = (contact[1:] != contact[:-1]).any(axis=1)
    largest = float(np.abs(np.diff(share, axis=0))[change].max())
    assert largest < 0.02, largest  # 0.575 W in one sample before the stand (0.004 W after)


def test_solo12_case_16_walks_in_physics(solo12_case) -> None:
    pytest.importorskip("mujoco")
    from silo4sim.run import simulate
    from silo4sim.settings import SimSettings

    robot, _, traj = solo12_case
    settings = replace(SimSettings(), friction=0.8, ball_feet=True)  # the corpus's physics
    doc = simulate(robot, traj, settings=settings).metrics
    assert doc["walks"], doc["reasons"]
    assert doc["slip_max_m"] <= 0.001, doc["slip_per_leg_m"]  # 5.7 mm before the stand
