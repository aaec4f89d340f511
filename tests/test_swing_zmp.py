"""The step builder checks a still-base lift for its zero-moment point too (issue 21).

The pipeline refuses a plan whose ZMP leaves the support polygon (planner/stability/
contact_forces.py); the builder checked the static whole-body CoM only, so a swing whose
leg accelerates hard (anymal corpus case 5: the top of a 0.17 m lift at 1 s a unit) planned
with the CoM 25.8 mm inside and was refused afterwards with the ZMP 3.9-7.0 mm outside, and
gait "auto" had no other gait to try. The lift now gets the body shift that keeps the ZMP
inside too (planner/gaits/builder.py, planner/stability/swing_com.py swing_zmp_in_world).
"""

from __future__ import annotations

import numpy as np
import pytest

from planner.gaits.builder import StepBuilder
from planner.model import planning_model
from planner.stability.margin import triangle_margins
from planner.stability.swing_com import SwingTiming

FEET = np.array([[0.3, 0.2, 0.0], [0.3, -0.2, 0.0], [-0.3, 0.2, 0.0], [-0.3, -0.2, 0.0]])
#: A ZMP that runs 60 mm off the CoM during the swing, towards the lifted foot (a stand-in
#: for a leg's swing).
AHEAD = np.array([-0.033, -0.05])


def _builder(zmp: bool) -> StepBuilder:
    def com(base, yaw, feet, leg, target):
        return np.tile(base[:2], (5, 1))

    b = StepBuilder(np.array([0.0, 0.0, 0.4]), 0.0, FEET, 0.02, swing_com=com)
    if zmp:
        b.swing_zmp = lambda base, yaw, feet, leg, target: com(base, yaw, feet, leg, target) + AHEAD
    return b


def test_a_lift_whose_zmp_leaves_the_support_is_shifted_until_it_is_inside() -> None:
    leg = 3  # RH: the other feet's triangle LF, RF, LH
    tri = np.delete(FEET, leg, axis=0)[:, :2]
    plain = _builder(zmp=False)
    plain.transfer(leg, FEET[leg] + [0.1, 0.0, 0.0], "t")
    zmp_then = triangle_margins(tri, (plain.base[:2] + AHEAD)[None])[0]
    assert zmp_then < 0  # the CoM rule alone lets the ZMP out
    b = _builder(zmp=True)
    b.transfer(leg, FEET[leg] + [0.1, 0.0, 0.0], "t")
    assert [s.label for s in b.steps] == ["shift", "t"]
    lifted = b.steps[1].position_base_start_in_world[:2]
    assert triangle_margins(tri, (lifted + AHEAD)[None])[0] >= b.zmp_least
    assert triangle_margins(tri, lifted[None])[0] >= b.threshold


@pytest.mark.parametrize("smooth", [False, True])
def test_the_swing_zmp_is_the_samples_zmp(anymal, smooth: bool) -> None:
    """swing_zmp_in_world is the ZMP the pipeline computes from the samples (the same CoM,
    differenced the same way): a leg swung alone, the base still."""
    from planner.gaits.steps import Step, StepKind
    from planner.stability.contact_forces import com_acceleration
    from planner.trajectory.sampling import sample_steps

    model = planning_model(anymal)
    base = np.array([0.0, 0.0, 0.45])
    feet = np.array([[0.35, 0.2, 0.0], [0.35, -0.2, 0.0], [-0.35, 0.2, 0.0], [-0.35, -0.2, 0.0]])
    end = feet[1] + [0.12, 0.03, 0.0]
    step = Step(StepKind.TRANSFER, "RF", 0.0, 1.0, base, base, 0.0, 0.0, feet[1], end,
                position_feet_in_world=feet)  # fmt: skip
    tr = sample_steps(model.planning_robot, (step,), 0.15, 100, 1.0, model=model, smooth=smooth)
    com = model.com_in_world(tr.q, tr.position_base_in_world, tr.yaw_base_in_world)
    acc = com_acceleration(com, tr.t)
    k = com[:, 2] / (9.80665 + acc[:, 2])
    sampled = com[:, :2] - k[:, None] * acc[:, :2]
    got = model.swing_zmp_in_world(
        base, 0.0, feet, 1, end, SwingTiming(0.15, smooth, 1.0, 0.0, 9.80665)
    )
    assert np.abs(got - sampled).max() < 1e-3
    assert np.abs(sampled - com[:, :2]).max() > 2e-3  # the swing moves it off the CoM
