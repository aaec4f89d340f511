"""The options of ``silo4 plan`` that bound what a plan asks of the floor and the motors:
friction, the least normal load of a stance foot, torque headroom, ground clearance
(docs/physics.md)."""

from __future__ import annotations

import argparse


def add_physics_options(p: argparse.ArgumentParser) -> None:
    """--friction, --min-normal-load, --torque-headroom and --ground-clearance on ``p``."""
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
        default=None,
        metavar="FRACTION",
        help="peak torque of every joint <= FRACTION of its URDF effort limit (default: the "
        "preset's, 0.85; thesis 1.0; --unit-time auto retimes to keep it)",
    )
    p.add_argument(
        "--ground-clearance",
        type=float,
        default=None,
        metavar="M",
        help="the margin M every collision shape of the robot but its feet keeps above the "
        "ground (the URDF's shapes, every sample): --height auto keeps it, a plan at a given "
        "height under it gets a warning, one touching the ground is refused (default: the "
        "preset's, 0.01)",
    )


def preset_with_contact_rule(args: argparse.Namespace):
    """The preset of ``--workspace`` with ``--friction``, ``--min-normal-load`` and, where
    given, ``--torque-headroom`` and ``--ground-clearance``."""
    from planner.errors import PlannerInputError
    from planner.presets import PRESETS

    preset = PRESETS[args.workspace]
    rule = preset.contact_forces._replace(
        friction=args.friction, min_normal_fraction=args.min_normal_load
    ).checked()
    preset = preset._replace(contact_forces=rule)
    headroom = getattr(args, "torque_headroom", None)
    if headroom is not None:
        if not 0.0 < headroom <= 1.0:
            raise PlannerInputError(f"--torque-headroom {headroom!r}: give a fraction in (0, 1]")
        preset = preset._replace(torque_headroom=float(headroom))
    clearance = getattr(args, "ground_clearance", None)
    if clearance is not None:
        if not 0.0 <= clearance < float("inf"):
            raise PlannerInputError(f"--ground-clearance {clearance!r}: give a length >= 0 [m]")
        preset = preset._replace(ground_clearance_m=float(clearance))
    return preset
