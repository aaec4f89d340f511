"""Static stability (thesis §5.1): support polygon, triangle-area test, signed margin S_m.

The CoG projection must lie inside the support polygon of the stance feet. The thesis tests
this with triangle areas (eq 5.1): the CoG is inside the support triangle when the three small
triangles (CoG + two adjacent feet) add up to the support triangle's area. That is an equality
of floats, so :func:`inside_support_triangle` compares with a relative tolerance, and the
planner decides with the signed stability margin S_m instead (:func:`support_margin`): the
distance from the CoG projection to the nearest edge of the support polygon, positive inside,
negative outside (then minus the distance to the most violated edge line).

All functions are vectorised over N samples; positions are horizontal (x, y) [m] in any one
frame (the planner uses the world frame W).
"""

from __future__ import annotations

import math
from itertools import combinations

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

_PAIRS = tuple(combinations(range(4), 2))


def triangle_area(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Signed area of triangles abc, eq 5.1: ½ det [[xa, ya, 1], [xb, yb, 1], [xc, yc, 1]].

    Args:
        a, b, c: vertices [m], shape (..., 2).

    Returns:
        area [m^2], shape (...), positive when a, b, c run counter-clockwise.
    """
    return 0.5 * ((b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
                  - (c[..., 0] - a[..., 0]) * (b[..., 1] - a[..., 1]))


def inside_support_triangle(feet: np.ndarray, cog: np.ndarray,
                            rel_tol: float = AREA_RELATIVE_TOLERANCE) -> np.ndarray:
    """Thesis test (§5.1, Fig 5.1): |A1| + |A2| + |A3| == |A| within a relative tolerance.

    Args:
        feet: the three support feet (x, y) [m], shape (..., 3, 2).
        cog: CoG projection (x, y) [m], shape (..., 2).

    Returns:
        True where the CoG is inside or on the triangle, shape (...).
    """
    f0, f1, f2 = feet[..., 0, :], feet[..., 1, :], feet[..., 2, :]
    area = np.abs(triangle_area(f0, f1, f2))
    parts = (np.abs(triangle_area(cog, f0, f1)) + np.abs(triangle_area(cog, f1, f2))
             + np.abs(triangle_area(cog, f2, f0)))
    return parts <= area * (1.0 + rel_tol)


def support_margin(feet: np.ndarray, contact: np.ndarray, cog: np.ndarray) -> np.ndarray:
    """Signed static stability margin S_m of the stance feet, vectorised.

    The support polygon is the convex hull of the feet in contact. A pair of stance feet is a
    hull edge when every other stance foot lies on one side of its line; S_m is the smallest
    signed distance of the CoG to a hull edge line, oriented so that the other feet are on the
    positive side. Inside a convex polygon that is the distance to the nearest edge.

    Args:
        feet: foot positions (x, y) [m], shape (N, 4, 2).
        contact: stance flags, shape (N, 4); rows need >= 3 stance feet (else -inf).
        cog: CoG projection (x, y) [m], shape (N, 2).

    Returns:
        S_m [m], shape (N,).
    """
    feet = np.asarray(feet, dtype=float)
    contact = np.asarray(contact, dtype=bool)
    n = feet.shape[0]
    margin = np.full(n, np.inf)
    any_edge = np.zeros(n, dtype=bool)
    for i, j in _PAIRS:
        a, b = feet[:, i], feet[:, j]
        edge = b - a
        length = np.hypot(edge[:, 0], edge[:, 1])
        length = np.where(length > COLLINEAR_TOLERANCE, length, np.nan)
        normal = np.stack([-edge[:, 1], edge[:, 0]], axis=1) / length[:, None]  # left normal
        # signed distances of the other stance feet
        others = [k for k in range(4) if k not in (i, j)]
        d_other = np.stack([np.einsum("nk,nk->n", feet[:, k] - a, normal) for k in others], 1)
        in_contact = contact[:, others]
        pos = np.all((d_other >= -COLLINEAR_TOLERANCE) | ~in_contact, axis=1)
        neg = np.all((d_other <= COLLINEAR_TOLERANCE) | ~in_contact, axis=1)
        is_edge = contact[:, i] & contact[:, j] & (pos ^ neg) & np.isfinite(length)
        sign = np.where(pos, 1.0, -1.0)
        d_cog = sign * np.einsum("nk,nk->n", cog - a, normal)
        margin = np.where(is_edge, np.minimum(margin, d_cog), margin)
        any_edge |= is_edge
    margin[~any_edge | (contact.sum(axis=1) < 3)] = -np.inf
    return margin


def triangle_margin(feet: np.ndarray, cog: np.ndarray) -> float:
    """S_m of one support triangle (3 feet, (3, 2) [m]) for one CoG (2,) [m]; scalar."""
    feet4 = np.zeros((1, 4, 2))
    feet4[0, :3] = feet
    contact = np.array([[True, True, True, False]])
    return float(support_margin(feet4, contact, np.asarray(cog, float)[None])[0])


def incenter(feet: np.ndarray) -> tuple[np.ndarray, float]:
    """Incenter (the point of largest margin) and inradius of a triangle (3, 2) [m]."""
    (ax, ay), (bx, by), (cx, cy) = (tuple(map(float, f)) for f in feet)
    la, lb, lc = math.hypot(bx - cx, by - cy), math.hypot(cx - ax, cy - ay), \
        math.hypot(ax - bx, ay - by)
    perimeter = la + lb + lc
    center = np.array([(la * ax + lb * bx + lc * cx) / perimeter,
                       (la * ay + lb * by + lc * cy) / perimeter])
    area2 = abs((bx - ax) * (cy - ay) - (cx - ax) * (by - ay))
    return center, area2 / perimeter


def shift_for_margin(feet: np.ndarray, cog: np.ndarray, target: float
                     ) -> np.ndarray | None:
    """Smallest move of the CoG towards the incenter that gives margin >= target.

    Along the segment cog -> incenter every edge distance is affine (and the margin, their
    minimum, concave), so the first point reaching the target is found in closed form.

    Args:
        feet: support triangle (3, 2) [m]; cog: (2,) [m]; target: wanted S_m [m].

    Returns:
        the new CoG (2,) [m], or None when the inradius is below the target.
    """
    center, radius = incenter(feet)
    if radius < target:
        return None
    pts = [tuple(map(float, f)) for f in feet]
    px, py = float(cog[0]), float(cog[1])
    alpha = 0.0
    for i in range(3):
        (ax, ay), (bx, by), (ox, oy) = pts[i], pts[(i + 1) % 3], pts[(i + 2) % 3]
        ex, ey = bx - ax, by - ay
        norm = math.hypot(ex, ey)
        nx, ny = -ey / norm, ex / norm
        if (ox - ax) * nx + (oy - ay) * ny < 0:
            nx, ny = -nx, -ny
        d0 = (px - ax) * nx + (py - ay) * ny
        d1 = (center[0] - ax) * nx + (center[1] - ay) * ny
        if d0 < target:
            alpha = max(alpha, (target - d0) / (d1 - d0))
    alpha = min(alpha, 1.0)
    return np.array([px + alpha * (center[0] - px), py + alpha * (center[1] - py)])
