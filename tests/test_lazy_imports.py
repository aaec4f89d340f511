"""``silo4 --help`` imports no heavy library (issue 14: within 3x of a bare Python start).

Checked structurally, not by the clock: a fresh interpreter builds the whole parser and
prints the help of every subcommand, then lists which heavy modules got imported.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

#: Libraries that cost 50-400 ms to import and no help text needs.
HEAVY = ("numpy", "pinocchio", "matplotlib", "meshcat", "rosbags", "tqdm", "yourdfpy", "xacro")

PROBE = """
import contextlib, io, sys
from viz.cli.main import build_parser
parser = build_parser()
for argv in (["--help"], ["plan", "--help"], ["cases", "--help"], ["export", "--help"],
             ["check", "--help"], ["animate", "--help"]):
    with contextlib.redirect_stdout(io.StringIO()):
        try:
            parser.parse_args(argv)
        except SystemExit:
            pass
print(" ".join(sorted({m.split(".")[0] for m in sys.modules} & set(sys.argv[1:]))))
"""


def test_help_imports_no_heavy_library() -> None:
    """Building the parser and every --help text imports none of HEAVY; the same probe
    does see numpy once the planner is imported (so the check can fail)."""
    out = subprocess.run(
        [sys.executable, "-c", PROBE, *HEAVY], capture_output=True, text=True, check=True
    ).stdout.split()
    assert out == []
    control = subprocess.run(
        [sys.executable, "-c", "import planner.path.plan_path\n" + PROBE, *HEAVY],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    assert "numpy" in control and "pinocchio" in control


#: Modules --help used to import for nothing (issue 14, a few ms each: with
#: PYTHONDONTWRITEBYTECODE=1, as on the CI machine, every module of ours is compiled on each
#: start, so its source size counts too): dataclasses (+ inspect, ast, dis) came with
#: silo4sim.thresholds for four defaults (now silo4sim/threshold_defaults.py); shutil (+ bz2, lzma,
#: fnmatch) with argparse's help formatter, only for the terminal width (now
#: viz.cli.common.help_width); planner.outputs.files and viz.cli.paths, needed only by a run.
NOT_FOR_HELP = (
    "dataclasses",
    "inspect",
    "silo4sim.thresholds",
    "shutil",
    "lzma",
    "planner.outputs.files",
    "viz.cli.paths",
)

PROBE_MODULES = PROBE.replace('{m.split(".")[0] for m in sys.modules}', "set(sys.modules)")


def test_help_imports_none_of_the_modules_it_used_to() -> None:
    """Building the parser and every --help text imports none of NOT_FOR_HELP; the same probe
    sees them once they are imported (so the check can fail)."""
    out = subprocess.run(
        [sys.executable, "-c", PROBE_MODULES, *NOT_FOR_HELP],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    assert out == []
    imports = "import silo4sim.thresholds, shutil, planner.outputs.files, viz.cli.paths\n"
    control = subprocess.run(
        [sys.executable, "-c", imports + PROBE_MODULES, *NOT_FOR_HELP],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    assert set(control) == set(NOT_FOR_HELP)


def test_threshold_defaults_are_the_thresholds_defaults() -> None:
    """The numbers --help shows are the Thresholds dataclass's defaults (one source)."""
    from silo4sim import threshold_defaults as d
    from silo4sim.thresholds import Thresholds

    t = Thresholds()
    assert (t.drift_m, t.slip_m, t.yaw_deg, t.tilt_deg) == (
        d.DEFAULT_DRIFT_M,
        d.DEFAULT_SLIP_M,
        d.DEFAULT_YAW_DEG,
        d.DEFAULT_TILT_DEG,
    )


@pytest.mark.parametrize("columns", ["50", "200", "", "x", "-3"])
def test_help_width_is_argparse_width(monkeypatch: pytest.MonkeyPatch, columns: str) -> None:
    """CliParser's help formatter gets the width argparse's own would (shutil's terminal
    width minus 2), with $COLUMNS set, empty or malformed (stdout is not a terminal here)."""
    import argparse
    import shutil

    from viz.cli.common import CliParser

    monkeypatch.setenv("COLUMNS", columns)
    ours = CliParser(prog="silo4")._get_formatter()
    theirs = argparse.ArgumentParser(prog="silo4")._get_formatter()
    assert ours._width == theirs._width == shutil.get_terminal_size().columns - 2


BLAS_PROBE = """
import os, sys
from viz.cli.main import main
try:
    main(sys.argv[1:])
except SystemExit:  # --help
    pass
import numpy  # noqa: F401  (what a run imports after main set the environment)
print(os.environ.get("OPENBLAS_NUM_THREADS"))
"""


@pytest.mark.parametrize(("preset", "expected"), [(None, "1"), ("3", "3")])
def test_silo4_runs_one_blas_thread_unless_told(preset, expected) -> None:
    """``silo4`` sets OPENBLAS_NUM_THREADS=1 before numpy is imported (the planner's thin
    products only spin OpenBLAS's workers), and keeps a user's own setting."""
    import os

    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    if preset is not None:
        env["OPENBLAS_NUM_THREADS"] = preset
    out = subprocess.run(
        [sys.executable, "-c", BLAS_PROBE, "robots", "--help"],
        capture_output=True,
        text=True,
        check=False,
        env=env,
    ).stdout.split()
    assert out[-1:] == [expected]
