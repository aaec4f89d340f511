"""Assumed gearing of every joint (docs/torques.md), importable without numpy.

The CLI shows these as option defaults in ``silo4 --help``; keeping them out of
``silo4kin.motors`` keeps that help text free of a numpy import (tests/test_lazy_imports.py).
"""

#: Assumed gear ratio for every joint [dimensionless] (docs/torques.md; thesis gives none).
DEFAULT_GEAR_RATIO = 100.0
#: Assumed gear efficiency for every joint [dimensionless] (docs/torques.md).
DEFAULT_GEAR_EFFICIENCY = 0.7
#: Gearing source of joints sized with the two defaults above (no gear data of the robot's).
ASSUMED_SOURCE = "assumed (SILO4's defaults)"
#: Gearing source of values the caller gave (options, a Gearing of its own).
GIVEN_SOURCE = "given"
