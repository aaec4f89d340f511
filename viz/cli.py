"""The ``silo4`` command line: ``check``, ``plan``, ``cases``, ``animate``, ``simulate``.

Exit codes: 0 success, 1 a check failed, 2 bad input (one line on stderr, no traceback).
Each subcommand lives in its own module with ``add_parser(subparsers)`` and ``run(args)``.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from silo4kin.errors import Silo4Error

EXIT_OK = 0
EXIT_CHECK_FAILED = 1
EXIT_BAD_INPUT = 2


class _Parser(argparse.ArgumentParser):
    """argparse exits with 2 on bad usage already; keep its message to one line."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.print_usage(sys.stderr)
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand registered."""
    from . import cli_animate, cli_check, cli_export, cli_plan, cli_robots, cli_simulate, cli_sweep, cli_workspace  # noqa: E501

    parser = _Parser(
        prog="silo4",
        description="Plan statically stable walking for insect-leg quadrupeds and check "
                    "their kinematics against the closed form (SILO4 thesis).",
        epilog="examples:\n"
               "  silo4 check\n"
               "  silo4 plan --waypoints \"0,1 1,1 0,2 0,3\" --height 0.4 "
               "--start-heading 90 --out out/straight\n"
               "  silo4 cases --out out/cases\n"
               "  silo4 animate out/straight --unit-time 0.5",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    cli_check.add_parser(sub)
    cli_plan.add_parsers(sub)
    cli_animate.add_parser(sub)
    cli_simulate.add_parser(sub)
    cli_export.add_parser(sub)
    cli_workspace.add_parser(sub)
    cli_sweep.add_parser(sub)
    cli_robots.add_parser(sub)
    return parser


def add_robot_arguments(p: argparse.ArgumentParser) -> None:
    """``--robot PATH`` and repeated ``--xacro-arg name=value`` (shared by subcommands)."""
    p.add_argument("--robot", metavar="PATH", default=None,
                   help="robot .urdf or .urdf.xacro (default: the SILO4 xacro)")
    p.add_argument("--xacro-arg", metavar="NAME=VALUE", action="append", default=[],
                   help="xacro argument override, repeatable (e.g. --xacro-arg L3=0.3)")
    p.add_argument("--package-dir", metavar="DIR", action="append", default=[],
                   help="folder to resolve package:// and relative mesh paths against")


def load_robot_from_args(args: argparse.Namespace):  # noqa: ANN201 (Robot)
    """Load the robot named by :func:`add_robot_arguments` options."""
    from silo4kin.errors import XacroArgumentError
    from silo4kin.robot import load_robot

    xacro_args: dict[str, str] = {}
    for item in args.xacro_arg:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise XacroArgumentError(
                f"--xacro-arg {item!r} is not NAME=VALUE", item, ())
        xacro_args[name.strip()] = value.strip()
    return load_robot(args.robot, xacro_args or None, package_dirs=args.package_dir or None)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``silo4`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)  # report.html shows the command
    try:
        return int(args.run(args))
    except Silo4Error as exc:
        print(f"silo4 {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
