"""Leg workspace, stride and footholds for a body height (thesis §4.2.1, Fig 4.7-4.8).

Two presets. ``default`` plans inside each leg's reachable ground set within its joint limits
(issue 9; planner/workspace/reach_insect.py computes the set from FK, planner/workspace/footholds.py chooses position 2
and the strides λ_x, λ_y inside it, with the stability, interference and IK checks of
:func:`_layout`). ``thesis`` keeps the thesis's square workspace, described here:

Square workspace (thesis §4.2.1, read as in thesis-notes.md "Footholds"): each leg's simplified
workspace is the square spanned in the base frame from its hip-yaw axis to the foot of a
reference pose with θ1 = 0 (the leg along its rest direction θb), ρ the horizontal distance of
that foot from the hip axis. For SILO4's diagonal legs (θb = ±45°, ±135°) the square has side
ρ/√2 and its centre, position 2, is the mid-point of the rest ray. For any rest direction
(e.g. legs pointing sideways, tests/robots/mantis.urdf) we keep that centre, hip + (ρ/2) u(θb),
and take the largest axis-aligned square around it whose corners stay within the horizontal
reach ρ: side e = ρ (√(k²/4 + 3/2) - k/2), k = |cos θb| + |sin θb|, which is ρ/√2 at 45°
(the thesis's square) and 0.82 ρ for a sideways leg. For travel along a body axis d, the three
footholds of a leg lie on the square's mid-line across d, at its far end, middle and near end
along d (positions 1, 2, 3; a leg behind the CoG is mirrored). The stride is λ = e (the
smallest over the legs).

The thesis preset's reference pose:
    thesis   The rule behind the Chapter 6 strides (thesis-notes.md): hip height above ground
             hh = h - Lz - ε, ε = 1e-4 m; if hh <= L3 then θ2 = 0, θ3 = -asin(hh/L3), else the
             leg is stretched (θ3 = 0, singular) with θ2 = -asin(hh/(L2+L3)). The stride is
             ρ|cos θb| = x_max - x_hip (the thesis subtracts a rounded 0.155 m for x_hip;
             we subtract the robot's hip coordinate, 0.56 mm more). Stability threshold 0
             (the thesis accepts the CoG on a support edge).

One height range: :func:`feasible_height_range` and :func:`workspace_for` take the robot as
loaded (URDF root) or in the planning frame (:func:`planning_robot`), and plan_path and
``silo4 plan`` call them, so every caller refuses the same heights.

Swing height (eq 5.12): h_max = (z_hip - z_ground)/2, half the hip height above ground.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import NamedTuple

import numpy as np

import planner.workspace.reach_mammal as reach_mammal
from planner.errors import PlannerInputError
from planner.gaits.steps import SHIFT_EXTRA_M
from planner.workspace.footholds import CRAB_ROOM_RAD, choose_centres, stable_stride
from planner.workspace.interference import LEG_CLEARANCE_M
from planner.workspace.reach_insect import reachable_set
from silo4kin.discovery import legs_in_body_com_frame
from silo4kin.foot_contact import foot_contact_offset_m
from silo4kin.geometry import LegGeometry
from silo4kin.kinematics import IK_COS_SLACK
from silo4kin.legs import inverse_kinematics

PRESETS: tuple[str, ...] = ("default", "thesis")
#: ε of the thesis stride rule [m] (thesis-notes.md: reproduces 0.3787 / 0.3328 / 0.1613).
THESIS_EPSILON_M = 1e-4
#: Knee margin of the default reference pose from θ3 = 0 [rad]: 20° keeps |det J| at
#: sin 20° = 34 % of its largest value at the corner of the workspace square.
DEFAULT_KNEE_MARGIN = np.deg2rad(20.0)
#: Lowest hip height above ground [m]: eq 5.12 then lifts the swing foot 1 cm.
MIN_HIP_CLEARANCE_M = 0.02
#: Lowest hip height above ground of the default preset [m]: eq 5.12 then lifts the swing
#: foot 2.5 cm, and below it the reachable set near the hip is too thin for the stability
#: shifts (tests/robots/mantis.urdf left its hip-pitch limit at 2-4.5 cm).
MIN_DEFAULT_HIP_CLEARANCE_M = 0.05
#: Smallest spin angle per cycle the default preset accepts [rad]: a robot that cannot turn
#: cannot follow a path (planner/path/plan_path.py); 2° is ~45 cycles for a quarter turn.
MIN_DEFAULT_SPIN_RAD = np.deg2rad(2.0)
#: Shortest stride the default preset accepts [m]; sets its upper height limit.
MIN_DEFAULT_STRIDE_M = 0.10
#: Shortest stride the thesis preset accepts [m] (1 cm: a stride at all).
MIN_STRIDE_M = 0.01
#: Default stability threshold of the default preset [m] (every lift keeps S_m >= this).
DEFAULT_STABILITY_THRESHOLD_M = 0.02
#: Reserve on the θ1 limits when sizing the default preset's spin angle per cycle [rad]:
#: room for the CoG shifts that keep the margin positive during the spin (a 5 cm shift seen
#: from a foot 0.3 m from its hip is ~10°). The thesis preset makes no shifts: no reserve.
SPIN_THETA1_RESERVE = np.deg2rad(10.0)
#: Room position 2 keeps from both hip-yaw limits in the default workspace [rad]: the θ1
#: reserve of the spin plus as much again for the spin angle itself.
CENTRE_YAW_RESERVE = 2.0 * SPIN_THETA1_RESERVE
#: The default preset keeps every foothold reachable with the body displaced this far in any
#: of 8 directions [m]: room for the stability shifts (threshold + 5 mm from a zero margin
#: needs ~3 cm).
SHIFT_RESERVE_M = 0.05
#: The 8 unit directions of that displacement, shape (8, 3).
RESERVE_DIRECTIONS = np.array([[np.cos(a), np.sin(a), 0.0]
                               for a in np.linspace(0, 2 * np.pi, 8, endpoint=False)])
#: Extra room over LEG_CLEARANCE_M kept between neighbouring footholds when sizing the
#: default stride [m] (crab angles and spin stances move the feet a little off the axis).
INTERFERENCE_SLACK_M = 0.02
#: Height grid of feasible_height_range for mammal legs [m]: their reachable sets are grid
#: masks (planner/workspace/reach_mammal.py), 2 cm keeps the search to a few seconds; the ends are
#: bisected to 0.1 mm as for insect legs.
MAMMAL_HEIGHT_GRID_M = 0.02
#: Slack when checking joint limits [rad].
JOINT_LIMIT_TOLERANCE = 1e-9
#: Extra erosions [m] tried in turn when the closed-form IK refuses the footholds chosen in
#: the sampled reachable sets (_layout).
CENTRE_RETRY_EROSION_M = (0.0, 0.005, 0.01, 0.02)


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
            "preset": self.preset, "height_m": self.height, "stride_m": self.stride_m,
            "stride_lateral_m": self.stride_lateral_m, "swing_height_m": self.swing_height_m,
            "reach_m": self.reach_m, "psi_max_deg": float(np.rad2deg(self.psi_max_rad)),
            "stability_threshold_m": self.stability_threshold_m,
            "position_mid_in_base": self.position_mid_in_base.tolist(),
        }


_PLANNING_ROBOTS: weakref.WeakSet = weakref.WeakSet()


@lru_cache(maxsize=16)
def _shifted(robot):
    com = np.asarray(robot.position_body_com_in_base, dtype=float)
    shifted = replace(robot, legs=legs_in_body_com_frame(robot.legs, com)) if np.any(com) \
        else robot
    _PLANNING_ROBOTS.add(shifted)
    return shifted


def planning_robot(robot):
    """The robot with its hips measured from the body CoG, the frame B the planner works in
    (design.md). For SILO4 the URDF root is the CoG and the robot is returned unchanged; for
    another URDF (tests/robots/mantis.urdf: CoG 4.5 cm ahead of and 4.2 cm above the root)
    only ``LegGeometry.position_hip_in_base`` moves, joint values are unaffected.

    Idempotent: a robot this function returned is returned as it is, so every public
    function of the planner can take either and they all mean the same heights (issue 9:
    feasible_height_range and plan_path used to disagree by the root-to-CoG offset). Cached
    per robot object, so the workspace caches keyed on it stay warm across plans."""
    if robot in _PLANNING_ROBOTS:
        return robot
    return _shifted(robot)


def _leg_params(robot) -> tuple[float, float, float, float]:
    """(Lz, L1, L2, L3) [m]: the hip axis depth below the CoG and the link lengths. A mammal
    leg (silo4kin.mammal) gives its HAA point's depth and (0, 0, size_m): L2 + L3 is only
    read as the longest reach below the hip."""
    leg = robot.legs[0]
    if is_mammal(robot):
        return -float(leg.position_hip_in_base[2]), 0.0, 0.0, float(leg.size_m)
    return -leg.hip_height, leg.L1, leg.L2, leg.L3


def is_mammal(robot) -> bool:
    """Whether the robot's legs are of the mammal family (hip ab/adduction first)."""
    return bool(robot.legs) and getattr(robot.legs[0], "family", "insect") == "mammal"


