"""The ball at the end of each leg: its radius, where its centre sits, where the ground is.

Most example-robot-data quadrupeds end each leg in a ball whose centre is the foot frame
(a1, go1, go2, solo12, b1, laikago, hyq) or sits above it (anymal: 2.3 cm up the foot frame's
z). :func:`foot_ball` reads the ball of the first leg's foot link (the four feet of every
supported robot are alike), in this order:

1. a radius the caller gives (centre on the foot frame);
2. the foot link's first ``<collision>`` sphere (r, and o_z the z of its origin);
3. a foot link that collides through a mesh: the ball is centred on the foot frame and r is
   the depth of the mesh's lowest point below it, measured on the link's meshes as
   Pinocchio loaded them for the robot (its visual model: go2's visual and collision foot
   meshes reach the same lowest point to 1e-7 m). go2: 22.9 mm, solo12: 16.0 mm; the
   mesh's bounding sphere about the foot frame is at most 3 mm larger (a shoe's upper part
   is not round);
4. otherwise a point foot, r = 0: SILO4 and the insect test robots, whose foot spheres are
   visual only (a marker in the animation, not a contact shape).

The planner, the simulator and the animation share one convention (docs/physics.md,
"Round feet"): a standing foot touches the ground at the contact point, foot-frame z minus
``contact_offset_m = r - o_z``; the offset is measured along the foot frame's z, taken as
vertical. That is exact for a ball centred on the foot frame (o_z = 0) whatever the leg's
pose; a ball above the foot frame (anymal: r = 31 mm, o_z = 23.25 mm) is modelled by its
equivalent ball, radius ``rolling_radius_m = r - o_z`` centred on the foot frame, which the
planner rolls and the sim stands on (the real ball's offset tilts with the shank: at
anymal's stance tilt the real ball would sink ~1 mm into the floor of the vertical model,
and the sim's calibration then fails by 4.6 mm).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

from silo4kin.memo import cached_on_first_argument


@dataclass(frozen=True)
class FootBall:
    """The round end of a leg.

    Attributes:
        radius_m: ball radius r [m]; 0 for a point foot.
        centre_z_in_foot_m: o_z, the ball centre on the foot frame's z axis [m].
        source: where r came from: "given", "collision sphere", "collision mesh" or
            "point foot".
    """

    radius_m: float
    centre_z_in_foot_m: float = 0.0
    source: str = "point foot"

    @property
    def contact_offset_m(self) -> float:
        """r - o_z: the foot frame's height above the ground when the foot stands [m]."""
        return self.radius_m - self.centre_z_in_foot_m

    @property
    def rolling_radius_m(self) -> float:
        """Radius of the ball centred on the foot frame that the planner rolls and the sim
        stands on (module docstring) [m]: r for a centred ball, r - o_z otherwise."""
        return self.contact_offset_m

    @property
    def rolls(self) -> bool:
        """The foot has a radius, so it rolls when its link rotates in stance."""
        return self.radius_m > 0.0


#: A point foot: r = 0 (the thesis's model).
POINT_FOOT = FootBall(0.0)


def _sphere_of(link: ET.Element, tag: str) -> tuple[float, float] | None:
    for element in link.iter(tag):
        sphere = element.find("geometry/sphere")
        if sphere is None:
            continue
        origin = element.find("origin")
        oz = float(origin.get("xyz", "0 0 0").split()[2]) if origin is not None else 0.0
        return float(sphere.get("radius", "0")), oz
    return None


def _link(urdf_xml: str, name: str) -> ET.Element | None:
    try:
        root = ET.fromstring(urdf_xml)
    except ET.ParseError:
        return None
    return next((link for link in root.iter("link") if link.get("name") == name), None)


def sphere_from_urdf(urdf_xml: str, foot_link: str) -> FootBall | None:
    """The first collision sphere of link ``foot_link``; None without one."""
    link = _link(urdf_xml, foot_link)
    found = None if link is None else _sphere_of(link, "collision")
    return None if found is None else FootBall(found[0], found[1], "collision sphere")


def collides_by_mesh(urdf_xml: str, foot_link: str) -> bool:
    """Link ``foot_link`` has a ``<collision>`` mesh."""
    link = _link(urdf_xml, foot_link)
    return link is not None and link.find("collision/geometry/mesh") is not None


def contact_offset_from_urdf(urdf_xml: str, foot_link: str) -> float:
    """r - o_z of the foot link's collision sphere [m]; 0 without one."""
    ball = sphere_from_urdf(urdf_xml, foot_link)
    return 0.0 if ball is None else ball.contact_offset_m


def _mesh_depth_below_foot_m(robot, foot_frame: str) -> float | None:
    """Depth of the lowest vertex of the meshes on the foot frame below it [m] (the robot's
    loaded geometry, module docstring), or None when no mesh hangs on the frame."""
    model, geometry_model = robot.model, getattr(robot, "visual_model", None)
    if geometry_model is None or not model.existFrame(foot_frame):
        return None
    fid = model.getFrameId(foot_frame)
    frame_in_joint = model.frames[fid].placement
    depths = []
    for obj in geometry_model.geometryObjects:
        if obj.parentFrame != fid or not hasattr(obj.geometry, "vertices"):
            continue
        vertices = np.asarray(obj.geometry.vertices(), dtype=float) * np.asarray(obj.meshScale)
        if not vertices.size:
            continue
        placement = frame_in_joint.inverse() * obj.placement  # mesh -> foot frame
        z = vertices @ placement.rotation[2] + placement.translation[2]
        depths.append(-float(z.min()))
    return max(depths) if depths else None


def foot_ball(robot, radius_m: float | None = None) -> FootBall:
    """The robot's foot ball (module docstring); ``radius_m`` [m] overrides the URDF's."""
    if radius_m is not None:
        if not np.isfinite(radius_m) or radius_m < 0:
            from .errors import Silo4Error

            raise Silo4Error(f"foot radius {radius_m!r} m: give a finite value >= 0")
        return FootBall(float(radius_m), 0.0, "given") if radius_m > 0 else POINT_FOOT
    return _foot_ball_of(robot)


@cached_on_first_argument(max_entries=1)
def _foot_ball_of(robot) -> FootBall:
    if not getattr(robot, "legs", None):
        return POINT_FOOT
    foot = robot.legs[0].foot_frame
    xml = getattr(robot, "urdf_xml", None)
    if xml:
        ball = sphere_from_urdf(xml, foot)
        if ball is not None:
            return ball
    if xml and collides_by_mesh(xml, foot) and hasattr(robot, "model"):
        depth = _mesh_depth_below_foot_m(robot, foot)
        if depth is not None and depth > 0:
            return FootBall(depth, 0.0, "collision mesh")
    return POINT_FOOT


def foot_contact_offset_m(robot) -> float:
    """The robot's foot contact offset r - o_z [m] (module docstring)."""
    return foot_ball(robot).contact_offset_m
