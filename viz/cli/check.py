"""``silo4 check``: closed-form kinematics and dynamics against Pinocchio for a robot."""

from __future__ import annotations

import argparse

from silo4kin.errors import Silo4Error
from viz.cli.common import EXIT_CHECK_FAILED, EXIT_OK, add_robot_arguments, load_robot_from_args

#: Most random configurations per leg: the check holds ~5 kB per sample (100 000 ~ 0.5 GB).
MAX_CHECK_SAMPLES = 100_000
#: numpy's seed range (SeedSequence takes non-negative integers; we keep 32 bits).
MAX_SEED = 2**32 - 1


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
    p.add_argument(
        "--samples",
        type=int,
        default=1000,
        help=f"random configurations per leg, 1-{MAX_CHECK_SAMPLES} (default 1000)",
    )
    p.add_argument("--seed", type=int, default=0, help=f"random seed, 0-{MAX_SEED} (default 0)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Load the robot, cross-check, print the table; 0 if all within tolerance, else 1."""
    if not 1 <= args.samples <= MAX_CHECK_SAMPLES:
        raise Silo4Error(
            f"--samples {args.samples}: must be an integer in [1, {MAX_CHECK_SAMPLES}]"
        )
    if not 0 <= args.seed <= MAX_SEED:
        raise Silo4Error(f"--seed {args.seed}: must be an integer in [0, {MAX_SEED}]")
    robot = load_robot_from_args(args)
    from silo4kin.check import cross_check, format_report
    from silo4kin.leg_family import INSECT, family_of

    rows = cross_check(robot, n=args.samples, seed=args.seed)
    source = robot.source.name if robot.source else robot.name
    print(
        f"robot {robot.name} ({source}): {len(robot.legs)} {robot.family} legs, total mass "
        f"{robot.total_mass:.2f} kg, {args.samples} random configurations per leg"
    )
    print(format_report(rows))
    if family_of(robot.legs[0]) is not INSECT:
        print(
            f"{robot.family} legs: kinematics only (silo4kin/mammal.py); their dynamics has "
            "no closed form here, Pinocchio's RNEA is the model"
        )
    failed = [r for r in rows if not r.ok]
    if failed:
        print(f"FAILED: {len(failed)} of {len(rows)} checks outside tolerance")
        return EXIT_CHECK_FAILED
    print(f"all {len(rows)} checks inside tolerance")
    return EXIT_OK
