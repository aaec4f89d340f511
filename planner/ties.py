"""How the planner compares the scores of its discrete choices, so that a plan does not depend
on the CPU it is computed on.

numpy computes sin, cos, arctan2, sums and products on different SIMD paths on different CPUs
(AVX2, AVX-512, ...); their results differ in the last bits (~1e-16 relative). A choice between
candidates whose scores are equal in exact arithmetic (two legs mirrored about the body's
axis, a travel direction at 45 deg between two body axes, two leg orders with the same total
shift) is then decided by that noise, and the plan's contact sequence, length and joint
values change from one machine to the next. Every such choice compares its scores rounded to
DECISION_DECIMALS (:func:`tie_key`): equal scores then tie exactly, and the tie goes to the
first candidate in the order the caller documents (its list, a dict's order, leg order LF, RF,
LH, RH). A rounded score still flips where the exact value lies within ~1e-16 of a multiple of
half a nanounit, which the noise reaches with a probability of ~1e-7 per comparison.
"""

from __future__ import annotations

#: Decimals kept of a score [its own unit: m, rad, m^2 ...] before candidates are compared:
#: 1 nm or 1 nrad, far below anything a servo tracks, far above float noise on values ~1.
DECISION_DECIMALS = 9


def tie_key(value: float) -> float:
    """``value`` rounded to DECISION_DECIMALS (-0.0 folded to 0.0), for sort keys, min/max
    keys and sign tests of the planner's discrete choices (module docstring)."""
    return round(float(value), DECISION_DECIMALS) + 0.0
