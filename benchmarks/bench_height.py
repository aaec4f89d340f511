"""Time `--height auto` (planner/path/height.py) on the thesis paths; prints the chosen heights.

    .venv/bin/python benchmarks/bench_height.py [--workspaces thesis,default]

For each thesis path (straight, circle, reduced circle) and preset: the height the search
picks, its time [units] and E_n [m], the Chapter 6 heights' times for comparison, the number
of candidate plans and the wall time of the search. A figure, not a test.
"""

from __future__ import annotations

import argparse
import time

from planner.path.height import SEARCH_SAMPLES_PER_UNIT, best_height
from planner.path.plan_path import plan_path
from planner.studies.cases import START_HEADING_RAD, THESIS_HEIGHTS_M, path_waypoints
from silo4kin.robot import load_robot


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workspaces", default="thesis,default")
    args = parser.parse_args()
    robot = load_robot()
    print(
        "preset  | path           | auto h [m] | time [units] | E_n [m] | "
        "time at h = 0.2 / 0.4 / 0.6 | plans | wall [s]"
    )
    for preset in args.workspaces.split(","):
        for path in ("straight", "circle", "circle-reduced"):
            waypoints, tolerance = path_waypoints(path)
            start = time.perf_counter()
            choice = best_height(
                robot,
                waypoints,
                workspace=preset,
                tolerance=tolerance,
                start_heading=START_HEADING_RAD,
            )
            wall = time.perf_counter() - start
            fixed = [
                plan_path(
                    robot,
                    waypoints,
                    h,
                    workspace=preset,
                    tolerance=tolerance,
                    start_heading=START_HEADING_RAD,
                    samples_per_unit=SEARCH_SAMPLES_PER_UNIT,
                ).trajectory.time_units[-1]
                for h in THESIS_HEIGHTS_M
            ]
            print(
                f"{preset:7s} | {path:14s} | {choice.height_m:10.3f} | "
                f"{choice.time_units:12.0f} | {choice.normalized_error_m:7.3f} | "
                f"{' / '.join(f'{t:.0f}' for t in fixed):27s} | "
                f"{len(choice.evaluated):5d} | {wall:8.1f}"
            )


if __name__ == "__main__":
    main()
