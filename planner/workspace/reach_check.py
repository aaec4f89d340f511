"""Whether a leg reaches foot targets within its joint limits: the workspace's one IK check.

:func:`reachable_in_limits` asks one leg (either family, silo4kin.legs);
:func:`reachable_in_limits_of_legs` and :func:`joint_values_of_legs` ask several legs in one
vectorised pass (silo4kin.kinematics.knee_down_ik_of_legs for insect legs), and
:func:`joint_values_in_limits_of_legs` both from one: the inner loop of the omnidirectional
gait, the crawl's sway and ψ_max's bisection. The limits are those of
silo4kin.joint_limits, with one tolerance.
"""

from __future__ import annotations

import numpy as np

from silo4kin.geometry import LegGeometry
from silo4kin.joint_limits import within_joint_limits
from silo4kin.kinematics import KneeDownLegs, knee_down_ik_of_legs
from silo4kin.leg_family import INSECT, family_of
from silo4kin.legs import inverse_kinematics
from silo4kin.memo import memo_of, memoised


def _theta1_reserve(theta1_reserve: float) -> np.ndarray:
    """(3,) [rad]: ``theta1_reserve`` on the first joint only."""
    return np.array([theta1_reserve, 0.0, 0.0])


def reachable_in_limits(
    leg: LegGeometry, position_foot_in_base: np.ndarray, theta1_reserve: float = 0.0
) -> np.ndarray:
    """Whether IK reaches each target (N, 3) [m] within the joint limits; (N,) bool.

    theta1_reserve [rad] narrows the hip-yaw range on both sides.
    Either leg family (silo4kin.legs: insect knee-down, mammal the rest pose's branch).
    """
    res = inverse_kinematics(leg, np.atleast_2d(np.asarray(position_foot_in_base, float)))
    q = np.where(np.isfinite(res.q), res.q, 0.0)
    return res.reachable & within_joint_limits(
        q, leg.q_lower, leg.q_upper, _theta1_reserve(theta1_reserve)
    )


class _LegTable:
    """The joint limits and knee-down IK table of a tuple of insect legs, kept in the first
    leg's memo (silo4kin.memo) under the ids of all of them."""

    def __init__(self, legs: tuple) -> None:
        self.legs = legs
        self.ik = KneeDownLegs.of(legs)
        self.q_lower = np.array([leg.q_lower for leg in legs], dtype=float)
        self.q_upper = np.array([leg.q_upper for leg in legs], dtype=float)


#: Leg tables a leg keeps (one per tuple of legs it is planned with).
LEG_TABLES_PER_LEG = 16


def _insect_leg_table(legs: tuple) -> _LegTable:
    tables = memo_of(legs[0]).setdefault("leg_tables", {})
    key = tuple(id(leg) for leg in legs)
    table = tables.get(key)
    if table is None or any(a is not b for a, b in zip(table.legs, legs)):  # ids reused
        tables.pop(key, None)
        table = memoised(tables, key, lambda: _LegTable(legs), LEG_TABLES_PER_LEG)
    return table


def _all_insect(legs: tuple) -> bool:
    return all(family_of(leg) is INSECT for leg in legs)


def reachable_in_limits_of_legs(
    legs, leg_index: np.ndarray, position_foot_in_base: np.ndarray, theta1_reserve: float = 0.0
) -> np.ndarray:
    """:func:`reachable_in_limits` of target i (N, 3) [m] for leg ``legs[leg_index[i]]``, for
    all legs in one vectorised pass, (N,) bool: the same values, bit for bit
    (tests/test_workspace.py). Insect legs: silo4kin.kinematics.knee_down_ik_of_legs; other
    families: one reachable_in_limits call per leg."""
    idx = np.asarray(leg_index, dtype=np.intp)
    p = np.asarray(position_foot_in_base, dtype=float).reshape(-1, 3)
    legs = tuple(legs)
    reserve = float(theta1_reserve)
    if not _all_insect(legs):
        out = np.zeros(len(p), dtype=bool)
        for k, leg in enumerate(legs):
            rows = np.flatnonzero(idx == k)
            if rows.size:
                out[rows] = reachable_in_limits(leg, p[rows], reserve)
        return out
    table = _insect_leg_table(legs)
    q, reachable = knee_down_ik_of_legs(table.ik, idx, p)
    q = np.where(np.isfinite(q), q, 0.0)
    return reachable & within_joint_limits(
        q, table.q_lower[idx], table.q_upper[idx], _theta1_reserve(reserve)
    )


def joint_values_of_legs(
    legs, leg_index: np.ndarray, position_foot_in_base: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(q (N, 3) [rad], NaN where out of reach; reachable (N,) bool): the IK of target i
    for leg ``legs[leg_index[i]]``, all insect legs in one pass
    (silo4kin.kinematics.knee_down_ik_of_legs). Legs of other families: their IK leg by leg."""
    idx = np.asarray(leg_index, dtype=np.intp)
    p = np.asarray(position_foot_in_base, dtype=float).reshape(-1, 3)
    legs = tuple(legs)
    if not _all_insect(legs):
        q, ok = np.full((len(p), 3), np.nan), np.zeros(len(p), dtype=bool)
        for k, leg in enumerate(legs):
            rows = np.flatnonzero(idx == k)
            if rows.size:
                res = inverse_kinematics(leg, p[rows])
                q[rows], ok[rows] = res.q, res.reachable
        return q, ok
    res = knee_down_ik_of_legs(_insect_leg_table(legs).ik, idx, p)
    return res.q, res.reachable


def joint_values_in_limits_of_legs(
    legs, leg_index: np.ndarray, position_foot_in_base: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(q (N, 3) [rad], NaN where out of reach; in limits (N,) bool): what
    :func:`joint_values_of_legs` and :func:`reachable_in_limits_of_legs` (no reserve) answer
    for the same targets, from one IK pass (the same values as calling both: the IK is
    elementwise, and the limits are compared as reachable_in_limits compares them)."""
    idx = np.asarray(leg_index, dtype=np.intp)
    q, reachable = joint_values_of_legs(legs, idx, position_foot_in_base)
    legs = tuple(legs)
    if _all_insect(legs):
        table = _insect_leg_table(legs)
        lower, upper = table.q_lower, table.q_upper
    else:
        lower = np.array([leg.q_lower for leg in legs], dtype=float)
        upper = np.array([leg.q_upper for leg in legs], dtype=float)
    in_limits = reachable & within_joint_limits(
        np.where(np.isfinite(q), q, 0.0), lower[idx], upper[idx], _theta1_reserve(0.0)
    )
    return q, in_limits
