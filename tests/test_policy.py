"""Presets (planner/presets.py) and what they change in a plan: swing height, stability
point, load, gait; step phases as enums; E_n from the CoG as walked."""

from __future__ import annotations

import numpy as np
import pytest

from planner.errors import PlannerInputError
from planner.gaits.steps import Phase, StepKind
from planner.path.metrics import compute_metrics
from planner.path.plan_path import plan_path
from planner.presets import MIN_SWING_HEIGHT_M, PRESETS, Load, Preset, StabilityPoint, preset_for

STRAIGHT = np.array([[0.0, 1.0], [1.0, 1.0], [0.0, 2.0], [0.0, 3.0]])


def test_presets_are_one_registry():
    """PRESETS is the one list of presets: the workspace layouts, the cases and the CLI
    choices are its names; a Preset object is accepted where a name is."""
    from planner.studies.cases import PRESETS as CASE_PRESETS
    from planner.workspace.layout import PRESETS as LAYOUTS

    assert preset_for("default").stability_point is StabilityPoint.WHOLE_BODY_COM
    assert preset_for("default").load is Load.TOTAL
    assert preset_for("thesis").stability_point is StabilityPoint.BODY_COG
    assert preset_for("thesis").load is Load.BODY
    assert set(PRESETS) == {"default", "thesis"} == set(LAYOUTS) == set(CASE_PRESETS)
    assert preset_for(PRESETS["thesis"]) is PRESETS["thesis"]
    assert isinstance(PRESETS["default"], Preset)
    with pytest.raises(PlannerInputError, match="default"):
        preset_for("fast")


def _max_swing_clearance(plan) -> float:
    """Highest foot above the ground while swinging [m]."""
    tr = plan.trajectory
    z = tr.position_foot_in_world[..., 2]
    return float(np.where(~tr.contact, z, 0.0).max())


def test_default_swing_clears_at_least_5_cm_the_thesis_keeps_eq_5_12(silo4):
    """h = 0.2 m: eq 5.12 lifts by half the hip height, 2.5 cm (thesis preset); the default
    lifts by MIN_SWING_HEIGHT_M; --swing-height sets it."""
    default = plan_path(silo4, STRAIGHT[:1], 0.2, samples_per_unit=20)
    thesis = plan_path(silo4, STRAIGHT[:1], 0.2, workspace="thesis", samples_per_unit=20)
    chosen = plan_path(silo4, STRAIGHT[:1], 0.2, samples_per_unit=20, swing_height_m=0.08)
    hip_clearance = 0.2 - 0.15
    assert _max_swing_clearance(thesis) == pytest.approx(hip_clearance / 2, abs=1e-9)
    assert _max_swing_clearance(default) == pytest.approx(MIN_SWING_HEIGHT_M, abs=1e-9)
    assert _max_swing_clearance(chosen) == pytest.approx(0.08, abs=1e-9)
    high = plan_path(silo4, STRAIGHT[:1], 0.5, samples_per_unit=20)
    assert _max_swing_clearance(high) == pytest.approx((0.5 - 0.15) / 2, abs=1e-9)
    with pytest.raises(PlannerInputError, match="swing_height_m"):
        plan_path(silo4, STRAIGHT[:1], 0.2, swing_height_m=-0.1)


def test_steps_carry_kind_and_phase_enums(silo4):
    plan = plan_path(silo4, STRAIGHT, 0.4, workspace="thesis", samples_per_unit=2)
    kinds = {s.kind for s in plan.steps}
    phases = {s.phase for s in plan.steps}
    assert kinds == set(StepKind)
    assert phases == {Phase.CREEP, Phase.SPIN, Phase.TRANSITION}
    m = compute_metrics(plan)
    n_body = sum(1 for s in plan.steps if s.phase == Phase.CREEP and s.kind == StepKind.BODY)
    assert m["distance_m"] == pytest.approx(n_body * plan.workspace.stride_m / 2)
    assert sum(m["time_units_by_phase"].values()) == pytest.approx(m["normalized_time"])
    assert plan.steps[0].to_dict()["phase"] in {p.value for p in Phase}


def test_normalized_error_is_measured_on_the_cog_as_walked(silo4):
    """E_n (eq 6.1) uses the sampled CoG (shifts included) where it comes nearest each
    waypoint from the end of that waypoint's last step to the end of the next one's (facing
    the path, planner/gaits/facing.py: the shifts folded into a segment's last step leave
    the body off the waypoint at the arrival), found here from the step list and the
    trajectory independently."""
    from planner.studies.cases import path_waypoints

    wp, _ = path_waypoints("circle")
    plan = plan_path(silo4, wp, 0.6, samples_per_unit=10, face_path=True)
    tr = plan.trajectory
    t_done = np.zeros(len(wp))
    for s in plan.steps:
        t_done[s.waypoint_index] = max(t_done[s.waypoint_index], s.t_end)
    t_done = np.maximum.accumulate(t_done)
    ends = np.append(t_done[1:], t_done[-1])
    errors = []
    for k in range(len(wp)):
        window = (tr.time_units >= t_done[k] - 1e-9) & (tr.time_units <= ends[k] + 1e-9)
        errors.append(np.min(np.hypot(*(tr.position_base_in_world[window, :2] - wp[k]).T)))
    expected = float(np.mean(errors))
    m = compute_metrics(plan)
    assert m["normalized_error_m"] == pytest.approx(expected, abs=1e-12)
    assert plan.n_shifts + plan.n_folded_shifts > 0  # the walked CoG differs here


