"""The defaults of the thresholds ``silo4 simulate --help`` shows, importable without
dataclasses (silo4sim/thresholds.py's Thresholds uses them as its field defaults:
``silo4 --help`` stays within 3x of a bare Python start, as silo4kin/motor_defaults.py)."""

#: Largest allowed CoG position error vs the plan [m].
DEFAULT_DRIFT_M = 0.020
#: Largest allowed slip of a stance foot, its sphere centre against the planned one [m].
DEFAULT_SLIP_M = 0.005
#: Largest allowed heading error [deg].
DEFAULT_YAW_DEG = 5.0
#: Largest allowed body tilt (roll/pitch combined) [deg]; beyond it: a fall.
DEFAULT_TILT_DEG = 20.0
