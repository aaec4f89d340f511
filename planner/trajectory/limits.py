"""URDF velocity and effort limits along a plan; the shortest unit time that keeps them.

A plan's geometry does not depend on the unit time T = unit_time_s (one leg transfer, thesis
§5.5): sampled at T, the joint rates are q̇(T) = q̇₁ / T and the accelerations q̈(T) = q̈₁ / T²,
with q̇₁, q̈₁ the rates at T = 1 s. The joint torques (App. A) are

    τ(T) = τ_static + τ_dyn / T²,

τ_static the support torques Jᵀ(-F) (A.30-A.34: quasi-static reactions, independent of T) plus
the legs' gravity, and τ_dyn = M(q) q̈₁ + C(q, q̇₁) q̇₁, quadratic in the rates (eq A.14-A.29).
The effort budget e of a joint is a fraction of its URDF effort limit (``headroom``, default 1
in these functions; the run pipeline asks for the preset's, planner.presets.TORQUE_HEADROOM
for the default): the sim's
servos clamp at
the URDF limit and add feedback torque on top of the plan's, so a plan at the limit has none
left for them. So a joint keeps its effort budget e for T >= sqrt(τ_dyn / (e - τ_static))
(τ_dyn > 0) or sqrt(-τ_dyn / (e + τ_static)) (τ_dyn < 0), and its velocity limit v for
T >= |q̇₁| / v. The
shortest allowed unit time is the largest of these over samples and joints; it exists when
|τ_static| <= e everywhere (no speed helps a robot too heavy for its motors).

:func:`shortest_unit_time` computes it in closed form and then verifies it with the real torque
computation (planner.trajectory.torques, Pinocchio RNEA + support reactions) on the plan retimed
to it, searching on from it where the load shares make the split depend on T (its docstring);
tests/test_limits.py also finds it by bisection on that real computation.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from planner.errors import PlanningError
from planner.presets import TORQUE_HEADROOM as TORQUE_HEADROOM  # the one value, re-exported
from planner.trajectory.samples import Trajectory
from planner.trajectory.torques import trajectory_torques
from silo4kin.robot import Robot

#: Relative slack on a limit [-]: 1e-9 of it (rounding in the torque computation, ~1e-12).
LIMIT_RTOL = 1e-9
#: The closed-form unit time is rounded up to this [s] (printed and stored values).
UNIT_TIME_RESOLUTION_S = 1e-4
#: Doublings of a closed-form unit time that fails the real torque check before giving up
#: (:func:`shortest_unit_time`), and the bisection's relative tolerance after them.
VERIFY_STEPS = 8
BISECTION_RTOL = 1e-3


class JointLimitError(PlanningError):
    """A plan breaks a URDF velocity or effort limit: names the joint, value, limit and time.

    ``motion_share``: where the plan keeps every velocity limit and its torques standing
    still keep the effort budget, so that only its motion breaks the budget at the unit time
    asked for, what its motion adds to each joint's torque where that joint breaks the
    budget, max (|τ| - |τ_static|) / URDF effort over those samples, (12,) (0 for a joint
    that keeps it); None otherwise."""

    def __init__(self, reason: str, motion_share: np.ndarray | None = None) -> None:
        super().__init__(reason)
        self.motion_share = motion_share


@dataclass(frozen=True)
class LimitCheck:
    """Worst use of the URDF limits along a plan at its unit time.

    Attributes:
        unit_time_s: the plan's unit time [s].
        shortest_unit_time_s: the shortest unit time keeping every limit [s].
        velocity_ratio: largest |q̇| / velocity limit [-].
        effort_ratio: largest |τ| / effort limit [-].
        violation: one line naming joint, value, limit and time, or None.
    """

    unit_time_s: float
    shortest_unit_time_s: float
    velocity_ratio: float
    effort_ratio: float
    violation: str | None

    def to_dict(self) -> dict[str, object]:
        """JSON-able summary (metrics.json "joint_limits")."""
        return {
            "unit_time_s": self.unit_time_s,
            "shortest_unit_time_s": self.shortest_unit_time_s,
            "velocity_ratio": self.velocity_ratio,
            "effort_ratio": self.effort_ratio,
        }


def urdf_limits(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """(velocity [rad/s], effort [N m]) limits of the 12 joints in our joint order, (12,)
    each, from the URDF (Pinocchio's velocityLimit / effortLimit, mapped by joint name)."""
    idx = [robot.model.joints[robot.model.getJointId(n)].idx_v for n in robot.joint_names]
    return (
        np.asarray(robot.model.velocityLimit, float)[idx],
        np.asarray(robot.model.effortLimit, float)[idx],
    )


def retime(trajectory: Trajectory, unit_time_s: float) -> Trajectory:
    """The same plan at another unit time [s]: t scaled, q̇ by T₀/T, q̈ by (T₀/T)²; torques
    dropped (they change: compute them again)."""
    k = trajectory.unit_time_s / float(unit_time_s)
    return replace(
        trajectory,
        t=trajectory.t / k,
        unit_time_s=float(unit_time_s),
        qd=trajectory.qd * k,
        qdd=trajectory.qdd * k * k,
        tau=None,
        tau_parts={},
    )


def at_rest(trajectory: Trajectory) -> Trajectory:
    """The plan standing still at every sample: q̇ = q̈ = 0, torques dropped (its torques are
    the static ones of the limit check, eq A.14 + A.34)."""
    return replace(
        trajectory,
        qd=np.zeros_like(trajectory.qd),
        qdd=np.zeros_like(trajectory.qdd),
        tau=None,
        tau_parts={},
    )


def _torques(robot: Robot, trajectory: Trajectory, load: str) -> np.ndarray:
    return trajectory_torques(robot, trajectory, load=load).total  # type: ignore[arg-type]


def _static_and_dynamic(
    robot: Robot, trajectory: Trajectory, load: str
) -> tuple[np.ndarray, np.ndarray]:
    """(τ_static, τ_dyn) (N, 12) [N m, N m s²] of the module docstring, from two real torque
    computations: at rest (q̇ = q̈ = 0) and at the plan's unit time."""
    tau_static = _torques(robot, at_rest(trajectory), load)
    tau_dyn = (_torques(robot, trajectory, load) - tau_static) * trajectory.unit_time_s**2
    return tau_static, tau_dyn


def _budget(robot: Robot, headroom: float) -> tuple[np.ndarray, np.ndarray]:
    """(velocity limits [rad/s], effort budget = headroom x URDF effort [N m]), (12,) each."""
    if not 0.0 < headroom <= 1.0:
        raise PlanningError(f"torque headroom {headroom!r}: give a fraction in (0, 1]")
    vel, eff = urdf_limits(robot)
    return vel, eff * headroom


def _effort_words(headroom: float) -> str:
    if headroom == 1.0:
        return "URDF effort limit"
    return f"effort budget ({headroom:g} x URDF, --torque-headroom)"


def _first_violation(
    robot: Robot, trajectory: Trajectory, tau: np.ndarray, headroom: float = 1.0
) -> str | None:
    """One line for the earliest sample breaking a limit, or None."""
    vel, eff = _budget(robot, headroom)
    over_v = np.abs(trajectory.qd) > vel * (1 + LIMIT_RTOL)
    over_e = np.abs(tau) > eff * (1 + LIMIT_RTOL)
    rows = np.flatnonzero(np.any(over_v | over_e, axis=1))
    if rows.size == 0:
        return None
    i = int(rows[0])
    t = float(trajectory.t[i])
    if over_v[i].any():
        j = int(np.argmax(np.abs(trajectory.qd[i]) / vel))
        return (
            f"joint {trajectory.joint_names[j]} velocity {abs(trajectory.qd[i, j]):.3f} rad/s "
            f"exceeds its URDF limit {vel[j]:.3f} rad/s at t = {t:.3f} s"
        )
    j = int(np.argmax(np.abs(tau[i]) / eff))
    return (
        f"joint {trajectory.joint_names[j]} torque {abs(tau[i, j]):.2f} N m exceeds its "
        f"{_effort_words(headroom)} {eff[j]:.2f} N m at t = {t:.3f} s"
    )


def check_static_effort(
    robot: Robot, trajectory: Trajectory, load: str = "body", headroom: float = 1.0
) -> None:
    """Raise JointLimitError when the plan's static torques (q̇ = q̈ = 0, eq A.30-A.34) alone
    break the effort budget ``headroom`` x URDF effort: no unit time helps (as
    :func:`shortest_unit_time_closed_form`, without the dynamic part)."""
    _, eff = _budget(robot, headroom)
    tau_static = _torques(robot, at_rest(trajectory), load)
    _refuse_static_over(trajectory, tau_static, eff, headroom)


def _refuse_static_over(
    trajectory: Trajectory, tau_static: np.ndarray, eff: np.ndarray, headroom: float = 1.0
) -> None:
    """JointLimitError at the first sample whose static torque breaks an effort limit."""
    over = np.abs(tau_static) > eff * (1 + LIMIT_RTOL)
    if over.any():
        i, j = (int(a[0]) for a in np.nonzero(over))
        raise JointLimitError(
            f"joint {trajectory.joint_names[j]} needs {abs(tau_static[i, j]):.2f} N m standing "
            f"still, above its {_effort_words(headroom)} {eff[j]:.2f} N m, at t_units = "
            f"{trajectory.time_units[i]:.2f}: no unit time helps"
        )


def limit_violation(
    robot: Robot, trajectory: Trajectory, load: str = "body", headroom: float = 1.0
) -> str | None:
    """One line for the earliest sample of ``trajectory`` (at its unit time) breaking a URDF
    velocity or effort limit, or None: one torque computation, no unit-time search (the
    default gait "auto" drops a crawl that breaks one, planner/path/plan_path.py)."""
    return _first_violation(robot, trajectory, _torques(robot, trajectory, load), headroom)


def shortest_unit_time_closed_form(
    robot: Robot, trajectory: Trajectory, load: str = "body", headroom: float = 1.0
) -> float:
    """Shortest unit time [s] keeping every URDF velocity and effort limit (module
    docstring), not rounded. Raises JointLimitError when a static torque alone breaks an
    effort limit (names joint, value, limit, time)."""
    vel, eff = _budget(robot, headroom)
    rates_1s = np.abs(trajectory.qd) * trajectory.unit_time_s  # q̇ at T = 1 s
    t_vel = float(np.max(rates_1s / vel)) if rates_1s.size else 0.0
    tau_static, tau_dyn = _static_and_dynamic(robot, trajectory, load)
    _refuse_static_over(trajectory, tau_static, eff, headroom)
    room = np.where(tau_dyn > 0, eff - tau_static, eff + tau_static)
    need = np.abs(tau_dyn) / np.maximum(room, 1e-300)
    t_eff = float(np.sqrt(np.max(need))) if need.size else 0.0
    return max(t_vel, t_eff)


def shortest_unit_time(
    robot: Robot, trajectory: Trajectory, load: str = "body", headroom: float = 1.0
) -> float:
    """Shortest unit time [s], rounded up to UNIT_TIME_RESOLUTION_S, verified with the real
    torque computation on the plan retimed to it.

    The closed form is exact where the load split does not depend on T: App. A's (load
    "body", transfer 0). The whole robot's split passes the load between the feet over
    LOAD_TRANSFER_S seconds (silo4kin/load_transfer.py), a share of a different number of
    samples at each T, and the floating robot (load "total") spreads its dynamic wrench by
    those shares: there a closed-form time that fails the check is a lower bound, and the
    time is found by bisection on the real check between it and a time that passes (the
    plan's own unit time when it passes, else doubled from the closed form), to
    BISECTION_RTOL of it (PlanningError when VERIFY_STEPS doublings find none)."""
    low = _rounded_up(shortest_unit_time_closed_form(robot, trajectory, load, headroom))

    def passes(t_s: float) -> bool:
        fast = retime(trajectory, t_s)
        return _first_violation(robot, fast, _torques(robot, fast, load), headroom) is None

    if passes(low):
        return low
    high = float(trajectory.unit_time_s)
    if high <= low or not passes(high):
        high = 2.0 * low
        for _ in range(VERIFY_STEPS):
            if passes(high):
                break
            low, high = high, 2.0 * high
        else:
            fast = retime(trajectory, high)
            raise PlanningError(
                f"no unit time up to {high:.4f} s passes the torque check: "
                f"{_first_violation(robot, fast, _torques(robot, fast, load), headroom)}"
            )
    while high - low > max(BISECTION_RTOL * high, UNIT_TIME_RESOLUTION_S):
        mid = _rounded_up(0.5 * (low + high))
        if mid >= high:
            break
        if passes(mid):
            high = mid
        else:
            low = mid
    return high


def _rounded_up(t_s: float) -> float:
    """``t_s`` rounded up to UNIT_TIME_RESOLUTION_S, at least one step [s]."""
    return max(
        float(np.ceil(t_s / UNIT_TIME_RESOLUTION_S)) * UNIT_TIME_RESOLUTION_S,
        UNIT_TIME_RESOLUTION_S,
    )


def check_limits(
    robot: Robot, trajectory: Trajectory, load: str = "body", headroom: float = 1.0
) -> LimitCheck:
    """Velocity and effort use along the plan at its unit time, and the shortest allowed one
    (effort_ratio: of the URDF effort limit; the violation and the unit time: of the budget)."""
    vel, eff = urdf_limits(robot)
    tau = _torques(robot, trajectory, load)
    return LimitCheck(
        unit_time_s=float(trajectory.unit_time_s),
        shortest_unit_time_s=shortest_unit_time(robot, trajectory, load, headroom),
        velocity_ratio=float(np.max(np.abs(trajectory.qd) / vel)),
        effort_ratio=float(np.max(np.abs(tau) / eff)),
        violation=_first_violation(robot, trajectory, tau, headroom),
    )


def enforce_limits(
    robot: Robot,
    trajectory: Trajectory,
    unit_time: float | str,
    load: str = "body",
    headroom: float = 1.0,
) -> tuple[Trajectory, LimitCheck]:
    """The trajectory at ``unit_time`` [s] if it keeps every URDF limit (else JointLimitError
    naming joint, value, limit and time), or retimed to the shortest allowed unit time when
    ``unit_time`` is "auto"; with the check at the returned unit time."""
    if unit_time == "auto":
        t_star = shortest_unit_time(robot, trajectory, load, headroom)
        trajectory = retime(trajectory, t_star)
    else:
        trajectory = retime(trajectory, float(unit_time))
    check = check_limits(robot, trajectory, load, headroom)  # refuses a static excess
    if check.violation is not None:
        raise JointLimitError(
            f"{check.violation} (unit time {check.unit_time_s:g} s; shortest "
            f"allowed {check.shortest_unit_time_s:.4f} s, or --unit-time auto)",
            motion_share=motion_share(robot, trajectory, load, headroom),
        )
    return trajectory, check


def motion_share(
    robot: Robot, trajectory: Trajectory, load: str = "body", headroom: float = 1.0
) -> np.ndarray | None:
    """What the plan's motion adds to each joint's torque where that joint breaks the effort
    budget at the plan's unit time, max (|τ| - |τ_static|) / URDF effort over those samples,
    (12,) (0 for a joint that keeps it): JointLimitError.motion_share. None where a velocity
    limit is broken, a static torque breaks the budget, or no joint breaks it."""
    vel, effort = urdf_limits(robot)
    if np.any(np.abs(trajectory.qd) > vel * (1 + LIMIT_RTOL)):
        return None
    still = np.abs(_torques(robot, at_rest(trajectory), load))
    if np.any(still > effort * headroom * (1 + LIMIT_RTOL)):
        return None
    moving = np.abs(_torques(robot, trajectory, load))
    over = moving > effort * headroom * (1 + LIMIT_RTOL)
    added = np.where(over, np.maximum(moving - still, 0.0) / effort, 0.0).max(axis=0)
    return added if np.any(added > 0.0) else None


def limit_plan(
    robot: Robot, plan, unit_time: float | str, load: str = "body", headroom: float = 1.0
):
    """:func:`enforce_limits` on a :class:`~planner.path.plan_path.Plan`: (the plan, at
    ``unit_time`` [s] or the shortest allowed one for "auto", and its LimitCheck)."""
    trajectory, check = enforce_limits(robot, plan.trajectory, unit_time, load, headroom)
    return replace(plan, trajectory=trajectory), check
