"""Benchmark: plan_path's wall time here against another git revision, in one run.

    python benchmarks/bench_against.py --against 77189d6           # a few thesis cases
    python benchmarks/bench_against.py --against main --repeats 5

Each case is planned in a fresh interpreter of this checkout and of REV (a temporary git
worktree, put first on PYTHONPATH), alternately, so both see the same machine load; each
interpreter warms up once and reports the median of its timed plans. Each timed plan's
waypoints are shifted by a few mm from the others' (the same shifts in both revisions), so a
memo of an earlier plan's first segment (77189d6 kept one in a module global) cannot replay
what a user's single plan would walk. Prints per case the
median wall time of both and their ratio (this / REV): the shared machine's speed drifts
10-30 % within an hour, so only the ratio in one run means something. Not a test.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: (path, height [m], preset): the thesis preset's largest case and two default plans.
CASES = (("circle", 0.2, "thesis"), ("straight", 0.4, "default"), ("circle", 0.6, "default"))

#: Runs in either revision: the planner's entry point moved from planner.path to
#: planner.path.plan_path and the cases from planner.cases to planner.studies.cases.
SNIPPET = r"""
import json, statistics, sys, time
import numpy as np
try:
    from planner.path.plan_path import plan_path
    from planner.studies.cases import path_waypoints
except ImportError:
    from planner.path import plan_path
    from planner.cases import path_waypoints
from silo4kin.robot import load_robot
path, height, preset, repeats = sys.argv[1], float(sys.argv[2]), sys.argv[3], int(sys.argv[4])
robot = load_robot()
waypoints, tolerance = path_waypoints(path)
def run(shift_m):
    return plan_path(robot, waypoints + [0.0, shift_m], height, start_heading=np.pi / 2,
                     workspace=preset, tolerance=tolerance)
plan = run(0.05)
times = []
for k in range(repeats):
    start = time.perf_counter(); plan = run(0.002 * k); times.append(time.perf_counter() - start)
print(json.dumps({"s": statistics.median(times), "samples": len(plan.trajectory)}))
"""


def time_case(tree: Path, case: tuple[str, float, str], repeats: int) -> dict[str, float]:
    """Median plan time [s] and sample count of ``case`` with the code of ``tree``."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    proc = subprocess.run(
        [sys.executable, "-c", SNIPPET, case[0], str(case[1]), case[2], str(repeats)],
        cwd=tree,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    if proc.returncode != 0:
        raise SystemExit(f"{tree}: {proc.stderr.strip().splitlines()[-1:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", required=True, help="git revision to compare with")
    parser.add_argument("--repeats", type=int, default=3, help="timed plans per interpreter")
    parser.add_argument("--rounds", type=int, default=2, help="alternations per case")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        tree = Path(tmp) / "rev"
        subprocess.run(
            ["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(tree), args.against],
            check=True,
        )
        try:
            print(
                f"{'case':28s} {'this [ms]':>10s} {args.against + ' [ms]':>14s} "
                f"{'ratio':>6s} samples"
            )
            for case in CASES:
                ours, theirs = [], []
                for _ in range(max(args.rounds, 1)):
                    theirs.append(time_case(tree, case, args.repeats))
                    ours.append(time_case(ROOT, case, args.repeats))
                a = statistics.median(r["s"] for r in ours)
                b = statistics.median(r["s"] for r in theirs)
                name = f"{case[0]} h {case[1]} {case[2]}"
                print(
                    f"{name:28s} {a * 1e3:10.1f} {b * 1e3:14.1f} {a / b:6.2f} "
                    f"{ours[0]['samples']} / {theirs[0]['samples']}"
                )
        finally:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)], check=False
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
