"""Leg shapes read from a robot's URDF: the links of each tibia and the tibia capsule radius.

The one place that reads a shank's shape: the physics model's tibia capsule
(silo4sim/urdf_collisions.py, silo4sim/model.py) and the planner's clearance rule
(planner/trajectory/clearance.py, through LegGeometry.tibia_radius_m, which load_robot sets)
take their radius from :func:`tibia_radii_m` (tests/test_tibia.py). The rule: the tibia
is the knee joint's child link and every link welded to it by fixed joints
(:func:`tibia_links`); its radius is that of the first cylinder or capsule among those
links' ``<collision>`` shapes, else among their ``<visual>`` shapes, in document order. A
URDF whose tibia has neither (meshes only, e.g. Go2's) gets DEFAULT_TIBIA_RADIUS_M, the
radius the physics model used before it read the URDF.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

from .errors import RobotDescriptionError

#: Tibia capsule radius of a URDF without a primitive tibia shape [m].
DEFAULT_TIBIA_RADIUS_M = 0.015
_ROUND_SHAPES = ("cylinder", "capsule")


def parse_urdf(urdf_xml: str) -> ET.Element:
    """The URDF's root element; RobotDescriptionError when the text is not XML."""
    try:
        return ET.fromstring(urdf_xml.encode() if isinstance(urdf_xml, str) else urdf_xml)
    except ET.ParseError as exc:
        raise RobotDescriptionError(f"the URDF text is not XML: {exc}") from None


def tibia_links(root: ET.Element, knee_joints: list[str]) -> dict[str, set[str]]:
    """Per knee joint, its child link and every link welded to it by fixed joints;
    RobotDescriptionError for a joint without parent or child, or a missing knee joint."""
    children: dict[str, list[tuple[str, str]]] = {}
    child_of: dict[str, str] = {}
    for j in root.findall("joint"):
        parent, child = j.find("parent"), j.find("child")
        if parent is None or child is None:
            raise RobotDescriptionError(
                f"URDF joint {j.get('name')!r} lacks a parent or child link"
            )
        children.setdefault(parent.get("link", ""), []).append(
            (child.get("link", ""), j.get("type", ""))
        )
        child_of[j.get("name", "")] = child.get("link", "")
    out: dict[str, set[str]] = {}
    for knee in knee_joints:
        if knee not in child_of:
            raise RobotDescriptionError(f"URDF has no joint {knee!r}")
        group, todo = set(), [child_of[knee]]
        while todo:
            link = todo.pop()
            group.add(link)
            todo += [c for c, kind in children.get(link, []) if kind == "fixed"]
        out[knee] = group
    return out


def _round_radius(elements: list[ET.Element]) -> float | None:
    """Radius [m] of the first cylinder or capsule among ``elements`` (visual/collision)."""
    for el in elements:
        geom = el.find("geometry")
        for tag in _ROUND_SHAPES:
            shape = None if geom is None else geom.find(tag)
            if shape is not None:
                try:
                    return float(shape.get("radius", ""))
                except ValueError:
                    continue
    return None


def tibia_radii_m(urdf_xml: str | ET.Element, knee_joints: list[str]) -> dict[str, float]:
    """Tibia capsule radius [m] per knee joint (module docstring)."""
    root = parse_urdf(urdf_xml) if not isinstance(urdf_xml, ET.Element) else urdf_xml
    groups = tibia_links(root, knee_joints)
    links = root.findall("link")
    out = {}
    for knee, group in groups.items():
        mine = [link for link in links if link.get("name", "") in group]
        collision = _round_radius([el for link in mine for el in link.findall("collision")])
        visual = _round_radius([el for link in mine for el in link.findall("visual")])
        radius = collision if collision is not None else visual
        out[knee] = DEFAULT_TIBIA_RADIUS_M if radius is None else radius
    return out
