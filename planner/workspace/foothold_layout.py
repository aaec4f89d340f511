"""Where the feet stand at a body height: foothold layout of the two presets (thesis §4.2.1).

Two presets. ``default`` plans inside each leg's reachable ground set within its joint limits
(planner/workspace/reach_insect.py and reach_mammal.py compute the sets,
planner/workspace/footholds.py chooses position 2 and the strides λ_x, λ_y inside it, with the
stability, interference and IK checks of :func:`foothold_layout`). ``thesis`` keeps the
thesis's square workspace, described here:

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

Swing height (eq 5.12): h_max = (z_hip - z_ground)/2, half the hip height above ground.
The PRESETS tuple and its check (:func:`check_preset`) live here for now.
"""

from __future__ import annotations

import numpy as np

from planner.errors import PlannerInputError
from planner.presets import FootholdRule, footholds_of, preset_for
from planner.stability.shifts import SHIFT_EXTRA_M
from planner.workspace.families import SPIN_THETA1_RESERVE, workspace_family
from planner.workspace.footholds import stable_stride
from planner.workspace.interference import LEG_CLEARANCE_M
from planner.workspace.reach_check import reachable_in_limits_of_legs
from planner.workspace.stance_budget import budget_nm, budget_scale
from silo4kin.foot_contact import foot_contact_offset_m
from silo4kin.memo import cached_on_first_argument

__all__ = ["SPIN_THETA1_RESERVE"]

PRESETS: tuple[str, ...] = ("default", "thesis")

#: ε of the thesis stride rule [m] (thesis-notes.md: reproduces 0.3787 / 0.3328 / 0.1613).
THESIS_EPSILON_M = 1e-4

#: Knee margin of the default reference pose from θ3 = 0 [rad]: 20° keeps |det J| at
#: sin 20° = 34 % of its largest value at the corner of the workspace square.
DEFAULT_KNEE_MARGIN = np.deg2rad(20.0)

#: Shortest stride the default preset accepts [m]; sets its upper height limit.
MIN_DEFAULT_STRIDE_M = 0.10

#: Shortest stride the thesis preset accepts [m] (1 cm: a stride at all).
MIN_STRIDE_M = 0.01

#: Default stability threshold of the default preset [m] (every lift keeps S_m >= this).
DEFAULT_STABILITY_THRESHOLD_M = 0.02

#: The default preset keeps every foothold reachable with the body displaced this far in any
#: of 8 directions [m]: room for the stability shifts (threshold + 5 mm from a zero margin
#: needs ~3 cm).
SHIFT_RESERVE_M = 0.05

#: The 8 unit directions of that displacement, shape (8, 3).
RESERVE_DIRECTIONS = np.array(
    [[np.cos(a), np.sin(a), 0.0] for a in np.linspace(0, 2 * np.pi, 8, endpoint=False)]
)

#: Extra room over LEG_CLEARANCE_M kept between neighbouring footholds when sizing the
#: default stride [m] (crab angles and spin stances move the feet a little off the axis).
INTERFERENCE_SLACK_M = 0.02

#: Travel directions of the creeping gait along each body axis: (axis, (2, 2) unit vectors).
AXIS_DIRECTIONS = (
    (0, np.array([[1.0, 0.0], [-1.0, 0.0]])),
    (1, np.array([[0.0, 1.0], [0.0, -1.0]])),
)

#: What bounds the default layout's λ_x (default_layout).
BOUNDS = ("reach", "stability", "effort")

#: Factors pulling the default centres towards the hips, tried where the effort budget cuts
#: λ_x (default_layout): a stance foot's joint torque is its load times its lever, and the
#: lever shortens with the foot's distance from the hip (the support, and the stability
#: strides, shrink with it).
CENTRE_PULLS = (0.95, 0.9, 0.85, 0.8, 0.75, 0.7, 0.65, 0.6)

#: A pulled layout replaces the unpulled one only when its λ_x is longer by this [m].
PULL_GAIN_M = 0.005

#: The pulls stop after this many in a row that do not lengthen λ_x.
PULL_PATIENCE = 2

#: Extra erosions [m] tried in turn when the closed-form IK refuses the footholds chosen in
#: the sampled reachable sets (foothold_layout).
CENTRE_RETRY_EROSION_M = (0.0, 0.005, 0.01, 0.02)


def hip_depth_m(robot) -> float:
    """Lz [m]: the depth of the first leg's hip axis (insect: hip yaw; mammal: HAA point)
    below the body CoG."""
    return -float(robot.legs[0].position_hip_in_base[2])


