"""``silo4 plan`` / ``silo4 cases``: exit codes, one-line errors, files written."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from silo4kin.errors import Silo4Error
from viz.cli.main import EXIT_BAD_INPUT, EXIT_OK, main
from viz.cli.plan import parse_waypoints, read_path_file

#: Cheap sampling for CLI runs: the CLI is under test here, not the planner.
FEW_SAMPLES = "4"


def run_cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def assert_one_line_error(err: str, *fragments: str) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])


def test_parse_waypoints_accepts_spaces_and_semicolons() -> None:
    """Points are x,y pairs separated by whitespace or ';' (with optional spaces)."""
    got = parse_waypoints(" 0,1 1.5,-2e-1;0 , 3 ")
    np.testing.assert_array_equal(got, [[0.0, 1.0], [1.5, -0.2], [0.0, 3.0]])


@pytest.mark.parametrize(
    "text, bad",
    [("0,1 1;1", "'1'"), ("0,1 a,2", "'a,2'"), ("0,1,2", "'0,1,2'"), ("   ", "no points")],
)
def test_parse_waypoints_names_the_bad_token(text: str, bad: str) -> None:
    """A malformed point raises a Silo4Error quoting the offending text."""
    with pytest.raises(Silo4Error, match=bad):
        parse_waypoints(text)


def test_path_file_with_and_without_header(tmp_path: Path) -> None:
    """A path CSV may start with a header naming x and y (any order) or go straight to data."""
    plain = tmp_path / "plain.csv"
    plain.write_text("# my path\n0,1\n\n1, 1\n")
    np.testing.assert_array_equal(read_path_file(plain), [[0, 1], [1, 1]])
    header = tmp_path / "header.csv"
    header.write_text("name,y,x\na,1,0\nb,1,1\n")
    np.testing.assert_array_equal(read_path_file(header), [[0, 1], [1, 1]])


def test_bad_waypoints_exit_2_one_line(tmp_path: Path, capsys) -> None:
    """Bad waypoint text: exit 2, one line on stderr naming the text, nothing written."""
    code, _, err = run_cli(
        capsys, "plan", "--waypoints", "0,1 1,x", "--height", "0.4", "--out", str(tmp_path / "out")
    )
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, "silo4 plan: error:", "'1,x'")
    assert not (tmp_path / "out").exists()


def test_missing_path_file_exit_2(tmp_path: Path, capsys) -> None:
    """A missing --path file: exit 2, the message names the file."""
    missing = tmp_path / "nope.csv"
    code, _, err = run_cli(
        capsys, "plan", "--path", str(missing), "--height", "0.4", "--out", str(tmp_path / "out")
    )
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, str(missing))


def test_non_numeric_line_in_path_file_exit_2(tmp_path: Path, capsys) -> None:
    """A data line that is not two numbers: exit 2, the message quotes the line."""
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n0,1\n1,one\n")
    code, _, err = run_cli(
        capsys, "plan", "--path", str(bad), "--height", "0.4", "--out", str(tmp_path / "out")
    )
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, "line 3", "'1,one'")


@pytest.mark.parametrize(
    "option, value, fragment",
    [
        ("--height", "nan", "--height"),
        ("--unit-time", "0", "--unit-time"),
        ("--samples-per-unit", "0", "--samples-per-unit"),
        ("--tolerance", "-1", "--tolerance"),
    ],
)
def test_bad_numbers_exit_2(tmp_path: Path, capsys, option: str, value: str, fragment: str) -> None:
    """Out-of-range numbers are refused before planning, naming the option."""
    argv = ["plan", "--waypoints", "0,1", "--height", "0.4", "--out", str(tmp_path / "o")]
    if option == "--height":
        argv[4] = value
    else:
        argv += [option, value]
    code, _, err = run_cli(capsys, *argv)
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, fragment)


def test_argparse_errors_exit_2(tmp_path: Path, capsys) -> None:
    """A non-numeric --height is an argparse error: exit 2, message names the option."""
    with pytest.raises(SystemExit) as info:
        main(["plan", "--waypoints", "0,1", "--height", "high", "--out", str(tmp_path)])
    assert info.value.code == EXIT_BAD_INPUT
    assert "--height" in capsys.readouterr().err


def test_cases_bad_list_exit_2(tmp_path: Path, capsys) -> None:
    """An unknown path name in --paths: exit 2 naming it and the allowed ones."""
    code, _, err = run_cli(capsys, "cases", "--out", str(tmp_path), "--paths", "spiral")
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, "'spiral'", "straight")


# ----------------------------------------------------------------- with the planner core


def test_plan_writes_folder_and_summary(tmp_path: Path, capsys) -> None:
    """A good plan exits 0, prints distance/time/E_n/margin and writes the four files."""
    pytest.importorskip("planner.path.plan_path")
    out = tmp_path / "straight"
    code, stdout, err = run_cli(
        capsys,
        "plan",
        "--waypoints",
        "0,1 1,1 0,2 0,3",
        "--height",
        "0.4",
        "--start-heading",
        "90",
        "--out",
        str(out),
        "--samples-per-unit",
        FEW_SAMPLES,
        "--no-html",
        "--no-plots",
    )
    assert code == EXIT_OK, err
    assert {p.name for p in out.iterdir()} == {
        "trajectory.csv",
        "trajectory.npz",
        "plan.json",
        "metrics.json",
        ".silo4-files",
    }
    for fragment in ("time units", "E_n", "min stability margin", "stride", str(out)):
        assert fragment in stdout
    plan = json.loads((out / "plan.json").read_text())
    assert plan["inputs"]["height_m"] == 0.4 and plan["steps"]


def test_plan_refuses_other_run_without_force(tmp_path: Path, capsys) -> None:
    """Planning a different path into a run folder: exit 2 unless --force."""
    pytest.importorskip("planner.path.plan_path")
    out = str(tmp_path / "run")
    base = [
        "plan",
        "--height",
        "0.4",
        "--out",
        out,
        "--samples-per-unit",
        FEW_SAMPLES,
        "--no-csv",
        "--no-html",
        "--no-plots",
    ]
    assert run_cli(capsys, *base, "--waypoints", "0,1")[0] == EXIT_OK
    code, _, err = run_cli(capsys, *base, "--waypoints", "0,2")
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, "different run", "--force")
    assert run_cli(capsys, *base, "--waypoints", "0,2", "--force")[0] == EXIT_OK


def test_plan_with_another_gait_is_another_run(tmp_path: Path, capsys) -> None:
    """--gait creep then --gait crawl into one folder: the second is a different run (exit 2,
    the creeping run kept) unless --force; the same command again replaces silently."""
    pytest.importorskip("planner.path.plan_path")
    out = tmp_path / "run"
    base = [
        "plan",
        "--waypoints",
        "0,1",
        "--height",
        "0.4",
        "--out",
        str(out),
        "--samples-per-unit",
        FEW_SAMPLES,
        "--no-csv",
        "--no-html",
        "--no-plots",
    ]
    assert run_cli(capsys, *base, "--gait", "creep")[0] == EXIT_OK
    assert run_cli(capsys, *base, "--gait", "creep")[0] == EXIT_OK
    code, _, err = run_cli(capsys, *base, "--gait", "crawl")
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, "different run", "--force")
    plan = json.loads((out / "plan.json").read_text())
    assert plan["inputs"]["gait"] == "creep" and plan["gait"] == "creep"
    assert run_cli(capsys, *base, "--gait", "crawl", "--force")[0] == EXIT_OK
    plan = json.loads((out / "plan.json").read_text())
    assert plan["inputs"]["gait"] == "crawl" and plan["gait"] == "crawl"


def test_plan_options_defaults_are_the_recorded_defaults() -> None:
    """`silo4 plan` and `silo4 cases` without options record exactly OPTION_DEFAULTS, the
    values an older plan.json without those keys is read as (so it stays the same run)."""
    from planner.outputs.export import OPTION_DEFAULTS
    from viz.cli.main import build_parser
    from viz.report.run_outputs import run_options

    parser = build_parser()
    plan_args = parser.parse_args(["plan", "--waypoints", "0,1", "--height", "0.4", "--out", "x"])
    assert run_options(plan_args) == OPTION_DEFAULTS
    cases_args = parser.parse_args(["cases", "--out", "x"])
    assert run_options(cases_args) == {
        k: v for k, v in OPTION_DEFAULTS.items() if k in run_options(cases_args)
    }


@pytest.mark.parametrize(
    "argv, key, value",
    [
        (["--gait", "creep"], "gait", "creep"),
        (["--gait", "crawl"], "gait", "crawl"),
        (["--face-path"], "face_path", True),
        (["--swing-height", "0.08"], "swing_height_request_m", 0.08),
        (["--unit-time", "auto"], "unit_time_auto", True),
        (["--no-torques"], "torques", False),
        (["--load", "body"], "load", "body"),
        (["--gear-ratio", "50"], "gear_ratio", 50.0),
        (["--gear-efficiency", "0.5"], "gear_efficiency", 0.5),
    ],
)
def test_every_plan_changing_option_is_recorded(argv: list[str], key: str, value) -> None:
    """Each option that changes a run's numbers but not Plan's own fields changes exactly its
    key of the recorded options (so the folder check tells the two runs apart)."""
    from planner.outputs.export import OPTION_DEFAULTS
    from viz.cli.main import build_parser
    from viz.report.run_outputs import run_options

    args = build_parser().parse_args(
        ["plan", "--waypoints", "0,1", "--height", "0.4", "--out", "x", *argv]
    )
    assert run_options(args) == {**OPTION_DEFAULTS, key: value}


def test_unreachable_height_exit_2(tmp_path: Path, capsys) -> None:
    """A height outside the feasible range: exit 2 with one line, no folder."""
    pytest.importorskip("planner.path.plan_path")
    code, _, err = run_cli(
        capsys, "plan", "--waypoints", "0,1", "--height", "0.9", "--out", str(tmp_path / "o")
    )
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, "0.9")
    assert not (tmp_path / "o").exists()


def test_cases_small_run_writes_page(tmp_path: Path, capsys) -> None:
    """``silo4 cases`` on one path/height/preset writes the case folder and the page."""
    pytest.importorskip("planner.path.plan_path")
    page = tmp_path / "results.md"
    code, stdout, err = run_cli(
        capsys,
        "cases",
        "--out",
        str(tmp_path / "cases"),
        "--paths",
        "straight",
        "--heights",
        "0.4",
        "--workspaces",
        "thesis",
        "--samples-per-unit",
        FEW_SAMPLES,
        "--no-ditch",
        "--results-md",
        str(page),
    )
    assert code == EXIT_OK, err
    assert (tmp_path / "cases" / "straight_h0.4_thesis" / "metrics.json").exists()
    # cases write no CSV unless asked (--csv): the npz holds the same data
    assert not (tmp_path / "cases" / "straight_h0.4_thesis" / "trajectory.csv").exists()
    text = page.read_text()
    assert "silo4 cases --out" in text and "Table 6.1" in text
    assert (tmp_path / "cases" / "results.md").read_text() == text


def test_plan_default_outputs_torques_animation_plots_report(tmp_path: Path, capsys) -> None:
    """By default a run folder has tau_<joint> columns, the motor sizing table in
    metrics.json, animation.html, PNG plots (SVG only with --svg) and report.html whose
    header names the exact command; --motors prints it; --window adds window plots."""
    pytest.importorskip("planner.path.plan_path")
    out = tmp_path / "full"
    code, stdout, err = run_cli(
        capsys,
        "plan",
        "--waypoints",
        "0,0.6",
        "--height",
        "0.4",
        "--out",
        str(out),
        "--samples-per-unit",
        FEW_SAMPLES,
        "--motors",
        "--gear-ratio",
        "50",
        "--window",
        "1:3",
    )
    assert code == EXIT_OK, err
    names = {p.name for p in out.iterdir()}
    assert {
        "animation.html",
        "report.html",
        "joint_positions.png",
        "cycle_cartesian.png",
        "path.png",
        "stability_margin.png",
        "torques.png",
        "joint_positions_window.png",
    } <= names
    assert not any(n.endswith(".svg") for n in names)
    report = (out / "report.html").read_text()
    assert "silo4 plan --waypoints 0,0.6 --height 0.4 --out" in report
    assert "--window 1:3" in report and "{" not in report.split("<body>")[1]
    walked = json.loads((out / "plan.json").read_text())["gait"]
    assert f"gait walked (and why another was dropped)</th><td>{walked}" in report
    header = (out / "trajectory.csv").read_text().splitlines()[0].split(",")
    tau_columns = [c for c in header if c.startswith("tau_")]
    assert len(tau_columns) == 12 and "tau_LF_knee" in tau_columns
    metrics = json.loads((out / "metrics.json").read_text())
    rows = metrics["motor_sizing"]
    assert [r["joint"] for r in rows][:3] == ["LF_hip_yaw", "LF_hip_pitch", "LF_knee"]
    assert all(r["gear_ratio"] == 50 for r in rows)
    assert "tau_m pk" in stdout and "LF_knee" in stdout
    assert "animation.html" in stdout


def test_plan_svg_on_request(tmp_path: Path, capsys) -> None:
    """--svg writes every plot as SVG beside its PNG."""
    pytest.importorskip("planner.path.plan_path")
    out = tmp_path / "svg"
    code, _, err = run_cli(
        capsys,
        "plan",
        "--waypoints",
        "0,0.6",
        "--height",
        "0.4",
        "--out",
        str(out),
        "--samples-per-unit",
        FEW_SAMPLES,
        "--no-html",
        "--svg",
    )
    assert code == EXIT_OK, err
    pngs = {p.stem for p in out.glob("*.png")}
    assert pngs and pngs == {p.stem for p in out.glob("*.svg")}


@pytest.mark.parametrize(
    "option, value", [("--gear-ratio", "0"), ("--gear-efficiency", "1.5"), ("--window", "5:1")]
)
def test_bad_gearing_exit_2(tmp_path: Path, capsys, option: str, value: str) -> None:
    code, _, err = run_cli(
        capsys,
        "plan",
        "--waypoints",
        "0,1",
        "--height",
        "0.4",
        "--out",
        str(tmp_path / "o"),
        option,
        value,
    )
    assert code == EXIT_BAD_INPUT
    assert_one_line_error(err, value)
    assert not (tmp_path / "o").exists()


def test_plan_prints_the_automatic_unit_time_and_no_negative_zero(tmp_path: Path, capsys) -> None:
    """--unit-time auto: its choice is a line on stdout (not only in plan.json); the summary
    never prints -0.000."""
    code, out, _ = run_cli(
        capsys,
        "plan",
        "--waypoints",
        "0,0.6",
        "--height",
        "0.4",
        "--unit-time",
        "auto",
        "--samples-per-unit",
        FEW_SAMPLES,
        "--no-html",
        "--no-plots",
        "--out",
        str(tmp_path / "run"),
    )
    metrics = json.loads((tmp_path / "run" / "metrics.json").read_text())
    assert code == EXIT_OK
    line = next(x for x in out.splitlines() if x.startswith("--unit-time auto: t_l = "))
    assert f"{metrics['joint_limits']['unit_time_s']:.4f} s" in line
    assert "-0.000" not in out and "gait " in out


def test_plan_after_an_interrupted_simulate(tmp_path: Path, capsys, monkeypatch) -> None:
    """``silo4 simulate`` stopped (SIGINT) after sim_drift.png is written: the same plan into
    the folder then works (the replay's files were recorded as silo4's)."""
    pytest.importorskip("mujoco")
    import viz.plots.sim_plots

    out = tmp_path / "run"
    plan = [
        "plan",
        "--waypoints",
        "0,0.3",
        "--height",
        "0.4",
        "--samples-per-unit",
        "20",
        "--no-html",
        "--no-plots",
        "--out",
        str(out),
    ]
    assert run_cli(capsys, *plan)[0] == EXIT_OK

    def stopped(folder, arrays, metrics):  # noqa: ANN001, ANN202
        (Path(folder) / "sim_drift.png").write_bytes(b"\x89PNG half")
        raise KeyboardInterrupt

    monkeypatch.setattr(viz.plots.sim_plots, "write_sim_plots", stopped)
    assert run_cli(capsys, "simulate", str(out), "--no-html")[0] == 130
    assert (out / "sim_drift.png").is_file()
    code, _, err = run_cli(capsys, *plan)
    assert code == EXIT_OK, err
    assert not (out / "sim_drift.png").exists()


def test_plan_sizes_motors_from_a_motors_file(tmp_path: Path, capsys) -> None:
    """--motors-file: each joint's gearing comes from the table (a joint type's entry over
    the table's default), metrics.json says so per joint, and plan.json records the file."""
    table = tmp_path / "motors.json"
    table.write_text(
        json.dumps(
            {"gear_ratio": 50, "gear_efficiency": 0.8, "joints": {"knee": {"gear_ratio": 120}}}
        )
    )
    out = tmp_path / "run"
    code = main(
        [
            "plan",
            "--waypoints",
            "0,1",
            "--height",
            "0.4",
            "--samples-per-unit",
            "10",
            "--no-html",
            "--no-plots",
            "--motors-file",
            str(table),
            "--out",
            str(out),
        ]
    )
    assert code == EXIT_OK
    rows = json.loads((out / "metrics.json").read_text())["motor_sizing"]
    assert {r["joint"]: r["gear_ratio"] for r in rows}["LF_knee"] == 120
    assert {r["joint"]: r["gear_ratio"] for r in rows}["LF_hip_yaw"] == 50
    assert {r["gear_efficiency"] for r in rows} == {0.8}
    assert all("motors file" in r["gearing_source"] for r in rows)
    inputs = json.loads((out / "plan.json").read_text())["inputs"]
    assert inputs["motors_file"] == str(table.resolve())
