"""A plan as a ros2_control ``control_msgs/action/FollowJointTrajectory`` goal (YAML).

    write_joint_trajectory_goal("out/goal.yaml", trajectory, GoalFields(rate_hz=50.0))
    # also writes out/send_goal.py, the sender for the robot's computer

What the goal holds is a :class:`GoalFields`: the points on a rate grid, positions [rad],
velocities [rad/s] and accelerations [rad/s^2], and effort [N m] only when asked
(joint_trajectory_controller of Humble refuses a trajectory with effort; later ones take it
only when they command effort).

Resampling keeps plan samples, unchanged: for every time ``k / rate_hz`` (k = 0, 1, ... up to
the plan's duration) the nearest sample (the earlier on a tie), each sample at most once, and
always the first and the last; each point keeps its sample's own time, so a point is the plan
exactly (q, qd, qdd of one sample, bit for bit: numbers are written with ``repr``). A plan
sampled more coarsely than ``rate_hz`` keeps every sample. Between points the controller
interpolates (a quintic spline from positions, velocities and accelerations); a cubic Hermite
from positions and velocities stays within :data:`INTERPOLATION_TOLERANCE_RAD` of the plan's
samples at 50 Hz (tests/test_ros2_export.py).

Sending: ``ros2 action send_goal ... "$(cat goal.yaml)"`` passes the goal as one argument, and
Linux limits one argument to 128 KiB (MAX_ARG_STRLEN): a few hundred points. The sender
``send_goal.py`` written beside the goal (:data:`SENDER`, this package's ``send_goal.py``, which
needs rclpy and control_msgs only) reads the file instead (docs/outputs.md).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from planner.outputs.files import check_target, record_written, write_atomic
from planner.trajectory.samples import Trajectory
from silo4kin.errors import Silo4Error
from viz.export.ros2_messages import sample_times_ns

#: Default goal rate [Hz].
DEFAULT_GOAL_RATE_HZ = 50.0
#: Largest goal rate [Hz] (a ros2_control loop rarely runs faster).
MAX_GOAL_RATE_HZ = 10_000.0
#: A cubic Hermite of the points kept at 50 Hz (q, qd) meets every plan sample within this
#: [rad] (3e-6 rad on the test plan, 100 samples per second).
INTERPOLATION_TOLERANCE_RAD = 1e-4
#: Linux's limit on one command-line argument (MAX_ARG_STRLEN) [bytes].
ARGUMENT_LIMIT_BYTES = 128 * 1024
#: The sender script written beside the goal (standalone: rclpy, control_msgs, PyYAML).
SENDER = Path(__file__).with_name("send_goal.py")
_NS = 1_000_000_000


@dataclass(frozen=True)
class GoalFields:
    """What a goal holds.

    Attributes:
        rate_hz: the rate grid the points are picked on [Hz], in (0, MAX_GOAL_RATE_HZ].
        with_effort: add each point's joint torques [N m] (the plan must have them).
    """

    rate_hz: float = DEFAULT_GOAL_RATE_HZ
    with_effort: bool = False

    def __post_init__(self) -> None:
        if not (0.0 < float(self.rate_hz) <= MAX_GOAL_RATE_HZ):  # also refuses NaN
            raise Silo4Error(
                f"--goal-rate {self.rate_hz}: must be in (0, {MAX_GOAL_RATE_HZ:g}] [Hz]"
            )


def resampled_indices(t: np.ndarray, rate_hz: float) -> np.ndarray:
    """Indices of the samples the goal keeps (module docstring), (M,) increasing.

    Args:
        t: (N,) sample times [s], increasing.
        rate_hz: the rate grid [Hz].
    """
    t = np.asarray(t, dtype=float) - float(t[0])
    if not np.all(np.isfinite(t)):
        raise Silo4Error("trajectory times must be finite")
    grid = np.arange(int(np.floor(t[-1] * rate_hz + 1e-9)) + 1) / rate_hz
    after = (
        np.clip(np.searchsorted(t, grid), 1, len(t) - 1)
        if len(t) > 1
        else np.zeros(len(grid), dtype=int)
    )
    before = np.maximum(after - 1, 0)
    nearest = np.where(np.abs(t[after] - grid) < np.abs(grid - t[before]), after, before)
    return np.unique(np.concatenate([[0], nearest, [len(t) - 1]]))


def _flow(values: np.ndarray) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def check_goal_fields(trajectory: Trajectory, fields: GoalFields) -> None:
    """Refuse effort asked of a plan without torques."""
    if fields.with_effort and trajectory.tau is None:
        raise Silo4Error(
            "--with-effort: the run has no joint torques (planned with "
            "--no-torques); plan again with torques"
        )


def joint_trajectory_goal_yaml(trajectory: Trajectory, fields: GoalFields) -> str:
    """The goal (module docstring) as YAML text: the FollowJointTrajectory goal's
    ``trajectory`` field, the others left at their defaults."""
    check_goal_fields(trajectory, fields)
    keep = resampled_indices(trajectory.t, fields.rate_hz)
    offsets = sample_times_ns(trajectory, 0)[keep]  # time_from_start [ns]
    units = "positions [rad], velocities [rad/s], accelerations [rad/s^2]" + (
        ", effort [N m]" if fields.with_effort else ""
    )
    lines = [
        "# control_msgs/action/FollowJointTrajectory goal written by silo4 export",
        f"# {len(keep)} of the plan's {len(trajectory)} samples (nearest to a "
        f"{fields.rate_hz:g} Hz grid); {units}",
        "# send it with: python3 send_goal.py THIS_FILE (beside it)",
        "trajectory:",
        "  header: {stamp: {sec: 0, nanosec: 0}, frame_id: ''}",
        "  joint_names: [" + ", ".join(trajectory.joint_names) + "]",
        "  points:",
    ]
    tau = trajectory.tau if fields.with_effort else None
    for k, ns in zip(keep, offsets):
        lines.append(f"    - positions: {_flow(trajectory.q[k])}")
        lines.append(f"      velocities: {_flow(trajectory.qd[k])}")
        lines.append(f"      accelerations: {_flow(trajectory.qdd[k])}")
        if tau is not None:
            lines.append(f"      effort: {_flow(tau[k])}")
        lines.append(f"      time_from_start: {{sec: {int(ns) // _NS}, nanosec: {int(ns) % _NS}}}")
    return "\n".join(lines) + "\n"


def sender_path(goal: str | Path) -> Path:
    """Where the sender script goes: ``send_goal.py`` beside the goal."""
    return Path(goal).with_name(SENDER.name)


def check_goal_targets(path: str | Path, *, inputs: Iterable[str | Path] = ()) -> None:
    """Whether the goal and its sender may be written (planner.outputs.files.check_target)."""
    check_target(path, inputs=inputs, what="--goal-yaml")
    check_target(sender_path(path), inputs=inputs, what="--goal-yaml (its send_goal.py)")


def write_joint_trajectory_goal(
    path: str | Path,
    trajectory: Trajectory,
    fields: GoalFields = GoalFields(),
    *,
    inputs: Iterable[str | Path] = (),
) -> Path:
    """Write the goal YAML and ``send_goal.py`` beside it, each atomically, and record them in
    the ``.silo4-files`` of their folder (so a rerun may replace them); a file silo4 did not
    write, or an input, is refused (planner.outputs.files.check_target). Returns the goal."""
    check_goal_targets(path, inputs=inputs)
    text = joint_trajectory_goal_yaml(trajectory, fields)
    sender = SENDER.read_text(encoding="utf-8")
    written = write_atomic(Path(path), lambda tmp: tmp.write_text(text), make_parents=True)
    script = write_atomic(sender_path(path), lambda tmp: tmp.write_text(sender))
    record_written([written, script])
    return written
