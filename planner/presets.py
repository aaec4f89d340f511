"""Planning presets: one registry of what a preset name means (docs/design.md, round 2).

A preset (``--workspace`` on the CLI, ``workspace=`` of plan_path) is a :class:`Preset`; the
planner, the metrics and the CLI read its attributes instead of comparing names:

| concern | ``thesis`` | ``default`` |
|---|---|---|
| stability point | body CoG (§5.1, App. A) | whole-robot CoM, legs as they move |
| threshold on every lift | 0 | 0.02 m (planner/workspace/layout.py) |
| footholds and stride | the thesis's square from one reference pose | each leg's reachable set |
| load the feet carry (torques) | body weight (App. A) | the whole robot |
| swing height | eq 5.12: half the hip height | eq 5.12, at least MIN_SWING_HEIGHT_M |
| gaits | "thesis": §5.5 as written | "auto": the faster of "crawl" and "creep" (any |
|       |                           | direction without turning), else "facing"; or one |
|       |                           | of "crawl", "creep", "facing", "plain" (docs/gaits.md) |
| tibia clearance | reported | held (planner/trajectory/clearance.py) |
| arrival | within the tolerance (§5.5) | the CoG lands on each waypoint (warned if not) |

The workspace of a preset (strides, footholds, ψ_max, threshold) is built by
planner/workspace/layout.py from the preset's :attr:`Preset.footholds`.
"""

from __future__ import annotations

from enum import Enum
from typing import NamedTuple

from planner.errors import PlannerInputError
from planner.stability.contact_rule import ZMP_MARGIN_M, ContactForceRule

#: Smallest swing height of the default preset [m]: eq 5.12 gives 2.5 cm at h = 0.2 m on
#: SILO4, which scuffs in physics replay; 5 cm clears a small stone or a step.
MIN_SWING_HEIGHT_M = 0.05
#: Fraction of each URDF effort limit a plan's peak torque may use (``--torque-headroom``)
#: [-]: the sim's servos clamp at the limit and add their feedback on top of the plan's
#: torque, so 15 % is left to it. The thesis preset keeps the whole limit (1.0): Chapter 6's
#: torques are computed against it (Table 6.2).
TORQUE_HEADROOM = 0.85
#: Least height above the ground of every collision shape of the robot but its feet [m]
#: (``--ground-clearance``; planner/trajectory/clearance.py reads the shapes from the URDF).
MIN_GROUND_CLEARANCE_M = 0.01
#: The gait name that asks for the preset's own choice (Preset.default_gait).
AUTO_GAIT = "auto"


class StrEnum(str, Enum):
    """A str-valued Enum whose str() is its value (enum.StrEnum needs Python 3.11)."""

    def __str__(self) -> str:
        return str(self.value)


class StabilityPoint(StrEnum):
    """The point kept inside the support polygon."""

    BODY_COG = "body"  # the base link's CoM (thesis §5.1)
    WHOLE_BODY_COM = "com"  # the whole robot's CoM, legs included


class FootholdRule(StrEnum):
    """Where the workspace puts the footholds (planner/workspace/foothold_layout.py)."""

    THESIS_SQUARE = "square"  # the thesis's square from one reference pose (§4.2.1)
    REACHABLE_SETS = "reachable"  # inside each leg's reachable set, with a shift reserve


class Load(StrEnum):
    """What the stance feet carry in the torques (silo4kin.joint_torques)."""

    BODY = "body"
    TOTAL = "total"


