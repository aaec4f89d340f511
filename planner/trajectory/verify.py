"""Sample-level verification of a plan (planner/path/plan_path.py): every sample reachable, finite,
within the joint limits, and stable by the policy's criterion whenever a leg is in the air;
with a contact-force check, every stance foot loaded and within the plan's friction
(planner/stability/contact_forces.py).

The step builder checks stability before any joint value exists; this is the independent second
check on the samples that are written (the margin of planner/trajectory/sampling.py is computed
from the sampled base, feet and, for the whole-body CoM, the sampled joint values).
"""

from __future__ import annotations

import numpy as np

from planner.errors import PlanningError
from planner.gaits.steps import Step
from planner.stability.contact_forces import ContactForceCheck
from planner.stability.margin import MARGIN_TOLERANCE
from planner.trajectory.clearance import tibia_low, tibia_violation
from planner.trajectory.samples import LEGS, Trajectory
from silo4kin.joint_limits import joint_limit_bounds

#: Slack of the sample-level stability check [m]: the step builder checks the whole-body CoM
#: on SWING_CHECK_SAMPLES configurations of each swing and samples may fall between two of
#: them, where S_m dips by < 1e-6 m (planner/model.py); 0.2 mm is a generous bound.
SAMPLE_MARGIN_SLACK_M = 2e-4


def verify_samples(
    legs,
    traj: Trajectory,
    steps: tuple[Step, ...],
    threshold: float,
    wp: np.ndarray,
    *,
    slack_m: float = 0.0,
    hold_tibias: bool = False,
    terrain=None,
) -> None:
    """Raise PlanningError at the first sample that is unreachable, off limits, or has
    ``traj.margin`` < threshold - slack_m [m] with a leg in the air, or (``hold_tibias``, the
    default preset) a tibia capsule within MIN_TIBIA_CLEARANCE_M of the ground
    (planner/trajectory/clearance.py); ``legs`` the leg geometry (joint limits), ``wp``
    (K, 2) [m] the waypoints (named in the message)."""
    lower, upper = joint_limit_bounds(
        np.concatenate([leg.q_lower for leg in legs]), np.concatenate([leg.q_upper for leg in legs])
    )
    q = traj.q
    finite = np.all(np.isfinite(q) & np.isfinite(traj.qd) & np.isfinite(traj.qdd), axis=1)
    within = np.all((q >= lower) & (q <= upper), axis=1)
    lifted = ~np.all(traj.contact, axis=1)
    stable = ~lifted | (traj.margin >= threshold - slack_m - MARGIN_TOLERANCE)
    tibia_clear = np.asarray(
        ~tibia_low(legs, traj, terrain).any(axis=1) if hold_tibias else np.ones_like(within),
        dtype=bool,
    )
    bad = np.flatnonzero(~(finite & within & stable & tibia_clear))
    if not bad.size:
        return
    i = int(bad[0])
    t_units = traj.time_units[i]
    step = _step_at(steps, t_units)
    if not finite[i]:
        reason = f"a foot target is out of reach or singular at t = {t_units:.2f} units"
    elif not within[i]:
        j = int(np.flatnonzero((q[i] < lower) | (q[i] > upper))[0])
        reason = (
            f"joint {traj.joint_names[j]} = {q[i, j]:.4f} rad leaves "
            f"[{lower[j]:.4f}, {upper[j]:.4f}] at t = {t_units:.2f} units"
            + _under_foot(terrain, traj, i, j // 3)
        )
    elif not tibia_clear[i]:
        reason = str(tibia_violation(legs, traj, terrain))  # its first row is i
    else:
        reason = (
            f"stability margin {traj.margin[i]:.4f} m < threshold {threshold:.4f} m "
            f"at t = {t_units:.2f} units"
        )
    raise _error_at(step, reason, wp)


def _under_foot(terrain, traj: Trajectory, i: int, leg: int) -> str:  # noqa: ANN001
    """On a terrain file's map, what lies under ``leg``'s foot at sample ``i`` and its slope,
    for a refusal beyond a robot's reach ("; foot LF over box 1 of terrain file ramp.yaml,
    12.5 deg from level"); empty on other grounds."""
    if not hasattr(terrain, "describe_at"):
        return ""
    xy = traj.position_foot_in_world[i, leg, :2]
    what = f"; foot {LEGS[leg]} over {terrain.describe_at(xy)} of {terrain.label()}"
    normal_z = float(terrain.normal_at(xy.reshape(1, 2))[0, 2])
    if np.isfinite(normal_z):
        what += f", {np.degrees(np.arccos(np.clip(normal_z, -1.0, 1.0))):.1f} deg from level"
    return what


def _step_at(steps: tuple[Step, ...], t_units: float) -> Step:
    starts = np.array([s.t_start for s in steps])
    return steps[
        int(np.clip(np.searchsorted(starts, t_units, side="right") - 1, 0, len(steps) - 1))
    ]


def _error_at(step: Step, reason: str, wp: np.ndarray) -> PlanningError:
    k = step.waypoint_index
    error = PlanningError(
        f"{reason} ({step.label})", k, None if k is None else (float(wp[k, 0]), float(wp[k, 1]))
    )
    error.step_start_units = float(step.t_start)
    return error


def contact_force_violation(
    traj: Trajectory, steps: tuple[Step, ...], wp: np.ndarray, check: ContactForceCheck
) -> PlanningError | None:
    """The PlanningError of the first sample whose stance feet break ``check``'s rule
    (planner/stability/contact_forces.py), naming foot, time, step and waypoint, or None.
    Checked on the plan at its final unit time (the forces grow as 1 / T²)."""
    if not steps:
        return None
    found = check.first_violation(traj)
    if found is None:
        return None
    i, foot, why = found
    t_units = float(traj.time_units[i])
    reason = f"stance foot {LEGS[foot]}: {why} at t = {t_units:.2f} units ({traj.t[i]:.3f} s)"
    return _error_at(_step_at(steps, t_units), reason, wp)
