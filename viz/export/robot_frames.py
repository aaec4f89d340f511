"""The URDF's link frames along a trajectory, as ROS 2 tf publishes them.

robot_state_publisher turns a URDF and joint positions into one transform per URDF joint,
parent link -> child link: the moving joints on ``/tf``, the fixed ones once on
``/tf_static``. :class:`RobotFrames` computes the same transforms with Pinocchio's forward
kinematics of the fixed-base model, so a bag carries them and RViz draws the robot without
robot_state_publisher running:

    transform_child_in_parent = inverse(oMf[parent]) * oMf[child]

with ``oMf`` the placement of each link's BODY frame in the model's root (the URDF root
link). The root link itself is :attr:`RobotFrames.root_link`: the one link that is no joint's
child.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from silo4kin.errors import Silo4Error


class LinkTransforms(NamedTuple):
    """Transforms parent link -> child link, one per URDF joint of a kind.

    Attributes:
        parent_links, child_links: (J,) link names.
        position_child_in_parent: (N, J, 3) [m].
        orientation_child_in_parent_xyzw: (N, J, 4) unit quaternions, scalar last.
    """

    parent_links: list[str]
    child_links: list[str]
    position_child_in_parent: np.ndarray
    orientation_child_in_parent_xyzw: np.ndarray


class UrdfJoint(NamedTuple):
    """One ``<joint>`` of a URDF: its name, kind ("fixed", "revolute", ...) and links."""

    name: str
    kind: str
    parent_link: str
    child_link: str


def urdf_joints(urdf_xml: str) -> list[UrdfJoint]:
    """Every ``<joint>`` of the URDF text, in file order."""
    try:
        root = ET.fromstring(urdf_xml)
    except ET.ParseError as exc:
        raise Silo4Error(f"robot description: malformed URDF XML ({exc})") from None
    joints = []
    for joint in root.iter("joint"):
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None:
            continue  # a transmission's <joint> reference, not a kinematic joint
        joints.append(
            UrdfJoint(
                joint.get("name", ""),
                joint.get("type", ""),
                parent.get("link", ""),
                child.get("link", ""),
            )
        )
    return joints


def root_link_name(urdf_xml: str) -> str:
    """The URDF's root link: the one ``<link>`` that is no joint's child."""
    children = {joint.child_link for joint in urdf_joints(urdf_xml)}  # refuses malformed XML
    links = [link.get("name", "") for link in ET.fromstring(urdf_xml).findall("link")]
    roots = [name for name in links if name not in children]
    if len(roots) != 1:
        raise Silo4Error(f"robot description: expected one root link, found {roots}")
    return roots[0]


class RobotFrames:
    """Link transforms of a URDF for joint positions in a given joint order.

    Args:
        urdf_xml: the URDF text (the robot the plan was made for).
        joint_names: (J,) the trajectory's joint order; each a 1-DoF URDF joint.
    """

    def __init__(self, urdf_xml: str, joint_names: Sequence[str]) -> None:
        self.root_link = root_link_name(urdf_xml)
        self.model = pin.buildModelFromXML(urdf_xml)
        self.data = self.model.createData()
        missing = [n for n in joint_names if not self.model.existJointName(n)]
        if missing:
            raise Silo4Error(
                f"the trajectory's joints {missing} are not in the robot "
                f"'{self.model.name}'; give the robot it was planned for (--robot)"
            )
        joints = [self.model.joints[self.model.getJointId(n)] for n in joint_names]
        if any(j.nq != 1 for j in joints):
            raise Silo4Error("the ROS 2 export handles 1-DoF joints only")
        self.q_index = np.array([j.idx_q for j in joints])
        self.joints = [j for j in urdf_joints(urdf_xml) if j.kind != "floating"]

    def _body_frame(self, link: str) -> int:
        return self.model.getFrameId(link, pin.BODY)

    def transforms(self, q: np.ndarray, *, fixed: bool) -> LinkTransforms:
        """The fixed joints' transforms (``fixed``) or the moving ones', for q (N, J) [rad]."""
        q = np.atleast_2d(np.asarray(q, dtype=float))
        chosen = [j for j in self.joints if (j.kind == "fixed") == fixed]
        frames = [(self._body_frame(j.parent_link), self._body_frame(j.child_link)) for j in chosen]
        position = np.empty((len(q), len(chosen), 3))
        orientation = np.empty((len(q), len(chosen), 4))
        q_pin = pin.neutral(self.model)
        for k in range(len(q)):  # Pinocchio's forward kinematics is one configuration a call
            q_pin[self.q_index] = q[k]
            pin.framesForwardKinematics(self.model, self.data, q_pin)
            for i, (parent, child) in enumerate(frames):
                placement = self.data.oMf[parent].actInv(self.data.oMf[child])
                position[k, i] = placement.translation
                orientation[k, i] = pin.Quaternion(placement.rotation).coeffs()  # x, y, z, w
        return LinkTransforms(
            [j.parent_link for j in chosen], [j.child_link for j in chosen], position, orientation
        )
