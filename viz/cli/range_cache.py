"""The user's cache of feasible height ranges: what ``silo4 plan`` need not compute again.

A robot's feasible height range (planner.workspace.heights.feasible_height_range) depends
only on its description and on the code that computes it, and for a mammal leg it is most
of a plan's time (go2: ~15 s of a 17 s ``silo4 plan --height 0.31``, 89 reachable-set
layouts and their bisections). So the commands that plan keep the ranges they computed in
the user's cache folder (viz/cli/robot_cache.py's: ``$SILO4_CACHE_DIR``, else
``$XDG_CACHE_HOME/silo4``, else ``~/.cache/silo4``), in its ``ranges/``, and give them to
the next run's robot before it plans:

- key: SHA-256 of the robot as the planner sees it (its expanded URDF, its leg family and
  its legs' geometry, which carries what an SRDF's reference posture chose), of the source
  of the packages that compute the range (silo4kin and planner: an edited or upgraded
  planner misses), and of numpy's and Pinocchio's versions;
- one JSON file per key, written atomically (planner/outputs/atomic.py); an unreadable or
  malformed file is a miss, a folder that cannot be written is skipped (the plan is made
  and written all the same);
- ``silo4 robots --clear-cache`` deletes these files with the rows (only files named as
  the cache names them); ``SILO4_NO_CACHE=1`` makes every command neither read nor write
  them.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from viz.cli.robot_cache import KeyedJsonFiles, code_fingerprint

#: Layout of a cached file; bump it when its keys or meaning change.
RANGE_FORMAT = 1
#: Environment variable that turns the cache off ("1").
NO_CACHE_ENV = "SILO4_NO_CACHE"


def robot_key(robot: Any) -> str:
    """The cache key of ``robot`` (a silo4kin.Robot): module docstring."""
    description = pickle.dumps((robot.urdf_xml, robot.family, robot.legs), protocol=4)
    digest = hashlib.sha256(f"{RANGE_FORMAT}\0{code_fingerprint()}\0".encode())
    digest.update(description)
    return digest.hexdigest()


class RangeCache(KeyedJsonFiles):
    """Feasible ranges in ``folder / "ranges"``, one JSON file per robot key."""

    subfolder = "ranges"
    own_name = re.compile(r"[0-9a-f]{40}\.json")

    @property
    def ranges_folder(self) -> Path:
        """Where the files are."""
        return self.files_folder

    def path_for(self, key: str) -> Path:
        """The file of ``key``."""
        return self.ranges_folder / f"{key[:40]}.json"

    def get(self, key: str) -> dict[tuple[str, bool, bool], tuple[float, float]]:
        """The ranges kept under ``key`` (empty when missing, unreadable or malformed)."""
        record = self.read(self.path_for(key), key)
        ranges: dict[tuple[str, bool, bool], tuple[float, float]] = {}
        for row in [] if record is None else record.get("ranges", []):
            if not (isinstance(row, list) and len(row) == 5):
                return {}
            preset, clear_stance, any_direction, lo, hi = row
            if not (
                isinstance(preset, str)
                and isinstance(clear_stance, bool)
                and isinstance(any_direction, bool)
                and all(isinstance(v, float) and v == v for v in (lo, hi))
                and lo <= hi
            ):
                return {}
            ranges[(preset, clear_stance, any_direction)] = (lo, hi)
        return ranges

    def put(self, key: str, ranges: dict[tuple[str, bool, bool], tuple[float, float]]) -> None:
        """Keep ``ranges`` under ``key`` (nothing when empty or unchanged); a folder that
        cannot be written is skipped."""
        if not ranges or ranges == self.get(key):
            return
        rows = [[p, c, a, float(lo), float(hi)] for (p, c, a), (lo, hi) in sorted(ranges.items())]
        self.write(self.path_for(key), {"key": key, "ranges": rows})


def cache_off() -> bool:
    """Whether ``SILO4_NO_CACHE`` turns the cache off."""
    return os.environ.get(NO_CACHE_ENV, "") not in ("", "0")


@contextmanager
def remembered_ranges(robot: Any) -> Iterator[None]:
    """Give ``robot`` the feasible ranges cached for it, and keep the ones it computed
    meanwhile (also when the command then fails: a range computed is right either way)."""
    from planner.workspace.heights import known_feasible_ranges, remember_feasible_ranges

    if cache_off():
        yield
        return
    cache = RangeCache()
    key = robot_key(robot)
    remember_feasible_ranges(robot, cache.get(key))
    try:
        yield
    finally:
        cache.put(key, {**cache.get(key), **known_feasible_ranges(robot)})
