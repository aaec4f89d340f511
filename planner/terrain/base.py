"""The ground under the robot: the :class:`Terrain` protocol and flat ground.

A terrain answers three questions in the world frame W (z up):

- ``height_at(xy)``: the ground height z [m] under points (N, 2) [m], shape (N,);
- ``normal_at(xy)``: the unit ground normal there, shape (N, 3);
- ``allows_foothold(position_foot_in_world)``: whether a foot may stand at (3,) [m]; a
  terrain may instead raise :class:`~planner.errors.FootholdRefused` saying why.

The planner asks the terrain for the ground under the start pose and asks it about every
foothold a step places (planner/gaits/builder.py, through :func:`foothold_rule`). On these
terrains the gaits keep the feet at the start pose's ground height; a terrain file's boxes,
posts or missing floor are walked by searching footholds on its surfaces
(planner/gaits/surface_footholds.py).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from planner.errors import FootholdRefused

#: The builder's foothold rule: called with every foothold (3,) in W [m]; raises
#: FootholdRefused to abandon the gait being built there (planner/gaits/builder.py).
FootholdRule = Callable[[np.ndarray], None]


@runtime_checkable
class Terrain(Protocol):
    """The ground (module docstring)."""

    def height_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        """Ground height z [m] under points (N, 2) [m], shape (N,)."""
        ...

    def normal_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        """Unit ground normal in W under points (N, 2) [m], shape (N, 3)."""
        ...

    def allows_foothold(self, position_foot_in_world: np.ndarray) -> bool:
        """Whether a foot may stand at (3,) in W [m] (or raise FootholdRefused)."""
        ...


@dataclass(frozen=True)
class FlatGround:
    """Level ground at height ``z`` [m] (default 0: the design's world frame); every foothold
    is allowed."""

    z: float = 0.0

    #: No foothold is refused: the builder need not ask (foothold_rule returns None).
    refuses_footholds = False

    def height_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy_in_world, dtype=float).reshape(-1, 2)
        return np.full(len(xy), float(self.z))

    def normal_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        xy = np.asarray(xy_in_world, dtype=float).reshape(-1, 2)
        return np.tile(np.array([0.0, 0.0, 1.0]), (len(xy), 1))

    def allows_foothold(self, position_foot_in_world: np.ndarray) -> bool:
        return True


def foothold_rule(terrain: Terrain) -> FootholdRule | None:
    """The builder's foothold rule of ``terrain``: raises FootholdRefused at a foothold the
    terrain does not allow; None when the terrain allows every foothold (its
    ``refuses_footholds`` attribute is False), so the builder asks nothing."""
    if not getattr(terrain, "refuses_footholds", True):
        return None

    def rule(position_foot_in_world: np.ndarray) -> None:
        if not terrain.allows_foothold(position_foot_in_world):
            raise FootholdRefused(position_foot_in_world)

    return rule


def level_height(terrain: Terrain) -> float | None:
    """The height z [m] of level ground: a FlatGround's ``z``, or that of the ``ground`` a
    terrain wraps (ForbiddenPolygons, CheckedFootholds); None for ground that is not level
    (its heights must be asked point by point)."""
    if isinstance(terrain, FlatGround):
        return float(terrain.z)
    inner = getattr(terrain, "ground", None)
    return None if inner is None else level_height(inner)


def ground_height_at(terrain: Terrain, xy_in_world: np.ndarray) -> float:
    """The ground height z [m] under one point (2,) [m]."""
    return float(terrain.height_at(np.asarray(xy_in_world, dtype=float).reshape(1, 2))[0])
