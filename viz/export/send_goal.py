#!/usr/bin/env python3
"""Send a FollowJointTrajectory goal YAML (written by ``silo4 export --goal-yaml``) to a
ros2_control joint_trajectory_controller, and wait for the result.

    python3 send_goal.py goal.yaml [/joint_trajectory_controller/follow_joint_trajectory]

Standalone: needs a sourced ROS 2 (rclpy, control_msgs, rosidl_runtime_py) and PyYAML, not
silo4. It reads the file itself, so a goal of any size goes through (``ros2 action send_goal
... "$(cat goal.yaml)"`` stops at 128 KiB, the limit of one command-line argument).
Exit 0 when the controller reports success.
"""

import sys


def main(argv: list) -> int:
    """Load the goal, send it, print the controller's answer; exit code 0 on success."""
    if len(argv) not in (2, 3):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    import rclpy
    import yaml
    from control_msgs.action import FollowJointTrajectory
    from rclpy.action import ActionClient
    from rosidl_runtime_py.set_message import set_message_fields

    action = argv[2] if len(argv) == 3 else "/joint_trajectory_controller/follow_joint_trajectory"
    with open(argv[1], encoding="utf-8") as file:
        goal = FollowJointTrajectory.Goal()
        set_message_fields(goal, yaml.safe_load(file))
    rclpy.init()
    node = rclpy.create_node("silo4_send_goal")
    try:
        client = ActionClient(node, FollowJointTrajectory, action)
        if not client.wait_for_server(timeout_sec=10.0):
            print(f"no action server {action} (is the controller active?)", file=sys.stderr)
            return 1
        print(f"sending {len(goal.trajectory.points)} points to {action}")
        sent = client.send_goal_async(goal)
        rclpy.spin_until_future_complete(node, sent)
        handle = sent.result()
        if not handle.accepted:
            print("goal rejected (see the controller's log)", file=sys.stderr)
            return 1
        done = handle.get_result_async()
        rclpy.spin_until_future_complete(node, done)
        result = done.result().result
        print(f"error_code {result.error_code} {result.error_string}")
        return 0 if result.error_code == FollowJointTrajectory.Result.SUCCESSFUL else 1
    finally:
        node.destroy_node()
        rclpy.shutdown()


if __name__ == "__main__":
    sys.exit(main(sys.argv))
