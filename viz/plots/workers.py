"""Plots drawn beside the rest of a run: worker processes, and the names of the figures.

matplotlib draws on one core and costs ~0.1 s of CPU per figure whatever we trim (measured:
ticks and text are most of it). ``silo4 plan`` therefore starts the plots in forked worker
processes before it writes the CSV, npz and animation, and collects them at the end
(a default run stays within 2x of one without plots). Each worker imports matplotlib
itself and writes a share of the figures into the run's temporary folder, forking once more
after the import so that a copy draws every other figure of its share (two cores drawing,
one matplotlib import; the copy dies with its worker); the parent only waits, so the files
and bytes are the same as drawing in-process.

``silo4 plan`` also forks one worker before it plans (:func:`prewarm`): it imports matplotlib
(~0.3 s) while the parent plans, then draws the share the job sends it through its pipe.

Where ``fork`` is unavailable (Windows) or only one CPU is present, the figures are drawn
in-process at :meth:`PlotJob.finish`. A worker's Silo4Error comes back as a Silo4Error with
the same message; any other failure as a RuntimeError naming the worker.

This module imports neither numpy nor matplotlib (``figure_stems`` and ``parse_window``
serve the CLI before any plotting starts).
"""

from __future__ import annotations

import math
import multiprocessing
import os
import re
import signal
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from planner.outputs.files import stop_requested, stop_signals_held
from silo4kin.errors import Silo4Error

#: Worker processes for the plots (each gets a share of the figures). One overlaps the
#: figures with the CSV, npz and animation; measured on the shared 2-core machine, two cost a
#: second matplotlib import and were slower (6.3-7.8 s vs 4.3-5.6 s wall). The environment
#: variable SILO4_PLOT_WORKERS overrides it (0: draw in-process, e.g. on a busy machine).
DEFAULT_WORKERS = 1


#: How often the parent looks for finished figures while it waits (progress bar) [s].
PROGRESS_POLL_S = 0.1


def default_workers() -> int:
    """SILO4_PLOT_WORKERS if set to a non-negative integer, else DEFAULT_WORKERS."""
    text = os.environ.get("SILO4_PLOT_WORKERS", "")
    return int(text) if text.isdigit() else DEFAULT_WORKERS


def parse_window(text: str) -> tuple[float, float]:
    """``"T0:T1"`` [s] -> (t0, t1) with 0 <= t0 < t1 (the ``--window`` option)."""
    parts = text.split(":")
    try:
        t0, t1 = (float(p) for p in parts)
    except ValueError:
        raise Silo4Error(f"--window {text!r}: expected T0:T1 in seconds, e.g. 10:20") from None
    if not (math.isfinite(t0) and math.isfinite(t1) and 0 <= t0 < t1):
        raise Silo4Error(f"--window {text!r}: need 0 <= T0 < T1 [s]")
    return t0, t1


def figure_stems(trajectory: Any, window: bool = False) -> list[str]:
    """The stems ``write_plots`` writes for this trajectory, in order."""
    stems = ["joint_positions", "joint_velocities", "joint_accelerations", "path",
             "stability_margin", "cycle_cartesian"]
    if trajectory.tau is not None:
        stems += ["torques"] + ["torques_" + re.sub(r"[^A-Za-z0-9_-]+", "_", p)
                                for p in sorted(trajectory.tau_parts)]
    if window:
        stems += [f"{s}_window" for s in stems[:3]] + (
            ["torques_window"] if trajectory.tau is not None else [])
    return stems


def _work(conn: Any, folder: Path, trajectory: Any, options: dict, only: list[str]) -> None:
    """Worker body: draw ``only`` into ``folder``; report "" or the error on ``conn``.

    The worker lives for one run, so it leaves Python's cyclic garbage collector off:
    matplotlib allocates ~10^5 container objects per figure, and each collection would walk
    them and the parent's inherited heap (touching it copies the forked pages)."""
    _worker_signals()
    _draw(conn, folder, trajectory, options, only)


def _worker_signals() -> None:
    """A worker's first step: the run's handlers are the parent's, so stop() or Ctrl-C end a
    worker at once; a signal that came while it was forked (stop_signals_held) means the
    parent stops the run and there is nothing to draw. The cyclic GC stays off (see _work).

    The handlers are a Python function that exits, not SIG_DFL: a signal that reached the
    fork before this step is only flagged at the C level, and Python drops a flagged signal
    whose handler has meanwhile become SIG_DFL (seen: terminate() right after the fork left
    the worker waiting forever)."""
    import gc

    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, _exit_now)
    if stop_requested():
        os._exit(1)
    gc.disable()


def _exit_now(signum: int, frame: object) -> None:
    os._exit(128 + signum)


