"""A plot worker process: how many a run uses, what one does, and how one is ended.

matplotlib draws on one core and costs ~0.1 s of CPU per figure whatever we trim (measured:
ticks and text are most of it), so a run draws its figures in forked workers
(viz/plots/workers.py). Each worker imports matplotlib itself and writes a share of the
figures into the run's temporary folder, forking once more after the import so that a copy
draws every other figure of its share (two cores drawing, one matplotlib import; the copy
dies with its worker); the parent only waits, so the files and bytes are the same as drawing
in-process. A worker reports a :class:`DrawReport` on its pipe.
"""

from __future__ import annotations

import enum
import multiprocessing
import os
import signal
from pathlib import Path
from typing import Any, NamedTuple

from planner.outputs.files import stop_requested
from silo4kin.errors import Silo4Error

#: Worker processes for the plots (each gets a share of the figures). One overlaps the
#: figures with the CSV, npz and animation; measured on the shared 2-core machine, two cost a
#: second matplotlib import and were slower (6.3-7.8 s vs 4.3-5.6 s wall). The environment
#: variable SILO4_PLOT_WORKERS overrides it (0: draw in-process, e.g. on a busy machine).
DEFAULT_WORKERS = 1


class Outcome(str, enum.Enum):
    """How a worker's drawing ended (its value is what a drawing copy writes to its pipe)."""

    OK = "ok"
    #: a Silo4Error (a figure could not be written): the parent raises one, same message
    USER_ERROR = "user"
    #: anything else: the parent raises a RuntimeError naming the worker
    INTERNAL_ERROR = "internal"


class DrawReport(NamedTuple):
    """What a worker sends back: how its drawing ended and the error's message ("" if OK)."""

    outcome: Outcome
    message: str = ""

    def raise_error(self) -> None:
        """Raise the error this report carries (nothing when OK)."""
        if self.outcome is Outcome.USER_ERROR:
            raise Silo4Error(self.message)
        if self.outcome is Outcome.INTERNAL_ERROR:
            raise RuntimeError(f"plot worker failed: {self.message}")


def default_workers() -> int:
    """SILO4_PLOT_WORKERS if set to a non-negative integer, else DEFAULT_WORKERS."""
    text = os.environ.get("SILO4_PLOT_WORKERS", "")
    return int(text) if text.isdigit() else DEFAULT_WORKERS


def can_fork() -> bool:
    return "fork" in multiprocessing.get_all_start_methods() and (os.cpu_count() or 1) > 1


def end_worker(proc: Any) -> None:
    """Stop a worker now: SIGKILL, which no handler can catch, delay or drop (a SIGTERM
    reaching a just-forked worker before its handlers are set can be lost, and join() would
    wait forever); whatever it wrote is in the run's temporary folder, removed with it."""
    if proc.is_alive():
        proc.kill()
    proc.join()


def work(conn: Any, folder: Path, trajectory: Any, options: dict, only: list[str]) -> None:
    """Worker body: draw ``only`` into ``folder``; report "" or the error on ``conn``.

    The worker lives for one run, so it leaves Python's cyclic garbage collector off:
    matplotlib allocates ~10^5 container objects per figure, and each collection would walk
    them and the parent's inherited heap (touching it copies the forked pages)."""
    worker_signals()
    draw(conn, folder, trajectory, options, only)


def worker_signals() -> None:
    """A worker's first step: the run's handlers are the parent's, so stop() or Ctrl-C end a
    worker at once; a signal that came while it was forked (stop_signals_held) means the
    parent stops the run and there is nothing to draw. The cyclic GC stays off (see work).

    The handlers are a Python function that exits, not SIG_DFL: a signal that reached the
    fork before this step is only flagged at the C level, and Python drops a flagged signal
    whose handler has meanwhile become SIG_DFL (seen: terminate() right after the fork left
    the worker waiting forever)."""
    import gc

    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, _exit_now)
    if stop_requested():
        os._exit(1)
    _die_with_parent()
    gc.disable()


def _die_with_parent() -> None:
    """Linux: SIGKILL this worker when the run's process dies (PR_SET_PDEATHSIG), so a run
    killed with SIGKILL leaves no worker drawing into the folder the next run removes and
    then printing a BrokenPipeError when it reports; a parent already gone: exit now."""
    parent = multiprocessing.parent_process()
    try:
        import ctypes

        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return
    prctl(1, signal.SIGKILL, 0, 0, 0)  # 1 = PR_SET_PDEATHSIG
    if parent is not None and os.getppid() != parent.pid:
        os._exit(1)


