"""``silo4 cases``: plan the thesis case studies (Ch. 6) through the plan pipeline (URDF
limits reported, not refused), write one run folder per case and the results page.

    silo4 cases --out out/cases --results-md docs/results.md
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import planner.presets as preset_registry  # numpy-free
from silo4kin.errors import Silo4Error
from viz.cli.common import (
    EXIT_CHECK_FAILED,
    EXIT_OK,
    add_folder_options,
    add_planning_options,
    add_robot_arguments,
    check_height,
    check_planning_options,
    is_dir,
    load_robot_from_args,
    plan_warnings,
    robot_label,
    robot_source,
)
from viz.report.run_outputs import (
    add_output_options,
    gearing_from_args,
    output_writers,
    run_options,
    run_request,
)

if TYPE_CHECKING:
    from planner.outputs.pipeline import RunRequest
    from planner.studies.cases import CaseResult, PathCase

#: A case the planner refuses (bad geometry for this robot) is reported, not fatal.
PlannerRefusal = Silo4Error

PATHS = ("straight", "circle", "circle-reduced")
PRESETS = tuple(preset_registry.PRESETS)
DEFAULTS = {"paths": ",".join(PATHS), "heights": "0.2,0.4,0.6", "workspaces": ",".join(PRESETS)}


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``cases``."""
    c = sub.add_parser(
        "cases",
        help="plan the thesis case studies and write the results page",
        description="Plan the straight path, the circle and the reduced-accuracy circle at "
        "h = 0.2, 0.4, 0.6 m with both workspace presets, and the ditch "
        "crossing (thesis Ch. 6); write one run folder per case under --out, "
        "OUT/results.md, and, with --results-md, the same page there too.",
        epilog="regenerate the docs page: silo4 cases --out out/cases --results-md docs/results.md",
    )
    c.add_argument("--out", required=True, metavar="DIR", help="output folder")
    c.add_argument(
        "--results-md",
        metavar="PATH",
        default=None,
        help="also write the results page here (e.g. docs/results.md)",
    )
    c.add_argument(
        "--paths",
        default=DEFAULTS["paths"],
        metavar="LIST",
        help="comma-separated subset of straight,circle,circle-reduced",
    )
    c.add_argument(
        "--heights",
        default=DEFAULTS["heights"],
        metavar="LIST",
        help="comma-separated body heights [m] (default 0.2,0.4,0.6)",
    )
    c.add_argument(
        "--workspaces",
        default=DEFAULTS["workspaces"],
        metavar="LIST",
        help="comma-separated presets (default thesis,default)",
    )
    c.add_argument(
        "--no-ditch", dest="ditch", action="store_false", help="skip the ditch crossing (Fig 6.30)"
    )
    c.add_argument(
        "--simulate",
        action="store_true",
        help="replay every case in MuJoCo physics and add the verdicts to the "
        "results page (see silo4 simulate)",
    )
    add_planning_options(c)
    add_folder_options(c, "case folders", csv=False)
    add_robot_arguments(c)
    add_output_options(c, visual_default=False)
    c.set_defaults(run=run_cases)


def _split(text: str, option: str, allowed: tuple[str, ...] | None = None) -> list[str]:
    items = [s.strip() for s in text.split(",") if s.strip()]
    if not items:
        raise Silo4Error(f"{option} {text!r}: empty list")
    if len(items) > 100:
        raise Silo4Error(f"{option}: {len(items)} items; at most 100")
    if allowed is not None:
        for item in items:
            if item not in allowed:
                raise Silo4Error(f"{option}: {item[:40]!r} is not one of {', '.join(allowed)}")
    return list(dict.fromkeys(items))  # a repeated item would overwrite its own folder


def _heights(text: str) -> list[float]:
    heights = []
    for item in _split(text, "--heights"):
        try:
            heights.append(float(item))
        except ValueError:
            raise Silo4Error(f"--heights: {item[:40]!r} is not a number [m]") from None
        check_height("--heights", heights[-1])
    return heights


