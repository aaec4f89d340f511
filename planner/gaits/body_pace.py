"""How long a four-foot body move takes (the creeping gait's body phase, planner/gaits/omni.py,
and the builder's shift step, planner/gaits/builder.py): long enough that the body's
acceleration moves the zero-moment point no further from the CoG than the stability margin.

A body move of d [m] on the quintic blend (planner/trajectory/profiles.py) over n time
units peaks at |c̈| = QUINTIC_PEAK_ACCELERATION d / n² [m/unit²]. That acceleration puts the
zero-moment point h |c̈| / g away from the CoG's ground projection (h the CoG's height above
the feet), towards the feet the body accelerates away from, and takes that share of the
load off the others: a quasi-static load the plan can account for (the contact forces,
planner/stability/contact_forces.py, take it in), but one that the body on its servo-driven
legs answers as a lightly damped oscillator. Measured (issue 21, anymal corpus case #17,
h = 0.505 m, docs/physics.md "Where the mammals' slip comes from"): its 1-unit body phases of
up to 0.24 m (1.39 m/s², the ZMP 7 cm off the CoG) rocked the body 12-30 mrad peak to peak
about its x axis at 2.1-2.2 Hz, a planned stance foot of 0.04 W lifted 3.9 mm and the feet
slipped 11.2 mm; the same plan with 2-unit body phases rocked <= 12 mrad and slipped 4.4 mm.
Case #29 (h = 0.614 m) slipped 6.2 mm with only the body phases paced: its 1-unit shifts of
up to 0.11 m put the ZMP 39.5 mm off; with them paced too it slipped 4.7 mm.

The rule: n >= sqrt(QUINTIC_PEAK_ACCELERATION d h / (g S)), at least the step's own time
(1 unit for both), rounded up to PACE_GRID_UNITS, with S the lift threshold the planner
keeps the CoG inside its support by (0.02 m by default) and h taken to the ground (a ball
foot's frame is its radius above it): the dynamic excursion of the ZMP stays within the
margin the static criterion keeps for what it does not model. A threshold of 0 (the
thesis preset) leaves the gait's own time. The acceleration is per time unit²; it is m/s² at
the planning unit time of 1 s and grows as 1 / T² at a shorter one.
"""

from __future__ import annotations

import math

#: Peak of the quintic blend's second derivative, 10 / sqrt(3) at τ = (3 - √3) / 6 [-] (the
#: default preset's body blend; the thesis's cosine peaks at π² / 2, lower).
QUINTIC_PEAK_ACCELERATION = 10.0 / math.sqrt(3.0)
#: Body-phase durations are rounded up to this grid [time units] (the crawl's four-foot
#: time is 0.5 unit: every samples-per-unit the gaits take samples it exactly).
PACE_GRID_UNITS = 0.5
#: Standard gravity [m/s²].
GRAVITY = 9.80665
#: Label of the creeping gait's body phase (planner/gaits/omni.py): paced also when a fold
#: moves its end (planner/gaits/fold.py).
CREEP_BODY_LABEL = "creep body"


def zmp_excursion_m(distance_m: float, height_m: float, units: float) -> float:
    """Largest distance [m] of the zero-moment point from the CoG's projection over a
    quintic body move of ``distance_m`` in ``units`` time units at 1 s per unit, the CoG
    ``height_m`` above the feet (module docstring)."""
    return QUINTIC_PEAK_ACCELERATION * distance_m * height_m / (GRAVITY * units * units)


def body_units(distance_m: float, height_m: float, margin_m: float, min_units: float) -> float:
    """Time units [-] of a four-foot body move of ``distance_m`` [m] with the CoG
    ``height_m`` [m] above the feet: at least ``min_units``, and long enough that
    :func:`zmp_excursion_m` <= ``margin_m`` (none asked for a margin <= 0), on the
    PACE_GRID_UNITS grid."""
    if margin_m <= 0.0 or distance_m <= 0.0 or height_m <= 0.0:
        return float(min_units)
    need = math.sqrt(QUINTIC_PEAK_ACCELERATION * distance_m * height_m / (GRAVITY * margin_m))
    if need <= min_units:
        return float(min_units)
    return math.ceil(need / PACE_GRID_UNITS - 1e-9) * PACE_GRID_UNITS
