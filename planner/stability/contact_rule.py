"""What every stance configuration must hold of its contact forces (contact_forces.py).

Numpy- and dataclass-free (a NamedTuple, as the Preset that carries it): ``silo4 --help``
builds the parser from planner/presets.py without importing either.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from planner.errors import PlannerInputError

#: The minimum normal load of a stance foot, as a fraction of the robot's weight, that
#: ``--min-normal-load`` asks for by default [-] (contact_forces.py says why 5 %).
MIN_NORMAL_LOAD_FRACTION = 0.05
#: Default friction coefficient a plan may use (mu_plan) [-]: half of a rubber foot on
#: concrete (~1) and of the sim's 1.0, a factor 2 to real floors.
PLAN_FRICTION = 0.5
#: Least distance of the zero-moment point inside the support polygon the default preset
#: asks [m]: 0, the physical bound (a rigid foot cannot pull; a centre of pressure outside
#: the stance feet tips the robot). Measured: a phasmid crawl whose four-foot sway put the
#: ZMP 19.6 mm outside fell in MuJoCo 1.7 s later; the 9 Chapter 6 default-preset plans keep
#: it 12.7-22.2 mm inside (docs/physics.md, "Zero-moment point").
ZMP_MARGIN_M = 0.0


class ContactForceRule(NamedTuple):
    """Limits on the ground forces of every stance foot (contact_forces.py).

    Attributes:
        friction: largest tangential / normal load of a stance foot (mu_plan) [-];
            None: not checked.
        min_normal_fraction: smallest normal load of a stance foot over the robot's weight
            [-]; None (the default): not checked. At MIN_NORMAL_LOAD_FRACTION it refuses
            every Chapter 6 case (docs/physics.md, "Contact forces").
        min_zmp_margin_m: smallest signed distance of the zero-moment point (the centre of
            pressure the ground must give for the planned CoM acceleration) inside the
            support polygon of the stance feet [m]; None: not checked. The default preset
            asks ZMP_MARGIN_M: a ZMP outside needs a foot to pull on the ground, and the
            robot tips (contact_forces.py).
    """

    friction: float | None = PLAN_FRICTION
    min_normal_fraction: float | None = None
    min_zmp_margin_m: float | None = None

    def checked(self) -> ContactForceRule:
        """The rule itself, or PlannerInputError naming a value out of range."""
        if self.friction is not None and not (math.isfinite(self.friction) and self.friction > 0):
            raise PlannerInputError(f"friction {self.friction!r}: give a coefficient > 0")
        fraction = self.min_normal_fraction
        if fraction is not None and not (math.isfinite(fraction) and 0 <= fraction < 1):
            raise PlannerInputError(
                f"minimum normal load {fraction!r}: give a fraction of the weight in [0, 1)"
            )
        zmp = self.min_zmp_margin_m
        if zmp is not None and not math.isfinite(zmp):
            raise PlannerInputError(f"zero-moment-point margin {zmp!r}: give a length [m]")
        return self

    @property
    def active(self) -> bool:
        """Whether the rule checks anything."""
        return (
            self.friction is not None
            or self.min_normal_fraction is not None
            or self.min_zmp_margin_m is not None
        )
