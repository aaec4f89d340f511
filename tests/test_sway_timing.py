"""The crawl's four-foot body moves last long enough for the joints to carry their
acceleration (planner/gaits/sway_timing.py), and the 36-waypoint circle walks in physics.

The physics test plans and replays three plans (10-25 s each on a shared machine): it runs
with SILO4_HEAVY=1.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

from planner.gaits.sway_timing import (
    DURATION_STEP_UNITS,
    QUINTIC_PEAK_PHASES,
    sway_timing_for,
)
from planner.model import planning_model
from planner.path.plan_path import plan_path
from planner.studies.cases import circle_waypoints
from silo4kin.joint_torques import joint_torques

#: Agreement of the rule's torques at rest with silo4kin.joint_torques [N m]: both are the
#: same sums of float64 terms in another order.
STATIC_TORQUE_ATOL_NM = 1e-9
HEADROOM = 0.85


@pytest.fixture(scope="module")
def stance(silo4):  # noqa: ANN001, ANN201
    """The first sample of the straight path at h 0.4 m: base (3,), yaw, feet (4, 3) [m]."""
    traj = plan_path(silo4, np.array([[0.0, 1.0], [0.0, 2.0]]), 0.4).trajectory
    return (
        traj.position_base_in_world[0],
        float(traj.yaw_base_in_world[0]),
        traj.position_foot_in_world[0],
    )


def test_torques_at_rest_are_the_quasi_static_ones(silo4, stance):
    """A move slow enough to have no acceleration asks the torques of eq A.14 + A.34 with
    the whole robot on four feet, as silo4kin.joint_torques computes them."""
    base, yaw, feet = stance
    model = planning_model(silo4)
    timing = sway_timing_for(model, HEADROOM, 1.0)
    end = base + np.array([0.03, 0.02, 0.0])
    q, com = timing._poses(base, end, yaw, feet)
    ratio = timing.torque_ratio(q, com, feet, yaw, 1e9)
    s = np.array([QUINTIC_PEAK_PHASES[0], QUINTIC_PEAK_PHASES[1]])
    s = s**3 * (10 - 15 * s + 6 * s * s)
    bases = base + s[:, None] * (end - base)
    c, si = np.cos(yaw), np.sin(yaw)
    rot = np.array([[c, -si, 0.0], [si, c, 0.0], [0.0, 0.0, 1.0]])
    feet_in_base = (feet[None] - bases[:, None]) @ rot + silo4.position_body_com_in_base
    jt = joint_torques(
        model.robot,
        q[1:3],
        np.zeros((2, 12)),
        np.zeros((2, 12)),
        np.ones((2, 4), bool),
        position_foot_in_base=feet_in_base,
        load="total",
    )
    expected = float(np.max(np.abs(jt.total) / timing.budget_nm))
    assert ratio == pytest.approx(expected, abs=STATIC_TORQUE_ATOL_NM / 60.0)


def test_a_fast_move_is_stretched_to_the_shortest_duration_within_the_budget(silo4, stance):
    """A 0.12 m sway in 0.5 units of 0.25 s asks more than the budget; the rule gives the
    shortest multiple of DURATION_STEP_UNITS that keeps it, and a slow one keeps 0.5."""
    base, yaw, feet = stance
    model = planning_model(silo4)
    end = base + np.array([0.12, 0.0, 0.0])
    fast = sway_timing_for(model, HEADROOM, 0.25)
    units = fast.units(base, end, yaw, feet, 0.5)
    assert units > 0.5
    q, com = fast._poses(base, end, yaw, feet)
    assert fast.torque_ratio(q, com, feet, yaw, units * 0.25) <= 1.0
    shorter = units - DURATION_STEP_UNITS
    assert fast.torque_ratio(q, com, feet, yaw, shorter * 0.25) > 1.0
    assert sway_timing_for(model, HEADROOM, 1.0).units(base, end, yaw, feet, 0.5) == 0.5


#: A torque headroom no sway's torques reach (x URDF effort): the ZMP rule alone decides.
NO_TORQUE_LIMIT = 100.0
#: The lift threshold of the default preset [m] (planner/workspace/layout.py).
THRESHOLD_M = 0.02


def _sway_towards_front_right(stance, distance_m):  # noqa: ANN001, ANN202
    """The stance and a move of ``distance_m`` [m] at 30 deg in W, towards the edge between
    the front feet."""
    base, yaw, feet = stance
    angle = np.radians(30.0)
    return base, base + distance_m * np.array([np.cos(angle), np.sin(angle), 0.0]), yaw, feet


def test_a_sway_whose_zmp_nears_an_edge_is_stretched(silo4, stance):
    """A 0.18 m sway in 0.5 unit at 1 s a unit keeps the joints' torques (any budget) but
    its ZMP comes within 10 mm of the front feet's edge at the decelerating peak; with the
    lift threshold asked of the ZMP it lasts the shortest multiple of DURATION_STEP_UNITS
    that keeps 20 mm (1 unit: 80 mm), and the rule switched off (margin 0: the thesis
    preset, and the torque-only rule before it) keeps 0.5."""
    base, end, yaw, feet = _sway_towards_front_right(stance, 0.18)
    model = planning_model(silo4)
    old = sway_timing_for(model, NO_TORQUE_LIMIT, 1.0)
    assert old.units(base, end, yaw, feet, 0.5) == 0.5
    new = sway_timing_for(model, NO_TORQUE_LIMIT, 1.0, THRESHOLD_M)
    q, com = new._poses(base, end, yaw, feet)
    assert 0.0 < new.zmp_margin(com, feet, 0.5) < THRESHOLD_M
    units = new.units(base, end, yaw, feet, 0.5)
    assert units > 0.5
    assert new.zmp_margin(com, feet, units) >= THRESHOLD_M
    assert new.zmp_margin(com, feet, units - DURATION_STEP_UNITS) < THRESHOLD_M


def test_a_sway_whose_zmp_keeps_the_threshold_is_not_stretched(silo4, stance):
    """The same direction over 0.16 m keeps its ZMP 34 mm inside at 0.5 unit: no change."""
    base, end, yaw, feet = _sway_towards_front_right(stance, 0.16)
    model = planning_model(silo4)
    new = sway_timing_for(model, NO_TORQUE_LIMIT, 1.0, THRESHOLD_M)
    q, com = new._poses(base, end, yaw, feet)
    assert new.zmp_margin(com, feet, 0.5) >= THRESHOLD_M
    assert new.units(base, end, yaw, feet, 0.5) == 0.5


@pytest.mark.skipif(
    not os.environ.get("SILO4_HEAVY"),
    reason="heavy (three plans replayed in MuJoCo, 30-75 s): SILO4_HEAVY=1",
)
@pytest.mark.parametrize("height", [0.2, 0.4, 0.6])
def test_the_36_waypoint_circle_walks(silo4, height):
    """The thesis circle sampled every 10 degrees, planned with the defaults as ``silo4 plan``
    plans it, walks in MuJoCo at h 0.2, 0.4 and 0.6 m and meets its tolerance."""
    pytest.importorskip("mujoco")
    from planner.outputs.pipeline import RunRequest, plan_run
    from planner.trajectory.torques import add_torques
    from silo4sim.run import simulate

    run = plan_run(silo4, circle_waypoints(count=36), height, RunRequest())
    plan = run.plan
    assert run.metrics["normalized_error_m"] <= plan.tolerance
    doc = simulate(silo4, add_torques(silo4, plan.trajectory, load="total")).metrics
    assert doc["walks"], doc["reasons"]
    assert sum(doc["effort_limit_s"].values()) == 0.0
