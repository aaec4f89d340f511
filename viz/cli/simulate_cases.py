"""``silo4 cases --simulate``: every case replayed in MuJoCo (viz/cli/simulate.py), and the
physics section and verdicts of docs/results.md."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from silo4kin.errors import Silo4Error
from viz.cli.simulate import simulate_into


def simulate_cases(
    robot: Any, results: list, out: Path, args: argparse.Namespace
) -> tuple[str, dict[str, str]]:
    """``silo4 cases --simulate``: replay every case, write its sim files into its folder,
    and return the results page's physics section (markdown) and each case's verdict
    (case name -> :func:`physics_verdict`) for the per-case tables.

    Feed-forward torques carry the whole robot (``load="total"``) where the stance feet can
    carry it; a plan whose whole-body CoM leaves the support polygon cannot get them (the
    planner's torque model refuses), so it is replayed with body-only torques, as the thesis
    computed them, and the row says so.
    """
    import time

    from planner.trajectory.torques import add_torques
    from silo4sim.thresholds import Thresholds
    from viz.cli.progress import track

    rows = []
    for result in track(results, "physics"):  # ~10 s a case: a bar at a terminal
        case, traj = result.case, result.plan.trajectory
        load = "total"
        try:
            traj = add_torques(robot, traj, load="total")
        except Silo4Error:
            load = "body"
            traj = add_torques(robot, traj, load="body")
        t0 = time.perf_counter()
        doc = simulate_into(
            out / case.name,
            robot,
            traj,
            Thresholds(),
            html=args.html,
            plots=args.plots,
            title=f"{robot.name}: {case.name}",
        )
        wall = time.perf_counter() - t0
        print(
            f"{case.name:28s} physics ({load} load): "
            + ("walks" if doc["walks"] else "does not walk: " + "; ".join(doc["reasons"]))
            + f"  ({wall:.1f} s)"
        )
        rows.append((case, load, doc, wall))
    return physics_section(rows), {
        case.name: physics_verdict(
            "walks" if doc.get("walks") else "does not walk",
            doc.get("fell"),
            calibrated="drift_max_m" in doc,
        )
        for case, _, doc, _ in rows
    }


def physics_verdict(verdict: str, fell: bool | None, *, calibrated: bool = True) -> str:
    """One word for a case table: walks, falls, does not walk, or calibration failed."""
    if not calibrated:
        return "calibration failed"
    if verdict == "walks":
        return "walks"
    return "falls" if fell else "does not walk"


def physics_section(rows: list) -> str:
    """Markdown table: one row per case (case, load, verdict, drift, slip, ...)."""
    lines = [
        "",
        "## Physics replay (MuJoCo)",
        "",
        "Each plan replayed in MuJoCo (`silo4 cases --simulate`; model, calibration and "
        "criteria: [physics.md](physics.md)): free-floating robot, 1 ms steps, joint servos "
        "with the plan's torques as feed-forward. *walks*: no fall, CoG drift <= 20 mm, "
        "stance-foot slip <= 5 mm, yaw error <= 5 deg, no ground contact but the feet. "
        "Load: the torques' load, `total` (body and legs) where the stance feet can carry "
        "it, else `body` (the thesis's model; the whole-body CoM leaves the support polygon "
        "somewhere in the plan).",
        "",
        "| case | preset | h [m] | load | physics | falls | drift max / final [mm] | "
        "slip max [mm] | yaw max [deg] | tilt max [deg] | non-foot contacts | "
        "peak torque sim / plan [N m] |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for case, load, doc, _wall in rows:
        verdict = "**walks**" if doc["walks"] else "does not walk"
        if "drift_max_m" not in doc:  # calibration failed
            lines.append(
                f"| {case.path} | {case.workspace} | {case.height_m:g} | {load} | "
                f"calibration failed | | | | | | | |"
            )
            continue
        contacts = ", ".join(sorted(doc["non_foot_contacts"])) or "none"
        fell = f"1 (t = {doc['fell_at_s']:.0f} s)" if doc["fell"] else "0"
        lines.append(
            f"| {case.path} | {case.workspace} | {case.height_m:g} | {load} | {verdict} | "
            f"{fell} | {1e3 * doc['drift_max_m']:.1f} / {1e3 * doc['drift_final_m']:.1f} | "
            f"{1e3 * doc['slip_max_m']:.1f} | {doc['yaw_error_max_deg']:.1f} | "
            f"{doc['max_tilt_deg']:.1f} | {contacts} | "
            f"{max(doc['torque_peak_sim_nm'].values()):.1f} / "
            f"{max(doc['torque_peak_plan_nm'].values()):.1f} |"
        )
    return "\n".join(lines) + "\n"
