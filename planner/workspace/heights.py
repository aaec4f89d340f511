"""The feasible body heights of a preset, and the stride at a height.

One height range: :func:`feasible_height_range` and :func:`stride_at` take the robot as loaded
(URDF root) or in the planning frame (planner.model.planning_robot), and plan_path and
``silo4 plan`` call them (through planner.workspace.layout.workspace_for), so every caller
refuses the same heights. The grid step, the run rule and the bisections are the leg
family's (planner/workspace/families.py).
"""

from __future__ import annotations

import numpy as np

from planner.errors import PlannerInputError
from planner.model import planning_robot
from planner.presets import FootholdRule, footholds_of, preset_for
from planner.trajectory.clearance import MIN_GROUND_CLEARANCE_M, clearance_of_poses
from planner.workspace.families import workspace_family
from planner.workspace.foothold_layout import (
    DEFAULT_STABILITY_THRESHOLD_M,
    MIN_DEFAULT_STRIDE_M,
    MIN_STRIDE_M,
    check_preset,
    default_layout,
    foothold_layout,
    hip_depth_m,
)
from planner.workspace.spin import MIN_DEFAULT_SPIN_RAD, default_spin_suffices
from silo4kin.leg_family import family_of
from silo4kin.memo import cached_on_first_argument, results_of

#: Lowest hip height above ground [m]: eq 5.12 then lifts the swing foot 1 cm.
MIN_HIP_CLEARANCE_M = 0.02


#: Step of the scan that clears each end of a longest run (mammal legs) of the holes its
#: coarse grid steps over [m], and how far in from each end it scans [m]: go2's stride is 0 at
#: 0.0474-0.0499 m between feasible 0.0449 and 0.0524 m.
END_SCAN_STEP_M = 0.0025
END_SCAN_DEPTH_M = 0.04


#: Lowest hip height above ground of the default preset [m]: eq 5.12 then lifts the swing
#: foot 2.5 cm, and below it the reachable set near the hip is too thin for the stability
#: shifts (tests/robots/mantis.urdf left its hip-pitch limit at 2-4.5 cm).
MIN_DEFAULT_HIP_CLEARANCE_M = 0.05


def _stride(robot, height: float, preset: str) -> float:
    """λ along the body x axis at a height [m] (the path follower's stride)."""
    return float(foothold_layout(robot, height, preset)[2][0])


def stride_at(robot, height: float, preset: str = "default") -> float:
    """``workspace_for(robot, height, preset).stride_m`` [m] (the same checks and value)
    without the rest of the Workspace: its spin angle ψ_max alone is a bisection of ~200 IK
    calls, and a scan of λ(h) over hundreds of heights (thesis_consistency.stride_jump)
    needs only λ.

    Raises:
        PlannerInputError: as :func:`workspace_for`.
    """
    check_preset(preset, robot)
    if not np.isfinite(height):
        raise PlannerInputError(f"height must be a finite number of metres, got {height!r}")
    robot = planning_robot(robot)
    check_height(robot, float(height), preset)
    return _stride(robot, float(height), preset)


