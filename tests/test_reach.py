"""Reachable-set workspace (issue 9): the ground set from FK, footholds inside it, one height
range for every robot, and the phasmid test robot planning across its whole range."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from test_cli_plan import assert_one_line_error, run_cli
from test_planner_invariants import check_invariants

from planner import PlannerInputError, PlanningError, plan_path
from planner.gaits.creep_spin import DIRECTIONS, creep_pairs
from planner.stability.margin import support_margin
from planner.workspace.footholds import creep_pairs_from_hips, lift_margin, segment_half_lengths
from planner.workspace.layout import (
    DEFAULT_KNEE_MARGIN,
    feasible_height_range,
    planning_robot,
    reachable_in_limits,
    workspace_for,
)
from planner.workspace.reach_insect import radial_interval, reachable_set
from silo4kin import load_robot
from silo4kin.kinematics import inverse_kinematics_masked
from viz.cli.main import EXIT_BAD_INPUT, EXIT_OK

ROBOTS_DIR = Path(__file__).resolve().parent / "robots"
#: The FK grid (161 x 161 over the limits) interpolated linearly: the interval ends err by
#: ~(L2 + L3) Δθ² / 8 ~ 3e-5 m on SILO4; 2e-4 m still fails on a wrong formula (cm).
INTERVAL_TOL_M = 2e-4
#: Points this far inside / outside the set are classified by IK without doubt [m] (5x the
#: interval error above).
CLASSIFY_MARGIN_M = 1e-3


@pytest.fixture(scope="module")
def robots(silo4):
    return {
        "silo4": silo4,
        "mantis": load_robot(ROBOTS_DIR / "mantis.urdf"),
        "phasmid": load_robot(ROBOTS_DIR / "phasmid.urdf.xacro"),
    }


@pytest.mark.parametrize("height", [0.25, 0.4, 0.55])
def test_outer_radius_matches_the_closed_form_reach(silo4, height):
    """SILO4 at mid heights: r_max = L1 + sqrt(r_m² - hh²), r_m = |L2 + L3 e^{-iθm}| the
    hip-pitch-to-foot distance at the knee margin θm (the old default reference pose)."""
    leg = silo4.legs[0]
    hh = height + leg.hip_height
    r_m = np.hypot(
        leg.L2 + leg.L3 * np.cos(DEFAULT_KNEE_MARGIN), leg.L3 * np.sin(DEFAULT_KNEE_MARGIN)
    )
    r_lo, r_hi = radial_interval(leg, -height, DEFAULT_KNEE_MARGIN)
    assert r_hi == pytest.approx(leg.L1 + np.sqrt(r_m**2 - hh**2), abs=INTERVAL_TOL_M)
    assert 0 < r_lo < 0.05  # the knee folds the foot back under the hip


@pytest.mark.parametrize("name", ["silo4", "mantis", "phasmid"])
def test_reachable_set_agrees_with_the_closed_form_ik(robots, name):
    """A ground point well inside a leg's set (computed from FK only) is reached by the
    closed-form IK within every joint limit with the knee >= the margin from θ3 = 0; a
    point well outside is not (out of reach, off limits or inside the knee margin)."""
    robot = planning_robot(robots[name])
    rng = np.random.default_rng(9)
    for height in np.linspace(*feasible_height_range(robot), 4):
        for leg in robot.legs:
            s = reachable_set(leg, (-height,), DEFAULT_KNEE_MARGIN)
            # (not within 1 cm of the hip axis, where the foot's direction is undefined)
            r = rng.uniform(0.01, leg.L1 + leg.L2 + leg.L3, 3000)
            phi = rng.uniform(-np.pi, np.pi, 3000)
            pts = np.column_stack(
                [
                    leg.position_hip_in_base[0] + r * np.cos(phi),
                    leg.position_hip_in_base[1] + r * np.sin(phi),
                    np.full(3000, -height),
                ]
            )
            res = inverse_kinematics_masked(leg, pts)
            theta3 = leg.joint_to_dh(np.where(np.isfinite(res.q), res.q, 0.0))[:, 2]
            ik_ok = reachable_in_limits(leg, pts) & (theta3 <= -DEFAULT_KNEE_MARGIN)
            inside = s.contains(pts, CLASSIFY_MARGIN_M)
            outside = ~s.contains(pts, -CLASSIFY_MARGIN_M)  # the set grown by the margin
            assert inside.sum() > 100 and outside.sum() > 100
            assert np.all(ik_ok[inside]), (name, height, leg.name)
            assert not np.any(ik_ok[outside]), (name, height, leg.name)


def test_segment_half_lengths_match_sampling(silo4):
    """The closed-form half-lengths equal a bisection on points sampled along the segment."""
    leg = silo4.legs[1]
    s = reachable_set(leg, (-0.4, -0.3), DEFAULT_KNEE_MARGIN)
    rng = np.random.default_rng(3)
    centres = leg.position_hip_in_base[:2] + rng.uniform(-0.5, 0.5, (200, 2))
    for angle in (0.0, 0.3, np.pi / 2):
        d = np.array([np.cos(angle), np.sin(angle)])
        a = segment_half_lengths(s, centres, d, 0.05)
        t = np.linspace(-1, 1, 2001)
        for c, ak in zip(centres, a):
            if ak == 0:
                assert not s.contains(c[None], 0.05)[0]
                continue
            assert s.contains(c + (0.999 * ak) * t[:, None] * d, 0.05).all()
            assert not s.contains(c + (1.01 * ak) * t[:, None] * d, 0.05).all()


def test_lift_margin_equals_support_margin():
    """The triangle fast path gives stability.support_margin's S_m."""
    rng = np.random.default_rng(1)
    feet, cog = rng.normal(size=(500, 3, 2)), rng.normal(size=(500, 2))
    feet4 = np.zeros((500, 4, 2))
    feet4[:, :3] = feet
    contact = np.zeros((500, 4), bool)
    contact[:, :3] = True
    np.testing.assert_allclose(
        lift_margin(feet, cog), support_margin(feet4, contact, cog), atol=1e-12
    )


