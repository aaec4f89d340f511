"""The ``silo4`` command line: ``check``, ``plan``, ``cases``, ``animate``, ``simulate``,
``export``, ``workspace``, ``sweep``.

Exit codes: 0 success (also when the reader of stdout closes it, ``silo4 robots | head -1``),
1 a check failed, 2 bad input (one line on stderr, no traceback), 130 / 143 / 129 interrupted
by SIGINT / SIGTERM / SIGHUP (temporary files removed). Each subcommand lives in its own module
with ``add_parser(subparsers)`` and ``run(args)``; what they share lives
in ``viz/cli/common.py`` (the import graph is a tree rooted here).
"""

from __future__ import annotations

import argparse
import functools
import os
import re
import signal
import sys
from collections.abc import Sequence
from typing import Any

from silo4kin.errors import Silo4Error
from viz.cli.common import (
    EXIT_BAD_INPUT,
    EXIT_CHECK_FAILED,
    EXIT_HUNG_UP,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_TERMINATED,
    CliParser,
    add_robot_arguments,
    load_robot_from_args,
    print_error,
)

# add_robot_arguments / load_robot_from_args are re-exported only for subcommand modules
# written before viz/cli/common.py existed; import them from cli_common (tests/test_layers.py
# names any module that imports viz/cli/main.py back).
__all__ = [
    "EXIT_BAD_INPUT",
    "EXIT_CHECK_FAILED",
    "EXIT_OK",
    "add_robot_arguments",
    "build_parser",
    "load_robot_from_args",
    "main",
]

#: A value that starts with '-' but is data, not an option: "-1,2", "-90", "-.5,1 2,3".
_NEGATIVE_VALUE = re.compile(r"^-(?:\d|\.\d)")


def package_version() -> str:
    """The installed distribution's version (``silo4 --version``)."""
    from importlib.metadata import PackageNotFoundError, version  # ~30 ms: only when asked

    try:
        return version("silo4kin")
    except PackageNotFoundError:  # running from a checkout that was never installed
        return "unknown (not installed)"


