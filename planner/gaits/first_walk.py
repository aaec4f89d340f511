"""Memo of a plan's first walked segment, for plans that start alike.

The ditch's route search (planner/studies/ditch.py) plans up to 221 routes per ditch, and every
route with the same approach offset walks the same first segment, (0, 0) to the approach
point, before it turns across the ditch; with gait "auto" it does so with both the
continuous crawl and the creeping gait. Nothing of the later waypoints enters that walk (the
gaits without turning walk to ``wp[aim]`` only, planner/gaits/without_turning.py), so the
builder's fields after it are a function of: the planning model, the workspace, the
stability threshold, the start heading, the gait, and the waypoint aimed at (its index is
in every step).

A :class:`FirstWalkMemo` is made by the caller that plans alike routes and passed to
plan_path (``first_walk_memo=``); it replays those fields (StepBuilder.snapshot / restore,
CrawlOrCreep.snapshot / restore) when it has them. The terrain's foothold rule can change
the walk: a foothold it refuses in a crawl attempt rolls the attempt back
(planner/gaits/crawl.py). So a walk is memoised only when the rule refused none of its
footholds, and a replay first asks the rule about the same footholds in the same order: if
it refuses one, the segment is walked for real instead (the rule is a pure function of the
foothold, and may see a foothold twice). The plans are the same bit for bit
(tests/test_perf_caches.py).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

from planner.gaits.builder import StepBuilder
from planner.workspace.layout import Workspace

#: Entries of a memo (a builder snapshot of a few dozen steps each).
FIRST_WALK_MEMO_SIZE = 256


def workspace_key(ws: Workspace) -> tuple:
    """Every field of ``ws`` as a hashable value (arrays as their dtype, shape and bytes)."""
    out = []
    for f in fields(ws):
        value = getattr(ws, f.name)
        if isinstance(value, np.ndarray):
            value = (value.dtype.str, value.shape, value.tobytes())
        out.append(value)
    return tuple(out)


@dataclass(frozen=True)
class _Entry:
    """One memoised first segment: the model it was walked for, the builder's and the
    crawler's snapshots after it, the footholds it placed (each (3,) [m]) and its result."""

    model: Any
    builder: dict
    crawler: Any
    footholds: list[np.ndarray]
    result: Any


@dataclass
class FirstWalkMemo:
    """First segments walked from the start pose (module docstring), at most ``size``."""

    size: int = FIRST_WALK_MEMO_SIZE
    entries: dict[tuple, _Entry] = field(default_factory=dict)
    hits: int = 0

    def walk(
        self, model: Any, key: tuple, b: StepBuilder, crawler: Any, walk: Callable[[], Any]
    ) -> Any:
        """``walk()`` (a segment's walk on the builder ``b``, with ``crawler`` the
        CrawlOrCreep or None). From the start pose (``b`` has no steps yet: the first
        segment), its result and the fields of ``b`` and ``crawler`` after it come from the
        memo when it has them for ``model`` and ``key`` (the caller's key holds everything
        else the walk depends on); a later segment is walked as is."""
        if b.steps:
            return walk()
        hit = self.entries.get(key)
        if (
            hit is not None
            and hit.model is model
            and _all_accepted(b.foothold_check, hit.footholds)
        ):
            b.restore(hit.builder)
            if crawler is not None:
                crawler.restore(hit.crawler)
            self.hits += 1
            return hit.result
        rule, seen, refused = b.foothold_check, [], []

        def recorded(position_foot_in_world: np.ndarray) -> None:
            seen.append(np.array(position_foot_in_world, dtype=float))
            if rule is not None:
                try:
                    rule(position_foot_in_world)
                except BaseException:
                    refused.append(len(seen))
                    raise

        b.foothold_check = recorded
        try:
            result = walk()
        finally:
            b.foothold_check = rule
        if not refused:
            if len(self.entries) >= self.size:
                self.entries.clear()
            self.entries[key] = _Entry(
                model, b.snapshot(), None if crawler is None else crawler.snapshot(), seen, result
            )
        return result


def walk_first_segment(
    memo: FirstWalkMemo | None,
    model: Any,
    key: tuple,
    b: StepBuilder,
    crawler: Any,
    walk: Callable[[], Any],
) -> Any:
    """``memo.walk(...)``, or ``walk()`` without a memo."""
    if memo is None:
        return walk()
    return memo.walk(model, key, b, crawler, walk)


def _all_accepted(rule: Callable[[np.ndarray], None] | None, footholds: list[np.ndarray]) -> bool:
    """Whether ``rule`` (None: no rule) accepts every foothold (3,) [m], in order."""
    if rule is None:
        return True
    for foothold in footholds:
        try:
            rule(foothold.copy())
        except Exception:  # noqa: BLE001 - any refusal: walk the segment for real
            return False
    return True
