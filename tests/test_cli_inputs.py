"""Waypoint strings and files, robot files with $(find) and meshes, replaying another robot's
run (issue 13 defects 3, 4, 16), and a hypothesis fuzz of ``--waypoints``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from planner.request import MAX_WAYPOINTS
from silo4kin.errors import RobotDescriptionError, Silo4Error
from silo4kin.robot import load_robot
from viz.cli.animate import _recorded_robot
from viz.cli.main import build_parser, join_negative_values, main
from viz.cli.paths import parse_waypoints, read_path_file

ROBOTS = Path(__file__).resolve().parent / "robots"
PARSER = build_parser()


# --------------------------------------------------------------------------- fuzz


@settings(max_examples=400, deadline=None)
@given(st.text(max_size=200))
def test_any_waypoint_text_parses_or_is_one_clear_error(text: str) -> None:
    """Any string: a (K, 2) array of finite numbers, or a Silo4Error (never another
    exception, never NaN or inf, never more than MAX_WAYPOINTS points)."""
    try:
        wp = parse_waypoints(text)
    except Silo4Error:
        return
    assert wp.ndim == 2 and wp.shape[1] == 2 and 1 <= len(wp) <= MAX_WAYPOINTS
    assert np.all(np.isfinite(wp))


finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.tuples(finite, finite), min_size=1, max_size=20),
    st.sampled_from([" ", ";", "  ", " ; ", "\t"]),
    st.sampled_from([",", " , ", ", "]),
)
def test_valid_waypoint_text_round_trips(points, sep, comma) -> None:
    """Points written with repr(), any separators: parsed back exactly, also through argparse
    when the first x is negative (defect 3: "-1,2" was taken for an option)."""
    text = sep.join(f"{x!r}{comma}{y!r}" for x, y in points)
    assert parse_waypoints(text).tolist() == [list(p) for p in points]
    argv = ["plan", "--waypoints", text, "--height", "0.4", "--out", "o"]
    args = PARSER.parse_args(join_negative_values(argv, PARSER))
    assert args.waypoints == text


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(alphabet="-0123456789.,e ;", min_size=1, max_size=40))
def test_dash_strings_never_crash_argparse(text: str) -> None:
    """Strings made of number characters and dashes: argparse either takes them as the
    --waypoints value or exits 2 with its one-line message (SystemExit), nothing else."""
    argv = ["plan", "--waypoints", text, "--height", "0.4", "--out", "o"]
    try:
        args = PARSER.parse_args(join_negative_values(argv, PARSER))
    except SystemExit as exc:
        assert exc.code == 2
        return
    assert args.waypoints == text


def test_negative_first_waypoint_cli(tmp_path: Path, capsys) -> None:
    """``--waypoints "-1,2"``-style input plans (was: "expected one argument")."""
    code = main(
        [
            "plan",
            "--waypoints",
            "-0.3,0.3 0,0.6",
            "--height",
            "0.4",
            "--out",
            str(tmp_path / "o"),
            "--samples-per-unit",
            "5",
            "--no-html",
            "--no-plots",
            "--torque-headroom",  # its LH knee needs 0.86 of the URDF effort standing still;
            "1",  # what is tested here is the parsing of the first waypoint
        ]
    )
    assert code == 0, capsys.readouterr().err
    plan = json.loads((tmp_path / "o" / "plan.json").read_text())
    assert plan["inputs"]["waypoints_in_world"][0] == [-0.3, 0.3]


# --------------------------------------------------------------------------- path files


@pytest.mark.parametrize(
    "data",
    [
        b"\xef\xbb\xbfx,y\r\n0,1\r\n1,1\r\n",  # spreadsheet UTF-8 with BOM, CRLF
        b"# Wegpunkte in Metern, gr\xf6\xdfer\n0,1\n1,1\n",  # a Latin-1 comment
        b"\xef\xbb\xbf0,1\n1,1\n",  # BOM, no header
        b"y,x,label\n1,0,a\n1,1,b\n",  # named columns in another order
    ],
)
def test_path_files_people_save_are_read(tmp_path: Path, data: bytes) -> None:
    """UTF-8 with a BOM, CRLF line ends, a Latin-1 comment: the waypoints (0,1) (1,1)."""
    (tmp_path / "p.csv").write_bytes(data)
    assert read_path_file(tmp_path / "p.csv").tolist() == [[0.0, 1.0], [1.0, 1.0]]


@pytest.mark.parametrize(
    "data,fragment",
    [
        (b"\x00\x01\x02\x03" * 10, "binary"),
        (b"0,1\n1\xe9,2\n", "line 2"),
        (b"0,1\nnan,2\n", "line 2"),
        (b"0,1\n1e999,2\n", "finite"),
        (b"# only a comment\n", "no waypoints"),
    ],
)
def test_bad_path_files_are_one_clear_error(tmp_path: Path, data: bytes, fragment) -> None:
    (tmp_path / "p.csv").write_bytes(data)
    with pytest.raises(Silo4Error, match=fragment):
        read_path_file(tmp_path / "p.csv")


def test_huge_path_file_is_refused_unread(tmp_path: Path) -> None:
    """A file over MAX_PATH_FILE_BYTES is refused from its size (never read into memory)."""
    big = tmp_path / "big.csv"
    with open(big, "wb") as f:
        f.truncate(10**9)  # sparse: no disk used
    with pytest.raises(Silo4Error, match="too large"):
        read_path_file(big)


# --------------------------------------------------------------------------- robots


@pytest.fixture(scope="module")
def find_robot(tmp_path_factory) -> tuple[Path, Path]:
    """mantis as a xacro that includes a file through $(find mypkg); the package folder."""
    tmp = tmp_path_factory.mktemp("find")
    (tmp / "pkgs" / "mypkg").mkdir(parents=True)
    (tmp / "pkgs" / "mypkg" / "props.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:property name="body_x" value="0.5"/></robot>\n'
    )
    text = (ROBOTS / "mantis.urdf").read_text()
    i = text.index("<robot")
    j = text.index(">", i)
    xacro = (
        text[:j] + ' xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="$(find mypkg)/props.xacro"/>' + text[j + 1 :]
    )
    xacro = xacro.replace('<box size="0.5 0.3 0.1"/>', '<box size="${body_x} 0.3 0.1"/>', 1)
    (tmp / "findbot.urdf.xacro").write_text(xacro)
    return tmp / "findbot.urdf.xacro", tmp / "pkgs"


def test_xacro_find_resolves_through_package_dir(find_robot) -> None:
    """``$(find mypkg)`` with package_dirs: loads (before: it failed even with --package-dir)."""
    xacro, pkgs = find_robot
    robot = load_robot(xacro, package_dirs=[str(pkgs)])
    assert len(robot.legs) == 4
    robot = load_robot(xacro, package_dirs=[str(pkgs / "mypkg")])  # the package folder itself
    assert len(robot.legs) == 4


def test_xacro_find_without_package_dir_names_the_option(find_robot) -> None:
    xacro, _ = find_robot
    with pytest.raises(RobotDescriptionError, match="--package-dir"):
        load_robot(xacro)


def test_missing_mesh_suggests_package_dir(tmp_path: Path) -> None:
    """A mesh that cannot be found: the error says to give --package-dir."""
    text = (
        (ROBOTS / "mantis.urdf")
        .read_text()
        .replace(
            '<box size="0.5 0.3 0.1"/>', '<mesh filename="package://mypkg/meshes/body.stl"/>', 1
        )
    )
    (tmp_path / "mesh.urdf").write_text(text)
    with pytest.raises(RobotDescriptionError, match="could not be found.*--package-dir"):
        load_robot(tmp_path / "mesh.urdf")


def test_animate_replays_another_robots_run_from_plan_json(tmp_path: Path, capsys) -> None:
    """plan.json records the robot file and xacro args; ``silo4 animate RUN`` without --robot
    loads that robot (before: it loaded SILO4 and refused mantis's trajectory)."""
    out = tmp_path / "mantis_run"
    assert (
        main(
            [
                "plan",
                "--waypoints",
                "0.3,0",
                "--height",
                "0.4",
                "--start-heading",
                "0",
                "--robot",
                str(ROBOTS / "mantis.urdf"),
                "--out",
                str(out),
                "--samples-per-unit",
                "5",
                "--no-html",
                "--no-plots",
            ]
        )
        == 0
    )
    source = json.loads((out / "plan.json").read_text())["robot_source"]
    assert source == {
        "file": str((ROBOTS / "mantis.urdf").resolve()),
        "name": None,
        "xacro_args": {},
        "package_dirs": [],
    }
    capsys.readouterr()
    assert main(["animate", str(out)]) == 0, capsys.readouterr().err
    assert (out / "animation.html").stat().st_size > 100_000


def test_plan_json_records_xacro_args(tmp_path: Path, capsys) -> None:
    """A SILO4 variant's xacro arguments are recorded and used again by animate."""
    out = tmp_path / "variant"
    assert (
        main(
            [
                "plan",
                "--waypoints",
                "0,0.3",
                "--height",
                "0.4",
                "--xacro-arg",
                "L3=0.32",
                "--out",
                str(out),
                "--samples-per-unit",
                "5",
                "--no-html",
                "--no-plots",
            ]
        )
        == 0
    )
    source = json.loads((out / "plan.json").read_text())["robot_source"]
    assert source["file"] is None and source["xacro_args"] == {"L3": "0.32"}
    args = build_parser().parse_args(["animate", str(out)])
    recorded = _recorded_robot(args, json.loads((out / "plan.json").read_text()))
    assert recorded.robot is None and recorded.xacro_arg == ["L3=0.32"]
    assert main(["animate", str(out), "--out", str(tmp_path / "a.html")]) == 0