def test_the_gait_that_ran_is_recorded(silo4):
    m = compute_metrics(plan_path(silo4, STRAIGHT, 0.4, samples_per_unit=2))
    assert m["gait"] == "crawl" and m["fallback_reason"] is None
    assert m["n_crawl_swings"] > 0 and 0.75 < m["duty_factor"] < 0.875
    m = compute_metrics(plan_path(silo4, STRAIGHT, 0.4, samples_per_unit=2, gait="creep"))
    assert m["gait"] == "creep" and m["fallback_reason"] is None
    assert m["n_crawl_swings"] == 0
    m = compute_metrics(plan_path(silo4, STRAIGHT, 0.4, samples_per_unit=2, face_path=True))
    assert m["gait"] == "facing" and m["fallback_reason"] is None
    m = compute_metrics(plan_path(silo4, STRAIGHT, 0.4, samples_per_unit=2, gait="plain"))
    assert m["gait"] == "plain" and m["fallback_reason"] is None
    m = compute_metrics(plan_path(silo4, STRAIGHT, 0.4, workspace="thesis", samples_per_unit=2))
    assert m["gait"] == "thesis" and m["fallback_reason"] is None


def test_a_fallback_to_the_plain_gait_is_recorded(silo4, monkeypatch):
    """When the fast gait's plan fails verification the plain gait runs and the plan (and
    metrics.json) say so with the reason; nothing falls back silently."""
    from planner.errors import PlanningError
    from planner.gaits.facing import FacingPath
    from planner.gaits.without_turning import ContinuousCrawl, OmniCreep

    def failing(self, request, slower_than=None):
        raise PlanningError("joint LF_knee leaves its limits (test)", 0, (0.0, 1.0))

    for gait in (FacingPath, ContinuousCrawl, OmniCreep):
        monkeypatch.setattr(gait, "plan", failing)
    plan = plan_path(silo4, STRAIGHT, 0.4, samples_per_unit=2)
    m = compute_metrics(plan)
    assert m["gait"] == "plain" and "LF_knee" in m["fallback_reason"]
    assert m["fallback_reason"].startswith("continuous crawl")
    assert "; omnidirectional gait: " in m["fallback_reason"]


def test_cli_thesis_preset_warns_in_one_line_and_records_it(tmp_path, capsys):
    """silo4 plan --workspace thesis: one warning line naming the worst sample and margin;
    metrics.json records it; the default load of the thesis preset is the body, of the
    default preset the whole robot; --swing-height reaches the plan."""
    import json

    from viz.cli.main import main

    code = main(
        [
            "plan",
            "--waypoints",
            "0,1 1,1 0,2 0,3",
            "--height",
            "0.6",
            "--workspace",
            "thesis",
            "--samples-per-unit",
            "10",
            "--out",
            str(tmp_path / "t"),
            "--no-html",
            "--no-plots",
        ]
    )
    err = capsys.readouterr().err
    assert code == 0
    lines = [ln for ln in err.splitlines() if ln.startswith("warning:")]
    assert len(lines) == 1 and "sample" in lines[0] and "mm" in lines[0]
    metrics = json.loads((tmp_path / "t" / "metrics.json").read_text())
    assert metrics["warnings"] == lines and metrics["com_outside_support"]["margin_com_m"] < 0
    assert metrics["torque_load"] == "body"
    code = main(
        [
            "plan",
            "--waypoints",
            "0,1",
            "--height",
            "0.2",
            "--samples-per-unit",
            "10",
            "--swing-height",
            "0.07",
            "--out",
            str(tmp_path / "d"),
            "--no-html",
            "--no-plots",
        ]
    )
    assert code == 0 and "warning" not in capsys.readouterr().err
    metrics = json.loads((tmp_path / "d" / "metrics.json").read_text())
    assert metrics["torque_load"] == "total" and metrics["swing_height_m"] == 0.07


def test_thesis_plan_with_the_full_load_names_the_com_not_a_zero_margin(silo4):
    """Issue 9: the thesis preset with load "total" was refused with "margin -0.0000 m" (the
    body CoG's); the error now names the whole-robot CoM and how far outside it is."""
    from planner.trajectory.torques import add_torques
    from silo4kin.errors import Silo4Error

    wp = np.array([[0.0, 1.0], [1.0, 1.0]])
    plan = plan_path(silo4, wp, 0.6, workspace="thesis", samples_per_unit=10)
    with pytest.raises(
        Silo4Error,
        match=r"whole-robot CoM outside the support polygon by "
        r"(0\.[1-9]|[1-9]\.\d) mm",
    ):
        add_torques(silo4, plan.trajectory, load="total")
    add_torques(silo4, plan.trajectory, load="body")
