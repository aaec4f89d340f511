"""The robot description is tested code: it expands, names follow the convention, every
actuated joint has limits, masses sum right, and bad input gets a clear error."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from silo4kin import (
    DEFAULT_XACRO,
    LEG_NAMES,
    RobotDescriptionError,
    XacroArgumentError,
    load_robot,
)
from silo4kin.xacro_files import declared_xacro_args, expand_xacro

#: Table A.1 + §2.1: 30 kg body + 4 x (1.22 + 1.26 + 0.63) kg [kg]; exact decimal sums,
#: float rounding only.
SILO4_TOTAL_MASS = 42.44
MASS_TOLERANCE = 1e-9
#: Geometry read back from the model vs the thesis's tables [m]; xacro prints ~15 digits.
GEOMETRY_TOLERANCE = 1e-12


def test_xacro_expands_to_a_urdf_with_the_naming_convention(silo4):
    """Joints {leg}_{hip_yaw,hip_pitch,knee}, links coxa/femur/tibia/foot, base_link root."""
    names = set(silo4.model.names[1:])
    for leg in LEG_NAMES:
        for suffix in ("hip_yaw", "hip_pitch", "knee"):
            assert f"{leg}_{suffix}" in names
        for link in ("coxa", "femur", "tibia", "foot"):
            assert silo4.model.existFrame(f"{leg}_{link}")
    assert silo4.model.frames[1].name == "base_link"
    assert silo4.joint_names[:3] == ["LF_hip_yaw", "LF_hip_pitch", "LF_knee"]
    assert [leg.name for leg in silo4.legs] == list(LEG_NAMES)


def test_pinocchio_orders_joints_by_name_and_we_map_by_name(silo4):
    """Pinocchio puts LH before RF; our order is LF, RF, LH, RH; q_index maps them."""
    pin_names = list(silo4.model.names[1:])
    assert pin_names.index("LH_hip_yaw") < pin_names.index("RF_hip_yaw")
    for k, name in enumerate(silo4.joint_names):
        assert pin_names[silo4.q_index[k]] == name
    q = np.arange(12.0)
    assert np.array_equal(silo4.from_pinocchio_q(silo4.to_pinocchio_q(q)), q)


def test_every_actuated_joint_has_limits_and_knee_down_range(silo4):
    """theta1 in [-90°, 90°] (thesis §3.2); knee-down: theta3 <= 0."""
    for leg in silo4.legs:
        assert np.all(np.isfinite(leg.q_lower)) and np.all(np.isfinite(leg.q_upper))
        assert np.all(leg.q_lower < leg.q_upper)
        assert leg.theta_lower[0] == pytest.approx(-math.pi / 2, abs=1e-12)
        assert leg.theta_upper[0] == pytest.approx(math.pi / 2, abs=1e-12)
        assert leg.theta_upper[2] <= 0.0
    assert np.all(silo4.model.effortLimit > 0) and np.all(silo4.model.velocityLimit > 0)


def test_masses_sum_to_table_a1_plus_body(silo4):
    """Free-flyer total mass 42.44 kg; body 30 kg with its CoG at the base origin."""
    assert silo4.model_free_flyer.nq == 19
    assert abs(silo4.total_mass - SILO4_TOTAL_MASS) < MASS_TOLERANCE
    assert abs(silo4.body_mass - 30.0) < MASS_TOLERANCE
    assert np.abs(silo4.position_body_com_in_base).max() < GEOMETRY_TOLERANCE


def test_leg_geometry_is_read_from_the_model_and_matches_table_3_1(silo4):
    """Lb 0.22, Lz 0.15, L1 0.06, L2 = L3 = 0.24, theta_b = thesis theta_b - pi/2."""
    thesis_theta_b = {
        "LF": 3 * math.pi / 4,
        "RF": math.pi / 4,
        "LH": -3 * math.pi / 4,
        "RH": -math.pi / 4,
    }
    for leg in silo4.legs:
        assert abs(leg.L1 - 0.06) < GEOMETRY_TOLERANCE
        assert abs(leg.L2 - 0.24) < GEOMETRY_TOLERANCE
        assert abs(leg.L3 - 0.24) < GEOMETRY_TOLERANCE
        assert abs(np.hypot(*leg.position_hip_in_base[:2]) - 0.22) < GEOMETRY_TOLERANCE
        assert abs(leg.hip_height + 0.15) < GEOMETRY_TOLERANCE
        expected = thesis_theta_b[leg.name] - math.pi / 2
        assert abs(math.remainder(leg.theta_b - expected, 2 * math.pi)) < GEOMETRY_TOLERANCE
        assert np.array_equal(leg.axis_sign, [1.0, 1.0, 1.0])
        assert np.abs(leg.zero_offset).max() < GEOMETRY_TOLERANCE
        masses = [link.mass for link in leg.links]
        assert masses == pytest.approx([1.22, 1.26, 0.63], abs=1e-12)
        assert [link.com[0] for link in leg.links] == pytest.approx(
            [0.0478, 0.1306, 0.1555], abs=1e-12
        )


def test_scalar_inertia_becomes_a_slender_rod_tensor(silo4):
    """Table A.1's scalar I -> diag(0, I, I) in the link frame (x along the link)."""
    for leg in silo4.legs:
        for link, inertia in zip(leg.links, (0.0184, 0.0225, 0.0108)):
            assert np.allclose(link.inertia, np.diag([0.0, inertia, inertia]), rtol=0, atol=1e-12)