def foot_levels(robot, height: float) -> tuple[float, float, float]:
    """Foot-frame heights in B [m] at the ground, half and full swing height at body height
    ``height`` [m]: the ground is foot_contact_offset_m below a standing foot frame
    (silo4kin/foot_contact.py; 0 for point feet, so -height for SILO4)."""
    ground = -height + foot_contact_offset_m(robot)
    swing = (height - _leg_params(robot)[0]) / 2.0
    return (ground, ground + swing / 2.0, ground + swing)


def _reachable_sets(robot, levels: tuple[float, ...]) -> tuple:
    """Each leg's reachable ground set at the foot heights ``levels`` [m] in B, of its family
    (planner/workspace/reach_insect.py, planner/workspace/reach_mammal.py)."""
    if is_mammal(robot):
        return tuple(reach_mammal.reachable_set(leg, levels, DEFAULT_KNEE_MARGIN)
                     for leg in robot.legs)
    return tuple(reachable_set(leg, levels, DEFAULT_KNEE_MARGIN) for leg in robot.legs)


def _thesis_reach(robot, height: float) -> float:
    """ρ of the thesis preset's reference pose [m] (module docstring)."""
    lz, l1, l2, l3 = _leg_params(robot)
    hh = height - lz - THESIS_EPSILON_M
    if hh <= l3:
        t2, t3 = 0.0, -np.arcsin(hh / l3)
    else:
        t2, t3 = -np.arcsin(min(hh / (l2 + l3), 1.0)), 0.0
    return float(l1 + l2 * np.cos(t2) + l3 * np.cos(t2 + t3))


