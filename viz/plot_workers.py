"""Plots drawn beside the rest of a run: worker processes, and the names of the figures.

matplotlib draws on one core and costs ~0.1 s of CPU per figure whatever we trim (measured:
ticks and text are most of it). ``silo4 plan`` therefore starts the plots in forked worker
processes before it writes the CSV, npz and animation, and collects them at the end
(issue 14: a default run within 2x of one without plots). Each worker imports matplotlib
itself and writes a share of the figures into the run's temporary folder; the parent only
waits, so the files and bytes are the same as drawing in-process.

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

from planner.files import stop_requested, stop_signals_held
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
    import gc

    for signum in (signal.SIGINT, signal.SIGTERM):   # the run's handlers are the parent's:
        signal.signal(signum, signal.SIG_DFL)         # stop() or Ctrl-C end a worker at once
    if stop_requested():   # a signal came while it was forked (stop_signals_held): the
        os._exit(1)        # parent stops the run; nothing to draw
    gc.disable()
    try:
        from .plots import write_plots

        write_plots(folder, trajectory, only=only, **options)
        conn.send(("ok", ""))
    except Silo4Error as exc:
        conn.send(("user", str(exc)))
    except BaseException as exc:  # noqa: BLE001 - reported to the parent, which raises
        conn.send(("internal", f"{type(exc).__name__}: {exc}"))
    finally:
        conn.close()


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
        can_fork = "fork" in multiprocessing.get_all_start_methods()
        self.workers = workers if can_fork and (os.cpu_count() or 1) > 1 else 0
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
            from .plots import write_plots

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
            if proc.is_alive():
                proc.terminate()
            proc.join()
            conn.close()
        self.running = []


def plot_job(trajectory: Any, *, waypoints_in_world: Sequence | None,
             formats: Sequence[str], window_s: tuple[float, float] | None,
             workers: int | None = None) -> PlotJob:
    """A :class:`PlotJob` with ``write_plots`` options (workers: :func:`default_workers`)."""
    return PlotJob(trajectory, {"waypoints_in_world": waypoints_in_world,
                                "formats": tuple(formats), "window_s": window_s},
                   default_workers() if workers is None else workers)
