"""``silo4 simulate RUN``: replay a saved plan in MuJoCo and say whether the robot walks it.

Writes RUN/sim.json (every figure), RUN/sim.npz (the simulated trajectory), RUN/model.xml
(the MJCF: ``python -m mujoco.viewer --mjcf RUN/model.xml``), RUN/sim.html (the simulated
robot with the plan as a ghost) and RUN/sim_drift.png, RUN/sim_slip.png. Exit 0 when it
walks, 1 when it does not, 2 on bad input (no trajectory, a URDF MuJoCo refuses, no mujoco).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from silo4kin.errors import Silo4Error
from viz.cli.common import (
    EXIT_CHECK_FAILED,
    EXIT_OK,
    add_robot_arguments,
    load_robot_from_args,
    recorded_robot_args,
)


def add_threshold_arguments(p: argparse.ArgumentParser) -> None:
    """--max-drift, --max-slip, --max-yaw, --max-tilt (defaults read from
    silo4sim/threshold_defaults.py, not silo4sim.thresholds: its dataclass import is ~6 ms
    of --help)."""
    from silo4sim.threshold_defaults import (
        DEFAULT_DRIFT_M,
        DEFAULT_SLIP_M,
        DEFAULT_TILT_DEG,
        DEFAULT_YAW_DEG,
    )

    p.add_argument(
        "--max-drift",
        type=float,
        default=1e3 * DEFAULT_DRIFT_M,
        metavar="MM",
        help=f"largest CoG error vs the plan [mm] (default {1e3 * DEFAULT_DRIFT_M:g})",
    )
    p.add_argument(
        "--max-slip",
        type=float,
        default=1e3 * DEFAULT_SLIP_M,
        metavar="MM",
        help=f"largest stance-foot slip [mm] (default {1e3 * DEFAULT_SLIP_M:g})",
    )
    p.add_argument(
        "--max-yaw",
        type=float,
        default=DEFAULT_YAW_DEG,
        metavar="DEG",
        help=f"largest heading error [deg] (default {DEFAULT_YAW_DEG:g})",
    )
    p.add_argument(
        "--max-tilt",
        type=float,
        default=DEFAULT_TILT_DEG,
        metavar="DEG",
        help=f"tilt that counts as a fall [deg] (default {DEFAULT_TILT_DEG:g})",
    )


def thresholds_from_args(args: argparse.Namespace):  # noqa: ANN201 (Thresholds)
    """Validated thresholds (each must be a positive number)."""
    import math

    from silo4sim.thresholds import Thresholds

    for option, value in (
        ("--max-drift", args.max_drift),
        ("--max-slip", args.max_slip),
        ("--max-yaw", args.max_yaw),
        ("--max-tilt", args.max_tilt),
    ):
        if not (math.isfinite(value) and value > 0):
            raise Silo4Error(f"{option} {value}: must be a positive number")
    return Thresholds(
        drift_m=args.max_drift / 1e3,
        slip_m=args.max_slip / 1e3,
        yaw_deg=args.max_yaw,
        tilt_deg=args.max_tilt,
    )


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``simulate``."""
    p = sub.add_parser(
        "simulate",
        help="replay a saved run in MuJoCo physics: does the robot walk it?",
        description="Build a MuJoCo model from the robot's URDF (free-floating base, floor, "
        "foot spheres, joint servos with the plan's torques as feed-forward), "
        "check that it stands still, replay RUN/trajectory.npz at 1 ms steps and "
        "write sim.json, sim.npz, model.xml, sim.html and drift/slip plots into "
        "RUN. Exit 0 when it walks, 1 when it does not.",
        epilog='example: silo4 plan --waypoints "0,1 1,1 0,2 0,3" --height 0.4 '
        "--load total --out out/straight && silo4 simulate out/straight",
    )
    p.add_argument("run_dir", metavar="RUN", help="a run folder written by silo4 plan")
    add_threshold_arguments(p)
    p.add_argument(
        "--html",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="write sim.html, the simulated robot with the plan as a ghost",
    )
    p.add_argument(
        "--plots",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="write sim_drift.png and sim_slip.png",
    )
    add_robot_arguments(p)
    p.set_defaults(run=run)


def sim_targets(folder: Path, *, html: bool, plots: bool) -> list[Path]:
    """The files :func:`simulate_into` writes into ``folder``."""
    names = [
        "model.xml",
        "sim.npz",
        "sim.json",
        *(["sim.html"] if html else []),
        *(["sim_drift.png", "sim_slip.png"] if plots else []),
    ]
    return [folder / name for name in names]


def simulate_into(
    folder: Path,
    robot: Any,
    trajectory: Any,
    thresholds: Any,
    *,
    html: bool,
    plots: bool,
    title: str,
    inputs: Any = (),
    terrain: Any = None,
) -> dict:
    """Simulate and write the outputs into ``folder``; returns the sim.json document.
    Every output is checked first (planner.outputs.files.check_target: a user's model.xml in the
    folder, or an input, refuses the replay before it starts). ``terrain``: plan.json's
    terrain document (silo4sim/terrain.py), None for the flat floor."""
    from planner.outputs.files import check_target, record_written

    targets = sim_targets(folder, html=html, plots=plots)
    for target in targets:
        check_target(target, inputs=inputs, what="output")
    # recorded before the first is written: a replay stopped half-way (SIGINT) leaves only
    # files silo4 owns, so the next `silo4 plan` into the folder may replace them
    record_written(targets)
    from silo4sim.run import simulate, write_sim_outputs
    from viz.cli.progress import waiting

    with waiting("simulating in MuJoCo"):
        result = simulate(robot, trajectory, thresholds, terrain=terrain)
    write_sim_outputs(folder, result)
    written: list[Path] = []
    if result.record is not None and plots:
        from viz.plots.sim_plots import write_sim_plots

        written += write_sim_plots(folder, result.arrays(), result.metrics)
    if result.record is not None and html:
        from viz.animation.sim_page import write_sim_animation_html

        written.append(
            write_sim_animation_html(
                folder / "sim.html",
                robot,
                trajectory,
                result.arrays(),
                title=f"{title} (physics replay)",
            )
        )
    record_written(written)  # the run folder stays replaceable by a new run
    return result.metrics


