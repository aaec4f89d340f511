"""The CLI contract under hostile input, one subprocess per case (issue 13).

For every case: the exit code is the expected one (0, 1 or 2); a refusal is exactly one line
on stderr naming the problem; no traceback ever; a refused run leaves the folder exactly as
it was (no output folder, no temporary or lock file); and every file the user had is still
there, byte for byte. The catalogue of refusals is docs/errors.md.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LONG = "x" * 300  # over NAME_MAX (255)
FEW = ["--samples-per-unit", "5", "--no-html", "--no-plots", "--no-torques"]
PLAN = ["plan", "--height", "0.4", *FEW]


def silo4(cwd: Path, *argv: str) -> subprocess.CompletedProcess:
    """Run ``silo4`` from this checkout (not an installed copy) in ``cwd``."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore")
    return subprocess.run(
        [sys.executable, "-m", "viz", *argv],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )


def _snapshot(folder: Path) -> dict[str, str]:
    """Every entry under ``folder``: relative path -> sha256 of a file, or 'dir'."""
    out = {}
    for p in sorted(folder.rglob("*")):
        key = p.relative_to(folder).as_posix()
        out[key] = "dir" if p.is_dir() else hashlib.sha256(p.read_bytes()).hexdigest()
    return out


@pytest.fixture(scope="module")
def template(tmp_path_factory) -> Path:
    """A folder as a user has it (make_user_folder)."""
    return make_user_folder(tmp_path_factory.mktemp("template"))