def swing_height_m(robot, height: float, preset: str = "default") -> float:
    """The swing height [m] the preset's plans lift a foot by at body height ``height`` [m]:
    h_max of eq 5.12 (half the hip's height above the ground), raised to the preset's least
    (Preset.swing_height: MIN_SWING_HEIGHT_M for the default, 0 for the thesis). The IK
    checks of the layout (:func:`_footholds_ok`) and of ψ_max (planner/workspace/spin.py)
    lift the feet by this height: with eq 5.12 alone they checked a lower lift than the
    plans make wherever eq 5.12 is under the least (issue 21: phasmid at h 0.1556 m, eq 5.12
    28 mm against the 50 mm swung; no right foot could be lifted at position 2 with the body
    displaced by the shift reserve, so neither the crawl nor the creeping gait found a step,
    and a spin transfer left the hip pitch's limit)."""
    return preset_for(preset).swing_height((height - hip_depth_m(robot)) / 2.0)


def foot_levels(robot, height: float) -> tuple[float, float, float]:
    """Foot-frame heights in B [m] at the ground, half and full swing height at body height
    ``height`` [m]: the ground is foot_contact_offset_m below a standing foot frame
    (silo4kin/foot_contact.py; 0 for point feet, so -height for SILO4). The swing height is
    eq 5.12's: the levels of the sampled reachable sets that place the centres (position 2),
    not the plans' lift (:func:`swing_height_m`), which the IK check of the footholds
    (:func:`_footholds_ok`) has the last word on. Measured: sets sampled at the plans' lift
    moved SILO4's centres at h 0.2 m so that the Chapter 6 straight path crept in 97.4
    units instead of crawling in 80.9 (> 0.7 x the thesis's 132)."""
    ground = -height + foot_contact_offset_m(robot)
    swing = (height - hip_depth_m(robot)) / 2.0
    return (ground, ground + swing / 2.0, ground + swing)


def _reachable_sets(robot, levels: tuple[float, ...]) -> tuple:
    """Each leg's reachable ground set at the foot heights ``levels`` [m] in B, of its family
    (planner/workspace/reach_insect.py, planner/workspace/reach_mammal.py)."""
    return workspace_family(robot).reachable_sets(tuple(robot.legs), levels, DEFAULT_KNEE_MARGIN)


def _thesis_reach(robot, height: float) -> float:
    """ρ of the thesis preset's reference pose [m] (module docstring; insect legs)."""
    leg = robot.legs[0]
    lz, l1, l2, l3 = -leg.hip_height, leg.L1, leg.L2, leg.L3
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
            [np.cos(leg.theta_b), np.sin(leg.theta_b)]
        )
    mid[:, 2] = -height
    return mid


def _footholds_ok(
    robot, height: float, preset: str, mid: np.ndarray, extent: tuple[float, float]
) -> bool:
    """All creeping footholds (positions 1-3 along ±x with λ_x = extent[0], ±y with
    λ_y = extent[1]), on the ground and lifted by the plans' swing height
    (:func:`swing_height_m`), reachable within limits
    by the closed-form IK; for the default preset also with the body displaced by
    SHIFT_RESERVE_M in 8 directions."""
    swing = swing_height_m(robot, height, preset)
    ex, ey = extent
    # the footholds on the ground, and lifted by the swing height (the swing apex passes
    # over position 2; the lifted rear/front footholds bound the rest of the swing arc)
    offsets = np.array(
        [
            [sx * ex / 2, sy * ey / 2, dz]
            for sx, sy in ((1, 0), (-1, 0), (0, 1), (0, -1), (0, 0))
            for dz in (0.0, swing)
        ]
    )
    pts = np.asarray(mid, dtype=float)[:, None, :] + offsets[None]  # (legs, 10, 3)
    if footholds_of(preset) is FootholdRule.REACHABLE_SETS:
        pts = pts[:, :, None, :] + SHIFT_RESERVE_M * RESERVE_DIRECTIONS[None, None]
    pts = pts.reshape(len(robot.legs), -1, 3)
    idx = np.repeat(np.arange(len(robot.legs)), pts.shape[1])
    return bool(np.all(reachable_in_limits_of_legs(robot.legs, idx, pts.reshape(-1, 3))))


def _shrink_to_reach(
    robot, height: float, preset: str, mid: np.ndarray, extent: tuple[float, float]
) -> float:
    """Largest factor f in [0, 1] with the footholds of extents f·extent reachable
    (_footholds_ok, bisection); 1 when they all are."""
    if _footholds_ok(robot, height, preset, mid, extent):
        return 1.0
    lo, hi = 0.0, 1.0
    for _ in range(30):
        m = 0.5 * (lo + hi)
        lo, hi = (
            (m, hi)
            if _footholds_ok(robot, height, preset, mid, (m * extent[0], m * extent[1]))
            else (lo, m)
        )
    return lo


