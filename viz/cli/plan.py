"""``silo4 plan``: plan a path, write the run folder (and ``silo4 cases``, registered here).

    silo4 plan --waypoints "0,1 1,1 0,2 0,3" --height 0.4 --start-heading 90 --out out/straight
    silo4 plan --path my_path.csv --height 0.3 --workspace thesis --out out/mine

Every option is checked before the robot is loaded and before any planning, and the output
folder before the plan (docs/errors.md lists each refusal). Torques, motor sizing,
animation.html, plots and report.html come from viz/report/run_outputs.py; their writers run inside
the atomic output folder write (planner.outputs.run_folder.write_run), so they appear together
with the CSV or not at all. Planning, the URDF limits, the torques and the metrics are the
one plan pipeline (planner.outputs.pipeline.plan_run) that ``silo4 cases`` and sweeps use too.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import viz.cli.cases as cli_cases
from planner.budget import MAX_COORDINATE_M
from viz.cli.common import (
    EXIT_CHECK_FAILED,
    EXIT_OK,
    add_folder_options,
    add_planning_options,
    add_robot_arguments,
    check_height,
    check_length_range,
    check_planning_options,
    check_range,
    load_robot_from_args,
    number_or_auto,
    plan_warnings,
    robot_label,
    robot_source,
)
from viz.cli.physics_options import add_physics_options, preset_with_contact_rule
from viz.cli.plan_summary import automatic_choices, format_summary
from viz.cli.progress import progress_bar, waiting
from viz.cli.simulate import format_sim_summary, simulate_writers
from viz.report.run_outputs import (
    add_output_options,
    gearing_from_args,
    output_writers,
    progress,
    run_options,
    run_request,
)

if TYPE_CHECKING:  # served by __getattr__ below
    from viz.cli.paths import parse_waypoints, read_path_file

__all__ = [
    "add_parsers",
    "format_summary",
    "parse_waypoints",
    "plan_warnings",
    "read_path_file",
    "run_plan",
]


def __getattr__(name: str) -> Any:
    """parse_waypoints / read_path_file, served from viz/cli/paths.py on first use (PEP 562):
    ``silo4 --help`` does not import it."""
    if name in ("parse_waypoints", "read_path_file"):
        import viz.cli.paths as cli_paths

        return getattr(cli_paths, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def add_parsers(sub: argparse._SubParsersAction) -> None:
    """Register ``plan`` and ``cases``."""
    p = sub.add_parser(
        "plan",
        help="plan a statically stable walk along waypoints (thesis Ch. 4-5)",
        description="Plan creeping and spinning gait cycles from (0, 0) through the waypoints "
        "at a constant body height, sample joint trajectories and write "
        "trajectory.csv, trajectory.npz, plan.json and metrics.json to --out.",
        epilog="A robot's feasible height range, once computed, is kept in $SILO4_CACHE_DIR "
        "(else ~/.cache/silo4) for the next run; SILO4_NO_CACHE=1 turns that off, silo4 "
        'robots --clear-cache deletes it.   example: silo4 plan --waypoints "0,1 1,1 0,2 '
        '0,3" --height 0.4 --start-heading 90 --out out/straight',
    )
    source = p.add_mutually_exclusive_group(required=True)
    source.add_argument(
        "--waypoints",
        metavar='"X,Y X,Y ..."',
        help='waypoints in the world frame [m], e.g. "0,1 1,1 0,2 0,3" '
        '(a first point with negative x works: "-1,2 0,3")',
    )
    source.add_argument(
        "--path",
        metavar="FILE.csv",
        help="CSV file of waypoints, columns x,y [m] (header optional)",
    )
    p.add_argument(
        "--height",
        type=number_or_auto("a number [m]"),
        required=True,
        metavar="M|auto",
        help="CoG height above the ground [m] (thesis range 0.15-0.63), or 'auto': "
        "the height that walks the path in the least time (thesis §7.2)",
    )
    p.add_argument(
        "--swing-height",
        type=float,
        default=None,
        metavar="M",
        help="how high each foot is lifted [m] (default: eq 5.12, half the hip "
        "height, at least 0.05 m; the thesis preset: eq 5.12)",
    )
    p.add_argument(
        "--simulate",
        action="store_true",
        help="replay the plan in MuJoCo physics too (see silo4 simulate); "
        "exit 1 when the robot does not walk it",
    )
    p.add_argument(
        "--start-heading",
        type=float,
        default=90.0,
        metavar="DEG",
        help="heading of the body x axis at the start [deg] (default 90: "
        "facing world +y, as in the thesis)",
    )
    add_planning_options(p, allow_auto=True)
    from planner.presets import PRESETS, gait_choices  # numpy-free: the registry of presets

    p.add_argument(
        "--workspace",
        choices=tuple(PRESETS),
        default="default",
        help="footholds and stride: 'default' keeps a reach margin from the "
        "stretched-leg singularity; 'thesis' reproduces Chapter 6's strides",
    )
    add_physics_options(p)
    p.add_argument(
        "--tolerance",
        type=float,
        default=None,
        metavar="M",
        help="path-following tolerance [m] (0.15 reproduces thesis Table 6.3)",
    )
    p.add_argument(
        "--face-path",
        action="store_true",
        help="default preset: turn to face each path segment, then walk forward "
        "(the thesis's habit); without it the body keeps its heading and "
        "walks in any direction (planner/gaits/omni.py)",
    )
    p.add_argument(
        "--gait",
        choices=gait_choices(),
        default="auto",
        help="'auto' (default): the preset's choice (default preset: the faster "
        "of 'crawl', body moving while a leg swings, and 'creep', only "
        "between swings, else 'facing'); 'facing' and 'plain' face each "
        "segment; 'thesis': §5.5 (docs/gaits.md)",
    )
    p.add_argument(
        "--terrain",
        metavar="FILE",
        help="terrain file (YAML or JSON: floor, boxes, cylinders, forbidden polygons, a height "
        "map; docs/terrain.md); footholds go on its surfaces and height map",
    )
    p.add_argument(
        "--out",
        required=True,
        metavar="DIR",
        help="output folder (a new folder, or a run folder silo4 wrote)",
    )
    add_folder_options(p, "an output folder")
    add_robot_arguments(p)
    add_output_options(p, visual_default=True)
    p.set_defaults(run=run_plan)
    cli_cases.add_parser(sub)


def check_plan_options(args: argparse.Namespace) -> None:
    """Every number of ``silo4 plan`` (before the robot is loaded)."""
    if args.height != "auto":
        check_height("--height", args.height)
    if args.swing_height is not None:
        check_length_range("--swing-height", args.swing_height, 1e-3, 1.0)
    check_range("--start-heading", args.start_heading, -360.0, 360.0, " [deg]")
    check_planning_options(args)
    if args.tolerance is not None:
        check_range("--tolerance", args.tolerance, 0.0, MAX_COORDINATE_M, " [m]")
    gearing_from_args(args)


def run_plan(args: argparse.Namespace) -> int:
    """Check the options and the folder, plan, write the folder, print a short summary."""
    import os

    from planner.outputs.files import check_output_path, check_target
    from viz.cli.paths import parse_waypoints, read_path_file

    out = check_output_path(args.out)
    # the path file and the robot file it reads are never a target (--robot go2 is a name)
    inputs = [p for p in (args.path, args.robot, args.terrain) if p and os.path.isfile(p)]
    # fail before the work, not after it (ownership checked again at the write)
    check_target(out, folder=True, inputs=inputs, what="output folder")
    waypoints = (
        parse_waypoints(args.waypoints) if args.waypoints is not None else read_path_file(args.path)
    )
    check_plan_options(args)
    if not args.plots:
        return _run_plan(args, out, waypoints)
    from viz.plots.prewarm import discard_warm, prewarm

    prewarm()  # matplotlib imports in a worker while we plan
    try:
        return _run_plan(args, out, waypoints)
    finally:
        discard_warm()  # unused when the run failed before its plots


@contextmanager
def _planning_progress(
    args: argparse.Namespace, what: list[str]
) -> Iterator[Callable[[int, int], None] | None]:
    """What a person at a terminal sees while the plan is made: ``--height auto`` counts
    the heights planned ("--height auto: heights 3/31"); otherwise the elapsed time.
    Yields the height search's callback (None without the search)."""
    if args.height != "auto":
        with waiting("planning" + (": " + ", ".join(what) if what else "")):
            yield None
        return
    with progress_bar(None, "--height auto: heights") as bar:
        shown = [0]

        def on_height_candidate(done: int, most: int) -> None:
            bar.total = most  # at most: the refinement may plan fewer
            bar.update(done - shown[0])
            shown[0] = done

        yield on_height_candidate