class _VersionAction(argparse.Action):
    """``--version``: look the version up only when asked (importlib.metadata costs more
    than the rest of ``silo4 --help``)."""

    def __init__(
        self,
        option_strings: Sequence[str],
        dest: str = argparse.SUPPRESS,
        default: str = argparse.SUPPRESS,
        help: str = "show the installed version and exit",
    ) -> None:  # noqa: A002
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: object,
        option_string: str | None = None,
    ) -> None:
        print(f"silo4 (silo4kin) {package_version()}")
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand registered."""
    import viz.cli.animate as cli_animate
    import viz.cli.check as cli_check
    import viz.cli.export as cli_export
    import viz.cli.plan as cli_plan
    import viz.cli.robots as cli_robots
    import viz.cli.simulate as cli_simulate
    import viz.cli.sweep as cli_sweep
    import viz.cli.workspace as cli_workspace
    from silo4kin.robot_library import known_robot_names

    parser = CliParser(
        prog="silo4",
        description="Plan statically stable walking for insect- and mammal-leg quadrupeds "
        "and check their kinematics against the closed form (SILO4 thesis).",
        epilog="examples:\n"
        "  silo4 check\n"
        '  silo4 plan --waypoints "0,1 1,1 0,2 0,3" --height 0.4 '
        "--start-heading 90 --out out/straight\n"
        "  silo4 cases --out out/cases\n"
        "  silo4 animate out/straight --unit-time 0.5\n"
        f"robots by name (--robot NAME): {', '.join(known_robot_names())}",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action=_VersionAction)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=CliParser)
    cli_check.add_parser(sub)
    cli_plan.add_parsers(sub)
    cli_animate.add_parser(sub)
    cli_simulate.add_parser(sub)
    cli_export.add_parser(sub)
    cli_workspace.add_parser(sub)
    cli_sweep.add_parser(sub)
    cli_robots.add_parser(sub)
    return parser


def _value_options(parser: argparse.ArgumentParser) -> set[str]:
    """Option strings (of the parser and its subparsers) that take a value."""
    options: set[str] = set()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                options |= _value_options(sub)
        elif action.option_strings and action.nargs != 0:
            options |= set(action.option_strings)
    return options


def join_negative_values(argv: Sequence[str], parser: argparse.ArgumentParser) -> list[str]:
    """``--waypoints -1,2`` -> ``--waypoints=-1,2``: argparse takes a value starting with '-'
    for an option unless it is a plain negative number, so a first waypoint with negative x
    was refused ("expected one argument")."""
    takes_value = _value_options(parser)
    out: list[str] = []
    i = 0
    while i < len(argv):
        token = argv[i]
        if token in takes_value and i + 1 < len(argv) and _NEGATIVE_VALUE.match(argv[i + 1]):
            out.append(f"{token}={argv[i + 1]}")
            i += 2
            continue
        out.append(token)
        i += 1
    return out


#: The last stop signal received (SIGINT -> exit 130, SIGTERM -> 143, SIGHUP -> 129).
_last_signal: list[int] = [signal.SIGTERM]


def _raise_terminated(signum: int, frame: object) -> None:
    """SIGTERM, SIGHUP and SIGINT: record the request (library code may swallow the exception, e.g.
    when the signal lands in a finaliser) and raise in the main thread so cleanup runs."""
    from planner.outputs.files import RunInterrupted, request_stop  # loaded by main() before

    request_stop()
    _last_signal[0] = signum
    if signum == signal.SIGINT:
        raise KeyboardInterrupt()
    raise RunInterrupted()


#: OpenBLAS threads of a ``silo4`` process unless the user sets OPENBLAS_NUM_THREADS: the
#: planner's products are thin ((N, 3) by (3, P) at most), where OpenBLAS's worker threads
#: only spin. ``silo4 cases`` (bench_run.py's 8 cases and ditch) on the shared 2-core machine
#: at load ~6: 8.43 -> 6.97 s CPU (medians of 3, alternated), the same outputs.
BLAS_THREADS = "1"


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``silo4`` console script."""
    # before numpy is imported (nothing above imports it); a user's own setting is kept
    os.environ.setdefault("OPENBLAS_NUM_THREADS", BLAS_THREADS)
    parser = build_parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    args = parser.parse_args(join_negative_values(argv, parser))
    # after the parse: --help does not need it; before the handlers that use it
    from planner.outputs.files import RunInterrupted, stop_requested

    previous = signal.getsignal(signal.SIGTERM) or signal.SIG_DFL
    previous_int = signal.getsignal(signal.SIGINT) or signal.default_int_handler
    in_main_thread = _set_sigterm(_raise_terminated)
    previous_hup = signal.getsignal(signal.SIGHUP) or signal.SIG_DFL
    if in_main_thread:
        signal.signal(signal.SIGINT, _raise_terminated)
        signal.signal(signal.SIGHUP, _raise_terminated)  # the terminal closed: clean up too
    previous_unraisable = sys.unraisablehook
    sys.unraisablehook = functools.partial(_quiet_interrupt, previous_unraisable)
    args.argv = argv  # report.html shows the command
    try:
        code = int(args.run(args))
        sys.stdout.flush()  # here, not at exit: a closed pipe is then caught below
        if stop_requested():  # a signal came but library code swallowed its exception
            if _last_signal[0] == signal.SIGINT:
                raise KeyboardInterrupt()
            raise RunInterrupted()
        return code
    except Silo4Error as exc:
        print_error(args.command, exc)
        return EXIT_BAD_INPUT
    except BrokenPipeError as exc:
        if _stdout_closed():  # by its reader (`silo4 robots | head -1`): the reader's choice
            _silence_stdout()
            return EXIT_OK
        print_error(args.command, f"a helper process ended early ({exc.strerror or exc})")
        return EXIT_BAD_INPUT
    except OSError as exc:  # a path the system refuses (name too long, no permission, disk full)
        where = f"{str(exc.filename)[:60]}: " if exc.filename else ""
        print_error(args.command, f"{where}{exc.strerror or exc}")
        return EXIT_BAD_INPUT
    except MemoryError:
        print_error(
            args.command, "out of memory; plan fewer samples (--samples-per-unit) or a shorter path"
        )
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except RunInterrupted:  # raised by the handler, or by planner.outputs.files on the stop flag
        if _last_signal[0] == signal.SIGINT:
            print("interrupted", file=sys.stderr)
            return EXIT_INTERRUPTED
        if _last_signal[0] == signal.SIGHUP:
            print("hung up", file=sys.stderr)
            return EXIT_HUNG_UP
        print("terminated", file=sys.stderr)
        return EXIT_TERMINATED
    finally:
        sys.unraisablehook = previous_unraisable
        if in_main_thread:
            _set_sigterm(previous)
            signal.signal(signal.SIGINT, previous_int)
            signal.signal(signal.SIGHUP, previous_hup)


def _stdout_closed() -> bool:
    """True when stdout is a pipe whose reader has gone (poll reports an error on it)."""
    import select

    try:
        poller = select.poll()
        poller.register(sys.stdout.fileno(), select.POLLOUT)
        return any(event & (select.POLLERR | select.POLLHUP) for _, event in poller.poll(0))
    except (OSError, ValueError, AttributeError):  # no real stdout: not a closed pipe
        return False


def _silence_stdout() -> None:
    """Point stdout at /dev/null: the reader has gone, and Python's flush at exit would
    otherwise print "Exception ignored ... BrokenPipeError"."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # no real stdout (a test's StringIO): nothing to silence
        pass


def _quiet_interrupt(previous: Any, unraisable: Any) -> None:
    """A SIGTERM that lands inside a finaliser or callback (e.g. logging's lock release)
    raises there, where Python can only print "Exception ignored ..." on stderr. The stop
    flag it set makes main() end the run anyway (exit 143, temporary folder removed), so that
    print would only break the one-line error contract; anything else is printed as usual."""
    from planner.outputs.files import RunInterrupted  # loaded by main() before

    if isinstance(unraisable.exc_value, (RunInterrupted, KeyboardInterrupt)):
        return
    previous(unraisable)


def _set_sigterm(handler) -> bool:  # noqa: ANN001 (a signal handler or SIG_DFL/SIG_IGN)
    """Install a SIGTERM handler; False (nothing done) outside the main thread."""
    try:
        signal.signal(signal.SIGTERM, handler)
    except (ValueError, TypeError):  # not the main thread, or no previous Python handler
        return False
    return True


if __name__ == "__main__":
    raise SystemExit(main())