def make_user_folder(t: Path) -> Path:
    """Fill ``t`` as a user has it: notes, path files, a run folder, broken runs."""
    result = silo4(t, *PLAN, "--waypoints", "0,0.3", "--out", "run")
    assert result.returncode == 0, result.stderr
    (t / "notes.txt").write_text("my notes\n")
    (t / "figure.png").write_bytes(b"\x89PNG a figure of mine\n")
    (t / "mine").mkdir()
    (t / "mine" / "thesis.tex").write_text("\\chapter{}\n")
    shutil.copytree(t / "run", t / "run_user")
    (t / "run_user" / "my_analysis.txt").write_text("keep me\n")
    (t / "bom.csv").write_bytes(b"\xef\xbb\xbfx,y\n0,0.3\n")
    (t / "latin1_comment.csv").write_bytes(b"# m\xe9tres\n0,0.3\n")
    (t / "latin1_data.csv").write_bytes(b"0,0.3\n1\xe9,2\n")
    (t / "binary.csv").write_bytes(bytes(range(256)) * 4)
    (t / "empty.csv").write_text("")
    (t / "header.csv").write_text("x,y\n")
    (t / "three.csv").write_text("1,2,3\n")
    (t / "cases_user" / "straight_h0.4_default").mkdir(parents=True)
    (t / "cases_user" / "straight_h0.4_default" / "mine.txt").write_text("mine\n")
    (t / "cases_page").mkdir()
    (t / "cases_page" / "results.md").write_text("# my results\n")
    (t / "sweep_user").mkdir()
    (t / "sweep_user" / "best.json").write_text('{"mine": true}\n')
    shutil.copytree(t / "run", t / "run_model")
    (t / "run_model" / "model.xml").write_text("<mujoco/>\n")
    _add_catalogue_files(t)
    npz = (t / "run" / "trajectory.npz").read_bytes()
    for name, data in (
        ("run_trunc", npz[: len(npz) // 2]),
        ("run_empty", b""),
        ("run_garbage", bytes(range(256)) * 64),
    ):
        (t / name).mkdir()
        (t / name / "trajectory.npz").write_bytes(data)
    return t


def _add_catalogue_files(t: Path) -> None:
    """The files of the issue's hostile catalogue: quoted, CRLF and semicolon CSVs, a xacro
    CPU bomb, a URDF in millimetres, hand-edited run folders (NaN in q, inf in qd, an
    oversized or a huge unknown npz member)."""
    import re
    import zipfile

    import numpy as np

    from planner.outputs.trajectory_npz import MAX_NPZ_MEMBER_BYTES
    from silo4kin.robot_files import read_robot_description

    (t / "quoted.csv").write_text('"x","y"\n"0","0.3"\n')
    (t / "quoted_no_header.csv").write_text('"0","0.3"\n"0","0.6"\n')
    (t / "crlf.csv").write_bytes(b"\xef\xbb\xbfx,y\r\n0,0.3\r\n")
    (t / "semicolon.csv").write_text("x;y\n0;0.3\n")
    (t / "bomb.urdf.xacro").write_text(
        '<?xml version="1.0"?>\n<robot name="bomb" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '\n  <xacro:property name="big" value="${9**9**9}"/>\n  <link name="base${big}"/>\n'
        "</robot>\n"
    )

    def scale(match: re.Match) -> str:
        values = " ".join(f"{float(v) * 1000:g}" for v in match.group(2).split())
        return f'{match.group(1)}="{values}"'

    (t / "mm.urdf").write_text(
        re.sub(r'\b(xyz|length|radius|size)="([^"]*)"', scale, read_robot_description())
    )
    block = bytes(1 << 20)
    for name, edit in (("run_nan_q", "q"), ("run_inf_qd", "qd"), ("run_big", None)):
        shutil.copytree(t / "run", t / name)
        npz = t / name / "trajectory.npz"
        if edit is None:
            continue
        with np.load(npz) as data:
            arrays = {key: data[key] for key in data.files}
        arrays[edit] = arrays[edit].copy()
        arrays[edit][-1, -1] = np.nan if edit == "q" else np.inf
        np.savez_compressed(npz, **arrays)
    for name, member in (("run_big", "tau_part_gravity.npy"), ("run_extra", "huge.npy")):
        if not (t / name).exists():
            shutil.copytree(t / "run", t / name)
        with zipfile.ZipFile(t / name / "trajectory.npz", "a", zipfile.ZIP_DEFLATED) as archive:
            with archive.open(member, "w", force_zip64=True) as data:
                for _ in range(MAX_NPZ_MEMBER_BYTES // len(block) + 2):
                    data.write(block)


# (id, argv, exit code, fragment of the one error line (or of stdout on success), new entry
# or a tuple of new entries)
CASES = [
    # defect 1: a waypoint within the tolerance, or a huge tolerance: a standing plan
    ("waypoint-at-start", [*PLAN, "--waypoints", "0,0", "--out", "o"], 0, "no leg lifted", "o"),
    (
        "huge-tolerance",
        [*PLAN, "--waypoints", "0,1", "--tolerance", "100", "--out", "o"],
        0,
        "0 time units",
        "o",
    ),
    (
        "absurd-tolerance",
        [*PLAN, "--waypoints", "0,1", "--tolerance", "1e300", "--out", "o"],
        2,
        "--tolerance",
        None,
    ),
    # defect 2: the work budget
    ("far-waypoint", [*PLAN, "--waypoints", "1e9,0", "--out", "o"], 2, "split", None),
    (
        "one-km",
        ["plan", "--height", "0.4", "--waypoints", "0,1000", "--out", "o"],
        2,
        "samples per unit",
        None,
    ),
    (
        "too-many-waypoints",
        [*PLAN, "--waypoints", " ".join(["0,0.1"] * 1001), "--out", "o"],
        2,
        "budget",
        None,
    ),
    # defect 3: a first waypoint with negative x is valid input
    ("negative-first-x", [*PLAN, "--waypoints", "-0.3,0.2", "--out", "o"], 0, "waypoints", "o"),
    (
        "negative-heading",
        [*PLAN, "--waypoints", "0,0.3", "--start-heading", "-90", "--out", "o"],
        0,
        "waypoints",
        "o",
    ),
    # defect 4: path files
    ("path-bom", [*PLAN, "--path", "bom.csv", "--out", "o"], 0, "waypoints", "o"),
    (
        "path-latin1-comment",
        [*PLAN, "--path", "latin1_comment.csv", "--out", "o"],
        0,
        "waypoints",
        "o",
    ),
    ("path-latin1-data", [*PLAN, "--path", "latin1_data.csv", "--out", "o"], 2, "line 2", None),
    ("path-binary", [*PLAN, "--path", "binary.csv", "--out", "o"], 2, "binary", None),
    ("path-empty", [*PLAN, "--path", "empty.csv", "--out", "o"], 2, "no waypoints", None),
    ("path-header-only", [*PLAN, "--path", "header.csv", "--out", "o"], 2, "no waypoints", None),
    ("path-three-columns", [*PLAN, "--path", "three.csv", "--out", "o"], 0, "waypoints", "o"),
    ("path-folder", [*PLAN, "--path", "mine", "--out", "o"], 2, "folder", None),
    ("path-missing", [*PLAN, "--path", "nope.csv", "--out", "o"], 2, "no such file", None),
    ("path-name-too-long", [*PLAN, "--path", LONG, "--out", "o"], 2, "--path", None),
    # defect 9 and siblings: numbers out of range
    (
        "unit-time-1e300",
        [*PLAN, "--waypoints", "0,1", "--unit-time", "1e300", "--out", "o"],
        2,
        "--unit-time",
        None,
    ),
    (
        "unit-time-zero",
        [*PLAN, "--waypoints", "0,1", "--unit-time", "0", "--out", "o"],
        2,
        "--unit-time",
        None,
    ),
    (
        "unit-time-nan",
        [*PLAN, "--waypoints", "0,1", "--unit-time", "nan", "--out", "o"],
        2,
        "--unit-time",
        None,
    ),
    (
        "samples-per-unit-huge",
        [
            "plan",
            "--height",
            "0.4",
            "--waypoints",
            "0,1",
            "--samples-per-unit",
            "100000",
            "--out",
            "o",
        ],
        2,
        "--samples-per-unit",
        None,
    ),
    (
        "samples-per-unit-zero",
        ["plan", "--height", "0.4", "--waypoints", "0,1", "--samples-per-unit", "0", "--out", "o"],
        2,
        "--samples-per-unit",
        None,
    ),
    (
        "height-text",
        [*PLAN, "--waypoints", "0,1", "--height", "abc", "--out", "o"],
        2,
        "--height",
        None,
    ),
    (
        "height-nan",
        [*PLAN, "--waypoints", "0,1", "--height", "nan", "--out", "o"],
        2,
        "--height",
        None,
    ),
    (
        "height-too-high",
        [*PLAN, "--waypoints", "0,1", "--height", "5", "--out", "o"],
        2,
        "feasible range",
        None,
    ),
    (
        "heading-huge",
        [*PLAN, "--waypoints", "0,1", "--start-heading", "1e300", "--out", "o"],
        2,
        "--start-heading",
        None,
    ),
    (
        "xacro-arg-huge",
        [*PLAN, "--waypoints", "0,1", "--xacro-arg", "L3=1e308", "--out", "o"],
        2,
        "finite number within",
        None,
    ),
    (
        "heading-inf",
        [*PLAN, "--waypoints", "0,1", "--start-heading", "inf", "--out", "o"],
        2,
        "--start-heading",
        None,
    ),
    (
        "gear-ratio-zero",
        [*PLAN, "--waypoints", "0,1", "--gear-ratio", "0", "--out", "o"],
        2,
        "gear",
        None,
    ),
    (
        "gear-efficiency-2",
        [*PLAN, "--waypoints", "0,1", "--gear-efficiency", "2", "--out", "o"],
        2,
        "efficiency",
        None,
    ),
    # waypoint strings
    ("waypoints-empty", [*PLAN, "--waypoints", "", "--out", "o"], 2, "no points", None),
    ("waypoints-triple", [*PLAN, "--waypoints", "1,2,3", "--out", "o"], 2, "not a point", None),
    ("waypoints-nan", [*PLAN, "--waypoints", "nan,1", "--out", "o"], 2, "not a point", None),
    ("waypoints-overflow", [*PLAN, "--waypoints", "1e999,0", "--out", "o"], 2, "finite", None),
    ("waypoints-hex", [*PLAN, "--waypoints", "0x1,2", "--out", "o"], 2, "not a point", None),
    # defects 6, 11, 12: the output folder
    ("out-empty", [*PLAN, "--waypoints", "0,1", "--out", ""], 2, "empty", None),
    ("out-dot", [*PLAN, "--waypoints", "0,1", "--out", "."], 2, "current folder", None),
    ("out-parent", [*PLAN, "--waypoints", "0,1", "--out", ".."], 2, "current folder", None),
    ("out-root", [*PLAN, "--waypoints", "0,1", "--out", "/"], 2, "current folder", None),
    ("out-is-file", [*PLAN, "--waypoints", "0,1", "--out", "notes.txt"], 2, "existing file", None),
    ("out-too-long", [*PLAN, "--waypoints", "0,1", "--out", LONG], 2, "bytes", None),
    ("out-user-folder", [*PLAN, "--waypoints", "0,0.3", "--out", "mine"], 2, "thesis.tex", None),
    (
        "rerun-with-user-file",
        [*PLAN, "--waypoints", "0,0.3", "--out", "run_user"],
        2,
        "my_analysis.txt",
        None,
    ),
    (
        "rerun-with-user-file-force",
        [*PLAN, "--waypoints", "0,0.3", "--out", "run_user", "--force"],
        2,
        "my_analysis.txt",
        None,
    ),
    ("other-run-no-force", [*PLAN, "--waypoints", "0,0.6", "--out", "run"], 2, "--force", None),
    # robots
    (
        "xacro-arg-no-equals",
        [*PLAN, "--waypoints", "0,1", "--xacro-arg", "L3", "--out", "o"],
        2,
        "NAME=VALUE",
        None,
    ),
    (
        "xacro-arg-text",
        [*PLAN, "--waypoints", "0,1", "--xacro-arg", "L3=abc", "--out", "o"],
        2,
        "not a number",
        None,
    ),
    (
        "xacro-arg-unknown",
        [*PLAN, "--waypoints", "0,1", "--xacro-arg", "nope=1", "--out", "o"],
        2,
        "unknown xacro argument",
        None,
    ),
    (
        "robot-missing",
        [*PLAN, "--waypoints", "0,1", "--robot", "nope.urdf", "--out", "o"],
        2,
        "not found",
        None,
    ),
    (
        "robot-binary",
        [*PLAN, "--waypoints", "0,1", "--robot", "binary.csv", "--out", "o"],
        2,
        "UTF-8",
        None,
    ),
    (
        "robot-text",
        [*PLAN, "--waypoints", "0,1", "--robot", "notes.txt", "--out", "o"],
        2,
        "URDF",
        None,
    ),
    (
        "robot-folder",
        [*PLAN, "--waypoints", "0,1", "--robot", "mine", "--out", "o"],
        2,
        "folder",
        None,
    ),
    (
        "robot-name-too-long",
        [*PLAN, "--waypoints", "0,1", "--robot", LONG, "--out", "o"],
        2,
        "robot file",
        None,
    ),
    (
        "package-dir-too-long",
        [*PLAN, "--waypoints", "0,1", "--package-dir", LONG, "--out", "o"],
        2,
        "--package-dir",
        None,
    ),
    (
        "package-dir-missing",
        [*PLAN, "--waypoints", "0,1", "--package-dir", "nope", "--out", "o"],
        2,
        "--package-dir",
        None,
    ),
    # defect 10: check
    ("check-seed-negative", ["check", "--seed", "-1", "--samples", "5"], 2, "--seed", None),
    ("check-samples-huge", ["check", "--samples", "10000000"], 2, "--samples", None),
    ("check-samples-zero", ["check", "--samples", "0"], 2, "--samples", None),
    # defect 5: animate on broken runs
    ("animate-truncated", ["animate", "run_trunc"], 2, "corrupt", None),
    ("animate-empty", ["animate", "run_empty"], 2, "corrupt", None),
    ("animate-garbage", ["animate", "run_garbage"], 2, "corrupt", None),
    ("animate-missing-run", ["animate", "nope"], 2, "not a folder", None),
    ("animate-run-is-file", ["animate", "notes.txt"], 2, "not a folder", None),
    ("animate-name-too-long", ["animate", LONG], 2, "RUN", None),
    ("animate-out-too-long", ["animate", "run", "--out", LONG], 2, "File name too long", None),
    ("animate-unit-time", ["animate", "run", "--unit-time", "1e300"], 2, "--unit-time", None),
    ("animate-out-folder", ["animate", "run", "--out", "mine"], 2, "file name", None),
    # defect 13 and siblings: cases
    (
        "cases-user-file-in-case-folder",
        [
            "cases",
            "--out",
            "cases_user",
            "--paths",
            "straight",
            "--heights",
            "0.4",
            "--workspaces",
            "default",
            "--no-ditch",
        ],
        2,
        "mine.txt",
        None,
    ),
    ("cases-heights-text", ["cases", "--out", "c", "--heights", "abc"], 2, "--heights", None),
    ("cases-paths-bogus", ["cases", "--out", "c", "--paths", "zigzag"], 2, "--paths", None),
    ("cases-out-file", ["cases", "--out", "notes.txt"], 2, "existing file", None),
    ("cases-unit-time", ["cases", "--out", "c", "--unit-time", "1e300"], 2, "--unit-time", None),
    (
        "cases-results-md-too-long",
        ["cases", "--out", "c", "--results-md", LONG],
        2,
        "--results-md",
        None,
    ),
    (
        "cases-results-md-folder",
        ["cases", "--out", "c", "--results-md", "mine"],
        2,
        "--results-md",
        None,
    ),
    # no command deletes or overwrites a file it did not write, --force or not
    (
        "export-bag-is-the-run",
        ["export", "run_user", "--ros2", "run_user", "--force"],
        2,
        "an input of this command",
        None,
    ),
    (
        "export-bag-is-a-user-folder",
        ["export", "run", "--ros2", "mine", "--force"],
        2,
        "thesis.tex",
        None,
    ),
    (
        "export-goal-over-plan-json",
        ["export", "run", "--goal-yaml", "run/plan.json"],
        2,
        "an input of this command",
        None,
    ),
    (
        "export-goal-over-a-user-file",
        ["export", "run", "--goal-yaml", "notes.txt"],
        2,
        "not written by silo4",
        None,
    ),
    (
        "export-goal-rate-zero",
        ["export", "run", "--goal-yaml", "g.yaml", "--goal-rate", "0"],
        2,
        "--goal-rate",
        None,
    ),
    (
        "export-effort-without-torques",
        ["export", "run", "--goal-yaml", "g.yaml", "--with-effort"],
        2,
        "no joint torques",
        None,
    ),
    (
        "export-start-time-zero",
        ["export", "run", "--ros2", "b.bag", "--start-time", "0"],
        2,
        "--start-time",
        None,
    ),
    (
        "animate-over-the-trajectory",
        ["animate", "run", "--out", "run/trajectory.npz"],
        2,
        "an input of this command",
        None,
    ),
    (
        "cases-user-results-md",
        [
            "cases",
            "--out",
            "cases_page",
            "--paths",
            "straight",
            "--heights",
            "0.4",
            "--workspaces",
            "default",
            "--no-ditch",
        ],
        2,
        "results.md exists and was not written by silo4",
        None,
    ),
    (
        "sweep-user-best-json",
        ["sweep", "--out", "sweep_user", "--heights", "0.4", "--force"],
        2,
        "best.json exists and was not written by silo4",
        None,
    ),
    (
        "simulate-user-model-xml",
        ["simulate", "run_model"],
        2,
        "model.xml exists and was not written by silo4",
        None,
    ),
    (
        "workspace-over-a-user-png",
        ["workspace", "--height", "0.4", "--out", "figure.png"],
        2,
        "figure.png exists and was not written by silo4",
        None,
    ),
    # the command line itself
    ("no-command", [], 2, "required", None),
    ("unknown-command", ["fly"], 2, "invalid choice", None),
    (
        "unknown-option",
        [*PLAN, "--waypoints", "0,1", "--out", "o", "--speed", "9"],
        2,
        "unrecognized arguments",
        None,
    ),
    ("version", ["--version"], 0, "silo4kin", None),
    # names and units: a suggestion, decided before any planning work
    (
        "height-in-centimetres",
        [*PLAN, "--waypoints", "0,1", "--height", "40", "--out", "o"],
        2,
        "did you mean 0.40 m",
        None,
    ),
    (
        "robot-name-typo",
        [*PLAN, "--waypoints", "0,1", "--robot", "go3", "--out", "o"],
        2,
        "did you mean go2",
        None,
    ),
    (
        "robot-not-a-quadruped",
        [*PLAN, "--waypoints", "0,1", "--robot", "ur5", "--out", "o"],
        2,
        "not a quadruped: found 1 leg chain",
        None,
    ),
    (
        "xacro-arg-millimetres",
        [*PLAN, "--waypoints", "0,1", "--xacro-arg", "L3=240", "--out", "o"],
        2,
        "leg length 240.3 m: did you give millimetres?",
        None,
    ),
    (
        "xacro-arg-ten-km",
        [*PLAN, "--waypoints", "0,1", "--xacro-arg", "L3=10000", "--out", "o"],
        2,
        "did you give millimetres?",
        None,
    ),
    # a plan with nothing to do is a plan: its folder, a still animation, and a line saying so
    (
        "nothing-to-do",
        [*PLAN, "--waypoints", "1e-300,1e-300", "--out", "o", "--plots"],
        0,
        "no plots: the plan has nothing to do",
        "o",
    ),
    (
        "height-auto-on-a-kilometre",
        [
            "plan",
            "--samples-per-unit",
            "5",
            "--no-html",
            "--no-plots",
            "--no-torques",
            "--waypoints",
            "0,1000",
            "--height",
            "auto",
            "--out",
            "o",
        ],
        2,
        "give a height in metres, or split the path",
        None,
    ),
    # the catalogue, the cases first tested in other files (tests/test_cli_names.py,
    # tests/test_trajectory_npz_checks.py, tests/test_robots_range.py) as rows here too
    ("path-rfc4180-quoted", [*PLAN, "--path", "quoted.csv", "--out", "o"], 0, "waypoints", "o"),
    (
        "path-rfc4180-quoted-no-header",
        [*PLAN, "--path", "quoted_no_header.csv", "--out", "o"],
        0,
        "waypoints",
        "o",
    ),
    ("path-bom-crlf", [*PLAN, "--path", "crlf.csv", "--out", "o"], 0, "waypoints", "o"),
    ("path-semicolon", [*PLAN, "--path", "semicolon.csv", "--out", "o"], 2, "';'", None),
    (
        "xacro-cpu-bomb",
        [*PLAN, "--waypoints", "0,0.3", "--robot", "bomb.urdf.xacro", "--out", "o"],
        2,
        "xacro expansion",
        None,
    ),
    (
        "urdf-in-millimetres",
        [*PLAN, "--waypoints", "0,0.3", "--robot", "mm.urdf", "--out", "o"],
        2,
        "did you give millimetres?",
        None,
    ),
    (
        "height-upper-end-printed",
        [*PLAN, "--waypoints", "0,0.3", "--height", "0.6056", "--out", "o"],
        0,
        "waypoints",
        "o",
    ),
    (
        "height-lower-end-printed",
        [*PLAN, "--waypoints", "0,0.3", "--height", "0.2", "--out", "o"],
        0,
        "waypoints",
        "o",
    ),
    ("simulate-nan-in-q", ["simulate", "run_nan_q"], 2, "finite numbers only", None),
    (
        "export-inf-in-qd",
        ["export", "run_inf_qd", "--goal-yaml", "g.yaml"],
        2,
        "finite numbers only",
        None,
    ),
    (
        "export-bag-inf-in-qd",
        ["export", "run_inf_qd", "--ros2", "b.bag"],
        2,
        "finite numbers only",
        None,
    ),
    ("animate-oversized-member", ["animate", "run_big"], 2, "bytes uncompressed", None),
    (  # a member silo4 does not write is never read, however large it decompresses
        "animate-huge-unknown-member",
        ["animate", "run_extra", "--out", "extra.html"],
        0,
        "wrote extra.html",
        ("extra.html", ".silo4-files"),  # the file, and the record that silo4 wrote it
    ),
    (
        "cases-heights-in-centimetres",
        ["cases", "--out", "c", "--heights", "40"],
        2,
        "did you mean 0.40 m",
        None,
    ),
    (
        "sweep-heights-in-millimetres",
        ["sweep", "--out", "sw", "--heights", "0.2,400"],
        2,
        "did you mean 0.400 m",
        None,
    ),
    (
        "workspace-height-in-centimetres",
        ["workspace", "--height", "40", "--out", "w.png"],
        2,
        "did you mean 0.40 m",
        None,
    ),
    (
        "swing-height-in-centimetres",
        [*PLAN, "--waypoints", "0,0.3", "--swing-height", "5", "--out", "o"],
        2,
        "did you mean 0.05 m",
        None,
    ),
    # every automatic choice is printed, with its reason
    (
        "gait-auto-says-why",
        [*PLAN, "--waypoints", "0,0.3", "--out", "o"],
        0,
        "--gait auto: crawl (the least time of the gaits tried",
        "o",
    ),
    (
        "unit-time-auto-says-what",
        [*PLAN, "--waypoints", "0,0.3", "--unit-time", "auto", "--out", "o"],
        0,
        "--unit-time auto: t_l = ",
        "o",
    ),
    # sweeps a new user tried (appended)
    (
        "sweep-ucx-protocol",
        ["sweep", "--out", "sw", "--heights", "0.4", "--scheduler", "ucx://127.0.0.1:8786"],
        2,
        "protocol 'ucx' is not available",
        None,
    ),
    (
        "sweep-unknown-protocol",
        ["sweep", "--out", "sw", "--heights", "0.4", "--scheduler", "carrier-pigeon://loft:1"],
        2,
        "is not available here",
        None,
    ),
    (
        "sweep-workers-over-the-cores",
        ["sweep", "--out", "sw", "--heights", "0.4", "--workers", "4096"],
        2,
        "--workers 4096: this machine offers",
        None,
    ),
    (
        "sweep-grid-of-a-million",
        [
            "sweep",
            "--out",
            "sw",
            "--heights",
            "0.2:0.6:0.0004",
            "--xacro-arg",
            "L2=0.1:0.3:0.0002",
        ],
        2,
        "configurations (1 paths x 1001 heights x 1 presets x 1001 L2); at most 100000",
        None,
    ),
]


@pytest.mark.parametrize(
    "argv,code,fragment,created", [c[1:] for c in CASES], ids=[c[0] for c in CASES]
)
def test_hostile_case(template: Path, tmp_path: Path, argv, code, fragment, created) -> None:
    """Exit code as listed, one error line naming the problem, no traceback, nothing left
    behind by a refusal, every user file intact."""
    cwd = tmp_path / "cwd"
    shutil.copytree(template, cwd)
    before = _snapshot(cwd)
    result = silo4(cwd, *argv)
    assert "Traceback" not in result.stderr + result.stdout, result.stderr
    assert result.returncode == code, (result.returncode, result.stderr)
    after = _snapshot(cwd)
    assert {k: v for k, v in after.items() if k in before} == before  # user files intact
    new = {k.split("/")[0] for k in after if k not in before}
    expected = set(created) if isinstance(created, tuple) else {created} if created else set()
    assert new == expected, new  # no temp, lock or partial folder
    if code == 2:
        lines = result.stderr.splitlines()
        assert len(lines) == 1, result.stderr
        assert fragment in lines[0], lines[0]
    else:
        assert fragment in result.stdout, result.stdout


def test_at_least_forty_hostile_cases() -> None:
    """The table holds >= 40 refusals."""
    assert sum(1 for c in CASES if c[2] == 2) >= 40


def test_cases_unit_time_is_used(template: Path, tmp_path: Path) -> None:
    """``silo4 cases --unit-time 2`` plans with 2 s per unit (it was accepted and ignored)."""
    result = silo4(
        tmp_path,
        "cases",
        "--out",
        "c",
        "--paths",
        "straight",
        "--heights",
        "0.4",
        "--workspaces",
        "default",
        "--no-ditch",
        "--unit-time",
        "2",
        "--samples-per-unit",
        "5",
        "--no-torques",
    )
    assert result.returncode == 0, result.stderr
    (case,) = [p for p in (tmp_path / "c").iterdir() if p.is_dir()]
    plan = json.loads((case / "plan.json").read_text())
    assert plan["inputs"]["unit_time_s"] == 2.0


def test_height_auto_counts_the_heights_on_a_terminal(tmp_path: Path) -> None:
    """``--height auto`` with stderr on a terminal shows how many heights are planned out of
    at most how many ("heights: ... 5/40"), not only the elapsed time."""
    import fcntl
    import pty
    import re
    import struct
    import termios

    leader, follower = pty.openpty()
    fcntl.ioctl(follower, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 100, 0, 0))
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore")
    proc = subprocess.Popen(
        [sys.executable, "-m", "viz", *PLAN, "--waypoints", "0,1 1,1", "--height", "auto"]
        + ["--out", "o"],
        cwd=tmp_path,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=follower,
    )
    os.close(follower)
    chunks = []
    while True:
        try:
            chunk = os.read(leader, 65536)
        except OSError:  # the terminal closed: the run ended
            break
        if not chunk:
            break
        chunks.append(chunk)
    os.close(leader)
    assert proc.wait(timeout=600) == 0
    shown = b"".join(chunks).decode(errors="replace")
    counts = [tuple(map(int, m)) for m in re.findall(r"heights:.*?(\d+)/(\d+)", shown)]
    assert counts, shown
    assert all(0 < done <= most for done, most in counts), counts