def _draw(conn: Any, folder: Path, trajectory: Any, options: dict, only: list[str]) -> None:
    """Draw ``only`` into ``folder``; send ("ok" | "user" | "internal", message) on ``conn``.

    With two cores or more the worker forks once more (:func:`_fork_helper`): the copy
    draws every other figure (matplotlib is imported already, so the split costs no second
    import), which halves the wall time of the plots when a core is free."""
    helper = _fork_helper(folder, trajectory, options, only[1::2]) if len(only) > 1 else None
    mine = only if helper is None else only[0::2]
    result = _draw_here(folder, trajectory, options, mine)
    if helper is not None:
        theirs = _helper_result(*helper)
        result = result if result[0] != "ok" else theirs
    try:
        conn.send(result)
    finally:
        conn.close()


def _draw_here(folder: Path, trajectory: Any, options: dict, only: list[str]
               ) -> tuple[str, str]:
    """Draw ``only`` into ``folder`` in this process: ("ok" | "user" | "internal", message)."""
    try:
        from viz.plots.run_plots import write_plots

        write_plots(folder, trajectory, only=only, **options)
        return ("ok", "")
    except Silo4Error as exc:
        return ("user", str(exc))
    except BaseException as exc:  # noqa: BLE001 - reported to the parent, which raises
        return ("internal", f"{type(exc).__name__}: {exc}")


