"""Print docs/robots.md's robot table: per robot, leg family, mass, feasible height range,
stride at mid-height, the thesis straight path (planner/studies/cases.py, unscaled: 4.41 m from the
origin) planned at mid-height (duration [time units], speed [m per unit]) and, with
``--simulate``, the physics verdict of the same path at PHYSICS_HEIGHTS_M (MuJoCo, sim/).

    .venv/bin/python scripts/robots_table.py [--markdown] [--simulate] [NAME ...]

``--markdown`` prints the table as docs/robots.md has it (paste it there); without, one
plain line per robot with the wall time.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from planner.path.plan_path import plan_path
from planner.studies.cases import START_HEADING_RAD, STRAIGHT_WAYPOINTS_IN_WORLD
from silo4kin import load_robot
from silo4kin.errors import Silo4Error
from viz.cli.robots import robot_names, robot_row

#: Heights of the physics replays [m]: go2 0.28, solo12 0.22 and anymal 0.49 as in
#: tests/test_mammal_sim.py (solo12 at 0.22 m, where its hind knees stay >= 54 mm above the
#: ground: at its mid-height 0.176 m they come within 2 cm and the shank strikes); the
#: others at their mid-height to the mm.
PHYSICS_HEIGHTS_M = {
    "go2": 0.28,
    "solo12": 0.22,
    "anymal": 0.49,
    "go1": 0.286,
    "a1": 0.289,
    "b1": 0.614,
    "laikago": 0.368,
    "anymal_c": 0.461,
    "hyq": 0.456,
}


def path_length_m() -> float:
    """Length of the straight path from the origin through its waypoints [m]."""
    wp = np.vstack([[0.0, 0.0], STRAIGHT_WAYPOINTS_IN_WORLD])
    return float(np.sum(np.linalg.norm(np.diff(wp, axis=0), axis=1)))


def planning_cell(name: str, height_m: float) -> str:
    """The straight path at ``height_m``: units and speed, or the refusal."""
    robot = load_robot(None if name == "silo4" else name)
    try:
        plan = plan_path(
            robot,
            STRAIGHT_WAYPOINTS_IN_WORLD,
            height_m,
            start_heading=START_HEADING_RAD,
            samples_per_unit=10,
        )
    except Silo4Error as exc:
        return f"h {height_m:.3f}: **refused**, {exc}"
    units = float(plan.trajectory.time_units[-1])
    return f"h {height_m:.3f}: {units:.0f} units, {path_length_m() / units:.4f} m/unit"


def physics_cell(name: str) -> str:
    """The verdict of the straight path replayed in MuJoCo at PHYSICS_HEIGHTS_M[name]."""
    from planner.trajectory.torques import add_torques
    from silo4sim.run import simulate

    if name not in PHYSICS_HEIGHTS_M:
        return "not run" if name != "silo4" else "walks (docs/results.md)"
    height = PHYSICS_HEIGHTS_M[name]
    robot = load_robot(name)
    plan = plan_path(robot, STRAIGHT_WAYPOINTS_IN_WORLD, height, start_heading=START_HEADING_RAD)
    doc = simulate(robot, add_torques(robot, plan.trajectory, load="total")).metrics
    servo = f"gains x{doc['servo']['scale']:.3f}"
    if "drift_max_m" not in doc:
        return f"h {height:g}: {'; '.join(doc['reasons'])} ({servo})"
    figures = (
        f"drift {1e3 * doc['drift_max_m']:.1f} mm, slip {1e3 * doc['slip_max_m']:.1f} mm, {servo}"
    )
    if doc["walks"]:
        return f"h {height:g}: **walks** ({figures})"
    return f"h {height:g}: does not walk: {'; '.join(doc['reasons'])} ({figures})"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*")
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--simulate", action="store_true")
    args = parser.parse_args(argv)
    if args.markdown:
        print(
            "| robot | family | mass kg | height range m | stride m (mid) | straight path at "
            "mid-height | physics: straight path |"
        )
        print("|---|---|---|---|---|---|---|")
    else:
        print(f"straight path {path_length_m():.3f} m")
    for name in args.names or robot_names():
        t0 = time.perf_counter()
        row = robot_row(name)
        if row["range_m"] is None:
            cells = [name, str(row["family"]), f"{row['mass_kg']:.2f}", "none", "-", "-", "-"]
        else:
            lo, hi = row["range_m"]  # type: ignore[misc]
            cells = [
                name,
                str(row["family"]),
                f"{row['mass_kg']:.2f}",
                f"{lo:.3f}-{hi:.3f}",
                f"{row['stride_m']:.3f}",
                planning_cell(name, round(0.5 * (lo + hi), 4)),
                physics_cell(name) if args.simulate else "not run",
            ]
        if args.markdown:
            print("| " + " | ".join(cells) + " |", flush=True)
        else:
            print(*cells, f"({time.perf_counter() - t0:.0f} s)", flush=True)


if __name__ == "__main__":
    main()
