"""``silo4 robots``: the robots the planner supports, with what it can do for each.

One line per robot (SILO4, the thesis's insect legs, then example-robot-data's quadrupeds by
loader name, silo4kin.robot_library): leg family, total mass, the default workspace's
feasible body-height range (planner.workspace.layout.feasible_height_range), the stride λ along
x at mid-height, and the heights at which it walks a path in every direction (elsewhere in
its range it walks only along its body axis: no stride across it, no spin). Lines are
printed as each robot is done: the mammal legs' reachable sets are grid masks
(planner/workspace/reach_mammal.py), a few seconds to a minute per robot; at a terminal a
bar on stderr says which robot is being computed. Computed rows are kept in the user's
cache folder per robot description, silo4 version and code (viz/cli/robot_cache.py), so a
second call reads them back in about a second; ``--no-cache`` computes every row again
without touching the cache, ``--clear-cache`` empties it first.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from silo4kin.errors import Silo4Error
from viz.cli.common import EXIT_OK

#: Columns of the table, as printed.
#: Decimals of the printed height range [m] (1 mm).
RANGE_DECIMALS = 3


def inward_range_text(low_m: float, high_m: float, decimals: int = RANGE_DECIMALS) -> str:
    """``low-high`` [m] rounded inwards (the low end up, the high end down) at ``decimals``:
    every height the text shows, its ends included, is one the planner accepts."""
    scale = 10**decimals
    low = math.ceil(round(low_m * scale, 6)) / scale
    high = math.floor(round(high_m * scale, 6)) / scale
    return f"{low:.{decimals}f}-{high:.{decimals}f}"


HEADER = (
    f"{'robot':<10} {'family':<7} {'mass kg':>8} {'height range m':>16} {'stride m':>9} "
    f"{'any direction m':>16}"
)


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``robots``."""
    p = sub.add_parser(
        "robots",
        help="list the supported robots: family, mass, height range, stride",
        description="The robots silo4 plans for (SILO4 and example-robot-data's quadrupeds "
        "by name), with leg family, total mass, the default workspace's feasible "
        "body-height range and the stride at mid-height.",
        epilog="example: silo4 robots --only go2,solo12",
    )
    p.add_argument(
        "--only",
        metavar="NAMES",
        default=None,
        help="comma-separated robot names (default: all; 'silo4' is the thesis's)",
    )
    p.add_argument(
        "--no-cache",
        action="store_true",
        help="compute every row again; neither read nor write the cache",
    )
    p.add_argument(
        "--clear-cache",
        action="store_true",
        help="delete the cached rows and feasible ranges first (folder: $SILO4_CACHE_DIR, "
        "else $XDG_CACHE_HOME/silo4 or ~/.cache/silo4)",
    )
    p.set_defaults(run=run)


def robot_names() -> tuple[str, ...]:
    """ "silo4" and example-robot-data's supported quadrupeds, in the library's order."""
    from silo4kin.robot_library import EXAMPLE_QUADRUPEDS

    return ("silo4",) + tuple(EXAMPLE_QUADRUPEDS)


def robot_row(name: str, *, remember_ranges: bool = False) -> dict[str, object]:
    """Family, mass [kg], feasible range (lo, hi) [m] or None, stride at mid-height [m], and
    the heights (lo, hi) [m] at which it walks a path in every direction, or None
    (feasible_height_range(..., any_direction=True): elsewhere in the range only along its
    body axis). With ``remember_ranges`` the ranges come from and go to the cache ``silo4
    plan`` keeps (viz/cli/range_cache.py), so either command finds what the other computed."""
    from contextlib import nullcontext

    from silo4kin import load_robot
    from viz.cli.range_cache import remembered_ranges

    robot = load_robot(None if name == "silo4" else name)
    with remembered_ranges(robot) if remember_ranges else nullcontext():
        return _row_of(name, robot)


def _row_of(name: str, robot: Any) -> dict[str, object]:
    """robot_row of the loaded ``robot``."""
    from planner.errors import PlannerInputError
    from planner.workspace.layout import feasible_height_range, stride_at

    row: dict[str, object] = {
        "robot": name,
        "family": robot.family,
        "mass_kg": float(robot.total_mass),
        "range_m": None,
        "stride_m": None,
        "any_direction_m": None,
    }
    try:
        lo, hi = feasible_height_range(robot)
    except PlannerInputError:
        return row
    row["range_m"] = (lo, hi)
    # workspace_for(...).stride_m without the rest of the Workspace (its spin angle)
    row["stride_m"] = stride_at(robot, round(0.5 * (lo + hi), 4))
    try:
        row["any_direction_m"] = feasible_height_range(robot, any_direction=True)
    except PlannerInputError:
        pass  # walks along its body only, at every feasible height
    return row


def format_row(row: dict[str, object]) -> str:
    """One table line (HEADER's columns)."""
    rng = row["range_m"]
    rng_text = "none" if rng is None else inward_range_text(rng[0], rng[1])  # type: ignore[index]
    stride = "-" if row["stride_m"] is None else f"{row['stride_m']:.3f}"
    turns = row.get("any_direction_m")
    turns_text = (
        ("none" if rng is not None else "-")
        if turns is None
        else inward_range_text(turns[0], turns[1])  # type: ignore[index]
    )
    return (
        f"{row['robot']:<10} {row['family']:<7} {row['mass_kg']:>8.2f} {rng_text:>16} "
        f"{stride:>9} {turns_text:>16}"
    )


def run(args: argparse.Namespace) -> int:
    """Print the table, one robot at a time."""
    names = robot_names()
    if args.only:
        asked = tuple(n.strip() for n in str(args.only).split(",") if n.strip())
        unknown = [n for n in asked if n not in names]
        if unknown:
            raise Silo4Error(
                f"--only: unknown robot(s) {', '.join(unknown)}; known: {', '.join(names)}"
            )
        names = asked
    from viz.cli.progress import progress_bar
    from viz.cli.range_cache import RangeCache
    from viz.cli.robot_cache import RobotRowCache, description_key

    if getattr(args, "clear_cache", False):
        RobotRowCache().clear()
        RangeCache().clear()  # silo4 plan's feasible ranges (viz/cli/range_cache.py)
    cache = None if getattr(args, "no_cache", False) else RobotRowCache()
    print(HEADER, flush=True)
    with progress_bar(len(names), "robots") as bar:  # stderr, at a terminal only
        for name in names:
            key = None if cache is None else description_key(name)
            row = None if cache is None or key is None else cache.get(name, key)
            if row is None:
                bar.set_postfix_str(f"{name}: reachable sets")
                row = robot_row(name, remember_ranges=cache is not None)
                if cache is not None and key is not None:
                    cache.put(name, key, row)
            print(format_row(row), flush=True)
            bar.update()
    return EXIT_OK