def _exit_now(signum: int, frame: object) -> None:
    os._exit(128 + signum)


def draw(conn: Any, folder: Path, trajectory: Any, options: dict, only: list[str]) -> None:
    """Draw ``only`` into ``folder``; send a :class:`DrawReport` on ``conn``.

    With two cores or more the worker forks once more (:func:`fork_helper`): the copy
    draws every other figure (matplotlib is imported already, so the split costs no second
    import), which halves the wall time of the plots when a core is free."""
    helper = fork_helper(folder, trajectory, options, only[1::2]) if len(only) > 1 else None
    mine = only if helper is None else only[0::2]
    result = draw_here(folder, trajectory, options, mine)
    if helper is not None:
        theirs = helper_result(*helper)
        result = result if result.outcome is not Outcome.OK else theirs
    try:
        conn.send(result)
    finally:
        conn.close()


def draw_here(folder: Path, trajectory: Any, options: dict, only: list[str]) -> DrawReport:
    """Draw ``only`` into ``folder`` in this process; how it ended."""
    try:
        from viz.plots.run_plots import write_plots

        write_plots(folder, trajectory, only=only, **options)
        return DrawReport(Outcome.OK)
    except Silo4Error as exc:
        return DrawReport(Outcome.USER_ERROR, str(exc))
    except BaseException as exc:  # noqa: BLE001 - reported to the parent, which raises
        return DrawReport(Outcome.INTERNAL_ERROR, f"{type(exc).__name__}: {exc}")


def fork_helper(
    folder: Path, trajectory: Any, options: dict, only: list[str]
) -> tuple[int, int] | None:
    """Fork a copy of this worker drawing ``only``: (its pid, the read end of the pipe it
    reports on), or None where that is not possible (one core, no fork, no parent-death
    signal). The copy dies with this worker (Linux PR_SET_PDEATHSIG: a run stopped with
    SIGKILL on the worker leaves no drawer behind)."""
    if (os.cpu_count() or 1) < 2 or not only or not hasattr(os, "fork"):
        return None
    try:
        import ctypes

        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None
    read_end, write_end = os.pipe()
    worker = os.getpid()
    pid = os.fork()
    if pid:
        os.close(write_end)
        return pid, read_end
    try:  # the copy: draw, report, never return
        os.close(read_end)
        if prctl(1, signal.SIGKILL, 0, 0, 0) != 0 or os.getppid() != worker:
            os._exit(1)  # (1 = PR_SET_PDEATHSIG; the worker is gone)
        report = draw_here(folder, trajectory, options, only)
        os.write(write_end, f"{report.outcome.value}\n{report.message}".encode())
        os._exit(0)
    except BaseException:  # noqa: BLE001 - the worker reports a copy that did not finish
        os._exit(1)


def helper_result(pid: int, read_end: int) -> DrawReport:
    """Wait for the copy of :func:`fork_helper`; its report."""
    chunks = []
    with os.fdopen(read_end, "rb") as pipe:
        while chunk := pipe.read(65536):
            chunks.append(chunk)
    _, status = os.waitpid(pid, 0)
    kind, _, message = b"".join(chunks).decode(errors="replace").partition("\n")
    if kind in {outcome.value for outcome in Outcome}:
        return DrawReport(Outcome(kind), message)
    return DrawReport(Outcome.INTERNAL_ERROR, f"plot helper process exited with status {status}")


def warm_work(conn: Any, parent_end: Any) -> None:
    """Pre-warmed worker body: import matplotlib and the plots while the parent plans, then
    draw the one job the parent sends (None or a closed pipe: exit, nothing to draw)."""
    parent_end.close()  # the parent's end, inherited by the fork: a parent that dies
    worker_signals()  # must leave this worker reading EOF, not waiting forever
    try:
        import viz.plots.run_plots  # noqa: F401 - the import is the point: ~0.3 s of matplotlib
    except BaseException:  # noqa: BLE001 - the job's own import reports it
        pass
    try:
        job = conn.recv()
    except (EOFError, OSError):
        os._exit(0)
    if job is None or stop_requested():
        os._exit(0)
    draw(conn, *job)