def feasible_height_range(
    robot, preset: str = "default", clear_stance: bool = True, any_direction: bool = False
) -> tuple[float, float]:
    """(min, max) body height the preset plans for [m], rounded inwards to 0.1 mm.

    The one range every planner entry point uses (``robot`` as loaded or in the planning
    frame). thesis: hips at least MIN_HIP_CLEARANCE_M above the ground (eq 5.12 lifts a foot
    1 cm; the thesis's 0.15 m puts SILO4's hips on the ground) and a stride of at least
    MIN_STRIDE_M with every creeping foothold reachable (SILO4: up to 0.63 m, legs vertical).
    default: hips at least MIN_DEFAULT_HIP_CLEARANCE_M up, a stride of at least
    MIN_DEFAULT_STRIDE_M inside the reachable sets with the creeping lifts stable, the
    neighbouring feet apart, every foothold reachable and the creeping stances within the
    joints' effort budget (foothold_layout, planner/workspace/stance_budget.py; a height
    refused for the budget says so, check_height), and with ``clear_stance``
    (the default; False gives the range of the legs' reach alone) the creeping stance
    clear of the ground but for the feet (:func:`stance_clear`: a mammal whose calves lie
    on the ground at a low height cannot walk there). Whether the robot can also walk
    across its body is the path's question, not the height's (issue 21, "feasibility
    follows the gait"): at a height with neither a stride across the body as long as the
    shortest (the gaits without turning walk any direction) nor a spin of at least
    MIN_DEFAULT_SPIN_RAD per cycle (to face the path), the default walks a path along its
    body axis, forwards and backwards (planner/gaits/facing.py), and refuses one that needs a
    turn naming the heights where it can turn (planner/gaits/walk.py check_can_spin). With
    ``any_direction`` the range asks for one of the two as well: the heights at which the
    default walks a path in every direction (:func:`walks_any_direction`). The range
    is the longest run of feasible heights on the leg family's grid (1 cm for insect legs,
    2 cm for mammal legs: WorkspaceFamily.height_grid_m; the first of equally long runs),
    each end then bisected; mammal legs' ends are then moved inwards past the holes an
    END_SCAN_STEP_M scan finds within END_SCAN_DEPTH_M of them (WorkspaceFamily.end_scan).
    The longest run, not the first: a leg may plan a sliver of heights low, cut off from the
    rest by heights where the creeping stance does not clear the ground (a folded mammal leg;
    the 100 N m SILO4 variant (L2 0.3, L3 0.35, Lb 0.25 m) at 0.2000-0.2035 m, whose tibias
    come within 9.2 mm of the ground at 0.204 m, issue 21), and a range that starts there
    leaves out every height the robot walks at.

    Kept in the planning robot's memo under (preset, clear_stance, any_direction):
    :func:`known_feasible_ranges` reads them, :func:`remember_feasible_ranges` fills them
    (``silo4 plan`` from its cache on disk, viz/cli/range_cache.py).
    """
    check_preset(preset, robot)
    return _feasible_height_range(
        planning_robot(robot), preset, bool(clear_stance), bool(any_direction)
    )


#: A range's memo key: (preset name, clear_stance, any_direction).
RangeKey = tuple[str, bool, bool]


def known_feasible_ranges(robot) -> dict[RangeKey, tuple[float, float]]:
    """The feasible ranges [m] computed for ``robot`` so far (or remembered), by
    (preset name, clear_stance, any_direction); presets given as objects are left out."""
    memo = results_of(_feasible_height_range, planning_robot(robot)) or {}
    return {
        key: (float(value[0]), float(value[1]))
        for key, value in memo.items()
        if isinstance(key, tuple)
        and len(key) == 3
        and isinstance(key[0], str)
        and isinstance(key[1], bool)
        and isinstance(key[2], bool)
    }


def remember_feasible_ranges(robot, ranges: dict[RangeKey, tuple[float, float]]) -> None:
    """Give ``robot``'s :func:`feasible_height_range` the ``ranges`` [m] of
    :func:`known_feasible_ranges` (computed from the same robot description by the same
    code: the caller's to know), so they are not computed again."""
    memo = results_of(_feasible_height_range, planning_robot(robot))
    if memo is None:
        return
    for (preset, clear_stance, any_direction), (lo, hi) in ranges.items():
        memo[(str(preset), bool(clear_stance), bool(any_direction))] = (float(lo), float(hi))


