"""The terrain in animation.html: boxes, cylinders, the height map as a triangle mesh and the
forbidden regions shaded (a :class:`~planner.terrain.terrain_map.TerrainMap`, docs/terrain.md).

Every object sits under ``{root}/terrain/`` in the world frame W [m]: ``box{i}``,
``cylinder{i}``, ``heightmap`` (the map's own triangulation, planner/terrain/heightmap.py,
so the mesh is the ground the planner and MuJoCo use) and ``forbidden{i}`` (the polygon,
clipped to the drawn patch, a few millimetres above the ground under its centre). The
ground patch and grid of viz/animation/markers.py are moved to the terrain's floor height
(hidden where there is no floor).
"""

from __future__ import annotations

import numpy as np
import umsgpack

from planner.terrain.terrain_map import TerrainMap
from viz.animation.recorder import (
    RecorderWindow,
    find_node,
    float32_ext,
    material,
    matrix_to_js,
    scene_object,
)

#: Colours of the terrain's solids, its height map and its forbidden regions.
COLOR_SOLID = 0x9E9480
COLOR_HEIGHTMAP = 0xA89F86
COLOR_FORBIDDEN = 0xD62728
#: Opacity of a forbidden region's shading.
FORBIDDEN_OPACITY = 0.45
#: Height of the shading above the ground [m] (over the ground patch, under the lines).
Z_FORBIDDEN = 0.002
#: Forbidden regions are drawn this far around the CoG's path [m] (a ditch is a strip
#: 2e7 m long).
FORBIDDEN_MARGIN_M = 1.5
#: Segments of a drawn cylinder's round side.
CYLINDER_SEGMENTS = 32


def _transform(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = rotation, position
    return out


def triangle_mesh(vertices: np.ndarray) -> dict:
    """A BufferGeometry of triangles ``vertices`` (T, 3, 3) [m] with flat per-face normals."""
    tri = np.asarray(vertices, dtype=float).reshape(-1, 3, 3)
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)

    def attribute(values: np.ndarray) -> dict:
        return {
            "itemSize": 3,
            "type": "Float32Array",
            "array": float32_ext(values.reshape(-1, 3)),
            "normalized": False,
        }

    return {
        "type": "BufferGeometry",
        "data": {
            "attributes": {
                "position": attribute(tri),
                "normal": attribute(np.repeat(normal, 3, axis=0)),
            }
        },
    }


def heightmap_triangles(terrain: TerrainMap) -> np.ndarray:
    """The height map's triangles (2 (R-1)(C-1), 3, 3) in W [m], split as the map is (the
    diagonal from sample (r, c) to (r+1, c+1)), counter-clockwise seen from above."""
    hm = terrain.heightmap
    if hm is None:
        return np.zeros((0, 3, 3))
    rows, cols = hm.heights.shape
    x = hm.origin_in_world[0] + hm.resolution * np.arange(cols)
    y = hm.origin_in_world[1] + hm.resolution * np.arange(rows)
    gx, gy = np.meshgrid(x, y)
    points = np.stack([gx, gy, hm.base_z + hm.heights], axis=-1)  # (R, C, 3)
    p00, p10 = points[:-1, :-1], points[:-1, 1:]
    p01, p11 = points[1:, :-1], points[1:, 1:]
    lower = np.stack([p00, p10, p11], axis=-2).reshape(-1, 3, 3)
    upper = np.stack([p00, p11, p01], axis=-2).reshape(-1, 3, 3)
    return np.concatenate([lower, upper])


