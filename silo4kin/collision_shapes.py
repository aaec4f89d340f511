"""A robot's collision shapes as points in their links' frames, for ground clearance.

:func:`collision_points` reads every link's ``<collision>`` shapes (a link without any: its
``<visual>`` shapes) from the robot's URDF text and turns each into points in the link frame
plus an inflation radius, so that the lowest point of the shape in any pose is
``min(z of the points) - inflation``:

- sphere: its centre, inflated by the radius (exact);
- capsule: points every SPACING_M on its axis, inflated by the radius (the lowest point
  of a whole capsule is at an end: exact);
- cylinder: RIM_POINTS points on rims every SPACING_M along its axis (the lowest point of
  a cylinder is on an end rim; the polygon is at most r (1 - cos(π / RIM_POINTS)) higher:
  0.9 % of r);
- box: points every SPACING_M on its 12 edges, corners included (exact);
- mesh: the vertices of a mesh file (``package://`` resolved from the robot's loaded visual
  meshes), scaled: STL (binary or ASCII) read here, any other format trimesh reads (COLLADA
  .dae through pycollada, OBJ, PLY) through trimesh, its scene's node transforms and units
  applied. A file that is missing or unreadable is left out and named in
  ``CollisionPoints.skipped``.

Points within FOOT_ZONE_M of a foot frame's origin on the foot's own rigid body (the knee's
child link and the links fixed to it) are the foot's: they are dropped, the rest is what
must stay off the ground.

:func:`tibia_capsules` is the other shape of each tibia: the capsule the physics replay gives
it instead of its URDF shapes (silo4sim/model.py builds its geom from this function, so the
planner measures the shape MuJoCo collides).
"""

from __future__ import annotations

import struct
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from .errors import RobotDescriptionError
from .shapes import parse_urdf, tibia_links, tibia_radii_m

#: Points on each rim of a cylinder, and the spacing of the rims, the capsule axis points
#: and the box edge points along a shape [m] (a foot zone cuts a shape part way).
RIM_POINTS = 24
SPACING_M = 0.01
#: Points of a foot's rigid body nearer than this to the foot frame's origin belong to the
#: foot [m] (the physics model's tibia capsule stops as far short of the foot:
#: silo4sim.settings.SimSettings.tibia_clearance_m).
FOOT_ZONE_M = 0.05


@dataclass(frozen=True, eq=False)
class LinkPoints:
    """The shape points of one link: ``frame_id`` of the link in the fixed-base Pinocchio
    model, ``points_in_link`` (P, 3) [m], ``inflation_m`` (P,) [m] (the lowest point of a
    point's shape is its z less its inflation)."""

    link: str
    frame_id: int
    points_in_link: np.ndarray
    inflation_m: np.ndarray


@dataclass(frozen=True, eq=False)
class CollisionPoints:
    """Every link's shape points (foot zones removed) and the meshes that were not read."""

    links: tuple[LinkPoints, ...]
    skipped: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class TibiaCapsule:
    """One leg's tibia capsule: the segment from ``start_in_link`` to ``end_in_link`` (3,)
    [m] in the frame of ``link`` (the knee joint's child link, ``frame_id`` its BODY frame in
    the fixed-base model), inflated by ``radius_m`` [m]."""

    leg: str
    link: str
    frame_id: int
    start_in_link: np.ndarray
    end_in_link: np.ndarray
    radius_m: float


def tibia_capsules(robot, foot_gap_m: float) -> tuple[TibiaCapsule, ...]:  # noqa: ANN001
    """Each leg's tibia capsule in legs order: from the knee's child link origin (on the knee
    axis) towards the foot frame's origin, stopping ``foot_gap_m`` [m] short of it (at the
    origin when the foot is nearer), radius silo4kin.shapes.tibia_radii_m; the shape
    silo4sim/model.py gives MuJoCo (SimSettings.tibia_clearance_m the gap)."""
    root = parse_urdf(robot.urdf_xml)
    knees = [leg.joint_names[2] for leg in robot.legs]
    radius = tibia_radii_m(root, knees)
    child = {
        j.get("name", ""): j.find("child").get("link", "")  # type: ignore[union-attr]
        for j in root.findall("joint")
        if j.get("name") in knees and j.find("child") is not None
    }
    model = robot.model
    out = []
    for leg, knee in zip(robot.legs, knees):
        frame_id = model.getFrameId(child[knee], pin.FrameType.BODY)
        link, foot_frame = model.frames[frame_id], model.frames[model.getFrameId(leg.foot_frame)]
        if link.parentJoint != foot_frame.parentJoint:
            raise RobotDescriptionError(
                f"foot frame {leg.foot_frame!r} does not move with the knee joint {knee!r}"
            )
        foot = np.array(link.placement.actInv(foot_frame.placement).translation)
        length = float(np.linalg.norm(foot))
        end = foot * max(0.0, 1.0 - foot_gap_m / length) if length > 0 else foot
        out.append(TibiaCapsule(leg.name, child[knee], frame_id, np.zeros(3), end, radius[knee]))
    return tuple(out)