@cached_on_first_argument(512)
def foothold_layout(robot, height: float, preset: str) -> tuple[float, np.ndarray, np.ndarray]:
    """(ρ [m], position 2 of every leg (4, 3) [m], extents (λ_x, λ_y) (2,) [m]) at a height.

    thesis: the square of the module docstring, λ its side, shortened (by bisection) only if
    some foothold is out of reach or limits (SILO4's all fit; a robot whose legs point sideways,
    tests/robots/mantis.urdf, has its near-hip footholds cut back). default: footholds inside
    the reachable sets (planner/workspace/reach_insect.py, planner/workspace/footholds.py): the
    sets at the ground, half and full swing height, knee margin DEFAULT_KNEE_MARGIN, eroded by
    SHIFT_RESERVE_M; strides shortened until the creeping gait keeps the stability threshold
    (footholds.stable_stride), then checked by IK (_footholds_ok), then shortened until the
    creeping stances keep the effort budget (planner/workspace/stance_budget.py); where that
    cuts λ_x, the centres are also pulled towards the hips (:data:`CENTRE_PULLS`) and the
    layout with the longest λ_x kept. ρ is the reference pose's reach (thesis) or the largest
    ground reach r_max (default).
    """
    return default_layout(robot, height, preset)[:3]


@cached_on_first_argument(512)
def default_layout(robot, height: float, preset: str) -> tuple[float, np.ndarray, np.ndarray, str]:
    """:func:`foothold_layout` and what bounds its λ_x (:data:`BOUNDS`): "reach" (the
    reachable sets, stability, interference and IK), "stability" (a λ_x under
    MIN_DEFAULT_STRIDE_M where the reachable sets hold one but no such stride keeps the
    stability threshold on every creeping lift: mantis above 0.5704 m, whose stretched legs'
    sets pull position 2 in towards its off-centre CoG) or "effort" (the creeping stances'
    static torques, planner/workspace/stance_budget.py: shorter than "reach" allows, 0 when
    even a zero stride breaks the budget at every centre pull)."""
    if footholds_of(preset) is FootholdRule.THESIS_SQUARE:
        rho = _thesis_reach(robot, height)
        side = float(_extents(robot, rho).min())
        mid = _mid_in_base(robot, rho, height)
        side *= _shrink_to_reach(robot, height, preset, mid, (side, side))
        return rho, mid, np.array([side, side]), "reach"
    levels = foot_levels(robot, height)
    sets = _reachable_sets(robot, levels)
    family = workspace_family(robot)
    hips = np.array([leg.position_hip_in_base for leg in robot.legs], dtype=float)
    # The sets are sampled (reach.py) and the closed-form IK has the last word
    # (_footholds_ok): where a centre sits on the sampled boundary, IK may refuse even a zero
    # stride (seen at one height of an L3 = 0.3 m variant). Then the centres are chosen
    # again from the sets eroded by a little more, instead of calling the height infeasible.
    best: tuple[np.ndarray, np.ndarray] = (np.zeros((4, 3)), np.zeros(2) - 1.0)
    used_erosion, longest = 0.0, 0.0
    for extra_erosion in CENTRE_RETRY_EROSION_M:
        centres, extents = family.choose_centres(
            tuple(robot.legs), sets, SHIFT_RESERVE_M + extra_erosion
        )
        mid = np.column_stack([centres, np.full(4, levels[0])])
        in_sets = np.array([extents[:, 0].min(), extents[:, 1].min()])
        lam = _reach_strides(robot, height, preset, hips, mid, in_sets)
        if lam[0] > best[1][0]:
            best, used_erosion, longest = (mid, lam), extra_erosion, float(in_sets[0])
        if lam[0] >= MIN_DEFAULT_STRIDE_M:
            break
    mid, lam = best
    rho = float(max(s.radius_upper_m for s in sets)) if sets else 0.0
    budget = budget_nm(robot, preset_for(preset).torque_headroom)
    kept = _budget_strides(robot, mid, lam, budget)
    if kept[0] >= lam[0]:
        return rho, mid, kept, _reach_bound(hips, mid, lam, longest)
    # the budget cuts λ_x: pull the centres in (shorter levers), keep the longest λ_x
    best_pulled, worse = (mid, kept), 0
    for pull in CENTRE_PULLS:
        pulled = mid.copy()
        pulled[:, :2] = hips[:, :2] + pull * (mid[:, :2] - hips[:, :2])
        # inside the reachable sets eroded as the centres were chosen (the knee's fold and
        # the swing's heights are bounded there), else no stride
        room = family.extents_at(sets, pulled[:, :2], SHIFT_RESERVE_M + used_erosion)
        reach = _reach_strides(robot, height, preset, hips, pulled, room.min(axis=0))
        cut = _budget_strides(robot, pulled, reach, budget)
        if cut[0] > best_pulled[1][0] + PULL_GAIN_M:
            best_pulled, worse = (pulled, cut), 0
        else:
            worse += 1
            if worse == PULL_PATIENCE:
                break
    return rho, best_pulled[0], best_pulled[1], "effort"


