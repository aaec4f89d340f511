"""``silo4 sweep`` refuses bad input with one line and exit 2, before any work or file."""

from __future__ import annotations

import pytest

from viz.cli.main import main


@pytest.mark.parametrize(("argv", "message"), [
    (["--heights", "auto"], "--heights auto needs the planner's automatic height"),
    (["--heights", "0.4:0.2:0.1"], "--heights: range '0.4:0.2:0.1' needs a <= b"),
    (["--heights=-0.2,0.3"], "is not a height"),
    (["--paths", "spiral"], "--paths: 'spiral' is not one of straight, circle, circle-reduced"),
    (["--workspaces", "fast"], "--workspaces: 'fast' is not one of"),
    (["--xacro-arg", "L9=0.2"], "--xacro-arg L9: unknown xacro argument"),
    (["--xacro-arg", "L2=0.2,x"], "--xacro-arg L2: 'x' is not a number"),
    (["--workers", "0"], "--workers 0: must be >= 1"),
    (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "sizes only the local cluster"),
    (["--samples-per-unit", "0"], "--samples-per-unit 0: must be >= 1"),
    (["--gear-efficiency", "1.5"], "gear efficiency 1.5"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, argv, message):
    out = tmp_path / "sweep"
    assert main(["sweep", *argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err
    assert not out.exists()


def test_simulate_is_refused_without_the_sim_package(tmp_path, capsys, monkeypatch):
    import sweep.task

    monkeypatch.setattr(sweep.task, "simulator_available", lambda: False)
    assert main(["sweep", "--simulate", "--out", str(tmp_path / "s")]) == 2
    assert "--simulate needs the physics replay package 'sim'" in capsys.readouterr().err


def test_progress_bar_draws_only_at_a_terminal(capsys, monkeypatch):
    from viz.cli.sweep import ProgressBar

    quiet = ProgressBar(4)
    quiet.update("straight h=0.4 default", "ok")
    quiet.close()
    assert capsys.readouterr().err == ""  # captured stderr is not a terminal
    monkeypatch.setattr("sys.stderr.isatty", lambda: True)
    bar = ProgressBar(4)
    bar.update("straight h=0.4 default", "ok")
    bar.update("straight h=0.1 default", "refused")
    bar.close()
    err = capsys.readouterr().err
    assert "2/4" in err and "1 not planned" in err and "#" * 15 + "." * 15 in err
