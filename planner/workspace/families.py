"""What the workspace does differently per leg family (silo4kin.leg_family).

An insect leg turns about the vertical first: its reachable ground set is a ring sector
(planner/workspace/reach_insect.py), position 2 keeps room from both hip-yaw limits, the
spin reserves room on θ1, and the feasible heights are scanned on a 1 cm grid. A mammal
leg has no hip yaw: its set is a grid mask (planner/workspace/reach_mammal.py), position 2
sits at the rest pose's lateral offset, the spin reserves nothing on θ1, and the feasible
heights are scanned on a coarser grid, each end of the range then moved inwards past the
holes a finer scan finds near it. Both families' range is the longest run of feasible grid
heights (planner/workspace/heights.py feasible_height_range: a folded mammal leg may plan a
sliver low, and so may an insect leg, issue 21). :func:`workspace_family` gives a robot's.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np

import planner.workspace.reach_mammal as reach_mammal
from planner.workspace.footholds import CRAB_ROOM_RAD, choose_centres
from planner.workspace.reach_insect import reachable_set
from planner.workspace.reach_insect import segment_half_lengths as insect_segments
from silo4kin.leg_family import INSECT, MAMMAL, LegFamily, family_of

#: Reserve on the θ1 limits when sizing the default preset's spin angle per cycle [rad]:
#: room for the CoG shifts that keep the margin positive during the spin (a 5 cm shift seen
#: from a foot 0.3 m from its hip is ~10°). The thesis preset makes no shifts: no reserve.
SPIN_THETA1_RESERVE = np.deg2rad(10.0)
#: Room position 2 keeps from both hip-yaw limits in the default workspace [rad]: the θ1
#: reserve of the spin plus as much again for the spin angle itself.
CENTRE_YAW_RESERVE = 2.0 * SPIN_THETA1_RESERVE
#: Height grid of feasible_height_range for insect legs [m].
INSECT_HEIGHT_GRID_M = 0.01
#: Height grid of feasible_height_range for mammal legs [m]: their reachable sets are grid
#: masks (planner/workspace/reach_mammal.py), 2 cm keeps the search to a few seconds; the ends are
#: bisected to 0.1 mm as for insect legs.
MAMMAL_HEIGHT_GRID_M = 0.02


class WorkspaceFamily(Protocol):
    """A leg family's workspace rules.

    Attributes:
        leg_family: the silo4kin family.
        height_grid_m: step of the feasible-height scan [m].
        edge_bisections: bisections of each end of the feasible range (to < 0.1 mm).
        spin_theta1_reserve_rad: room kept on θ1 when sizing the default spin [rad].
        end_scan: whether each end of the feasible range (the longest run of feasible grid
            heights) is moved inwards past the holes a finer scan finds near it
            (planner/workspace/heights.py _past_end_holes).
    """

    leg_family: LegFamily
    height_grid_m: float
    edge_bisections: int
    spin_theta1_reserve_rad: float
    end_scan: bool

    def reachable_sets(
        self, legs: tuple, levels: tuple[float, ...], knee_margin_rad: float
    ) -> tuple:
        """Each leg's reachable ground set at the foot heights ``levels`` [m] in B."""

    def choose_centres(
        self, legs: tuple, sets: tuple, erosion_m: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """(position 2 (x, y) per leg (L, 2) [m], extents (L, 2) [m]) inside ``sets``
        eroded by ``erosion_m`` [m]."""

    def extents_at(self, sets: tuple, centres: np.ndarray, erosion_m: float) -> np.ndarray:
        """Extents (L, 2) [m] (full lengths along x, fitted along x turned by 0 and
        ±CRAB_ROOM_RAD, and along y) of given centres (L, 2) [m] inside ``sets`` eroded by
        ``erosion_m`` [m]; 0 for a centre outside (choose_centres' extents, elsewhere)."""


class InsectWorkspace:
    """Insect legs (module docstring)."""

    leg_family = INSECT
    height_grid_m = INSECT_HEIGHT_GRID_M
    edge_bisections = 10  # 1 cm / 2^10 < 0.1 mm, the rounding
    spin_theta1_reserve_rad = float(SPIN_THETA1_RESERVE)
    end_scan = False

    def reachable_sets(
        self, legs: tuple, levels: tuple[float, ...], knee_margin_rad: float
    ) -> tuple:
        return tuple(reachable_set(leg, levels, knee_margin_rad) for leg in legs)

    def choose_centres(
        self, legs: tuple, sets: tuple, erosion_m: float
    ) -> tuple[np.ndarray, np.ndarray]:
        return choose_centres(sets, erosion_m, CENTRE_YAW_RESERVE)

    def extents_at(self, sets: tuple, centres: np.ndarray, erosion_m: float) -> np.ndarray:
        return _extents_at(insect_segments, sets, centres, erosion_m)


class MammalWorkspace:
    """Mammal legs (module docstring)."""

    leg_family = MAMMAL
    height_grid_m = MAMMAL_HEIGHT_GRID_M
    edge_bisections = 11  # 2 cm / 2^11 < 0.1 mm
    spin_theta1_reserve_rad = 0.0  # no hip yaw to reserve
    end_scan = True

    def reachable_sets(
        self, legs: tuple, levels: tuple[float, ...], knee_margin_rad: float
    ) -> tuple:
        return tuple(reach_mammal.reachable_set(leg, levels, knee_margin_rad) for leg in legs)

    def choose_centres(
        self, legs: tuple, sets: tuple, erosion_m: float
    ) -> tuple[np.ndarray, np.ndarray]:
        rest_y = np.array([reach_mammal.rest_lateral_in_base(leg) for leg in legs])
        return reach_mammal.choose_centres(sets, erosion_m, CRAB_ROOM_RAD, rest_y)

    def extents_at(self, sets: tuple, centres: np.ndarray, erosion_m: float) -> np.ndarray:
        return _extents_at(reach_mammal.segment_half_lengths, sets, centres, erosion_m)


def _extents_at(segments: Any, sets: tuple, centres: np.ndarray, erosion_m: float) -> np.ndarray:
    """WorkspaceFamily.extents_at with a family's segment_half_lengths."""
    out = np.zeros((len(sets), 2))
    for k, s in enumerate(sets):
        c = np.asarray(centres, dtype=float)[k : k + 1, :2]
        ax = min(
            float(segments(s, c, np.array([np.cos(a), np.sin(a)]), erosion_m)[0])
            for a in (-CRAB_ROOM_RAD, 0.0, CRAB_ROOM_RAD)
        )
        ay = float(segments(s, c, np.array([0.0, 1.0]), erosion_m)[0])
        out[k] = 2.0 * ax, 2.0 * ay
    return out


_BY_FAMILY: dict[str, WorkspaceFamily] = {
    INSECT.name: InsectWorkspace(),
    MAMMAL.name: MammalWorkspace(),
}


def workspace_family(robot: Any) -> WorkspaceFamily:
    """The :class:`WorkspaceFamily` of a robot's legs (insect for a robot without legs)."""
    family = family_of(robot.legs[0]) if robot.legs else INSECT
    return _BY_FAMILY[family.name]
