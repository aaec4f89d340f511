"""A terrain file's ground as a :class:`~planner.terrain.base.Terrain`: floor, boxes,
cylinders, a height map and forbidden polygons (the file format: docs/terrain.md).

The ground under a point (x, y) is the highest of: the floor (a plane at ``floor_z``; None:
no floor, a void), the floor plus the height map over its grid, the tops of the boxes and of
the cylinders: what a ray cast straight down from above hits first. Where nothing lies
under a point its height is -inf and its normal NaN.

A level floor with forbidden polygons is planned as :meth:`TerrainMap.level_terrain` (the
floor with the forbidden polygons, planner/terrain/forbidden.py), exactly as before; boxes,
cylinders, a height map or a missing floor are planned on the map itself, footholds searched
on its surfaces and its height map (planner/gaits/surface_footholds.py, :func:`gait_terrain`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from planner.errors import PlannerInputError
from planner.terrain.base import FlatGround, Terrain
from planner.terrain.forbidden import ForbiddenPolygons
from planner.terrain.heightmap import HeightMap
from planner.terrain.shapes import Box, Cylinder, Surface

#: Half the side of the square that stands for the floor in :meth:`TerrainMap.surfaces` [m].
FLOOR_SURFACE_HALF_SIDE_M = 1e3
#: Where plan_path puts the CoG at the start, in W [m] (planner/gaits/walk.py start_builder).
START_XY_IN_WORLD = (0.0, 0.0)
#: Rays of the disc over which a sphere is measured against the height map
#: (:meth:`TerrainMap.sphere_clearance`): the centre and this many points on its circle.
HEIGHTMAP_DISC_DIRECTIONS = 8
#: How far a foothold keeps from a forbidden polygon's edges by default [m] (the ditch
#: study's FOOT_CLEARANCE_M, planner/studies/ditch.py: the foot sphere's contact point).
FORBIDDEN_CLEARANCE_M = 0.01


class TerrainNotWalkableError(PlannerInputError):
    """A terrain the gaits cannot plan on yet; the message names what is in the way."""


@dataclass(frozen=True, eq=False)
class TerrainMap:
    """The ground of a terrain file (module docstring). Every array is in W [m].

    Attributes:
        floor_z: height of the ground plane [m]; None: no floor.
        boxes, cylinders: the solids (planner/terrain/shapes.py).
        forbidden_xy_in_world: convex polygons (M, 2) where no foot may stand.
        heightmap: heights added to the floor over a grid, or None.
        forbidden_clearance_m: a foothold keeps this far from a forbidden polygon [m].
        name: the file the terrain came from, for messages ("": none).
    """

    floor_z: float | None = 0.0
    boxes: tuple[Box, ...] = ()
    cylinders: tuple[Cylinder, ...] = ()
    forbidden_xy_in_world: tuple[np.ndarray, ...] = ()
    heightmap: HeightMap | None = None
    forbidden_clearance_m: float = FORBIDDEN_CLEARANCE_M
    name: str = ""
    _forbidden: ForbiddenPolygons = field(init=False, repr=False, compare=False)

    refuses_footholds = True

    def __post_init__(self) -> None:
        object.__setattr__(
            self,
            "_forbidden",
            ForbiddenPolygons(self.forbidden_xy_in_world, clearance_m=self.forbidden_clearance_m),
        )

    def _tops(self, xy_in_world: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every part's top (K, N) [m] and normal (K, N, 3) under points (N, 2)."""
        xy = np.asarray(xy_in_world, dtype=float).reshape(-1, 2)
        tops: list[tuple[np.ndarray, np.ndarray]] = []
        if self.floor_z is not None:
            tops.append(
                (np.full(len(xy), float(self.floor_z)), np.tile([0.0, 0.0, 1.0], (len(xy), 1)))
            )
        if self.heightmap is not None:
            tops.append(self.heightmap.top_at(xy))
        tops += [box.top_at(xy) for box in self.boxes]
        tops += [cylinder.top_at(xy) for cylinder in self.cylinders]
        if not tops:
            return np.full((1, len(xy)), -np.inf), np.full((1, len(xy), 3), np.nan)
        return np.array([z for z, _ in tops]), np.array([n for _, n in tops])

    def height_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        """Ground height z [m] under points (N, 2) [m], shape (N,); -inf over a void."""
        return self._tops(xy_in_world)[0].max(axis=0)

    def ground_at(self, xy_in_world: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(:meth:`height_at`, :meth:`normal_at`, :meth:`part_at`) under points (N, 2) [m]
        in one pass over the parts."""
        z, normals = self._tops(xy_in_world)
        top = np.argmax(z, axis=0)
        height = z.max(axis=0)
        return height, normals[top, np.arange(z.shape[1])], np.where(np.isfinite(height), top, -1)

    def normal_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        """Unit normal (N, 3) of the surface that gives :meth:`height_at`; NaN over a void."""
        z, normals = self._tops(xy_in_world)
        return normals[np.argmax(z, axis=0), np.arange(z.shape[1])]

    def part_at(self, xy_in_world: np.ndarray) -> np.ndarray:
        """Which part gives :meth:`height_at` under points (N, 2) [m], shape (N,) int: the
        floor, the height map, the boxes, the cylinders, numbered in that order over the
        parts present (the first of equal tops); -1 over a void."""
        z, _ = self._tops(xy_in_world)
        part = np.argmax(z, axis=0)
        return np.where(np.isfinite(z.max(axis=0)), part, -1)

    def part_names(self) -> list[str]:
        """The names of the parts :meth:`part_at` numbers ("floor", "height map", "box 0",
        "cylinder 2"), in its order."""
        return (
            (["floor"] if self.floor_z is not None else [])
            + (["height map"] if self.heightmap is not None else [])
            + [f"box {i}" for i in range(len(self.boxes))]
            + [f"cylinder {i}" for i in range(len(self.cylinders))]
        )

    def part_maps(self) -> list[TerrainMap]:
        """Each part alone as a TerrainMap, in :meth:`part_names` order (which part is
        nearest a shape, for a refusal)."""
        return (
            ([TerrainMap(floor_z=self.floor_z)] if self.floor_z is not None else [])
            + ([TerrainMap(None, heightmap=self.heightmap)] if self.heightmap is not None else [])
            + [TerrainMap(None, boxes=(box,)) for box in self.boxes]
            + [TerrainMap(None, cylinders=(cylinder,)) for cylinder in self.cylinders]
        )

    def describe_at(self, xy_in_world: np.ndarray) -> str:
        """What lies under the point (2,) [m], for a refusal: "a void", a part's name
        (:meth:`part_names`), or the height map's cell ("height map cell (row r, column c)")."""
        xy = np.asarray(xy_in_world, dtype=float).reshape(1, 2)
        part = int(self.part_at(xy)[0])
        if part < 0:
            return "a void"
        name = self.part_names()[part]
        if name == "height map" and self.heightmap is not None:
            row, column = self.heightmap.cell_at(xy[0])
            return f"height map cell (row {row}, column {column})"
        return name

    def label(self) -> str:
        """How a refusal names this terrain: "terrain file NAME", or "terrain" unnamed."""
        return f"terrain file {self.name}" if self.name else "terrain"

    def lowest_clearance(self, points_in_world: np.ndarray) -> np.ndarray:
        """Signed height [m] of points (N, 3) above the ground under them, shape (N,):
        negative below the top the ground shows from above (inside a box included); +inf
        over a void."""
        pts = np.asarray(points_in_world, dtype=float).reshape(-1, 3)
        return pts[:, 2] - self.height_at(pts[:, :2])

    def sphere_clearance(
        self, center_in_world: np.ndarray, radius_m: np.ndarray | float = 0.0
    ) -> np.ndarray:
        """Signed clearance [m] of spheres (centres (N, 3) in W, radii (N,) or one [m]) from
        the terrain's solids, shape (N,): the least over the parts of the centre's distance
        to the part less the radius; negative: the sphere enters the part. Unlike
        :meth:`lowest_clearance` (the height above the top under the centre) it sees side
        faces: a sphere beside a riser, its centre outside the box's footprint, is measured
        to the riser. Floor: the half-space under ``floor_z`` (z - floor_z). Boxes and
        cylinders: their exact signed distance (planner/terrain/shapes.py). Height map: the
        height above its highest point under the centre and HEIGHTMAP_DISC_DIRECTIONS points
        on the circle of the radius around it (a disc sampled, not an exact distance). No
        part: +inf."""
        pts = np.asarray(center_in_world, dtype=float).reshape(-1, 3)
        radius = np.broadcast_to(np.asarray(radius_m, dtype=float), (len(pts),))
        distance = np.full(len(pts), np.inf)
        if self.floor_z is not None:
            distance = np.minimum(distance, pts[:, 2] - float(self.floor_z))
        if self.heightmap is not None:
            angles = 2.0 * np.pi * np.arange(HEIGHTMAP_DISC_DIRECTIONS) / HEIGHTMAP_DISC_DIRECTIONS
            unit = np.vstack([np.zeros(2), np.column_stack([np.cos(angles), np.sin(angles)])])
            disc = pts[:, None, :2] + radius[:, None, None] * unit[None]  # (N, D+1, 2)
            top = self.heightmap.top_at(disc.reshape(-1, 2))[0].reshape(disc.shape[:2])
            distance = np.minimum(distance, pts[:, 2] - top.max(axis=1))
        solids: tuple[Box | Cylinder, ...] = (*self.boxes, *self.cylinders)
        for solid in solids:
            distance = np.minimum(distance, solid.signed_distance(pts))
        return distance - radius

    def allows_footholds(self, xy_in_world: np.ndarray) -> np.ndarray:
        """Whether a foot may stand over each point (N, 2) or (N, 3) [m], shape (N,): there
        is ground under it and it keeps ``forbidden_clearance_m`` from every forbidden
        polygon (planner.terrain.forbidden.ForbiddenPolygons.clearances)."""
        pts = np.asarray(xy_in_world, dtype=float)
        pts = pts.reshape(-1, pts.shape[-1])
        ground = np.isfinite(self.height_at(pts[:, :2]))
        return ground & (self._forbidden.clearances(pts) >= self.forbidden_clearance_m)

    def allows_foothold(self, position_foot_in_world: np.ndarray) -> bool:
        """:meth:`allows_footholds` of one foothold (3,) in W [m]."""
        return bool(self.allows_footholds(np.reshape(position_foot_in_world, (1, -1)))[0])

    def surfaces(self) -> list[Surface]:
        """The flat top faces a foot may use: the floor (a square of half side
        FLOOR_SURFACE_HALF_SIDE_M), each box's and each cylinder's top. The height map's
        triangles are not listed (ask :meth:`height_at` / :meth:`normal_at`); forbidden
        polygons are not cut out (ask :meth:`allows_footholds`)."""
        out = []
        if self.floor_z is not None:
            s = FLOOR_SURFACE_HALF_SIDE_M
            square = np.array([[-s, -s], [s, -s], [s, s], [-s, s]])
            out.append(
                Surface(
                    np.column_stack([square, np.full(4, float(self.floor_z))]),
                    np.array([0.0, 0.0, 1.0]),
                    "floor",
                )
            )
        out += [box.surface(f"box {i}") for i, box in enumerate(self.boxes)]
        out += [cyl.surface(f"cylinder {i}") for i, cyl in enumerate(self.cylinders)]
        return out

    def obstacles(self) -> list[str]:
        """What today's gaits cannot walk, in words ("2 boxes", "a height map", "no
        floor"); empty for a level floor with forbidden polygons."""
        found = [
            f"{len(parts)} {one if len(parts) == 1 else many}"
            for parts, one, many in (
                (self.boxes, "box", "boxes"),
                (self.cylinders, "cylinder", "cylinders"),
            )
            if parts
        ]
        if self.heightmap is not None:
            found.append("a height map")
        if self.floor_z is None:
            found.append("no floor")
        return found

    def level_terrain(self) -> Terrain:
        """The terrain today's gaits plan on: the level floor (FlatGround) with the
        forbidden polygons (ForbiddenPolygons, the ditch's terrain), exactly as if they were
        passed to plan_path.

        Raises:
            TerrainNotWalkableError: boxes, cylinders, a height map or no floor.
        """
        found = self.obstacles()
        if found or self.floor_z is None:
            what = f"terrain file {self.name}" if self.name else "terrain"
            raise TerrainNotWalkableError(
                f"{what}: {', '.join(found)}: stairs/boxes need foothold search on surfaces: "
                "not built yet (today's gaits walk a level floor with forbidden regions)"
            )
        ground = FlatGround(float(self.floor_z))
        if not self.forbidden_xy_in_world:
            return ground
        return ForbiddenPolygons(
            self.forbidden_xy_in_world, clearance_m=self.forbidden_clearance_m, ground=ground
        )

    def to_document(self) -> dict[str, Any]:
        """The terrain as terrain-file content (plain JSON types, the height map inline):
        what plan.json records; :func:`planner.terrain.terrain_file.terrain_from_document`
        reads it back."""
        return {
            "floor": None if self.floor_z is None else float(self.floor_z),
            "boxes": [
                {
                    "center": [float(v) for v in b.center_in_world],
                    "size": [float(v) for v in b.size],
                    "rpy": [float(v) for v in b.rpy_deg],
                }
                for b in self.boxes
            ],
            "cylinders": [
                {
                    "center": [float(v) for v in c.center_in_world],
                    "radius": float(c.radius),
                    "height": float(c.height),
                }
                for c in self.cylinders
            ],
            "forbidden": [np.asarray(p, dtype=float).tolist() for p in self.forbidden_xy_in_world],
            "heightmap": None if self.heightmap is None else self.heightmap.to_document(),
        }


def gait_terrain(terrain: Terrain) -> Terrain:
    """The terrain the gaits plan on for ``terrain``: for a TerrainMap with only a floor its
    :meth:`TerrainMap.level_terrain` (level ground, planned as before), for one with boxes,
    cylinders, a height map, forbidden polygons or no floor the map itself (its footholds
    are searched on its surfaces, around its forbidden polygons,
    planner/gaits/surface_footholds.py: ForbiddenPolygons would refuse a foothold in one
    instead of moving it, so the thesis's ditch file at h = 0.4 m was refused); any other
    Terrain itself.

    Raises:
        TerrainNotWalkableError: nothing under the start (START_XY_IN_WORLD): no floor there.
    """
    if not isinstance(terrain, TerrainMap):
        return terrain
    if not np.isfinite(terrain.height_at(np.array([START_XY_IN_WORLD]))[0]):
        what = f"terrain file {terrain.name}" if terrain.name else "terrain"
        raise TerrainNotWalkableError(
            f"{what}: floor: null, and nothing lies under the start "
            f"({START_XY_IN_WORLD[0]:g}, {START_XY_IN_WORLD[1]:g}) m, where the robot stands "
            "first: put a box or a post under it"
        )
    if not terrain.obstacles() and not terrain.forbidden_xy_in_world:
        return terrain.level_terrain()
    return terrain
