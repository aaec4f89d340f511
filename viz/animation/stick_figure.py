"""The robot drawn as a stick figure of primitives (viz/animation/scene.py): when its
meshes cannot be read or nothing fits the page's budget."""

from __future__ import annotations

import numpy as np

from silo4kin.frames import homogeneous
from silo4kin.robot import Robot
from viz.animation.recorder import (
    RecorderWindow,
    material,
    scene_object,
)

#: Stick figure (when the meshes cannot fit MESH_BUDGET_BYTES: viz/animation/mesh_budget.py):
#: link radius and body box height [m].
STICK_RADIUS_M = 0.012
STICK_BODY_HEIGHT_M = 0.06
STICK_COLOUR = 0x7A8699


def _segment(
    rec: RecorderWindow, parent: str, name: str, end: np.ndarray, radius: float, colour: int
) -> None:
    """A cylinder from the origin of ``parent`` to ``end`` (3,) [m] in its frame."""
    length = float(np.linalg.norm(end))
    if length < 1e-6:
        return
    y = np.asarray(end, float) / length  # three.js cylinders run along y
    helper = np.array([1.0, 0.0, 0.0]) if abs(y[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    x = np.cross(y, helper)
    x /= np.linalg.norm(x)
    rot = np.column_stack([x, y, np.cross(x, y)])
    path = f"{parent}/{name}"
    rec.record(
        {
            "type": "set_object",
            "path": path,
            "object": scene_object(
                path,
                "Mesh",
                {
                    "type": "CylinderGeometry",
                    "radiusTop": radius,
                    "radiusBottom": radius,
                    "height": length,
                    "radialSegments": 12,
                },
                material("", colour),
                intrinsic=homogeneous(rot, 0.5 * np.asarray(end, float)),
            ),
        }
    )


def add_stick_figure(rec: RecorderWindow, robot: Robot, link_path: dict) -> None:
    """Primitives instead of meshes (RobotMeshes.stick_figure): the body as the box spanned by the
    first joints' origins, each link as a cylinder to its child joint or foot frame."""
    model = robot.model
    tops = np.array(
        [
            model.jointPlacements[j].translation
            for j in range(1, model.njoints)
            if model.parents[j] == 0
        ]
    )
    if len(tops):
        lo, hi = tops.min(axis=0), tops.max(axis=0)
        size = np.maximum(hi - lo, 0.05)
        size[2] = STICK_BODY_HEIGHT_M
        path = f"{link_path[0]}/stick_body"
        rec.record(
            {
                "type": "set_object",
                "path": path,
                "object": scene_object(
                    path,
                    "Mesh",
                    {
                        "type": "BoxGeometry",
                        "width": float(size[0]),
                        "height": float(size[1]),
                        "depth": float(size[2]),
                    },
                    material("", 0x5B6B84),
                    intrinsic=homogeneous(np.eye(3), 0.5 * (lo + hi)),
                ),
            }
        )
    for j in range(1, model.njoints):
        parent = model.parents[j]
        if parent != 0:
            _segment(
                rec,
                link_path[parent],
                f"stick_{model.names[j]}",
                model.jointPlacements[j].translation,
                STICK_RADIUS_M,
                STICK_COLOUR,
            )
    for leg in robot.legs:
        frame = model.frames[model.getFrameId(leg.foot_frame)]
        _segment(
            rec,
            link_path[frame.parentJoint],
            f"stick_{leg.name}_foot",
            frame.placement.translation,
            STICK_RADIUS_M,
            STICK_COLOUR,
        )
