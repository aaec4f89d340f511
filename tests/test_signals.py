"""A stop leaves nothing the run created, and the same command run again works.

Each run is ``silo4 plan`` in a subprocess with a stall hook (:data:`STALL_RUNNER`): the
hook wraps one writer so that, once it has done its work, it creates a marker file and
waits. The test waits for the marker, then signals: the signal lands at the named moment
every time, whatever the machine's speed (no sleep races the run).

- SIGINT / SIGTERM / SIGHUP once animation.html is in the temporary run folder: exit 128 +
  signal, one line, no ``o``, no ``.o.tmp-*``, no ``.o.lock``; the same command then works.
- SIGKILL of the run while its plot worker draws: the worker dies with it (no worker goes on
  drawing into the folder and prints a BrokenPipeError traceback when it reports), the next
  run removes the stale ``.o.lock`` and ``.o.tmp-*`` and writes ``o``; entries that are not
  a dead run's temporaries stay (planner/outputs/leftovers.py, ownership.py).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
COMMAND = [
    "plan",
    "--waypoints",
    "0,0.6",
    "--height",
    "0.4",
    "--samples-per-unit",
    "10",
    "--no-torques",
    "--out",
    "o",
]

#: ``python -c STALL_RUNNER HOOK MARKER silo4-args...``: silo4 with one writer stalled.
#: after-animation: animation.html is written, then the main process waits (signals reach
#: it there). plots-orphaned: the plot worker waits until the run's process is gone, then
#: draws and reports as a worker that outlived its run would.
STALL_RUNNER = """
import os, sys, time
hook, marker, argv = sys.argv[1], sys.argv[2], sys.argv[3:]
run_pid = os.getpid()

def mark():
    with open(marker, "w"):
        pass

if hook == "after-animation":
    import viz.animation.page as page
    written = page.write_animation_html

    def stalled(*args, **kwargs):
        written(*args, **kwargs)
        mark()
        while True:
            time.sleep(60)

    page.write_animation_html = stalled
elif hook == "plots-orphaned":
    import viz.plots.run_plots as run_plots
    drawn = run_plots.write_plots

    def orphaned(*args, **kwargs):
        mark()
        while True:
            try:
                os.kill(run_pid, 0)
            except ProcessLookupError:
                break
            time.sleep(0.01)
        return drawn(*args, **kwargs)

    run_plots.write_plots = orphaned
else:
    raise SystemExit(f"unknown hook {hook}")
from viz.cli.main import main
raise SystemExit(main(argv))
"""

#: A safety net for a stuck child, not a timing bound.
TIMEOUT_S = 600


def _env() -> dict[str, str]:
    return dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore", SILO4_PLOT_WORKERS="1")


def _start_stalled(cwd: Path, hook: str, argv: list[str]) -> tuple[subprocess.Popen, Path]:
    marker = cwd.parent / f"{cwd.name}.{hook}.marker"
    proc = subprocess.Popen(
        [sys.executable, "-c", STALL_RUNNER, hook, str(marker), *argv],
        cwd=cwd,
        env=_env(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + TIMEOUT_S
    while not marker.exists():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.01)
    return proc, marker


def _silo4(cwd: Path, argv: list[str]) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "viz", *argv],
        cwd=cwd,
        env=_env(),
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
    )


@pytest.fixture
def cwd(tmp_path: Path) -> Path:
    """A working folder holding a file of the user's."""
    folder = tmp_path / "cwd"
    folder.mkdir()
    (folder / "notes.txt").write_text("mine\n")
    return folder


@pytest.mark.parametrize(
    "sig,code,line",
    [
        (signal.SIGINT, 130, "interrupted"),
        (signal.SIGTERM, 143, "terminated"),
        (signal.SIGHUP, 129, "hung up"),
    ],
)
def test_a_stop_after_the_animation_leaves_nothing(
    cwd: Path, sig: int, code: int, line: str
) -> None:
    """A stop once animation.html is in ``.o.tmp-*``: exit 128 + signal, one line, nothing
    the run created is left; the same command run again writes ``o``."""
    argv = [*COMMAND, "--html", "--plots"]
    proc, _marker = _start_stalled(cwd, "after-animation", argv)
    (tmp,) = [p for p in cwd.iterdir() if p.name.startswith(".o.tmp-")]
    assert (tmp / "animation.html").is_file()  # the named moment
    proc.send_signal(sig)
    _out, err = proc.communicate(timeout=TIMEOUT_S)
    assert proc.returncode == code, err
    assert err.splitlines() == [line], err
    assert sorted(p.name for p in cwd.iterdir()) == ["notes.txt"]
    again = _silo4(cwd, argv)
    assert again.returncode == 0, again.stderr
    assert "Traceback" not in again.stderr, again.stderr
    assert sorted(p.name for p in cwd.iterdir()) == ["notes.txt", "o"]
    assert (cwd / "o" / "animation.html").is_file()


def test_a_killed_run_leaves_no_worker_and_the_next_run_cleans_up(cwd: Path) -> None:
    """SIGKILL of the run while its plot worker draws: no traceback from a worker that
    outlived it, the stale lock and temporary folder are removed by the same command run
    again (exit 0, no traceback), and what is not a dead run's temporary stays."""
    (cwd / ".o.tmp-mine").mkdir()  # not named <pid>-: not silo4's to remove
    argv = [*COMMAND, "--no-html", "--plots"]
    proc, _marker = _start_stalled(cwd, "plots-orphaned", argv)
    proc.kill()
    proc.wait(timeout=TIMEOUT_S)  # reaped: its pid is gone, as for a user's kill -9
    _out, err = proc.communicate(timeout=TIMEOUT_S)  # EOF once every worker is gone too
    assert proc.returncode == -signal.SIGKILL
    assert "Traceback" not in err and "BrokenPipeError" not in err, err
    left = sorted(p.name for p in cwd.iterdir())
    assert ".o.lock" in left and any(n.startswith(f".o.tmp-{proc.pid}-") for n in left), left
    again = _silo4(cwd, argv)
    assert again.returncode == 0, again.stderr
    assert "Traceback" not in again.stderr, again.stderr
    assert sorted(p.name for p in cwd.iterdir()) == [".o.tmp-mine", "notes.txt", "o"]
    assert (cwd / "notes.txt").read_text() == "mine\n"
