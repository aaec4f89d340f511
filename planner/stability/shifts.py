"""Stability shifts (thesis §5.1, docs/decisions.md "Stability shifts"): where to move the
CoG so that a lift keeps a margin, in closed form.

- :func:`shift_for_margin`: the smallest move towards the support triangle's incenter that
  reaches a target S_m (one lift);
- :func:`closest_point_with_margin`: the point nearest a given one with S_m >= target in
  several triangles at once (folding the shifts of a group of lifts into one body phase).

Margins are those of planner/stability/margin.py (edge lines with inward normals).
"""

from __future__ import annotations

import math

import numpy as np

from planner.stability.margin import COLLINEAR_TOLERANCE

#: A shift aims this far above the threshold [m], so the lift never sits exactly on it.
SHIFT_EXTRA_M = 0.005


def _incenter_xy(
    a: tuple[float, float], b: tuple[float, float], c: tuple[float, float]
) -> tuple[float, float, float]:
    """(x, y, inradius) [m] of the triangle abc, in Python floats."""
    (ax, ay), (bx, by), (cx, cy) = a, b, c
    la, lb, lc = (
        math.hypot(bx - cx, by - cy),
        math.hypot(cx - ax, cy - ay),
        math.hypot(ax - bx, ay - by),
    )
    perimeter = la + lb + lc
    area2 = abs((bx - ax) * (cy - ay) - (cx - ax) * (by - ay))
    return (
        (la * ax + lb * bx + lc * cx) / perimeter,
        (la * ay + lb * by + lc * cy) / perimeter,
        area2 / perimeter,
    )


def incenter(feet: np.ndarray) -> tuple[np.ndarray, float]:
    """Incenter (the point of largest margin) and inradius of a triangle (3, 2) [m]."""
    a, b, c = ((float(f[0]), float(f[1])) for f in feet)
    x, y, radius = _incenter_xy(a, b, c)
    return np.array([x, y]), radius


def shift_for_margin_xy(
    a: tuple[float, float],
    b: tuple[float, float],
    c: tuple[float, float],
    cog: tuple[float, float],
    target: float,
) -> tuple[float, float] | None:
    """:func:`shift_for_margin` on Python floats (triangle abc, CoG, target [m]); the gait
    planner calls it thousands of times per plan."""
    cx, cy, radius = _incenter_xy(a, b, c)
    if radius < target:
        return None
    pts = (a, b, c)
    px, py = cog
    alpha = 0.0
    for i in range(3):
        (ax, ay), (bx, by), (ox, oy) = pts[i], pts[(i + 1) % 3], pts[(i + 2) % 3]
        ex, ey = bx - ax, by - ay
        norm = math.hypot(ex, ey)
        nx, ny = -ey / norm, ex / norm
        if (ox - ax) * nx + (oy - ay) * ny < 0:
            nx, ny = -nx, -ny
        d0 = (px - ax) * nx + (py - ay) * ny
        d1 = (cx - ax) * nx + (cy - ay) * ny
        if d0 < target:
            alpha = max(alpha, (target - d0) / (d1 - d0))
    alpha = min(alpha, 1.0)
    return px + alpha * (cx - px), py + alpha * (cy - py)


def shift_for_margin(feet: np.ndarray, cog: np.ndarray, target: float) -> np.ndarray | None:
    """Smallest move of the CoG towards the incenter that gives margin >= target.

    Along the segment cog -> incenter every edge distance is affine (and the margin, their
    minimum, concave), so the first point reaching the target is found in closed form.

    Args:
        feet: support triangle (3, 2) [m]; cog: (2,) [m]; target: wanted S_m [m].

    Returns:
        the new CoG (2,) [m], or None when the inradius is below the target.
    """
    a, b, c = ((float(f[0]), float(f[1])) for f in feet)
    new = shift_for_margin_xy(a, b, c, (float(cog[0]), float(cog[1])), float(target))
    return None if new is None else np.array(new)


def _inward_half_planes(
    triangles: list[tuple[tuple[float, float], ...]], target: float
) -> list[tuple[float, float, float]]:
    """Half-planes n·p >= c (unit n) of the points with S_m >= target in every triangle."""
    planes = []
    for tri in triangles:
        for i in range(3):
            (ax, ay), (bx, by), (ox, oy) = tri[i], tri[(i + 1) % 3], tri[(i + 2) % 3]
            ex, ey = bx - ax, by - ay
            norm = math.hypot(ex, ey)
            if norm < COLLINEAR_TOLERANCE:
                return []
            nx, ny = -ey / norm, ex / norm
            if (ox - ax) * nx + (oy - ay) * ny < 0:
                nx, ny = -nx, -ny
            planes.append((nx, ny, nx * ax + ny * ay + target))
    return planes


def closest_point_with_margin(
    triangles: list[tuple[tuple[float, float], ...]], point: tuple[float, float], target: float
) -> tuple[float, float] | None:
    """The point nearest ``point`` (x, y) [m] whose S_m is >= ``target`` [m] in every one of
    ``triangles`` (each three (x, y) feet [m]), or None when no point has that margin in all.

    The points with S_m >= target in a triangle are the triangle shrunk by the target, an
    intersection of three half-planes; their intersection over the triangles is a convex
    polygon, built by clipping (Sutherland-Hodgman) a box around the first triangle. The
    nearest point is ``point`` itself when inside, else the nearest point of the polygon's
    boundary. Used to fold the stability shifts of the lifts between two body phases into the
    first body phase (planner/gaits/builder.py).
    """
    planes = _inward_half_planes(triangles, target)
    if not planes:
        return None
    xs = [p[0] for p in triangles[0]]
    ys = [p[1] for p in triangles[0]]
    poly = [(min(xs), min(ys)), (max(xs), min(ys)), (max(xs), max(ys)), (min(xs), max(ys))]
    for nx, ny, c in planes:
        out: list[tuple[float, float]] = []
        n = len(poly)
        for i in range(n):
            p, q = poly[i], poly[(i + 1) % n]
            dp, dq = nx * p[0] + ny * p[1] - c, nx * q[0] + ny * q[1] - c
            if dp >= 0:
                out.append(p)
            if (dp >= 0) != (dq >= 0):
                s = dp / (dp - dq)
                out.append((p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])))
        poly = out
        if len(poly) < 3:
            return None
    px, py = point
    if all(nx * px + ny * py >= c for nx, ny, c in planes):
        return px, py
    best, best_d = None, math.inf
    for i in range(len(poly)):
        (ax, ay), (bx, by) = poly[i], poly[(i + 1) % len(poly)]
        ex, ey = bx - ax, by - ay
        e2 = ex * ex + ey * ey
        s = 0.0 if e2 == 0.0 else min(max(((px - ax) * ex + (py - ay) * ey) / e2, 0.0), 1.0)
        qx, qy = ax + s * ex, ay + s * ey
        d = math.hypot(qx - px, qy - py)
        if d < best_d:
            best, best_d = (qx, qy), d
    return best
