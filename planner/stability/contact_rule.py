"""What every stance configuration must hold of its contact forces (contact_forces.py).

Numpy-free: the Preset registry (planner/presets.py) carries a rule and the CLI reads it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from planner.errors import PlannerInputError

#: The minimum normal load of a stance foot, as a fraction of the robot's weight, that
#: ``--min-normal-load`` asks for by default [-] (contact_forces.py says why 5 %).
MIN_NORMAL_LOAD_FRACTION = 0.05
#: Default friction coefficient a plan may use (mu_plan) [-]: half of a rubber foot on
#: concrete (~1) and of the sim's 1.0, a factor 2 to real floors.
PLAN_FRICTION = 0.5


@dataclass(frozen=True)
class ContactForceRule:
    """Limits on the ground forces of every stance foot (contact_forces.py).

    Attributes:
        friction: largest tangential / normal load of a stance foot (mu_plan) [-];
            None: not checked.
        min_normal_fraction: smallest normal load of a stance foot over the robot's weight
            [-]; None (the default): not checked. At MIN_NORMAL_LOAD_FRACTION it refuses
            every Chapter 6 case (docs/physics.md, "Contact forces").
    """

    friction: float | None = PLAN_FRICTION
    min_normal_fraction: float | None = None

    def __post_init__(self) -> None:
        if self.friction is not None and not (math.isfinite(self.friction) and self.friction > 0):
            raise PlannerInputError(f"friction {self.friction!r}: give a coefficient > 0")
        fraction = self.min_normal_fraction
        if fraction is not None and not (math.isfinite(fraction) and 0 <= fraction < 1):
            raise PlannerInputError(
                f"minimum normal load {fraction!r}: give a fraction of the weight in [0, 1)"
            )

    @property
    def active(self) -> bool:
        """Whether the rule checks anything."""
        return self.friction is not None or self.min_normal_fraction is not None
