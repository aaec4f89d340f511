"""Print docs/robots.md's planning table: per robot, leg family, mass, feasible height range,
stride at mid-height and the thesis straight path (planner/cases.py, unscaled: 4.41 m from
the origin) planned at mid-height: duration [time units] and speed [m per unit].

    .venv/bin/python scripts/robots_table.py [NAME ...]
"""

from __future__ import annotations

import sys
import time

import numpy as np

from planner.cases import START_HEADING_RAD, STRAIGHT_WAYPOINTS_IN_WORLD
from planner.path import plan_path
from silo4kin import load_robot
from silo4kin.errors import Silo4Error
from viz.cli_robots import robot_names, robot_row


def main(names: list[str]) -> None:
    wp = STRAIGHT_WAYPOINTS_IN_WORLD
    length = float(np.sum(np.linalg.norm(np.diff(np.vstack([[0.0, 0.0], wp]), axis=0), axis=1)))
    print(f"straight path {length:.3f} m; columns: robot family mass_kg range_m stride_m "
          "height_m duration_units speed_m_per_unit seconds")
    for name in names or robot_names():
        t0 = time.perf_counter()
        row = robot_row(name)
        if row["range_m"] is None:
            print(name, row["family"], f"{row['mass_kg']:.2f}", "none", flush=True)
            continue
        lo, hi = row["range_m"]
        h = round(0.5 * (lo + hi), 4)
        robot = load_robot(None if name == "silo4" else name)
        try:
            plan = plan_path(robot, wp, h, start_heading=START_HEADING_RAD,
                             samples_per_unit=10)
        except Silo4Error as exc:
            print(name, row["family"], f"{row['mass_kg']:.2f}", f"{lo:.3f}-{hi:.3f}",
                  f"{row['stride_m']:.3f}", f"{h:.3f}", "refused:", exc, flush=True)
            continue
        units = float(plan.trajectory.time_units[-1])
        print(name, row["family"], f"{row['mass_kg']:.2f}", f"{lo:.3f}-{hi:.3f}",
              f"{row['stride_m']:.3f}", f"{h:.3f}", f"{units:.0f}", f"{length / units:.4f}",
              f"{time.perf_counter() - t0:.0f}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
