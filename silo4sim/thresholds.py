"""When a replay counts as walking: the thresholds (no numpy, no mujoco, so the
CLI can show their defaults in ``--help`` without importing either)."""

from __future__ import annotations

from dataclasses import dataclass

from .threshold_defaults import (
    DEFAULT_DRIFT_M,
    DEFAULT_SLIP_M,
    DEFAULT_TILT_DEG,
    DEFAULT_YAW_DEG,
)


@dataclass(frozen=True)
class Thresholds:
    """When a replay counts as walking (defaults: silo4sim/threshold_defaults.py), and the
    contact criteria.

    Attributes:
        drift_m: largest allowed CoG position error vs the plan [m].
        slip_m: largest allowed slip of a stance foot, its sphere centre against the planned
            one (silo4sim.metrics) [m].
        yaw_deg: largest allowed heading error [deg].
        tilt_deg: largest allowed body tilt (roll/pitch combined) [deg]; beyond it: a fall.
        fall_height_ratio: a fall when the CoG sinks below this fraction of its planned
            height [-].
        contact_force_n: a foot or body touches the floor above this normal force [N].
        transition_s: time after a touch-down and before a lift-off in which a foot's
            contact is not judged [s] (a servoed foot lands within a few ms of the plan).
        standing_drift_m: the calibration's bound on the CoG motion while standing [m].
        scuff_height_m: a swing foot touching the floor scuffs only where the plan has it
            this high [m] (near lift-off and touch-down, and in the first sample's swing
            leg still on the ground, a touch is planned).
    """

    drift_m: float = DEFAULT_DRIFT_M
    slip_m: float = DEFAULT_SLIP_M
    yaw_deg: float = DEFAULT_YAW_DEG
    tilt_deg: float = DEFAULT_TILT_DEG
    fall_height_ratio: float = 0.5
    contact_force_n: float = 1.0
    transition_s: float = 0.05
    standing_drift_m: float = 0.001
    scuff_height_m: float = 0.005
