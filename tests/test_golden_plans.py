"""Every golden plan (tests/golden_plans.py) plans to the same fingerprint as when stored.

A refactor keeps every fingerprint; a change that moves plans on purpose rewrites
tests/golden_plans.json in its own commit (``tests/golden_plans.py --update``) and says why.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from golden_plans import (
    fingerprint_trajectory,
    load_golden,
    plan_fingerprint,
    random_case_specs,
    robot_loader,
    thesis_case_specs,
)

GOLDEN = load_golden()
_ROBOTS = robot_loader()


def test_golden_file_holds_the_cases_of_the_module():
    """The stored inputs are the cases the module defines (nothing dropped or edited)."""
    stored = [{k: v for k, v in case.items() if k != "fingerprint"} for case in GOLDEN]
    assert stored == thesis_case_specs() + random_case_specs()
    assert len(GOLDEN) == 38


def test_fingerprint_sees_a_change_of_one_nanoradian_step():
    """The fingerprint changes when one joint value moves by 1e-8 rad (above the rounding)."""
    spec = GOLDEN[0]
    from planner import plan_path

    plan = plan_path(
        _ROBOTS("silo4"),
        np.asarray(spec["waypoints"]),
        spec["height"],
        start_heading=spec["start_heading"],
        workspace=spec["preset"],
    )
    trajectory = plan.trajectory
    q = trajectory.q.copy()
    q[len(q) // 2, 4] += 1e-8
    moved = replace(trajectory, q=q)
    assert fingerprint_trajectory(moved) != fingerprint_trajectory(trajectory)


@pytest.mark.parametrize("case", GOLDEN, ids=[case["name"] for case in GOLDEN])
def test_plan_matches_its_golden_fingerprint(case):
    """The plan of the stored inputs hashes to the stored fingerprint."""
    assert plan_fingerprint(case, _ROBOTS(case["robot"])) == case["fingerprint"]
