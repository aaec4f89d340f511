"""Prepare a robot's URDF text for MuJoCo: physical inertias, collision shapes, no visuals.

MuJoCo reads a URDF's ``<collision>`` elements as its geoms. Many planning URDFs (SILO4's
among them) have none, and then a body or knee striking the ground would pass through it
unseen. This module rewrites the URDF text (the robot itself is unchanged):

- a link keeps its ``<collision>`` shapes except meshes named by package:// (example-robot-
  data's go2 and solo12 name theirs so, and MuJoCo cannot open them; a mesh file path stays,
  and a missing file is MuJoCo's error naming it): their bodies and thighs then have no
  floor contact, only the tibia capsules and feet
  of :mod:`silo4sim.model`); a link left without gets a copy of its primitive visuals (box,
  cylinder, sphere; meshes are skipped likewise);
- the links rigidly attached to each tibia (the knee joint's child and its fixed
  descendants, feet included) lose their shapes: the tibia becomes a capsule that stops
  short of the foot, and the foot a small sphere (both added by :mod:`silo4sim.model`), so the
  only contact the planner expects, the foot tip, is the only one a stance foot makes;
- inertia tensors with principal moments below ``MIN_INERTIA_RATIO`` of the link's largest
  are raised to it (MuJoCo refuses SILO4's slender-rod tensors diag(0, I, I): "inertia must
  have positive eigenvalues"). Raising them to 1 % changes no figure we measure
  (docs/physics.md).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np

from silo4kin.errors import RobotDescriptionError
from silo4kin.shapes import parse_urdf, tibia_links, tibia_radii_m

from .errors import MujocoModelError

#: Smallest principal moment of inertia relative to the link's largest (see module doc).
MIN_INERTIA_RATIO = 0.01
#: Principal moment given to a link whose tensor is all zero but has mass [kg m^2 per kg].
_POINT_MASS_INERTIA_PER_KG = 1e-6
_PRIMITIVES = ("box", "cylinder", "sphere")


def _parse(urdf_xml: str) -> ET.Element:
    """The URDF's root element (silo4kin.shapes.parse_urdf; its error as MujocoModelError)."""
    try:
        return parse_urdf(urdf_xml)
    except RobotDescriptionError as exc:
        raise MujocoModelError(str(exc)) from None


def rigid_tibia_links(root: ET.Element, knee_joints: list[str]) -> dict[str, set[str]]:
    """Per knee joint, its child link and every link welded to it by fixed joints
    (silo4kin.shapes.tibia_links; its errors as MujocoModelError)."""
    try:
        return tibia_links(root, knee_joints)
    except RobotDescriptionError as exc:
        raise MujocoModelError(str(exc)) from None


def _fix_inertia(link: ET.Element) -> None:
    """Raise tiny principal moments (MIN_INERTIA_RATIO) in place."""
    inertial = link.find("inertial")
    if inertial is None:
        return
    mass_el, inertia_el = inertial.find("mass"), inertial.find("inertia")
    if mass_el is None or inertia_el is None:
        return
    try:
        mass = float(mass_el.get("value", "0"))
        c = {k: float(inertia_el.get(k, "0")) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    except ValueError:
        raise MujocoModelError(
            f"link {link.get('name')!r}: <inertial> has a non-numeric value"
        ) from None
    tensor = np.array(
        [
            [c["ixx"], c["ixy"], c["ixz"]],
            [c["ixy"], c["iyy"], c["iyz"]],
            [c["ixz"], c["iyz"], c["izz"]],
        ]
    )
    if mass <= 0:
        return
    moments, axes = np.linalg.eigh(tensor)
    largest = max(float(moments.max()), _POINT_MASS_INERTIA_PER_KG * mass)
    floor = MIN_INERTIA_RATIO * largest
    if moments.min() >= floor:
        return
    fixed = axes @ np.diag(np.maximum(moments, floor)) @ axes.T
    for key, (i, j) in {
        "ixx": (0, 0),
        "ixy": (0, 1),
        "ixz": (0, 2),
        "iyy": (1, 1),
        "iyz": (1, 2),
        "izz": (2, 2),
    }.items():
        inertia_el.set(key, repr(float(fixed[i, j])))


def prepare_urdf(urdf_xml: str, knee_joints: list[str]) -> tuple[str, dict[str, float]]:
    """The URDF text MuJoCo will load (see the module doc) and the tibia radii.

    Args:
        urdf_xml: the robot's expanded URDF.
        knee_joints: the 4 knee joint names (third joint of each leg).

    Returns:
        (urdf text with collision shapes, no visuals, physical inertias and a ``<mujoco>``
        compiler element; tibia capsule radius [m] per knee joint,
        silo4kin.shapes.tibia_radii_m).
    """
    root = _parse(urdf_xml)
    welded = rigid_tibia_links(root, knee_joints)
    tibia_links = {link: knee for knee, group in welded.items() for link in group}
    radius = tibia_radii_m(root, knee_joints)
    for link in root.findall("link"):
        _fix_inertia(link)
        name = link.get("name", "")
        visuals = link.findall("visual")
        collisions = link.findall("collision")
        if name in tibia_links:
            for el in collisions:
                link.remove(el)
        else:
            for el in collisions:  # mesh collisions: files by package:// (see above)
                geom = el.find("geometry")
                mesh = None if geom is None else geom.find("mesh")
                if mesh is not None and mesh.get("filename", "").startswith("package://"):
                    link.remove(el)
            collisions = link.findall("collision")
        if name not in tibia_links and not collisions:
            for vis in visuals:
                geom = vis.find("geometry")
                if geom is None or not any(geom.find(p) is not None for p in _PRIMITIVES):
                    continue
                col = ET.SubElement(link, "collision")
                for child in vis:
                    if child.tag in ("origin", "geometry"):
                        col.append(child)
        for vis in link.findall("visual"):
            link.remove(vis)
    for el in root.findall("mujoco"):
        root.remove(el)
    mj = ET.SubElement(root, "mujoco")
    ET.SubElement(
        mj,
        "compiler",
        {
            "fusestatic": "false",
            "discardvisual": "true",
            "strippath": "false",
            "balanceinertia": "true",
        },
    )
    return ET.tostring(root, encoding="unicode"), radius
