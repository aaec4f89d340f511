"""Static stability (§5.1): triangle areas, the area test, the signed margin S_m, shifts."""

import numpy as np
import pytest

from planner.stability.margin import (
    inside_support_triangle,
    support_margin,
    triangle_area,
    triangle_margin,
)
from planner.stability.shifts import incenter, shift_for_margin

#: Margins here are built from exact coordinates ~0.5 m; 1e-12 m is far above rounding.
EXACT_M = 1e-12
SQUARE = np.array([[0.3, 0.3], [0.3, -0.3], [-0.3, 0.3], [-0.3, -0.3]])  # LF RF LH RH


def test_triangle_area_eq_5_1_sign_and_value():
    a, b, c = np.array([0.0, 0.0]), np.array([1.0, 0.0]), np.array([0.0, 2.0])
    assert triangle_area(a, b, c) == pytest.approx(1.0, abs=EXACT_M)
    assert triangle_area(a, c, b) == pytest.approx(-1.0, abs=EXACT_M)


def test_square_stance_lifting_any_leg_puts_cog_on_an_edge():
    """Thesis-notes: all feet at position 2 and a leg lifted gives S_m = 0."""
    feet = np.repeat(SQUARE[None], 4, axis=0)
    contact = ~np.eye(4, dtype=bool)
    m = support_margin(feet, contact, np.zeros((4, 2)))
    np.testing.assert_allclose(m, 0.0, atol=EXACT_M)


def test_four_feet_margin_is_distance_to_nearest_side():
    m = support_margin(SQUARE[None], np.ones((1, 4), bool), np.array([[0.1, 0.05]]))
    assert m[0] == pytest.approx(0.2, abs=EXACT_M)


def test_margin_negative_outside_and_matches_area_test():
    """The sign of S_m agrees with the triangle-area test of eq 5.1 on random points."""
    rng = np.random.default_rng(3)
    tri = rng.uniform(-0.5, 0.5, size=(500, 3, 2))
    cog = tri.mean(axis=1) + rng.uniform(-0.25, 0.25, size=(500, 2))
    feet = np.concatenate([tri, np.zeros((500, 1, 2))], axis=1)
    contact = np.tile([True, True, True, False], (500, 1))
    m = support_margin(feet, contact, cog)
    inside = inside_support_triangle(tri, cog)
    clear = np.abs(m) > 1e-9  # points on an edge may go either way
    assert np.all((m[clear] > 0) == inside[clear])
    assert (m > 0).sum() > 100 and (m < 0).sum() > 100


def test_margin_equals_point_to_segment_distance_inside():
    tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    assert triangle_margin(tri, np.array([0.2, 0.1])) == pytest.approx(0.1, abs=EXACT_M)


def test_four_feet_with_one_inside_uses_the_hull():
    feet = np.array([[[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0], [0.0, 0.0]]])
    m = support_margin(feet, np.ones((1, 4), bool), np.array([[0.0, 0.0]]))
    ref = triangle_margin(feet[0, :3], np.array([0.0, 0.0]))
    assert m[0] == pytest.approx(ref, abs=EXACT_M)


def test_fewer_than_three_feet_has_no_support():
    m = support_margin(SQUARE[None], np.array([[True, True, False, False]]), np.zeros((1, 2)))
    assert m[0] == -np.inf


def test_shift_reaches_target_and_refuses_impossible():
    tri = SQUARE[[1, 2, 3]]
    new = shift_for_margin(tri, np.zeros(2), 0.03)
    assert triangle_margin(tri, new) == pytest.approx(0.03, abs=1e-9)
    _, r = incenter(tri)
    assert shift_for_margin(tri, np.zeros(2), r + 0.01) is None


