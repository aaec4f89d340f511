"""The result of planning a path (planner/path/plan_path.py): :class:`Plan` and its turns."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from planner.gaits.steps import Step
from planner.presets import Preset, preset_for
from planner.trajectory.samples import Trajectory
from planner.workspace.layout import Workspace


@dataclass(frozen=True)
class SpinRecord:
    """One turn: waypoint index, total angle ψ [rad], cycles (ours and the thesis's count),
    leg order per cycle (leg names)."""

    waypoint_index: int
    psi_rad: float
    cycles: int
    thesis_cycles: int
    orders: tuple[tuple[str, ...], ...]


@dataclass(frozen=True, eq=False)
class Plan:
    """A planned path.

    Attributes:
        waypoints_in_world: (K, 2) [m], as given.
        height: body CoG height h [m].
        workspace: the :class:`~planner.workspace.layout.Workspace` used.
        steps: the step list (planner/gaits/steps.py).
        trajectory: dense samples (planner/trajectory/samples.py).
        start_heading: world yaw of the base x axis at t = 0 [rad].
        tolerance: [m] (module docstring).
        stability_threshold: minimum S_m required on every lift [m].
        position_reached_in_world: nominal CoG (x, y) when each waypoint was done, (K, 2) [m].
        spins: the turns made.
        n_creep_half_cycles: number of creeping half cycles (4 units each).
        n_shifts: stability shifts inserted (1 unit each).
        n_folded_shifts: stability shifts folded into a body phase (no time).
        preset: the :class:`~planner.presets.Preset` planned with.
        gait: the name of the gait that walked (planner/gaits/registry.py, the names
            ``plan_path(gait=)`` takes): "crawl" (the continuous crawl), "creep" (the
            omnidirectional creeping gait), "facing" (facing the path, crab and look-ahead
            turns), "plain" (the default preset's creeping and spinning gait) or "thesis"
            (§5.5 as written).
        fallback_reason: why a faster gait was not used (its PlanningError), or None.
        time_reached_units: time [units] when each waypoint was done, (K,).
        position_walked_in_world: the sampled CoG (x, y) at those times, (K, 2) [m] (what
            E_n measures: the CoG as walked, shifts included).
        height_search: with ``height="auto"``, how the height was chosen
            (:meth:`planner.path.height.HeightChoice.to_json`), else None.
        nominal_distance_m: length of the nominal CoG path [m] where the steps vary in length
            (omni gait); None where it is the count of creeping body phases x λ/2.
        n_crawl_swings: swings of the continuous crawl (body moving); its creeping half
            cycles (planner/gaits/crawl.py, CrawlOrCreep) are in n_creep_half_cycles.
    """

    waypoints_in_world: np.ndarray
    height: float
    workspace: Workspace
    steps: tuple[Step, ...]
    trajectory: Trajectory
    start_heading: float
    tolerance: float
    stability_threshold: float
    position_reached_in_world: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    spins: tuple[SpinRecord, ...] = ()
    n_creep_half_cycles: int = 0
    n_shifts: int = 0
    n_folded_shifts: int = 0
    preset: Preset = field(default_factory=lambda: preset_for("default"))
    gait: str = "plain"
    fallback_reason: str | None = None
    time_reached_units: np.ndarray = field(default_factory=lambda: np.zeros(0))
    position_walked_in_world: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    height_search: dict | None = None
    nominal_distance_m: float | None = None
    n_crawl_swings: int = 0