def _extents(robot, rho: float) -> np.ndarray:
    """Square sides (e, e) per leg [m], shape (4, 2) (module docstring)."""
    tb = np.array([leg.theta_b for leg in robot.legs])
    k = np.abs(np.cos(tb)) + np.abs(np.sin(tb))
    side = rho * (np.sqrt(k * k / 4.0 + 1.5) - k / 2.0)
    return np.stack([side, side], axis=1)


def _mid_in_base(robot, rho: float, height: float) -> np.ndarray:
    """Position 2 of every leg: the mid-point of its rest ray, on the ground, (4, 3) [m]."""
    mid = np.empty((4, 3))
    for k, leg in enumerate(robot.legs):
        mid[k, :2] = leg.position_hip_in_base[:2] + 0.5 * rho * np.array(
            [np.cos(leg.theta_b), np.sin(leg.theta_b)])
    mid[:, 2] = -height
    return mid


def _footholds_ok(robot, height: float, preset: str, mid: np.ndarray,
                  extent: tuple[float, float]) -> bool:
    """All creeping footholds (positions 1-3 along ±x with λ_x = extent[0], ±y with
    λ_y = extent[1]), on the ground and lifted by the swing height, reachable within limits
    by the closed-form IK; for the default preset also with the body displaced by
    SHIFT_RESERVE_M in 8 directions."""
    swing = (height - _leg_params(robot)[0]) / 2.0          # h_max of eq 5.12 [m]
    ex, ey = extent
    # the footholds on the ground, and lifted by the swing height (the swing apex passes
    # over position 2; the lifted rear/front footholds bound the rest of the swing arc)
    offsets = np.array([[sx * ex / 2, sy * ey / 2, dz]
                        for sx, sy in ((1, 0), (-1, 0), (0, 1), (0, -1), (0, 0))
                        for dz in (0.0, swing)])
    pts = np.asarray(mid, dtype=float)[:, None, :] + offsets[None]           # (legs, 10, 3)
    if preset == "default":
        pts = pts[:, :, None, :] + SHIFT_RESERVE_M * RESERVE_DIRECTIONS[None, None]
    pts = pts.reshape(len(robot.legs), -1, 3)
    idx = np.repeat(np.arange(len(robot.legs)), pts.shape[1])
    return bool(np.all(reachable_in_limits_of_legs(robot.legs, idx, pts.reshape(-1, 3))))


def _shrink_to_reach(robot, height: float, preset: str, mid: np.ndarray,
                     extent: tuple[float, float]) -> float:
    """Largest factor f in [0, 1] with the footholds of extents f·extent reachable
    (_footholds_ok, bisection); 1 when they all are."""
    if _footholds_ok(robot, height, preset, mid, extent):
        return 1.0
    lo, hi = 0.0, 1.0
    for _ in range(30):
        m = 0.5 * (lo + hi)
        lo, hi = (m, hi) if _footholds_ok(robot, height, preset, mid,
                                          (m * extent[0], m * extent[1])) else (lo, m)
    return lo


@lru_cache(maxsize=512)
def _layout(robot, height: float, preset: str) -> tuple[float, np.ndarray, np.ndarray]:
    """(ρ [m], position 2 of every leg (4, 3) [m], extents (λ_x, λ_y) (2,) [m]) at a height.

    thesis: the square of the module docstring, λ its side, shortened (by bisection) only if
    some foothold is out of reach or limits (SILO4's all fit; a robot whose legs point
    sideways, tests/robots/mantis.urdf, has its near-hip footholds cut back).
    default: footholds inside the reachable sets (planner/workspace/reach_insect.py, planner/workspace/footholds.py):
    the sets at the ground, half and full swing height, knee margin DEFAULT_KNEE_MARGIN,
    eroded by SHIFT_RESERVE_M; strides shortened until the creeping gait keeps the
    stability threshold (footholds.stable_stride), then checked by IK (_footholds_ok).
    ρ is the reference pose's reach (thesis) or the largest ground reach r_max (default).
    """
    if preset == "thesis":
        rho = _thesis_reach(robot, height)
        lam = float(_extents(robot, rho).min())
        mid = _mid_in_base(robot, rho, height)
        lam *= _shrink_to_reach(robot, height, preset, mid, (lam, lam))
        return rho, mid, np.array([lam, lam])
    levels = foot_levels(robot, height)
    sets = _reachable_sets(robot, levels)
    rest_y = (np.array([reach_mammal.rest_lateral_in_base(leg) for leg in robot.legs])
              if is_mammal(robot) else None)
    hips = np.array([leg.position_hip_in_base for leg in robot.legs], dtype=float)
    # The sets are sampled (reach.py) and the closed-form IK has the last word
    # (_footholds_ok): where a centre sits on the sampled boundary, IK may refuse even a zero
    # stride (seen at one height of an L3 = 0.3 m variant). Then the centres are chosen
    # again from the sets eroded by a little more, instead of calling the height infeasible.
    best: tuple[np.ndarray, np.ndarray] = (np.zeros((4, 3)), np.zeros(2) - 1.0)
    for extra_erosion in CENTRE_RETRY_EROSION_M:
        if rest_y is not None:
            centres, extents = reach_mammal.choose_centres(
                sets, SHIFT_RESERVE_M + extra_erosion, CRAB_ROOM_RAD, rest_y)
        else:
            centres, extents = choose_centres(sets, SHIFT_RESERVE_M + extra_erosion,
                                              CENTRE_YAW_RESERVE)
        mid = np.column_stack([centres, np.full(4, levels[0])])
        lam = np.array([extents[:, 0].min(), extents[:, 1].min()])
        for axis, dirs in ((0, np.array([[1.0, 0.0], [-1.0, 0.0]])),
                           (1, np.array([[0.0, 1.0], [0.0, -1.0]]))):
            lam[axis] = stable_stride(hips, mid, float(lam[axis]), dirs,
                                      DEFAULT_STABILITY_THRESHOLD_M + SHIFT_EXTRA_M)
        lam = np.minimum(lam, _interference_caps(mid))
        lam = np.clip(lam, 0.0, None)
        lam *= _shrink_to_reach(robot, height, preset, mid, (float(lam[0]), float(lam[1])))
        if lam[0] > best[1][0]:
            best = (mid, lam)
        if lam[0] >= MIN_DEFAULT_STRIDE_M:
            break
    mid, lam = best
    rho = float(max(s.radius_upper_m for s in sets)) if sets else 0.0
    return rho, mid, lam


