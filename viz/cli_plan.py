"""``silo4 plan`` and ``silo4 cases``: plan a path / the thesis case studies, write the outputs.

    silo4 plan --waypoints "0,1 1,1 0,2 0,3" --height 0.4 --start-heading 90 --out out/straight
    silo4 plan --path my_path.csv --height 0.3 --workspace thesis --out out/mine
    silo4 cases --out out/cases --results-md docs/results.md

Torques, motor sizing, animation.html, plots and report.html come from viz/run_outputs.py;
their writers run inside the atomic output folder write (planner.export.write_run), so they
appear together with the CSV or not at all.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from silo4kin.errors import Silo4Error

if TYPE_CHECKING:
    import numpy as np

from .cli import EXIT_CHECK_FAILED, EXIT_OK, add_robot_arguments, load_robot_from_args
from .cli_simulate import format_sim_summary, simulate_writers
from .run_outputs import (
    add_output_options,
    gearing_from_args,
    output_writers,
    progress,
    with_torques,
)

#: A case the planner refuses (bad geometry for this robot) is reported, not fatal.
PlannerRefusal = Silo4Error


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_POINT = re.compile(rf"^\s*({_NUMBER})\s*,\s*({_NUMBER})\s*$")


# --------------------------------------------------------------------------- parsing


def parse_waypoints(text: str) -> np.ndarray:
    """``"0,1 1,1 0,2"`` -> (K, 2) array [m]; points separated by spaces or ';'."""
    import numpy as np

    tokens = [tok for tok in re.split(r"[\s;]+", re.sub(r"\s*,\s*", ",", text.strip())) if tok]
    if not tokens:
        raise Silo4Error(f"--waypoints {text!r}: no points; give x,y pairs, e.g. \"0,1 1,1\"")
    points = []
    for tok in tokens:
        match = _POINT.match(tok)
        if match is None:
            raise Silo4Error(f"--waypoints: {tok!r} is not a point x,y (two numbers in metres "
                             "separated by a comma, points separated by spaces), "
                             "e.g. \"0,1 1,1\"")
        points.append((float(match.group(1)), float(match.group(2))))
    return np.array(points)


def read_path_file(path: str | Path) -> np.ndarray:
    """Waypoints (K, 2) [m] from a CSV file with columns x, y (header line optional).

    Blank lines and lines starting with '#' are skipped. With a header, columns named ``x``
    and ``y`` are used (any order, other columns ignored); without, the first two columns.
    """
    import numpy as np

    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except OSError as exc:
        raise Silo4Error(f"--path {path}: cannot read the file ({exc.strerror or exc})") from exc
    rows = [(n, line) for n, line in enumerate(lines, 1)
            if line.strip() and not line.lstrip().startswith("#")]
    if not rows:
        raise Silo4Error(f"--path {path}: no waypoints (expected lines x,y)")
    columns = (0, 1)
    first = [c.strip() for c in rows[0][1].split(",")]
    if not all(re.fullmatch(_NUMBER, c) for c in first[:2]):
        names = [c.lower() for c in first]
        if "x" not in names or "y" not in names:
            raise Silo4Error(f"--path {path}: line {rows[0][0]} {rows[0][1].strip()!r} is "
                             "neither a point x,y nor a header naming columns x and y")
        columns = (names.index("x"), names.index("y"))
        rows = rows[1:]
    points = []
    for n, line in rows:
        cells = [c.strip() for c in line.split(",")]
        try:
            points.append((float(cells[columns[0]]), float(cells[columns[1]])))
        except (ValueError, IndexError):
            raise Silo4Error(f"--path {path}: line {n} {line.strip()!r} is not a point x,y "
                             "(two numbers in metres)") from None
    if not points:
        raise Silo4Error(f"--path {path}: no waypoints after the header")
    return np.array(points)


def _finite(name: str, value: float | None) -> None:
    if value is not None and not math.isfinite(value):
        raise Silo4Error(f"{name} {value}: must be a finite number")


def _positive(name: str, value: float | None) -> None:
    _finite(name, value)
    if value is not None and value <= 0:
        raise Silo4Error(f"{name} {value}: must be > 0")


def plan_warnings(metrics: Any) -> list[str]:
    """The metrics' warning lines (planner.metrics: e.g. the whole-robot CoM leaving the
    support polygon with the thesis preset)."""
    lines = metrics.get("warnings") or []
    return [str(line) for line in lines] if isinstance(lines, list) else []


def robot_label(args: argparse.Namespace, robot: Any) -> str:
    """Robot name plus non-default xacro arguments, recorded in plan.json."""
    overrides = " ".join(sorted(args.xacro_arg))
    source = f" from {args.robot}" if args.robot else ""
    return f"{robot.name}{source}" + (f" [{overrides}]" if overrides else "")


# --------------------------------------------------------------------------- parsers


def add_parsers(sub: argparse._SubParsersAction) -> None:
    """Register ``plan`` and ``cases``."""
    p = sub.add_parser(
        "plan", help="plan a statically stable walk along waypoints (thesis Ch. 4-5)",
        description="Plan creeping and spinning gait cycles from (0, 0) through the waypoints "
                    "at a constant body height, sample joint trajectories and write "
                    "trajectory.csv, trajectory.npz, plan.json and metrics.json to --out.",
        epilog="example: silo4 plan --waypoints \"0,1 1,1 0,2 0,3\" --height 0.4 "
               "--start-heading 90 --out out/straight")
    source = p.add_mutually_exclusive_group(required=True)
    source.add_argument("--waypoints", metavar="\"X,Y X,Y ...\"",
                        help="waypoints in the world frame [m], e.g. \"0,1 1,1 0,2 0,3\"")
    source.add_argument("--path", metavar="FILE.csv",
                        help="CSV file of waypoints, columns x,y [m] (header optional)")
    p.add_argument("--height", type=float, required=True,
                   help="CoG height above the ground [m] (thesis range 0.15-0.63)")
    p.add_argument("--start-heading", type=float, default=90.0, metavar="DEG",
                   help="heading of the body x axis at the start [deg] (default 90: "
                        "facing world +y, as in the thesis)")
    _add_planning_options(p)
    p.add_argument("--workspace", choices=("default", "thesis"), default="default",
                   help="footholds and stride: 'default' keeps a reach margin from the "
                        "stretched-leg singularity; 'thesis' reproduces Chapter 6's strides")
    p.add_argument("--tolerance", type=float, default=None, metavar="M",
                   help="path-following tolerance [m] (0.15 reproduces thesis Table 6.3)")
    p.add_argument("--swing-height", type=float, default=None, metavar="M",
                   help="how high each foot is lifted [m] (default: eq 5.12, half the hip "
                        "height, at least 0.05 m; the thesis preset: eq 5.12)")
    p.add_argument("--face-path", action="store_true",
                   help="default preset: turn to face each path segment, then walk forward "
                        "(the thesis's habit); without it the body keeps its heading and "
                        "walks in any direction (planner/omni.py)")
    p.add_argument("--out", required=True, metavar="DIR", help="output folder")
    _add_folder_options(p, "an output folder")
    add_robot_arguments(p)
    add_output_options(p, visual_default=True)
    p.add_argument("--simulate", action="store_true",
                   help="replay the plan in MuJoCo physics too (see silo4 simulate); "
                        "exit 1 when the robot does not walk it")
    p.set_defaults(run=run_plan)

    c = sub.add_parser(
        "cases", help="plan the thesis case studies and write the results page",
        description="Plan the straight path, the circle and the reduced-accuracy circle at "
                    "h = 0.2, 0.4, 0.6 m with both workspace presets, and the ditch "
                    "crossing (thesis Ch. 6); write one run folder per case under --out, "
                    "OUT/results.md, and, with --results-md, the same page there too.",
        epilog="regenerate the docs page: silo4 cases --out out/cases "
               "--results-md docs/results.md")
    c.add_argument("--out", required=True, metavar="DIR", help="output folder")
    c.add_argument("--results-md", metavar="PATH", default=None,
                   help="also write the results page here (e.g. docs/results.md)")
    c.add_argument("--paths", default="straight,circle,circle-reduced", metavar="LIST",
                   help="comma-separated subset of straight,circle,circle-reduced")
    c.add_argument("--heights", default="0.2,0.4,0.6", metavar="LIST",
                   help="comma-separated body heights [m] (default 0.2,0.4,0.6)")
    c.add_argument("--workspaces", default="thesis,default", metavar="LIST",
                   help="comma-separated presets (default thesis,default)")
    c.add_argument("--no-ditch", dest="ditch", action="store_false",
                   help="skip the ditch crossing (Fig 6.30)")
    c.add_argument("--simulate", action="store_true",
                   help="replay every case in MuJoCo physics and add the verdicts to the "
                        "results page (see silo4 simulate)")
    _add_planning_options(c)
    _add_folder_options(c, "case folders", csv=False)
    add_robot_arguments(c)
    add_output_options(c, visual_default=False)
    c.set_defaults(run=run_cases)


def _add_folder_options(p: argparse.ArgumentParser, what: str, csv: bool = True) -> None:
    p.add_argument("--force", action="store_true",
                   help=f"replace {what} that holds a different run")
    # cases: off by default (18 folders of CSV are ~300 MB and 2/3 of its CPU time)
    p.add_argument("--csv", action=argparse.BooleanOptionalAction, default=csv,
                   help="write trajectory.csv (trajectory.npz has the same data, exactly) "
                        f"(default: {'on' if csv else 'off'})")


def _add_planning_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--samples-per-unit", type=int, default=100, metavar="N",
                   help="samples per time unit t_l (default 100, thesis §5.5)")
    p.add_argument("--unit-time", type=_unit_time, default=1.0, metavar="S",
                   help="duration of one time unit (one leg transfer) [s], checked against "
                        "the URDF velocity and effort limits; 'auto': the shortest within "
                        "them (default 1)")


def _unit_time(text: str) -> float | str:
    """--unit-time: a number of seconds or 'auto'."""
    if text.strip().lower() == "auto":
        return "auto"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds or 'auto'"
                                         ) from None


def _check_planning_options(args: argparse.Namespace) -> None:
    if args.samples_per_unit < 1:
        raise Silo4Error(f"--samples-per-unit {args.samples_per_unit}: must be >= 1")
    if args.unit_time != "auto":
        _positive("--unit-time", args.unit_time)


# --------------------------------------------------------------------------- plan


def run_plan(args: argparse.Namespace) -> int:
    """Plan, write the folder, print a short summary."""
    import numpy as np

    from silo4kin.motors import format_sizing_table

    waypoints = (parse_waypoints(args.waypoints) if args.waypoints is not None
                 else read_path_file(args.path))
    if not np.all(np.isfinite(waypoints)):
        raise Silo4Error("waypoints must be finite numbers")
    _positive("--height", args.height)
    _finite("--start-heading", args.start_heading)
    _check_planning_options(args)
    _positive("--swing-height", args.swing_height)
    if args.tolerance is not None:
        _finite("--tolerance", args.tolerance)
        if args.tolerance < 0:
            raise Silo4Error(f"--tolerance {args.tolerance}: must be >= 0 [m]")
    from planner.export import write_run
    from planner.limits import limit_plan
    from planner.metrics import compute_metrics
    from planner.path import plan_path

    gearing_from_args(args)  # validate before the work
    robot = load_robot_from_args(args)
    t0 = time.perf_counter()
    plan = plan_path(robot, waypoints, args.height, start_heading=math.radians(args.start_heading),
                     workspace=args.workspace, tolerance=args.tolerance,
                     samples_per_unit=args.samples_per_unit,
                     unit_time_s=1.0 if args.unit_time == "auto" else args.unit_time,
                     swing_height_m=args.swing_height, face_path=args.face_path)
    plan, limits = limit_plan(robot, plan, args.unit_time,
                              load=args.load or str(plan.policy.load))
    metrics = compute_metrics(plan)
    metrics["joint_limits"] = limits.to_dict()
    for line in plan_warnings(metrics):
        print(line, file=sys.stderr)
    progress(f"  planned {len(plan.trajectory)} samples in {time.perf_counter() - t0:.2f} s")
    plan, metrics = with_torques(robot, plan, metrics, args)
    label = robot_label(args, robot)
    physics: list[dict] = []
    write_run(args.out, plan, metrics, robot_name=label, force=args.force, write_csv=args.csv,
              extra_writers=output_writers(args, plan, metrics, robot, title=label)
              + (simulate_writers(args, plan.trajectory, robot, label, physics)
                 if args.simulate else []))
    print(format_summary(plan, metrics, len(waypoints)))
    sizing = metrics.get("motor_sizing")
    if args.motors and isinstance(sizing, list):
        print(format_sizing_table(sizing))
    folder = Path(args.out)
    print(f"wrote {folder}/: {' '.join(sorted(p.name for p in folder.iterdir()))}")
    if args.html:
        print(f"open {(folder / 'animation.html').resolve().as_uri()}")
    if physics:
        print(format_sim_summary(physics[0]))
        return EXIT_OK if physics[0]["walks"] else EXIT_CHECK_FAILED
    return EXIT_OK


def format_summary(plan: Any, metrics: dict, n_waypoints: int) -> str:
    """Two lines: path, time, distance, speed; E_n, margin, cycles."""
    m = metrics
    return (f"{n_waypoints} waypoints at h = {plan.height:.3g} m, workspace "
            f"{plan.workspace.preset} (stride {m['stride_m']:.4f} m): "
            f"{m['normalized_time']:.0f} time units, {m['distance_m']:.2f} m, "
            f"{m['average_speed']:.3f} m/unit\n"
            f"E_n {m['normalized_error_m']:.3f} m, min stability margin "
            f"{m['min_stability_margin_m']:.3f} m, {m.get('n_creep_cycles', '?')} creep "
            f"cycles, {m.get('n_spin_cycles', '?')} spin cycles")


# --------------------------------------------------------------------------- cases


def _split(text: str, option: str, allowed: tuple[str, ...] | None = None) -> list[str]:
    items = [s.strip() for s in text.split(",") if s.strip()]
    if not items:
        raise Silo4Error(f"{option} {text!r}: empty list")
    if allowed is not None:
        for item in items:
            if item not in allowed:
                raise Silo4Error(f"{option}: {item!r} is not one of {', '.join(allowed)}")
    return items


def run_cases(args: argparse.Namespace) -> int:
    """Plan the thesis cases, write each run folder and the results page."""
    paths = _split(args.paths, "--paths", ("straight", "circle", "circle-reduced"))
    presets = _split(args.workspaces, "--workspaces", ("thesis", "default"))
    heights = []
    for item in _split(args.heights, "--heights"):
        try:
            heights.append(float(item))
        except ValueError:
            raise Silo4Error(f"--heights: {item!r} is not a number [m]") from None
        _positive("--heights", heights[-1])
    _check_planning_options(args)
    from planner.cases import run_case, thesis_cases
    from planner.ditch import plan_ditch_cases
    from planner.export import write_run
    from planner.files import write_text_atomically
    from planner.results_page import render_results_page

    from .progress import track

    gearing_from_args(args)  # validate before the work
    robot = load_robot_from_args(args)
    out = Path(args.out)
    label = robot_label(args, robot)

    results, refused = [], []
    for case in track(list(thesis_cases(paths, heights, presets)), "cases"):
        try:
            result = run_case(robot, case, samples_per_unit=args.samples_per_unit)
        except PlannerRefusal as exc:  # the planner said why; report it, go on
            print(f"{case.name:28s} refused: {exc}", file=sys.stderr)
            refused.append((case, str(exc)))
            continue
        plan, metrics = with_torques(robot, result.plan, result.metrics, args)
        write_run(out / case.name, plan, metrics, robot_name=label,
                  force=args.force, write_csv=args.csv,
                  extra_writers=output_writers(args, plan, metrics, robot,
                                               title=f"{label}: {case.name}"))
        m = result.metrics
        for line in plan_warnings(m):
            print(f"{case.name:28s} {line}", file=sys.stderr)
        margin = m["min_stability_margin_m"]
        margin = 0.0 if margin is not None and abs(margin) < 1e-9 else margin
        print(f"{case.name:28s} {m['normalized_time']:5.0f} units {m['distance_m']:5.2f} m "
              f"E_n {m['normalized_error_m']:.3f} m  margin {margin:.3f} m"
              f"  ({result.wall_time_s:.2f} s)")
        results.append(result)
    ditches = plan_ditch_cases(robot, presets, samples_per_unit=args.samples_per_unit) \
        if args.ditch else []
    for d in ditches:
        print(d.summary())
    page = render_results_page(results, ditches, refused=refused,
                               command=regenerate_command(args))
    if args.simulate:
        from .cli_simulate import simulate_cases

        page += simulate_cases(robot, results, out, args)
    written = [write_text_atomically(out / "results.md", page)]
    if args.results_md:
        written.append(write_text_atomically(Path(args.results_md), page))
    print(f"wrote {len(results)} case folders under {out}; results page: "
          + ", ".join(str(w) for w in written))
    if refused:
        print(f"{len(refused)} case(s) refused by the planner (listed on the page)",
              file=sys.stderr)
        return EXIT_CHECK_FAILED
    return EXIT_OK


def regenerate_command(args: argparse.Namespace) -> str:
    """The command line that regenerates the page (printed at its top)."""
    parts = ["silo4 cases --out", str(args.out)]
    if args.results_md:
        parts += ["--results-md", str(args.results_md)]
    defaults = {"paths": "straight,circle,circle-reduced", "heights": "0.2,0.4,0.6",
                "workspaces": "thesis,default"}
    for key, default in defaults.items():
        if getattr(args, key) != default:
            parts += [f"--{key}", getattr(args, key)]
    if args.samples_per_unit != 100:
        parts += ["--samples-per-unit", str(args.samples_per_unit)]
    if not args.ditch:
        parts.append("--no-ditch")
    if getattr(args, "simulate", False):
        parts.append("--simulate")
    if args.robot:
        parts += ["--robot", str(args.robot)]
    for item in args.xacro_arg:
        parts += ["--xacro-arg", item]
    return " ".join(parts)
