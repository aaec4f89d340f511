"""What every ``silo4`` subcommand shares: exit codes, robot options, value checks, error lines.

The import graph of the CLI is a tree: ``viz/cli/main.py`` (entry point) imports the subcommand
modules, and they import this module; nothing here imports them back.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, cast

from planner.budget import MAX_SAMPLES_PER_UNIT, UNIT_TIME_RANGE_S
from silo4kin.errors import Silo4Error, XacroArgumentError

EXIT_OK = 0
EXIT_CHECK_FAILED = 1
EXIT_BAD_INPUT = 2
#: 128 + signal number, as a shell reports a process ended by SIGINT / SIGTERM / SIGHUP.
EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143
EXIT_HUNG_UP = 129

#: Longest text of a user error printed (a message quoting a whole file stays one line).
MAX_ERROR_CHARS = 2000


class CliParser(argparse.ArgumentParser):
    """argparse exits with 2 on bad usage already; keep its message to one line."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {one_line(message)}\n")

    def _get_formatter(self) -> argparse.HelpFormatter:
        # argparse's formatter imports shutil (with bz2, lzma, fnmatch: ~2.5 ms of
        # `silo4 --help`) only to ask the terminal width: the same width here
        # (typeshed's _FormatterClass declares only prog; every argparse formatter takes width)
        formatter_class = cast("type[argparse.HelpFormatter]", self.formatter_class)
        return formatter_class(prog=self.prog, width=help_width())


def help_width() -> int:
    """The width argparse's HelpFormatter uses (``shutil.get_terminal_size().columns - 2``:
    $COLUMNS if a positive integer, else the width of the terminal on stdout, else 80),
    found without importing shutil."""
    import os

    try:
        columns = int(os.environ["COLUMNS"])
    except (KeyError, ValueError):
        columns = 0
    if columns <= 0:
        stdout = sys.__stdout__
        try:
            columns = (os.get_terminal_size(stdout.fileno()).columns if stdout else 0) or 80
        except (AttributeError, ValueError, OSError):  # no stdout, or not a terminal
            columns = 80
    return columns - 2


def one_line(text: object) -> str:
    """``text`` on a single line (newlines and tabs become spaces), at most MAX_ERROR_CHARS."""
    flat = " ".join(str(text).split())
    return flat if len(flat) <= MAX_ERROR_CHARS else flat[: MAX_ERROR_CHARS - 3] + "..."


def print_error(command: str, exc: BaseException | str) -> None:
    """The one line a user error becomes on stderr: ``silo4 COMMAND: error: MESSAGE``."""
    print(f"silo4 {command}: error: {one_line(exc)}", file=sys.stderr)


# --------------------------------------------------------------------------- robot


def add_robot_arguments(p: argparse.ArgumentParser) -> None:
    """``--robot PATH|NAME``, repeated ``--xacro-arg name=value`` and ``--package-dir DIR``."""
    from silo4kin.robot_library import known_robot_names  # light: no numpy, no dataclasses

    p.add_argument(
        "--robot",
        metavar="PATH|NAME",
        default=None,
        help="robot .urdf or .urdf.xacro file, or a robot name: "
        f"{', '.join(known_robot_names())} (example-robot-data's; "
        "robot_descriptions spellings such as go2_description too) "
        "(default: the SILO4 xacro)",
    )
    p.add_argument(
        "--xacro-arg",
        metavar="NAME=VALUE",
        action="append",
        default=[],
        help="xacro argument override, repeatable (e.g. --xacro-arg L3=0.3)",
    )
    p.add_argument(
        "--package-dir",
        metavar="DIR",
        action="append",
        default=[],
        help="folder to resolve package://, $(find pkg) and relative mesh "
        "paths against, repeatable",
    )


def xacro_args_from(args: argparse.Namespace) -> dict[str, str]:
    """``--xacro-arg`` items as a name -> value mapping (refuses items that are not NAME=VALUE)."""
    xacro_args: dict[str, str] = {}
    for item in args.xacro_arg:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise XacroArgumentError(f"--xacro-arg {item!r} is not NAME=VALUE", item, ())
        xacro_args[name.strip()] = value.strip()
    return xacro_args


def is_dir(path: str | Path, option: str) -> bool:
    """``Path.is_dir`` that turns a name the system refuses (too long, ...) into a Silo4Error
    naming the option, instead of an OSError."""
    try:
        return Path(path).is_dir()
    except OSError as exc:
        raise Silo4Error(f"{option} {str(path)[:40]!r}...: {exc.strerror or exc}") from None


