"""Run the grid on Dask: one configuration per task, one row per task (design.md, "Sweeps").

    with dask_client(scheduler=None, workers=2) as client:        # a LocalCluster
        for config, row in run_configs(client, configs, settings):
            ...

No scheduler address: a ``distributed.LocalCluster`` on 127.0.0.1 with one single-threaded
worker process per core (or ``workers``), no dashboard. A scheduler address
(``tcp://host:port``): the same tasks on an existing Dask cluster (``dask scheduler`` /
``dask worker``, or any deployment); its workers need silo4kin installed. Dask is imported
only here (the optional ``sweep`` extra).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from silo4kin.errors import Silo4Error

from .grid import SweepConfig, SweepInputError
from .task import ERROR, SweepSettings, config_columns, plan_row

#: Default wait for a scheduler to answer, and for an existing cluster to offer a worker [s].
DEFAULT_CONNECT_TIMEOUT_S = 5.0


class SchedulerUnreachableError(Silo4Error):
    """The Dask scheduler at the given address did not answer (or has no worker).

    Attributes:
        address: the scheduler address given.
    """

    def __init__(self, message: str, address: str) -> None:
        super().__init__(message)
        self.address = address


class EngineMissingError(Silo4Error):
    """Dask is not installed (it comes with the optional ``sweep`` extra)."""


def default_workers() -> int:
    """One worker per core this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _distributed() -> Any:
    try:
        import distributed
    except ImportError:
        raise EngineMissingError("silo4 sweep needs Dask: pip install 'silo4kin[sweep]'") from None
    return distributed


@contextmanager
def sigint_ignored() -> Iterator[None]:
    """SIGINT ignored while the block starts processes (which keep ignoring it: a Ctrl-C at
    the terminal reaches the whole process group, and a worker that dies of it prints a
    traceback); the caller's handler afterwards. Outside the main thread: nothing changes."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextmanager
def dask_client(
    scheduler: str | None = None,
    workers: int | None = None,
    connect_timeout_s: float = DEFAULT_CONNECT_TIMEOUT_S,
) -> Iterator[Any]:
    """A ``distributed.Client``: of a new LocalCluster, or connected to ``scheduler``.

    Raises:
        SweepInputError: ``workers`` < 1, or given together with ``scheduler``.
        SchedulerUnreachableError: the scheduler does not answer within connect_timeout_s,
            or has no worker within that time.
    """
    distributed = _distributed()
    if workers is not None and workers < 1:
        raise SweepInputError(f"--workers {workers}: must be >= 1")
    if scheduler is None:
        with sigint_ignored():  # the workers inherit it: Ctrl-C stops this process only
            cluster = distributed.LocalCluster(
                n_workers=workers or default_workers(),
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                dashboard_address="127.0.0.1:0",
                silence_logs=logging.ERROR,
            )
        try:
            with distributed.Client(cluster) as client:
                yield client
        finally:
            cluster.close()
        return
    if workers is not None:
        raise SweepInputError(
            "--workers sizes the local cluster; an existing cluster at "
            "--scheduler has the workers it was started with"
        )
    check_protocol(scheduler)
    probe_scheduler(scheduler, connect_timeout_s)
    try:
        client = distributed.Client(scheduler, timeout=connect_timeout_s)
    except (OSError, TimeoutError, ValueError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise SchedulerUnreachableError(
            f"cannot reach the Dask scheduler at {scheduler} within {connect_timeout_s:g} s "
            f"({reason}); start one with `dask scheduler` or check the address",
            scheduler,
        ) from None
    try:
        try:
            client.wait_for_workers(1, timeout=connect_timeout_s)
        except (OSError, TimeoutError) as exc:
            raise SchedulerUnreachableError(
                f"the Dask scheduler at {scheduler} has no worker after {connect_timeout_s:g} s "
                "; start one with `dask worker " + scheduler + "`",
                scheduler,
            ) from exc
        yield client
    finally:
        client.close()


def check_protocol(scheduler: str) -> None:
    """The address's protocol (``tcp://`` when none is given) is one Dask can use here.

    Raises:
        SweepInputError: an unknown protocol, or one whose package is not installed (ucx).
    """
    from distributed.comm import registry

    scheme = scheduler.split("://", 1)[0] if "://" in scheduler else "tcp"
    try:
        registry.get_backend(scheme).get_connector()
    except Exception as exc:  # ValueError (unknown), ImportError/TypeError (not installed)
        usable = []
        for name in sorted(registry.backends):
            try:
                registry.get_backend(name).get_connector()
            except Exception:  # noqa: S112 (a backend that cannot connect is not listed)
                continue
            usable.append(name)
        raise SweepInputError(
            f"--scheduler {scheduler}: protocol {scheme!r} is not available here "
            f"({type(exc).__name__}); use one of {', '.join(usable)}"
        ) from None


def probe_scheduler(scheduler: str, timeout_s: float) -> None:
    """Ask the scheduler who it is, giving up after ``timeout_s`` [s] in all: a port that
    accepts and never answers is refused as fast as one that refuses the connection.

    Raises:
        SchedulerUnreachableError: no answer within ``timeout_s``.
    """
    import asyncio

    distributed = _distributed()

    async def identity() -> object:
        async with distributed.core.rpc(scheduler, timeout=timeout_s) as remote:
            return await remote.identity()

    try:
        asyncio.run(asyncio.wait_for(identity(), timeout_s))
    except Exception as exc:  # OSError, TimeoutError, a comm error: all mean no scheduler
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise SchedulerUnreachableError(
            f"cannot reach the Dask scheduler at {scheduler} within {timeout_s:g} s "
            f"({reason}); start one with `dask scheduler` or check the address",
            scheduler,
        ) from None


def run_configs(
    client: Any,
    configs: Sequence[SweepConfig],
    settings: SweepSettings,
    task: Callable[[SweepConfig, SweepSettings], dict[str, Any]] = plan_row,
) -> Iterator[tuple[SweepConfig, dict[str, Any]]]:
    """Submit one task per configuration; yield (config, row) as tasks finish.

    A task that dies with its worker (or fails outside plan_row) still yields a row, with
    status "error" and the reason. ``task`` is silo4sweep.task.plan_row (tests pass others).
    """
    distributed = _distributed()
    futures = {client.submit(task, config, settings, pure=False): config for config in configs}
    for future in distributed.as_completed(list(futures)):
        config = futures.pop(future)
        if future.status == "finished":
            row = future.result()
        else:
            exc = future.exception()
            row = config_columns(config)
            row.update(
                status=ERROR, reason=f"task failed: {type(exc).__name__}: {exc}".splitlines()[0]
            )
        future.release()
        yield config, row
