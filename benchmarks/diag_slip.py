"""Diagnose one corpus case's stance slip in physics: which foot slips, when, and what the
plan asks of it then (normal load and friction demand of planner/stability/contact_forces.py,
the sim's measured foot force, servos at the effort limit).

    .venv/bin/python benchmarks/diag_slip.py INDEX [--cases 30] [--seed 20261202]

Plans case INDEX of benchmarks/bench_corpus.py alone (its height from its robot's range;
the other robots' ranges do not change the random draws), replays it with the corpus's
PHYSICS settings and prints, per leg, its worst stance: slip [mm], when it starts, the
plan's smallest normal load in that stance (fraction of the weight) and the largest friction
demand, the sim's smallest measured normal force. A figure, not a test.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_corpus as bc  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    from planner.outputs.pipeline import RunRequest, plan_run
    from planner.stability.contact_forces import ContactForceCheck
    from planner.stability.contact_rule import ContactForceRule
    from planner.trajectory.torques import add_torques, transfer_time_s
    from planner.workspace.heights import feasible_height_range
    from silo4kin import load_robot
    from silo4sim.metrics import _judged, stance_slip
    from silo4sim.run import simulate

    parser = argparse.ArgumentParser()
    parser.add_argument("index", type=int)
    parser.add_argument("--cases", type=int, default=30)
    parser.add_argument("--seed", type=int, default=bc.DEFAULT_SEED)
    args = parser.parse_args(argv)
    labels = list(bc.ROBOTS)
    label = labels[args.index % len(labels)]
    robot = load_robot(bc.ROBOTS[label])
    lo_hi = feasible_height_range(robot, "default", True)
    case = bc.corpus_cases(args.cases, args.seed, labels, dict.fromkeys(labels, lo_hi))[args.index]
    print(case.describe())
    plan = plan_run(
        robot,
        case.waypoints_in_world,
        case.height_m,
        RunRequest(torque_headroom=1.0),
        start_heading=case.start_heading,
    ).plan
    traj = add_torques(robot, plan.trajectory, load="total")
    from planner.model import planning_model

    model = planning_model(robot)
    # the loads the torques were computed with (the whole robot, passed on over the
    # load transfer time at contact changes: silo4kin/load_transfer.py)
    check = ContactForceCheck(
        ContactForceRule(), model, 9.80665, transfer_s=transfer_time_s("total")
    )
    forces = check.forces(traj)
    share = forces.normal_n / forces.weight_n
    demand = forces.friction_demand
    change = (traj.contact[1:] != traj.contact[:-1]).any(axis=1)
    load_step = np.abs(np.diff(share, axis=0)).max(axis=1)
    tau_step = np.abs(np.diff(np.asarray(traj.tau), axis=0)).max(axis=1)
    print(
        f"planned contact at the start {traj.contact[0]}, loads {np.round(share[0], 3)} W; "
        f"largest step per sample at a contact change: load {load_step[change].max():.3f} W, "
        f"torque {tau_step[change].max():.2f} N m; elsewhere {load_step[~change].max():.3f} W, "
        f"{tau_step[~change].max():.2f} N m; stance samples under 5 % W "
        f"{100 * (share[traj.contact] < 0.05).mean():.1f} %, "
        f"least {share[traj.contact].min():.4f} W"
    )
    result = simulate(robot, traj, settings=bc.physics_settings())
    doc = result.metrics
    print("reasons:", doc["reasons"])
    print("calibration:", doc.get("calibration"))
    rec = result.record
    if rec is None:
        print("plan start: normal load share per foot", np.round(share[0], 4))
        return 0
    sm = result.sim_model
    n, dt = rec.steps_run, sm.settings.timestep_s
    margin = int(round(0.05 / dt))
    ref = rec.reference
    feet = rec.get("foot_position", sm).reshape(n, 4, 3)
    f_sim = rec.get("foot_force", sm)
    t_plan = traj.t
    print("effort_limit_s:", {k: v for k, v in doc["effort_limit_s"].items() if v})
    planned = ref.position_ball_centre_in_world  # what measure compares (silo4sim.metrics)
    for leg in range(4):
        slip, starts = stance_slip(
            feet[:, leg, :2] - planned[:n, leg, :2], ref.contact[:n, leg], margin
        )
        if not slip.size:
            continue
        k = int(np.argmax(slip))
        _, s0, s1 = _judged(ref.contact[:n, leg], margin)
        a, b = int(s0[k]), int(s1[k])
        # the step where the slip grows fastest
        d = np.linalg.norm(
            feet[a:b, leg, :2] - planned[a:b, leg, :2] - (feet[a, leg, :2] - planned[a, leg, :2]),
            axis=1,
        )
        grow = a + int(np.argmax(np.gradient(d)))
        ta, tb, tg = ref.t[a], ref.t[b - 1], ref.t[grow]
        inside = (t_plan >= ta) & (t_plan <= tb)
        print(
            f"leg {leg}: worst stance slip {1e3 * slip[k]:.2f} mm, stance {ta:.2f}-{tb:.2f} s, "
            f"fastest at {tg:.2f} s; plan min load {share[inside, leg].min():.3f} W, "
            f"load at fastest {np.interp(tg, t_plan, share[:, leg]):.3f} W, "
            f"max demand {demand[inside].max():.3f}; sim min force "
            f"{f_sim[a:b, leg].min():.2f} N (weight {forces.weight_n:.1f} N), "
            f"slip > 1 mm first at "
            f"{ref.t[a + int(np.argmax(d > 1e-3))] if (d > 1e-3).any() else None}"
        )
        # other legs' swing at the fastest instant
        sw = [j for j in range(4) if not ref.contact[grow, j]]
        print(f"    swinging at fastest: {sw}")
        for i in range(a, b, max(1, (b - a) // 12)):
            print(
                f"    t {ref.t[i]:7.2f} s  "
                f"plan load {np.interp(ref.t[i], t_plan, share[:, leg]):.3f} W"
                f"  sim {f_sim[i, leg] / forces.weight_n:.3f} W  slip {1e3 * d[i - a]:.2f} mm"
                f"  swing {[j for j in range(4) if not ref.contact[i, j]]}"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
