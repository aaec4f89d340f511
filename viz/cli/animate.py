"""``silo4 animate``: (re)write a run folder's animation.html from its trajectory.npz.

Plays back a saved plan with the same or another visual of the robot, e.g. after changing
the playback speed, without planning again. Without ``--robot`` the robot recorded in the
run's plan.json (``robot_source``: file, xacro arguments, package folders) is loaded, so a
run planned for another robot replays as planned.

The page goes to ``--out``; else, so that RUN/animation.html keeps matching the run's CSV and
report, to RUN/animation_<unit time>s.html (e.g. ``animation_0.5s.html``), or to
RUN/animation.html when the run has none yet and the unit time is the planned one;
``--replace`` writes RUN/animation.html whatever it held.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np

from planner.budget import UNIT_TIME_RANGE_S
from silo4kin.errors import Silo4Error
from viz.cli.common import (
    EXIT_OK,
    add_robot_arguments,
    check_range,
    is_dir,
    load_robot_from_args,
    recorded_robot_args,
)


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``animate``."""
    p = sub.add_parser(
        "animate",
        help="write animation.html for a saved run (trajectory.npz)",
        description="Read RUN/trajectory.npz (and the waypoints in RUN/plan.json), load the "
        "robot (by default the one plan.json records), and write a "
        "self-contained animation.html (default: into RUN).",
        epilog="example: silo4 animate out/straight --unit-time 0.5   "
        "(writes out/straight/animation_0.5s.html)",
    )
    p.add_argument("run_dir", metavar="RUN", help="a run folder written by silo4 plan")
    p.add_argument(
        "--out",
        metavar="FILE.html",
        default=None,
        help="output file (default RUN/animation_<S>s.html, so RUN/animation.html "
        "keeps matching the run; RUN/animation.html when the run has none "
        "and the unit time is as planned)",
    )
    p.add_argument(
        "--replace",
        action="store_true",
        help="write RUN/animation.html, replacing the run's own animation",
    )
    p.add_argument(
        "--unit-time",
        type=float,
        default=None,
        metavar="S",
        help="play one time unit in S seconds (default: as planned)",
    )
    add_robot_arguments(p)
    p.set_defaults(run=run)


def _read_plan_json(run_dir: Path) -> dict[str, Any]:
    """plan.json as a dict, or {} when it is missing or unreadable (it is optional here)."""
    import json  # here: `silo4 --help` imports this module

    try:
        document = json.loads((run_dir / "plan.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return document if isinstance(document, dict) else {}


def _waypoints(document: dict[str, Any]) -> np.ndarray | None:
    import numpy as np

    try:
        waypoints = np.asarray(document["inputs"]["waypoints_in_world"], dtype=float)
    except (KeyError, TypeError, ValueError):
        return None  # the animation is still useful without the desired path
    ok = waypoints.ndim == 2 and waypoints.shape[1:] == (2,) and np.all(np.isfinite(waypoints))
    return waypoints if ok else None


def _recorded_robot(args: argparse.Namespace, document: dict[str, Any]) -> argparse.Namespace:
    """The robot options: the user's, or (none given) those plan.json's robot_source records."""
    return recorded_robot_args(args, document)


def default_target(
    run_dir: Path, planned_s: float, unit_time_s: float | None, replace: bool
) -> Path:
    """Where the page goes without --out (module docstring): RUN/animation.html with
    ``replace`` or when there is none and the unit time is ``planned_s`` [s]; else
    RUN/animation_<unit time>s.html."""
    unit = planned_s if unit_time_s is None else unit_time_s
    own = run_dir / "animation.html"
    if replace or (not own.exists() and abs(unit - planned_s) <= 1e-12 * planned_s):
        return own
    return run_dir / f"animation_{unit:g}s.html"


def run(args: argparse.Namespace) -> int:
    """Load the run and the robot, write the HTML; a trajectory of another robot: exit 2."""

    from planner.outputs.export import read_trajectory_npz
    from viz.animation.page import write_animation_html
    from viz.animation.terrain import recorded_terrain

    run_dir = Path(args.run_dir)
    if not is_dir(run_dir, "RUN"):
        raise Silo4Error(
            f"RUN {args.run_dir!r}: not a folder; give a run folder written by silo4 plan"
        )
    if args.unit_time is not None:
        check_range("--unit-time", args.unit_time, *UNIT_TIME_RANGE_S, " [s]")
    if args.out is not None and (not args.out.strip() or is_dir(args.out, "--out")):
        raise Silo4Error(f"--out {args.out!r}: expected a file name, e.g. RUN/slow.html")
    from planner.outputs.export import run_inputs
    from planner.outputs.files import check_target, record_written

    if args.out is not None and args.replace:
        raise Silo4Error("--replace writes RUN/animation.html; drop --out, or drop --replace")
    trajectory = read_trajectory_npz(run_dir / "trajectory.npz")
    out = (
        Path(args.out)
        if args.out
        else default_target(run_dir, trajectory.unit_time_s, args.unit_time, args.replace)
    )
    check_target(out, inputs=run_inputs(run_dir), what="--out")  # before the robot loads
    document = _read_plan_json(run_dir)
    robot = load_robot_from_args(_recorded_robot(args, document))
    write_animation_html(
        out,
        robot,
        trajectory,
        waypoints_in_world=_waypoints(document),
        unit_time_s=args.unit_time,
        title=f"{robot.name}: {run_dir.name}",
        terrain=recorded_terrain(document),
    )
    record_written([out])  # a run folder stays replaceable by a new run; a rerun may
    # replace a file written elsewhere
    print(f"wrote {out} ({out.stat().st_size / 1e6:.2f} MB); open {out.resolve().as_uri()}")
    return EXIT_OK
