"""What a run folder holds beyond the plan's data: the pipeline's request from the options
(torques and motor sizing, App. A), the HTML animation, the plots and the report — options,
and the writers that fill the temporary folder of ``planner.outputs.run_folder.write_run``
(so everything appears or nothing does).
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from viz.cli.common import add_gear_options
from viz.cli.progress import progress_bar

if TYPE_CHECKING:
    from planner.outputs.pipeline import RunRequest
    from silo4kin.motors import Gearing

Writer = Callable[[Path], None]


def add_output_options(p: argparse.ArgumentParser, *, visual_default: bool) -> None:
    """--html/--no-html, --plots/--no-plots, --report, torque and gear options."""
    p.add_argument(
        "--html",
        action=argparse.BooleanOptionalAction,
        default=visual_default,
        help="write animation.html, the self-contained Meshcat animation "
        f"(default: {'on' if visual_default else 'off'})",
    )
    p.add_argument(
        "--plots",
        action=argparse.BooleanOptionalAction,
        default=visual_default,
        help="write PNG plots (joints, path, margin, torques, a cycle's Cartesian "
        f"trajectories) (default: {'on' if visual_default else 'off'})",
    )
    p.add_argument(
        "--svg",
        action="store_true",
        help="also write every plot as SVG (vector; each costs a second render)",
    )
    p.add_argument(
        "--window",
        metavar="T0:T1",
        default=None,
        help="also plot the joint histories from T0 to T1 [s] (e.g. 10:20)",
    )
    p.add_argument(
        "--torques",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="joint torques (tau_<joint> columns) and motor sizing in metrics.json (default: on)",
    )
    p.add_argument(
        "--load",
        choices=("body", "total"),
        default=None,
        help="mass the feet carry: 'body' (30 kg, the thesis) or 'total' "
        "(body and legs) (default: total; the thesis preset: body)",
    )
    add_gear_options(p)
    p.add_argument(
        "--motors",
        action="store_true",
        help="print the motor sizing table (peak/RMS torque, speed, power)",
    )


def gearing_from_args(
    args: argparse.Namespace, joint_names: Sequence[str] | None = None
) -> Gearing:
    """Validated gearing (bad values raise Silo4Error naming them): the ``--motors-file``
    table for ``joint_names`` when given (read once the robot is known), else
    ``--gear-ratio`` / ``--gear-efficiency`` for every joint."""
    from silo4kin.motor_table import gearing_from_options

    motors_file = getattr(args, "motors_file", None)
    if joint_names is None:  # validating the options before the robot loads
        names: Sequence[str] = [f"joint {k}" for k in range(12)]
        motors_file = None
    else:
        names = joint_names
    return gearing_from_options(names, args.gear_ratio, args.gear_efficiency, motors_file)


def run_request(args: argparse.Namespace, joint_names: Sequence[str] | None = None) -> RunRequest:
    """The plan pipeline's request from the options (planner.outputs.pipeline): unit time
    (``--unit-time``, a number [s] or "auto"), ``--load``, the gearing when ``--torques``
    (``--motors-file`` read for the robot's ``joint_names``); a URDF limit violation
    refuses the plan."""
    from planner.outputs.pipeline import RunRequest

    load = getattr(args, "load", None)
    return RunRequest(
        unit_time=args.unit_time,
        load="body" if load == "body" else "total" if load == "total" else None,
        gearing=gearing_from_args(args, joint_names) if args.torques else None,
        **({"torque_headroom": args.torque_headroom} if hasattr(args, "torque_headroom") else {}),
    )


def run_options(args: argparse.Namespace) -> dict[str, Any]:
    """The options that change a run's numbers but that its plan does not carry, for plan.json
    "inputs" (``planner.outputs.run_folder.write_run(options=...)``, keys of
    planner.outputs.documents.OPTION_DEFAULTS): two runs that differ in one are different
    runs (``--force`` to replace one by the other).
    An option a subcommand lacks (``silo4 cases`` has no --gait) is left at its default."""
    options: dict[str, Any] = {
        "unit_time_auto": getattr(args, "unit_time", None) == "auto",
        "torques": bool(args.torques),
        "load": getattr(args, "load", None),
        "gear_ratio": float(args.gear_ratio),
        "gear_efficiency": float(args.gear_efficiency),
        "motors_file": None
        if getattr(args, "motors_file", None) is None
        else str(Path(args.motors_file).resolve()),
    }
    if hasattr(args, "gait"):  # silo4 plan's planner options
        from planner.terrain.terrain_file import terrain_document

        options.update(
            gait=args.gait,
            face_path=bool(args.face_path),
            swing_height_request_m=args.swing_height,
            terrain=terrain_document(getattr(args, "terrain_map", None)),
        )
    return options


def exact_command(args: argparse.Namespace) -> str:
    """The command line that made this run, shell-quoted (report.html's header).

    ``viz.cli.main`` records its argv on ``args.argv``; without it (an API caller), the
    process's own arguments.
    """
    argv: Sequence[str] = getattr(args, "argv", None) or sys.argv[1:]
    return " ".join(shlex.quote(a) for a in ["silo4", *argv])


def run_inputs(args: argparse.Namespace, plan: Any, title: str) -> dict[str, Any]:
    """What the report's header shows: robot, waypoints, height, preset, the gait walked (the
    one asked for when it differs, and the plan's fallback reason), the command."""
    waypoints = [(float(x), float(y)) for x, y, *_ in plan.waypoints_in_world]
    walked = str(getattr(plan, "gait", ""))
    asked = getattr(args, "gait", None)
    gait = walked if asked in (None, "auto", walked) else f"{walked} (asked: {asked})"
    if getattr(plan, "fallback_reason", None):
        gait += f"; {plan.fallback_reason}"
    return {
        "robot": title,
        "waypoints_in_world": waypoints,
        "height_m": float(plan.height),
        "workspace": getattr(plan.workspace, "preset", str(plan.workspace)),
        "gait": gait,
        "unit_time_s": float(plan.trajectory.unit_time_s),
        "command": exact_command(args),
    }


def output_writers(
    args: argparse.Namespace,
    plan: Any,
    metrics: dict,
    robot: Any,
    title: str,
    before_report: Sequence[Writer] = (),
) -> list[Writer]:
    """Writers for animation.html, plots and report.html, as the options ask;
    ``before_report`` (the physics replay of ``plan --simulate``) runs before the report,
    so the page shows what they wrote."""
    writers: list[Writer] = []
    waypoints = plan.waypoints_in_world
    made: list[Path] = []
    window = None
    if getattr(args, "window", None):
        from viz.plots.figure_names import parse_window

        window = parse_window(args.window)  # a bad window is refused before any work
    formats = ("png", "svg") if getattr(args, "svg", False) else ("png",)

    if args.html:
        from viz.animation.page import write_animation_html

        terrain = getattr(args, "terrain_map", None)  # silo4 plan --terrain, read once

        def html(folder: Path) -> None:
            _stage(
                "animation.html",
                lambda: write_animation_html(
                    folder / "animation.html",
                    robot,
                    plan.trajectory,
                    waypoints_in_world=waypoints,
                    title=title,
                    terrain=terrain,
                ),
            )

        writers.append(html)
    if args.plots and len(plan.trajectory) < 2:
        print("no plots: the plan has nothing to do (one sample, the start pose)")
    elif args.plots:
        writers.append(_PlotWriter(plan.trajectory, waypoints, formats, window, made))
    if getattr(args, "terrain_map", None) is not None and (args.html or args.plots):
        from viz.report.terrain_view import terrain_view_writer  # the report's top view

        writers.append(terrain_view_writer(args.terrain_map, plan.trajectory, made))
    writers.extend(before_report)
    if args.html or args.plots:
        from viz.report.page import write_report

        def report(folder: Path) -> None:
            write_report(
                folder,
                metrics=metrics,
                plots=made,
                animation="animation.html" if args.html else None,
                title=title,
                inputs=run_inputs(args, plan, title),
            )

        writers.append(report)
    return writers


class _PlotWriter:
    """The plots writer: started before the CSV (worker processes, viz/plots/workers.py),
    collected after the other writers; the written files go into ``made``."""

    def __init__(
        self,
        trajectory: Any,
        waypoints: Any,
        formats: Sequence[str],
        window: tuple[float, float] | None,
        made: list[Path],
    ) -> None:
        from viz.plots.workers import plot_job

        self.job = plot_job(
            trajectory, waypoints_in_world=waypoints, formats=formats, window_s=window
        )
        self.made = made

    def start(self, folder: Path) -> None:
        self.job.start(folder)

    def stop(self) -> None:
        self.job.stop()

    def __call__(self, folder: Path) -> None:
        with progress_bar(len(self.job.stems), "plots") as bar:
            self.made.extend(self.job.finish(folder, on_figure=lambda stem: bar.update()))


def progress(message: str, end: str = "\n") -> None:
    """A progress line on stderr, only for a person at a terminal (keeps logs and pipes clean)."""
    if sys.stderr.isatty():
        print(message, end=end, file=sys.stderr, flush=True)


def _stage(name: str, work: Callable[[], Any]) -> Any:
    """Run one output stage, telling the user what is being written and how long it took."""
    progress(f"  writing {name} ...", end="")
    t0 = time.perf_counter()
    result = work()
    progress(f" {time.perf_counter() - t0:.1f} s")
    return result