def reach_layout(robot, height: float) -> dict[str, object]:
    """What the default workspace sees at any body height ``height`` [m], feasible or not (for
    ``silo4 workspace``): "sets" (each leg's ReachableSet at the ground, half and full swing
    height), "erosion_m" (the shift reserve), "position_mid_in_base" (4, 3) [m],
    "stride_m" (λ_x, λ_y) [m], "min_stride_m", "psi_max_rad" and "min_spin_rad" (spin per
    cycle), "hip_clearance_m" and "min_hip_clearance_m", "feasible_range" (the default's)."""
    robot = planning_robot(robot)
    lz = _leg_params(robot)[0]
    levels = foot_levels(robot, float(height))
    _, mid, lam = _layout(robot, float(height), "default")
    try:
        rng: tuple[float, float] | None = feasible_height_range(robot, "default")
    except PlannerInputError:
        rng = None
    return {"sets": _reachable_sets(robot, levels),
            "erosion_m": SHIFT_RESERVE_M, "position_mid_in_base": mid,
            "stride_m": (float(lam[0]), float(lam[1])), "min_stride_m": MIN_DEFAULT_STRIDE_M,
            "psi_max_rad": _default_psi_max(robot, float(height)) if lam[0] > 0 else 0.0,
            "min_spin_rad": float(MIN_DEFAULT_SPIN_RAD), "hip_clearance_m": float(height - lz),
            "min_hip_clearance_m": MIN_DEFAULT_HIP_CLEARANCE_M, "feasible_range": rng}


def _interference_caps(mid: np.ndarray) -> np.ndarray:
    """Longest (λ_x, λ_y) [m] keeping neighbouring feet LEG_CLEARANCE_M + INTERFERENCE_SLACK_M
    apart (thesis §3.6, planner/workspace/interference.py): in the creeping gait a leg can stand at its
    front foothold while its neighbour along the travel direction is still at its rear one,
    λ closer than their positions 2 (the same pair swings one after the other)."""
    gap = LEG_CLEARANCE_M + INTERFERENCE_SLACK_M
    caps = []
    for axis, pairs in ((0, ((0, 2), (1, 3))), (1, ((0, 1), (2, 3)))):
        caps.append(min(abs(mid[a, axis] - mid[b, axis]) for a, b in pairs) - gap)
    return np.array(caps)


def _stride(robot, height: float, preset: str) -> float:
    """λ along the body x axis at a height [m] (the path follower's stride)."""
    return float(_layout(robot, height, preset)[2][0])


def stride_at(robot, height: float, preset: str = "default") -> float:
    """``workspace_for(robot, height, preset).stride_m`` [m] (the same checks and value)
    without the rest of the Workspace: its spin angle ψ_max alone is a bisection of ~200 IK
    calls, and a scan of λ(h) over hundreds of heights (thesis_consistency.stride_jump)
    needs only λ.

    Raises:
        PlannerInputError: as :func:`workspace_for`.
    """
    _check_preset(preset, robot)
    if not np.isfinite(height):
        raise PlannerInputError(f"height must be a finite number of metres, got {height!r}")
    robot = planning_robot(robot)
    _check_height(robot, float(height), preset)
    return _stride(robot, float(height), preset)