def _origin(el: ET.Element) -> pin.SE3:
    """The ``<origin xyz rpy>`` of a visual/collision element, as a link-frame SE3."""
    o = el.find("origin")
    xyz = np.zeros(3) if o is None else np.array([float(v) for v in o.get("xyz", "0 0 0").split()])
    rpy = np.zeros(3) if o is None else np.array([float(v) for v in o.get("rpy", "0 0 0").split()])
    return pin.SE3(pin.rpy.rpyToMatrix(*rpy), xyz)


def read_stl_vertices(path: Path) -> np.ndarray:
    """The distinct vertices (V, 3) of an STL file, binary or ASCII [file units]."""
    data = path.read_bytes()
    if data[:5].lower() == b"solid" and b"facet" in data[:512]:
        words = data.decode(errors="replace").split()
        pts = [
            [float(words[i + 1]), float(words[i + 2]), float(words[i + 3])]
            for i, w in enumerate(words)
            if w == "vertex"
        ]
        return np.unique(np.array(pts, dtype=float).reshape(-1, 3), axis=0)
    (n,) = struct.unpack_from("<I", data, 80)
    rec = np.frombuffer(data[84 : 84 + 50 * n], dtype=np.uint8).reshape(n, 50)
    tri = rec[:, 12:48].copy().view("<f4").reshape(n, 3, 3).astype(float)
    return np.unique(tri.reshape(-1, 3), axis=0)


def read_mesh_vertices(path: Path) -> np.ndarray | None:
    """The vertices (V, 3) of a mesh file [file units, metres for COLLADA], or None when it
    cannot be read (module docstring)."""
    if path.suffix.lower() == ".stl":
        return read_stl_vertices(path)
    import trimesh

    try:
        mesh = trimesh.load(str(path), force="mesh")
    except Exception:  # noqa: BLE001 (trimesh and its loaders raise many kinds)
        return None
    vertices = np.asarray(getattr(mesh, "vertices", np.zeros((0, 3))), dtype=float)
    return np.unique(vertices, axis=0) if len(vertices) else None


def _package_roots(visual_model: pin.GeometryModel, root: ET.Element) -> dict[str, Path]:
    """package name -> folder, from the loaded visual meshes' resolved paths."""
    out: dict[str, Path] = {}
    for g in visual_model.geometryObjects:
        path = str(getattr(g, "meshPath", "") or "")
        for mesh in root.iter("mesh"):
            uri = mesh.get("filename", "")
            if not uri.startswith("package://"):
                continue
            package = uri[len("package://") :].split("/", 1)[0]
            marker = f"/{package}/"
            if package not in out and marker in path:
                out[package] = Path(path[: path.index(marker) + len(marker)])
    return out


def _resolve(uri: str, roots: dict[str, Path], source: Path | None) -> Path | None:
    if uri.startswith("package://"):
        package, _, rest = uri[len("package://") :].partition("/")
        return roots[package] / rest if package in roots else None
    if uri.startswith("file://"):
        uri = uri[len("file://") :]
    path = Path(uri)
    if not path.is_absolute() and source is not None:
        path = source.parent / path
    return path


def _along(length: float) -> np.ndarray:
    """Coordinates [m] from -length/2 to length/2, ends included, at most SPACING_M apart."""
    return np.linspace(-length / 2, length / 2, max(2, int(np.ceil(length / SPACING_M)) + 1))


