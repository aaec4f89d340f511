"""``silo4 export RUN``: a saved run for robots (ROS 2 bag, ros2_control goal).

    silo4 export out/straight --ros2 out/straight.bag
    silo4 export out/straight --ros2 out/straight.bag --goal-yaml out/straight_goal.yaml

Reads ``RUN/trajectory.npz`` (exact, with the URDF root link's pose) and writes what
viz/export/ros2.py describes. No ROS
install is needed (the pure-Python ``rosbags`` library writes the MCAP bag).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from silo4kin.errors import Silo4Error


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``export``."""
    p = sub.add_parser(
        "export", help="export a run for a ROS 2 robot (rosbag2 MCAP, ros2_control goal)",
        description="Write a run's joint trajectory (trajectory_msgs/JointTrajectory) and body "
                    "path (nav_msgs/Path) into a rosbag2 (MCAP), and/or a "
                    "FollowJointTrajectory goal YAML for a ros2_control "
                    "JointTrajectoryController. No ROS install needed.",
        epilog="example: silo4 export out/straight --ros2 out/straight.bag "
               "--goal-yaml out/straight_goal.yaml")
    p.add_argument("run_dir", metavar="RUN", help="run folder written by 'silo4 plan'")
    p.add_argument("--ros2", metavar="BAG", default=None,
                   help="rosbag2 folder to write (MCAP storage)")
    p.add_argument("--goal-yaml", metavar="FILE", default=None,
                   help="FollowJointTrajectory goal for ros2 action send_goal")
    p.add_argument("--force", action="store_true",
                   help="replace an existing BAG folder silo4 wrote (never your own files)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Read the run, write the requested exports, name them."""
    if args.ros2 is None and args.goal_yaml is None:
        raise Silo4Error("nothing to export: give --ros2 BAG and/or --goal-yaml FILE")
    import numpy as np

    from planner.outputs.files import check_target
    from planner.outputs.root_pose import root_pose_in_world
    from planner.outputs.run_folder import run_inputs
    from planner.outputs.trajectory_npz import read_root_pose_npz, read_trajectory_npz
    from viz.export.ros2 import check_bag_target, write_joint_trajectory_goal, write_ros2_bag

    npz = Path(args.run_dir) / "trajectory.npz"
    trajectory = read_trajectory_npz(npz)
    root_pose = read_root_pose_npz(npz)
    if root_pose is None:  # a run written before the pose was recorded
        if args.ros2 is not None:
            print(f"warning: {npz} has no URDF root link pose (an older run): /body_path "
                  "holds the body CoG frame B_c; plan again for the root link",
                  file=sys.stderr)
        root_pose = root_pose_in_world(trajectory, np.zeros(3))
    inputs = run_inputs(args.run_dir)  # the run is never a target (docs/errors.md)
    # both targets before either is written: a refusal changes nothing
    if args.ros2 is not None:
        check_bag_target(args.ros2, force=args.force, inputs=inputs)
    if args.goal_yaml is not None:
        check_target(args.goal_yaml, inputs=inputs, what="--goal-yaml")
        if args.ros2 is not None and Path(args.goal_yaml).absolute() == Path(
                args.ros2).absolute():
            raise Silo4Error(f"--goal-yaml {args.goal_yaml} is the --ros2 bag folder too; "
                             "give them different names")
    written = []
    if args.ros2 is not None:
        written.append(write_ros2_bag(args.ros2, trajectory, root_pose, force=args.force,
                                      inputs=inputs))
    if args.goal_yaml is not None:
        written.append(write_joint_trajectory_goal(args.goal_yaml, trajectory, inputs=inputs))
    print(f"exported {len(trajectory)} samples ({float(trajectory.t[-1]):.2f} s): "
          + ", ".join(str(w) for w in written))
    return 0
