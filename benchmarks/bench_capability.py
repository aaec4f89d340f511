"""Capability table: for each robot the largest step rise (a block), the widest gap (no floor)
and the steepest ramp it plans AND walks in `silo4 simulate`'s default replay, found by a
doubling scan then bisection over a scenario scaled to the robot; prints the table and, for
the first value beyond each capability, how the planner answered (it should refuse naming
the terrain file and the part under the failing foothold; a plan that does not walk is a
defect and is printed as one).

    .venv/bin/python benchmarks/bench_capability.py [--robots silo4 mantis phasmid go2]
                                                    [--obstacles block gap ramp] [--bisect 2]

The scenarios (straight walks along +y from the origin, laid out from the robot's default
workspace at its height, bench_terrain.HEIGHTS_M): block: a floor at z = 0 and a box of the
rise, 1.5 strides deep, starting one stride ahead of the front feet; gap: two platforms
(tops at z = 0) over a void, the gap starting one stride ahead of the front feet; ramp: a
plank 0.02 m thick rolled about x, its top's lower edge on the floor one stride ahead of the
front feet, as long as the feet's span plus 2.5 strides, then a flat box at its top height.
Each walk ends with the hind feet half a stride past the obstacle. Planning and replay are
bench_terrain.plan_and_walk (``silo4 plan``'s defaults, ``silo4 simulate``'s).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from bench_terrain import HEIGHTS_M, ROBOTS, Layout, _edge_margin_m, layout_for, plan_and_walk

PLANK_THICKNESS_M = 0.02


def _platform(y0: float, y1: float, half_width: float, top: float = 0.0) -> dict:
    return {"center": [0.0, 0.5 * (y0 + y1), top - 0.25], "size": [2 * half_width, y1 - y0, 0.5]}


def block(layout: Layout, rise_m: float) -> tuple[dict, float]:
    """A box ``rise_m`` [m] high on the floor; returns (document, goal y [m])."""
    y0 = layout.front_y_m + layout.stride_m
    depth = 1.5 * layout.stride_m
    box = {
        "center": [0.0, y0 + 0.5 * depth, 0.5 * rise_m],
        "size": [2 * layout.column_x_m + 0.6, depth, rise_m],
    }
    goal = y0 + depth - layout.hind_y_m + 0.5 * layout.stride_m + _edge_margin_m()
    return {"floor": 0.0, "boxes": [box]}, goal


def gap(layout: Layout, width_m: float) -> tuple[dict, float]:
    """Two platforms with ``width_m`` [m] of void between them."""
    y0 = layout.front_y_m + layout.stride_m
    y1 = y0 + width_m
    goal = y1 - layout.hind_y_m + 0.5 * layout.stride_m + _edge_margin_m()
    half = layout.column_x_m + 0.4
    boxes = [
        _platform(layout.hind_y_m - 1.0, y0, half),
        _platform(y1, goal + layout.front_y_m + 1.0, half),
    ]
    return {"floor": None, "boxes": boxes}, goal


def ramp(layout: Layout, angle_deg: float) -> tuple[dict, float]:
    """A plank rolled ``angle_deg`` [deg] up along +y, then a flat box at its top."""
    a, t = math.radians(angle_deg), PLANK_THICKNESS_M
    length = (layout.front_y_m - layout.hind_y_m) + 2.5 * layout.stride_m
    y0 = layout.front_y_m + layout.stride_m
    center = [
        0.0,
        y0 + 0.5 * length * math.cos(a) + 0.5 * t * math.sin(a),
        0.5 * length * math.sin(a) - 0.5 * t * math.cos(a),
    ]
    top_z, y1 = length * math.sin(a), y0 + length * math.cos(a)
    width = 2 * layout.column_x_m + 0.6
    goal = y1 - layout.hind_y_m + 0.5 * layout.stride_m + _edge_margin_m()
    depth = goal + layout.front_y_m + 0.5 - y1
    boxes = [
        {"center": center, "size": [width, length, t], "rpy": [angle_deg, 0.0, 0.0]},
        {"center": [0.0, y1 + 0.5 * depth, 0.5 * top_z], "size": [width, depth, top_z]},
    ]
    return {"floor": 0.0, "boxes": boxes}, goal


@dataclass(frozen=True)
class Obstacle:
    """A scaled scenario: name, unit, first value tried (x h / 0.4 m for lengths)."""

    name: str
    unit: str
    first: float
    scenario: Callable[[Layout, float], tuple[dict, float]]
    scales_with_height: bool


OBSTACLES = {
    "block": Obstacle("block", "m", 0.04, block, True),
    "gap": Obstacle("gap", "m", 0.1, gap, True),
    "ramp": Obstacle("ramp", "deg", 5.0, ramp, False),
}
#: Doublings tried before giving up on finding a value that does not walk.
MAX_DOUBLINGS = 5


@dataclass
class Trial:
    """One value tried: it walks, plans but falls (a defect), or is refused; its reasons."""

    value: float
    planned: bool
    walks: bool
    reasons: list[str]

    def verdict(self) -> str:
        return "walks" if self.walks else "PLANS, DOES NOT WALK" if self.planned else "refused"


def capability(robot, layout: Layout, obstacle: Obstacle, bisections: int, echo) -> tuple:  # noqa: ANN001
    """(largest walked value or None, first value beyond it that does not walk, trials):
    double from ``obstacle.first`` until a value does not walk, then bisect ``bisections``
    times between the last that walked and the first that did not."""
    trials: list[Trial] = []

    def trial(value: float) -> Trial:
        document, goal = obstacle.scenario(layout, value)
        t0 = time.perf_counter()
        planned, walks, _, _, reasons = plan_and_walk(
            robot, np.array([[0.0, goal]]), layout.height_m, document
        )
        done = Trial(value, planned, walks, reasons)
        trials.append(done)
        echo(
            f"  {obstacle.name} {value:.4g} {obstacle.unit}: {done.verdict()} "
            f"({time.perf_counter() - t0:.0f} s)"
        )
        for reason in reasons:
            echo(f"      {reason}")
        return done

    scale = layout.height_m / 0.4 if obstacle.scales_with_height else 1.0
    good, bad, value = None, None, round(obstacle.first * scale, 4)
    for _ in range(MAX_DOUBLINGS):
        if trial(value).walks:
            good, value = value, 2 * value
        else:
            bad = value
            break
    if bad is None:
        return good, None, trials
    low = good if good is not None else 0.0
    for _ in range(bisections):
        middle = round(0.5 * (low + bad), 4)
        if trial(middle).walks:
            low = good = middle
        else:
            bad = middle
    return good, bad, trials


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="+", choices=list(ROBOTS), default=list(ROBOTS))
    parser.add_argument("--obstacles", nargs="+", choices=list(OBSTACLES), default=list(OBSTACLES))
    parser.add_argument("--bisect", type=int, default=2, help="bisections after the scan")
    args = parser.parse_args(argv)
    from silo4kin import load_robot

    echo = lambda s: print(s, flush=True)  # noqa: E731
    rows, beyond = [], []
    for label in args.robots:
        robot = load_robot(ROBOTS[label])
        layout = layout_for(robot, HEIGHTS_M[label])
        echo(f"{label} h={layout.height_m} m (stride {layout.stride_m:.3f} m)")
        cells = []
        for name in args.obstacles:
            obstacle = OBSTACLES[name]
            good, bad, trials = capability(robot, layout, obstacle, args.bisect, echo)
            walked = "none" if good is None else f"{good:.4g} {obstacle.unit}"
            first_bad = next((t for t in trials if t.value == bad), None)
            if first_bad is None:
                cells.append(f"{walked} (all tried walk)")
                continue
            cells.append(f"{walked} ({bad:.4g}: {first_bad.verdict()})")
            why = first_bad.reasons[0] if first_bad.reasons else ""
            named = "names the terrain" if "terrain file" in why else "DOES NOT NAME THE TERRAIN"
            if first_bad.planned:
                named = "DEFECT: plans a walk that fails"
            beyond.append(
                f"{label} {name} {bad:.4g} {obstacle.unit}: {first_bad.verdict()}, {named}: {why}"
            )
        rows.append(f"| {label} | {layout.height_m} | " + " | ".join(cells) + " |")
    print("\n| robot | h [m] | " + " | ".join(f"largest {n}" for n in args.obstacles) + " |")
    print("|---|---|" + "---|" * len(args.obstacles))
    print("\n".join(rows))
    print("\nBeyond each capability:")
    print("\n".join(beyond))
    return 0


if __name__ == "__main__":
    sys.exit(main())