@cached_on_first_argument(32)
def _feasible_height_range(
    robot, preset: str, clear_stance: bool, any_direction: bool
) -> tuple[float, float]:
    """:func:`feasible_height_range` of the planning robot ``robot``, all arguments given."""
    lowest, highest, grid = _height_grid(robot, preset)
    min_stride = _min_stride_m(preset)

    def ok(h: float) -> bool:
        if not _height_ok(robot, h, preset, clear_stance):
            return False
        return not any_direction or walks_any_direction(robot, h, preset)

    family = workspace_family(robot)
    feasible = np.array([ok(float(h)) for h in grid], dtype=bool)
    if not feasible.any():
        raise PlannerInputError(
            f"robot {robot.name!r}: no body height gives a stride of {min_stride} m or more "
            f"with the {preset!r} workspace (footholds out of reach or joint limits, or "
            "creeping stances above the joints' effort budget)"
            + (
                f", and a stride of {min_stride} m across the body or a spin of "
                f"{np.rad2deg(MIN_DEFAULT_SPIN_RAD):.0f} deg per cycle to walk any direction"
                if any_direction
                else ""
            )
        )
    first, last = _longest_run(feasible)

    def edge(good: float, bad: float) -> float:
        for _ in range(family.edge_bisections):  # to < 0.1 mm, the rounding
            m = 0.5 * (good + bad)
            good, bad = (m, bad) if ok(m) else (good, m)
        return good

    lo = lowest if first == 0 else edge(float(grid[first]), float(grid[first - 1]))
    hi = edge(float(grid[last]), float(grid[last + 1]) if last + 1 < grid.size else highest)
    if family.end_scan:
        lo, hi = _past_end_holes(ok, lo, hi, edge)
        if lo > hi:  # a sliver of feasible heights, holes on both sides (hyq: its HAA budget)
            raise PlannerInputError(
                f"robot {robot.name!r}: no run of body heights gives a stride of {min_stride} m "
                f"or more with the {preset!r} workspace (footholds out of reach or joint "
                "limits, or creeping stances above the joints' effort budget): feasible only "
                f"near {0.5 * (lo + hi):.4g} m, with holes on both sides"
            )
    return (_rounded_up(lo), _rounded_down(hi))


def _longest_run(feasible: np.ndarray) -> tuple[int, int]:
    """(first, last) grid index of the longest run of True in ``feasible`` (the first of
    equally long runs; at least one True)."""
    runs = np.flatnonzero(np.diff(np.concatenate([[0], feasible.astype(int), [0]])))
    starts, ends = runs[::2], runs[1::2] - 1
    k = int(np.argmax(ends - starts))
    return int(starts[k]), int(ends[k])


def _past_end_holes(ok, lo: float, hi: float, edge) -> tuple[float, float]:  # noqa: ANN001
    """(lo, hi) [m] moved inwards past every height within END_SCAN_DEPTH_M of each end,
    on an END_SCAN_STEP_M scan, where ``ok`` fails (each new end bisected by ``edge``)."""
    depth = min(END_SCAN_DEPTH_M, 0.5 * (hi - lo))
    up = lo + END_SCAN_STEP_M * np.arange(1, int(depth / END_SCAN_STEP_M) + 1)
    bad = [float(h) for h in up if not ok(float(h))]
    if bad:
        above = bad[-1] + END_SCAN_STEP_M
        lo = edge(above, bad[-1]) if ok(above) else above
    down = hi - END_SCAN_STEP_M * np.arange(1, int(depth / END_SCAN_STEP_M) + 1)
    bad = [float(h) for h in down if not ok(float(h))]
    if bad:
        below = bad[-1] - END_SCAN_STEP_M
        hi = edge(below, bad[-1]) if ok(below) else below
    return lo, hi


def _min_stride_m(preset: str) -> float:
    """The shortest stride the preset plans with [m] (by its foothold rule)."""
    reachable_sets = footholds_of(preset) is FootholdRule.REACHABLE_SETS
    return MIN_DEFAULT_STRIDE_M if reachable_sets else MIN_STRIDE_M


def _height_grid(robot, preset: str) -> tuple[float, float, np.ndarray]:
    """(lowest [m], highest [m], the grid of heights [m]) :func:`feasible_height_range` scans
    (``robot`` in the planning frame)."""
    lz = hip_depth_m(robot)
    family = workspace_family(robot)
    clearance = (
        MIN_DEFAULT_HIP_CLEARANCE_M
        if footholds_of(preset) is FootholdRule.REACHABLE_SETS
        else MIN_HIP_CLEARANCE_M
    )
    lowest = float(np.ceil(round((lz + clearance) * 1e4, 6)) / 1e4)
    highest = family.leg_family.highest_body_height_m(robot.legs[0])
    return lowest, highest, np.arange(lowest, highest, family.height_grid_m)