def _fork_helper(folder: Path, trajectory: Any, options: dict, only: list[str]
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
    try:                                   # the copy: draw, report, never return
        os.close(read_end)
        if prctl(1, signal.SIGKILL, 0, 0, 0) != 0 or os.getppid() != worker:
            os._exit(1)                    # (1 = PR_SET_PDEATHSIG; the worker is gone)
        kind, message = _draw_here(folder, trajectory, options, only)
        os.write(write_end, f"{kind}\n{message}".encode())
        os._exit(0)
    except BaseException:  # noqa: BLE001 - the worker reports a copy that did not finish
        os._exit(1)


def _helper_result(pid: int, read_end: int) -> tuple[str, str]:
    """Wait for the copy of :func:`_fork_helper`; its ("ok" | "user" | "internal", message)."""
    chunks = []
    with os.fdopen(read_end, "rb") as pipe:
        while chunk := pipe.read(65536):
            chunks.append(chunk)
    _, status = os.waitpid(pid, 0)
    kind, _, message = b"".join(chunks).decode(errors="replace").partition("\n")
    if kind in ("ok", "user", "internal"):
        return kind, message
    return "internal", f"plot helper process exited with status {status}"


def _warm(conn: Any, parent_end: Any) -> None:
    """Pre-warmed worker body: import matplotlib and the plots while the parent plans, then
    draw the one job the parent sends (None or a closed pipe: exit, nothing to draw)."""
    parent_end.close()      # the parent's end, inherited by the fork: a parent that dies
    _worker_signals()       # must leave this worker reading EOF, not waiting forever
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
    _draw(conn, *job)


#: Pre-warmed workers started by :func:`prewarm` and not yet given a job: (process, pipe).
_WARM: list[tuple[Any, Any]] = []

#: Largest trajectory [bytes of its arrays] sent to a pre-warmed worker through its pipe;
#: past it the job forks a fresh worker, which shares the trajectory's pages instead.
WARM_MAX_BYTES = 64 * 2**20


def prewarm() -> None:
    """Fork one plot worker now that imports matplotlib while the caller plans (``silo4
    plan``: the import is ~0.3 s of the plots' ~1.4 s, and planning leaves a core free), to
    be given its job by :meth:`PlotJob.start`. A no-op where jobs draw in-process. A worker
    never given a job ends with the run (daemon, and EOF on its pipe)."""
    if _WARM or not _can_fork() or default_workers() < 1:
        return
    ctx = multiprocessing.get_context("fork")
    parent, child = ctx.Pipe(duplex=True)
    proc = ctx.Process(target=_warm, args=(child, parent), daemon=True)
    with stop_signals_held():
        proc.start()
        _WARM.append((proc, parent))
    child.close()


def _take_warm(trajectory: Any) -> tuple[Any, Any] | None:
    """A live pre-warmed worker for ``trajectory``, or None (none, dead, or too big a job)."""
    while _WARM:
        proc, conn = _WARM.pop()
        if proc.is_alive() and _array_bytes(trajectory) <= WARM_MAX_BYTES:
            return proc, conn
        conn.close()
        _end(proc)
    return None


def discard_warm() -> None:
    """End any pre-warmed worker not given a job (a run that failed or wrote no plots)."""
    while _WARM:
        proc, conn = _WARM.pop()
        conn.close()
        _end(proc)


def _end(proc: Any) -> None:
    """Stop a worker now: SIGKILL, which no handler can catch, delay or drop (a SIGTERM
    reaching a just-forked worker before its handlers are set can be lost, and join() would
    wait forever); whatever it wrote is in the run's temporary folder, removed with it."""
    if proc.is_alive():
        proc.kill()
    proc.join()


def _array_bytes(trajectory: Any) -> int:
    values = vars(trajectory).values() if hasattr(trajectory, "__dict__") else ()
    return sum(int(getattr(v, "nbytes", 0)) for v in values)


def _can_fork() -> bool:
    return "fork" in multiprocessing.get_all_start_methods() and (os.cpu_count() or 1) > 1


class PlotJob:
    """The plots of one run, started with :meth:`start` and collected with :meth:`finish`.

    Args:
        trajectory: the plan.
        options: keyword arguments of ``write_plots`` (waypoints_in_world, formats,
            window_s).
        workers: processes to use; 0 draws in-process.
    """

    def __init__(self, trajectory: Any, options: dict, workers: int = DEFAULT_WORKERS) -> None:
        self.trajectory = trajectory
        self.options = options
        self.stems = figure_stems(trajectory, window=options.get("window_s") is not None)
        self.workers = workers if _can_fork() else 0
        self.running: list[tuple[Any, Any]] = []
        self.folder: Path | None = None

    def files(self, folder: Path) -> list[Path]:
        """The files the job writes, in figure order then format order."""
        return [folder / f"{stem}.{fmt}" for stem in self.stems
                for fmt in self.options.get("formats", ("png",))]

    def start(self, folder: Path) -> None:
        """Fork the workers drawing into ``folder`` (no-op when drawing in-process)."""
        self.folder = folder
        if not self.workers:
            return
        ctx = multiprocessing.get_context("fork")
        for share in (self.stems[i::self.workers] for i in range(self.workers)):
            if not share:
                continue
            warm = _take_warm(self.trajectory)
            if warm is not None:   # matplotlib already imported (prewarm)
                with stop_signals_held():
                    self.running.append(warm)
                try:
                    warm[1].send((folder, self.trajectory, self.options, share))
                    continue
                except (OSError, ValueError):   # it died meanwhile: fork a fresh one
                    self.running.remove(warm)
                    _end(warm[0])
                    warm[1].close()
            parent, child = ctx.Pipe(duplex=False)
            proc = ctx.Process(target=_work, args=(child, folder, self.trajectory,
                                                   self.options, share), daemon=True)
            # SIGINT/SIGTERM wait until the worker is registered: a signal during the fork
            # would leave a worker that stop() does not know, drawing into a folder the run
            # removes (seen in tests/test_run_folder.py)
            with stop_signals_held():
                proc.start()
                self.running.append((proc, parent))
            child.close()

    def finish(self, folder: Path, on_figure: Any = None) -> list[Path]:
        """Wait for the workers (or draw now); returns :meth:`files`.

        Raises:
            Silo4Error: a figure could not be written (the worker's message).
            RuntimeError: a worker failed otherwise.
        """
        if self.folder is None or not self.running:
            from viz.plots.run_plots import write_plots

            return write_plots(folder, self.trajectory, on_figure=on_figure, **self.options)
        errors: list[tuple[str, str]] = []
        done: set[str] = set()

        def tick() -> None:  # progress: a figure is done when its last format exists
            if on_figure is None:
                return
            last = self.options.get("formats", ("png",))[-1]
            for stem in self.stems:
                if stem not in done and (folder / f"{stem}.{last}").exists():
                    done.add(stem)
                    on_figure(stem)

        try:
            for _, conn in self.running:
                while not conn.poll(PROGRESS_POLL_S):
                    tick()
            for proc, conn in self.running:
                try:
                    kind, message = conn.recv()
                except EOFError:
                    kind, message = "internal", f"plot worker exited with {proc.exitcode}"
                proc.join()
                if kind != "ok":
                    errors.append((kind, message))
        finally:
            self.stop()
        for kind, message in errors:
            if kind == "user":
                raise Silo4Error(message)
            raise RuntimeError(f"plot worker failed: {message}")
        tick()
        return self.files(folder)

    def stop(self) -> None:
        """End any worker still running (after an error elsewhere in the run)."""
        for proc, conn in self.running:
            _end(proc)
            conn.close()
        self.running = []


def plot_job(trajectory: Any, *, waypoints_in_world: Sequence | None,
             formats: Sequence[str], window_s: tuple[float, float] | None,
             workers: int | None = None) -> PlotJob:
    """A :class:`PlotJob` with ``write_plots`` options (workers: :func:`default_workers`)."""
    return PlotJob(trajectory, {"waypoints_in_world": waypoints_in_world,
                                "formats": tuple(formats), "window_s": window_s},
                   default_workers() if workers is None else workers)
