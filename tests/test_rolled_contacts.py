"""Ball feet checked where they roll to: the step builder's lifts stand on the contact points
the samples have (planner/gaits/rolled_contacts.py), with no allowance above the threshold.

The independent reference is Pinocchio: the contact points from its forward kinematics of the
planned joints (ball centre minus r ẑ), and the whole-body CoM from its centerOfMass.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner import plan_path
from planner.gaits.rolled_contacts import RolledContacts
from planner.model import planning_robot
from planner.trajectory.samples import LEGS
from planner.trajectory.verify import SAMPLE_MARGIN_SLACK_M
from silo4kin.foot_contact import foot_ball
from silo4kin.robot import load_robot

#: Waypoints [m] of a go2 path with a turn (creep, shifts and folds), at h = 0.28 m.
GO2_PATH = np.array([[0.3, 0.0], [0.3, 0.3]])
GO2_HEIGHT_M = 0.28
#: The builder's prediction and the sampler agree to this [m]: both integrate the same
#: rolling (roll_feet) along the same base path, by different trapezoids (16 samples per
#: segment against the plan's samples per unit); a go2 stance rolls ~10 mm.
PREDICTION_AGREES_M = 5e-6


@pytest.fixture(scope="module")
def go2_plan(go2):
    return plan_path(go2, GO2_PATH, GO2_HEIGHT_M, start_heading=0.0)


def _cross(u: np.ndarray, v: np.ndarray) -> float:
    """z of the cross product of two (2,) vectors."""
    return float(u[0] * v[1] - u[1] * v[0])


def _signed_distance_to_triangle(tri: np.ndarray, p: np.ndarray) -> float:
    """Smallest signed distance [m] of ``p`` (2,) to the edge lines of ``tri`` (3, 2),
    positive inside (written here, not the planner's kernel)."""
    area = _cross(tri[1] - tri[0], tri[2] - tri[0])
    sign = 1.0 if area > 0 else -1.0
    out = []
    for i in range(3):
        a, b = tri[i], tri[(i + 1) % 3]
        out.append(sign * _cross(b - a, p - a) / np.linalg.norm(b - a))
    return float(min(out))


def _whole_body_com_in_base(robot, model, data, q_pin: np.ndarray) -> np.ndarray:
    """Whole-robot CoM in B [m] (3,): Pinocchio's legs (the fixed-base model carries no base
    mass) and the base link's inertia from the free-flyer model, weighted by mass."""
    body = robot.model_free_flyer.inertias[1]
    legs_com = pin.centerOfMass(model, data, q_pin)
    legs_mass = pin.computeTotalMass(model)
    com_in_root = (legs_mass * legs_com + body.mass * np.asarray(body.lever)) / (
        legs_mass + body.mass
    )
    return com_in_root - robot.position_body_com_in_base


def test_lifts_keep_the_threshold_on_pinocchio_contact_points(go2, go2_plan):
    """On every sample with a foot lifted, the whole-body CoM (Pinocchio) is at least the
    threshold inside the triangle of the three stance contact points (Pinocchio FK of the
    ball centres, minus r ẑ), less only the verification's sampling slack."""
    plan, tr = go2_plan, go2_plan.trajectory
    assert foot_ball(go2).rolls
    model, data = go2.model, go2.model.createData()
    q_pin = go2.to_pinocchio_q(tr.q)
    root = go2.position_body_com_in_base  # planning frame B = body CoG
    fids = [model.getFrameId(leg.foot_frame) for leg in go2.legs]
    lifted = np.flatnonzero(~np.all(tr.contact, axis=1))
    assert len(lifted) > 100
    worst = np.inf
    for i in lifted:
        c, s = np.cos(tr.yaw_base_in_world[i]), np.sin(tr.yaw_base_in_world[i])
        rot = np.array([[c, -s], [s, c]])
        pin.forwardKinematics(model, data, q_pin[i])
        pin.updateFramePlacements(model, data)
        com_b = _whole_body_com_in_base(go2, model, data, q_pin[i])
        com = tr.position_base_in_world[i, :2] + rot @ com_b[:2]
        stance = [j for j in range(4) if tr.contact[i, j]]
        tri = np.array(
            [
                tr.position_base_in_world[i, :2] + rot @ (data.oMf[fids[j]].translation - root)[:2]
                for j in stance
            ]
        )
        worst = min(worst, _signed_distance_to_triangle(tri, com))
    assert worst >= plan.stability_threshold - SAMPLE_MARGIN_SLACK_M
    # the plan is tight: it would not keep the threshold on the footholds' triangle alone
    assert worst < plan.stability_threshold + 2e-3


def test_the_builder_predicts_the_sampled_contact_points(go2, go2_plan):
    """At the start of every transfer the predictor's contact points of the stance feet
    (from the steps before it) are the sampled contact points, to PREDICTION_AGREES_M, and
    they differ from the footholds (the balls rolled)."""
    plan, tr = go2_plan, go2_plan.trajectory
    predictor = RolledContacts(planning_robot(go2).legs, foot_ball(go2))  # legs in B
    spu = round(1.0 / (tr.time_units[1] - tr.time_units[0]))
    rolled_most = 0.0
    steps = list(plan.steps)
    for i, step in enumerate(steps):
        if step.leg is None or step.position_feet_in_world is None:
            continue
        predicted = predictor.contact_points(
            steps[:i], step.position_feet_in_world, step.position_base_start_in_world,
            step.yaw_base_start,
        )  # fmt: skip
        row = int(round(step.t_start * spu))
        leg = LEGS.index(step.leg)
        for j in range(4):
            if j == leg:
                continue
            sampled = tr.position_foot_in_world[row, j, :2]
            assert np.max(np.abs(predicted[j, :2] - sampled)) < PREDICTION_AGREES_M
            rolled_most = max(
                rolled_most, float(np.hypot(*(sampled - step.position_feet_in_world[j, :2])))
            )
    assert rolled_most > 1e-3


def test_a_first_shift_rolls_the_feet_as_a_later_one_does(go2, go2_plan):
    """Before the first step, the contact points the builder predicts for a base it may shift
    to are those it has once the shift is a step: the balls roll from the start pose (a
    first shift was checked on unrolled contacts: solo12 of the corpus, seed 20261202 #22 of
    200, 22.8 mm of margin predicted and 18.3 mm sampled, under the 20 mm threshold)."""
    from planner.gaits.builder import StepBuilder
    from planner.gaits.steps import Phase, StepKind

    first = go2_plan.steps[0]
    base0, yaw = first.position_base_start_in_world, first.yaw_base_start
    feet = first.position_feet_in_world
    legs = planning_robot(go2).legs
    b = StepBuilder(base0, yaw, feet, 0.02, rolled_contacts=RolledContacts(legs, foot_ball(go2)))
    shifted = base0 + np.array([0.03, -0.04, 0.0])
    predicted = b.contact_points(b.feet, shifted)
    b.body(shifted, yaw, 1.0, StepKind.BODY, "shift", Phase.SHIFT)
    after = b.contact_points(b.feet, b.base)
    assert np.max(np.abs(predicted - after)) < PREDICTION_AGREES_M
    assert np.max(np.hypot(*(after - feet)[:, :2].T)) > 1e-3  # the balls rolled


@pytest.mark.parametrize("name, height_m", [("go2", 0.28), ("solo12", 0.2)])
def test_legs_rolled_together_roll_as_each_alone(name, height_m):
    """A new check pose adds the same last segment to every stance foot's base path; the
    predictor rolls those legs in one fixed point (_segments_together). Each leg's d is the
    one its own roll_feet pass gives (_segment), to the last bits (different batch lengths
    may take numpy's vector or scalar path for cos/sin: <= 1e-15 m), on random segments with
    a turn; a control: the legs' d differ from one another by more than 1e-4 m."""
    robot = load_robot(name)
    legs = planning_robot(robot).legs
    predictor = RolledContacts(legs, foot_ball(robot))
    hips = np.array([leg.position_hip_in_base for leg in legs])
    rest = hips[:, :2] + np.column_stack([np.zeros(4), 0.03 * np.sign(hips[:, 1])])
    rng = np.random.default_rng(3)
    spread = 0.0
    for _ in range(4):
        start = np.array([*rng.uniform(-0.02, 0.02, 2), height_m, rng.uniform(-0.3, 0.3)])
        end = start + np.array([*rng.uniform(-0.06, 0.06, 2), 0.0, rng.uniform(-0.1, 0.1)])
        c, s = np.cos(start[3]), np.sin(start[3])
        feet = (rest @ np.array([[c, s], [-s, c]])) + start[:2]
        feet = np.column_stack([feet, np.zeros(4)])
        together = predictor._segments_together([0, 1, 2, 3], start, end, feet)
        for j in range(4):
            alone = predictor._segment(j, start, end, feet[j], None)
            np.testing.assert_allclose(together[j], alone, rtol=0.0, atol=1e-15)
        spread = max(spread, float(np.ptp(np.array(together)[:, :2], axis=0).max()))
    assert spread > 1e-4
