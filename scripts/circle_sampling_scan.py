"""Print how the `thesis` preset's circle times and distances depend on the circle's sampling.

The thesis gives no sampling of its radius-1 m circle (Tables 6.2, 6.3); this scan is what
docs/thesis-contradictions.md quotes. Run: .venv/bin/python scripts/circle_sampling_scan.py
"""

from __future__ import annotations

import numpy as np

from planner.path.metrics import compute_metrics
from planner.path.plan_path import plan_path
from planner.studies.cases import REDUCED_TOLERANCE_M, THESIS_TABLES, circle_waypoints
from silo4kin.robot import load_robot

#: Time in units and the counted distance do not depend on the sampling in time.
SAMPLES_PER_UNIT = 2
HEIGHTS_M = (0.2, 0.4, 0.6)


def main() -> None:
    robot = load_robot()
    print(
        "count | Table 6.2 time (vs printed) at h = 0.2 / 0.4 / 0.6 | within 3 % | "
        "Table 6.3 distance [m] at h = 0.2 / 0.4 / 0.6"
    )
    for count in range(12, 73):
        waypoints = circle_waypoints(count=count)
        times, fits, dists = [], True, []
        for h in HEIGHTS_M:
            m = compute_metrics(
                plan_path(
                    robot, waypoints, h, workspace="thesis", samples_per_unit=SAMPLES_PER_UNIT
                )
            )
            row = THESIS_TABLES[("circle", h)]
            rel = m["normalized_time"] / row.time_units - 1
            fits &= (
                abs(rel) <= 0.03 and abs(m["normalized_error_m"] - row.normalized_error_m) <= 0.015
            )
            times.append(f"{m['normalized_time']:.0f} ({100 * rel:+.1f} %)")
            reduced = compute_metrics(
                plan_path(
                    robot,
                    waypoints,
                    h,
                    workspace="thesis",
                    tolerance=REDUCED_TOLERANCE_M,
                    samples_per_unit=SAMPLES_PER_UNIT,
                )
            )
            dists.append(reduced["distance_m"])
        print(
            f"{count} | {' / '.join(times)} | {'yes' if fits else 'no'} | "
            f"{' / '.join(f'{d:.2f}' for d in dists)}  (min {np.min(dists):.2f})"
        )


if __name__ == "__main__":
    main()
