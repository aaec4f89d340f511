"""How long a leg transfer takes (the step builder's transfer, planner/gaits/builder.py): long
enough that the swinging leg's accelerations move the zero-moment point no further from the
whole-robot CoM than the stability margin, as the body moves are paced (body_pace.py).

With the base standing, the swing leg is the only mass that accelerates: lifting it, carrying
it forward and setting it down moves the whole-robot CoM c by the leg's share of the robot's
mass, and c̈ puts the zero-moment point z = c_xy - (c_z - ground) c̈_xy / (g + c̈_z) off the
CoM's ground projection (planner/stability/swing_com.py swing_zmp_in_world, the profiles the
samples have). That excursion is a load the stance feet take on and off within the swing,
which the servo-driven legs answer as the body's lightly damped mode (docs/physics.md, "What
moves the light feet"). Measured (issue 21, anymal on the thesis straight path at its
``--height auto`` height 0.3887 m, 1 s a unit): its 1-unit swings of 0.17 m (eq 5.12) and
strides up to 0.55 m put the ZMP 24 mm off the CoM on average and 47 mm at most (the leg is
11 % of the robot's 30 kg), the body swayed 2.6-4.3 mm in each swing and was left 1 mm
behind at each landing; over 81 units it drifted 21.4 mm (> 20 mm) and the feet slipped up
to 3.4 mm. The same plan with 1.5-unit swings drifted 3.2 mm and slipped 0.4 mm.

The rule: a transfer lasts the fewest units n >= 1 on PACE_GRID_UNITS whose excursion at 1 s
a unit, swung over n units, is at most S, the lift threshold the planner keeps the CoM inside
its support by (0.02 m by default): the dynamic excursion stays within the margin the static
criterion keeps for what it does not model. The excursion falls about as 1 / n² (c̈ does);
each candidate is checked on the swing itself. A threshold of 0 (the thesis preset) leaves
the thesis's 1 unit. As for the body phases, the bound is at the planning unit time of 1 s.
"""

from __future__ import annotations

from collections.abc import Callable

from planner.gaits.body_pace import PACE_GRID_UNITS

#: The longest transfer the rule asks for [units]: the excursion falls as 1 / n², so 4 units
#: cut it 16-fold (anymal's worst swing: 47 mm -> 3 mm); a swing that still breaks the margin
#: there is left to the run's contact-force check.
MAX_TRANSFER_UNITS = 4.0


def transfer_units(
    excursion_m: Callable[[float], float], margin_m: float, min_units: float
) -> float:
    """Time units [-] of a transfer: at least ``min_units``, and the fewest on the
    PACE_GRID_UNITS grid (up to MAX_TRANSFER_UNITS) whose ``excursion_m(units)`` [m] (the
    ZMP's largest distance from the CoM over the swing lasting ``units`` at 1 s a unit) is at
    most ``margin_m``; ``min_units`` when no margin is asked for (<= 0) or the excursion is
    not a number (a foot out of reach: the builder's reach checks refuse it)."""
    if margin_m <= 0.0:
        return float(min_units)
    first = excursion_m(float(min_units))
    if not first > margin_m:  # within the margin, or NaN
        return float(min_units)
    units = float(min_units) + PACE_GRID_UNITS
    while units < MAX_TRANSFER_UNITS and excursion_m(units) > margin_m:
        units += PACE_GRID_UNITS
    return float(min(units, MAX_TRANSFER_UNITS))
