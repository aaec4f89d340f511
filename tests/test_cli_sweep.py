"""``silo4 sweep`` refuses bad input with one line and exit 2, before any work or file."""

from __future__ import annotations

import pytest

from viz.cli.main import main


@pytest.mark.parametrize(
    ("argv", "message"),
    [
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
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, argv, message):
    out = tmp_path / "sweep"
    assert main(["sweep", *argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err
    assert not out.exists()


def test_simulate_is_refused_without_the_sim_package(tmp_path, capsys, monkeypatch):
    import silo4sweep.task

    monkeypatch.setattr(silo4sweep.task, "simulator_available", lambda: False)
    assert main(["sweep", "--simulate", "--out", str(tmp_path / "s")]) == 2
    assert "--simulate needs the physics replay package 'silo4sim'" in capsys.readouterr().err


def test_sweep_progress_is_a_bar_on_stderr_at_a_terminal(monkeypatch, capsys):
    """The sweep's progress is viz.cli.progress's bar: on stderr when it is a terminal
    (count, rows not planned, the configuration), nothing on stdout."""
    import io
    import sys
    from argparse import Namespace
    from contextlib import contextmanager

    import silo4sweep.engine
    from silo4sweep.grid import SweepConfig
    from viz.cli.sweep import _run

    class Tty(io.StringIO):
        def isatty(self) -> bool:
            return True

    class Table:
        rows: list = []

        def start(self) -> None: ...

        def add(self, config, row) -> None:  # noqa: ANN001
            self.rows.append(row)

    @contextmanager
    def client(*_):  # noqa: ANN002, ANN202
        yield None

    configs = [SweepConfig("straight", 0.4, "default"), SweepConfig("straight", 0.1, "default")]
    monkeypatch.setattr(silo4sweep.engine, "dask_client", client)
    monkeypatch.setattr(
        silo4sweep.engine,
        "run_configs",
        lambda _c, todo, _s: [
            (c, {"status": "ok" if c.height_m > 0.2 else "refused"}) for c in todo
        ],
    )
    monkeypatch.setattr("viz.cli.progress.MIN_VISIBLE_S", 0.0)
    err = Tty()
    monkeypatch.setattr(sys, "stderr", err)
    _run(Namespace(scheduler=None, workers=1, connect_timeout=1.0), Table(), configs, None)
    assert "sweep" in err.getvalue() and "1 not planned" in err.getvalue()
    assert capsys.readouterr().out == ""


def test_a_scheduler_that_accepts_and_never_answers_gives_up_in_seconds(tmp_path, capsys):
    """A port that accepts the connection and never speaks: one line, exit 2, within the
    connect timeout (plus start-up), nothing written."""
    import socket
    import time

    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)  # the kernel accepts; nobody ever answers
    address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
    out = tmp_path / "sweep"
    try:
        t0 = time.monotonic()
        code = main(
            [
                "sweep",
                "--heights",
                "0.4",
                "--scheduler",
                address,
                "--connect-timeout",
                "1",
                "--out",
                str(out),
            ]
        )
        elapsed = time.monotonic() - t0
    finally:
        server.close()
    assert code == 2 and elapsed < 15, elapsed
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith(f"silo4 sweep: error: cannot reach the Dask scheduler at {address}")
    assert not out.exists()


def test_grid_size_is_counted_before_it_is_built():
    """A grid over MAX_GRID_CONFIGS is refused by its count, naming the bound."""
    from silo4sweep.grid import SweepInputError, check_grid_size, design_grid, grid_size

    heights, l2 = [0.1 * k for k in range(1, 1002)], [0.001 * k for k in range(1000)]
    assert grid_size(["straight"], heights, {"L2": l2}, ["default"]) == 1_001_000
    with pytest.raises(SweepInputError, match="1001000 configurations .* at most 100000"):
        design_grid(["straight"], heights, {"L2": l2}, ["default"])
    assert check_grid_size(["straight"], [0.4], {}, ["default"]) == 1


def test_sigint_during_a_sweep_exits_130_quietly_and_the_table_resumes(tmp_path):
    """Ctrl-C (SIGINT to the whole process group, as a terminal sends it) during a local
    sweep: exit 130, the one line "interrupted", no traceback from the workers, sweep.csv
    holds whole rows only, and the same command then plans only what is missing."""
    import csv as csv_module
    import os
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    out = tmp_path / "sweep"
    argv = [
        sys.executable,
        "-m",
        "viz",
        "sweep",
        "--heights",
        "0.2:0.6:0.01",
        "--workers",
        "1",
        "--samples-per-unit",
        "20",
        "--out",
        str(out),
    ]  # 1: any machine has a core
    env = dict(os.environ, PYTHONPATH=str(root), PYTHONWARNINGS="ignore")
    proc = subprocess.Popen(
        argv,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    csv = out / "sweep.csv"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if csv.is_file() and csv.read_text().count("\n") >= 3:
            break
        time.sleep(0.2)
    assert proc.poll() is None, proc.communicate()  # still sweeping: interrupt it
    os.killpg(proc.pid, signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, (stdout, stderr)
    assert "Traceback" not in stderr and stderr.strip().splitlines()[-1] == "interrupted"
    lines = csv.read_text().splitlines()
    rows = list(csv_module.reader(lines))  # a reason may hold a quoted comma
    assert csv.read_text().endswith("\n") and len({len(row) for row in rows}) == 1
    done = len(lines) - 1
    rerun = subprocess.run(argv, env=env, capture_output=True, text=True, timeout=600)
    assert rerun.returncode == 0, rerun.stderr
    assert f"41 configurations, {done} already in" in rerun.stderr
