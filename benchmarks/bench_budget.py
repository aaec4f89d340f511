"""Benchmark: the work budget (planner/request.py) — the largest plan it accepts, its wall time
and peak memory through the whole ``silo4 plan`` run, and how fast a far waypoint is refused.

    python benchmarks/bench_budget.py                  # straight path at h = 0.4 m, SILO4
    python benchmarks/bench_budget.py --html --plots   # with the animation and the plots too

Each run is a fresh ``silo4 plan`` subprocess in a temporary folder; peak memory is its
maximum resident set size (getrusage of the child). The path is straight ahead along +y, as
long as the budget allows at --samples-per-unit (found from the same estimate the planner
uses). Prints one line per run. Not a test: timings depend on the machine.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from planner.request import MAX_TOTAL_SAMPLES, estimate_time_units
from planner.workspace.layout import workspace_for
from silo4kin.robot import load_robot

ROOT = Path(__file__).resolve().parent.parent


def longest_accepted_y(height: float, samples_per_unit: int, fraction: float) -> float:
    """Length [m] of the straight path whose estimate is ``fraction`` of the budget."""
    ws = workspace_for(load_robot(), height, "default")
    units_per_m = estimate_time_units([[0.0, 1.0]], math.pi / 2, ws.stride_m, ws.psi_max_rad)
    return fraction * (MAX_TOTAL_SAMPLES - 1) / samples_per_unit / units_per_m


def run(argv: list[str]) -> tuple[int, float, float, str]:
    """Run silo4 in a temporary folder: exit code, wall time [s], peak RSS [MB], last line."""
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, PYTHONPATH=str(ROOT))
        before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        t0 = time.perf_counter()
        proc = subprocess.run(
            [sys.executable, "-m", "viz", *argv], cwd=tmp, env=env, capture_output=True, text=True
        )
        wall = time.perf_counter() - t0
        peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    lines = (proc.stdout + proc.stderr).strip().splitlines()
    peak_mb = max(peak, before) / 1024.0  # ru_maxrss is in kB on Linux; the max over children
    return proc.returncode, wall, peak_mb, lines[-1] if lines else ""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--height", type=float, default=0.4)
    parser.add_argument("--samples-per-unit", type=int, default=100)
    parser.add_argument("--html", action="store_true")
    parser.add_argument("--plots", action="store_true")
    parser.add_argument(
        "--fractions",
        default="0.25,0.5,0.99",
        help="path lengths as fractions of the budget, run smallest first",
    )
    args = parser.parse_args()
    spu = args.samples_per_unit
    visual = ["--html" if args.html else "--no-html", "--plots" if args.plots else "--no-plots"]
    print(
        f"budget {MAX_TOTAL_SAMPLES:,} samples; h = {args.height} m; {spu} samples/unit; "
        f"{' '.join(visual)}"
    )
    code, wall, peak, last = run(
        ["plan", "--waypoints", "1e9,0", "--height", str(args.height), "--out", "far"]
    )
    print(
        f"far waypoint 1e9,0: exit {code} in {wall:.2f} s (incl. ~1 s start-up), "
        f"peak {peak:.0f} MB: {last}"
    )
    for fraction in (float(f) for f in args.fractions.split(",")):
        y = longest_accepted_y(args.height, spu, fraction)
        code, wall, peak, last = run(
            [
                "plan",
                "--waypoints",
                f"0,{y:.3f}",
                "--height",
                str(args.height),
                "--samples-per-unit",
                str(spu),
                "--out",
                "run",
                *visual,
            ]
        )
        print(
            f"straight {y:7.2f} m ({fraction:.0%} of the budget): exit {code}, "
            f"{wall:6.1f} s, peak {peak:6.0f} MB"
        )
    y = longest_accepted_y(args.height, spu, 1.02)
    code, wall, peak, last = run(
        [
            "plan",
            "--waypoints",
            f"0,{y:.3f}",
            "--height",
            str(args.height),
            "--samples-per-unit",
            str(spu),
            "--out",
            "run",
        ]
    )
    print(f"straight {y:7.2f} m (102% of the budget): exit {code} in {wall:.2f} s: {last}")


if __name__ == "__main__":
    main()