@pytest.mark.parametrize("name", ["silo4", "mantis", "phasmid"])
def test_creep_pairs_match_the_gait(robots, name):
    ws = workspace_for(robots[name], 0.3)
    for direction, d in DIRECTIONS.items():
        assert creep_pairs_from_hips(ws.position_hip_in_base, d) == creep_pairs(ws, direction)


@pytest.mark.parametrize("name", ["silo4", "mantis", "phasmid"])
@pytest.mark.parametrize("preset", ["default", "thesis"])
def test_one_height_range_everywhere(robots, capsys, tmp_path, name, preset):
    """feasible_height_range (URDF-root robot or planning-frame robot), plan_path and the
    CLI refusal agree: both ends plan, 1 mm beyond either end is refused naming the range."""
    robot = robots[name]
    lo, hi = feasible_height_range(robot, preset)
    assert (lo, hi) == feasible_height_range(planning_robot(robot), preset)
    for h in (lo, hi):
        try:
            plan_path(robot, [(0.0, 0.3)], h, workspace=preset, samples_per_unit=4)
        except PlanningError:
            # the height is accepted; the thesis preset has no reserves and may still refuse
            # a path on a robot with an off-centre CoG (docs/robots.md)
            assert preset == "thesis" and name != "silo4"
    for h in (lo - 1e-3, hi + 1e-3):
        with pytest.raises(PlannerInputError, match=rf"\[{lo:.4g}, {hi:.4g}\]"):
            plan_path(robot, [(0.0, 0.3)], h, workspace=preset, samples_per_unit=4)
    robot_args = [] if name == "silo4" else ["--robot", str(robots[name].source)]
    code, _, err = run_cli(
        capsys,
        "plan",
        "--waypoints",
        "0,0.3",
        "--height",
        f"{hi + 1e-3}",
        "--workspace",
        preset,
        "--out",
        str(tmp_path / "run"),
        "--samples-per-unit",
        "4",
        *robot_args,
    )
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, f"[{lo:.4g}, {hi:.4g}]")
    assert not (tmp_path / "run").exists()


def test_phasmid_plans_across_its_whole_range(robots):
    """The limited robot (sideways legs, ±57° hip yaw, 150° knee): the thesis-square
    workspace gave [0.3311, 0.5075] m and refused h = 0.2 m; the reachable set plans from
    0.1525 m (hips 5.25 cm up) to where the spin runs out (its any-direction range; above
    it, up to its range's top, it walks along its body: tests/test_cannot_turn.py), with a
    stride >= 0.2 m over most of it, every invariant holding on a path with turns. Below
    0.18 m the stride is shorter (0.1 m at 0.1525 m, where the range now starts): the layout
    lifts the feet by the plans' 5 cm swing, not eq 5.12's 2.6-4 cm
    (planner/workspace/foothold_layout.py swing_height_m)."""
    robot = robots["phasmid"]
    lo, hi = feasible_height_range(robot, any_direction=True)
    assert lo <= 0.2 and hi - lo > 0.3
    full = feasible_height_range(robot)  # the spin asked of no height: one more run above
    assert full[0] == lo and full[1] > hi + 0.01
    for h in np.linspace(lo, hi, 6):
        ws = workspace_for(robot, h)
        if 0.18 <= h < hi - 0.05:
            assert ws.stride_m >= 0.2
        elif h < hi - 0.05:
            assert ws.stride_m >= 0.1 - 1e-3
        plan = plan_path(robot, [(0.6, 0.2), (0.0, 0.8)], h, samples_per_unit=10)
        check_invariants(planning_robot(robot), plan)


def test_silo4_workspace_cli_draws_and_names_the_range(capsys, tmp_path):
    out = tmp_path / "ws.png"
    code, text, _ = run_cli(capsys, "workspace", "--height", "0.4", "--out", str(out))
    assert code == EXIT_OK and out.stat().st_size > 10_000
    lo, hi = feasible_height_range(load_robot())
    assert f"[{lo:.4g}, {hi:.4g}]" in text
    code, _, err = run_cli(capsys, "workspace", "--height", "0.4", "--out", str(tmp_path / "x.txt"))
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, ".png")