@cached_on_first_argument(512)
def _height_ok(robot, height: float, preset: str, clear_stance: bool = True) -> bool:
    """Whether the preset plans at ``height`` [m] (:func:`feasible_height_range`): a stride
    λ_x of at least the preset's shortest; with ``clear_stance`` the creeping stance clear
    of the ground (:func:`stance_clear`). Whether a path across the body can be walked there
    is :func:`walks_any_direction`'s question.
    Kept in the robot's memo: every plan's height check (:func:`_inside_feasible_run`) asks
    the same grid heights again, and ``--height auto`` plans ~40 candidates (SILO4: 754
    calls, 82 heights, ~20 % of the search in stance_clear's IK and clearance)."""
    lam = foothold_layout(robot, height, preset)[2]
    min_stride = _min_stride_m(preset)
    if lam[0] < min_stride:
        return False
    if footholds_of(preset) is FootholdRule.THESIS_SQUARE:
        return True
    return not clear_stance or stance_clear(robot, height)


def walks_any_direction(robot, height: float, preset: str = "default") -> bool:
    """Whether the preset walks a path in every direction at ``height`` [m] (``robot`` in the
    planning frame): the thesis preset always (its square spins to face the path, §5.5); the
    default where the stride across the body λ_y is as long as the shortest stride (the
    gaits without turning) or the stance turns at least MIN_DEFAULT_SPIN_RAD per cycle (to
    face the path: planner/workspace/spin.py). Elsewhere the default walks only along its
    body axis (tests/robots/mantis.urdf above 0.5041 m: λ_y 0, ψ_max 0)."""
    if footholds_of(preset) is FootholdRule.THESIS_SQUARE:
        return True
    lam = foothold_layout(robot, height, preset)[2]
    return bool(lam[1] >= _min_stride_m(preset) or default_spin_suffices(robot, height))


def stance_clear(robot, height: float) -> bool:
    """Whether the default's creeping stance at ``height`` [m] (every foot at position 2,
    and all shifted by -λ/2 and +λ/2 along x: the stance's extremes) keeps every shape of
    the robot but its feet MIN_GROUND_CLEARANCE_M above the ground
    (planner/trajectory/clearance.py, the URDF's shapes); ``robot`` in the planning frame.
    A stance with a foot out of reach is not measured (False when none is reached)."""
    _, mid, lam = foothold_layout(robot, height, "default")
    stances = np.array(
        [mid + np.array([dx, 0.0, 0.0]) for dx in (-0.5 * lam[0], 0.0, 0.5 * lam[0])]
    )
    clearance = stance_clearance(robot, height, stances)
    clearance = clearance[np.isfinite(clearance)]
    if not len(clearance):
        return False
    return bool(clearance.min() >= MIN_GROUND_CLEARANCE_M)


def stance_clearance(robot, height: float, position_feet_in_base: np.ndarray) -> np.ndarray:
    """The least height above flat ground [m] of every shape of ``robot`` but its feet
    (planner/trajectory/clearance.py clearance_of_poses, the URDF's collision shapes), (P,),
    for each of the stances ``position_feet_in_base`` (P, L, 3) [m] (the feet in the base
    frame B, legs in ``robot.legs`` order) with the base at ``height`` [m], level, its yaw
    0; each leg's joints from its family's closed-form IK. NaN where a foot is out of
    reach. ``robot`` in the planning frame."""
    feet = np.asarray(position_feet_in_base, dtype=float)
    q = np.concatenate(
        [family_of(leg).inverse_kinematics(leg, feet[:, k]).q for k, leg in enumerate(robot.legs)],
        axis=1,
    )
    out = np.full(len(feet), np.nan)
    rows = np.flatnonzero(~np.isnan(q).any(axis=1))
    if rows.size:
        base = np.tile([0.0, 0.0, float(height)], (rows.size, 1))
        out[rows] = clearance_of_poses(robot, q[rows], base, np.zeros(rows.size)).min(axis=1)
    return out