def run_cases(args: argparse.Namespace) -> int:
    """Plan the thesis cases, write each run folder and the results page."""
    from dataclasses import replace

    from planner.model import as_planning_model
    from planner.outputs.files import (
        check_output_path,
        check_replaceable,
        check_target,
        record_written,
    )

    out = check_output_path(args.out)
    paths = _split(args.paths, "--paths", PATHS)
    presets = _split(args.workspaces, "--workspaces", PRESETS)
    heights = _heights(args.heights)
    check_planning_options(args)
    results_md = check_results_md(args.results_md)
    gearing_from_args(args)  # validate before the work
    from planner.outputs.documents import plan_document
    from planner.outputs.files import write_text_atomically
    from planner.outputs.pipeline import OnLimitViolation
    from planner.outputs.run_folder import check_output_folder, write_run
    from planner.studies.cases import thesis_cases
    from planner.studies.ditch import plan_ditch_cases
    from viz.cli.progress import track
    from viz.report.results_page import render_results_page

    cases = list(thesis_cases(paths, heights, presets))
    for case in cases:  # a user's file in any case folder: refuse before planning anything
        check_replaceable(out / case.name)
    check_target(Path(args.out) / "results.md", what="--out")  # a results.md of the user's
    if results_md is not None:
        check_target(results_md, what="--results-md")
    robot = load_robot_from_args(args)
    label = robot_label(args, robot)
    position_body_com_in_root = as_planning_model(robot).position_body_com_in_root
    # a case that breaks a URDF limit is reported (a warning line, metrics.json), not refused
    request = replace(
        run_request(args, robot.joint_names), on_limit_violation=OnLimitViolation.REPORT
    )

    results, refused, planned = [], [], []
    for case in track(cases, "cases"):
        try:
            planned.append((case, plan_case(robot, case, request, args.samples_per_unit)))
        except PlannerRefusal as exc:  # the planner said why; report it, go on
            print(f"{case.name:28s} refused: {exc}", file=sys.stderr)
            refused.append((case, str(exc)))
    # every case folder checked before any is written (a folder holding another run without
    # --force refuses the whole command, and leaves the others as they were)
    for case, result in planned:
        check_output_folder(
            out / case.name,
            plan_document(result.plan, label, run_options(args))["inputs"],
            force=args.force,
        )
    for case, result in track(planned, "writing case folders"):
        plan, metrics = result.plan, dict(result.metrics)
        write_run(
            out / case.name,
            plan,
            metrics,
            robot_name=label,
            position_body_com_in_root=position_body_com_in_root,
            force=args.force,
            write_csv=args.csv,
            robot_source=robot_source(args),
            options=run_options(args),
            extra_writers=output_writers(args, plan, metrics, robot, title=f"{label}: {case.name}"),
        )
        m = result.metrics
        for line in plan_warnings(m):
            print(f"{case.name:28s} {line}", file=sys.stderr)
        margin = m["min_stability_margin_m"]
        margin = 0.0 if margin is not None and abs(margin) < 5e-4 else margin  # no -0.000
        print(
            f"{case.name:28s} {m['normalized_time']:5.0f} units {m['distance_m']:5.2f} m "
            f"E_n {m['normalized_error_m']:.3f} m  margin {margin:.3f} m"
            f"  ({result.wall_time_s:.2f} s)"
        )
        results.append(result)
    ditches = (
        plan_ditch_cases(robot, presets, samples_per_unit=args.samples_per_unit)
        if args.ditch
        else []
    )
    for d in ditches:
        print(d.summary())
    section, verdicts = "", {}  # type: tuple[str, dict[str, str]]
    if args.simulate:
        from viz.cli.simulate_cases import simulate_cases

        section, verdicts = simulate_cases(robot, results, out, args)
    page = (
        render_results_page(
            results,
            ditches,
            refused=refused,
            command=regenerate_command(args),
            physics=verdicts,
            robot=robot,
        )
        + section
    )
    written = []
    for target in [out / "results.md", *([results_md] if results_md is not None else [])]:
        written.append(write_text_atomically(target, page))
        record_written(written[-1:])  # silo4's now: the same command may replace it
    print(
        f"wrote {len(results)} case folders under {out}; results page: "
        + ", ".join(str(w) for w in written)
    )
    if refused:
        print(
            f"{len(refused)} case(s) refused by the planner (listed on the page)", file=sys.stderr
        )
        return EXIT_CHECK_FAILED
    return EXIT_OK


def plan_case(robot: Any, case: PathCase, request: RunRequest, samples_per_unit: int) -> CaseResult:
    """One thesis case through the plan pipeline (planner.outputs.pipeline.plan_run: plan,
    URDF limits, torques, metrics), timed [s]."""
    from planner.outputs.pipeline import plan_run
    from planner.studies.cases import CaseResult

    start = time.perf_counter()
    run = plan_run(
        robot,
        case.waypoints_in_world,
        case.height_m,
        request,
        start_heading=case.start_heading_rad,
        workspace=case.workspace,
        tolerance=case.tolerance_m,
        samples_per_unit=samples_per_unit,
    )
    return CaseResult(case, run.plan, run.metrics, time.perf_counter() - start)


def check_results_md(text: str | None) -> Path | None:
    """``--results-md``: a file path whose folder exists (never a folder itself)."""
    if text is None:
        return None
    path = Path(text)
    if not text.strip() or is_dir(path, "--results-md"):
        raise Silo4Error(f"--results-md {text!r}: expected a file name, e.g. docs/results.md")
    if not is_dir(path.absolute().parent, "--results-md"):
        raise Silo4Error(f"--results-md {text!r}: folder {path.absolute().parent} does not exist")
    return path


def regenerate_command(args: argparse.Namespace) -> str:
    """The command line that regenerates the page (printed at its top)."""
    parts = ["silo4 cases --out", str(args.out)]
    if args.results_md:
        parts += ["--results-md", str(args.results_md)]
    for key, default in DEFAULTS.items():
        if getattr(args, key) != default:
            parts += [f"--{key}", getattr(args, key)]
    if args.samples_per_unit != 100:
        parts += ["--samples-per-unit", str(args.samples_per_unit)]
    if args.unit_time != 1.0:
        parts += ["--unit-time", f"{args.unit_time:g}"]
    if not args.ditch:
        parts.append("--no-ditch")
    if getattr(args, "simulate", False):
        parts.append("--simulate")
    if args.robot:
        parts += ["--robot", str(args.robot)]
    for item in args.xacro_arg:
        parts += ["--xacro-arg", item]
    return " ".join(parts)
