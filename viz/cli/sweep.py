"""``silo4 sweep``: plan a design grid (paths x heights x xacro arguments x presets) on Dask.

    silo4 sweep --paths straight,circle --heights 0.2:0.6:0.05 --xacro-arg L2=0.2,0.25 \\
        --xacro-arg L3=0.2,0.25,0.3 --workspaces default --out out/sweep
    silo4 sweep ... --scheduler tcp://10.0.0.5:8786      # the same grid on a Dask cluster

Writes DIR/sweep.csv (rows appended as they arrive, resumable), sweep.parquet, sweep.json
(settings), best.json and pareto.png (silo4sweep.summary), and with --results-md the results page
(silo4sweep.report). The work itself is silo4sweep.task.plan_row, one Dask task per configuration.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from silo4kin.errors import RobotDescriptionError, Silo4Error
from viz.cli.common import add_gear_options, check_height
from viz.cli.progress import progress_bar
from viz.cli.sweep_outputs import SUMMARY_NAMES, finish_sweep, page_image


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``sweep``."""
    p = sub.add_parser(
        "sweep",
        help="plan a grid of paths x heights x xacro arguments x presets on Dask",
        description="Plan every configuration of the cartesian grid (one Dask task each) with\n"
        "its torques, and write one row per configuration to OUT/sweep.csv (and\n"
        "sweep.parquet), best.json (best height per path and design) and\n"
        "pareto.png (time vs peak torque). A configuration that cannot be planned\n"
        "is a row with its reason. A rerun skips rows already in OUT/sweep.csv.",
        epilog="example: silo4 sweep --paths straight,circle --heights 0.2:0.6:0.05 "
        "--xacro-arg L2=0.2,0.25 --xacro-arg L3=0.2,0.25,0.3 --out out/sweep\n"
        "on a cluster: add --scheduler tcp://HOST:8786 (docs/sweeps.md)",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--paths",
        default="straight",
        metavar="LIST",
        help="comma-separated thesis paths: straight, circle, circle-reduced (default straight)",
    )
    p.add_argument(
        "--heights",
        default="0.2:0.6:0.05",
        metavar="VALUES",
        help="CoG heights [m]: a:b:step (b included) and/or a,b,c (default 0.2:0.6:0.05)",
    )
    p.add_argument(
        "--xacro-arg",
        metavar="NAME=VALUES",
        action="append",
        default=[],
        help="a xacro argument and its values, a:b:step and/or a,b,c, repeatable "
        "(e.g. --xacro-arg L2=0.2,0.25)",
    )
    p.add_argument(
        "--workspaces",
        default="default",
        metavar="LIST",
        help="comma-separated workspace presets: default, thesis (default: default)",
    )
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        default=None,
        help="Dask scheduler of an existing cluster, e.g. tcp://host:8786 "
        "(default: a local cluster, one worker process per core)",
    )
    p.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="N",
        help="worker processes of the local cluster (default: one per core)",
    )
    p.add_argument(
        "--connect-timeout",
        type=float,
        default=5.0,
        metavar="S",
        help="how long to wait for the scheduler and a worker [s] (default 5)",
    )
    p.add_argument(
        "--simulate",
        action="store_true",
        help="replay each plan in the physics simulator (needs the sim package)",
    )
    p.add_argument(
        "--samples-per-unit",
        type=int,
        default=100,
        metavar="N",
        help="samples per time unit t_l (default 100, thesis §5.5)",
    )
    p.add_argument(
        "--load",
        choices=("body", "total"),
        default=None,
        help="mass the feet carry for the torques: body (the thesis) or total "
        "(default: the planner's choice for the preset, else body)",
    )
    add_gear_options(p)
    p.add_argument(
        "--robot",
        metavar="PATH",
        default=None,
        help="robot .urdf or .urdf.xacro, readable on every worker (default: the SILO4 xacro)",
    )
    p.add_argument(
        "--results-md",
        metavar="PATH",
        default=None,
        help="also write the sweep's results page here (e.g. docs/sweep_results.md)",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="start anew in a folder holding a sweep with other settings",
    )
    p.set_defaults(run=run_sweep)


def _check_robot(robot: str | None, xacro_names: list[str]) -> None:
    """The robot file loads and declares every swept xacro argument (before any work)."""
    from silo4kin.errors import XacroArgumentError
    from silo4kin.robot import DEFAULT_XACRO, load_robot
    from silo4kin.xacro_files import declared_xacro_args

    load_robot(robot)
    path = Path(robot) if robot else DEFAULT_XACRO
    if not xacro_names:
        return
    if not path.name.endswith(".xacro"):
        raise RobotDescriptionError(f"--xacro-arg given for a plain URDF ({path.name})")
    declared = declared_xacro_args(path)
    for name in xacro_names:
        if name not in declared:
            raise XacroArgumentError(
                f"--xacro-arg {name}: unknown xacro argument for "
                f"{path.name}; valid arguments: {', '.join(declared)}",
                name,
                declared,
            )


