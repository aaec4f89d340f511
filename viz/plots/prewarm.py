"""The plot worker forked before a run plans (``silo4 plan``): it imports matplotlib (~0.3 s)
while the parent plans, then draws the share the run's PlotJob (viz/plots/workers.py) sends
it through its pipe."""

from __future__ import annotations

import multiprocessing
from typing import Any

from planner.outputs.files import stop_signals_held
from viz.plots.worker_process import can_fork, default_workers, end_worker, warm_work

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
    if _WARM or not can_fork() or default_workers() < 1:
        return
    ctx = multiprocessing.get_context("fork")
    parent, child = ctx.Pipe(duplex=True)
    proc = ctx.Process(target=warm_work, args=(child, parent), daemon=True)
    with stop_signals_held():
        proc.start()
        _WARM.append((proc, parent))
    child.close()


def take_warm(trajectory: Any) -> tuple[Any, Any] | None:
    """A live pre-warmed worker for ``trajectory``, or None (none, dead, or too big a job)."""
    while _WARM:
        proc, conn = _WARM.pop()
        if proc.is_alive() and _array_bytes(trajectory) <= WARM_MAX_BYTES:
            return proc, conn
        conn.close()
        end_worker(proc)
    return None


def discard_warm() -> None:
    """End any pre-warmed worker not given a job (a run that failed or wrote no plots)."""
    while _WARM:
        proc, conn = _WARM.pop()
        conn.close()
        end_worker(proc)


def _array_bytes(trajectory: Any) -> int:
    values = vars(trajectory).values() if hasattr(trajectory, "__dict__") else ()
    return sum(int(getattr(v, "nbytes", 0)) for v in values)