class Preset(NamedTuple):
    """What a preset means for planning (module docstring). Immutable; a NamedTuple rather
    than a dataclass so that the CLI reads its choices from :data:`PRESETS` while
    ``silo4 --help`` imports neither numpy nor dataclasses (tests/test_lazy_imports.py).

    Attributes:
        name: preset name (also the workspace layout's, planner/workspace/layout.py).
        stability_point: the point whose margin is the planner's criterion.
        load: default load of the torques.
        min_swing_height_m: lower bound on the swing height [m] (0: eq 5.12 as is).
        gaits: the gait names a caller may ask for (planner/gaits/registry.py), "auto"
            included: it means ``default_gait``.
        default_gait: the gait "auto" stands for.
        holds_tibias: the samples are refused when a tibia dips below the ground clearance.
        arrives: its gaits land the nominal CoG on each waypoint (a miss is warned about,
            planner/path/metrics.py).
        follows_thesis: plans the thesis as written: its cases are the ones compared with
            the thesis's own numbers (planner/studies/thesis_consistency.py).
        description: one line for the CLI's help.
        footholds: the workspace's foothold rule; it also fixes the workspace's minimum
            stride and hip clearance, its lift threshold and spin rule
            (planner/workspace/layout.py).
        contact_forces: the ground forces every stance foot must keep: friction demand
            <= mu_plan, and optionally a minimum normal load (planner/stability/contact_rule.py).
        torque_headroom: the fraction of each URDF effort limit a run's planned torques may
            use (planner/outputs/pipeline.py: ``silo4 plan``, ``silo4 cases``, sweeps).
        ground_clearance_m: the least height above the ground of every non-foot collision
            shape on every sample of a run's plan [m] (planner/trajectory/clearance.py; the
            ``--height auto`` search skips heights below it).
        step_torque_headroom: the fraction of each joint's URDF effort limit the step builder
            lets a stance's torques use (its load caps, foothold search and body-move timing,
            planner/gaits/walk.py), one per joint in the robot's joint order; None:
            ``torque_headroom`` for every joint. A run whose motion alone breaks its budget is
            planned again with the joints that broke it lowered (planner/outputs/pipeline.py).
    """

    name: str
    stability_point: StabilityPoint
    load: Load
    min_swing_height_m: float
    gaits: tuple[str, ...]
    default_gait: str
    holds_tibias: bool
    arrives: bool
    follows_thesis: bool
    description: str
    footholds: FootholdRule
    contact_forces: ContactForceRule = ContactForceRule()
    torque_headroom: float = TORQUE_HEADROOM
    ground_clearance_m: float = MIN_GROUND_CLEARANCE_M
    step_torque_headroom: tuple[float, ...] | None = None

    @property
    def builder_torque_headroom(self) -> float | tuple[float, ...]:
        """The step builder's fraction of each joint's URDF effort (``step_torque_headroom``,
        else ``torque_headroom``)."""
        if self.step_torque_headroom is None:
            return self.torque_headroom
        return self.step_torque_headroom

    def swing_height(self, eq_5_12_m: float, override_m: float | None = None) -> float:
        """The swing height [m]: ``override_m`` when given, else eq 5.12's value raised to
        ``min_swing_height_m``."""
        if override_m is not None:
            return float(override_m)
        return max(float(eq_5_12_m), self.min_swing_height_m)

    def gait_name(self, asked: str | None, *, face_path: bool = False) -> str:
        """The gait name this preset walks for ``asked`` (None or "auto": its default) and
        ``face_path`` (the same as asking for "facing"); refuses a gait it does not offer
        with PlannerInputError naming the choices."""
        if face_path:
            if asked not in (None, AUTO_GAIT, "facing"):
                raise PlannerInputError(
                    f"face_path walks the gait 'facing'; it cannot be combined with gait {asked!r}"
                )
            asked = "facing"
        name = self.default_gait if asked in (None, AUTO_GAIT) else asked
        if name not in self.gaits:
            what = "face_path (gait 'facing')" if face_path else f"gait {asked!r}"
            raise PlannerInputError(
                f"the {self.name!r} preset does not offer {what}; choose one of {list(self.gaits)}"
            )
        return name


#: Every preset by name, the thesis first (the order of the Chapter 6 comparison).
PRESETS: dict[str, Preset] = {
    "thesis": Preset(
        "thesis",
        StabilityPoint.BODY_COG,
        Load.BODY,
        0.0,
        gaits=(AUTO_GAIT, "thesis"),
        default_gait="thesis",
        holds_tibias=False,
        arrives=False,
        follows_thesis=True,
        description="reproduces Chapter 6's strides, body CoG and the gait of §5.5",
        footholds=FootholdRule.THESIS_SQUARE,
        torque_headroom=1.0,
    ),
    "default": Preset(
        "default",
        StabilityPoint.WHOLE_BODY_COM,
        Load.TOTAL,
        MIN_SWING_HEIGHT_M,
        gaits=(AUTO_GAIT, "crawl", "creep", "facing", "plain"),
        default_gait=AUTO_GAIT,
        holds_tibias=True,
        contact_forces=ContactForceRule(min_zmp_margin_m=ZMP_MARGIN_M),
        arrives=True,
        follows_thesis=False,
        description="keeps a reach margin from the stretched-leg singularity; whole-robot "
        "CoM; walks in any direction",
        footholds=FootholdRule.REACHABLE_SETS,
    ),
}


#: The leg families whose "auto" tries the crawl (planner/gaits/registry.py): it is checked in
#: physics on insect legs only (a mammal's crawl slipped and drifted where its creeping gait
#: walks, docs/robots.md).
CRAWL_BY_DEFAULT_FAMILIES = ("insect",)


def preset_for(preset: str | Preset) -> Preset:
    """The :class:`Preset` of a name (or the preset itself); raises PlannerInputError naming
    the choices."""
    if isinstance(preset, Preset):
        return preset
    try:
        return PRESETS[preset]
    except (KeyError, TypeError):
        raise PlannerInputError(
            f"unknown workspace preset {preset!r}; choose one of {list(PRESETS)}"
        ) from None


def footholds_of(preset: str | Preset) -> FootholdRule:
    """The foothold rule of a preset (or its name); raises PlannerInputError as
    :func:`preset_for`."""
    return preset_for(preset).footholds


def gait_choices() -> tuple[str, ...]:
    """Every gait name some preset offers, in registry order (the CLI's ``--gait``)."""
    return tuple(dict.fromkeys(g for p in PRESETS.values() for g in p.gaits))
