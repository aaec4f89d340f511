"""Memo of a plan's first walked segment (issue 14: the CPU time of ``silo4 cases``).

The ditch's route search (planner/studies/ditch.py) plans up to 221 routes per ditch, and every route
with the same approach offset walks the same first segment, (0, 0) to the approach point,
before it turns across the ditch; with gait "auto" it does so with both the continuous crawl
and the creeping gait. Nothing of the later waypoints enters that walk (the gaits without
turning walk to ``wp[aim]`` only, planner/path/plan_path.py), so the builder's state after it is a
function of: the planning model, the workspace, the stability threshold, the start heading,
the gait (crawl or creep), and the waypoint aimed at (its index is in every step).

:func:`walk_first_segment` replays that state from the memo when it has it. The foothold
check (plan_path's ``foothold_check``) can change the walk: a foothold it refuses in a crawl
attempt rolls the attempt back (planner/gaits/crawl.py). So a walk is memoised only when the check
refused none of its footholds, and a replay first asks the check about the same footholds in
the same order: if it refuses one, the segment is walked for real instead (the check is a
pure function of the foothold, and may see a foothold twice). The plans are the same bit for
bit (tests/test_perf_caches.py).
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import fields
from typing import Any

import numpy as np

from planner.gaits.builder import StepBuilder
from planner.workspace.layout import Workspace

#: Entries of the memo (a builder state of a few dozen steps each).
FIRST_WALK_MEMO_SIZE = 256
_MEMO: dict[tuple, tuple[Any, dict, Any, list[np.ndarray], tuple[int, float]]] = {}


def workspace_key(ws: Workspace) -> tuple:
    """Every field of ``ws`` as a hashable value (arrays as their dtype, shape and bytes)."""
    out = []
    for f in fields(ws):
        value = getattr(ws, f.name)
        if isinstance(value, np.ndarray):
            value = (value.dtype.str, value.shape, value.tobytes())
        out.append(value)
    return tuple(out)


def walk_first_segment(model: Any, key: tuple, b: StepBuilder, crawler: Any,
                       walk: Callable[[], tuple[int, float]]) -> tuple[int, float]:
    """``walk()`` (a segment's walk on the builder ``b``, with ``crawler`` the CrawlOrCreep or
    None). From the start pose (``b`` has no steps yet: the first segment), its result and
    the state of ``b`` and ``crawler`` after it come from the memo when it has them, for
    ``model`` and ``key`` (module docstring; the caller's key holds everything else the walk
    depends on); a later segment is walked as is."""
    if b.steps:
        return walk()
    full = (id(model), *key)
    hit = _MEMO.get(full)
    if hit is not None and hit[0] is model and _all_accepted(b.foothold_check, hit[3]):
        _, state, crawler_state, _, result = hit
        b.restore_state(state)
        if crawler is not None:
            crawler.__dict__.update(copy.deepcopy(crawler_state))
        return result
    check, seen, refused = b.foothold_check, [], []

    def recorded(position_foot_in_world: np.ndarray) -> None:
        seen.append(np.array(position_foot_in_world, dtype=float))
        if check is not None:
            try:
                check(position_foot_in_world)
            except BaseException:
                refused.append(len(seen))
                raise

    b.foothold_check = recorded
    try:
        result = walk()
    finally:
        b.foothold_check = check
    if not refused:
        if len(_MEMO) >= FIRST_WALK_MEMO_SIZE:
            _MEMO.clear()
        _MEMO[full] = (model, b.state(), None if crawler is None else copy.deepcopy(
            crawler.__dict__), seen, result)
    return result


def _all_accepted(check: Callable[[np.ndarray], None] | None,
                  footholds: list[np.ndarray]) -> bool:
    """Whether ``check`` (None: no check) accepts every foothold (3,) [m], in order."""
    if check is None:
        return True
    for foothold in footholds:
        try:
            check(foothold.copy())
        except Exception:  # noqa: BLE001 - any refusal: walk the segment for real
            return False
    return True
