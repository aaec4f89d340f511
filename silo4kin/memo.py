"""Memos kept on the objects whose state they are.

A robot, a planning model or a leg table owns a plain ``dict`` (a private field created with
the object, e.g. ``field(default_factory=dict, init=False)`` of a frozen dataclass); the
results computed from that object are stored there, so they live exactly as long as it does
and no module holds a global table keyed on ``id()``. :func:`memoised` is the one lookup.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Hashable
from typing import Any, TypeVar

T = TypeVar("T")

_MISSING: Any = object()


def memoised(
    memo: dict[Hashable, Any],
    key: Hashable,
    compute: Callable[[], T],
    max_entries: int | None = None,
) -> T:
    """``memo[key]``, computing and storing ``compute()`` when absent; a memo that already
    holds ``max_entries`` entries is emptied first (the inputs of a planner run repeat within
    the run, so emptying costs one recomputation of each)."""
    hit = memo.get(key, _MISSING)
    if hit is _MISSING:
        if max_entries is not None and len(memo) >= max_entries:
            memo.clear()
        hit = memo[key] = compute()
    return hit


def memo_of(owner: Any) -> dict[Hashable, Any]:
    """The memo dict of ``owner`` (its ``_memo`` field)."""
    memo: dict[Hashable, Any] = owner._memo
    return memo


def cached_on_first_argument(max_entries: int) -> Callable[[Callable[..., T]], Callable[..., T]]:
    """Decorator: memoise a function of an object (its first argument, e.g. a robot) and
    hashable other arguments in that object's memo (:func:`memo_of`), at most
    ``max_entries`` results per function and object. An object without a memo (a stand-in
    in a test) gets the result computed each time."""

    def decorate(function: Callable[..., T]) -> Callable[..., T]:
        @functools.wraps(function)
        def wrapper(owner: Any, *args: Any, **kwargs: Any) -> T:
            memo = getattr(owner, "_memo", None)
            if memo is None:
                return function(owner, *args, **kwargs)
            own = memo.get(function)
            if own is None:
                own = memo[function] = {}
            key = (args, tuple(sorted(kwargs.items()))) if kwargs else args
            return memoised(own, key, lambda: function(owner, *args, **kwargs), max_entries)

        return wrapper

    return decorate


def results_of(function: Callable[..., Any], owner: Any) -> dict[Hashable, Any] | None:
    """The results ``function`` (decorated by :func:`cached_on_first_argument`) keeps for
    ``owner``, keyed by its other arguments as passed (a dict that may be read and filled,
    e.g. from a store on disk), or None for an object without a memo."""
    memo = getattr(owner, "_memo", None)
    if memo is None:
        return None
    own: dict[Hashable, Any] = memo.setdefault(getattr(function, "__wrapped__", function), {})
    return own
