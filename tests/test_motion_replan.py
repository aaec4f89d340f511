"""A run whose motion alone breaks the effort budget is planned again with the step builder's
share of the effort lowered (planner/outputs/pipeline.py plan_run, MOTION_REPLANS).

mantis (tests/robots) low in its range, 200-case corpus #7 of benchmarks/bench_corpus.py:
the load caps held arm3_lift at 33.85 of its 34.00 N m budget standing still, and the
floating robot's torques (planner/trajectory/floating_torques.py) asked 34.01 N m in motion.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import planner.outputs.pipeline as pipeline
from planner.outputs.pipeline import RunRequest, plan_run
from planner.path.metrics import compute_metrics
from planner.trajectory.limits import JointLimitError, urdf_limits
from planner.trajectory.torques import trajectory_torques
from silo4kin.robot import load_robot

MANTIS = Path(__file__).parent / "robots" / "mantis.urdf"
PATH = np.array([[-0.28, -1.07], [0.41, -1.19], [0.88, -1.87]])
HEIGHT_M = 0.1927
HEADING_RAD = np.radians(52.0)


@pytest.fixture(scope="module")
def mantis():
    return load_robot(str(MANTIS))


def test_one_plan_alone_breaks_the_budget_in_motion(mantis, monkeypatch) -> None:
    """Without a second plan the run is refused, and the refusal measures the excess."""
    monkeypatch.setattr(pipeline, "MOTION_REPLANS", 1)
    with pytest.raises(JointLimitError, match="exceeds its effort budget") as refused:
        plan_run(mantis, PATH, HEIGHT_M, RunRequest(), start_heading=HEADING_RAD)
    share = refused.value.motion_share
    assert share.shape == (12,) and 0.0 < share.max() < 0.05
    assert mantis.joint_names[int(np.argmax(share))] == "arm3_lift"


def test_the_run_plans_again_leaving_its_motion_room(mantis) -> None:
    run = plan_run(mantis, PATH, HEIGHT_M, RunRequest(), start_heading=HEADING_RAD)
    plan = run.plan
    headroom = plan.preset.torque_headroom
    lowered = np.asarray(plan.preset.step_torque_headroom)
    assert lowered.shape == (12,) and lowered.min() < headroom
    assert np.all(lowered <= headroom)  # only the joints that broke the budget are lowered
    assert np.sum(lowered < headroom) < 12
    _, effort = urdf_limits(mantis)
    tau = trajectory_torques(mantis, plan.trajectory, load="total").total
    assert np.max(np.abs(tau) / effort) <= headroom * (1 + 1e-9)
    assert run.limits.violation is None and run.limits.unit_time_s == 1.0
    assert compute_metrics(plan)["normalized_error_m"] <= plan.tolerance


def test_a_static_excess_is_not_planned_again(mantis) -> None:
    """No motion helps a pose whose standing torques break the budget: refused at once,
    motion_share None (a 5 % headroom, far under mantis's standing torques)."""
    with pytest.raises(JointLimitError, match="no unit time helps") as refused:
        plan_run(
            mantis,
            PATH,
            HEIGHT_M,
            RunRequest(torque_headroom=0.05),
            start_heading=HEADING_RAD,
        )
    assert refused.value.motion_share is None


def test_a_reported_violation_is_planned_again_too(silo4) -> None:
    """``silo4 cases`` and sweeps report a limit violation instead of refusing it: the second
    plan happens alike (SILO4's crawl to (-0.3, 0.2) at 0.4 m: RH_knee 51.48 N m in a moving
    transfer against 51.00; tests/test_pipeline.py), and the run reports no violation."""
    from planner.outputs.pipeline import OnLimitViolation

    request = RunRequest(on_limit_violation=OnLimitViolation.REPORT)
    run = plan_run(silo4, [[-0.3, 0.2]], 0.4, request, samples_per_unit=10, gait="crawl")
    assert run.metrics["joint_limits"]["violation"] is None
    assert run.plan.gait == "crawl" and run.plan.preset.step_torque_headroom is not None
    monkey = pytest.MonkeyPatch()
    monkey.setattr(pipeline, "MOTION_REPLANS", 1)
    try:
        once = plan_run(silo4, [[-0.3, 0.2]], 0.4, request, samples_per_unit=10, gait="crawl")
    finally:
        monkey.undo()
    assert "RH_knee" in once.metrics["joint_limits"]["violation"]
