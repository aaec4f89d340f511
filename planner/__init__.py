"""planner: statically stable gaits, trajectories and path following (thesis Ch. 4-5).

Layer 2: imports silo4kin, never viz.
"""

from .trajectory import LEGS, Trajectory

__all__ = ["LEGS", "Trajectory"]
