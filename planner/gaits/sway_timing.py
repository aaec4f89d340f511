"""How long a four-foot body move must last for its joints to carry its acceleration.

The plan's torques are quasi-static (eq A.30-A.34: the feet carry the weight about the CoM,
vertically); the servos that follow the plan must add what the body's acceleration asks of
the ground. A body move of the crawl (planner/gaits/crawl.py: its sways and arrivals, all
four feet down) follows the quintic of eq 5.16 over d units, so the CoM's acceleration peaks
at s̈_max Δc / T² (s̈_max = 10 / sqrt(3), at τ = 1/2 -+ sqrt(3)/6; Δc the CoM's move, T the
move's duration [s]). Newton then asks of the ground, at those two instants,

    F = m (c̈ + g ẑ)                                   (total ground force)
    z = c_xy - (c_z - ground) c̈_xy / (c̈_z + g)         (zero-moment point)
    N_i  vertical reactions about z (eq A.30-A.33, silo4kin/support.py), four feet
    F_i = N_i F / F_z                                  (each foot's force, parallel to F:
                                                        contact_forces.py's split)

and each stance leg's joints carry tau = tau_gravity(q) - J_iᵀ F_i (eq A.14 static + A.34
with the whole force). A move is given the shortest duration, d units or longer, whose
torques at both instants stay within the joints' effort budget (the preset's torque
headroom x URDF effort): tau grows with 1 / T², so a longer move always helps unless the
pose alone breaks the budget (then d is kept: the run's limit check refuses it, naming the
joint). The duration is rounded up to a multiple of DURATION_STEP_UNITS.

Measured (SILO4, the 36-waypoint circle at h 0.4 m, default preset): a sway of 0.233 m in
0.5 units (1 s per unit) asks 5.4 m/s² of the body; its quasi-static torques say 23 N m at
the LF knee, the sway's own forces put 0.61 of the weight on LF and 200 N across the feet,
and in MuJoCo the knee sat at its 60 N m effort limit and the feet slipped 10.5 mm.

The same move must also keep its zero-moment point (z above, at the two peak instants) at
least the lift threshold S inside the four feet's support polygon (support_margin, the
margin of eq 5.3 taken of z instead of the CoG): the margin the static criterion keeps the
CoG by for what it does not model, kept by the point the ground must push through while the
body accelerates (the creep's body phases keep the same S as the ZMP's whole excursion,
planner/gaits/body_pace.py; the contact-force check only asks z inside, margin 0,
planner/stability/contact_rule.py). A move is given the shortest duration that keeps both
rules; where even MAX_STRETCH x d leaves z within S of an edge (the pose's own CoG is that
close) the ZMP rule asks nothing more and the run's checks judge the plan. S <= 0 (the
thesis preset) leaves the rule off.

Measured (issue 21, the 200-case corpus of benchmarks/bench_corpus.py, phasmid, default
preset, MuJoCo): case #152 (h 0.4338 m) swayed 128.6 mm in 0.5 unit right after LH landed,
its ZMP 1.5 mm inside the four feet (the plan's own split gave LH 0 N); in physics LH
carried 0 N for 0.25 s, RH unloaded, LF and RF slid and the feet slipped 8.9 mm. Case #182
(h 0.4895 m) swayed 176.9 mm in 0.5 unit, its ZMP 10.7 mm inside, and slipped 9.4 mm. Every
other sway of both plans kept >= 60 mm.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from planner.stability.margin import support_margin
from planner.trajectory.limits import urdf_limits
from planner.workspace.reach_check import joint_values_of_legs
from silo4kin.errors import Silo4Error
from silo4kin.frames import rotation_z
from silo4kin.joint_torques import motion_torques
from silo4kin.legs import jacobian
from silo4kin.robot import STANDARD_GRAVITY
from silo4kin.support import support_reactions

#: Peak |s̈| of the quintic blend of eq 5.16 over a unit duration, and the phases where it
#: occurs (planner/trajectory/profiles.py quintic_blend) [-].
QUINTIC_PEAK_ACCELERATION = 10.0 / math.sqrt(3.0)
QUINTIC_PEAK_PHASES = (0.5 - math.sqrt(3.0) / 6.0, 0.5 + math.sqrt(3.0) / 6.0)
#: A lengthened move's duration is a multiple of this [time units t_l]: the crawl's
#: four-foot phase (FOUR_FOOT_UNITS), so every step boundary stays on the same sample grid
#: as the crawl's other steps (a 0.05-unit step put boundaries between the samples at 10
#: samples per unit, where the swing's rest at lift-off cannot be seen).
DURATION_STEP_UNITS = 0.5
#: The longest a move is stretched, as a multiple of its nominal duration [-]: beyond it the
#: pose's own (static) torque is what breaks the budget and no duration helps.
MAX_STRETCH = 8.0


def _quintic_s(tau: float) -> float:
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau * tau)


@dataclass(frozen=True, eq=False)
class SwayTiming:
    """The duration rule of the module docstring for one robot and plan.

    Attributes:
        model: the PlanningModel (com_in_world, total_mass, robot, planning_robot).
        budget_nm: each joint's effort budget (12,) [N m], our joint order.
        unit_time_s: the plan's duration of one time unit [s].
        gravity: g [m/s²].
        zmp_margin_m: S, the least margin of the ZMP inside the four feet [m] (module
            docstring); <= 0 leaves that rule off.
    """

    model: Any
    budget_nm: np.ndarray
    unit_time_s: float
    gravity: float = STANDARD_GRAVITY
    zmp_margin_m: float = 0.0

    def _poses(self, base_start, base_end, yaw, feet_in_world):
        """Joints (P, 12), CoM (P, 3) at the start, the two peak instants and the end of
        the move, or None where a foot is out of reach."""
        s = np.array([0.0, *(_quintic_s(p) for p in QUINTIC_PEAK_PHASES), 1.0])
        bases = base_start + s[:, None] * (base_end - base_start)
        rel = feet_in_world[None, :, :] - bases[:, None, :]
        in_base = rel @ rotation_z(float(yaw))  # R^T v for row vectors
        legs = self.model.planning_robot.legs
        q, ok = joint_values_of_legs(legs, np.tile(np.arange(4), len(s)), in_base.reshape(-1, 3))
        if not np.all(ok) or not np.all(np.isfinite(q)):
            return None
        q = q.reshape(len(s), 12)
        com = self.model.com_in_world(q, bases, np.full(len(s), float(yaw)))
        return q, com

    def _peak_zmp(self, com, feet_in_world, duration_s: float):
        """The acceleration (2, 3) [m/s²], total ground force (2, 3) [N] and zero-moment
        point (2, 2) [m] at the two peak instants of a move of ``duration_s`` [s] (module
        docstring), or None where the ground would have to pull the robot down."""
        g = self.gravity
        mass = float(self.model.total_mass)
        dc = com[-1] - com[0]
        peak = QUINTIC_PEAK_ACCELERATION * dc / duration_s**2
        acc = np.stack([peak, -peak])  # at the two peak phases, (2, 3) [m/s²]
        ck = com[1:3]
        force = mass * (acc + np.array([0.0, 0.0, g]))  # (2, 3)
        if np.any(force[:, 2] <= 0.0):
            return None
        ground = float(np.mean(feet_in_world[:, 2]))
        lever = (ck[:, 2] - ground) * mass / force[:, 2]
        return acc, force, ck[:, :2] - lever[:, None] * acc[:, :2]

    def zmp_margin(self, com, feet_in_world, duration_s: float) -> float:
        """Least margin [m] of the ZMP inside the four feet's support polygon at the two
        peak instants of a move of ``duration_s`` [s] (module docstring); com (4, 3) at
        start, peaks, end."""
        peaks = self._peak_zmp(com, feet_in_world, duration_s)
        if peaks is None:
            return -math.inf
        feet = np.broadcast_to(feet_in_world[None, :, :2], (2, 4, 2))
        return float(np.min(support_margin(feet, np.ones((2, 4), dtype=bool), peaks[2])))

    def torque_ratio(self, q, com, feet_in_world, yaw, duration_s: float) -> float:
        """Largest |tau| / budget over the joints at the two peak instants of a move of
        ``duration_s`` [s] (module docstring); q (4, 12), com (4, 3) at start, peaks, end."""
        g = self.gravity
        peaks = self._peak_zmp(com, feet_in_world, duration_s)
        if peaks is None:
            return math.inf  # the ground would have to pull the robot down
        acc, force, zmp = peaks
        qk = q[1:3]
        rel = feet_in_world[None, :, :2] - zmp[:, None, :]
        contact = np.ones((2, 4), dtype=bool)
        r = support_reactions(rel, contact, force[:, 2])
        if np.any(r.unloadable):
            return math.inf
        per_foot = r.force[..., None] * (force / force[:, 2:3])[:, None, :]  # (2, 4, 3) in W
        per_foot_in_base = per_foot @ rotation_z(float(yaw))
        robot = self.model.robot
        zeros = np.zeros_like(qk)
        tau = motion_torques(robot, qk, zeros, zeros, gravity=g)
        for k, leg in enumerate(robot.legs):
            jac = jacobian(leg, qk[:, 3 * k : 3 * k + 3])  # (2, 3, 3)
            tau[:, 3 * k : 3 * k + 3] -= np.einsum("nij,ni->nj", jac, per_foot_in_base[:, k])
        return float(np.max(np.abs(tau) / self.budget_nm))

    def units(self, base_start, base_end, yaw: float, feet_in_world, nominal_units: float) -> float:
        """The duration [units] of a four-foot body move from ``base_start`` to ``base_end``
        (3,) [m] at heading ``yaw`` [rad] with the feet at ``feet_in_world`` (4, 3) [m]:
        ``nominal_units`` when its torques keep the budget, else the shortest longer one that
        does, a multiple of DURATION_STEP_UNITS (module docstring)."""
        base_start = np.asarray(base_start, dtype=float)
        base_end = np.asarray(base_end, dtype=float)
        feet = np.asarray(feet_in_world, dtype=float)
        if float(np.hypot(*(base_end[:2] - base_start[:2]))) <= 1e-9:
            return nominal_units
        try:
            poses = self._poses(base_start, base_end, yaw, feet)
        except Silo4Error:
            return nominal_units
        if poses is None:
            return nominal_units
        q, com = poses
        units = _shortest(
            lambda u: self.torque_ratio(q, com, feet, yaw, u * self.unit_time_s) <= 1.0,
            nominal_units,
        )
        if self.zmp_margin_m > 0.0:
            units = max(
                units,
                _shortest(
                    lambda u: self.zmp_margin(com, feet, u * self.unit_time_s) >= self.zmp_margin_m,
                    nominal_units,
                ),
            )
        return units


def _shortest(keeps: Callable[[float], bool], nominal_units: float) -> float:
    """``nominal_units`` when ``keeps`` it, else the shortest longer multiple of
    DURATION_STEP_UNITS up to MAX_STRETCH x that keeps (bisection: a longer move's
    acceleration is smaller); ``nominal_units`` when none does (the pose itself breaks the
    rule: the run's checks say so)."""
    if keeps(nominal_units):
        return nominal_units
    longest = MAX_STRETCH * nominal_units
    if not keeps(longest):
        return nominal_units
    lo = math.ceil(nominal_units / DURATION_STEP_UNITS - 1e-9)
    hi = math.ceil(longest / DURATION_STEP_UNITS - 1e-9)
    while hi - lo > 1:  # lo fails, hi keeps
        mid = (lo + hi) // 2
        if keeps(mid * DURATION_STEP_UNITS):
            hi = mid
        else:
            lo = mid
    return hi * DURATION_STEP_UNITS


def sway_timing_for(
    model: Any, headroom: float | tuple[float, ...], unit_time_s: float, zmp_margin_m: float = 0.0
) -> SwayTiming:
    """The rule for a PlanningModel at the preset's torque ``headroom`` (fraction of the URDF
    effort), the plan's unit time [s] and the ZMP's least margin ``zmp_margin_m`` [m] (the
    lift threshold; <= 0: no ZMP rule)."""
    _, effort = urdf_limits(model.robot)
    return SwayTiming(
        model,
        effort * np.asarray(headroom, dtype=float),
        float(unit_time_s),
        zmp_margin_m=float(zmp_margin_m),
    )
