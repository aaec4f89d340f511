"""planner: statically stable gaits, trajectories and path following (thesis Ch. 4-5).

Layer 2: imports silo4kin, never viz.
"""

from .errors import PlannerInputError, PlanningError
from .metrics import compute_metrics
from .path import DEFAULT_TOLERANCE_M, Plan, SpinRecord, plan_path
from .stability import inside_support_triangle, support_margin, triangle_area
from .steps import Step
from .trajectory import LEGS, Trajectory
from .workspace import PRESETS, Workspace, feasible_height_range, workspace_for

__all__ = [
    "DEFAULT_TOLERANCE_M", "LEGS", "PRESETS", "Plan", "PlannerInputError", "PlanningError",
    "SpinRecord", "Step", "Trajectory", "Workspace", "compute_metrics",
    "feasible_height_range", "inside_support_triangle", "plan_path", "support_margin",
    "triangle_area", "workspace_for",
]
