"""A second, independent reading of the robot files: yourdfpy (a pure-Python URDF parser with
its own forward kinematics) against our closed form, which reads the model through Pinocchio.

If Pinocchio's URDF import and yourdfpy disagreed on an axis, origin or limit, or our
LegGeometry extraction misread one, the foot positions would differ here.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest
import yourdfpy

from silo4kin import kinematics, load_robot

ROBOTS = Path(__file__).resolve().parent / "robots"
#: Foot positions [m]: both sides chain a few 4x4 products of O(0.5 m), rounding ~1e-15.
FK_TOLERANCE = 1e-12
N_SAMPLES = 60


@pytest.fixture(scope="module", params=["silo4", "mantis", "variant"])
def robot_and_urdf(request):
    robot = {
        "silo4": lambda: load_robot(),
        "mantis": lambda: load_robot(ROBOTS / "mantis.urdf"),
        "variant": lambda: load_robot(xacro_args={"L2": 0.3, "L3": 0.35}),
    }[request.param]()
    urdf = yourdfpy.URDF.load(
        io.StringIO(robot.urdf_xml),
        build_scene_graph=True,
        load_meshes=False,
        build_collision_scene_graph=False,
    )
    return robot, urdf


def test_joint_limits_match_the_parser(robot_and_urdf):
    robot, urdf = robot_and_urdf
    for leg in robot.legs:
        for name, lo, hi in zip(leg.joint_names, leg.q_lower, leg.q_upper):
            limit = urdf.joint_map[name].limit
            assert (limit.lower, limit.upper) == pytest.approx((lo, hi), abs=1e-12)


def test_closed_form_fk_matches_yourdfpy(robot_and_urdf):
    """Random in-limit joint values: foot in the root frame from yourdfpy's scene graph
    equals the closed form of eq 3.5 (with axis signs and zero offsets from the model)."""
    robot, urdf = robot_and_urdf
    rng = np.random.default_rng(5)
    root = urdf.base_link
    lower = np.concatenate([leg.q_lower for leg in robot.legs])
    upper = np.concatenate([leg.q_upper for leg in robot.legs])
    q = rng.uniform(lower, upper, size=(N_SAMPLES, 12))
    names = robot.joint_names
    worst = 0.0
    for sample in q:
        urdf.update_cfg(dict(zip(names, sample)))
        for k, leg in enumerate(robot.legs):
            parsed = urdf.get_transform(leg.foot_frame, root)[:3, 3]
            ours = kinematics.forward_kinematics(leg, sample[3 * k : 3 * k + 3])
            worst = max(worst, float(np.abs(parsed - ours).max()))
    assert worst < FK_TOLERANCE
