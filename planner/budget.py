"""The work budget's limits (docs/errors.md "Work budget"), in a module without numpy so the
CLI can check options and print ``--help`` without importing it. planner/request.py applies them.
"""

#: Most waypoints in one plan (each one costs a look-ahead over the rest of the path).
MAX_WAYPOINTS = 1000
#: Most samples in one plan. Planning, torques and the files take ~2 kB of memory per sample
#: at the peak, so 500 000 samples stay near 1 GB (docs/errors.md "Work budget").
MAX_TOTAL_SAMPLES = 500_000
#: Samples per time unit t_l accepted (thesis §5.5 uses 100).
MAX_SAMPLES_PER_UNIT = 1000
#: Duration of one time unit [s]: from a 1 ms leg transfer to one of ~17 minutes. Outside
#: this range velocities and accelerations over- or underflow (1e300 s overflowed).
UNIT_TIME_RANGE_S = (1e-3, 1e3)
#: Largest |coordinate| of a waypoint or tolerance [m]: 1000 km, far beyond any budget.
MAX_COORDINATE_M = 1e6
#: Most time units t_l the ``--height auto`` search may plan over all its candidate heights
#: (each candidate is a whole plan at the search's sampling; ~6 ms of planning per unit on
#: SILO4 here): the thesis circle (~12 000 estimated in all) and go2's straight path fit, a
#: path of a kilometre (~600 000) is refused at once.
MAX_HEIGHT_SEARCH_UNITS = 60_000
