"""How the robot's visual meshes fit the animation's size budget (MESH_BUDGET_BYTES).

The page embeds every visual geometry's mesh once per geometry object (go2's hip.dae four
times). When those bytes fit the budget, the files go in as they are. When they do not
(example-robot-data: go2's 5.3 MB of COLLADA files, 11 MB as embedded; solo12 2.5 MB of
STL), every mesh is decimated to the same fraction of its triangles by quadric edge
collapse (fast-simplification; where it stops short, as on meshes of many small open
parts, vertex clustering takes it the rest of the way) and embedded as binary STL (50 bytes
per triangle), the fraction chosen so the total fits. The triangles are read from the files
with trimesh (and pycollada for COLLADA), every part of a file in the file's frame, times the
URDF's mesh scale: the triangles coal loads for ``robot.visual_model`` index only the first
part of a multi-part COLLADA file (go2's thigh.dae would lose its lower two thirds).
Simplified meshes lose their file's own materials: they are drawn in the URDF's colour, or
MESH_GREY when it gives none.

Only when no fraction fits (or the triangles cannot be read or decimated) does the robot
become a stick figure of primitives (viz/animation/scene.py). Either way the page's legend
and the terminal say what was drawn (:attr:`RobotMeshes.note`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from silo4kin.robot import Robot

#: Largest total size of the visual meshes the animation embeds [bytes]. The page's budget
#: is 4 MB (animation.MAX_HTML_BYTES) with ~0.85 MB of viewer; 1 MB of meshes leaves room
#: for the keyframes of a long path.
MESH_BUDGET_BYTES = 1_000_000
#: Binary STL: an 84-byte header and 50 bytes per triangle [bytes].
STL_HEADER_BYTES = 84
STL_TRIANGLE_BYTES = 50
#: Fewest triangles a simplified mesh keeps; below this a robot is a stick figure instead.
MIN_TRIANGLES_PER_MESH = 12
#: Colour of a simplified mesh whose URDF gives no colour (Pinocchio's default: white).
MESH_GREY = 0xB4BCC8
#: Decimation passes: each rescales the fraction by the bytes it overshot by.
MAX_DECIMATION_PASSES = 4
#: Vertices closer than this are one vertex before simplification [m] (COLLADA parts and
#: seams repeat their shared vertices; 1 um is far below any visual detail).
WELD_TOLERANCE_M = 1e-6
#: Grid sizes tried per mesh when clustering its vertices (bisection on a log scale).
CLUSTER_BISECTIONS = 14
PRIMITIVES = ("Box", "Sphere", "Cylinder", "Capsule")


class MeshesSimplified(UserWarning):
    """What the animation drew instead of the robot's full meshes (printed once per page)."""


@dataclass(frozen=True)
class RobotMeshes:
    """The meshes the animation embeds, by geometry object name.

    Attributes:
        stl: binary STL bytes of every simplified mesh; empty when the files fit as they are
            or the robot is a stick figure.
        stick_figure: meshes left out, primitives drawn instead.
        note: one line for the legend and the terminal; None when the meshes are drawn whole.
        kept_fraction: triangles kept over triangles loaded [0, 1] (1 when whole).
    """

    stl: dict[str, bytes] = field(default_factory=dict)
    stick_figure: bool = False
    note: str | None = None
    kept_fraction: float = 1.0


def mesh_path(geom: Any) -> Path | None:
    """The mesh file of a visual geometry object, or None (a primitive, no readable file)."""
    path = Path(getattr(geom, "meshPath", "") or "")
    if type(geom.geometry).__name__ in PRIMITIVES or not path.is_file():
        return None
    return path


def mesh_bytes(robot: Robot) -> int:
    """Bytes of the mesh files the page would embed as they are: one copy per geometry."""
    return int(
        sum(
            p.stat().st_size
            for g in robot.visual_model.geometryObjects
            if (p := mesh_path(g)) is not None
        )
    )


