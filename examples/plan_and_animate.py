"""Plan the thesis straight path, add joint torques, print the metrics, write the animation."""

from pathlib import Path

import numpy as np

from planner import plan_path
from planner.path.metrics import compute_metrics
from planner.trajectory.torques import add_torques
from silo4kin import load_robot
from viz.animation.page import write_animation_html

if __name__ == "__main__":
    robot = load_robot()
    waypoints_in_world = np.array([[0.0, 1.0], [1.0, 1.0], [0.0, 2.0], [0.0, 3.0]])  # [m]
    plan = plan_path(robot, waypoints_in_world, height=0.4, start_heading=np.pi / 2)
    trajectory = add_torques(robot, plan.trajectory)  # tau = leg motion + body support
    metrics = compute_metrics(plan)
    print(
        f"{metrics['normalized_time']:.0f} time units, {metrics['distance_m']:.2f} m, "
        f"E_n {metrics['normalized_error_m']:.3f} m, "
        f"min margin {metrics['min_stability_margin_m']:.3f} m"
    )
    print(
        "peak |tau| per joint [N m]:",
        dict(zip(trajectory.joint_names, np.round(np.abs(trajectory.tau).max(axis=0), 1))),
    )
    out = write_animation_html(
        Path("straight_path.html"), robot, trajectory, waypoints_in_world=waypoints_in_world
    )
    print(f"open {out.resolve().as_uri()}")
