"""The tibia rule inside the reach set the default gaits search (issue 21, item 6).

The default preset refuses samples where an insect leg's tibia capsule comes within
MIN_TIBIA_CLEARANCE_M of the ground (planner/trajectory/clearance.py). Checked only on the
sampled plan, that rule dropped a whole gait for one foothold (the zig-zag ``1,0 0,0.6 1,1.2
0,1.8`` at h = 0.25 m: the crawl by RF's tibia at 1.0 mm, the creeping gait by RH's at 1.2
mm), and the plan fell back to facing the path, missing its tolerance. The gaits' own foothold
searches (the omnidirectional gait's step halving, the crawl's advance halving and sway
checks) ask :func:`tibias_clear` beside the joint limits, so a foothold that would bring a
tibia down is replaced by a shorter or other step there, before another gait is tried.

The search measures each foot target's leg with the body level at the workspace height h
above flat ground (the capsule in closed form, tibia_clearance_of_rows) and asks
TIBIA_SEARCH_MARGIN_M more than the rule: the plan's samples lie between the configurations
searched. Legs are held as the sample check holds them: insect legs whose capsule clears the
rule at position 2.
"""

from __future__ import annotations

import numpy as np

from planner.trajectory.clearance import MIN_TIBIA_CLEARANCE_M, tibia_clearance_of_rows
from planner.workspace.layout import Workspace, joint_values_of_legs
from silo4kin.leg_family import INSECT, family_of

#: Clearance asked of a searched foothold beyond MIN_TIBIA_CLEARANCE_M [m]: the samples
#: between two searched configurations of a step (its ends and middle) dip below the lower
#: end by less than this on SILO4's steps (the capsule's height is smooth in the foot's
#: position; the step's middle is searched).
TIBIA_SEARCH_MARGIN_M = 0.001


def tibias_clear(
    legs, ws: Workspace, leg_index: np.ndarray, position_foot_in_base: np.ndarray
) -> np.ndarray:
    """(N,) bool: whether leg ``legs[leg_index[i]]`` with its foot at row i (N, 3) [m] in B
    keeps its tibia capsule MIN_TIBIA_CLEARANCE_M + TIBIA_SEARCH_MARGIN_M above the ground
    (module docstring); True for legs not held and for targets out of reach (the reach check
    answers for those)."""
    idx = np.asarray(leg_index, dtype=np.intp)
    if not _insect(legs)[idx].any():
        return np.ones(len(idx), dtype=bool)
    rows, targets = with_positions_2(legs, ws, idx, position_foot_in_base)
    q, _ = joint_values_of_legs(legs, rows, targets)
    return tibias_clear_at(legs, ws, rows, q)


def with_positions_2(
    legs, ws: Workspace, leg_index: np.ndarray, position_foot_in_base: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(leg index (L + N,), targets (L + N, 3) [m] in B): every leg's position 2 (L legs,
    whose tibia clearance says which legs are held), then the N targets of
    :func:`tibias_clear`; the rows whose joint values :func:`tibias_clear_at` takes."""
    n_legs = len(legs)
    rows = np.concatenate([np.arange(n_legs), np.asarray(leg_index, dtype=np.intp)])
    targets = np.concatenate(
        [
            ws.position_mid_in_base[:n_legs],
            np.asarray(position_foot_in_base, dtype=float).reshape(-1, 3),
        ]
    )
    return rows, targets


def tibias_clear_at(
    legs, ws: Workspace, rows_with_positions_2: np.ndarray, q: np.ndarray
) -> np.ndarray:
    """:func:`tibias_clear` of the targets after the first len(legs) rows of
    :func:`with_positions_2`, given the joint values ``q`` (L + N, 3) [rad] of those rows
    (NaN where out of reach): (N,) bool."""
    n_legs = len(legs)
    idx = rows_with_positions_2[n_legs:]
    insect = _insect(legs)
    if not insect[idx].any():
        return np.ones(len(idx), dtype=bool)
    clearance = tibia_clearance_of_rows(legs, rows_with_positions_2, q, float(ws.height))
    held = insect & (clearance[:n_legs] >= MIN_TIBIA_CLEARANCE_M)
    low = clearance[n_legs:] < MIN_TIBIA_CLEARANCE_M + TIBIA_SEARCH_MARGIN_M  # NaN: False
    return ~(held[idx] & low)


def _insect(legs) -> np.ndarray:
    """(L,) bool: which legs are insect legs (the only ones the tibia rule holds)."""
    return np.array([family_of(leg) is INSECT for leg in legs])
