"""Time the physics replay of a ~150-unit plan (issue 10 target: <= 20 s on this 2-core machine).

    .venv/bin/python benchmarks/bench_sim.py [--repeats 3] [--height 0.4]

Plans the thesis straight path (default preset, 144 time units at h = 0.4 m, 1 s per unit,
full-load torques), then times each stage of ``silo4sim.run.simulate``: building the MuJoCo model,
the 3 s standing calibration, the replay (1 ms steps, mujoco.rollout) and the measures.
Prints the median of the repeats and the real-time factor; a figure, not a test.
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from planner.path.plan_path import plan_path
from planner.trajectory.torques import add_torques
from silo4kin import load_robot
from silo4sim.metrics import measure, measure_standing
from silo4sim.model import build_sim_model
from silo4sim.replay import replay, stand_still
from silo4sim.run import CALIBRATION_S


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--height", type=float, default=0.4)
    args = parser.parse_args()
    robot = load_robot()
    plan = plan_path(
        robot, np.array([[0, 1], [1, 1], [0, 2], [0, 3]]), args.height, start_heading=math.pi / 2
    )
    traj = add_torques(robot, plan.trajectory, load="total")
    units = float(traj.time_units[-1] - traj.time_units[0])
    times: dict[str, list[float]] = {
        "build": [],
        "calibration": [],
        "replay": [],
        "measure": [],
        "total": [],
    }
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        sm = build_sim_model(robot)
        t1 = time.perf_counter()
        measure_standing(sm, stand_still(sm, traj, CALIBRATION_S))
        t2 = time.perf_counter()
        record = replay(sm, traj)
        t3 = time.perf_counter()
        doc = measure(sm, record)
        t4 = time.perf_counter()
        for key, value in zip(times, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t4 - t0)):
            times[key].append(value)
    median = {k: round(float(np.median(v)), 3) for k, v in times.items()}
    simulated = doc["simulated_s"] + CALIBRATION_S
    print(
        json.dumps(
            {
                "plan_time_units": units,
                "simulated_s": simulated,
                "steps": int(round(simulated / sm.settings.timestep_s)),
                "median_s": median,
                "real_time_factor": round(simulated / median["total"], 1),
                "target_s": 20.0,
                "walks": doc["walks"],
                "drift_max_mm": 1e3 * doc["drift_max_m"],
            },
            indent=2,
        )
    )


if __name__ == "__main__":
    main()