def load_robot_from_args(args: argparse.Namespace) -> Any:
    """Load the robot named by :func:`add_robot_arguments` options (a ``silo4kin.Robot``)."""
    from silo4kin.robot import load_robot

    for folder in args.package_dir:
        if not is_dir(folder, "--package-dir"):
            raise Silo4Error(f"--package-dir {folder!r}: not a folder")
    xacro_args = xacro_args_from(args)
    return load_robot(args.robot, xacro_args or None, package_dirs=args.package_dir or None)


def robot_source(args: argparse.Namespace) -> dict[str, Any]:
    """Where the robot came from, recorded in plan.json so ``silo4 animate`` and ``silo4
    simulate`` load it again: ``{"file": absolute path or None (SILO4 or a robot by name),
    "name": library name (e.g. "go2") or None, "xacro_args": {...}, "package_dirs": [...]}``."""
    from silo4kin.robot_library import looks_like_name

    named = bool(args.robot) and looks_like_name(args.robot)
    return {
        "file": str(Path(args.robot).resolve()) if args.robot and not named else None,
        "name": args.robot if named else None,
        "xacro_args": xacro_args_from(args),
        "package_dirs": [str(Path(d).resolve()) for d in args.package_dir],
    }


def recorded_robot_args(args: argparse.Namespace, document: dict[str, Any]) -> argparse.Namespace:
    """The robot options of a run: the user's (``--robot`` or ``--xacro-arg`` given), else
    those its plan.json ``robot_source`` records (:func:`robot_source`)."""
    source = document.get("robot_source")
    if args.robot or args.xacro_arg or not isinstance(source, dict):
        return args
    file, name = source.get("file"), source.get("name")
    xacro = source.get("xacro_args") or {}
    dirs = source.get("package_dirs") or []
    if (
        not (file is None or isinstance(file, str))
        or not (name is None or isinstance(name, str))
        or not isinstance(xacro, dict)
        or not isinstance(dirs, list)
    ):
        raise Silo4Error(f"{args.run_dir}/plan.json: robot_source is malformed; give --robot")
    if file is not None and not Path(file).is_file():
        raise Silo4Error(
            f"{args.run_dir}/plan.json records robot file {file}, which does not "
            "exist any more; give --robot"
        )
    return argparse.Namespace(
        robot=file or name,
        xacro_arg=[f"{k}={v}" for k, v in xacro.items()],
        package_dir=[str(d) for d in dirs] + list(args.package_dir),
    )


# --------------------------------------------------------------------------- numbers


def check_finite(name: str, value: float | None) -> None:
    """Refuse NaN and infinities (argparse's ``type=float`` accepts both)."""
    if value is not None and not math.isfinite(value):
        raise Silo4Error(f"{name} {value}: must be a finite number")


def check_positive(name: str, value: float | None) -> None:
    """Refuse a value that is not finite and > 0."""
    check_finite(name, value)
    if value is not None and value <= 0:
        raise Silo4Error(f"{name} {value}: must be > 0")


def check_height(name: str, value: float) -> None:
    """Refuse a body height that is not finite and > 0, or that looks like centimetres or
    millimetres ("did you mean 0.40 m?", planner/request.py), before the robot is loaded."""
    from planner.request import check_height_scale

    check_positive(name, value)
    check_height_scale(name, value)


def check_range(name: str, value: float, lo: float, hi: float, unit: str = "") -> None:
    """Refuse a value outside [lo, hi] (also NaN), naming the range."""
    check_finite(name, value)
    if not lo <= value <= hi:
        raise Silo4Error(f"{name} {value:g}: must be in [{lo:g}, {hi:g}]{unit}")


def check_length_range(name: str, value: float, lo: float, hi: float) -> None:
    """:func:`check_range` for a length [m]; a value above ``hi`` that is in range as
    centimetres or millimetres gets "did you mean 0.05 m (cm)?"."""
    check_finite(name, value)
    if lo <= value <= hi:
        return
    guesses = [
        f"{value / scale:.{digits}f} m ({unit})"
        for scale, digits, unit in ((100.0, 2, "cm"), (1000.0, 3, "mm"))
        if value > hi and lo <= value / scale <= hi
    ]
    hint = f"; did you mean {' or '.join(guesses)}? lengths are in metres" if guesses else ""
    raise Silo4Error(f"{name} {value:g}: must be in [{lo:g}, {hi:g}] [m]{hint}")


# --------------------------------------------------------------------------- plan options


