"""Benchmark: sweep throughput on a LocalCluster of 1 and of 2 worker processes.

    python benchmarks/bench_sweep.py                      # 32 configurations, 3 rounds
    python benchmarks/bench_sweep.py --rounds 1 --samples-per-unit 20

The grid: straight and circle, heights 0.2:0.55:0.05, L3 in {0.24, 0.3} (SILO4, default
preset), each configuration planned with its torques (silo4sweep.task.plan_row, one Dask task).
Each cluster is started, warmed up with one pass over the grid (worker start, imports and
robot loading are not throughput), then timed over ``--rounds`` passes, alternating 1 and 2
workers so that load from other processes on the machine hits both alike. Prints the best
and median configurations per second and the speed-up of 2 workers over 1 (issue 15
target on a 2-core machine: >= 1.6x), with the load average seen, and the CPU time the
worker processes used: CPU s per configuration (the same for 1 and 2 workers when the
engine adds no overhead) and cores obtained = worker CPU / wall (on a machine shared with
other work, the speed-up is bounded by the ratio of cores obtained). Not a test: timings
depend on the machine.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

from silo4sweep.engine import dask_client, run_configs
from silo4sweep.grid import design_grid, parse_values
from silo4sweep.task import OK, SweepSettings


def timed_pass(client, configs, settings) -> tuple[float, float]:  # noqa: ANN001
    """Wall time [s] of one pass over the grid and the CPU time [s] its worker processes
    used meanwhile (time.process_time on each worker); every row must be planned."""
    cpu0 = client.run(time.process_time)
    t0 = time.perf_counter()
    statuses = [row["status"] for _, row in run_configs(client, configs, settings)]
    wall = time.perf_counter() - t0
    cpu1 = client.run(time.process_time)
    if statuses.count(OK) != len(configs):
        raise SystemExit(f"benchmark grid has unplanned rows: {statuses}")
    return wall, sum(cpu1[w] - cpu0[w] for w in cpu1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--samples-per-unit", type=int, default=100)
    args = parser.parse_args()
    configs = design_grid(
        ["straight", "circle"], parse_values("0.2:0.55:0.05", "h"), {"L3": [0.24, 0.3]}, ["default"]
    )
    settings = SweepSettings(samples_per_unit=args.samples_per_unit)
    print(
        f"{len(configs)} configurations, {args.samples_per_unit} samples per unit, "
        f"{os.cpu_count()} cores, load average before {os.getloadavg()[0]:.2f}"
    )
    walls: dict[int, list[float]] = {1: [], 2: []}
    cpus: dict[int, list[float]] = {1: [], 2: []}
    with dask_client(workers=1) as one, dask_client(workers=2) as two:
        clients = {1: one, 2: two}
        for client in clients.values():
            timed_pass(client, configs, settings)  # warm-up: imports, robots, caches
        for r in range(args.rounds):
            for n, client in clients.items():
                wall, cpu = timed_pass(client, configs, settings)
                walls[n].append(wall)
                cpus[n].append(cpu)
                print(
                    f"  round {r + 1}: {n} worker(s) {wall:6.2f} s "
                    f"({len(configs) / wall:5.2f} configurations/s), worker CPU {cpu:6.2f} s "
                    f"= {cpu / wall:.2f} cores obtained, load {os.getloadavg()[0]:.2f}"
                )
    for n in (1, 2):
        print(
            f"{n} worker(s): best {len(configs) / min(walls[n]):.2f}, median "
            f"{len(configs) / statistics.median(walls[n]):.2f} configurations/s; "
            f"{statistics.median(cpus[n]) / len(configs):.3f} CPU s per configuration"
        )
    print(
        f"speed-up of 2 workers over 1: best {min(walls[1]) / min(walls[2]):.2f}x, median "
        f"{statistics.median(walls[1]) / statistics.median(walls[2]):.2f}x (target >= 1.6x)"
    )


if __name__ == "__main__":
    main()