def clip_polygon(polygon_xy: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """A convex polygon (M, 2) [m] clipped to the rectangle lo..hi (Sutherland-Hodgman),
    (K, 2); empty when it lies outside."""
    pts = [np.asarray(p, dtype=float) for p in polygon_xy]
    for axis in (0, 1):
        for bound, keep in ((lo[axis], 1.0), (hi[axis], -1.0)):
            out: list[np.ndarray] = []
            for a, b in zip(pts, pts[1:] + pts[:1]):
                da, db = keep * (a[axis] - bound), keep * (b[axis] - bound)
                if da >= 0:
                    out.append(a)
                if da * db < 0:
                    out.append(a + (b - a) * (da / (da - db)))
            pts = out
            if not pts:
                return np.zeros((0, 2))
    return np.array(pts)


def lift_ground(rec: RecorderWindow, root: str, floor_z: float) -> None:
    """Raise the ground patch and its grid (viz/animation/markers.py draws them at z = 0)
    by ``floor_z`` [m], so they sit at the terrain's floor: the patch keeps its recorded
    transform with ``floor_z`` added to its z, the grid gets the translation (0, 0, floor_z)."""
    patch = find_node(rec.tree, [p for p in f"{root}/ground_patch".split("/") if p])
    if patch.transform is not None:
        recorded = umsgpack.unpackb(patch.transform)["matrix"]
        matrix = np.array(recorded, dtype=float).reshape(4, 4).T  # column-major
        matrix[2, 3] += floor_z
        rec.record(
            {
                "type": "set_transform",
                "path": f"{root}/ground_patch",
                "matrix": matrix_to_js(matrix),
            }
        )
    grid = np.eye(4)
    grid[2, 3] = floor_z
    rec.record({"type": "set_transform", "path": f"{root}/grid", "matrix": matrix_to_js(grid)})


def add_terrain_scene(
    rec: RecorderWindow, root: str, terrain: TerrainMap, path_xy_in_world: np.ndarray
) -> list[str]:
    """Record the terrain's objects (module docstring), put the ground patch and its grid
    at the floor's height (:func:`lift_ground`), or hide them over a terrain without a
    floor; forbidden regions are clipped to
    the points ``path_xy_in_world`` (N, 2) [m] (the CoG's path) plus FORBIDDEN_MARGIN_M.
    Returns the scene paths recorded."""
    if terrain.floor_z is None:  # a void: no ground patch nor grid (viz/animation/markers.py)
        for name in ("ground_patch", "grid"):
            rec.record(
                {
                    "type": "set_property",
                    "path": f"{root}/{name}",
                    "property": "visible",
                    "value": False,
                }
            )
    elif terrain.floor_z != 0.0:
        lift_ground(rec, root, float(terrain.floor_z))
    xy = np.asarray(path_xy_in_world, dtype=float).reshape(-1, 2)
    lo, hi = xy.min(axis=0) - FORBIDDEN_MARGIN_M, xy.max(axis=0) + FORBIDDEN_MARGIN_M
    paths: list[str] = []

    def put(name: str, obj_kind: str, geometry: dict, mat: dict, transform=None, intrinsic=None):
        path = f"{root}/terrain/{name}"
        rec.record(
            {
                "type": "set_object",
                "path": path,
                "object": scene_object(path, obj_kind, geometry, mat, intrinsic),
            }
        )
        if transform is not None:
            rec.record({"type": "set_transform", "path": path, "matrix": matrix_to_js(transform)})
        paths.append(path)

    for i, box in enumerate(terrain.boxes):
        width, height, depth = (float(v) for v in box.size)
        put(
            f"box{i}",
            "Mesh",
            {"type": "BoxGeometry", "width": width, "height": height, "depth": depth},
            material("", COLOR_SOLID),
            _transform(box.rotation_box_to_world, box.center_in_world),
        )
    for i, cyl in enumerate(terrain.cylinders):
        # three.js cylinders run along y: +90 deg about x stands them along z
        stand = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])
        put(
            f"cylinder{i}",
            "Mesh",
            {
                "type": "CylinderGeometry",
                "radiusTop": float(cyl.radius),
                "radiusBottom": float(cyl.radius),
                "height": float(cyl.height),
                "radialSegments": CYLINDER_SEGMENTS,
            },
            material("", COLOR_SOLID),
            _transform(np.eye(3), cyl.center_in_world),
            stand,
        )
    triangles = heightmap_triangles(terrain)
    if len(triangles):
        put("heightmap", "Mesh", triangle_mesh(triangles), material("", COLOR_HEIGHTMAP))
    for i, polygon in enumerate(terrain.forbidden_xy_in_world):
        shown = clip_polygon(polygon, lo, hi)
        if len(shown) < 3:
            continue
        z = terrain.height_at(shown.mean(axis=0).reshape(1, 2))[0]
        z = (0.0 if not np.isfinite(z) else float(z)) + Z_FORBIDDEN
        fan = np.array([[shown[0], shown[k], shown[k + 1]] for k in range(1, len(shown) - 1)])
        tri = np.concatenate([fan, np.full((len(fan), 3, 1), z)], axis=-1)
        put(
            f"forbidden{i}",
            "Mesh",
            triangle_mesh(tri),
            material("", COLOR_FORBIDDEN, opacity=FORBIDDEN_OPACITY),
        )
    return paths


def recorded_terrain(plan_document: dict) -> TerrainMap | None:
    """The terrain a run's plan.json records (``inputs.terrain``), or None (flat ground).

    Raises:
        planner.terrain.TerrainFileError: a recorded terrain that does not read (named).
    """
    from planner.terrain.terrain_file import terrain_from_document

    document = (plan_document.get("inputs") or {}).get("terrain")
    return None if document is None else terrain_from_document(document, name="plan.json")
