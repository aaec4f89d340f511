"""planner: statically stable gaits, trajectories and path following (thesis Ch. 4-5).

Layer 2: imports silo4kin, never viz.
"""

from importlib import import_module
from typing import TYPE_CHECKING, Any

from planner.errors import PlannerInputError, PlanningError

#: Names served lazily (PEP 562): the CLI imports ``planner.outputs.files`` and ``planner.request``
#: to check options, and ``silo4 --help`` must not import numpy and Pinocchio for that.
_LAZY = {
    "compute_metrics": "path.metrics",
    "DEFAULT_TOLERANCE_M": "path.plan_path",
    "Plan": "path.plan_path",
    "SpinRecord": "path.plan_path",
    "plan_path": "path.plan_path",
    "inside_support_triangle": "stability.margin",
    "support_margin": "stability.margin",
    "triangle_area": "stability.margin",
    "Step": "gaits.steps",
    "LEGS": "trajectory.samples",
    "Trajectory": "trajectory.samples",
    "PRESETS": "presets",
    "Preset": "presets",
    "preset_for": "presets",
    "Height": "request",
    "FlatGround": "terrain",
    "Terrain": "terrain",
    "Workspace": "workspace.layout",
    "feasible_height_range": "workspace.layout",
    "workspace_for": "workspace.layout",
}

if TYPE_CHECKING:
    from planner.gaits.steps import Step
    from planner.path.metrics import compute_metrics
    from planner.path.plan_path import DEFAULT_TOLERANCE_M, Plan, SpinRecord, plan_path
    from planner.presets import PRESETS, Preset, preset_for
    from planner.request import Height
    from planner.stability.margin import inside_support_triangle, support_margin, triangle_area
    from planner.terrain import FlatGround, Terrain
    from planner.trajectory.samples import LEGS, Trajectory
    from planner.workspace.layout import Workspace, feasible_height_range, workspace_for


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "DEFAULT_TOLERANCE_M",
    "LEGS",
    "PRESETS",
    "FlatGround",
    "Height",
    "Plan",
    "PlannerInputError",
    "PlanningError",
    "Preset",
    "SpinRecord",
    "Step",
    "Terrain",
    "Trajectory",
    "Workspace",
    "compute_metrics",
    "feasible_height_range",
    "inside_support_triangle",
    "plan_path",
    "preset_for",
    "support_margin",
    "triangle_area",
    "workspace_for",
]
