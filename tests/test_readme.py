"""The README's console block (under "What you get") runs top to bottom as written.

Each ``$ .venv/bin/silo4 ...`` line runs in order in one temporary folder, as
``python -m viz ...`` of this checkout, and must exit 0 (``silo4 check`` and ``silo4
simulate`` say 0/1 in their comment: 0 is what the README promises for these robots).
The folder holds what the README assumes: ``tests/robots`` and ``examples`` (links to this
checkout's) and a ``my_path.csv`` of the user's.

Two lines run with a small budget (BUDGET_OPTIONS): the line as written, with options
appended that a later value overrides (argparse keeps the last), so the command, its
parsing and its outputs are the README's and only the amount of work is cut. Find it with
``pytest -k readme``; it takes about five minutes on a shared 2-core machine.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"

#: README commands run with options appended to cut their work, and why (each one alone,
#: not a prefix): the option values appended replace the README's.
BUDGET_OPTIONS = {
    "silo4 robots": (
        ["--only", "silo4"],
        "every robot's reachable sets take minutes; SILO4 alone",
    ),
    "silo4 sweep --paths straight,circle --heights 0.2:0.6:0.05 --xacro-arg L2=0.2,0.25 "
    "--xacro-arg L3=0.2,0.25,0.3 --out out/sweep": (
        ["--paths", "straight", "--heights", "0.4", "--samples-per-unit", "5"],
        "108 plans on Dask take about 90 s on 2 cores; its 6 designs at one height and path",
    ),
}


def console_block(text: str) -> str:
    """The first ```console block after the "What you get" heading."""
    start = text.index("## What you get")
    match = re.search(r"```console\n(.*?)```", text[start:], flags=re.S)
    if match is None:
        raise AssertionError("README: no console block under 'What you get'")
    return match.group(1)


def silo4_commands(block: str) -> list[list[str]]:
    """The argv of each ``$ .venv/bin/silo4 ...`` line (``\\``-continued lines joined,
    comments dropped), in order."""
    joined = re.sub(r"\\\n\s*", " ", block)
    commands = []
    for line in joined.splitlines():
        if not line.startswith("$ "):
            continue
        argv = shlex.split(line[2:], comments=True)
        if argv and argv[0].endswith("silo4"):
            commands.append(argv[1:])
    return commands


def test_the_block_is_found_and_parsed() -> None:
    """The block exists, every command line is a silo4 one, and no two plans write the
    same --out folder with different options (the README ran into "holds a different run")."""
    commands = silo4_commands(console_block(README.read_text(encoding="utf-8")))
    assert len(commands) >= 10 and commands[0] == ["check"]
    outs: dict[str, list[str]] = {}
    for argv in commands:
        if argv[0] == "plan":
            out = argv[argv.index("--out") + 1]
            rest = [a for a in argv if a != "--simulate"]
            assert outs.setdefault(out, rest) == rest, f"two different runs into {out}"


def test_readme_console_block_runs_in_order(tmp_path: Path) -> None:
    """Every silo4 line of the block, in order, exits 0 (BUDGET_OPTIONS: a smaller budget)."""
    commands = silo4_commands(console_block(README.read_text(encoding="utf-8")))
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "robots").symlink_to(ROOT / "tests" / "robots")
    (tmp_path / "examples").symlink_to(ROOT / "examples")  # the terrain files
    (tmp_path / "my_path.csv").write_text("x,y\n0,1\n1,1\n1,2\n", encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore", MPLBACKEND="Agg")
    budgeted = []
    for argv in commands:
        text = "silo4 " + " ".join(argv)
        if text in BUDGET_OPTIONS:
            budgeted.append(text)
            argv = [*argv, *BUDGET_OPTIONS[text][0]]
        result = subprocess.run(
            [sys.executable, "-m", "viz", *argv],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert result.returncode == 0, f"{text}: exit {result.returncode}\n{result.stderr}"
        assert "Traceback" not in result.stderr, result.stderr
    assert budgeted == list(BUDGET_OPTIONS), budgeted  # every budgeted line is in the README
    assert (tmp_path / "out" / "sweep" / "sweep.csv").is_file()
