"""The load passed between the feet at contact changes (silo4kin/load_transfer.py) and the
swing dwell that leaves four-foot time for it (planner/trajectory/profiles.py, dwell).

Independent references: the equilibrium of the reactions (their sum and moments about the
CoG), a brute-force search of the weighted split over the one-dimensional family of
four-foot splits, and the plan's own samples (feet, contacts) for the dwell.
"""

from __future__ import annotations

import numpy as np
import pytest

from planner import plan_path
from planner.trajectory.torques import fixed_hip_torques
from silo4kin.errors import Silo4Error
from silo4kin.load_transfer import LOAD_TRANSFER_S, load_shares
from silo4kin.support import support_moment_residual, support_reactions

STRAIGHT = np.array([[0.0, 1.0], [1.0, 1.0], [0.0, 2.0]])


def test_shares_ramp_from_zero_at_touchdown_and_to_zero_at_lift_off() -> None:
    """A stance between two swings starts and ends at share 0 and reaches 1 after T; the
    smoothstep is 1/2 at T/2; swing feet 0; stances at the plan's ends are not ramped."""
    dt, T = 0.01, 0.2
    t = np.arange(101) * dt
    contact = np.ones((101, 4), dtype=bool)
    contact[10:30, 0] = False  # leg 0 swings 0.10-0.29 s, lands at 0.30 s
    contact[80:, 1] = False  # leg 1 lifts after 0.79 s and stays up
    s = load_shares(contact, t, T)
    assert np.all(s[10:30, 0] == 0.0) and np.all(s[80:, 1] == 0.0)
    assert s[30, 0] == 0.0 and s[79, 1] == 0.0  # touchdown / lift-off samples carry nothing
    assert s[40, 0] == pytest.approx(0.5)  # T/2 after touchdown
    assert s[9, 0] == 0.0  # the last stance sample before the swing
    assert s[8, 0] == pytest.approx(3 * 0.05**2 - 2 * 0.05**3)  # 0.01 s before it
    assert s[0, 1] == 1.0 and s[100, 0] == 1.0  # the plan's ends are not ramped
    assert np.all(s[:, 2:] == 1.0)
    assert np.all(np.diff(s[30:51, 0]) > 0) and s[50, 0] == 1.0
    np.testing.assert_array_equal(load_shares(contact, t, 0.0), contact.astype(float))


def test_shares_refuse_bad_input() -> None:
    contact = np.ones((5, 4), dtype=bool)
    with pytest.raises(Silo4Error, match=">= 0 s"):
        load_shares(contact, np.arange(5.0), -0.1)
    with pytest.raises(Silo4Error, match="must be"):
        load_shares(contact, np.arange(4.0), 0.2)
    with pytest.raises(Silo4Error, match="share"):
        support_reactions(np.zeros((5, 4, 2)) + np.eye(4, 2), contact, 10.0, share=contact * 2.0)


def _four_feet(rng: np.random.Generator, n: int) -> np.ndarray:
    """Feet (n, 4, 2) around a CoG at the origin, one per quadrant (the CoG well inside)."""
    signs = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]], dtype=float)
    return signs * rng.uniform(0.15, 0.4, size=(n, 4, 2))


def test_weighted_split_carries_the_load_and_is_the_least_weighted_one() -> None:
    """With shares the four-foot split still balances the load (sum W, no moment about the
    CoG), a foot of share 0 carries nothing, all shares 1 give eq A.31, and the split is
    the least Σ F²/s among the non-negative splits (brute force over the null line)."""
    rng = np.random.default_rng(7)
    n, weight = 200, 400.0
    feet = _four_feet(rng, n)
    contact = np.ones((n, 4), dtype=bool)
    share = rng.uniform(0.05, 1.0, size=(n, 4))
    share[:40, 0] = 0.0  # a foot about to lift (or just landed)
    r = support_reactions(feet, contact, weight, share=share)
    assert not r.unloadable.any()
    np.testing.assert_allclose(r.force.sum(axis=1), weight, rtol=1e-12)
    np.testing.assert_allclose(support_moment_residual(feet, r.force), 0.0, atol=1e-9)
    assert np.all(r.force >= -1e-9 * weight)
    # share 0 unloads the foot wherever the other three can carry the load alone
    three = contact.copy()
    three[:, 0] = False
    alone = ~support_reactions(feet, three, weight).unloadable[:40]
    assert 5 < alone.sum() < 40
    np.testing.assert_allclose(r.force[:40][alone, 0], 0.0, atol=1e-9)
    assert np.all(r.force[:40][~alone, 0] > 0)
    ones = support_reactions(feet, contact, weight, share=np.ones((n, 4)))
    plain = support_reactions(feet, contact, weight)
    np.testing.assert_allclose(ones.force, plain.force, atol=1e-9)
    assert np.abs(r.force - plain.force).max() > 1.0  # the shares do move the split
    # brute force: every split is the least-norm one plus t times the null direction
    for i in range(40, 60):
        f0, s = plain.least_norm[i], share[i]
        a = np.vstack([feet[i].T, np.ones(4)])
        null = np.linalg.svd(a)[2][-1]
        t = np.linspace(-2 * weight, 2 * weight, 400_001)
        splits = f0 + t[:, None] * null
        cost = np.where(np.all(splits >= 0, axis=1), np.sum(splits**2 / s, axis=1), np.inf)
        best = splits[np.argmin(cost)]
        np.testing.assert_allclose(r.force[i], best, atol=2e-2)  # the grid's step 1e-2 N


@pytest.fixture(scope="module")
def crawl(silo4):
    """The default straight path at 0.4 m (the crawl)."""
    return plan_path(silo4, STRAIGHT, 0.4, start_heading=np.pi / 2)


def test_reactions_are_continuous_where_a_fourth_foot_lands_or_lifts(silo4, crawl) -> None:
    """With the load transfer the reactions change by < 0.001 W per 10 ms sample where the
    stance goes from three feet to four or back, and by < 0.1 W anywhere: no foot lands on
    the sample another lifts (the default stands on four feet between two swings,
    planner/gaits/walk.py swap_stand_units; without it the module docstring's jump); each
    sample split on its own (transfer 0) steps by > 0.25 W at those changes. (The quasi-static
    split, App. A's with the whole robot: the floating robot's forces start from it and add
    what the motion asks, which changes as fast as the crawl's sways accelerate.)"""
    tr = crawl.trajectory
    weight = silo4.total_mass * 9.80665

    def reactions(transfer_s: float) -> np.ndarray:
        return fixed_hip_torques(silo4, tr, "total", 9.80665, "rnea", transfer_s).reactions

    passed = reactions(LOAD_TRANSFER_S)
    instant = reactions(0.0)
    n = tr.contact.sum(axis=1)
    four = n[1:] != n[:-1]  # a fourth foot lands or lifts
    swap = (n[1:] == n[:-1]) & np.any(tr.contact[1:] != tr.contact[:-1], axis=1)
    assert four.sum() > 20 and swap.sum() == 0
    step_passed = np.abs(np.diff(passed, axis=0)).max(axis=1)
    step_instant = np.abs(np.diff(instant, axis=0)).max(axis=1)
    assert step_passed[four].max() < 1e-3 * weight
    assert step_passed.max() < 0.1 * weight
    assert step_instant[four].max() > 0.25 * weight
    assert LOAD_TRANSFER_S > 0
