"""A run's terrain in MuJoCo: the floor plane, boxes, cylinders and a height field, built
from the terrain document plan.json records (``inputs.terrain``, the terrain file's content
with its height map inline: docs/terrain.md).

The sim reads the document itself (it does not import the planner's terrain code), so a ray
cast into this model (``mujoco.mj_ray``) is an independent check of the planner's
``TerrainMap.height_at``: tests/test_terrain_sim.py. Every geom is raised by ``z_shift_m``
[m], the distance from the planner's ground to the sim's floor under a standing foot frame
(silo4sim/model.py: foot_contact_offset_m - foot radius), and collides as the floor does.

MuJoCo's height field (``hfield``) spans nrow x ncol samples over [-size_x, size_x] x
[-size_y, size_y] about its geom, row 0 at -y, its elevations normalised to [0, 1] and scaled
by size_z above the geom: the map's sample (r, c) at origin + resolution (c, r) is vertex
(r, c) of a field centred on the grid.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .errors import import_mujoco

#: The terrain of a run without one: the floor at the planner's ground.
FLAT_FLOOR: Mapping[str, Any] = {"floor": 0.0}
#: Depth of the height field's base below its lowest point [m] (MuJoCo's size[3] > 0).
HFIELD_BASE_DEPTH_M = 0.05
#: Colour of terrain solids in MuJoCo's viewer (RGBA).
TERRAIN_RGBA = [0.62, 0.58, 0.5, 1.0]


def _rotation_rpy_deg(rpy_deg: Any) -> np.ndarray:
    """R = R_z(yaw) R_y(pitch) R_x(roll) of roll, pitch, yaw [deg] (URDF's rpy), (3, 3)."""
    roll, pitch, yaw = np.radians(np.asarray(rpy_deg, dtype=float))
    c, s = np.cos, np.sin
    rx = np.array([[1, 0, 0], [0, c(roll), -s(roll)], [0, s(roll), c(roll)]])
    ry = np.array([[c(pitch), 0, s(pitch)], [0, 1, 0], [-s(pitch), 0, c(pitch)]])
    rz = np.array([[c(yaw), -s(yaw), 0], [s(yaw), c(yaw), 0], [0, 0, 1]])
    return rz @ ry @ rx


def add_terrain(
    spec: Any, document: Mapping[str, Any], *, z_shift_m: float, friction: list[float]
) -> list[str]:
    """Add the terrain of ``document`` to ``spec``'s world body (module docstring); returns
    the names of the geoms added ("floor", "box0", "cylinder0", "heightmap")."""
    mujoco = import_mujoco()

    shift = np.array([0.0, 0.0, float(z_shift_m)])
    common = dict(contype=1, conaffinity=2, friction=friction, rgba=TERRAIN_RGBA)
    names = []
    floor = document.get("floor", 0.0)
    if floor is not None:
        spec.worldbody.add_geom(
            name="floor",
            type=mujoco.mjtGeom.mjGEOM_PLANE,
            size=[0, 0, 1],
            pos=[0.0, 0.0, float(floor) + z_shift_m],
            **{**common, "rgba": [0.8, 0.8, 0.8, 1]},
        )
        names.append("floor")
    for i, box in enumerate(document.get("boxes") or ()):
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, _rotation_rpy_deg(box.get("rpy", (0, 0, 0))).ravel())
        spec.worldbody.add_geom(
            name=f"box{i}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=0.5 * np.asarray(box["size"], dtype=float),
            pos=np.asarray(box["center"], dtype=float) + shift,
            quat=quat,
            **common,
        )
        names.append(f"box{i}")
    for i, cyl in enumerate(document.get("cylinders") or ()):
        spec.worldbody.add_geom(
            name=f"cylinder{i}",
            type=mujoco.mjtGeom.mjGEOM_CYLINDER,
            size=[float(cyl["radius"]), 0.5 * float(cyl["height"]), 0.0],
            pos=np.asarray(cyl["center"], dtype=float) + shift,
            **common,
        )
        names.append(f"cylinder{i}")
    heightmap = document.get("heightmap")
    if heightmap is not None:
        _add_heightfield(spec, heightmap, 0.0 if floor is None else float(floor), shift, common)
        names.append("heightmap")
    return names


def _add_heightfield(
    spec: Any, heightmap: Mapping[str, Any], base_z: float, shift: np.ndarray, common: dict
) -> None:
    """The height map as an hfield asset and its geom (module docstring)."""
    mujoco = import_mujoco()

    heights = np.asarray(heightmap["heights"], dtype=float)  # (R, C), rows along y
    rows, cols = heights.shape
    resolution = float(heightmap["resolution"])
    origin = np.asarray(heightmap["origin"], dtype=float)
    low, high = float(heights.min()), float(heights.max())
    span = high - low if high > low else 1.0
    half = 0.5 * resolution * np.array([cols - 1, rows - 1], dtype=float)
    field = spec.add_hfield(
        name="terrain_heightmap",
        nrow=rows,
        ncol=cols,
        size=[half[0], half[1], span, HFIELD_BASE_DEPTH_M],
    )
    field.userdata = ((heights - low) / span).ravel().tolist()
    spec.worldbody.add_geom(
        name="heightmap",
        type=mujoco.mjtGeom.mjGEOM_HFIELD,
        hfieldname="terrain_heightmap",
        pos=[origin[0] + half[0], origin[1] + half[1], base_z + low + shift[2]],
        **common,
    )
