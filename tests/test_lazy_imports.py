"""``silo4 --help`` imports no heavy library (issue 14: within 3x of a bare Python start).

Checked structurally, not by the clock: a fresh interpreter builds the whole parser and
prints the help of every subcommand, then lists which heavy modules got imported.
"""

from __future__ import annotations

import subprocess
import sys

#: Libraries that cost 50-400 ms to import and no help text needs.
HEAVY = ("numpy", "pinocchio", "matplotlib", "meshcat", "rosbags", "tqdm", "yourdfpy", "xacro")

PROBE = """
import contextlib, io, sys
from viz.cli import build_parser
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
    out = subprocess.run([sys.executable, "-c", PROBE, *HEAVY], capture_output=True,
                         text=True, check=True).stdout.split()
    assert out == []
    control = subprocess.run([sys.executable, "-c", "import planner.path\n" + PROBE, *HEAVY],
                             capture_output=True, text=True, check=True).stdout.split()
    assert "numpy" in control and "pinocchio" in control
