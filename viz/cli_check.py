"""``silo4 check``: closed-form kinematics and dynamics against Pinocchio for a robot."""

from __future__ import annotations

import argparse

from .cli import EXIT_CHECK_FAILED, EXIT_OK, add_robot_arguments, load_robot_from_args


def add_parser(sub: argparse._SubParsersAction) -> None:
    """Register ``check``."""
    p = sub.add_parser(
        "check",
        help="closed form (thesis Ch. 3, App. A) vs Pinocchio for a robot",
        description="Compare the closed-form FK, Jacobian, dJ*qd, IK, M, C*qd, G and inverse "
                    "dynamics against Pinocchio on random configurations inside the joint "
                    "limits. Exit 0 when every deviation is inside its tolerance, 1 otherwise.",
        epilog="example: silo4 check --robot tests/robots/mantis.urdf --samples 2000",
    )
    add_robot_arguments(p)
    p.add_argument("--samples", type=int, default=1000,
                   help="random configurations per leg (default 1000)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Load the robot, cross-check, print the table; 0 if all within tolerance, else 1."""
    from silo4kin.errors import Silo4Error

    if args.samples < 1:
        raise Silo4Error(f"--samples {args.samples}: must be a positive integer")
    robot = load_robot_from_args(args)
    from silo4kin.check import cross_check, format_report

    rows = cross_check(robot, n=args.samples, seed=args.seed)
    source = robot.source.name if robot.source else robot.name
    print(f"robot {robot.name} ({source}): {len(robot.legs)} {robot.family} legs, total mass "
          f"{robot.total_mass:.2f} kg, {args.samples} random configurations per leg")
    print(format_report(rows))
    if robot.family != "insect":
        print(f"{robot.family} legs: kinematics only (silo4kin/mammal.py); their dynamics has "
              "no closed form here, Pinocchio's RNEA is the model")
    failed = [r for r in rows if not r.ok]
    if failed:
        print(f"FAILED: {len(failed)} of {len(rows)} checks outside tolerance")
        return EXIT_CHECK_FAILED
    print(f"all {len(rows)} checks inside tolerance")
    return EXIT_OK