def _inside_feasible_run(robot, height: float, preset: str) -> bool:
    """True only if ``height`` [m] is inside :func:`feasible_height_range`, found without the
    whole range. The grid is read from its lowest height until the run of feasible heights
    in hand is known to be the range's, the longest (longer than every run before it, and at
    least as long as any the unread rest of the grid can hold: one of its heights would be
    the gap), and then True once the run reaches a grid height at or above ``height`` with
    ``height`` not below the run's first grid height (between it and the bisected end only
    the whole range knows); heights compared after the range's own rounding to 0.1 mm.
    False means "ask feasible_height_range": also for mammal legs, whose ends move past
    holes a finer scan finds (WorkspaceFamily.end_scan). The whole range of SILO4 is ~50
    workspace layouts and its bisections; this answer needs the grid up to the run's
    middle at most."""
    if workspace_family(robot).end_scan:
        return False  # the ends move inwards past holes only the whole range's scan finds
    lowest, _, grid = _height_grid(robot, preset)
    n = int(grid.size)
    if not (n and lowest <= height):
        return False
    longest_before = 0  # the longest run read so far that has ended [grid heights]
    start = -1  # first grid index of the run in hand (-1: none)
    for k in range(n):
        if not _height_ok(robot, float(grid[k]), preset, True):
            if start >= 0:
                longest_before, start = max(longest_before, k - start), -1
            continue
        if start < 0:
            start = k
        length = k - start + 1
        if length > longest_before and length >= n - k - 2:  # the range's run
            begins = lowest if start == 0 else _rounded_up(float(grid[start]))
            if height < begins:
                return False
            if _rounded_down(float(grid[k])) >= height:
                return True
    return False


def _rounded_up(h: float) -> float:
    """``h`` [m] rounded up to 0.1 mm as the range's lower end is."""
    return float(np.ceil(round(h * 1e4, 6)) / 1e4)


def _rounded_down(h: float) -> float:
    """``h`` [m] rounded down to 0.1 mm as the range's upper end is."""
    return float(np.floor(round(h * 1e4, 6)) / 1e4)


def check_height(robot, height: float, preset: str) -> None:
    """Refuse a height outside :func:`feasible_height_range` (the message names the range)."""
    known = known_feasible_ranges(robot).get((preset, True, False))
    if known is not None and known[0] <= height <= known[1]:
        return
    if known is None and _inside_feasible_run(robot, height, preset):
        return
    lo, hi = feasible_height_range(robot, preset)
    if not lo <= height <= hi:
        raise PlannerInputError(
            f"height {height:.4g} m is outside the feasible range [{lo:.4g}, {hi:.4g}] m of "
            f"the {preset!r} workspace for robot {robot.name!r}"
            + _bound_reason(robot, height, preset)
        )


def _bound_reason(robot, height: float, preset: str) -> str:
    """A clause naming what leaves ``height`` [m] without a stride when it is the effort
    budget or the stability threshold (foothold_layout.default_layout bounded by "effort" or
    "stability"), else ""."""
    lowest, highest, _ = _height_grid(robot, preset)
    if footholds_of(preset) is not FootholdRule.REACHABLE_SETS or not lowest <= height < highest:
        return ""
    _, _, lam, bound = default_layout(robot, height, preset)
    min_stride = _min_stride_m(preset)
    if lam[0] >= min_stride:
        return ""
    if bound == "effort":
        headroom = preset_for(preset).torque_headroom
        return (
            f": at {height:.4g} m the creeping stances need more static torque than the effort "
            f"budget ({headroom:g} x URDF effort) at every stride of {min_stride} m or "
            "more, even with the feet pulled towards the hips"
        )
    if bound == "stability":
        return (
            f": at {height:.4g} m the legs reach a stride of {min_stride} m or more along the "
            f"body, but none keeps the stability threshold of {DEFAULT_STABILITY_THRESHOLD_M} m "
            "on every creeping lift (the footholds stand too near the CoG); the 'thesis' "
            "workspace accepts a margin of 0"
        )
    return ""
