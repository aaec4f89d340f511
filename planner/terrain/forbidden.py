"""Terrains that forbid footholds: convex polygons no foot may stand in (a ditch, a hole),
and a caller's own foothold function (plan_path's ``foothold_check``).

Both keep the heights and normals of the ground they wrap (flat ground by default).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from planner.errors import FootholdRefused, PlannerInputError
from planner.terrain.base import FlatGround, Terrain

#: Footholds are compared rounded to this many decimals [m] (1 nm), as sampled footholds
#: are (planner/studies/ditch.py footholds_in_world).
FOOTHOLD_DECIMALS = 9


def _half_planes(polygon_xy: np.ndarray) -> tuple[tuple[float, float, float], ...]:
    """(n_x, n_y, c) per edge of a convex polygon (M, 2) [m], outward unit normal n and
    offset c = n · vertex: a point p is inside when n · p - c <= 0 for every edge."""
    pts = np.asarray(polygon_xy, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 3 or not np.all(np.isfinite(pts)):
        raise PlannerInputError(
            f"a forbidden polygon needs at least 3 finite (x, y) vertices "
            f"[m], got shape {pts.shape}"
        )
    edges = np.roll(pts, -1, axis=0) - pts
    area2 = float(np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1]))
    sign = 1.0 if area2 > 0 else -1.0  # counter-clockwise: outward is (e_y, -e_x)
    out = []
    for (ex, ey), (vx, vy) in zip(edges, pts):
        length = float(np.hypot(ex, ey))
        nx, ny = sign * ey / length, -sign * ex / length
        out.append((float(nx), float(ny), float(nx * vx + ny * vy)))
    return tuple(out)


@dataclass(frozen=True, eq=False)
class ForbiddenPolygons:
    """``ground`` with convex polygons (each (M, 2) in W [m]) where no foothold may be: a
    foothold (rounded to FOOTHOLD_DECIMALS) is refused when its signed distance to a polygon
    is below ``clearance_m`` [m]. The distance is the largest of the signed distances to
    the polygon's edge lines (negative inside): exact inside and beside an edge, shorter
    than the true distance off a corner (a corner keeps a little more clearance)."""

    polygons_xy_in_world: Sequence[np.ndarray]
    clearance_m: float = 0.0
    ground: Terrain = field(default_factory=FlatGround)
    _planes: tuple = field(init=False, repr=False, compare=False)

    refuses_footholds = True

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "_planes", tuple(_half_planes(p) for p in self.polygons_xy_in_world)
        )

    def height_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        return self.ground.height_at(xy_in_world)

    def normal_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        return self.ground.normal_at(xy_in_world)

    def clearance(self, position_foot_in_world: np.ndarray) -> float:
        """Signed distance [m] of a foothold (x, y rounded to 1 nm) to the nearest polygon
        (class docstring; negative inside, inf without polygons)."""
        x = float(np.round(position_foot_in_world[0], FOOTHOLD_DECIMALS))
        y = float(np.round(position_foot_in_world[1], FOOTHOLD_DECIMALS))
        # python floats: the route search asks ~10^4 times per ditch
        return min(
            (max(nx * x + ny * y - c for nx, ny, c in planes) for planes in self._planes),
            default=float("inf"),
        )

    def clearances(self, points_in_world: np.ndarray) -> np.ndarray:
        """:meth:`clearance` of points (N, 2) or (N, 3) [m] at once, shape (N,): the same
        numbers (the same float operations, vectorised)."""
        pts = np.asarray(points_in_world, dtype=float)
        xy = np.round(pts.reshape(-1, pts.shape[-1])[:, :2], FOOTHOLD_DECIMALS)
        out = np.full(len(xy), np.inf)
        for planes in self._planes:
            n = np.array(planes)  # (M, 3): n_x, n_y, c per edge
            signed = xy[:, :1] * n[:, 0] + xy[:, 1:2] * n[:, 1] - n[:, 2]
            out = np.minimum(out, signed.max(axis=1))
        return out

    def allows_foothold(self, position_foot_in_world: np.ndarray) -> bool:
        return self.clearance(position_foot_in_world) >= self.clearance_m


@dataclass(frozen=True)
class CheckedFootholds:
    """``ground`` whose footholds a caller's function decides: ``check(foothold (3,) [m])``
    refuses one by raising any exception (plan_path's ``foothold_check``); the planner sees
    it as FootholdRefused, the exception as its cause. A pure function of the foothold: it
    may be asked twice about one."""

    check: Callable[[np.ndarray], None]
    ground: Terrain = field(default_factory=FlatGround)

    refuses_footholds = True

    def height_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        return self.ground.height_at(xy_in_world)

    def normal_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        return self.ground.normal_at(xy_in_world)

    def allows_foothold(self, position_foot_in_world: np.ndarray) -> bool:
        try:
            self.check(position_foot_in_world)
        except Exception as exc:  # noqa: BLE001 - any refusal, kept as the cause
            raise FootholdRefused(position_foot_in_world, repr(exc)) from exc
        return True