def test_a_xacro_argument_changes_the_model_and_the_closed_form_input():
    """One argument away: L3 = 0.3 shows up in LegGeometry (no second copy of the numbers)."""
    robot = load_robot(xacro_args={"L3": 0.3, "body_mass": 25})
    assert all(abs(leg.L3 - 0.3) < GEOMETRY_TOLERANCE for leg in robot.legs)
    assert abs(robot.total_mass - (25 + 4 * 3.11)) < MASS_TOLERANCE


def test_unknown_xacro_argument_lists_the_valid_ones():
    with pytest.raises(XacroArgumentError) as err:
        load_robot(xacro_args={"L4": 0.3})
    assert "L4" in str(err.value) and "L3" in str(err.value)
    assert "L1" in err.value.valid


def test_non_numeric_xacro_argument_is_refused():
    with pytest.raises(XacroArgumentError, match="not a number"):
        load_robot(xacro_args={"L2": "long"})


def test_declared_arguments_cover_every_geometric_and_mass_parameter():
    names = set(declared_xacro_args(DEFAULT_XACRO))
    assert {
        "L1",
        "L2",
        "L3",
        "Lb",
        "Lz",
        "m1",
        "m2",
        "m3",
        "Lcm1",
        "Lcm2",
        "Lcm3",
        "I1",
        "I2",
        "I3",
        "body_mass",
        "body_length",
        "body_width",
        "body_height",
        "theta_b_LF",
        "theta_b_RF",
        "theta_b_LH",
        "theta_b_RH",
    } <= names


def test_missing_file_is_a_clear_error(tmp_path: Path):
    with pytest.raises(RobotDescriptionError, match="not found"):
        load_robot(tmp_path / "nope.urdf")


def test_malformed_urdf_is_a_clear_error(tmp_path: Path):
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'></robot>")
    with pytest.raises(RobotDescriptionError, match="malformed"):
        load_robot(bad)


def test_broken_urdf_is_refused_by_pinocchio(tmp_path: Path):
    """A joint whose parent link does not exist."""
    urdf = expand_xacro(DEFAULT_XACRO).replace('<parent link="LF_coxa"/>', '<parent link="ghost"/>')
    path = tmp_path / "broken.urdf"
    path.write_text(urdf)
    with pytest.raises(RobotDescriptionError):
        load_robot(path)


def test_model_without_the_expected_joints_is_refused(tmp_path: Path):
    """A robot whose legs are not named (nor discoverable) as SILO4's."""
    urdf = (
        "<robot name='stick'><link name='base_link'/><link name='a'/>"
        "<joint name='j' type='revolute'><parent link='base_link'/><child link='a'/>"
        "<axis xyz='0 0 1'/><limit lower='-1' upper='1' effort='1' velocity='1'/></joint>"
        "</robot>"
    )
    path = tmp_path / "stick.urdf"
    path.write_text(urdf)
    with pytest.raises(RobotDescriptionError):
        load_robot(path)


def test_loader_rejects_a_leg_whose_first_axis_is_not_vertical(silo4, tmp_path: Path):
    """A hip ab/adduction leg (first axis along x) is not an insect leg."""
    urdf = silo4.urdf_xml
    start = urdf.index('<joint name="LF_hip_yaw"')
    end = urdf.index("</joint>", start)
    joint = urdf[start:end].replace('<axis xyz="0 0 1"/>', '<axis xyz="1 0 0"/>')
    path = tmp_path / "mammal.urdf"
    path.write_text(urdf[:start] + joint + urdf[end:])
    with pytest.raises(RobotDescriptionError, match="vertical"):
        load_robot(path)


def test_visual_model_has_primitive_geometry_for_every_link(silo4):
    """Box body, a cylinder per leg link, a sphere per foot: 1 + 4 x 4 visuals."""
    geoms = silo4.visual_model.geometryObjects
    assert len(geoms) == 17
    kinds = sorted(type(g.geometry).__name__ for g in geoms)
    assert kinds.count("Cylinder") == 12 and kinds.count("Sphere") == 4
    assert kinds.count("Box") == 1


def test_leg_geometry_is_frozen(silo4):
    with pytest.raises(dataclasses.FrozenInstanceError):
        silo4.legs[0].L1 = 1.0  # type: ignore[misc]


def test_gravity_is_standard(silo4):
    assert silo4.model.gravity.linear == pytest.approx([0, 0, -9.81])
    assert isinstance(silo4.model, pin.Model)


@pytest.mark.parametrize("name,chains", [("ur5", 1), ("talos", 3)])
def test_example_robot_that_is_not_a_quadruped_is_named_so(name: str, chains: int) -> None:
    """example-robot-data's arm and humanoid: "not a quadruped: found N leg chains"."""
    pytest.importorskip("example_robot_data")
    with pytest.raises(RobotDescriptionError, match=f"not a quadruped: found {chains} leg chain"):
        load_robot(name)


def test_robot_descriptions_name_loads_the_library_robot() -> None:
    """``go2_description`` (robot_descriptions.py's name, and go2's URDF name) is go2."""
    pytest.importorskip("example_robot_data")
    robot = load_robot("go2_description")
    assert robot.library_name == "go2"
    assert robot.family == "mammal"


def test_unknown_robot_name_suggests_the_closest() -> None:
    """A typo gets difflib's closest known name."""
    with pytest.raises(RobotDescriptionError, match="did you mean go2"):
        load_robot("go3")


def test_legs_in_millimetres_are_refused() -> None:
    """A tibia given in mm (L3=240): "leg length ... m: did you give millimetres?"."""
    with pytest.raises(RobotDescriptionError, match="did you give millimetres"):
        load_robot(xacro_args={"L3": 240})
