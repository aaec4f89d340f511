"""``silo4 sweep`` on real Dask clusters: a LocalCluster of 2 worker processes, and a
``dask scheduler`` + ``dask worker`` started as processes on 127.0.0.1, give sweep.csv
byte for byte equal to the same rows computed in this process; a refused configuration is
a row with its reason; a rerun adds nothing; an unreachable scheduler is one line, exit 2."""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from silo4sweep.grid import design_grid
from silo4sweep.table import CSV_NAME, SweepTable, read_table
from silo4sweep.task import REFUSED, SweepSettings, plan_row
from viz.cli.main import main

pytest.importorskip("distributed")

#: A tiny grid: one height below the feasible range (refused), two leg lengths, coarse sampling.
GRID_ARGS = [
    "--paths",
    "straight",
    "--heights",
    "0.15,0.3,0.45",
    "--xacro-arg",
    "L3=0.24,0.3",
    "--samples-per-unit",
    "4",
]
SETTINGS = SweepSettings(samples_per_unit=4)
GRID = design_grid(["straight"], [0.15, 0.3, 0.45], {"L3": [0.24, 0.3]}, ["default"])
#: Start-up allowance for the scheduler and worker processes (not a timing assertion) [s].
STARTUP_S = 120.0


@pytest.fixture(scope="module")
def in_process_csv(tmp_path_factory) -> str:
    """sweep.csv of the grid computed here, one plan_row after the other (no Dask)."""
    folder = tmp_path_factory.mktemp("local")
    table = SweepTable(folder, ["L3"], SETTINGS)
    table.start()
    for config in GRID:
        table.add(config, plan_row(config, SETTINGS))
    table.finish(GRID)
    return (folder / CSV_NAME).read_text()


@pytest.fixture(scope="module")
def local_cluster_run(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("cluster") / "sweep"
    assert main(["sweep", *GRID_ARGS, "--workers", "2", "--out", str(out)]) == 0
    return out


def test_local_cluster_table_equals_the_in_process_table(local_cluster_run, in_process_csv):
    assert (local_cluster_run / CSV_NAME).read_text() == in_process_csv
    rows = read_table(local_cluster_run / CSV_NAME)
    assert len(rows) == len(GRID) == 6
    refused = [r for r in rows if r["status"] == REFUSED]
    assert [r["height_m"] for r in refused] == [0.15, 0.15]
    assert all("feasible range" in r["reason"] for r in refused)
    for name in ("sweep.parquet", "best.json", "pareto.png", "sweep.json"):
        assert (local_cluster_run / name).stat().st_size > 0
    best = json.loads((local_cluster_run / "best.json").read_text())
    assert {e["design"]["L3"] for e in best["best_height"]} == {0.24, 0.3}


def test_parquet_holds_the_same_rows(local_cluster_run):
    pq = pytest.importorskip("pyarrow.parquet")
    table = pq.read_table(local_cluster_run / "sweep.parquet").to_pylist()
    assert table == read_table(local_cluster_run / CSV_NAME)


def test_a_rerun_adds_nothing(local_cluster_run, capsys):
    before = (local_cluster_run / CSV_NAME).read_bytes()
    capsys.readouterr()
    assert main(["sweep", *GRID_ARGS, "--workers", "2", "--out", str(local_cluster_run)]) == 0
    assert "6 configurations, 6 already in" in capsys.readouterr().err
    assert (local_cluster_run / CSV_NAME).read_bytes() == before


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_scheduler_and_worker_processes_give_the_same_table(tmp_path, in_process_csv):
    dask = str(Path(sys.executable).with_name("dask"))
    scheduler_file = tmp_path / "scheduler.json"
    procs = [
        subprocess.Popen(
            [
                dask,
                "scheduler",
                "--host",
                "127.0.0.1",
                "--port",
                "0",
                "--no-dashboard",
                "--scheduler-file",
                str(scheduler_file),
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    ]
    try:
        deadline = time.monotonic() + STARTUP_S
        while not scheduler_file.exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        address = json.loads(scheduler_file.read_text())["address"]
        assert address.startswith("tcp://127.0.0.1:")
        procs.append(
            subprocess.Popen(
                [
                    dask,
                    "worker",
                    address,
                    "--host",
                    "127.0.0.1",
                    "--nworkers",
                    "1",
                    "--nthreads",
                    "1",
                    "--no-dashboard",
                ],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
        )
        out = tmp_path / "sweep"
        assert (
            main(
                [
                    "sweep",
                    *GRID_ARGS,
                    "--scheduler",
                    address,
                    "--connect-timeout",
                    str(STARTUP_S),
                    "--out",
                    str(out),
                ]
            )
            == 0
        )
        assert (out / CSV_NAME).read_text() == in_process_csv
    finally:
        for proc in reversed(procs):
            proc.terminate()
        for proc in procs:
            proc.wait(timeout=STARTUP_S)


def test_an_unreachable_scheduler_is_one_line_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "sweep"
    address = f"tcp://127.0.0.1:{_free_port()}"
    code = main(
        [
            "sweep",
            *GRID_ARGS,
            "--scheduler",
            address,
            "--connect-timeout",
            "1",
            "--out",
            str(out),
        ]
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert err[-1].startswith(f"silo4 sweep: error: cannot reach the Dask scheduler at {address}")
    assert not any(line.startswith("Traceback") for line in err)
    assert not (out / CSV_NAME).exists()


def test_a_task_that_kills_its_worker_is_an_error_row_and_the_sweep_goes_on():
    """A configuration whose task takes its worker process down (a segfault, the OOM
    killer) becomes a row with status "error"; the other configurations are planned."""
    import os

    import dask

    from silo4sweep.engine import dask_client, run_configs

    grid = GRID[1:3]  # two plannable configurations
    doomed = grid[0].key

    def crash_one(config, settings):  # pickled by value (defined here), runs on the worker
        if config.key == doomed:
            os._exit(1)
        return plan_row(config, settings)

    # no retry of a task that killed a worker; 2 workers holding one task each, so the other
    # task is not on the dying one (a task queued on a dying worker is suspected too)
    with dask.config.set(
        {
            "distributed.scheduler.allowed-failures": 0,
            "distributed.scheduler.worker-saturation": 1.0,
        }
    ):
        with dask_client(workers=2) as client:
            rows = dict(
                (c.key, row) for c, row in run_configs(client, grid, SETTINGS, task=crash_one)
            )
    assert rows[doomed]["status"] == "error"
    assert rows[doomed]["reason"].startswith("task failed: KilledWorker")
    assert rows[grid[1].key]["status"] == "ok"