@lru_cache(maxsize=32)
def feasible_height_range(robot, preset: str = "default") -> tuple[float, float]:
    """(min, max) body height the preset plans for [m], rounded inwards to 0.1 mm.

    The one range every planner entry point uses (``robot`` as loaded or in the planning
    frame). thesis: hips at least MIN_HIP_CLEARANCE_M above the ground (eq 5.12 lifts a foot
    1 cm; the thesis's 0.15 m puts SILO4's hips on the ground) and a stride of at least
    MIN_STRIDE_M with every creeping foothold reachable (SILO4: up to 0.63 m, legs vertical).
    default: hips at least MIN_DEFAULT_HIP_CLEARANCE_M up, a stride of at least
    MIN_DEFAULT_STRIDE_M inside the reachable sets with the creeping lifts stable, the
    neighbouring feet apart and every foothold reachable (_layout), and a spin of at least
    MIN_DEFAULT_SPIN_RAD per cycle. The range is found on a 1 cm grid, then each end by
    bisection; the first feasible run of heights is returned (mammal legs: the longest run,
    on a MAMMAL_HEIGHT_GRID_M grid).
    """
    _check_preset(preset, robot)
    robot = planning_robot(robot)
    lowest, highest, grid = _height_grid(robot, preset)
    min_stride = MIN_DEFAULT_STRIDE_M if preset == "default" else MIN_STRIDE_M

    def ok(h: float) -> bool:
        return _height_ok(robot, h, preset)

    mammal = is_mammal(robot)
    feasible = np.zeros(grid.size, dtype=bool)
    for k, h in enumerate(grid):
        feasible[k] = ok(float(h))
        if not mammal and k > 0 and feasible[k - 1] and not feasible[k]:
            break               # the first run has ended: the rest of the grid is not read
    if not feasible.any():
        raise PlannerInputError(
            f"robot {robot.name!r}: no body height gives a stride of {min_stride} m or more "
            f"with the {preset!r} workspace (footholds out of reach or joint limits)")
    first = int(np.argmax(feasible))
    last = first + int(np.argmin(np.append(feasible[first:], False))) - 1
    if mammal:                   # the longest run: a folded mammal leg may plan a sliver low
        runs = np.flatnonzero(np.diff(np.concatenate([[0], feasible.astype(int), [0]])))
        starts, ends = runs[::2], runs[1::2] - 1
        k = int(np.argmax(ends - starts))
        first, last = int(starts[k]), int(ends[k])

    def edge(good: float, bad: float) -> float:
        for _ in range(11 if mammal else 10):  # 1 cm / 2^10 < 0.1 mm, the rounding
            m = 0.5 * (good + bad)
            good, bad = (m, bad) if ok(m) else (good, m)
        return good

    lo = lowest if first == 0 else edge(float(grid[first]), float(grid[first - 1]))
    hi = edge(float(grid[last]), float(grid[last + 1]) if last + 1 < grid.size else highest)
    return (float(np.ceil(round(lo * 1e4, 6)) / 1e4), float(np.floor(round(hi * 1e4, 6)) / 1e4))


def _height_grid(robot, preset: str) -> tuple[float, float, np.ndarray]:
    """(lowest [m], highest [m], the grid of heights [m]) :func:`feasible_height_range` scans
    (``robot`` in the planning frame)."""
    lz, _, l2, l3 = _leg_params(robot)
    clearance = MIN_DEFAULT_HIP_CLEARANCE_M if preset == "default" else MIN_HIP_CLEARANCE_M
    lowest = float(np.ceil(round((lz + clearance) * 1e4, 6)) / 1e4)
    highest = lz + l2 + l3
    return lowest, highest, np.arange(lowest, highest,
                                      MAMMAL_HEIGHT_GRID_M if is_mammal(robot) else 0.01)


def _height_ok(robot, height: float, preset: str) -> bool:
    """Whether the preset plans at ``height`` [m]: the stride condition and (default) the
    spin condition of :func:`feasible_height_range`."""
    min_stride = MIN_DEFAULT_STRIDE_M if preset == "default" else MIN_STRIDE_M
    if _stride(robot, height, preset) < min_stride:
        return False
    return preset == "thesis" or _default_spin_suffices(robot, height)


def _inside_feasible_run(robot, height: float, preset: str) -> bool:
    """True only if ``height`` [m] is inside :func:`feasible_height_range`, found without the
    whole range: insect legs, the grid's first height feasible (then the range starts
    there), and every grid height from it up to the first one at or above ``height``
    feasible (then the first run, and the range, reach at least that far; compared after
    the range's own rounding to 0.1 mm). False means "ask feasible_height_range" (issue 14:
    `silo4 cases` scanned SILO4's whole range, ~50 workspace layouts, for heights whose
    answer the first 11-21 give)."""
    if is_mammal(robot):
        return False          # the range is the longest run, not the first
    lowest, _, grid = _height_grid(robot, preset)
    if not (grid.size and lowest <= height):
        return False
    for h in grid:
        if not _height_ok(robot, float(h), preset):
            return False
        if float(np.floor(round(float(h) * 1e4, 6)) / 1e4) >= height:
            return True
    return False


def _check_height(robot, height: float, preset: str) -> None:
    """Refuse a height outside :func:`feasible_height_range` (the message names the range)."""
    if _inside_feasible_run(robot, height, preset):
        return
    lo, hi = feasible_height_range(robot, preset)
    if not lo <= height <= hi:
        raise PlannerInputError(
            f"height {height:.4g} m is outside the feasible range [{lo:.4g}, {hi:.4g}] m of "
            f"the {preset!r} workspace for robot {robot.name!r}")


