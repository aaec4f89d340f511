"""Where the foothold search on a terrain's surfaces looks (planner/gaits/surface_footholds.py):
the grid of candidate points around a nominal foothold, nearest first, and the rings of the
edge and wall tests around a candidate: EDGE_RINGS rings of EDGE_DIRECTIONS rays, the outer
ring at margin / cos(pi / EDGE_DIRECTIONS), so that a straight edge nearer than the margin
passes between no two rays of the outer ring unmet.
"""

from __future__ import annotations

import numpy as np

#: Rays and rings of the edge test (module docstring).
EDGE_DIRECTIONS = 32
EDGE_RINGS = 3


def disc_offsets(step_m: float, radius_m: float) -> np.ndarray:
    """Grid offsets (K, 2) [m] of spacing ``step_m`` [m] within ``radius_m`` [m], nearest
    first (the origin first; ties by x, then y)."""
    n = int(np.floor(radius_m / step_m))
    g = np.arange(-n, n + 1) * step_m
    xy = np.stack(np.meshgrid(g, g), axis=-1).reshape(-1, 2)
    d = np.hypot(xy[:, 0], xy[:, 1])
    keep = d <= radius_m + 1e-12
    order = np.lexsort((xy[keep, 1], xy[keep, 0], d[keep]))
    return xy[keep][order]


def ring_offsets(margin_m: float) -> np.ndarray:
    """Points (R, 2) [m] of the edge test's rings around a candidate for a margin
    ``margin_m`` [m] (module docstring), ring by ring from the innermost."""
    outer = margin_m / np.cos(np.pi / EDGE_DIRECTIONS)
    angles = 2.0 * np.pi * np.arange(EDGE_DIRECTIONS) / EDGE_DIRECTIONS
    rays = np.column_stack([np.cos(angles), np.sin(angles)])
    radii = outer * np.arange(1, EDGE_RINGS + 1) / EDGE_RINGS
    return (radii[:, None, None] * rays[None]).reshape(-1, 2)
