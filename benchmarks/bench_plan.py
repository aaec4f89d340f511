"""Benchmark: plan + sample the largest thesis case, against a per-sample Pinocchio loop.

    python benchmarks/bench_plan.py                       # circle at h = 0.2 m (issue 3 target)
    python benchmarks/bench_plan.py --path straight --height 0.4 --samples-per-unit 5

Prints the wall time of planning + sampling (planner.path.plan_path: gait steps, stability
checks, closed-form IK, J^-1 p', J^-1 (p'' - J' q') for every sample, vectorised), the
samples per second, and the same sampling done the way one would without the closed form:
a Python loop over samples calling Pinocchio (Newton IK on the foot frames warm-started from
the previous sample, frame Jacobians, J' q' from the classical acceleration), as a ratio.
The loop gets the foot targets, velocities and accelerations in the base frame precomputed,
so it times only the per-sample kinematics. Issue 3 target: < 0.1 s after import, >= 20x.
Not a test: timings depend on the machine; tests only check that it runs.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import numpy as np
import pinocchio as pin

from planner.path.plan_path import plan_path
from planner.studies.cases import path_waypoints
from silo4kin import kinematics
from silo4kin.joint_torques import benchmark_torques
from silo4kin.robot import load_robot

#: Newton IK stops when every foot is within this of its target [m] (1 um, far below any
#: planning tolerance; the closed form is exact to ~1e-15).
NEWTON_TOLERANCE_M = 1e-6
#: Newton iterations allowed per sample (warm start: usually 1-3 are used).
NEWTON_MAX_ITERATIONS = 20


def pinocchio_loop(robot, trajectory) -> tuple[float, np.ndarray, int]:
    """Per-sample Pinocchio sampling; returns (wall time [s], q (N, 12), Newton iterations)."""
    model, data = robot.model, robot.model.createData()
    idx = robot.q_index
    fids = [model.getFrameId(leg.foot_frame) for leg in robot.legs]
    n = len(trajectory)
    # inputs, outside the timed loop: foot position/velocity/acceleration in the base frame
    yaw = trajectory.yaw_base_in_world
    c, s = np.cos(yaw), np.sin(yaw)
    rel = trajectory.position_foot_in_world - trajectory.position_base_in_world[:, None, :]
    p_base = np.stack(
        [
            c[:, None] * rel[..., 0] + s[:, None] * rel[..., 1],
            -s[:, None] * rel[..., 0] + c[:, None] * rel[..., 1],
            rel[..., 2],
        ],
        -1,
    )
    pd_base = np.empty_like(p_base)
    pdd_base = np.empty_like(p_base)
    for k, leg in enumerate(robot.legs):
        q_leg, qd_leg = trajectory.q[:, 3 * k : 3 * k + 3], trajectory.qd[:, 3 * k : 3 * k + 3]
        qdd_leg = trajectory.qdd[:, 3 * k : 3 * k + 3]
        jac = kinematics.jacobian(leg, q_leg)
        pd_base[:, k] = np.einsum("nij,nj->ni", jac, qd_leg)
        pdd_base[:, k] = np.einsum("nij,nj->ni", jac, qdd_leg) + np.einsum(
            "nij,nj->ni", kinematics.jacobian_derivative(leg, q_leg, qd_leg), qd_leg
        )
    q_out = np.empty((n, 12))
    q_pin = robot.to_pinocchio_q(trajectory.q[0])
    zeros = np.zeros(model.nv)
    iterations = 0
    frame = pin.LOCAL_WORLD_ALIGNED
    start = time.perf_counter()
    for i in range(n):
        target = p_base[i].reshape(12)
        for _ in range(NEWTON_MAX_ITERATIONS):  # IK: Newton on the four feet at once
            pin.forwardKinematics(model, data, q_pin)
            pin.updateFramePlacements(model, data)
            error = target - np.concatenate([data.oMf[f].translation for f in fids])
            if np.max(np.abs(error)) < NEWTON_TOLERANCE_M:
                break
            pin.computeJointJacobians(model, data, q_pin)
            jac = np.vstack([pin.getFrameJacobian(model, data, f, frame)[:3] for f in fids])
            q_pin = q_pin + np.linalg.solve(jac[:, idx], error)[np.argsort(idx)]
            iterations += 1
        pin.computeJointJacobians(model, data, q_pin)
        jac = np.vstack([pin.getFrameJacobian(model, data, f, frame)[:3] for f in fids])[:, idx]
        qd = np.linalg.solve(jac, pd_base[i].reshape(12))  # q' = J^-1 p'
        pin.forwardKinematics(model, data, q_pin, robot.to_pinocchio_q(qd), zeros)
        jdqd = np.concatenate(
            [pin.getFrameClassicalAcceleration(model, data, f, frame).linear for f in fids]
        )
        np.linalg.solve(jac, pdd_base[i].reshape(12) - jdqd)  # q'' = J^-1 (p'' - J' q')
        q_out[i] = robot.from_pinocchio_q(q_pin)
    return time.perf_counter() - start, q_out, iterations


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--path", default="circle", choices=("straight", "circle", "circle-reduced")
    )
    parser.add_argument("--height", type=float, default=0.2)
    parser.add_argument("--workspace", default="thesis", choices=("thesis", "default"))
    parser.add_argument("--samples-per-unit", type=int, default=100)
    parser.add_argument("--repeat", type=int, default=5, help="planning runs (median)")
    args = parser.parse_args(argv)

    robot = load_robot()
    waypoints, tolerance = path_waypoints(args.path)

    def run():
        return plan_path(
            robot,
            waypoints,
            args.height,
            start_heading=np.pi / 2,
            workspace=args.workspace,
            tolerance=tolerance,
            samples_per_unit=args.samples_per_unit,
        )

    plan = run()  # warm-up (first-call caches)
    times = []
    for _ in range(max(args.repeat, 1)):
        start = time.perf_counter()
        plan = run()
        times.append(time.perf_counter() - start)
    ours = statistics.median(times)
    n = len(plan.trajectory)
    loop_time, q_loop, iterations = pinocchio_loop(robot, plan.trajectory)
    deviation = float(np.max(np.abs(q_loop - plan.trajectory.q)))
    print(
        f"case: {args.path} at h = {args.height} m, workspace {args.workspace}, "
        f"{args.samples_per_unit} samples/unit -> {n} samples, "
        f"{plan.trajectory.time_units[-1]:.0f} time units, {len(plan.steps)} steps"
    )
    print(
        f"plan + sample (median of {len(times)}): {ours * 1e3:.1f} ms, "
        f"{n / ours:,.0f} samples/s  (target < 100 ms)"
    )
    print(
        f"per-sample Pinocchio loop (IK Newton + J + J'q'): {loop_time * 1e3:.1f} ms, "
        f"{n / loop_time:,.0f} samples/s, {iterations / n:.2f} Newton steps/sample, "
        f"max |q_loop - q| = {deviation:.1e} rad"
    )
    print(f"ratio loop / ours: {loop_time / ours:.1f}x  (target >= 20x)")
    # torques of the same plan (issue 4): batched RNEA + support vs a per-sample rnea loop
    tr = plan.trajectory
    bench = benchmark_torques(robot, tr.q, tr.qd, tr.qdd, tr.contact)
    print(
        f"torques, {n} samples: motion by batched rnea {bench['rnea_batch_s'] * 1e3:.1f} ms, "
        f"per-sample rnea loop {bench['rnea_loop_s'] * 1e3:.1f} ms "
        f"(ratio {bench['loop_over_batch']:.1f}x), vectorised closed form "
        f"{bench['closed_form_s'] * 1e3:.1f} ms; whole joint_torques (reactions + motion + "
        f"support) {bench['joint_torques_s'] * 1e3:.1f} ms"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
