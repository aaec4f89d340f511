"""Names and messages at the CLI boundary: robot names with suggestions, heights typed in
centimetres, CSV dialects (quotes, byte order marks, CRLF, semicolons), a xacro whose
expression would never finish, and a stdout closed by its reader. Each refusal is one line
and comes within seconds."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from planner.errors import PlannerInputError
from planner.request import Height, check_height_scale
from silo4kin.robot_library import canonical_robot_name, known_robot_names, unknown_robot_message
from viz.cli.paths import read_path_file

ROOT = Path(__file__).resolve().parent.parent
PLAN = [
    "plan",
    "--height",
    "0.4",
    "--samples-per-unit",
    "5",
    "--no-html",
    "--no-plots",
    "--no-torques",
]
#: A refusal that is decided before any planning work comes within this [s] (a cold start
#: with Pinocchio and the SILO4 xacro is ~1 s; the bounded xacro child stops at 5 s of CPU
#: or 15 s of wall time; a loaded 2-core machine stretches both).
REFUSAL_SECONDS = 30.0


def silo4(cwd: Path, *argv: str) -> subprocess.CompletedProcess:
    """Run ``silo4`` from this checkout in ``cwd``."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore")
    return subprocess.run(
        [sys.executable, "-m", "viz", *argv],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_description_names_are_the_loader_names() -> None:
    """robot_descriptions.py's ``go2_description`` (and the URDF's own name) is go2."""
    assert canonical_robot_name("go2_description") == "go2"
    assert canonical_robot_name(" Go2 ") == "go2"
    assert canonical_robot_name("silo4_description") == "silo4"
    assert canonical_robot_name("_description") == "_description"


def test_unknown_robot_suggests_the_closest_name_once() -> None:
    """difflib over the known names: 'go3' -> go2 first, no name twice, every name listed."""
    message = unknown_robot_message("go3", (*known_robot_names(), "go2"))
    assert "did you mean go2 or" in message
    assert message.count("go2 or go2") == 0
    assert all(name in message for name in known_robot_names())


@pytest.mark.parametrize(
    "height,guess",
    [(40.0, "0.40 m (cm)"), (400.0, "0.400 m (mm)"), (240.0, "2.40 m (cm) or 0.240 m (mm)")],
)
def test_height_in_cm_or_mm_is_refused_with_a_guess(height: float, guess: str) -> None:
    """A height above 10 m is a unit slip: the message offers the value read as cm / mm."""
    with pytest.raises(PlannerInputError, match="did you mean") as info:
        check_height_scale("--height", height)
    assert guess in str(info.value)
    with pytest.raises(PlannerInputError, match="did you mean"):
        Height.fixed(height)


def test_plausible_heights_pass_the_scale_check() -> None:
    """Heights up to 10 m are left to the workspace's feasible range (5 m: 'feasible range')."""
    for height in (0.05, 0.4, 5.0, 10.0):
        check_height_scale("--height", height)


@pytest.mark.parametrize(
    "text",
    [
        '"x","y"\n"0","0.3"\n',
        '"0","0.3"\n"1","1"\n',
        '\ufeff"x","y"\r\n"0","0.3"\r\n',
        "\ufeffx,y\r\n0,0.3\r\n",
        "# comment\n\ufeffx,y\n0,0.3\n",
    ],
)
def test_quoted_bom_and_crlf_csv_are_read(tmp_path: Path, text: str) -> None:
    """RFC 4180 quotes, with or without header, a UTF-8 BOM and CRLF line ends are read."""
    path = tmp_path / "p.csv"
    path.write_bytes(text.encode("utf-8"))
    assert read_path_file(path).tolist()[0] == [0.0, 0.3]


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-be"])
def test_utf16_csv_with_its_byte_order_mark_is_read(tmp_path: Path, encoding: str) -> None:
    """A spreadsheet's "Unicode text" export (UTF-16 with a BOM) is text, not binary."""
    path = tmp_path / "p.csv"
    data = "x,y\r\n0,0.3\r\n".encode(encoding)
    if encoding == "utf-16-be":
        data = b"\xfe\xff" + data
    path.write_bytes(data)
    assert read_path_file(path).tolist() == [[0.0, 0.3]]


def test_semicolon_csv_gets_a_hint(tmp_path: Path) -> None:
    """A file whose columns are separated by ';' is refused saying so."""
    path = tmp_path / "p.csv"
    path.write_text("x;y\n0;0.3\n")
    from silo4kin.errors import Silo4Error

    with pytest.raises(Silo4Error, match="separated by ';'"):
        read_path_file(path)


def test_help_lists_the_robot_names() -> None:
    """``silo4 plan --help`` documents --robot PATH|NAME and names every robot."""
    result = silo4(ROOT, "plan", "--help")
    assert result.returncode == 0
    flat = " ".join(result.stdout.split())
    assert "PATH|NAME" in flat
    assert all(name in flat for name in known_robot_names())


def _one_line_within(
    result: subprocess.CompletedProcess, seconds: float, elapsed: float, fragment: str
) -> None:
    assert "Traceback" not in result.stderr
    assert result.returncode == 2, result.stderr
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and fragment in lines[0], result.stderr
    assert elapsed < seconds, elapsed


def test_xacro_cpu_bomb_is_stopped_in_seconds(tmp_path: Path) -> None:
    """``${9**9**9}`` in a xacro: the bounded expansion stops it, one line, no leftovers."""
    (tmp_path / "bomb.urdf.xacro").write_text(
        '<?xml version="1.0"?>\n<robot name="bomb" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '\n  <xacro:property name="big" value="${9**9**9}"/>\n  <link name="base${big}"/>\n'
        "</robot>\n"
    )
    start = time.monotonic()
    result = silo4(
        tmp_path, *PLAN, "--waypoints", "0,0.3", "--robot", "bomb.urdf.xacro", "--out", "o"
    )
    _one_line_within(result, REFUSAL_SECONDS, time.monotonic() - start, "xacro expansion")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bomb.urdf.xacro"]


def test_millimetre_urdf_is_refused_in_seconds(tmp_path: Path) -> None:
    """The SILO4 URDF with every length x1000 (a CAD export in mm): "did you give
    millimetres?" before any planning."""
    import re

    from silo4kin.robot_files import read_robot_description

    urdf = read_robot_description()

    def scale(match: re.Match) -> str:
        return (
            f'{match.group(1)}="'
            + " ".join(f"{float(v) * 1000:g}" for v in match.group(2).split())
            + '"'
        )

    urdf = re.sub(r'\b(xyz|length|radius|size)="([^"]*)"', scale, urdf)
    (tmp_path / "mm.urdf").write_text(urdf)
    start = time.monotonic()
    result = silo4(tmp_path, *PLAN, "--waypoints", "0,0.3", "--robot", "mm.urdf", "--out", "o")
    _one_line_within(result, REFUSAL_SECONDS, time.monotonic() - start, "did you give millimetres?")


@pytest.mark.parametrize(
    "argv,lines",
    [
        (["robots", "--only", "silo4,silo4"], 1),
        (
            [
                "plan",
                "--height",
                "0.4",
                "--waypoints",
                "0,0.3",
                "--samples-per-unit",
                "5",
                "--no-html",
                "--no-plots",
                "--motors",
                "--out",
                "o",
            ],
            2,
        ),
    ],
)
def test_closed_stdout_ends_quietly(tmp_path: Path, argv: list[str], lines: int) -> None:
    """``silo4 ... | head -N``: no "error: Broken pipe", no traceback, exit 0."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore")
    command = " ".join([sys.executable, "-m", "viz", *(f"'{a}'" for a in argv)])
    result = subprocess.run(
        ["bash", "-c", f"set -o pipefail; {command} | head -{lines}"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.stderr == "", result.stderr
    assert result.returncode == 0
    assert len(result.stdout.splitlines()) == lines
