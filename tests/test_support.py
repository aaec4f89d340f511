"""Vertical ground reactions of the stance feet (thesis eq A.30-A.33), silo4kin.support."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from silo4kin.errors import Silo4Error
from silo4kin.support import SupportError, support_moment_residual, support_reactions

#: Force balance tolerance relative to the weight [dimensionless]: a 3x3 / 3x4 solve with
#: entries ~0.3 m and 1 has condition ~10-100 for SILO4-like stances; 1e-12 of W is ~1e3 eps.
FORCE_TOLERANCE = 1e-12
#: Moment balance tolerance relative to W * 1 m [dimensionless], same reasoning.
MOMENT_TOLERANCE = 1e-12

WEIGHT = 30.0 * 9.81  # [N], the thesis's body load


def _stances(n: int, seed: int) -> np.ndarray:
    """SILO4-like feet (N, 4, 3) around the CoG: one foot per quadrant, 0.2-0.5 m out, z = -h."""
    rng = np.random.default_rng(seed)
    angle = np.array([1, -1, 3, -3]) * np.pi / 4 + rng.uniform(-0.5, 0.5, (n, 4))
    radius = rng.uniform(0.2, 0.5, (n, 4))
    p = np.stack([radius * np.cos(angle), radius * np.sin(angle), np.full((n, 4), -0.4)], axis=2)
    return p + np.array([*rng.uniform(-0.05, 0.05, 2), 0.0])  # CoG a little off-centre


def _inside_triangle(p: np.ndarray) -> bool:
    """Origin strictly inside the triangle p (3, 2)."""

    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    s = [cross(p[(i + 1) % 3] - p[i], -p[i]) for i in range(3)]
    return bool(all(v > 1e-9 for v in s) or all(v < -1e-9 for v in s))


def test_four_feet_sum_to_weight_and_zero_moment():
    """At every four-foot sample the reactions sum to m g and their moment about the CoG is 0."""
    p = _stances(2000, seed=1)
    r = support_reactions(p, np.ones((2000, 4), bool), WEIGHT)
    assert np.abs(r.force.sum(axis=1) - WEIGHT).max() < FORCE_TOLERANCE * WEIGHT
    assert np.abs(support_moment_residual(p, r.force)).max() < MOMENT_TOLERANCE * WEIGHT
    assert not r.unloadable.any()
    assert r.force.min() >= 0.0 - 1e-9 * WEIGHT


def test_four_feet_least_norm_is_eq_a31_when_nonnegative():
    """Where no reaction is negative the result is exactly Aᵀ(AAᵀ)⁻¹W (eq A.31)."""
    p = _stances(200, seed=2)
    r = support_reactions(p, np.ones((200, 4), bool), WEIGHT)
    for i in range(0, 200, 17):
        A = np.vstack([p[i, :, 0], p[i, :, 1], np.ones(4)])
        F = A.T @ np.linalg.solve(A @ A.T, [0.0, 0.0, WEIGHT])
        if F.min() >= 0:
            assert np.abs(r.force[i] - F).max() < FORCE_TOLERANCE * WEIGHT


@pytest.mark.parametrize("lifted", range(4))
def test_three_feet_swing_foot_carries_nothing(lifted):
    """A foot in the air carries nothing; the three others satisfy A F = W exactly (eq A.33)."""
    p = _stances(500, seed=3 + lifted)
    keep = np.array([_inside_triangle(np.delete(p[i, :, :2], lifted, axis=0)) for i in range(500)])
    p = p[keep]
    contact = np.ones((p.shape[0], 4), bool)
    contact[:, lifted] = False
    p[:, lifted] = np.nan  # a swing foot's position must not matter
    r = support_reactions(p, contact, WEIGHT)
    assert np.all(r.force[:, lifted] == 0.0)
    assert np.abs(r.force.sum(axis=1) - WEIGHT).max() < FORCE_TOLERANCE * WEIGHT
    assert np.abs(support_moment_residual(np.nan_to_num(p), r.force)).max() < (
        MOMENT_TOLERANCE * WEIGHT
    )
    assert not r.unloadable.any() and r.force.min() >= 0


def test_three_feet_cog_outside_triangle_is_unloadable():
    """CoG outside the support triangle: some reaction is negative and the sample is flagged."""
    p = np.array([[[0.3, 0.3, 0], [0.3, -0.3, 0], [-0.3, 0.3, 0], [-0.3, -0.3, 0]]])
    p[..., 0] += 0.1  # CoG behind the front pair... and the rear-left foot
    contact = np.array([[True, True, True, False]])
    p[..., :2] += np.array([0.05, -0.05])  # origin now outside triangle LF-RF-LH
    r = support_reactions(p, contact, WEIGHT)
    assert r.unloadable[0] and r.force[0].min() < 0


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.lists(st.floats(-0.5, 0.5), min_size=8, max_size=8))
def test_nonnegative_split_exists_iff_cog_in_hull(xy):
    """Four feet: a non-negative split is returned iff the CoG lies in the feet's convex hull,
    and then it balances W with every reaction >= 0."""
    p = np.zeros((1, 4, 3))
    p[0, :, :2] = np.reshape(xy, (4, 2))
    try:
        r = support_reactions(p, np.ones((1, 4), bool), WEIGHT)
    except SupportError:
        return  # collinear feet: undefined split, reported
    in_hull = any(
        _inside_triangle(p[0, list(tri), :2]) for tri in itertools.combinations(range(4), 3)
    )
    if in_hull:
        assert not r.unloadable[0]
        assert r.force.min() >= -1e-9 * WEIGHT
        assert abs(r.force.sum() - WEIGHT) < 1e-9 * WEIGHT
        assert np.abs(support_moment_residual(p, r.force)).max() < 1e-9 * WEIGHT
        # least norm among non-negative splits: never larger than... the least-norm split
        assert np.linalg.norm(r.force) >= np.linalg.norm(r.least_norm) - 1e-9 * WEIGHT


def test_least_norm_can_pull_inside_polygon_and_is_corrected():
    """Near an edge of a skewed quadrilateral, eq A.31 asks a foot to pull although the CoG is
    inside the polygon; the returned split unloads that foot instead (docs/thesis-notes.md)."""
    p = np.zeros((1, 4, 3))
    p[0, :, :2] = [[-0.368, 0.023], [-0.350, 0.113], [0.074, -0.192], [0.008, 0.009]]
    r = support_reactions(p, np.ones((1, 4), bool), WEIGHT)
    assert r.least_norm[0].min() < -0.1 * WEIGHT  # eq A.31 pulls
    assert r.corrected[0] and not r.unloadable[0]
    assert r.force[0].min() >= -1e-9 * WEIGHT and np.isclose(
        r.force[0].min(), 0.0, atol=1e-9 * WEIGHT
    )
    assert abs(r.force.sum() - WEIGHT) < FORCE_TOLERANCE * WEIGHT
    r_thesis = support_reactions(p, np.ones((1, 4), bool), WEIGHT, nonnegative=False)
    assert np.array_equal(r_thesis.force, r.least_norm)


def test_total_mass_weight_array():
    """A per-sample weight (N,) is honoured sample by sample."""
    p = _stances(3, seed=9)
    w = np.array([100.0, 200.0, 416.3])
    r = support_reactions(p, np.ones((3, 4), bool), w)
    assert np.abs(r.force.sum(axis=1) - w).max() < FORCE_TOLERANCE * w.max()


def test_fewer_than_three_feet_names_sample():
    p = _stances(5, seed=4)
    contact = np.ones((5, 4), bool)
    contact[3, :2] = False
    with pytest.raises(SupportError, match="sample 3 has 2 stance feet") as info:
        support_reactions(p, contact, WEIGHT)
    assert info.value.sample == 3


def test_collinear_feet_name_sample():
    p = np.zeros((2, 4, 3))
    p[:, :, 0] = [0.3, 0.1, -0.1, -0.3]  # all on the x axis
    with pytest.raises(SupportError, match="sample 0: the stance feet are collinear"):
        support_reactions(p, np.ones((2, 4), bool), WEIGHT)


@pytest.mark.parametrize("weight", [0.0, -1.0, np.nan])
def test_bad_weight(weight):
    with pytest.raises(Silo4Error, match="weight must be finite and > 0"):
        support_reactions(_stances(2, seed=5), np.ones((2, 4), bool), weight)


def test_bad_shapes():
    with pytest.raises(Silo4Error, match="expected"):
        support_reactions(np.zeros((2, 3, 3)), np.ones((2, 3), bool), WEIGHT)
    with pytest.raises(Silo4Error, match="contact has shape"):
        support_reactions(np.zeros((2, 4, 3)), np.ones((3, 4), bool), WEIGHT)
