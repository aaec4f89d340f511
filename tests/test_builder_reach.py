"""A gait's step is checked for reach when it is built, not left to the samples' verification
(planner/gaits/builder.py StepBuilder.lift_margin and _shift_rounds, issue 21).

The control: the SILO4 xacro variant (L2 0.3, L3 0.35, Lb 0.25 m, 60 N m joints) at
h 0.21484375 m to (1, 1) m, drawn by tests/test_other_robots.py. The crawl and the creeping
gait are refused for the effort budget (OverBudget); the plain creeping and spinning gait
(facing's fallback) had shifted the base 0.26 m behind the nominal CoG for the budget, then
swung RF to its front foothold 1.1 m away: the swing's whole-body CoM was NaN, its margin NaN
passed the builder's ``margin < threshold`` test, and the plan was refused by the samples'
verification ("a foot target is out of reach or singular at t = 47.40 units (creep transfer
RF)"), which the test's contract (OverBudget only) does not allow.
"""

from __future__ import annotations

import numpy as np
from test_planner_invariants import check_invariants

from planner import plan_path
from planner.path.plan_path import robot_in_body_com_frame
from silo4kin import load_robot

HEIGHT_M = 0.21484375


def test_the_variant_plans_where_its_swing_had_left_the_reach():
    robot = load_robot(xacro_args={"L2": 0.3, "L3": 0.35, "Lb": 0.25})
    plan = plan_path(robot, np.array([[1.0, 1.0]]), HEIGHT_M, samples_per_unit=10)
    # the crawl and the creep: OverBudget; facing crabs less since its crab limit keeps the
    # turned stances' shapes 1 cm off the ground (round 20), and its tibias now clear: the
    # plain gait, which it fell back to before, is not needed
    assert plan.gait == "facing"
    check_invariants(robot_in_body_com_frame(robot), plan)