def _random_triangles(rng: np.random.Generator, n: int) -> np.ndarray:
    """n triangles (3, 2) [m]: half generic, half near-degenerate (a vertex within ~1e-13 to
    1e-11 m of the opposite side's line, or two vertices within ~1e-12 m of each other)."""
    tris = rng.uniform(-0.5, 0.5, (n, 3, 2))
    for t in tris[n // 2 :]:
        a, b = t[0], t[1]
        along, height = rng.uniform(-0.5, 1.5), 10.0 ** rng.uniform(-13, -11)
        e = b - a
        normal = np.array([-e[1], e[0]]) / np.hypot(*e)
        t[2] = a + along * e + rng.choice([-1.0, 1.0]) * height * normal
        if rng.uniform() < 0.25:
            t[1] = a + 10.0 ** rng.uniform(-13, -11) * rng.normal(size=2)
    return tris


def test_fast_paths_equal_the_reference_support_margin():
    """One support-margin implementation (support_margin); its fast paths agree with it on
    seeded random triangles and points, inside and outside, near-degenerate triangles
    included: triangle_margins (K points, one triangle), triangle_margin_xy (Python floats),
    margin_to_edges (per-step edge lines), footholds.lift_margin (N triangles). The float
    paths round each edge distance differently (margin.py docstring): equal within 1e-15 m,
    and -inf (degenerate) in the same cases."""
    from planner.stability.margin import (
        margin_to_edges,
        support_edges,
        triangle_margin_xy,
        triangle_margins,
    )
    from planner.workspace.footholds import lift_margin

    rng = np.random.default_rng(9)
    tris = _random_triangles(rng, 400)
    n_degenerate = 0
    for tri in tris:
        pts = rng.uniform(-0.6, 0.6, (40, 2))
        feet = np.zeros((40, 4, 2))
        feet[:, :3] = tri
        contact = np.tile([True, True, True, False], (40, 1))
        ref = support_margin(feet, contact, pts)
        n_degenerate += bool(np.isneginf(ref[0]))
        np.testing.assert_allclose(triangle_margins(tri, pts), ref, atol=1e-15, rtol=0)
        scalar = [triangle_margin_xy(*map(tuple, tri), tuple(p)) for p in pts]
        np.testing.assert_allclose(scalar, ref, atol=1e-15, rtol=0)
        edges = support_edges(feet[:1], contact[:1])
        np.testing.assert_array_equal(margin_to_edges(edges, np.zeros(40, int), pts), ref)
        np.testing.assert_array_equal(lift_margin(np.repeat(tri[None], 40, 0), pts), ref)
    assert 50 < n_degenerate < 200  # both sides of the degeneracy rule were exercised


def test_degeneracy_rule_is_the_collinear_tolerance():
    """A triangle is degenerate (S_m = -inf) exactly when a vertex is within
    COLLINEAR_TOLERANCE of the opposite side's line or a side is that short; a flat triangle
    whose long side's opposite vertex is within the tolerance has no support even though its
    short sides are still edges."""
    from planner.stability.margin import COLLINEAR_TOLERANCE, triangle_margin_xy

    for height, finite in ((0.5 * COLLINEAR_TOLERANCE, False), (2.0 * COLLINEAR_TOLERANCE, True)):
        tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, height]])
        assert np.isfinite(triangle_margin(tri, np.array([0.5, 0.0]))) == finite
        assert np.isfinite(triangle_margin_xy(*map(tuple, tri), (0.5, 0.0))) == finite


def test_shift_margins_equal_the_kernel():
    """The edge distances of shifts.py (the shift's closed form, the half-planes of
    closest_point_with_margin) give the kernel's S_m: the shifted CoG has the target margin
    and the closest point's margin is >= the target, on seeded random triangles."""
    from planner.stability.shifts import closest_point_with_margin, shift_for_margin_xy

    rng = np.random.default_rng(11)
    checked = 0
    for tri in rng.uniform(-0.5, 0.5, (300, 3, 2)):
        pts = tuple(tuple(float(v) for v in p) for p in tri)
        cog = (float(rng.uniform(-0.3, 0.3)), float(rng.uniform(-0.3, 0.3)))
        target = float(rng.uniform(0.0, 0.05))
        new = shift_for_margin_xy(*pts, cog, target)
        if new is not None and triangle_margin(tri, np.array(cog)) < target:
            assert triangle_margin(tri, np.array(new)) == pytest.approx(target, abs=1e-12)
            checked += 1
        near = closest_point_with_margin([pts], cog, target)
        if near is not None:
            assert triangle_margin(tri, np.array(near)) >= target - 1e-12
    assert checked > 30
