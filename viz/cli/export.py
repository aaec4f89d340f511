"""``silo4 export RUN``: a saved run for robots (ROS 2 bag, ros2_control goal).

    silo4 export out/straight --ros2 out/straight.bag
    silo4 export out/straight --goal-yaml out/robot/goal.yaml --goal-rate 100 --with-effort

Reads ``RUN/trajectory.npz`` (exact, with the URDF root link's pose) and, for the bag, the
robot ``RUN/plan.json`` records (``robot_source``, as ``silo4 animate``; ``--robot`` overrides
it), and writes what viz/export/ros2.py and viz/export/goal.py describe. No ROS install is
needed (the pure-Python ``rosbags`` library writes the MCAP bag).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

from silo4kin.errors import Silo4Error
from viz.cli.common import add_robot_arguments

#: Default ``--start-time`` [s since the Unix epoch]: 2000-01-01T00:00:00Z
#: (viz.export.ros2_messages.DEFAULT_START_TIME_NS; kept here so ``--help`` imports no numpy).
DEFAULT_START_TIME_S = 946_684_800
#: Default ``--goal-rate`` [Hz] (viz.export.goal.DEFAULT_GOAL_RATE_HZ).
DEFAULT_GOAL_RATE_HZ = 50.0


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``export``."""
    p = sub.add_parser(
        "export",
        help="export a run for a ROS 2 robot (rosbag2 MCAP, ros2_control goal)",
        description="Write a run into a rosbag2 (MCAP) that RViz replays (/joint_states, /tf, "
        "/tf_static, /robot_description, the JointTrajectory and the body path), "
        "and/or a FollowJointTrajectory goal YAML for a ros2_control "
        "joint_trajectory_controller with send_goal.py beside it. No ROS install "
        "needed.",
        epilog="example: silo4 export out/straight --ros2 out/straight.bag "
        "--goal-yaml out/straight_goal.yaml",
    )
    p.add_argument("run_dir", metavar="RUN", help="run folder written by 'silo4 plan'")
    p.add_argument(
        "--ros2", metavar="BAG", default=None, help="rosbag2 folder to write (MCAP storage)"
    )
    p.add_argument(
        "--start-time",
        metavar="S",
        type=float,
        default=DEFAULT_START_TIME_S,
        help="bag time of the first sample [s since the Unix epoch] (default "
        f"{DEFAULT_START_TIME_S}: 2000-01-01T00:00:00Z, so a run gives the "
        "same bag every time)",
    )
    p.add_argument(
        "--goal-yaml",
        metavar="FILE",
        default=None,
        help="FollowJointTrajectory goal to write (send_goal.py goes beside it)",
    )
    p.add_argument(
        "--goal-rate",
        metavar="HZ",
        type=float,
        default=DEFAULT_GOAL_RATE_HZ,
        help=f"goal points: the plan's samples nearest to a HZ grid (default "
        f"{DEFAULT_GOAL_RATE_HZ:g})",
    )
    p.add_argument(
        "--with-effort",
        action="store_true",
        help="add joint torques to the goal (Humble's joint_trajectory_controller refuses them)",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="replace an existing BAG folder silo4 wrote (never your own files)",
    )
    add_robot_arguments(p)
    p.set_defaults(run=run)


def _plan_document(run_dir: Path) -> dict[str, Any]:
    """RUN/plan.json (its robot_source names the robot), or {} without a readable one."""
    import json

    try:
        document = json.loads((run_dir / "plan.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return document if isinstance(document, dict) else {}


def _start_time_ns(seconds: float) -> int:
    if not math.isfinite(seconds) or not 0 < seconds < 2**63 / 1e9:
        raise Silo4Error(
            f"--start-time {seconds:g}: must be a time > 0 [s since the Unix epoch], before 2262"
        )
    return int(round(seconds * 1e9))


def run(args: argparse.Namespace) -> int:
    """Read the run, write the requested exports, name them."""
    if args.ros2 is None and args.goal_yaml is None:
        raise Silo4Error("nothing to export: give --ros2 BAG and/or --goal-yaml FILE")
    start_time_ns = _start_time_ns(args.start_time)
    import numpy as np

    from planner.outputs.root_pose import root_pose_in_world
    from planner.outputs.run_folder import run_inputs
    from planner.outputs.trajectory_npz import read_root_pose_npz, read_trajectory_npz
    from viz.cli.common import load_robot_from_args, recorded_robot_args
    from viz.export.goal import (
        ARGUMENT_LIMIT_BYTES,
        GoalFields,
        check_goal_fields,
        check_goal_targets,
        resampled_indices,
        sender_path,
        write_joint_trajectory_goal,
    )
    from viz.export.robot_frames import RobotFrames
    from viz.export.ros2 import check_bag_target, write_ros2_bag

    fields = GoalFields(rate_hz=args.goal_rate, with_effort=args.with_effort)
    inputs = run_inputs(args.run_dir)  # the run is never a target (docs/errors.md)
    # both targets before either is written: a refusal changes nothing
    if args.ros2 is not None:
        check_bag_target(args.ros2, force=args.force, inputs=inputs)
    if args.goal_yaml is not None:
        check_goal_targets(args.goal_yaml, inputs=inputs)
        if args.ros2 is not None and Path(args.goal_yaml).absolute() == Path(args.ros2).absolute():
            raise Silo4Error(
                f"--goal-yaml {args.goal_yaml} is the --ros2 bag folder too; "
                "give them different names"
            )
    npz = Path(args.run_dir) / "trajectory.npz"
    trajectory = read_trajectory_npz(npz)
    if args.goal_yaml is not None:
        check_goal_fields(trajectory, fields)
    written: list[Path | str] = []
    if args.ros2 is not None:
        robot = load_robot_from_args(recorded_robot_args(args, _plan_document(Path(args.run_dir))))
        frames = RobotFrames(robot.urdf_xml, trajectory.joint_names)
        root_pose = read_root_pose_npz(npz)
        if root_pose is None:  # a run written before the pose was recorded
            print(
                f"warning: {npz} has no URDF root link pose (an older run): /tf and "
                "/body_path hold the body CoG frame B_c; plan again for the root link",
                file=sys.stderr,
            )
            root_pose = root_pose_in_world(trajectory, np.zeros(3))
        written.append(
            write_ros2_bag(
                args.ros2,
                trajectory,
                root_pose,
                frames,
                robot.urdf_xml,
                start_time_ns=start_time_ns,
                force=args.force,
                inputs=inputs,
            )
        )
    if args.goal_yaml is not None:
        goal = write_joint_trajectory_goal(args.goal_yaml, trajectory, fields, inputs=inputs)
        points = len(resampled_indices(trajectory.t, fields.rate_hz))
        size = goal.stat().st_size
        how = (
            f"over the {ARGUMENT_LIMIT_BYTES // 1024} KiB of one argument, send it with"
            if size > ARGUMENT_LIMIT_BYTES
            else "send it with"
        )
        written.append(
            f"{goal} ({points} points, {size / 1024:.0f} KiB; {how} python3 "
            f"{sender_path(goal)} {goal})"
        )
    print(
        f"exported {len(trajectory)} samples ({float(trajectory.t[-1]):.2f} s): "
        + ", ".join(str(w) for w in written)
    )
    return 0
