"""Static stability (thesis §5.1): support polygon, triangle-area test, signed margin S_m.

The CoG projection must lie inside the support polygon of the stance feet. The thesis tests
this with triangle areas (eq 5.1): the CoG is inside the support triangle when the three small
triangles (CoG + two adjacent feet) add up to the support triangle's area. That is an equality
of floats, so :func:`inside_support_triangle` compares with a relative tolerance, and the
planner decides with the signed stability margin S_m instead (:func:`support_margin`): the
distance from the CoG projection to the nearest edge of the support polygon, positive inside,
negative outside (then minus the distance to the most violated edge line).

All functions are vectorised over N samples; positions are horizontal (x, y) [m] in any one
frame (the planner uses the world frame W). The one kernel is the signed distance to the hull
edge lines, :func:`margin_to_edges` over :func:`support_edges`; :func:`support_margin` is
that kernel for one support state per CoG, :func:`triangle_margin` its scalar view.
:func:`triangle_margins` and :func:`triangle_margin_xy` are float fast paths for one
triangle. They compute each edge distance as (e x (p - u)) / |e| instead of the kernel's
(p - u) . n with n = e⊥ / |e|: the same real number, rounded differently (the two differ by a
few ulps, < 1e-15 m for coordinates ~1 m). They keep that form because the golden plan
fingerprints (tests/test_golden_plans.py) were recorded with it and a margin compared with a
threshold can flip on an ulp. They apply the same degeneracy rule, with the vertex height
taken as |doubled area| / side instead of the kernel's (o - u) . n; the two decisions differ
only when a height lies within a few ulps of COLLINEAR_TOLERANCE. tests/test_stability.py
checks the margins agree within 1e-15 m and the -inf cases coincide on seeded random
triangles, near-degenerate ones included.

The one degeneracy rule: a pair of stance feet is a hull edge when it is longer than
COLLINEAR_TOLERANCE and the other stance feet lie on one side of its line, at least one of
them farther than COLLINEAR_TOLERANCE from it; the support has an interior (and a finite S_m)
when it has >= 3 stance feet and >= 3 such edges, else S_m = -inf. For a triangle that is:
every side longer than COLLINEAR_TOLERANCE and every vertex farther than COLLINEAR_TOLERANCE
from the opposite side's line. Where to move the CoG for a margin:
planner/stability/shifts.py.
"""

from __future__ import annotations

import math
from itertools import combinations
from typing import NamedTuple

import numpy as np

#: Relative tolerance of the area equality of eq 5.1 [dimensionless]: areas are sums of
#: products of coordinates of size ~0.5 m, so rounding is ~1e-16 relative; 1e-9 accepts
#: rounding and rejects any point more than ~1e-9 * perimeter outside.
AREA_RELATIVE_TOLERANCE = 1e-9
#: Slack on the margin when comparing with a threshold [m]: a CoG placed exactly at the
#: threshold by construction may compute 1e-17 m below it.
MARGIN_TOLERANCE = 1e-9
#: Feet closer than this to a line count as on it when finding hull edges [m].
COLLINEAR_TOLERANCE = 1e-12
#: A support needs this many hull edges to have an interior (module docstring).
MIN_EDGES = 3


