"""Leg workspace, stride and footholds for a body height (thesis §4.2.1, Fig 4.7-4.8).

Square workspace (thesis §4.2.1, read as in thesis-notes.md "Footholds"): each leg's simplified
workspace is the rectangle spanned in the base frame from its hip-yaw axis to the foot of a
reference pose with θ1 = 0 (the leg along its rest direction θb). With ρ the horizontal
distance of that foot from the hip axis, the rectangle's extents are e_x = ρ|cos θb| along x
and e_y = ρ|sin θb| along y. For travel along a body axis d, the three footholds of a leg lie
on the rectangle's mid-line across d, at the rectangle's far end, middle and hip end along d
(positions 1, 2, 3; a leg behind the CoG is mirrored). The stride is λ = e_d (the smallest over
the legs). Position 2, the rectangle's centre, is on the hip diagonal (θ1 = 0) for θb = ±45°.

Presets (the reference pose):
    thesis   The rule behind the Chapter 6 strides (thesis-notes.md): hip height above ground
             hh = h - Lz - ε, ε = 1e-4 m; if hh <= L3 then θ2 = 0, θ3 = -asin(hh/L3), else the
             leg is stretched (θ3 = 0, singular) with θ2 = -asin(hh/(L2+L3)). The stride is
             ρ|cos θb| = x_max - x_hip (the thesis subtracts a rounded 0.155 m for x_hip;
             we subtract the robot's hip coordinate, 0.56 mm more). Stability threshold 0
             (the thesis accepts the CoG on a support edge).
    default  The reference pose keeps a knee margin of DEFAULT_KNEE_MARGIN from the θ3 = 0
             singularity: hip-pitch-to-foot distance r_m = |L2 + L3 e^{-i θm}|, ρ = L1 +
             sqrt(r_m² - hh²) with the exact hh. Stride decreases monotonically with h.

Swing height (eq 5.12): h_max = (z_hip - z_ground)/2, half the hip height above ground.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from silo4kin.geometry import LegGeometry
from silo4kin.kinematics import inverse_kinematics_masked

from .errors import PlannerInputError

PRESETS: tuple[str, ...] = ("default", "thesis")
#: ε of the thesis stride rule [m] (thesis-notes.md: reproduces 0.3787 / 0.3328 / 0.1613).
THESIS_EPSILON_M = 1e-4
#: Knee margin of the default reference pose from θ3 = 0 [rad]: 20° keeps |det J| at
#: sin 20° = 34 % of its largest value at the corner of the workspace square.
DEFAULT_KNEE_MARGIN = np.deg2rad(20.0)
#: Lowest hip height above ground [m]: eq 5.12 then lifts the swing foot 1 cm.
MIN_HIP_CLEARANCE_M = 0.02
#: Shortest stride the default preset accepts [m]; sets its upper height limit.
MIN_DEFAULT_STRIDE_M = 0.10
#: Default stability threshold of the default preset [m] (every lift keeps S_m >= this).
DEFAULT_STABILITY_THRESHOLD_M = 0.02
#: Reserve on the θ1 limits when sizing the default preset's spin angle per cycle [rad]:
#: room for the CoG shifts that keep the margin positive during the spin (a 5 cm shift seen
#: from a foot 0.3 m from its hip is ~10°). The thesis preset makes no shifts: no reserve.
SPIN_THETA1_RESERVE = np.deg2rad(10.0)
#: The default preset keeps every foothold reachable with the body displaced this far in any
#: of 8 directions [m]: room for the stability shifts (threshold + 5 mm from a zero margin
#: needs ~3 cm).
SHIFT_RESERVE_M = 0.05
_RESERVE_DIRECTIONS = np.array([[np.cos(a), np.sin(a), 0.0]
                                for a in np.linspace(0, 2 * np.pi, 8, endpoint=False)])
#: Slack when checking joint limits [rad].
JOINT_LIMIT_TOLERANCE = 1e-9


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


def _leg_params(robot) -> tuple[float, float, float, float]:
    leg: LegGeometry = robot.legs[0]
    return -leg.hip_height, leg.L1, leg.L2, leg.L3


def _reach(robot, height: float, preset: str) -> float:
    """ρ of the reference pose [m] (module docstring)."""
    lz, l1, l2, l3 = _leg_params(robot)
    if preset == "thesis":
        hh = height - lz - THESIS_EPSILON_M
        if hh <= l3:
            t2, t3 = 0.0, -np.arcsin(hh / l3)
        else:
            t2, t3 = -np.arcsin(min(hh / (l2 + l3), 1.0)), 0.0
        return float(l1 + l2 * np.cos(t2) + l3 * np.cos(t2 + t3))
    hh = height - lz
    r_m = np.hypot(l2 + l3 * np.cos(DEFAULT_KNEE_MARGIN), l3 * np.sin(DEFAULT_KNEE_MARGIN))
    return float(l1 + np.sqrt(max(r_m**2 - hh**2, 0.0)))


def _extents(robot, rho: float) -> np.ndarray:
    tb = np.array([leg.theta_b for leg in robot.legs])
    return rho * np.stack([np.abs(np.cos(tb)), np.abs(np.sin(tb))], axis=1)


def _footholds_ok(robot, height: float, preset: str) -> bool:
    """All creeping footholds (positions 1-3 along ±x, ±y) reachable within limits."""
    extent = _extents(robot, _reach(robot, height, preset))
    lam = extent.min(axis=0)
    for k, leg in enumerate(robot.legs):
        hip = leg.position_hip_in_base
        mid = np.array([hip[0] + np.sign(hip[0]) * extent[k, 0] / 2,
                        hip[1] + np.sign(hip[1]) * extent[k, 1] / 2, -height])
        pts = np.array([mid + np.array([sx * lam[0] / 2, sy * lam[1] / 2, 0.0])
                        for sx, sy in ((1, 0), (-1, 0), (0, 1), (0, -1), (0, 0))])
        if preset == "default":
            pts = (pts[:, None, :] + SHIFT_RESERVE_M * _RESERVE_DIRECTIONS[None]).reshape(-1, 3)
        if not np.all(reachable_in_limits(leg, pts)):
            return False
    return True


@lru_cache(maxsize=32)
def feasible_height_range(robot, preset: str = "default") -> tuple[float, float]:
    """(min, max) body height the preset plans for [m], rounded inwards to 0.1 mm.

    min = Lz + MIN_HIP_CLEARANCE_M (hips 2 cm above ground, so eq 5.12 lifts a foot 1 cm;
    the thesis's 0.15 m puts the hips on the ground). max = the largest height whose creeping
    footholds are all reachable within the joint limits (thesis: 0.63 m, legs vertical, where
    no stride is left), and for the default preset whose stride is >= MIN_DEFAULT_STRIDE_M.
    """
    _check_preset(preset)
    lz, l1, l2, l3 = _leg_params(robot)
    lo = float(np.ceil((lz + MIN_HIP_CLEARANCE_M) * 1e4) / 1e4)

    def ok(h: float) -> bool:
        if preset == "default" and float(np.min(_extents(robot, _reach(robot, h, preset)))) \
                < MIN_DEFAULT_STRIDE_M:
            return False
        return _footholds_ok(robot, h, preset)

    a, b = lo, lz + l2 + l3
    for _ in range(40):  # bisection: the stride shrinks monotonically with h
        m = 0.5 * (a + b)
        a, b = (m, b) if ok(m) else (a, m)
    return lo, float(np.floor(a * 1e4) / 1e4)


def _check_preset(preset: str) -> None:
    if preset not in PRESETS:
        raise PlannerInputError(f"unknown workspace preset {preset!r}; choose one of {PRESETS}")


def reachable_in_limits(leg: LegGeometry, position_foot_in_base: np.ndarray,
                        theta1_reserve: float = 0.0) -> np.ndarray:
    """Whether IK reaches each target (N, 3) [m] within the joint limits; (N,) bool.

    theta1_reserve [rad] narrows the hip-yaw range on both sides.
    """
    res = inverse_kinematics_masked(leg, np.atleast_2d(position_foot_in_base))
    q = np.where(np.isfinite(res.q), res.q, 0.0)
    lo = leg.q_lower - JOINT_LIMIT_TOLERANCE + np.array([theta1_reserve, 0.0, 0.0])
    hi = leg.q_upper + JOINT_LIMIT_TOLERANCE - np.array([theta1_reserve, 0.0, 0.0])
    return res.reachable & np.all((q >= lo) & (q <= hi), axis=1)


def _rotation(psi: float) -> np.ndarray:
    c, s = np.cos(psi), np.sin(psi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _psi_max(robot, mid: np.ndarray, reserve: float, shift: float) -> float:
    """Largest ψ <= π/2 with the spin stance rotated by ±ψ about the CoG reachable with θ1
    narrowed by ``reserve`` [rad] and the body displaced by up to ``shift`` [m]
    (thesis-notes.md: acos(Lb / |p2|) for SILO4 without reserves)."""
    offsets = np.vstack([np.zeros(3), shift * _RESERVE_DIRECTIONS])

    def ok(psi: float) -> bool:
        return all(bool(np.all(reachable_in_limits(
            leg, (_rotation(sign * psi) @ mid[i])[None] + offsets, reserve)))
            for i, leg in enumerate(robot.legs) for sign in (1.0, -1.0))
    if ok(np.pi / 2):
        return float(np.pi / 2)
    lo, hi = 0.0, np.pi / 2
    for _ in range(40):
        m = 0.5 * (lo + hi)
        lo, hi = (m, hi) if ok(m) else (lo, m)
    return float(lo)


def workspace_for(robot, height: float, preset: str = "default") -> Workspace:
    """Workspace, stride and footholds at body height ``height`` [m].

    Raises:
        PlannerInputError: unknown preset, non-finite height, or height outside
            :func:`feasible_height_range` (the message names the range).
    """
    _check_preset(preset)
    if not np.isfinite(height):
        raise PlannerInputError(f"height must be a finite number of metres, got {height!r}")
    lo, hi = feasible_height_range(robot, preset)
    if not lo <= height <= hi:
        raise PlannerInputError(
            f"height {height:.4g} m is outside the feasible range [{lo:.4g}, {hi:.4g}] m of "
            f"the {preset!r} workspace for robot {robot.name!r}")
    lz = _leg_params(robot)[0]
    rho = _reach(robot, height, preset)
    extent = _extents(robot, rho)
    hips = np.array([leg.position_hip_in_base for leg in robot.legs], dtype=float)
    sign = np.sign(hips[:, :2])
    mid = np.empty((4, 3))
    mid[:, :2] = hips[:, :2] + sign * extent / 2.0
    mid[:, 2] = -height
    hip_clear = height - lz
    return Workspace(
        preset=preset, height=float(height), hip_clearance_m=float(hip_clear), reach_m=rho,
        stride_m=float(extent[:, 0].min()), stride_lateral_m=float(extent[:, 1].min()),
        swing_height_m=float(hip_clear / 2.0), position_hip_in_base=hips, extent_m=extent,
        position_mid_in_base=mid,
        psi_max_rad=_psi_max(robot, mid, *((0.0, 0.0) if preset == "thesis"
                                            else (SPIN_THETA1_RESERVE, SHIFT_RESERVE_M))),
        stability_threshold_m=0.0 if preset == "thesis" else DEFAULT_STABILITY_THRESHOLD_M,
        half_cycles=preset != "thesis",
    )
