"""The plots of one run, drawn beside the rest of it in worker processes.

``silo4 plan`` starts the plots in forked worker processes (viz/plots/worker_process.py)
before it writes the CSV, npz and animation, and collects them at the end (a default run
stays within 2x of one without plots); a worker pre-warmed before planning
(viz/plots/prewarm.py) takes the first share.

Where ``fork`` is unavailable (Windows) or only one CPU is present, the figures are drawn
in-process at :meth:`PlotJob.finish`. A worker's Silo4Error comes back as a Silo4Error with
the same message; any other failure as a RuntimeError naming the worker.
"""

from __future__ import annotations

import multiprocessing
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from planner.outputs.files import stop_signals_held
from viz.plots.figure_names import figure_stems
from viz.plots.prewarm import take_warm
from viz.plots.worker_process import (
    DEFAULT_WORKERS,
    DrawReport,
    Outcome,
    can_fork,
    default_workers,
    end_worker,
    work,
)

#: How often the parent looks for finished figures while it waits (progress bar) [s].
PROGRESS_POLL_S = 0.1


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
        self.workers = workers if can_fork() else 0
        self.running: list[tuple[Any, Any]] = []
        self.folder: Path | None = None

    def files(self, folder: Path) -> list[Path]:
        """The files the job writes, in figure order then format order."""
        return [
            folder / f"{stem}.{fmt}"
            for stem in self.stems
            for fmt in self.options.get("formats", ("png",))
        ]

    def start(self, folder: Path) -> None:
        """Fork the workers drawing into ``folder`` (no-op when drawing in-process)."""
        self.folder = folder
        if not self.workers:
            return
        ctx = multiprocessing.get_context("fork")
        for share in (self.stems[i :: self.workers] for i in range(self.workers)):
            if not share:
                continue
            warm = take_warm(self.trajectory)
            if warm is not None:  # matplotlib already imported (prewarm)
                with stop_signals_held():
                    self.running.append(warm)
                try:
                    warm[1].send((folder, self.trajectory, self.options, share))
                    continue
                except (OSError, ValueError):  # it died meanwhile: fork a fresh one
                    self.running.remove(warm)
                    end_worker(warm[0])
                    warm[1].close()
            parent, child = ctx.Pipe(duplex=False)
            proc = ctx.Process(
                target=work, args=(child, folder, self.trajectory, self.options, share), daemon=True
            )
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
        errors: list[DrawReport] = []
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
                    report = conn.recv()
                except EOFError:
                    report = DrawReport(
                        Outcome.INTERNAL_ERROR, f"plot worker exited with {proc.exitcode}"
                    )
                proc.join()
                if report.outcome is not Outcome.OK:
                    errors.append(report)
        finally:
            self.stop()
        for report in errors:
            report.raise_error()
        tick()
        return self.files(folder)

    def stop(self) -> None:
        """End any worker still running (after an error elsewhere in the run)."""
        for proc, conn in self.running:
            end_worker(proc)
            conn.close()
        self.running = []


def plot_job(
    trajectory: Any,
    *,
    waypoints_in_world: Sequence | None,
    formats: Sequence[str],
    window_s: tuple[float, float] | None,
    workers: int | None = None,
) -> PlotJob:
    """A :class:`PlotJob` with ``write_plots`` options (workers: :func:`default_workers`)."""
    return PlotJob(
        trajectory,
        {"waypoints_in_world": waypoints_in_world, "formats": tuple(formats), "window_s": window_s},
        default_workers() if workers is None else workers,
    )
