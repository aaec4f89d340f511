"""Points the animation and the plots draw on the ground: waypoints and footholds given as
(M, 2) or (M, 3) points in W, and the footholds a plan used (start and touch-downs)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from planner.trajectory.samples import Trajectory
from silo4kin.errors import Silo4Error


def points_in_world(points: np.ndarray | Sequence | None, name: str) -> np.ndarray | None:
    """(M, 2) or (M, 3) points in W -> (M, 3) with z = 0 when 2-D; None stays None."""
    if points is None:
        return None
    arr = np.asarray(points, dtype=float)
    if arr.ndim != 2 or arr.shape[1] not in (2, 3) or not np.all(np.isfinite(arr)):
        raise Silo4Error(
            f"{name} must be finite points of shape (M, 2) or (M, 3), got shape {arr.shape}"
        )
    if arr.shape[1] == 2:
        arr = np.column_stack([arr, np.zeros(len(arr))])
    return arr


def touchdown_footholds(trajectory: Trajectory) -> np.ndarray:
    """Footholds used by the plan: every foot position at the start and at each touch-down.

    Returns:
        position_foothold_in_world [m], shape (M, 3), in time order.
    """
    contact = np.asarray(trajectory.contact, dtype=bool)
    feet = np.asarray(trajectory.position_foot_in_world, dtype=float)
    first = feet[0][contact[0]]
    touch = np.argwhere(contact[1:] & ~contact[:-1])  # (sample - 1, leg)
    later = feet[touch[:, 0] + 1, touch[:, 1]]
    return np.concatenate([first, later], axis=0)
