"""What a gait is to the path planner: the :class:`Gait` protocol and the request it plans.

A gait turns a :class:`PlanRequest` (the planning model, the preset, the workspace at the
height, the waypoints and the options of plan_path) into a checked, sampled and verified
:class:`~planner.plan.Plan` whose ``gait`` is the gait's name, or raises
:class:`~planner.errors.PlanningError` saying why it cannot. The gaits (docs/gaits.md):

| name | class (module in planner/gaits/) | what it walks |
|---|---|---|
| ``thesis``, ``plain`` | CreepSpin (thesis_walk.py) | §5.5: spin to face, then creep |
| ``facing`` | FacingPath (facing.py) | crab angles, look-ahead turns, folded shifts |
| ``creep`` | OmniCreep (without_turning.py) | the omnidirectional creeping gait |
| ``crawl`` | ContinuousCrawl (without_turning.py) | the continuous crawl (crawl.py) |

and the combinators of planner/gaits/combinators.py (Fastest, Fallback, DefaultFor) that
make the presets' "auto" (planner/gaits/registry.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np

from planner.model import PlanningModel
from planner.presets import Preset
from planner.terrain.base import FootholdRule, Terrain, foothold_rule
from planner.workspace.layout import Workspace

if TYPE_CHECKING:
    from planner.gaits.first_walk import FirstWalkMemo
    from planner.plan import Plan


class NotFaster(Exception):
    """A gait's steps take at least as long as the plan already in hand (``slower_than``):
    the rest is not built (Fastest)."""


@dataclass(frozen=True)
class PlanRequest:
    """One plan to make, every input checked (planner/path/plan_path.py).

    Attributes:
        model: the robot in the planning frame.
        preset: the preset (planner/presets.py).
        workspace: the preset's workspace at the height, swing height applied.
        waypoints_in_world: (K, 2) [m].
        start_heading: world yaw of the base x axis at t = 0 [rad].
        tolerance: path-following tolerance [m].
        threshold: minimum stability margin on every lift [m].
        samples_per_unit: samples per time unit.
        unit_time_s: duration of one time unit [s].
        terrain: the ground (planner/terrain/base.py).
        first_walk_memo: first segments shared by plans that start alike, or None.
    """

    model: PlanningModel
    preset: Preset
    workspace: Workspace
    waypoints_in_world: np.ndarray
    start_heading: float
    tolerance: float
    threshold: float
    samples_per_unit: int
    unit_time_s: float
    terrain: Terrain
    first_walk_memo: FirstWalkMemo | None = None

    def foothold_rule(self) -> FootholdRule | None:
        """The terrain's rule for every placed foothold (None: all allowed)."""
        return foothold_rule(self.terrain)


class Gait(Protocol):
    """One way of walking a path (module docstring).

    Attributes:
        name: what ``plan_path(gait=)`` and ``--gait`` call it, and ``Plan.gait`` reports.
        label: how a fallback reason names it ("continuous crawl: ...").
    """

    @property
    def name(self) -> str: ...

    @property
    def label(self) -> str: ...

    def plan(self, request: PlanRequest, slower_than: float | None = None) -> Plan:
        """The plan of this gait; with ``slower_than`` [units], :class:`NotFaster` as soon
        as its steps take at least that long. Raises PlanningError (no stable, reachable
        step), FootholdRefused (the terrain refused a foothold)."""
        ...


def fewest_units(gait: Gait, request: PlanRequest) -> float:
    """A lower bound [units] on the duration of ``gait``'s plan of ``request``: the gait's
    own ``fewest_units(request)`` where it has one (a gait that can bound its duration
    without building a step, e.g. OmniCreep), else 0. Fastest does not build a gait whose
    bound reaches the plan in hand (it would stop with NotFaster)."""
    bound = getattr(gait, "fewest_units", None)
    return 0.0 if bound is None else float(bound(request))
