"""Progress for slow command-line work: bars (cases, plots, robots, sweeps) and a line with
the elapsed time for work without steps (--height auto, a physics replay).

    with progress_bar(total=len(cases), desc="cases") as bar:
        for case in cases:
            ...
            bar.update()

    for case in track(cases, desc="cases"):   # the same, for a plain loop
        ...

    with waiting("--height auto: searching heights"):   # no steps: the elapsed time
        ...

A bar (tqdm) or line appears on stderr only when stderr is a terminal: stdout stays the
same whatever it is piped to, and a log of stderr stays clean. tqdm is imported only when a
bar is shown (``silo4 --help`` pays nothing for it). Both appear after MIN_VISIBLE_S, so
work that ends sooner (most single plans) prints nothing, and both erase themselves.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

T = TypeVar("T")

#: A bar is drawn only once the work has run this long [s] ("anything over ~2 s").
MIN_VISIBLE_S = 2.0


class _Silent:
    """The bar's interface doing nothing (stderr is not a terminal)."""

    def update(self, n: int = 1) -> None:
        """Advance by ``n`` steps (ignored)."""

    def set_postfix_str(self, text: str) -> None:
        """Show ``text`` after the bar (ignored)."""


def enabled() -> bool:
    """True when a person watches: stderr is an interactive terminal."""
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):  # replaced or closed stdout
        return False


@contextmanager
def progress_bar(total: int | None, desc: str) -> Iterator[Any]:
    """A progress bar of ``total`` steps on stderr, or a silent stand-in.

    Yields:
        an object with ``update(n=1)`` and ``set_postfix_str(text)``.
    """
    if not enabled():
        yield _Silent()
        return
    from tqdm import tqdm

    bar = tqdm(
        total=total,
        desc=desc,
        file=sys.stderr,
        delay=MIN_VISIBLE_S,
        leave=False,
        dynamic_ncols=True,
        unit="step",
    )
    try:
        yield bar
    finally:
        bar.close()


def track(items: Iterable[T], desc: str, total: int | None = None) -> Iterator[T]:
    """Iterate ``items`` with a progress bar (see :func:`progress_bar`)."""
    if total is None and hasattr(items, "__len__"):
        total = len(items)  # type: ignore[arg-type]
    with progress_bar(total, desc) as bar:
        for item in items:
            yield item
            bar.update()


#: How often the line of :func:`waiting` is redrawn [s].
REDRAW_S = 0.5


@contextmanager
def waiting(desc: str) -> Iterator[None]:
    """``desc ... N s`` on stderr while the block runs (from MIN_VISIBLE_S on, redrawn every
    REDRAW_S, erased at the end); nothing when stderr is not a terminal."""
    if not enabled():
        yield
        return
    stream, done, t0 = sys.stderr, threading.Event(), time.perf_counter()
    shown = False

    def draw() -> None:
        nonlocal shown
        if done.wait(MIN_VISIBLE_S):
            return
        while True:
            stream.write(f"\r{desc} ... {time.perf_counter() - t0:.0f} s")
            stream.flush()
            shown = True
            if done.wait(REDRAW_S):
                return

    thread = threading.Thread(target=draw, daemon=True)
    thread.start()
    try:
        yield
    finally:
        done.set()
        thread.join()
        if shown:
            stream.write("\r\033[K")
            stream.flush()
