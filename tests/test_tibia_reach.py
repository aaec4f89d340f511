"""The tibia rule inside the default gaits' foothold search (planner/gaits/tibia_reach.py):
its decision against Pinocchio's frame placements, and a path whose gaits without turning
were dropped by the rule on the samples (then facing the path, E_n 24 mm > 10 mm)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner import plan_path
from planner.gaits.tibia_reach import TIBIA_SEARCH_MARGIN_M, tibias_clear
from planner.trajectory.clearance import MIN_TIBIA_CLEARANCE_M, TIBIA_FOOT_GAP_M
from planner.trajectory.verify import verify_samples
from planner.workspace.layout import workspace_for
from silo4kin.legs import inverse_kinematics


def _pinocchio_clearance(robot, leg_index: int, q_leg: np.ndarray, height_m: float) -> float:
    """Lowest point of the tibia capsule above flat ground, body level at height_m [m]: the
    knee joint's placement to TIBIA_FOOT_GAP_M short of the foot frame, minus the radius."""
    model = robot.model_free_flyer
    data = model.createData()
    q = np.zeros(12)
    q[3 * leg_index : 3 * leg_index + 3] = q_leg
    pin.forwardKinematics(
        model, data, np.r_[0.0, 0.0, height_m, 0, 0, 0, 1, robot.to_pinocchio_q(q)]
    )
    leg = robot.legs[leg_index]
    frame = model.frames[model.getFrameId(leg.foot_frame)]
    knee = data.oMi[frame.parentJoint]
    foot = frame.placement.translation
    end = knee.act(foot * (1 - TIBIA_FOOT_GAP_M / np.linalg.norm(foot)))
    return float(min(knee.translation[2], end[2]) - leg.tibia_radius_m)


@pytest.mark.parametrize("height", [0.2, 0.25, 0.35])
def test_decision_matches_pinocchio(silo4, height):
    """Random foot targets on the ground around position 2 (up to 0.25 m off): a target is
    refused exactly when Pinocchio puts its held leg's capsule under the rule plus the search
    margin; some targets of each kind are drawn."""
    ws = workspace_for(silo4, height, "default")
    rng = np.random.default_rng(int(height * 100))
    legs = rng.integers(0, 4, 120)
    targets = ws.position_mid_in_base[legs].copy()
    targets[:, :2] += rng.uniform(-0.25, 0.25, (120, 2))
    got = tibias_clear(silo4.legs, ws, legs, targets)
    held = [
        _pinocchio_clearance(
            silo4, k, inverse_kinematics(silo4.legs[k], ws.position_mid_in_base[k]).q, height
        )
        >= MIN_TIBIA_CLEARANCE_M
        for k in range(4)
    ]
    expected = np.ones(120, dtype=bool)
    for i, (k, p) in enumerate(zip(legs, targets)):
        res = inverse_kinematics(silo4.legs[k], p)
        if held[k] and bool(np.all(res.reachable)):
            low = _pinocchio_clearance(silo4, int(k), np.asarray(res.q).reshape(3), height)
            expected[i] = low >= MIN_TIBIA_CLEARANCE_M + TIBIA_SEARCH_MARGIN_M
    np.testing.assert_array_equal(got, expected)
    assert got.any() and not got.all()


def test_zig_zag_walks_without_turning_within_its_tolerance(silo4):
    """At h = 0.25 m both gaits without turning were refused by a tibia 1.0-1.2 mm above the
    ground on the samples and the plan faced the path (E_n 24 mm > 10 mm); the searches
    now pick other steps there."""
    plan = plan_path(silo4, np.array([[1, 0], [0, 0.6], [1, 1.2], [0, 1.8]]), 0.25)
    assert plan.gait in ("crawl", "creep")
    assert "tibia" not in (plan.fallback_reason or "")
    errors = np.hypot(*(plan.position_walked_in_world - plan.waypoints_in_world).T)
    assert errors.mean() <= plan.tolerance
    verify_samples(
        silo4.legs,
        plan.trajectory,
        plan.steps,
        plan.stability_threshold,
        plan.waypoints_in_world,
        hold_tibias=True,
    )