def _reach_strides(
    robot, height: float, preset: str, hips: np.ndarray, mid: np.ndarray, longest: np.ndarray
) -> np.ndarray:
    """(λ_x, λ_y) [m] <= ``longest`` at centres ``mid`` (4, 3): the creeping lifts stable
    (footholds.stable_stride), the neighbouring feet apart (_interference_caps), every
    foothold reachable (_shrink_to_reach)."""
    lam = np.array(longest, dtype=float)
    for axis, dirs in AXIS_DIRECTIONS:
        lam[axis] = stable_stride(
            hips, mid, float(lam[axis]), dirs, DEFAULT_STABILITY_THRESHOLD_M + SHIFT_EXTRA_M
        )
    lam = np.minimum(lam, _interference_caps(mid))
    lam = np.clip(lam, 0.0, None)
    return lam * _shrink_to_reach(robot, height, preset, mid, (float(lam[0]), float(lam[1])))


def _reach_bound(hips: np.ndarray, mid: np.ndarray, lam: np.ndarray, longest: float) -> str:
    """ "stability" where ``lam`` (2,) [m] at centres ``mid`` (4, 3) has λ_x under
    MIN_DEFAULT_STRIDE_M although the reachable sets hold ``longest`` >= it along x [m] and no
    stride of it keeps the stability threshold on every creeping lift along x
    (footholds.stable_stride, as _reach_strides asks it), else "reach"."""
    if lam[0] >= MIN_DEFAULT_STRIDE_M or longest < MIN_DEFAULT_STRIDE_M:
        return "reach"
    threshold = DEFAULT_STABILITY_THRESHOLD_M + SHIFT_EXTRA_M
    stable = stable_stride(hips, mid, longest, AXIS_DIRECTIONS[0][1], threshold)
    return "stability" if stable < MIN_DEFAULT_STRIDE_M else "reach"


def _budget_strides(robot, mid: np.ndarray, lam: np.ndarray, budget: np.ndarray) -> np.ndarray:
    """(λ_x, λ_y) [m]: ``lam`` scaled until the creeping stances keep ``budget`` (12,)
    [N m] along every travel direction (stance_budget.budget_scale); 0 where even every
    foot at its centre breaks it."""
    return max(budget_scale(robot, mid, lam, DEFAULT_STABILITY_THRESHOLD_M, budget), 0.0) * lam


def _interference_caps(mid: np.ndarray) -> np.ndarray:
    """Longest (λ_x, λ_y) [m] keeping neighbouring feet LEG_CLEARANCE_M + INTERFERENCE_SLACK_M
    apart (thesis §3.6, planner/workspace/interference.py): in the creeping gait a leg can stand
    at its front foothold while its neighbour along the travel direction is still at its rear
    one, λ closer than their positions 2 (the same pair swings one after the other)."""
    gap = LEG_CLEARANCE_M + INTERFERENCE_SLACK_M
    caps = []
    for axis, pairs in ((0, ((0, 2), (1, 3))), (1, ((0, 1), (2, 3)))):
        caps.append(min(abs(mid[a, axis] - mid[b, axis]) for a, b in pairs) - gap)
    return np.array(caps)


def check_preset(preset: str, robot=None) -> None:
    """Refuse an unknown preset, and the thesis preset for legs without a hip yaw."""
    if preset not in PRESETS:
        raise PlannerInputError(f"unknown workspace preset {preset!r}; choose one of {PRESETS}")
    if (
        footholds_of(preset) is FootholdRule.THESIS_SQUARE
        and robot is not None
        and not workspace_family(robot).leg_family.has_hip_yaw
    ):
        raise PlannerInputError(
            f"robot {robot.name!r} has mammal legs: the 'thesis' workspace is the thesis's "
            "square from a hip-yaw reference pose, which a leg without a vertical first axis "
            "does not have; use the 'default' workspace (reachable sets)"
        )
