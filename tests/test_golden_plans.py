"""Every golden plan (tests/golden_plans.py) plans to the same fingerprint as when stored.

A refactor keeps every fingerprint; a change that moves plans on purpose rewrites
tests/golden_plans.json in its own commit (``tests/golden_plans.py --update``) and says why.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from golden_plans import (
    PROJECTION_ATOL,
    fingerprint_differences,
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


def _first_plan():
    from planner import plan_path

    spec = GOLDEN[0]
    return plan_path(
        _ROBOTS("silo4"),
        np.asarray(spec["waypoints"]),
        spec["height"],
        start_heading=spec["start_heading"],
        workspace=spec["preset"],
    ).trajectory


def test_fingerprint_sees_a_change_of_one_joint_by_ten_nanoradians():
    """One joint value moved by 1e-8 rad changes the fingerprint; so does one contact flag."""
    trajectory = _first_plan()
    q = trajectory.q.copy()
    q[len(q) // 2, 4] += 1e-8
    moved = fingerprint_trajectory(replace(trajectory, q=q))
    differences = fingerprint_differences(moved, fingerprint_trajectory(trajectory))
    assert [d.split(":")[0] for d in differences] == ["q"]
    contact = trajectory.contact.copy()
    contact[len(contact) // 2, 0] = ~contact[len(contact) // 2, 0]
    flipped = fingerprint_trajectory(replace(trajectory, contact=contact))
    differences = fingerprint_differences(flipped, fingerprint_trajectory(trajectory))
    assert [d.split(":")[0] for d in differences] == ["contact_sha256"]


def test_fingerprint_ignores_last_bit_noise():
    """Every value moved by a few ulps (what another CPU's SIMD path gives) keeps the
    fingerprint: the tolerance is not what decides a refactor's verdict on one machine."""
    trajectory = _first_plan()
    rng = np.random.default_rng(5)
    noisy = {
        field: np.asarray(getattr(trajectory, field))
        * (
            1.0
            + rng.choice([-4, -1, 0, 1, 4], size=np.shape(getattr(trajectory, field))) * 2.0**-52
        )
        for field in ("t", "position_base_in_world", "yaw_base_in_world", "q")
    }
    got = fingerprint_trajectory(replace(trajectory, **noisy))
    assert fingerprint_differences(got, fingerprint_trajectory(trajectory)) == []
    assert PROJECTION_ATOL <= 1e-9


@pytest.mark.parametrize("case", GOLDEN, ids=[case["name"] for case in GOLDEN])
def test_plan_matches_its_golden_fingerprint(case):
    """The plan of the stored inputs has the stored fingerprint (exact discrete parts, float
    sums within PROJECTION_ATOL)."""
    got = plan_fingerprint(case, _ROBOTS(case["robot"]))
    assert fingerprint_differences(got, case["fingerprint"]) == []