def run_sweep(args: argparse.Namespace) -> int:
    """Build the grid, run the missing configurations, write the table and its summaries."""
    from planner.workspace.layout import PRESETS
    from silo4sweep.grid import (
        KNOWN_PATHS,
        check_grid_size,
        design_grid,
        parse_names,
        parse_values,
        parse_xacro_sweeps,
    )
    from silo4sweep.table import SweepTable
    from silo4sweep.task import SweepSettings, simulator_available

    paths = parse_names(args.paths, "--paths", KNOWN_PATHS)
    if args.heights.strip() == "auto":
        raise Silo4Error(
            "--heights auto needs the planner's automatic height, "
            "which this version lacks; give heights, e.g. 0.2:0.6:0.05"
        )
    heights = parse_values(args.heights, "--heights")
    if min(heights) <= 0:
        raise Silo4Error(f"--heights: {min(heights)} is not a height; heights are > 0 [m]")
    check_height("--heights", max(heights))  # 40 for 0.40 m: "did you mean"
    xacro = parse_xacro_sweeps(args.xacro_arg)
    presets = parse_names(args.workspaces, "--workspaces", PRESETS)
    if args.samples_per_unit < 1:
        raise Silo4Error(f"--samples-per-unit {args.samples_per_unit}: must be >= 1")
    if args.workers is not None and (args.workers < 1 or args.scheduler):
        raise Silo4Error(
            f"--workers {args.workers}: must be >= 1, and sizes only the local "
            "cluster (an existing cluster at --scheduler has its own workers)"
        )
    from silo4sweep.engine import check_protocol, default_workers

    cores = default_workers()
    if args.workers is not None and args.workers > cores:
        raise Silo4Error(
            f"--workers {args.workers}: this machine offers {cores} core(s) to "
            f"silo4; give at most {cores} (one worker process per core)"
        )
    if not args.connect_timeout > 0:
        raise Silo4Error(f"--connect-timeout {args.connect_timeout}: must be > 0 [s]")
    if args.scheduler:
        check_protocol(args.scheduler)
    if args.simulate and not simulator_available():
        raise Silo4Error(
            "--simulate needs the physics replay package 'silo4sim', which is not installed here"
        )
    from silo4kin.motors import Gearing

    Gearing.uniform(12, args.gear_ratio, args.gear_efficiency)  # validate before the work
    _check_robot(args.robot, list(xacro))
    settings = SweepSettings(
        samples_per_unit=args.samples_per_unit,
        load=args.load,
        gear_ratio=args.gear_ratio,
        gear_efficiency=args.gear_efficiency,
        robot=str(Path(args.robot).resolve()) if args.robot else None,
        simulate=args.simulate,
    )
    check_grid_size(paths, heights, xacro, presets)  # counted before it is built
    configs = design_grid(paths, heights, xacro, presets)
    out = Path(args.out)
    check_sweep_targets(args)  # before the table is read or the engine started
    table = SweepTable(out, list(xacro), settings, force=args.force)
    todo = table.missing(configs)
    print(
        f"{len(configs)} configurations, {len(configs) - len(todo)} already in "
        f"{out / 'sweep.csv'}, {len(todo)} to plan",
        file=sys.stderr,
    )
    wall = 0.0
    if todo:
        wall = _run(args, table, todo, settings)
    return finish_sweep(args, table, configs, list(xacro), len(todo), wall)


def check_sweep_targets(args: argparse.Namespace) -> None:
    """Every file the sweep would write, by the output-safety rule (planner.outputs.files.
    check_target): a file of the user's in DIR (a best.json) or at --results-md is never
    replaced, with or without --force; the robot file is never a target."""
    import os

    from planner.outputs.files import OutputFolderError, check_target
    from silo4sweep.table import CSV_NAME, PARQUET_NAME, SETTINGS_NAME

    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise OutputFolderError(f"--out {args.out!r} is an existing file, not a folder", out)
    inputs = [args.robot] if args.robot and os.path.isfile(args.robot) else []
    for name in (CSV_NAME, SETTINGS_NAME, PARQUET_NAME, *SUMMARY_NAMES):
        check_target(out / name, inputs=inputs, what="--out")
    if args.results_md:
        page = Path(args.results_md)
        for target in (page, page_image(page)):
            check_target(target, inputs=inputs, what="--results-md")


def _run(args: argparse.Namespace, table, todo, settings) -> float:  # noqa: ANN001
    from silo4sweep.engine import dask_client, run_configs

    with dask_client(args.scheduler, args.workers, args.connect_timeout) as client:
        table.start()  # only once the engine is up: nothing written for a dead scheduler
        t0 = time.perf_counter()
        failed = 0
        # rate and ETA on stderr at a terminal (viz.cli.progress); rows are on disk at once
        with progress_bar(len(todo), "sweep") as bar:
            for config, row in run_configs(client, todo, settings):
                table.add(config, row)
                failed += row["status"] != "ok"
                bar.set_postfix_str(f"{failed} not planned | {config.label[:40]}")
                bar.update()
        return time.perf_counter() - t0