def add_folder_options(p: argparse.ArgumentParser, what: str, csv: bool = True) -> None:
    """``--force`` and ``--csv/--no-csv`` (default ``csv``)."""
    p.add_argument(
        "--force",
        action="store_true",
        help=f"replace {what} that holds a different run (never your own files)",
    )
    # cases: off by default (18 folders of CSV are ~300 MB and 2/3 of its CPU time)
    p.add_argument(
        "--csv",
        action=argparse.BooleanOptionalAction,
        default=csv,
        help="write trajectory.csv (trajectory.npz has the same data, exactly) "
        f"(default: {'on' if csv else 'off'})",
    )


def number_or_auto(what: str) -> Callable[[str], float | str]:
    """An argparse ``type``: a number (``what`` names its unit) or the word 'auto'."""

    def parse(text: str) -> float | str:
        if text.strip().lower() == "auto":
            return "auto"
        try:
            return float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{text[:40]!r} is neither {what} nor 'auto'"
            ) from None

    return parse


def add_planning_options(p: argparse.ArgumentParser, allow_auto: bool = False) -> None:
    """``--samples-per-unit`` and ``--unit-time`` (``auto`` too where ``allow_auto``)."""
    p.add_argument(
        "--samples-per-unit",
        type=int,
        default=100,
        metavar="N",
        help=f"samples per time unit t_l, 1-{MAX_SAMPLES_PER_UNIT} (default 100, thesis §5.5)",
    )
    if allow_auto:
        p.add_argument(
            "--unit-time",
            type=number_or_auto("a number of seconds"),
            default=1.0,
            metavar="S|auto",
            help="duration of one time unit (one leg transfer) [s] "
            f"({UNIT_TIME_RANGE_S[0]:g}-{UNIT_TIME_RANGE_S[1]:g}, default 1), "
            "checked against the URDF velocity and effort limits; 'auto': "
            "the shortest within them",
        )
    else:
        p.add_argument(
            "--unit-time",
            type=float,
            default=1.0,
            metavar="S",
            help="duration of one time unit (one leg transfer) [s] "
            f"({UNIT_TIME_RANGE_S[0]:g}-{UNIT_TIME_RANGE_S[1]:g}, default 1)",
        )


def check_planning_options(args: argparse.Namespace) -> None:
    """Refuse --samples-per-unit and --unit-time outside their ranges (planner/request.py)."""
    if not 1 <= args.samples_per_unit <= MAX_SAMPLES_PER_UNIT:
        raise Silo4Error(
            f"--samples-per-unit {args.samples_per_unit}: must be in [1, {MAX_SAMPLES_PER_UNIT}]"
        )
    if args.unit_time != "auto":
        check_range("--unit-time", args.unit_time, *UNIT_TIME_RANGE_S, " [s]")


def add_gear_options(p: argparse.ArgumentParser) -> None:
    """``--gear-ratio`` and ``--gear-efficiency`` (motor sizing, eq A.35-A.36)."""
    from silo4kin.motor_defaults import DEFAULT_GEAR_EFFICIENCY, DEFAULT_GEAR_RATIO

    p.add_argument(
        "--gear-ratio",
        type=float,
        default=DEFAULT_GEAR_RATIO,
        metavar="MU",
        help=f"gear ratio of every joint, eq A.35-A.36 (default {DEFAULT_GEAR_RATIO:g})",
    )
    p.add_argument(
        "--gear-efficiency",
        type=float,
        default=DEFAULT_GEAR_EFFICIENCY,
        metavar="ETA",
        help=f"gear efficiency of every joint, in (0, 1] (default {DEFAULT_GEAR_EFFICIENCY:g})",
    )
    p.add_argument(
        "--motors-file",
        metavar="FILE",
        default=None,
        help="motor table (JSON or YAML: gear ratio and efficiency for all "
        "joints, per joint type or per joint; docs/torques.md) instead of "
        "--gear-ratio / --gear-efficiency",
    )


def plan_warnings(metrics: Any) -> list[str]:
    """The metrics' warning lines (planner.path.metrics: e.g. the whole-robot CoM leaving the
    support polygon with the thesis preset)."""
    lines = metrics.get("warnings") or []
    return [str(line) for line in lines] if isinstance(lines, list) else []


def robot_label(args: argparse.Namespace, robot: Any) -> str:
    """Robot name plus non-default xacro arguments, recorded in plan.json."""
    overrides = " ".join(sorted(args.xacro_arg))
    source = f" from {args.robot}" if args.robot else ""
    return f"{robot.name}{source}" + (f" [{overrides}]" if overrides else "")
