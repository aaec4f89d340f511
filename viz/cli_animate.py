"""``silo4 animate``: (re)write a run folder's animation.html from its trajectory.npz.

Plays back a saved plan with the same or another visual of the robot, e.g. after changing
the playback speed, without planning again.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from silo4kin.errors import Silo4Error

from .cli import EXIT_OK, add_robot_arguments, load_robot_from_args


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``animate``."""
    p = sub.add_parser(
        "animate", help="write animation.html for a saved run (trajectory.npz)",
        description="Read RUN/trajectory.npz (and the waypoints in RUN/plan.json), load the "
                    "robot, and write a self-contained animation.html (default: into RUN).",
        epilog="example: silo4 animate out/straight --unit-time 0.5")
    p.add_argument("run_dir", metavar="RUN", help="a run folder written by silo4 plan")
    p.add_argument("--out", metavar="FILE.html", default=None,
                   help="output file (default RUN/animation.html)")
    p.add_argument("--unit-time", type=float, default=None, metavar="S",
                   help="play one time unit in S seconds (default: as planned)")
    add_robot_arguments(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Load the run and the robot, write the HTML; a trajectory of another robot: exit 2."""
    import numpy as np

    from planner.export import read_trajectory_npz

    from .animation import write_animation_html

    run_dir = Path(args.run_dir)
    trajectory = read_trajectory_npz(run_dir / "trajectory.npz")
    waypoints = None
    try:
        plan = json.loads((run_dir / "plan.json").read_text())
        waypoints = np.asarray(plan["inputs"]["waypoints_in_world"], dtype=float)
    except (OSError, ValueError, KeyError, TypeError):
        pass  # the animation is still useful without the desired path
    if args.unit_time is not None and not (np.isfinite(args.unit_time) and args.unit_time > 0):
        raise Silo4Error(f"--unit-time {args.unit_time}: must be > 0 [s]")
    robot = load_robot_from_args(args)
    out = Path(args.out) if args.out else run_dir / "animation.html"
    write_animation_html(out, robot, trajectory, waypoints_in_world=waypoints,
                         unit_time_s=args.unit_time, title=f"{robot.name}: {run_dir.name}")
    print(f"wrote {out} ({out.stat().st_size / 1e6:.2f} MB); open {out.resolve().as_uri()}")
    return EXIT_OK