def fit_meshes(robot: Robot, budget_bytes: int = MESH_BUDGET_BYTES) -> RobotMeshes:
    """Decide how the robot's meshes go into the page within ``budget_bytes`` (module doc)."""
    meshes = [g for g in robot.visual_model.geometryObjects if mesh_path(g) is not None]
    if not meshes or mesh_bytes(robot) <= budget_bytes:
        return RobotMeshes()
    budget_mb = f"{budget_bytes / 1e6:g} MB"
    files = {
        g.name: (str(mesh_path(g)), np.asarray(g.meshScale, dtype=float).tobytes()) for g in meshes
    }  # the four legs share their mesh files
    try:
        triangles = {}
        for g in meshes:
            if files[g.name] not in triangles:
                triangles[files[g.name]] = _triangles(g)
    except ImportError:
        return _stick(
            f"stick figure: meshes over {budget_mb} are simplified with trimesh "
            "and pycollada, not installed (pip install trimesh pycollada)"
        )
    except Exception as exc:  # trimesh and its loaders raise anything on a broken file
        return _stick(f"stick figure: meshes unreadable ({exc})")
    total = sum(len(triangles[files[g.name]][1]) for g in meshes)
    fraction = (budget_bytes - STL_HEADER_BYTES * len(meshes)) / (STL_TRIANGLE_BYTES * total)
    try:
        for _ in range(MAX_DECIMATION_PASSES):
            if fraction * total < MIN_TRIANGLES_PER_MESH * len(meshes):
                return _stick(f"stick figure: the meshes do not fit {budget_mb} even simplified")
            by_file = {
                key: _stl_bytes(*_decimate(v, f, fraction)) for key, (v, f) in triangles.items()
            }
            stl = {g.name: by_file[files[g.name]] for g in meshes}
            size = sum(len(b) for b in stl.values())
            if size <= budget_bytes:
                kept = (
                    sum((len(b) - STL_HEADER_BYTES) // STL_TRIANGLE_BYTES for b in stl.values())
                    / total
                )
                return RobotMeshes(
                    stl=stl,
                    kept_fraction=kept,
                    note=(
                        f"Meshes simplified to {100 * kept:.0f} % of their triangles to fit "
                        f"{budget_mb}."
                    ),
                )
            fraction *= 0.98 * budget_bytes / size
    except (RuntimeError, ValueError) as exc:
        return _stick(f"stick figure: meshes could not be simplified ({exc})")
    return _stick(f"stick figure: the meshes do not fit {budget_mb} even simplified")


def warn_once(meshes: RobotMeshes) -> None:
    """Print the note on the terminal (a MeshesSimplified warning), once per page."""
    if meshes.note is not None:
        warnings.warn(f"animation: {meshes.note}", MeshesSimplified, stacklevel=3)


def _stick(note: str) -> RobotMeshes:
    return RobotMeshes(stick_figure=True, note=note[0].upper() + note[1:], kept_fraction=0.0)


def _triangles(geom: Any) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) [m] and triangles (F, 3) of a visual geometry's mesh: from its file,
    every part in the file's frame (trimesh), times the URDF's mesh scale; from the mesh
    coal loaded when trimesh finds no triangles in the file (anymal's foot.dae)."""
    import trimesh

    mesh: Any = trimesh.load(str(mesh_path(geom)), force="mesh", process=False)  # a Trimesh
    vertices = np.asarray(mesh.vertices, dtype=float).reshape(-1, 3)
    faces = np.asarray(mesh.faces, dtype=np.int64).reshape(-1, 3)
    if len(faces):
        return vertices * np.asarray(geom.meshScale, dtype=float), faces
    shape = geom.geometry  # a coal BVH mesh, mesh scale applied
    vertices = np.asarray(shape.vertices(), dtype=float).reshape(-1, 3)
    faces = np.array(
        [[t[0], t[1], t[2]] for t in (shape.tri_indices(i) for i in range(shape.num_tris))],
        dtype=np.int64,
    ).reshape(-1, 3)
    if not len(faces) or faces.max() >= len(vertices):
        raise ValueError(f"{mesh_path(geom)}: a mesh without triangles")
    return vertices, faces


def _decimate(
    vertices: np.ndarray, faces: np.ndarray, fraction: float
) -> tuple[np.ndarray, np.ndarray]:
    """About ``fraction`` of the triangles of a mesh (at least MIN_TRIANGLES_PER_MESH), by
    quadric edge collapse (fast-simplification) of the mesh with its coincident vertices
    welded (within WELD_TOLERANCE_M), so the parts' seams collapse too."""
    import fast_simplification

    keep = max(MIN_TRIANGLES_PER_MESH, int(fraction * len(faces)))
    if keep >= len(faces):
        return vertices, faces
    cells = np.round((vertices - vertices.min(axis=0)) / WELD_TOLERANCE_M).astype(np.int64)
    _, first, inverse = np.unique(_row_keys(cells), return_index=True, return_inverse=True)
    welded = inverse.reshape(-1)[faces]
    points, out = fast_simplification.simplify(
        vertices[first].astype(np.float32),
        welded.astype(np.int32),
        target_reduction=1.0 - keep / len(faces),
    )
    points, out = np.asarray(points, dtype=float), np.asarray(out, dtype=np.int64)
    return (points, out) if len(out) <= keep else _cluster_to(points, out, keep)


def _cluster_to(
    vertices: np.ndarray, faces: np.ndarray, keep: int
) -> tuple[np.ndarray, np.ndarray]:
    """At most ``keep`` triangles by vertex clustering, for meshes whose edge collapse stops
    short (many small open parts): the smallest grid cell (bisection over
    CLUSTER_BISECTIONS sizes) whose merged vertices leave few enough triangles."""
    diagonal = float(np.linalg.norm(np.ptp(vertices, axis=0))) or 1.0
    lo, hi = np.log(diagonal * 1e-5), np.log(diagonal)
    best = _cluster(vertices, faces, diagonal)
    for _ in range(CLUSTER_BISECTIONS):
        mid = 0.5 * (lo + hi)
        points, out = _cluster(vertices, faces, float(np.exp(mid)))
        if len(out) <= keep:
            best, hi = (points, out), mid
        else:
            lo = mid
    return best


def _cluster(
    vertices: np.ndarray, faces: np.ndarray, cell_m: float
) -> tuple[np.ndarray, np.ndarray]:
    """The mesh with the vertices of each ``cell_m`` grid cube [m] merged into their mean;
    collapsed and repeated triangles dropped, the others keep their orientation."""
    cells = np.floor((vertices - vertices.min(axis=0)) / cell_m).astype(np.int64)
    _, inverse = np.unique(_row_keys(cells), return_inverse=True)
    inverse = inverse.reshape(-1)
    count = np.bincount(inverse)
    points = np.zeros((len(count), 3))
    np.add.at(points, inverse, vertices)
    points /= count[:, None]
    merged = inverse[faces]
    whole = (
        (merged[:, 0] != merged[:, 1])
        & (merged[:, 1] != merged[:, 2])
        & (merged[:, 0] != merged[:, 2])
    )
    merged = merged[whole]
    _, first = np.unique(_row_keys(np.sort(merged, axis=1)), return_index=True)
    return points, merged[np.sort(first)]


def _row_keys(rows: np.ndarray) -> np.ndarray:
    """One int64 per row of non-negative integers (N, 3), equal exactly when the rows are."""
    span = rows.max(axis=0) + 1 if len(rows) else np.ones(3, dtype=np.int64)
    if float(np.prod(span.astype(float))) < 2.0**62:
        return (rows[:, 0] * span[1] + rows[:, 1]) * span[2] + rows[:, 2]
    return np.unique(rows, axis=0, return_inverse=True)[1].reshape(-1)


def _stl_bytes(vertices: np.ndarray, faces: np.ndarray) -> bytes:
    """A binary STL of the mesh: header, count, then normal and 3 corners per triangle."""
    corners = vertices[faces].astype(np.float32)  # (F, 3, 3)
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    record = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    record["n"], record["v"] = normal, corners
    header = b"silo4kin simplified mesh".ljust(80, b" ")
    return header + np.array(len(faces), dtype="<u4").tobytes() + record.tobytes()