def simulate_writers(
    args: argparse.Namespace, trajectory: Any, robot: Any, title: str, documents: list[dict]
) -> list:
    """For ``silo4 plan --simulate``: a writer that simulates into the run's temporary
    folder (so the run appears whole or not at all) and appends sim.json to ``documents``."""
    from planner.terrain.terrain_file import terrain_document
    from silo4sim.thresholds import Thresholds

    def write(folder: Path) -> None:
        documents.append(
            simulate_into(
                folder,
                robot,
                trajectory,
                Thresholds(),
                html=args.html,
                plots=args.plots,
                title=title,
                terrain=terrain_document(getattr(args, "terrain_map", None)),
            )
        )

    return [write]


def run(args: argparse.Namespace) -> int:
    """Simulate RUN; print the one-screen summary; exit 0 walks / 1 does not."""
    from planner.outputs.export import run_inputs
    from planner.outputs.files import check_target
    from silo4sim.run import read_run_trajectory

    thresholds = thresholds_from_args(args)
    run_dir = Path(args.run_dir)
    trajectory = read_run_trajectory(run_dir)
    for target in sim_targets(run_dir, html=args.html, plots=args.plots):  # before the robot
        check_target(target, inputs=run_inputs(run_dir), what="output")
    plan_document = _plan_document(run_dir)
    robot = load_robot_from_args(recorded_robot_args(args, plan_document))
    doc = simulate_into(
        run_dir,
        robot,
        trajectory,
        thresholds,
        html=args.html,
        plots=args.plots,
        title=f"{robot.name}: {run_dir.name}",
        inputs=run_inputs(run_dir),
        terrain=(plan_document.get("inputs") or {}).get("terrain"),  # silo4sim/terrain.py
    )
    from viz.report.page import add_physics_section

    add_physics_section(run_dir)  # report.html shows the verdict and links sim.html
    print(format_sim_summary(doc))
    return EXIT_OK if doc["walks"] else EXIT_CHECK_FAILED


def _plan_document(run_dir: Path) -> dict:
    """RUN/plan.json (where robot_source says which robot planned it), or {} without one."""
    import json

    try:
        document = json.loads((run_dir / "plan.json").read_text())
    except (OSError, ValueError):
        return {}
    return document if isinstance(document, dict) else {}


def format_sim_summary(doc: dict) -> str:
    """The one-screen summary of a sim.json document."""
    lines = []
    cal = doc.get("calibration")
    if cal:
        lines.append(
            f"calibration: standing {cal['seconds']:g} s moved the CoG "
            f"{1e3 * cal['base_drift_m']:.3f} mm, feet {1e3 * cal['foot_slip_m']:.3f} "
            f"mm ({'ok' if cal['ok'] else 'FAILED'})"
        )
    if "drift_max_m" in doc:
        th = doc["thresholds"]
        lines += [
            f"simulated {doc['simulated_s']:.1f} s of a {doc['plan_duration_s']:.1f} s plan "
            f"in {doc['wall_time_s']:.1f} s (MuJoCo, {1e3 * doc['settings']['timestep_s']:g} "
            f"ms steps, feed-forward torques: {'yes' if doc['feedforward'] else 'NO'})",
            f"falls {doc['falls']}, max roll {doc['max_roll_deg']:.2f} deg, pitch "
            f"{doc['max_pitch_deg']:.2f} deg",
            f"CoG error vs plan: max {1e3 * doc['drift_max_m']:.1f} mm, final "
            f"{1e3 * doc['drift_final_m']:.1f} mm (limit {1e3 * th['drift_m']:g}); yaw error "
            f"max {doc['yaw_error_max_deg']:.2f} deg (limit {th['yaw_deg']:g})",
            f"foot slip: max {1e3 * doc['slip_max_m']:.2f} mm over {doc['stances']} stances "
            f"(limit {1e3 * th['slip_m']:g}); stances losing contact "
            f"{doc['stances_missing_contact']}; swing scuffing "
            f"{sum(doc['scuff_s'].values()):.3f} s",
            "non-foot ground contacts: "
            + (
                ", ".join(
                    f"{k} {v['seconds']:.3f} s from t = {v['first_s']:.2f} s"
                    for k, v in doc["non_foot_contacts"].items()
                )
                or "none"
            ),
            f"joint tracking: max {max(doc['joint_tracking_max_deg'].values()):.2f} deg; "
            f"torque peak sim {max(doc['torque_peak_sim_nm'].values()):.1f} N m vs plan "
            f"{max(doc['torque_peak_plan_nm'].values()):.1f} N m; at effort limit "
            f"{sum(doc['effort_limit_s'].values()):.3f} joint-s",
        ]
    verdict = "WALKS" if doc["walks"] else "DOES NOT WALK: " + "; ".join(doc["reasons"])
    lines.append(verdict)
    return "\n".join(lines)
