"""Planning policies: what a workspace preset means beyond its footholds (docs/design.md, round 2).

A preset name ("default", "thesis") selects a :class:`Policy`; the planner, the metrics and
the CLI ask the policy instead of comparing preset strings:

| concern | ``thesis`` | ``default`` |
|---|---|---|
| stability point | body CoG (§5.1, App. A) | whole-robot CoM, legs as they move |
| threshold on every lift | 0 (workspace preset) | 0.02 m (workspace preset) |
| load the feet carry (torques) | body weight (App. A) | the whole robot |
| swing height | eq 5.12: half the hip height | eq 5.12, at least MIN_SWING_HEIGHT_M |
| gait | §5.5 as written | any direction without turning: continuous crawl or creeping |
|      |                  | gait, the faster (planner/gaits/crawl.py, omni.py), smooth profiles; |
|      |                  | --face-path: crab, look-ahead turns, folded shifts |

The workspace (strides, footholds, ψ_max, threshold) stays in planner/workspace/layout.py.
"""

from __future__ import annotations

from dataclasses import dataclass

from planner.errors import PlannerInputError
from planner.gaits.steps import StrEnum

#: Smallest swing height of the default policy [m]: eq 5.12 gives 2.5 cm at h = 0.2 m on
#: SILO4, which scuffs in physics replay (issue 9); 5 cm clears a small stone or a step.
MIN_SWING_HEIGHT_M = 0.05


class StabilityPoint(StrEnum):
    """The point kept inside the support polygon."""

    BODY_COG = "body"      # the base link's CoM (thesis §5.1)
    WHOLE_BODY_COM = "com"  # the whole robot's CoM, legs included


class Load(StrEnum):
    """What the stance feet carry in the torques (silo4kin.joint_torques)."""

    BODY = "body"
    TOTAL = "total"


@dataclass(frozen=True)
class Policy:
    """What a preset means for planning (module docstring).

    Attributes:
        name: preset name.
        stability_point: the point whose margin is the planner's criterion.
        load: default load of the torques.
        min_swing_height_m: lower bound on the swing height [m] (0: eq 5.12 as is).
        fast_gait: crab gait, look-ahead turns, spins without transitions, folded shifts.
    """

    name: str
    stability_point: StabilityPoint
    load: Load
    min_swing_height_m: float
    fast_gait: bool

    def swing_height(self, eq_5_12_m: float, override_m: float | None = None) -> float:
        """The swing height [m]: ``override_m`` when given, else eq 5.12's value raised to
        ``min_swing_height_m``."""
        if override_m is not None:
            return float(override_m)
        return max(float(eq_5_12_m), self.min_swing_height_m)


POLICIES: dict[str, Policy] = {
    "default": Policy("default", StabilityPoint.WHOLE_BODY_COM, Load.TOTAL,
                      MIN_SWING_HEIGHT_M, fast_gait=True),
    "thesis": Policy("thesis", StabilityPoint.BODY_COG, Load.BODY, 0.0, fast_gait=False),
}


def policy_for(preset: str) -> Policy:
    """The policy of a preset name; raises PlannerInputError naming the choices."""
    try:
        return POLICIES[preset]
    except (KeyError, TypeError):
        raise PlannerInputError(f"unknown workspace preset {preset!r}; choose one of "
                                f"{list(POLICIES)}") from None
