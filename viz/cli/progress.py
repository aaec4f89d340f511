"""Progress bars for slow command-line work (cases, plots, later simulate and sweeps).

    with progress_bar(total=len(cases), desc="cases") as bar:
        for case in cases:
            ...
            bar.update()

    for case in track(cases, desc="cases"):   # the same, for a plain loop
        ...

A bar (tqdm, on stderr) appears only when stdout is a terminal: piped or logged output stays
clean and byte-for-byte the same with or without a terminal. tqdm is imported only when a
bar is shown (``silo4 --help`` pays nothing for it). Bars appear after MIN_VISIBLE_S, so
work that ends sooner (most single plans) prints nothing.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

T = TypeVar("T")

#: A bar is drawn only once the work has run this long [s] ("anything over ~2 s").
MIN_VISIBLE_S = 2.0


class _Silent:
    """The bar's interface doing nothing (stdout is not a terminal)."""

    def update(self, n: int = 1) -> None:
        """Advance by ``n`` steps (ignored)."""

    def set_postfix_str(self, text: str) -> None:
        """Show ``text`` after the bar (ignored)."""


def enabled() -> bool:
    """True when a person watches: stdout is an interactive terminal."""
    try:
        return sys.stdout.isatty()
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

    bar = tqdm(total=total, desc=desc, file=sys.stderr, delay=MIN_VISIBLE_S, leave=False,
               dynamic_ncols=True, unit="step")
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
