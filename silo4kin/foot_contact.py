"""Where the ground is under a foot frame: the contact convention for round feet.

Most example-robot-data quadrupeds end each leg in a ball whose centre is the foot frame
(a1, go1, b1, laikago, hyq) or sits just above it (anymal: 2.3 cm up the foot frame's z).
The planner, the simulator and the animation place the foot frame, so all three use one
convention (docs/robots.md, "Round feet"):

    the ground touches a standing foot at foot-frame z minus ``foot_contact_offset_m``,

with ``foot_contact_offset_m = r - o_z`` read from the URDF: r the radius of the foot link's
collision sphere, o_z the z of that sphere's origin in the foot link (the foot frame). A foot
link without a collision sphere (SILO4's point feet; go2 and solo12, whose feet collide
through meshes) gives 0, the thesis's point foot. The offset is measured along the foot
frame's z, taken as vertical: exact for a ball centred on the foot frame (o = 0) whatever
the leg's pose; anymal's offset ball is approximated (its 2.3 cm offset tilts with the shank).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from functools import lru_cache


def contact_offset_from_urdf(urdf_xml: str, foot_link: str) -> float:
    """r - o_z of the first collision sphere of link ``foot_link`` [m]; 0 without one."""
    try:
        root = ET.fromstring(urdf_xml)
    except ET.ParseError:
        return 0.0
    for link in root.iter("link"):
        if link.get("name") != foot_link:
            continue
        for col in link.iter("collision"):
            sphere = col.find("geometry/sphere")
            if sphere is None:
                continue
            origin = col.find("origin")
            oz = float(origin.get("xyz", "0 0 0").split()[2]) if origin is not None else 0.0
            return float(sphere.get("radius", "0")) - oz
    return 0.0


@lru_cache(maxsize=64)
def foot_contact_offset_m(robot) -> float:
    """The robot's foot contact offset [m] (module docstring): the first leg's foot link
    (the four feet of every supported robot are alike); 0 when the URDF text is not at hand."""
    xml = getattr(robot, "urdf_xml", None)
    if not xml or not robot.legs:
        return 0.0
    return contact_offset_from_urdf(xml, robot.legs[0].foot_frame)
