"""The gait a preset walks for a gait name (planner/presets.py Preset.gait_name): one object
per name, built of the gait classes of planner/gaits/base.py.

| name | gait |
|---|---|
| ``thesis`` | CreepSpin: §5.5 as written (the thesis preset's only gait) |
| ``plain`` | CreepSpin in the default preset's workspace |
| ``facing`` | Fallback(FacingPath, plain) |
| ``creep`` | OmniCreep |
| ``crawl`` | ContinuousCrawl |
| ``auto`` (default preset) | Fallback(Fastest(crawl on insect legs, creep), facing) |

A gait asked for by name walks that gait or fails with its reason; only "auto" (and
"facing", whose fallback is named in ``Plan.gait``) chooses.
"""

from __future__ import annotations

from collections.abc import Callable

from planner.gaits.base import Gait
from planner.gaits.combinators import DefaultFor, Fallback, Fastest
from planner.gaits.facing import FacingPath
from planner.gaits.thesis_walk import CreepSpin
from planner.gaits.without_turning import ContinuousCrawl, OmniCreep
from planner.presets import AUTO_GAIT, CRAWL_BY_DEFAULT_FAMILIES, Preset


def _facing() -> Gait:
    return Fallback(FacingPath(), CreepSpin("plain"))


def _auto() -> Gait:
    crawl = DefaultFor(
        ContinuousCrawl(),
        CRAWL_BY_DEFAULT_FAMILIES,
        "not validated in physics; gait='crawl' plans it",
    )
    return Fallback(Fastest((crawl, OmniCreep())), _facing())


_GAITS: dict[str, Callable[[], Gait]] = {
    "thesis": lambda: CreepSpin("thesis"),
    "plain": lambda: CreepSpin("plain"),
    "facing": _facing,
    "creep": OmniCreep,
    "crawl": ContinuousCrawl,
    AUTO_GAIT: _auto,
}


def gait_for(preset: Preset, asked: str | None = None, *, face_path: bool = False) -> Gait:
    """The gait object of ``preset`` for the name ``asked`` (None or "auto": the preset's
    default) and ``face_path``; PlannerInputError for a gait the preset does not offer."""
    return _GAITS[preset.gait_name(asked, face_path=face_path)]()