def _check_preset(preset: str, robot=None) -> None:
    if preset not in PRESETS:
        raise PlannerInputError(f"unknown workspace preset {preset!r}; choose one of {PRESETS}")
    if preset == "thesis" and robot is not None and is_mammal(robot):
        raise PlannerInputError(
            f"robot {robot.name!r} has mammal legs: the 'thesis' workspace is the thesis's "
            "square from a hip-yaw reference pose, which a leg without a vertical first axis "
            "does not have; use the 'default' workspace (reachable sets)")


def reachable_in_limits(leg: LegGeometry, position_foot_in_base: np.ndarray,
                        theta1_reserve: float = 0.0) -> np.ndarray:
    """Whether IK reaches each target (N, 3) [m] within the joint limits; (N,) bool.

    theta1_reserve [rad] narrows the hip-yaw range on both sides.
    Either leg family (silo4kin.legs: insect knee-down, mammal the rest pose's branch).
    """
    res = inverse_kinematics(leg, np.atleast_2d(np.asarray(position_foot_in_base, float)))
    q = np.where(np.isfinite(res.q), res.q, 0.0)
    lo = leg.q_lower - JOINT_LIMIT_TOLERANCE + np.array([theta1_reserve, 0.0, 0.0])
    hi = leg.q_upper + JOINT_LIMIT_TOLERANCE - np.array([theta1_reserve, 0.0, 0.0])
    return res.reachable & np.all((q >= lo) & (q <= hi), axis=1)


class _InsectLegTable(NamedTuple):
    """Per-leg constants of :func:`reachable_in_limits_of_legs`, one row per leg, each the
    same Python value silo4kin.kinematics.inverse_kinematics_masked computes from its leg."""

    legs: tuple                # the LegGeometry objects (kept alive: the cache key is ids)
    hip: np.ndarray            # (L, 3) position_hip_in_base [m]
    theta_b: np.ndarray        # (L,) [rad]
    l1: np.ndarray             # (L,) [m]
    l2: np.ndarray             # (L,) L2 [m]
    l3: np.ndarray             # (L,) L3 [m]
    l2_sq: np.ndarray          # (L,) L2**2 [m²]
    l3_sq: np.ndarray          # (L,) L3**2 [m²]
    two_l2_l3: np.ndarray      # (L,) 2.0 * L2 * L3 [m²]
    zero_offset: np.ndarray    # (L, 3) [rad]
    axis_sign: np.ndarray      # (L, 3)
    q_lower: np.ndarray        # (L, 3) [rad]
    q_upper: np.ndarray        # (L, 3) [rad]


_LEG_TABLES: dict[tuple[int, ...], _InsectLegTable] = {}


def _insect_leg_table(legs: tuple) -> _InsectLegTable:
    key = tuple(id(leg) for leg in legs)
    table = _LEG_TABLES.get(key)
    if table is None:
        if len(_LEG_TABLES) > 64:
            _LEG_TABLES.clear()
        table = _LEG_TABLES[key] = _InsectLegTable(
            legs=tuple(legs),
            hip=np.array([leg.position_hip_in_base for leg in legs], dtype=float),
            theta_b=np.array([leg.theta_b for leg in legs], dtype=float),
            l1=np.array([leg.L1 for leg in legs], dtype=float),
            l2=np.array([leg.L2 for leg in legs], dtype=float),
            l3=np.array([leg.L3 for leg in legs], dtype=float),
            l2_sq=np.array([leg.L2**2 for leg in legs], dtype=float),
            l3_sq=np.array([leg.L3**2 for leg in legs], dtype=float),
            two_l2_l3=np.array([2.0 * leg.L2 * leg.L3 for leg in legs], dtype=float),
            zero_offset=np.array([leg.zero_offset for leg in legs], dtype=float),
            axis_sign=np.array([leg.axis_sign for leg in legs], dtype=float),
            q_lower=np.array([leg.q_lower for leg in legs], dtype=float),
            q_upper=np.array([leg.q_upper for leg in legs], dtype=float))
    return table


def reachable_in_limits_of_legs(legs, leg_index: np.ndarray, position_foot_in_base: np.ndarray,
                                theta1_reserve: float = 0.0) -> np.ndarray:
    """:func:`reachable_in_limits` of target i (N, 3) [m] for leg ``legs[leg_index[i]]``, for
    all legs in one vectorised pass, (N,) bool: the same values, bit for bit
    (tests/test_workspace.py), at a fraction of the cost of one call per leg (issue 14:
    these checks are the inner loop of the omnidirectional gait and of ψ_max's bisection).
    Insect legs: the knee-down IK of silo4kin.kinematics.inverse_kinematics_masked with
    per-row constants; other families: one reachable_in_limits call per leg."""
    idx = np.asarray(leg_index, dtype=np.intp)
    p = np.asarray(position_foot_in_base, dtype=float).reshape(-1, 3)
    return _reachable_of_legs(tuple(legs), idx, p, float(theta1_reserve))


