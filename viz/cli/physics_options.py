"""The options of ``silo4 plan`` that bound what a plan asks of the floor and the motors:
friction, the least normal load of a stance foot, torque headroom (docs/physics.md)."""

from __future__ import annotations

import argparse


def add_physics_options(p: argparse.ArgumentParser) -> None:
    """--friction, --min-normal-load and --torque-headroom on parser ``p``."""
    p.add_argument(
        "--friction",
        type=float,
        default=0.5,
        metavar="MU",
        help="friction the plan may ask of the floor: tangential / normal load of every "
        "stance foot <= MU (default 0.5; planner/stability/contact_forces.py)",
    )
    p.add_argument(
        "--min-normal-load",
        type=float,
        default=None,
        metavar="FRACTION",
        help="every stance foot carries >= FRACTION of the weight (e.g. 0.05; off by default)",
    )
    p.add_argument(
        "--torque-headroom",
        type=float,
        default=0.85,  # planner.trajectory.limits.TORQUE_HEADROOM (numpy-free parser)
        metavar="FRACTION",
        help="peak torque of every joint <= FRACTION of its URDF effort limit (default 0.85; "
        "--unit-time auto retimes to keep it)",
    )


def preset_with_contact_rule(args: argparse.Namespace):
    """The preset of ``--workspace`` with ``--friction`` and ``--min-normal-load``."""
    from planner.presets import PRESETS
    from planner.stability.contact_rule import ContactForceRule

    rule = ContactForceRule(args.friction, args.min_normal_load).checked()
    return PRESETS[args.workspace]._replace(contact_forces=rule)
