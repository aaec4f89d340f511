"""The one plan pipeline (planner/outputs/pipeline.py): plan -> URDF limits -> torques ->
metrics, the same for ``silo4 plan``, ``silo4 cases`` and sweeps; only what a limit violation
does differs (refused or reported)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from planner.outputs.pipeline import OnLimitViolation, RunRequest, plan_run
from planner.trajectory.limits import JointLimitError, limit_plan
from planner.trajectory.torques import add_torques
from silo4kin.motors import Gearing

WAYPOINTS = np.array([[0.0, 0.3]])
HEIGHT_M = 0.4
#: A unit time far too short for SILO4's joint velocity limits [s].
TOO_FAST_S = 0.02


def test_a_violation_is_refused_or_reported(silo4) -> None:
    """REFUSE raises JointLimitError naming the limit; REPORT keeps the plan at its unit
    time and names the same violation in metrics (joint_limits.violation and a warning); a
    plan within the limits reports none."""
    request = RunRequest(unit_time=TOO_FAST_S)
    with pytest.raises(JointLimitError) as refused:
        plan_run(silo4, WAYPOINTS, HEIGHT_M, request, samples_per_unit=10)
    run = plan_run(
        silo4,
        WAYPOINTS,
        HEIGHT_M,
        replace(request, on_limit_violation=OnLimitViolation.REPORT),
        samples_per_unit=10,
    )
    assert run.plan.trajectory.unit_time_s == TOO_FAST_S
    violation = run.metrics["joint_limits"]["violation"]
    assert violation and violation in str(refused.value)
    assert any(violation in line for line in run.metrics["warnings"])
    fine = plan_run(
        silo4,
        WAYPOINTS,
        HEIGHT_M,
        RunRequest(on_limit_violation=OnLimitViolation.REPORT),
        samples_per_unit=10,
    )
    assert fine.metrics["joint_limits"] == {"unit_time_s": 1.0, "violation": None}


def test_the_pipeline_is_the_steps_it_names(silo4) -> None:
    """plan_run gives what plan_path, limit_plan, the friction's and the zero-moment point's
    unit time, add_torques and
    the sizing give one after the other: the same trajectory, bit for bit, and the metrics
    keys the run folder holds."""
    from planner.model import planning_model
    from planner.path.plan_path import plan_path
    from planner.stability.contact_forces import ContactForceCheck
    from silo4kin.robot import STANDARD_GRAVITY

    gearing = Gearing.uniform(12, 100.0, 0.7)
    run = plan_run(
        silo4,
        WAYPOINTS,
        HEIGHT_M,
        RunRequest(unit_time="auto", gearing=gearing),
        samples_per_unit=10,
    )
    plan = plan_path(silo4, WAYPOINTS, HEIGHT_M, samples_per_unit=10)
    plan, limits = limit_plan(silo4, plan, "auto", load=str(plan.preset.load))
    contact = ContactForceCheck(plan.preset.contact_forces, planning_model(silo4), STANDARD_GRAVITY)
    t_friction = max(
        contact.unit_time_for_friction(plan.trajectory),
        contact.unit_time_for_zmp(plan.trajectory),
    )
    assert t_friction > limits.unit_time_s  # the crawl's sway needs more time than the limits
    plan, limits = limit_plan(silo4, plan, t_friction, load=str(plan.preset.load))
    assert contact.first_violation(plan.trajectory) is None
    trajectory = add_torques(silo4, plan.trajectory, load=str(plan.preset.load))
    assert run.limits == limits
    np.testing.assert_array_equal(run.plan.trajectory.t, trajectory.t)
    np.testing.assert_array_equal(run.plan.trajectory.tau, trajectory.tau)
    assert run.metrics["joint_limits"] == limits.to_dict()
    assert run.metrics["torque_load"] == str(plan.preset.load)
    assert len(run.metrics["motor_sizing"]) == 12


def test_no_gearing_no_torques(silo4) -> None:
    """Without gearing the trajectory has no torques and the metrics no sizing."""
    run = plan_run(silo4, WAYPOINTS, HEIGHT_M, RunRequest(), samples_per_unit=10)
    assert run.plan.trajectory.tau is None
    assert "motor_sizing" not in run.metrics and "joint_limits" in run.metrics


def test_the_crawl_keeps_the_effort_budget_it_broke_before(silo4) -> None:
    """(-0.3, 0.2) at h = 0.4 m: the crawl "auto" prefers needed 52.2 N m of RH_knee standing
    still, above the 0.85 x 60 N m budget, at every unit time, and the pipeline planned the
    omnidirectional creeping gait instead. Its moving transfers now end where the stance
    legs keep the budget (planner/gaits/sway.py capped_sway_end); in motion the floating
    robot's torques add 2.85 N m to RH_knee there (51.48 N m), and the run plans the crawl
    again leaving its stances that room (plan_run, tests/test_motion_replan.py): 12.7 units.
    Asked for by name the crawl plans and passes the run's checks; "auto" takes the faster
    gait that keeps them, the creeping gait's 12.2 units, without a fallback (the fallback
    itself: test_the_other_gait_follows_gait_autos_families)."""
    from planner.trajectory.limits import check_static_effort

    waypoints = np.array([[-0.3, 0.2]])
    runs = {
        gait: plan_run(silo4, waypoints, HEIGHT_M, RunRequest(), samples_per_unit=10, gait=gait)
        for gait in ("crawl", "auto")
    }
    assert runs["crawl"].plan.gait == "crawl"
    assert runs["auto"].plan.trajectory.t[-1] <= runs["crawl"].plan.trajectory.t[-1]
    for run in runs.values():
        assert run.plan.fallback_reason is None and run.limits.violation is None
        check_static_effort(silo4, run.plan.trajectory, load="total", headroom=0.85)
        errors = np.hypot(*(run.plan.position_walked_in_world - run.plan.waypoints_in_world).T)
        assert errors.mean() <= run.plan.tolerance


@pytest.mark.parametrize("robot_name, replanned", [(None, ["crawl"]), ("go2", [])])
def test_the_other_gait_follows_gait_autos_families(silo4, monkeypatch, robot_name, replanned):
    """Where the pipeline refuses gait auto's creeping plan, it plans the crawl only on the
    legs gait auto crawls on (planner/presets.py CRAWL_BY_DEFAULT_FAMILIES: insect legs);
    a mammal's refusal stands."""
    import planner.outputs.pipeline as pipeline
    from planner.errors import PlanningError
    from silo4kin.robot import load_robot

    robot = silo4 if robot_name is None else load_robot(robot_name)
    asked: list[str] = []
    real_plan_path = pipeline.plan_path

    def plan_path(*args, **kwargs):
        asked.append(kwargs.get("gait", "auto"))
        return real_plan_path(*args, **{**kwargs, "gait": "creep"})

    def finish_plan(robot, plan, request):
        raise PlanningError("refused for the test")

    monkeypatch.setattr(pipeline, "plan_path", plan_path)
    monkeypatch.setattr(pipeline, "finish_plan", finish_plan)
    height = HEIGHT_M if robot_name is None else 0.3
    with pytest.raises(PlanningError, match="refused for the test"):
        plan_run(robot, WAYPOINTS, height, RunRequest(), samples_per_unit=10)
    assert asked == ["auto", *replanned]
