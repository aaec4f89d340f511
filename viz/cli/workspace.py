"""``silo4 workspace``: draw each leg's reachable set, footholds and stride at a body height.

Shows why a height is or is not feasible for the default workspace (thesis Figs 3.4, 4.7):
the sets, the footholds along the body x axis and the stride, with the feasible range.
"""

from __future__ import annotations

import argparse

from silo4kin.errors import Silo4Error
from viz.cli.common import EXIT_OK, add_robot_arguments, check_height, load_robot_from_args


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``workspace``."""
    p = sub.add_parser(
        "workspace",
        help="draw the legs' reachable sets, footholds and stride at a height",
        description="Top view of each leg's reachable ground set within the joint limits "
        "(default workspace), the creeping footholds and the stride at body "
        "height H, and whether H is feasible.",
        epilog="example: silo4 workspace --height 0.4 --out workspace.png",
    )
    p.add_argument(
        "--height", type=float, required=True, metavar="H", help="CoG height above the ground [m]"
    )
    p.add_argument("--out", metavar="FILE.png", required=True, help="output PNG file")
    add_robot_arguments(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Validate, load the robot, write the PNG, print the stride and the range."""
    check_height("--height", args.height)  # positive, and "did you mean 0.40 m" for 40
    if not str(args.out).lower().endswith(".png"):
        raise Silo4Error(f"--out {args.out}: must be a .png file")
    from planner.outputs.files import check_target, record_written
    from planner.workspace.layout import reach_layout
    from viz.cli.range_cache import remembered_ranges
    from viz.plots.workspace import write_workspace_png

    check_target(args.out, what="--out")  # a PNG of the user's is never replaced
    robot = load_robot_from_args(args)
    with remembered_ranges(robot):  # the feasible ranges of earlier runs (range_cache.py)
        path = write_workspace_png(args.out, robot, args.height)
        record_written([path])  # so the same command may replace it
        layout = reach_layout(robot, args.height)
    rng = layout.feasible_range
    lam_x, lam_y = layout.stride_m
    rng_text = "none" if rng is None else f"[{rng[0]:.4g}, {rng[1]:.4g}] m"
    print(
        f"h = {args.height:.4g} m: stride x {lam_x:.4f} m, y {lam_y:.4f} m; "
        f"feasible range {rng_text}; wrote {path}"
    )
    return EXIT_OK
