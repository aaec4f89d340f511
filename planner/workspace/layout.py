"""Leg workspace, stride and footholds for a body height (thesis §4.2.1, Fig 4.7-4.8).

:func:`workspace_for` gathers one :class:`Workspace` from the modules of the method:

- planner/workspace/foothold_layout.py: the presets (``default``: reachable sets;
  ``thesis``: the thesis's square) and position 2 and the strides λ_x, λ_y;
- planner/workspace/spin.py: the spin angle per cycle ψ_max;
- planner/workspace/heights.py: the feasible body heights, checked first;
- planner/workspace/reach_check.py: the IK-within-limits check they all use;
- planner/workspace/families.py: what differs per leg family.

It also serves, for the modules that import them from here, the names of those modules
(re-exported below); the frame change is planner.model.planning_robot.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.errors import PlannerInputError
from planner.model import planning_robot
from planner.presets import FootholdRule, footholds_of
from planner.workspace.families import (
    CENTRE_YAW_RESERVE,
    MAMMAL_HEIGHT_GRID_M,
    SPIN_THETA1_RESERVE,
    workspace_family,
)
from planner.workspace.foothold_layout import (
    CENTRE_RETRY_EROSION_M,
    DEFAULT_KNEE_MARGIN,
    DEFAULT_STABILITY_THRESHOLD_M,
    INTERFERENCE_SLACK_M,
    MIN_DEFAULT_STRIDE_M,
    MIN_STRIDE_M,
    PRESETS,
    RESERVE_DIRECTIONS,
    SHIFT_RESERVE_M,
    THESIS_EPSILON_M,
    _reachable_sets,
    check_preset,
    foot_levels,
    foothold_layout,
    hip_depth_m,
)
from planner.workspace.heights import (
    MIN_DEFAULT_HIP_CLEARANCE_M,
    MIN_HIP_CLEARANCE_M,
    _inside_feasible_run,
    check_height,
    feasible_height_range,
    stride_at,
    walks_any_direction,
)
from planner.workspace.reach_check import (
    joint_values_of_legs,
    reachable_in_limits,
    reachable_in_limits_of_legs,
)
from planner.workspace.reach_insect import ReachableSet
from planner.workspace.reach_mammal import MammalReachableSet
from planner.workspace.spin import MIN_DEFAULT_SPIN_RAD, default_psi_max, psi_max
from silo4kin.joint_limits import JOINT_LIMIT_TOLERANCE
from silo4kin.memo import cached_on_first_argument

__all__ = [
    "CENTRE_RETRY_EROSION_M",
    "CENTRE_YAW_RESERVE",
    "DEFAULT_KNEE_MARGIN",
    "DEFAULT_STABILITY_THRESHOLD_M",
    "INTERFERENCE_SLACK_M",
    "JOINT_LIMIT_TOLERANCE",
    "MAMMAL_HEIGHT_GRID_M",
    "MIN_DEFAULT_HIP_CLEARANCE_M",
    "MIN_DEFAULT_SPIN_RAD",
    "MIN_DEFAULT_STRIDE_M",
    "MIN_HIP_CLEARANCE_M",
    "MIN_STRIDE_M",
    "PRESETS",
    "ReachLayout",
    "RESERVE_DIRECTIONS",
    "SHIFT_RESERVE_M",
    "SPIN_THETA1_RESERVE",
    "THESIS_EPSILON_M",
    "Workspace",
    "_inside_feasible_run",
    "_reachable_sets",
    "feasible_height_range",
    "foot_levels",
    "is_mammal",
    "joint_values_of_legs",
    "planning_robot",
    "reach_layout",
    "reachable_in_limits",
    "reachable_in_limits_of_legs",
    "stride_at",
    "walks_any_direction",
    "workspace_for",
]


@dataclass(frozen=True, eq=False)
class Workspace:
    """Workspace, stride and footholds of one robot at one body height.

    Attributes:
        preset: "default" or "thesis".
        height: body CoG height h above ground [m].
        hip_clearance_m: hip-yaw axis height above ground, h + hip z in base [m].
        reach_m: horizontal foot distance ρ from the hip axis in the reference pose [m].
        stride_m: λ along the body x axis (forward) [m].
        stride_lateral_m: λ along the body y axis [m].
        swing_height_m: h_max of eq 5.12 [m].
        position_hip_in_base: hips [m], shape (4, 3), legs LF, RF, LH, RH.
        extent_m: rectangle extents (e_x, e_y) per leg [m], shape (4, 2).
        position_mid_in_base: position 2 (rectangle centre, on the ground) [m], shape (4, 3).
        psi_max_rad: largest spin angle per spinning-gait cycle [rad].
        stability_threshold_m: default minimum S_m on every lift [m].
        half_cycles: whether the path follower may end on half a creeping cycle.
    """

    preset: str
    height: float
    hip_clearance_m: float
    reach_m: float
    stride_m: float
    stride_lateral_m: float
    swing_height_m: float
    position_hip_in_base: np.ndarray
    extent_m: np.ndarray
    position_mid_in_base: np.ndarray
    psi_max_rad: float
    stability_threshold_m: float
    half_cycles: bool

    def stride_along(self, direction: np.ndarray) -> float:
        """λ along a body axis direction (unit (2,) or (3,)) [m]."""
        d = np.abs(np.asarray(direction, float)[:2])
        return float(np.min(self.extent_m @ d))

    def to_dict(self) -> dict[str, object]:
        """JSON-able summary."""
        return {
            "preset": self.preset,
            "height_m": self.height,
            "stride_m": self.stride_m,
            "stride_lateral_m": self.stride_lateral_m,
            "swing_height_m": self.swing_height_m,
            "reach_m": self.reach_m,
            "psi_max_deg": float(np.rad2deg(self.psi_max_rad)),
            "stability_threshold_m": self.stability_threshold_m,
            "position_mid_in_base": self.position_mid_in_base.tolist(),
        }


def is_mammal(robot) -> bool:
    """Whether the robot's legs have no hip yaw (the mammal family; silo4kin.leg_family)."""
    return not workspace_family(robot).leg_family.has_hip_yaw


