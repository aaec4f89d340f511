"""How a clearance under its threshold is written in a refusal: in millimetres, rounded
down to 0.1 mm, so a shape 9.96 mm from the ground reads "9.9 mm ... under the 10 mm", not
"10.0 mm ... under the 10 mm" (the rounding put the figure on the threshold it failed)."""

from __future__ import annotations

import math


def mm_down(value_m: float) -> str:
    """``value_m`` [m] in mm, rounded down to 0.1 mm, one decimal (a value exactly on a
    tenth, up to float error in the scaling, stays on it)."""
    tenths = math.floor(round(float(value_m) * 1e4, 6))
    return f"{tenths / 10:.1f}"
