"""Stop signals during a write: SIGINT / SIGTERM / SIGHUP never cut a folder swap in two.

The CLI turns SIGTERM into :class:`RunInterrupted` and records the request
(:func:`request_stop`); the folder swap checks the record again right before the rename, so
a stop holds even when library code swallowed the exception. :func:`stop_signals_held` and
:func:`signals_deferred` hold the signals back across steps that must not be split.
"""

from __future__ import annotations

import contextlib
import signal
from collections.abc import Iterator
from typing import Any


class RunInterrupted(BaseException):  # noqa: N818 (like KeyboardInterrupt, not an error)
    """A signal asked the run to stop (the CLI raises it from its SIGTERM handler)."""


#: The signals that stop a run (SIGHUP: the terminal closed); the CLI handles each.
STOP_SIGNALS: tuple[signal.Signals, ...] = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)

_stop_requested = False


def request_stop() -> None:
    """Record that a signal asked the run to stop. Checked again just before a run folder is
    swapped into place, so the request holds even if library code swallowed the exception
    the signal handler raised."""
    global _stop_requested
    _stop_requested = True


def stop_requested() -> bool:
    """Whether :func:`request_stop` was called in this process."""
    return _stop_requested


@contextlib.contextmanager
def stop_signals_held() -> Iterator[None]:
    """SIGINT/SIGTERM wait until the block ends, then reach the handlers they would have
    reached: for steps that must not be cut in two (a folder made but not yet known, a worker
    forked but not yet registered). Python runs a handler between bytecodes, and a signal
    that has already arrived is not held back by pthread_sigmask, so the handlers are swapped
    for one that only remembers (and sets the stop flag, :func:`request_stop`). Main thread
    only; elsewhere a no-op."""
    caught: list[int] = []

    def remember(signum: int, frame: object) -> None:
        request_stop()
        caught.append(signum)

    old: dict[int, Any] = {}
    try:
        for signum in STOP_SIGNALS:
            old[signum] = signal.signal(signum, remember)
    except ValueError:  # not the main thread: nothing swapped
        yield
        return
    try:
        yield
    finally:
        for held, handler in old.items():
            signal.signal(held, signal.SIG_DFL if handler is None else handler)
        for number in caught[:1]:
            signal.raise_signal(number)


@contextlib.contextmanager
def signals_deferred() -> Iterator[None]:
    """Hold the STOP_SIGNALS back while a folder is swapped (delivered right after)."""
    blocked = set(STOP_SIGNALS)
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, blocked)
    except (AttributeError, OSError, ValueError):
        yield
        return
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)
