"""Scene content of animation.html: the robot's kinematic tree, markers, camera.

The robot is mirrored joint by joint (stack-notes.md: animating one rotation per joint is
~3x smaller than animating every geometry's pose). For a revolute joint j with parent p:

    .../<p link>/<joint>        static: jointPlacement[j] @ R_align   (R_align z = joint axis)
    .../<joint>/q               animated: rotation about its z axis = q_j [rad]
    .../<joint>/q/link          static: R_align^T, so the link's frame is Pinocchio's joint frame
    .../<joint>/q/link/<geom>   visual geometry at its placement (robot.visual_model)

Above the tree, ``ground`` carries the CoG's ground projection (x, y, 0) and the yaw, and
``ground/base`` the CoG height z: the base frame B in W is ``ground @ base``;
``base/urdf_root`` places the URDF root link at -position_body_com_in_base (zero for SILO4).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import umsgpack

from silo4kin.errors import Silo4Error
from silo4kin.frames import homogeneous
from silo4kin.robot import Robot
from viz.animation.mesh_budget import (
    MESH_BUDGET_BYTES,
    MESH_GREY,
    RobotMeshes,
    fit_meshes,
    mesh_path,
)
from viz.animation.recorder import (
    EXT_UINT8,
    RecorderWindow,
    color_to_int,
    material,
    matrix_to_js,
    scene_object,
)
from viz.animation.stick_figure import add_stick_figure

#: A joint's local rotation axis is taken as unit when |axis| = 1 within this [rad/rad]
#: (Pinocchio joint transforms are exact to ~1e-15).
AXIS_TOLERANCE = 1e-9
#: Number of support-polygon edge objects (a quadruped's polygon has at most 4 edges).
MAX_SUPPORT_EDGES = 4
#: Heights of flat markers above the ground, to avoid z-fighting with it [m].
Z_LINES = 0.003
Z_MARKERS = 0.004
#: Colours.
COLOR_STANCE = 0xD62728
COLOR_SUPPORT = 0xC2185B
COLOR_PATH = 0x2CA02C
COLOR_COG = 0xFF7F0E
COLOR_FOOTHOLD = 0x1F3A93
COLOR_GROUND = 0xE8E8E0
COLOR_SWING = 0xF5C400


@dataclass
class RobotTree:
    """Scene paths of the animated nodes."""

    ground_path: str
    base_path: str
    joint_rotation_paths: dict[str, str] = field(default_factory=dict)
    stance_marker_paths: list[str] = field(default_factory=list)
    swing_marker_paths: list[str] = field(default_factory=list)
    robot_path: str = ""


def _rotation_z_to(axis: np.ndarray) -> np.ndarray:
    """A rotation matrix (3, 3) taking +z to the unit vector ``axis``."""
    z = np.array([0.0, 0.0, 1.0])
    c = float(np.dot(z, axis))
    if c > 1.0 - AXIS_TOLERANCE:
        return np.eye(3)
    if c < -1.0 + AXIS_TOLERANCE:
        return np.diag([1.0, -1.0, -1.0])
    v = np.cross(z, axis)
    return np.asarray(pin.exp3(v / np.linalg.norm(v) * np.arccos(np.clip(c, -1.0, 1.0))))


def joint_axes(model: pin.Model) -> dict[int, np.ndarray]:
    """Local rotation axis of every joint (in its own frame), shape (3,) each.

    Raises:
        Silo4Error: a joint is not a 1-dof revolute joint.
    """
    data = model.createData()
    axes = {}
    for j in range(1, model.njoints):
        if model.nqs[j] != 1 or model.nvs[j] != 1:
            raise Silo4Error(
                f"joint {model.names[j]!r} has nq={model.nqs[j]}; the animation "
                "supports 1-dof revolute joints only"
            )
        q = pin.neutral(model)
        q[model.idx_qs[j]] = 1.0  # [rad]
        pin.forwardKinematics(model, data, q)
        local = (data.oMi[model.parents[j]] * model.jointPlacements[j]).inverse() * data.oMi[j]
        axis = np.asarray(pin.log3(local.rotation))
        if (
            np.linalg.norm(local.translation) > AXIS_TOLERANCE
            or abs(np.linalg.norm(axis) - 1.0) > AXIS_TOLERANCE
        ):
            raise Silo4Error(
                f"joint {model.names[j]!r} is not a revolute joint; the animation "
                "supports revolute joints only"
            )
        axes[j] = axis / np.linalg.norm(axis)
    return axes


def _simplified_mesh(geom: Any, uuid: str, stl: bytes) -> dict:
    """A meshcat set_object payload of a simplified mesh (binary STL, scale already applied)."""
    rgba = np.asarray(geom.meshColor, dtype=float)
    colour = MESH_GREY if np.all(rgba == 1.0) else color_to_int(rgba[:3])
    return scene_object(
        uuid,
        "Mesh",
        {"type": "_meshfile_geometry", "format": "stl", "data": umsgpack.Ext(EXT_UINT8, stl)},
        material("", colour, opacity=float(rgba[3])),
    )


def _geometry(geom: Any, uuid: str) -> dict | None:
    """A meshcat set_object payload for one pinocchio GeometryObject, or None if unsupported."""
    shape = geom.geometry
    kind = type(shape).__name__
    rgba = np.asarray(geom.meshColor, dtype=float)
    mat = material("", color_to_int(rgba[:3]), opacity=float(rgba[3]))
    if kind == "Box":
        w, h, d = (2.0 * np.asarray(shape.halfSide)).tolist()
        return scene_object(
            uuid, "Mesh", {"type": "BoxGeometry", "width": w, "height": h, "depth": d}, mat
        )
    if kind == "Sphere":
        return scene_object(
            uuid,
            "Mesh",
            {
                "type": "SphereGeometry",
                "radius": float(shape.radius),
                "widthSegments": 16,
                "heightSegments": 12,
            },
            mat,
        )
    if kind in ("Cylinder", "Capsule"):
        # three.js cylinders run along y; URDF cylinders along z: rotate by +90 deg about x.
        return scene_object(
            uuid,
            "Mesh",
            {
                "type": "CylinderGeometry",
                "radiusTop": float(shape.radius),
                "radiusBottom": float(shape.radius),
                "height": 2.0 * float(shape.halfLength),
                "radialSegments": 24,
            },
            mat,
            intrinsic=homogeneous(pin.utils.rotate("x", np.pi / 2)),
        )
    mesh_path = Path(getattr(geom, "meshPath", "") or "")
    fmt = mesh_path.suffix.lower().lstrip(".")
    if fmt in ("stl", "obj", "dae") and mesh_path.is_file():
        data: Any = (
            umsgpack.Ext(EXT_UINT8, mesh_path.read_bytes())
            if fmt == "stl"
            else mesh_path.read_text(encoding="utf-8", errors="replace")
        )
        scale = np.diag(np.append(np.asarray(geom.meshScale, dtype=float), 1.0))
        return scene_object(
            uuid,
            "Mesh",
            {"type": "_meshfile_geometry", "format": fmt, "data": data},
            mat,
            intrinsic=scale,
        )
    warnings.warn(
        f"animation: visual {geom.name!r} ({kind}, {mesh_path or 'no file'}) is not "
        "a box, sphere, cylinder or readable stl/obj/dae mesh; left out",
        stacklevel=3,
    )
    return None


def add_robot_tree(
    rec: RecorderWindow, robot: Robot, root: str, meshes: RobotMeshes | None = None
) -> RobotTree:
    """Record the robot's visuals as a tree of joint nodes; return the animated paths.

    ``meshes``: how the meshes fit the budget (default: :func:`fit_meshes` of ``robot``).
    """
    model = robot.model
    meshes = meshes if meshes is not None else fit_meshes(robot, MESH_BUDGET_BYTES)
    tree = RobotTree(ground_path=f"{root}/ground", base_path=f"{root}/ground/base")
    # The trajectory's base frame B sits at the body CoG; the URDF root link may not
    # (tests/robots/mantis.urdf). Place the root at -position_body_com_in_base in B.
    root_path = f"{tree.base_path}/urdf_root"
    tree.robot_path = root_path
    rec.record(
        {
            "type": "set_transform",
            "path": root_path,
            "matrix": matrix_to_js(
                homogeneous(np.eye(3), -np.asarray(robot.position_body_com_in_base, dtype=float))
            ),
        }
    )
    link_path = {0: root_path}
    for j, axis in joint_axes(model).items():  # parents come before children in Pinocchio
        name = model.names[j]
        align = _rotation_z_to(axis)
        joint_path = f"{link_path[model.parents[j]]}/{name}"
        rec.record(
            {
                "type": "set_transform",
                "path": joint_path,
                "matrix": matrix_to_js(model.jointPlacements[j].homogeneous @ homogeneous(align)),
            }
        )
        tree.joint_rotation_paths[name] = f"{joint_path}/q"
        link_path[j] = f"{joint_path}/q/link"
        rec.record(
            {
                "type": "set_transform",
                "path": link_path[j],
                "matrix": matrix_to_js(homogeneous(align.T)),
            }
        )
    if meshes.stick_figure:
        add_stick_figure(rec, robot, link_path)
    for geom in robot.visual_model.geometryObjects:
        path = f"{link_path[geom.parentJoint]}/{geom.name}"
        if meshes.stick_figure and mesh_path(geom) is not None:
            continue  # drawn by the stick figure instead
        stl = meshes.stl.get(geom.name)
        obj = _geometry(geom, uuid=path) if stl is None else _simplified_mesh(geom, path, stl)
        if obj is not None:
            rec.record({"type": "set_object", "path": path, "object": obj})
            rec.record(
                {
                    "type": "set_transform",
                    "path": path,
                    "matrix": matrix_to_js(geom.placement.homogeneous),
                }
            )
    radius = 0.035  # [m] stance highlight, a little larger than SILO4's 25 mm foot spheres
    for leg in robot.legs:
        frame = model.frames[model.getFrameId(leg.foot_frame)]
        for kind, color, paths in (
            ("stance", COLOR_STANCE, tree.stance_marker_paths),
            ("swing", COLOR_SWING, tree.swing_marker_paths),
        ):
            path = f"{link_path[frame.parentJoint]}/{kind}_{leg.name}"
            rec.record(
                {
                    "type": "set_transform",
                    "path": path,
                    "matrix": matrix_to_js(frame.placement.homogeneous),
                }
            )
            rec.record(
                {
                    "type": "set_object",
                    "path": f"{path}/marker",
                    "object": scene_object(
                        f"{path}/marker",
                        "Mesh",
                        {
                            "type": "SphereGeometry",
                            "radius": radius,
                            "widthSegments": 16,
                            "heightSegments": 12,
                        },
                        material("", color),
                    ),
                }
            )
            paths.append(path)
    marker = f"{tree.ground_path}/cog_projection"
    rec.record(
        {
            "type": "set_object",
            "path": marker,
            "object": scene_object(
                marker,
                "Mesh",
                {
                    "type": "CylinderGeometry",
                    "radiusTop": 0.03,
                    "radiusBottom": 0.03,
                    "height": 0.004,
                    "radialSegments": 24,
                },
                material("", COLOR_COG),
                intrinsic=homogeneous(pin.utils.rotate("x", np.pi / 2), (0.0, 0.0, Z_MARKERS)),
            ),
        }
    )
    return tree