@dataclass(frozen=True, eq=False)
class ReachLayout:
    """What the default workspace sees at one body height, feasible or not (for
    ``silo4 workspace``).

    Attributes:
        sets: each leg's reachable ground set (LF, RF, LH, RH), intersected over the ground,
            half and full swing height.
        erosion_m: the stability-shift reserve the footholds keep from the sets' edges [m].
        position_mid_in_base: position 2 of each leg [m], shape (4, 3).
        stride_m: (λ_x, λ_y) [m].
        min_stride_m: the default workspace's shortest stride [m].
        psi_max_rad: spin per spinning-gait cycle [rad] (0 without a stride).
        min_spin_rad: the default workspace's smallest spin per cycle [rad].
        hip_clearance_m: hip-yaw axis height above the ground [m].
        min_hip_clearance_m: the default workspace's smallest hip clearance [m].
        feasible_range: the default workspace's feasible heights (lo, hi) [m], or None.
    """

    sets: tuple[ReachableSet | MammalReachableSet, ...]
    erosion_m: float
    position_mid_in_base: np.ndarray
    stride_m: tuple[float, float]
    min_stride_m: float
    psi_max_rad: float
    min_spin_rad: float
    hip_clearance_m: float
    min_hip_clearance_m: float
    feasible_range: tuple[float, float] | None


def reach_layout(robot, height: float) -> ReachLayout:
    """The :class:`ReachLayout` of the default workspace at body height ``height`` [m]."""
    robot = planning_robot(robot)
    lz = hip_depth_m(robot)
    levels = foot_levels(robot, float(height))
    _, mid, lam = foothold_layout(robot, float(height), "default")
    try:
        rng: tuple[float, float] | None = feasible_height_range(robot, "default")
    except PlannerInputError:
        rng = None
    return ReachLayout(
        sets=tuple(_reachable_sets(robot, levels)),
        erosion_m=SHIFT_RESERVE_M,
        position_mid_in_base=mid,
        stride_m=(float(lam[0]), float(lam[1])),
        min_stride_m=MIN_DEFAULT_STRIDE_M,
        psi_max_rad=float(default_psi_max(robot, float(height))) if lam[0] > 0 else 0.0,
        min_spin_rad=float(MIN_DEFAULT_SPIN_RAD),
        hip_clearance_m=float(height - lz),
        min_hip_clearance_m=MIN_DEFAULT_HIP_CLEARANCE_M,
        feasible_range=rng,
    )


def workspace_for(robot, height: float, preset: str = "default") -> Workspace:
    """Workspace, stride and footholds at body height ``height`` [m].

    Raises:
        PlannerInputError: unknown preset, non-finite height, or height outside
            :func:`feasible_height_range` (the message names the range).
    """
    check_preset(preset, robot)
    if not np.isfinite(height):
        raise PlannerInputError(f"height must be a finite number of metres, got {height!r}")
    return _workspace(planning_robot(robot), float(height), preset)


@cached_on_first_argument(256)
def _workspace(robot, height: float, preset: str) -> Workspace:
    """workspace_for's result, built once per (planning robot, height, preset): plan_path,
    its input check and the ditch's route search ask for the same workspaces hundreds of
    times. Its arrays are read-only, since every caller shares them."""
    check_height(robot, height, preset)
    lz = hip_depth_m(robot)
    rho, mid, lam = foothold_layout(robot, height, preset)
    extent = np.tile(lam, (4, 1))
    hips = np.array([leg.position_hip_in_base for leg in robot.legs], dtype=float)
    hip_clear = height - lz
    square = footholds_of(preset) is FootholdRule.THESIS_SQUARE
    ws = Workspace(
        preset=preset,
        height=float(height),
        hip_clearance_m=float(hip_clear),
        reach_m=rho,
        stride_m=float(extent[:, 0].min()),
        stride_lateral_m=float(extent[:, 1].min()),
        swing_height_m=float(hip_clear / 2.0),
        position_hip_in_base=hips,
        extent_m=extent,
        position_mid_in_base=mid,
        psi_max_rad=(
            psi_max(robot, mid, 0.0, 0.0) if square else default_psi_max(robot, float(height))
        ),
        stability_threshold_m=0.0 if square else DEFAULT_STABILITY_THRESHOLD_M,
        half_cycles=not square,
    )
    for array in (ws.position_hip_in_base, ws.extent_m, ws.position_mid_in_base):
        array.setflags(write=False)
    return ws
