"""The ground the planner walks on: the Terrain protocol and its kinds (planner/terrain/base.py),
and terrain files (planner/terrain/terrain_file.py, docs/terrain.md)."""

from planner.terrain.base import FlatGround, Terrain, foothold_rule
from planner.terrain.forbidden import CheckedFootholds, ForbiddenPolygons
from planner.terrain.terrain_file import TerrainFileError, load_terrain, terrain_from_document
from planner.terrain.terrain_map import TerrainMap, TerrainNotWalkableError, gait_terrain

__all__ = [
    "CheckedFootholds",
    "FlatGround",
    "ForbiddenPolygons",
    "Terrain",
    "TerrainFileError",
    "TerrainMap",
    "TerrainNotWalkableError",
    "foothold_rule",
    "gait_terrain",
    "load_terrain",
    "terrain_from_document",
]
