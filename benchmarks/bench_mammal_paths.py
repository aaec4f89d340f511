"""The mammals on two named paths at their ``--height auto`` heights, in physics.

    .venv/bin/python benchmarks/bench_mammal_paths.py [--robots go2 solo12 anymal]

Issue 21 asks that go2, solo12 and anymal walk, with their ball feet, the thesis straight
path (0,1) (1,1) (0,2) (0,3) and an L-shaped path at the heights ``--height auto`` picks.
The L path here is (0,1) (0,2) (1,2): a metre ahead, then a metre to the right, a 90 degree
corner. Each robot is planned as ``silo4 plan --height auto`` plans it (the run pipeline,
the default preset: its torque headroom, contact forces and ground clearance), and replayed
as the corpus replays (benchmarks/bench_corpus.py: friction 0.8, the URDF's feet, the sim's
thresholds). Prints, per robot and path, the height chosen, the gait, E_n against the
tolerance, the sim's verdict with drift and slip, and the planning and replay seconds. A
figure, not a test (tests/test_mammal_sim.py walks the straight path at fixed heights).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_corpus as bc  # noqa: E402

PATHS: dict[str, np.ndarray] = {
    "straight": np.array([[0.0, 1.0], [1.0, 1.0], [0.0, 2.0], [0.0, 3.0]]),
    "L": np.array([[0.0, 1.0], [0.0, 2.0], [1.0, 2.0]]),
}
MAMMALS = ("go2", "solo12", "anymal")


def run_one(robot, waypoints: np.ndarray) -> str:  # noqa: ANN001
    """One line: the plan at ``--height auto`` and its replay."""
    from planner.errors import PlanningError
    from planner.outputs.pipeline import RunRequest, plan_run
    from planner.path.metrics import compute_metrics
    from planner.trajectory.torques import add_torques
    from silo4kin.errors import Silo4Error
    from silo4sim.run import simulate

    t0 = time.process_time()
    try:
        plan = plan_run(robot, waypoints, "auto", RunRequest()).plan
    except (PlanningError, Silo4Error) as exc:
        return f"REFUSED ({type(exc).__name__}: {exc})"
    t_plan = time.process_time() - t0
    error = float(compute_metrics(plan)["normalized_error_m"])
    traj = add_torques(robot, plan.trajectory, load="total")
    t0 = time.process_time()
    doc = simulate(robot, traj, settings=bc.physics_settings()).metrics
    t_sim = time.process_time() - t0
    walks = bool(doc["walks"]) and error <= plan.tolerance
    verdict = "walks" if walks else "DOES NOT WALK"
    reasons = "" if walks else " (" + "; ".join(doc["reasons"]) + ")"
    return (
        f"h {plan.height:.4f} m, {plan.gait}, E_n {1e3 * error:.1f}/{1e3 * plan.tolerance:.0f} "
        f"mm, {verdict}: drift {1e3 * doc['drift_max_m']:.1f} mm, "
        f"slip {1e3 * doc['slip_max_m']:.1f} mm"
        f"{reasons}; plan {t_plan:.0f} s, replay {t_sim:.0f} s CPU"
    )


def main(argv: list[str] | None = None) -> int:
    from silo4kin import load_robot

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="+", choices=MAMMALS, default=list(MAMMALS))
    parser.add_argument("--paths", nargs="+", choices=list(PATHS), default=list(PATHS))
    args = parser.parse_args(argv)
    for name in args.robots:
        robot = load_robot(name)
        for label in args.paths:
            print(f"{name:7s} {label:9s} {run_one(robot, PATHS[label])}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
