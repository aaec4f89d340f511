"""The ground the planner walks on: the Terrain protocol and its kinds (planner/terrain/base.py)."""

from planner.terrain.base import FlatGround, Terrain, foothold_rule
from planner.terrain.forbidden import CheckedFootholds, ForbiddenPolygons

__all__ = ["CheckedFootholds", "FlatGround", "ForbiddenPolygons", "Terrain", "foothold_rule"]