def triangle_area(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Signed area of triangles abc, eq 5.1: ½ det [[xa, ya, 1], [xb, yb, 1], [xc, yc, 1]].

    Args:
        a, b, c: vertices [m], shape (..., 2).

    Returns:
        area [m^2], shape (...), positive when a, b, c run counter-clockwise.
    """
    return 0.5 * (
        (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
        - (c[..., 0] - a[..., 0]) * (b[..., 1] - a[..., 1])
    )


def inside_support_triangle(
    feet: np.ndarray, cog: np.ndarray, rel_tol: float = AREA_RELATIVE_TOLERANCE
) -> np.ndarray:
    """Thesis test (§5.1, Fig 5.1): |A1| + |A2| + |A3| == |A| within a relative tolerance.

    Args:
        feet: the three support feet (x, y) [m], shape (..., 3, 2).
        cog: CoG projection (x, y) [m], shape (..., 2).

    Returns:
        True where the CoG is inside or on the triangle, shape (...).
    """
    f0, f1, f2 = feet[..., 0, :], feet[..., 1, :], feet[..., 2, :]
    area = np.abs(triangle_area(f0, f1, f2))
    parts = (
        np.abs(triangle_area(cog, f0, f1))
        + np.abs(triangle_area(cog, f1, f2))
        + np.abs(triangle_area(cog, f2, f0))
    )
    return parts <= area * (1.0 + rel_tol)


class SupportEdges(NamedTuple):
    """Hull edge lines of the stance feet, one row per support state (see support_margin).

    Attributes:
        point: a foot on each edge line (x, y) [m], shape (R, E, 2).
        normal: unit normal of each line pointing into the polygon, shape (R, E, 2).
        valid: False for rows with < 3 stance feet or < MIN_EDGES edges (S_m = -inf there),
        shape (R,).
    Rows have E >= 1 slots; a row with fewer edges repeats its first edge.
    """

    point: np.ndarray
    normal: np.ndarray
    valid: np.ndarray


def _edge_pairs(feet: np.ndarray, contact: np.ndarray):
    """Per foot pair i < j of the F feet: is_edge (R,), foot i (R, 2), inward normal (R, 2)."""
    n_feet = feet.shape[1]
    for i, j in combinations(range(n_feet), 2):
        a, b = feet[:, i], feet[:, j]
        edge = b - a
        length = np.hypot(edge[:, 0], edge[:, 1])
        length = np.where(length > COLLINEAR_TOLERANCE, length, np.nan)
        normal = np.stack([-edge[:, 1], edge[:, 0]], axis=1) / length[:, None]  # left normal
        # signed distances of the other stance feet
        others = [k for k in range(n_feet) if k not in (i, j)]
        d_other = np.stack([np.einsum("nk,nk->n", feet[:, k] - a, normal) for k in others], 1)
        in_contact = contact[:, others]
        pos = np.all((d_other >= -COLLINEAR_TOLERANCE) | ~in_contact, axis=1)
        neg = np.all((d_other <= COLLINEAR_TOLERANCE) | ~in_contact, axis=1)
        is_edge = contact[:, i] & contact[:, j] & (pos ^ neg) & np.isfinite(length)
        sign = np.where(pos, 1.0, -1.0)
        yield is_edge, a, normal * sign[:, None]


def support_edges(feet: np.ndarray, contact: np.ndarray) -> SupportEdges:
    """The hull edge lines of :func:`support_margin` for R support states (feet (R, F, 2)
    [m], contact (R, F), F >= 3 feet), so that S_m of many CoG positions over one support
    state costs a few signed distances each (:func:`margin_to_edges`)."""
    feet = np.asarray(feet, dtype=float)
    contact = np.asarray(contact, dtype=bool)
    pairs = list(_edge_pairs(feet, contact))
    is_edge = np.stack([p[0] for p in pairs], 1)  # (R, 6)
    point = np.stack([p[1] for p in pairs], 1)  # (R, 6, 2)
    normal = np.stack([p[2] for p in pairs], 1)
    valid = (is_edge.sum(axis=1) >= MIN_EDGES) & (contact.sum(axis=1) >= 3)
    # compact the edges to the first E slots; pad with the row's first edge (min unchanged)
    order = np.argsort(~is_edge, axis=1, kind="stable")
    n_edges = is_edge.sum(axis=1)
    width = max(int(n_edges.max(initial=0)), 1)
    slot = np.where(np.arange(width) < n_edges[:, None], order[:, :width], order[:, :1])
    rows = np.arange(len(feet))[:, None]
    return SupportEdges(point[rows, slot], normal[rows, slot], valid)


def margin_to_edges(edges: SupportEdges, row: np.ndarray, cog: np.ndarray) -> np.ndarray:
    """S_m of CoG projections cog (N, 2) [m] in support states edges[row] (row: (N,) ints);
    shape (N,). Equal to :func:`support_margin` of the same feet, contact and CoG."""
    cog_x, cog_y = cog[:, 0], cog[:, 1]

    def distance(e: int) -> np.ndarray:  # signed distance to edge line e
        point, normal = edges.point[:, e], edges.normal[:, e]
        return (cog_x - point[row, 0]) * normal[row, 0] + (cog_y - point[row, 1]) * normal[row, 1]

    margin = distance(0)
    for e in range(1, edges.point.shape[1]):
        np.minimum(margin, distance(e), out=margin)
    margin[~edges.valid[row]] = -np.inf
    return margin


def support_margin(feet: np.ndarray, contact: np.ndarray, cog: np.ndarray) -> np.ndarray:
    """Signed static stability margin S_m of the stance feet, vectorised.

    The support polygon is the convex hull of the feet in contact. A pair of stance feet is a
    hull edge when every other stance foot lies on one side of its line; S_m is the smallest
    signed distance of the CoG to a hull edge line, oriented so that the other feet are on the
    positive side. Inside a convex polygon that is the distance to the nearest edge.

    Args:
        feet: foot positions (x, y) [m], shape (N, F, 2), F >= 3.
        contact: stance flags, shape (N, F); rows need >= 3 stance feet (else -inf).
        cog: CoG projection (x, y) [m], shape (N, 2).

    Returns:
        S_m [m], shape (N,).
    """
    feet = np.asarray(feet, dtype=float)
    cog = np.asarray(cog, dtype=float)
    return margin_to_edges(support_edges(feet, contact), np.arange(feet.shape[0]), cog)


def _degenerate(area2: float, lengths: tuple[float, ...]) -> bool:
    """The degeneracy rule (module docstring) from the doubled signed area [m²] and side
    lengths [m] of a triangle: a side no longer than COLLINEAR_TOLERANCE, or a vertex no
    farther than that from the opposite side's line (height |area2| / side)."""
    return not all(
        length > COLLINEAR_TOLERANCE and abs(area2) / length > COLLINEAR_TOLERANCE
        for length in lengths
    )


def triangle_margins(feet: np.ndarray, points: np.ndarray) -> np.ndarray:
    """S_m of many points (K, 2) [m] in one support triangle (3, 2) [m], shape (K,): the fast
    path of :func:`support_margin` for three stance feet (equal to it within 1e-15 m,
    tests/test_stability.py); -inf for a degenerate triangle."""
    a, b, c = (tuple(p) for p in np.asarray(feet, dtype=float)[:, :2].tolist())
    points = np.asarray(points, dtype=float)
    x, y = points[:, 0], points[:, 1]
    area2 = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
    sides = [(u, v, v[0] - u[0], v[1] - u[1]) for u, v in ((a, b), (b, c), (c, a))]
    lengths = tuple(math.hypot(ex, ey) for _, _, ex, ey in sides)
    if _degenerate(area2, lengths):
        return np.full(points.shape[0], -np.inf)
    sign = 1.0 if area2 > 0 else -1.0
    margin = np.full(points.shape[0], np.inf)
    for (u, _, ex, ey), length in zip(sides, lengths):  # Python floats: the same IEEE ops
        np.minimum(margin, sign * (ex * (y - u[1]) - ey * (x - u[0])) / length, out=margin)
    return margin


def triangle_margin_xy(
    a: tuple[float, float], b: tuple[float, float], c: tuple[float, float], p: tuple[float, float]
) -> float:
    """S_m of point p in triangle abc on Python floats [m] (the gait search calls it
    thousands of times per plan): the scalar fast path of :func:`support_margin` (equal to
    it within 1e-15 m, tests/test_stability.py); -inf for a degenerate triangle."""
    area2 = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
    aarea2 = abs(area2)
    sign = 1.0 if area2 > 0 else -1.0
    m = math.inf
    for u, v in ((a, b), (b, c), (c, a)):
        ex, ey = v[0] - u[0], v[1] - u[1]
        length = math.hypot(ex, ey)
        if not (length > COLLINEAR_TOLERANCE and aarea2 / length > COLLINEAR_TOLERANCE):
            return -math.inf  # the degeneracy rule, inlined (hot path)
        d = sign * (ex * (p[1] - u[1]) - ey * (p[0] - u[0])) / length
        m = min(m, d)
    return m


def triangle_margin(feet: np.ndarray, cog: np.ndarray) -> float:
    """S_m of one support triangle (3 feet, (3, 2) [m]) for one CoG (2,) [m]; scalar."""
    feet4 = np.zeros((1, 4, 2))
    feet4[0, :3] = feet
    contact = np.array([[True, True, True, False]])
    return float(support_margin(feet4, contact, np.asarray(cog, float)[None])[0])