def _reachable_of_legs(legs: tuple, idx: np.ndarray, p: np.ndarray, theta1_reserve: float
                       ) -> np.ndarray:
    """reachable_in_limits_of_legs on checked arrays."""
    if any(getattr(leg, "family", "insect") != "insect" for leg in legs):
        out = np.zeros(len(p), dtype=bool)
        for k, leg in enumerate(legs):
            rows = np.flatnonzero(idx == k)
            if rows.size:
                out[rows] = reachable_in_limits(leg, p[rows], theta1_reserve)
        return out
    c = _insect_leg_table(legs)
    q, reachable = _insect_joint_values(c, idx, p)
    q = np.where(np.isfinite(q), q, 0.0)
    reserve = np.array([theta1_reserve, 0.0, 0.0])
    lo = (c.q_lower - JOINT_LIMIT_TOLERANCE + reserve)[idx]
    hi = (c.q_upper + JOINT_LIMIT_TOLERANCE - reserve)[idx]
    return reachable & np.all((q >= lo) & (q <= hi), axis=1)


def joint_values_of_legs(legs, leg_index: np.ndarray, position_foot_in_base: np.ndarray
                         ) -> tuple[np.ndarray, np.ndarray]:
    """(q (N, 3) [rad], NaN where out of reach; reachable (N,) bool): the IK of target i
    for leg ``legs[leg_index[i]]``, all insect legs in one pass: the values of
    silo4kin.kinematics.inverse_kinematics_masked per leg, bit for bit
    (tests/test_perf_caches.py). Legs of other families: their IK leg by leg."""
    idx = np.asarray(leg_index, dtype=np.intp)
    p = np.asarray(position_foot_in_base, dtype=float).reshape(-1, 3)
    legs = tuple(legs)
    if any(getattr(leg, "family", "insect") != "insect" for leg in legs):
        q, ok = np.full((len(p), 3), np.nan), np.zeros(len(p), dtype=bool)
        for k, leg in enumerate(legs):
            rows = np.flatnonzero(idx == k)
            if rows.size:
                res = inverse_kinematics(leg, p[rows])
                q[rows], ok[rows] = res.q, res.reachable
        return q, ok
    return _insect_joint_values(_insect_leg_table(legs), idx, p)


def _insect_joint_values(c: _InsectLegTable, idx: np.ndarray, p: np.ndarray
                         ) -> tuple[np.ndarray, np.ndarray]:
    """joint_values_of_legs for insect legs (the per-row constants of ``c``)."""
    rel = p - c.hip[idx]
    theta1 = np.arctan2(rel[:, 1], rel[:, 0]) - c.theta_b[idx]
    theta1 = np.arctan2(np.sin(theta1), np.cos(theta1))
    rho = np.hypot(rel[:, 0], rel[:, 1])
    r = rho - c.l1[idx]
    z = rel[:, 2]
    cos3 = (r * r + z * z - c.l2_sq[idx] - c.l3_sq[idx]) / c.two_l2_l3[idx]
    reachable = np.abs(cos3) <= 1.0 + IK_COS_SLACK
    theta3 = -np.arccos(np.clip(cos3, -1.0, 1.0))
    l2, l3 = c.l2[idx], c.l3[idx]
    theta2 = np.arctan2(z, r) - np.arctan2(l3 * np.sin(theta3), l2 + l3 * np.cos(theta3))
    theta2 = np.arctan2(np.sin(theta2), np.cos(theta2))
    theta = np.stack([theta1, theta2, theta3], axis=1)
    q = (theta - c.zero_offset[idx]) * c.axis_sign[idx]
    q[~reachable] = np.nan
    return q, reachable


def rotation_z(yaw: float) -> np.ndarray:
    """Rotation about z by ``yaw`` [rad], (3, 3) (eq 4.3 / 5.29)."""
    c, s = float(np.cos(yaw)), float(np.sin(yaw))
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _psi_max(robot, mid: np.ndarray, reserve: float, shift: float,
             starts: np.ndarray | None = None, swing_m: float = 0.0,
             decided_at: float | None = None) -> float:
    """Largest ψ <= π/2 with the spin stance rotated by ±ψ about the CoG reachable with θ1
    narrowed by ``reserve`` [rad] and the body displaced by up to ``shift`` [m]
    (thesis-notes.md: acos(Lb / |p2|) for SILO4 without reserves). With ``starts`` (4, K, 3)
    [m], the swings from those footholds to the rotated stance (straight in x, y, lifted by
    ``swing_m`` sin(πs) [m], as the default's first spin cycle from the creeping stance,
    planner/path/plan_path.py) must be reachable too: their chords pass nearer the hip.

    With ``decided_at`` [rad] the bisection stops as soon as its result is known to be
    >= decided_at or < decided_at, and returns a value on that same side (the bisection's
    probes are the same, so the answer is that of the full bisection, monotone or not)."""
    offsets = np.vstack([np.zeros(3), shift * RESERVE_DIRECTIONS])
    s = np.linspace(0.1, 0.9, 5)[:, None]

    lift_m = swing_m * np.sin(np.pi * s[:, 0])          # (5,) the chords' lift [m]
    n_legs = len(robot.legs)
    # (leg, sign) pairs in the order leg 0 +ψ, leg 0 -ψ, leg 1 +ψ, ...
    starts2 = None if starts is None else np.repeat(np.asarray(starts, float), 2, axis=0)
    per_pair = 1 if starts is None else 1 + 5 * starts2.shape[1]
    idx = np.repeat(np.arange(n_legs).repeat(2), per_pair * len(offsets))

    def ok(psi: float) -> bool:          # every leg, both signs, in one vectorised IK pass
        targets = np.array([rotation_z(sign * psi) @ mid[i]
                            for i in range(n_legs) for sign in (1.0, -1.0)])    # (2L, 3)
        if starts2 is None:
            pts = targets[:, None, :]
        else:                            # the chords from each start to the rotated foothold
            chords = starts2[:, :, None, :] + s[None, None] * (
                targets[:, None, :] - starts2)[:, :, None, :]                 # (2L, K, 5, 3)
            chords[..., 2] += lift_m
            pts = np.concatenate([targets[:, None, :],
                                  chords.reshape(len(targets), -1, 3)], axis=1)
        pts = (pts[:, :, None, :] + offsets[None, None]).reshape(-1, 3)
        return bool(np.all(reachable_in_limits_of_legs(robot.legs, idx, pts, reserve)))
    if ok(np.pi / 2):
        return float(np.pi / 2)
    lo, hi = 0.0, np.pi / 2
    for _ in range(24):                                  # π/2 / 2^24 < 1e-7 rad
        if decided_at is not None and (lo >= decided_at or hi <= decided_at):
            break       # lo only grows and the result stays below hi: its side is known
        m = 0.5 * (lo + hi)
        lo, hi = (m, hi) if ok(m) else (lo, m)
    return float(lo)


