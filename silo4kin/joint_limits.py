"""The one joint-limit check of the toolkit, with its one tolerance.

Every place that asks "are these joint values inside the URDF limits?" (the workspace's reach
checks, the mammal IK, the sample verification, the thesis-consistency page) calls
:func:`joint_limit_bounds` or :func:`within_joint_limits`.
"""

from __future__ import annotations

import numpy as np

#: Slack on the URDF joint limits [rad]: IK of a target placed exactly on a limit by FK
#: returns it with a rounding error of ~1e-15 rad; 1e-9 rad (~0.3 µm of foot motion at a
#: 0.3 m lever) accepts that and nothing a servo would notice.
JOINT_LIMIT_TOLERANCE = 1e-9


def joint_limit_bounds(
    q_lower: np.ndarray, q_upper: np.ndarray, reserve: np.ndarray | float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """(lowest, highest) accepted joint values [rad]: the limits (..., 3) widened by
    JOINT_LIMIT_TOLERANCE and narrowed by ``reserve`` [rad] (scalar or broadcastable, e.g.
    (3,) to reserve room on one joint only)."""
    lo = np.asarray(q_lower, dtype=float) - JOINT_LIMIT_TOLERANCE + reserve
    hi = np.asarray(q_upper, dtype=float) + JOINT_LIMIT_TOLERANCE - reserve
    return lo, hi


def within_joint_limits(
    q: np.ndarray, q_lower: np.ndarray, q_upper: np.ndarray, reserve: np.ndarray | float = 0.0
) -> np.ndarray:
    """Whether every joint value of each row of ``q`` (..., J) [rad] lies within
    :func:`joint_limit_bounds` of ``q_lower``/``q_upper`` (broadcastable to q); (...,) bool.
    NaN joint values are outside."""
    lo, hi = joint_limit_bounds(q_lower, q_upper, reserve)
    return np.all((q >= lo) & (q <= hi), axis=-1)
