"""planner: statically stable gaits, trajectories and path following (thesis Ch. 4-5).

Layer 2: imports silo4kin, never viz.
"""

from importlib import import_module
from typing import TYPE_CHECKING, Any

from .errors import PlannerInputError, PlanningError

#: Names served lazily (PEP 562): the CLI imports ``planner.files`` and ``planner.inputs``
#: to check options, and ``silo4 --help`` must not import numpy and Pinocchio for that.
_LAZY = {
    "compute_metrics": "metrics",
    "DEFAULT_TOLERANCE_M": "path", "Plan": "path", "SpinRecord": "path", "plan_path": "path",
    "inside_support_triangle": "stability", "support_margin": "stability",
    "triangle_area": "stability",
    "Step": "steps",
    "LEGS": "trajectory", "Trajectory": "trajectory",
    "PRESETS": "workspace", "Workspace": "workspace",
    "feasible_height_range": "workspace", "workspace_for": "workspace",
}

if TYPE_CHECKING:
    from .metrics import compute_metrics
    from .path import DEFAULT_TOLERANCE_M, Plan, SpinRecord, plan_path
    from .stability import inside_support_triangle, support_margin, triangle_area
    from .steps import Step
    from .trajectory import LEGS, Trajectory
    from .workspace import PRESETS, Workspace, feasible_height_range, workspace_for


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "DEFAULT_TOLERANCE_M", "LEGS", "PRESETS", "Plan", "PlannerInputError", "PlanningError",
    "SpinRecord", "Step", "Trajectory", "Workspace", "compute_metrics",
    "feasible_height_range", "inside_support_triangle", "plan_path", "support_margin",
    "triangle_area", "workspace_for",
]