@lru_cache(maxsize=512)
def _default_psi_max(robot, height: float) -> float:
    """ψ_max of the default workspace [rad]: θ1 reserve, shift reserve, and the swings from
    the creeping footholds to the rotated stance (_psi_max). A mammal leg has no hip yaw: its
    yaw comes from HAA and the two pitches, so no θ1 reserve (the shift reserve stays)."""
    _, mid, lam, starts, reserve, swing = _default_psi_inputs(robot, height)
    return _psi_max(robot, mid, reserve, SHIFT_RESERVE_M, starts=starts, swing_m=swing)


def _default_psi_inputs(robot, height: float) -> tuple:
    """(ρ, mid, λ, starts, θ1 reserve, swing height) of :func:`_default_psi_max`."""
    rho, mid, lam = _layout(robot, height, "default")
    starts = mid[:, None, :] + np.array([[-lam[0] / 2, 0, 0], [0, 0, 0], [lam[0] / 2, 0, 0]])
    reserve = 0.0 if is_mammal(robot) else SPIN_THETA1_RESERVE    # no hip yaw to reserve
    return rho, mid, lam, starts, reserve, (height - _leg_params(robot)[0]) / 2.0


@lru_cache(maxsize=512)
def _default_spin_suffices(robot, height: float) -> bool:
    """``_default_psi_max(robot, height) >= MIN_DEFAULT_SPIN_RAD``, by a bisection that stops
    once the answer is known (feasible_height_range asks this at ~70 heights; the full ψ_max
    takes 25 IK passes, the answer mostly one)."""
    _, mid, lam, starts, reserve, swing = _default_psi_inputs(robot, height)
    return _psi_max(robot, mid, reserve, SHIFT_RESERVE_M, starts=starts, swing_m=swing,
                    decided_at=float(MIN_DEFAULT_SPIN_RAD)) >= MIN_DEFAULT_SPIN_RAD


def workspace_for(robot, height: float, preset: str = "default") -> Workspace:
    """Workspace, stride and footholds at body height ``height`` [m].

    Raises:
        PlannerInputError: unknown preset, non-finite height, or height outside
            :func:`feasible_height_range` (the message names the range).
    """
    _check_preset(preset, robot)
    if not np.isfinite(height):
        raise PlannerInputError(f"height must be a finite number of metres, got {height!r}")
    return _workspace(planning_robot(robot), float(height), preset)


@lru_cache(maxsize=256)
def _workspace(robot, height: float, preset: str) -> Workspace:
    """workspace_for's result, built once per (planning robot, height, preset): plan_path,
    its input check and the ditch's route search ask for the same workspaces hundreds of
    times. Its arrays are read-only, since every caller shares them."""
    _check_height(robot, height, preset)
    lz = _leg_params(robot)[0]
    rho, mid, lam = _layout(robot, height, preset)
    extent = np.tile(lam, (4, 1))
    hips = np.array([leg.position_hip_in_base for leg in robot.legs], dtype=float)
    hip_clear = height - lz
    ws = Workspace(
        preset=preset, height=float(height), hip_clearance_m=float(hip_clear), reach_m=rho,
        stride_m=float(extent[:, 0].min()), stride_lateral_m=float(extent[:, 1].min()),
        swing_height_m=float(hip_clear / 2.0), position_hip_in_base=hips, extent_m=extent,
        position_mid_in_base=mid,
        psi_max_rad=(_psi_max(robot, mid, 0.0, 0.0) if preset == "thesis"
                     else _default_psi_max(robot, float(height))),
        stability_threshold_m=0.0 if preset == "thesis" else DEFAULT_STABILITY_THRESHOLD_M,
        half_cycles=preset != "thesis",
    )
    for array in (ws.position_hip_in_base, ws.extent_m, ws.position_mid_in_base):
        array.setflags(write=False)
    return ws