def _run_plan(args: argparse.Namespace, out: Path, waypoints: Any) -> int:
    """run_plan after the cheap checks: plan, write, summarise."""
    from planner.terrain import load_terrain
    from viz.cli.range_cache import remembered_ranges

    terrain = None if args.terrain is None else load_terrain(args.terrain)  # before the robot
    args.terrain_map = terrain  # the file read once: plan.json, the HTML and the sim use it
    robot = load_robot_from_args(args)
    with remembered_ranges(robot):  # the feasible ranges of earlier runs (range_cache.py)
        return _plan_and_write(args, out, waypoints, robot, terrain)


def _plan_and_write(
    args: argparse.Namespace, out: Path, waypoints: Any, robot: Any, terrain: Any
) -> int:
    """_run_plan once the robot is loaded."""
    from planner.model import as_planning_model
    from planner.outputs.pipeline import plan_run
    from planner.outputs.run_folder import write_run
    from silo4kin.motors import format_sizing_table

    t0 = time.perf_counter()
    what = [
        w
        for w, auto in (
            ("searching heights", args.height == "auto"),
            ("finding the shortest unit time", args.unit_time == "auto"),
        )
        if auto
    ]
    with _planning_progress(args, what) as on_height_candidate:
        run = plan_run(
            robot,
            waypoints,
            args.height,
            run_request(args, robot.joint_names),
            start_heading=math.radians(args.start_heading),
            workspace=preset_with_contact_rule(args),
            tolerance=args.tolerance,
            samples_per_unit=args.samples_per_unit,
            swing_height_m=args.swing_height,
            face_path=args.face_path,
            gait=args.gait,
            terrain=terrain,
            on_height_candidate=on_height_candidate,
        )
    plan, metrics = run.plan, run.metrics
    for line in plan_warnings(metrics):
        print(line, file=sys.stderr)
    if plan.height_search is not None:
        search = plan.height_search
        lo, hi = search["feasible_range_m"]
        print(
            f"--height auto: h = {plan.height:.3f} m ({search['time_units']:.0f} units, "
            f"best of {search['n_evaluated']} heights in [{lo:.4g}, {hi:.4g}] m)"
        )
    progress(f"  planned {len(plan.trajectory)} samples in {time.perf_counter() - t0:.2f} s")
    for line in automatic_choices(args, plan, metrics):
        print(line)
    summary = format_summary(plan, metrics, len(waypoints))  # before writing: nothing after fails
    label = robot_label(args, robot)
    physics: list[dict] = []
    files = write_run(
        out,
        plan,
        metrics,
        robot_name=label,
        force=args.force,
        position_body_com_in_root=as_planning_model(robot).position_body_com_in_root,
        write_csv=args.csv,
        robot_source=robot_source(args),
        options=run_options(args),
        extra_writers=output_writers(
            args,
            plan,
            metrics,
            robot,
            title=label,
            before_report=simulate_writers(args, plan.trajectory, robot, label, physics)
            if args.simulate
            else (),
        ),
    )
    print(summary)
    sizing = metrics.get("motor_sizing")
    if args.motors and isinstance(sizing, list):
        print(format_sizing_table(sizing))
    print(f"wrote {Path(args.out)}/: {' '.join(sorted(files))}")
    if args.html:
        print(f"open {(out / 'animation.html').as_uri()}")
    if physics:
        print(format_sim_summary(physics[0]))
        return EXIT_OK if physics[0]["walks"] else EXIT_CHECK_FAILED
    return EXIT_OK
