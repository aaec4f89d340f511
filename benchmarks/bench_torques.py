"""Time the joint-torque computation (App. A.2) for a plan-sized batch: batched RNEA vs a
per-sample rnea loop vs the vectorised closed form, and the whole motion + support pipeline.

    /work/venv-dev/bin/python benchmarks/bench_torques.py [--samples 42000] [--repeats 3]

The samples are synthetic (a smooth joint trajectory around a stance with a creeping-gait
contact pattern: each leg lifted for 1 of every 8 time units); the timing does not depend on
the values. The planner benchmark calls silo4kin.joint_torques.benchmark_torques on a real plan.
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from silo4kin import kinematics as K
from silo4kin import load_robot
from silo4kin.joint_torques import benchmark_torques


def synthetic_plan(robot, n: int, seed: int = 0) -> tuple[np.ndarray, ...]:
    """q, qd, qdd (n, 12) and contact (n, 4): feet near mid-stroke at h = 0.4 m, small sines."""
    rng = np.random.default_rng(seed)
    q0 = np.concatenate(
        [
            K.inverse_kinematics(
                leg,
                np.array(
                    [
                        leg.position_hip_in_base[0] + 0.25 * np.cos(leg.theta_b),
                        leg.position_hip_in_base[1] + 0.25 * np.sin(leg.theta_b),
                        -0.4,
                    ]
                ),
            )
            for leg in robot.legs
        ]
    )
    t = np.linspace(0.0, n / 100.0, n)[:, None]  # 100 samples per time unit
    a, w, phi = rng.uniform(0.02, 0.1, 12), rng.uniform(0.5, 2.0, 12), rng.uniform(0, 6, 12)
    q = q0 + a * np.sin(w * t + phi)
    qd = a * w * np.cos(w * t + phi)
    qdd = -a * w**2 * np.sin(w * t + phi)
    unit = (t[:, 0] % 8.0).astype(int)  # creeping cycle 4-2-B-3-1-B: 8 units
    contact = np.ones((n, 4), bool)
    for leg, u in zip((3, 1, 2, 0), (0, 1, 4, 5)):  # RH, RF, LH, LF lifted one unit each
        contact[unit == u, leg] = False
    return q, qd, qdd, contact


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=42000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    robot = load_robot()
    q, qd, qdd, contact = synthetic_plan(robot, args.samples)
    result = benchmark_torques(robot, q, qd, qdd, contact, repeats=args.repeats)
    print(json.dumps(result, indent=2))
    n = result["samples"]
    print(
        f"{int(n)} samples: batched rnea {result['rnea_batch_s'] * 1e3:.1f} ms "
        f"({result['rnea_batch_s'] / n * 1e9:.0f} ns/sample), per-sample loop "
        f"{result['rnea_loop_s'] * 1e3:.1f} ms (x{result['loop_over_batch']:.2f}), closed "
        f"form {result['closed_form_s'] * 1e3:.1f} ms, full joint_torques "
        f"{result['joint_torques_s'] * 1e3:.1f} ms"
    )


if __name__ == "__main__":
    main()