def _shape_points(
    geom: ET.Element, roots: dict[str, Path], source: Path | None
) -> tuple[np.ndarray, np.ndarray] | str:
    """(points (P, 3) [m] in the element's origin frame, inflation (P,) [m]), or the name
    of a mesh that could not be read."""
    shape = geom[0]
    if shape.tag == "sphere":
        return np.zeros((1, 3)), np.full(1, float(shape.get("radius", "0")))
    if shape.tag in ("cylinder", "capsule"):
        r, length = float(shape.get("radius", "0")), float(shape.get("length", "0"))
        z = _along(length)
        if shape.tag == "capsule":
            return np.column_stack([np.zeros_like(z), np.zeros_like(z), z]), np.full(z.size, r)
        a = np.linspace(0.0, 2 * np.pi, RIM_POINTS, endpoint=False)
        rim = np.column_stack([r * np.cos(a), r * np.sin(a)])
        pts = np.vstack([np.column_stack([rim, np.full(a.size, zk)]) for zk in z])
        return pts, np.zeros(len(pts))
    if shape.tag == "box":
        half = np.array([float(v) for v in shape.get("size", "0 0 0").split()]) / 2
        edges = []
        for axis in range(3):  # the 4 edges along each axis
            t = _along(2 * half[axis])
            for s1 in (-1, 1):
                for s2 in (-1, 1):
                    e = np.zeros((t.size, 3))
                    e[:, axis] = t
                    others = [i for i in range(3) if i != axis]
                    e[:, others[0]], e[:, others[1]] = s1 * half[others[0]], s2 * half[others[1]]
                    edges.append(e)
        pts = np.vstack(edges)
        return pts, np.zeros(len(pts))
    if shape.tag == "mesh":
        uri = shape.get("filename", "")
        path = _resolve(uri, roots, source)
        vertices = None if path is None or not path.is_file() else read_mesh_vertices(path)
        if vertices is None:
            return uri
        scale = np.array([float(v) for v in shape.get("scale", "1 1 1").split()])
        pts = vertices * scale
        return pts, np.zeros(len(pts))
    return f"<{shape.tag}>"


def _hull(points: np.ndarray, inflation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The points that can be lowest in some pose: per inflation value, the vertices of their
    convex hull (scipy.spatial, when installed; otherwise every point is kept)."""
    try:
        from scipy.spatial import ConvexHull, QhullError
    except ImportError:  # the same answer, only slower
        return points, inflation
    keep = []
    for r in np.unique(inflation):
        rows = np.flatnonzero(inflation == r)
        try:
            keep.append(rows[ConvexHull(points[rows]).vertices])
        except (QhullError, ValueError):  # flat or too few points: all of them
            keep.append(rows)
    rows = np.sort(np.concatenate(keep)) if keep else np.arange(0)
    return points[rows], inflation[rows]


def collision_points(robot) -> CollisionPoints:  # noqa: ANN001 (silo4kin.robot.Robot)
    """Every link's shape points of ``robot`` (module docstring), cached on the robot."""
    memo = robot._memo
    if "collision_points" not in memo:
        memo["collision_points"] = _collision_points(robot)
    return memo["collision_points"]


def _collision_points(robot) -> CollisionPoints:  # noqa: ANN001
    root = parse_urdf(robot.urdf_xml)
    roots = _package_roots(robot.visual_model, root)
    model = robot.model
    knees = [leg.joint_names[2] for leg in robot.legs]
    groups = tibia_links(root, knees)
    # tibia-group link -> the foot frame origins in that link's frame [m]
    feet: dict[str, list[np.ndarray]] = {}
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    pin.updateFramePlacements(model, data)
    for leg, knee in zip(robot.legs, knees):
        foot = data.oMf[model.getFrameId(leg.foot_frame)]
        for link in groups[knee]:
            link_pose = data.oMf[model.getFrameId(link, pin.FrameType.BODY)]
            feet.setdefault(link, []).append((link_pose.actInv(foot)).translation)
    links, skipped = [], []
    for link_el in root.findall("link"):
        name = link_el.get("name", "")
        elements = link_el.findall("collision") or link_el.findall("visual")
        pts_all, infl_all = [], []
        for el in elements:
            geom = el.find("geometry")
            if geom is None or not len(geom):
                continue
            got = _shape_points(geom, roots, robot.source)
            if isinstance(got, str):
                skipped.append(f"{name}: {got}")
                continue
            pts, infl = got
            origin = _origin(el)
            pts_all.append(pts @ origin.rotation.T + origin.translation)
            infl_all.append(infl)
        if not pts_all or not model.existFrame(name, pin.FrameType.BODY):
            continue
        pts, infl = np.vstack(pts_all), np.concatenate(infl_all)
        for foot in feet.get(name, []):
            keep = np.linalg.norm(pts - foot, axis=1) - infl >= FOOT_ZONE_M
            pts, infl = pts[keep], infl[keep]
        pts, infl = _hull(pts, infl)
        if len(pts):
            links.append(LinkPoints(name, model.getFrameId(name, pin.FrameType.BODY), pts, infl))
    return CollisionPoints(tuple(links), tuple(skipped))
