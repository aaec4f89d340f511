"""Leg discovery: any insect-leg quadruped is found from its geometry, with no names
assumed, checked against Pinocchio; anything else is refused with a message naming the reason.

Robots: SILO4 (default xacro), a SILO4 xacro variant with other lengths, and
tests/robots/mantis.urdf, written for this suite with every convention unlike SILO4's.
Negative examples: solo12, anymal, hyq (example-robot-data) and SILO4 mutated one fault at a
time.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from silo4kin import LEG_NAMES, RobotDescriptionError, load_robot
from silo4kin.body_frame import body_com, hip_depth_below_com, legs_in_body_com_frame
from silo4kin.check import cross_check, format_report
from silo4kin.discovery import NotInsectLegError, discover_legs, format_discovery
from silo4kin.knee_convention import knee_convention
from silo4kin.robot import silo4_leg_names

ROBOTS_DIR = Path(__file__).resolve().parent / "robots"
MANTIS = ROBOTS_DIR / "mantis.urdf"
#: SILO4 with other lengths, one xacro argument each.
VARIANT_ARGS = {"L2": 0.3, "L3": 0.35, "Lb": 0.25}
#: Random states per robot for the closed form vs Pinocchio check (1000 per leg).
N_CROSS_CHECK = 1000
#: Geometry read back vs the numbers written in the URDF [m or rad]: the URDF prints 16-17
#: significant digits, the extraction adds a few roundings.
GEOMETRY_TOLERANCE = 1e-12

DEG = math.pi / 180.0


@pytest.fixture(scope="module")
def mantis():
    return load_robot(MANTIS)


@pytest.fixture(scope="module")
def variant():
    return load_robot(xacro_args=VARIANT_ARGS)


# ----------------------------------------------------------------------------- positives


def test_silo4_discovery_equals_the_naming_convention(silo4):
    """On SILO4, discovery finds exactly the legs the names say, in the order LF, RF, LH, RH."""
    found = discover_legs(silo4.model)
    assert list(found) == list(LEG_NAMES)
    assert found == silo4_leg_names(silo4.model)
    assert silo4.joint_names[:3] == ["LF_hip_yaw", "LF_hip_pitch", "LF_knee"]
    print(format_discovery(silo4))


def test_mantis_discovery_finds_the_written_geometry(mantis):
    """Names, rest directions, lengths, axis signs, zero offsets, Lz of the mantis header."""
    print(format_discovery(mantis))
    expected = {  # leg: (URDF prefix, theta_b, axis_sign)
        "LF": ("arm2", 90 * DEG, (1, 1, 1)),
        "RF": ("arm4", -90 * DEG, (1, 1, -1)),
        "LH": ("arm3", 90 * DEG, (1, 1, 1)),
        "RH": ("arm1", -90 * DEG, (-1, -1, -1)),
    }
    com = np.array([(14 * 0.03 + 1.5 * 0.18) / 15.5, 0.0, (14 * 0.02 + 0.2 + 0.5 * 0.35) / 15.5])
    assert mantis.body_mass == pytest.approx(15.5, abs=GEOMETRY_TOLERANCE)
    np.testing.assert_allclose(mantis.position_body_com_in_base, com, atol=GEOMETRY_TOLERANCE)
    for leg in mantis.legs:
        prefix, theta_b, signs = expected[leg.name]
        assert leg.joint_names == (f"{prefix}_swing", f"{prefix}_lift", f"{prefix}_flex")
        assert leg.foot_frame == f"{prefix}_paw"
        x = 0.2 if leg.name[1] == "F" else -0.2
        y = 0.15 if leg.name[0] == "L" else -0.15
        np.testing.assert_allclose(leg.position_hip_in_base, [x, y, -0.08], atol=GEOMETRY_TOLERANCE)
        assert leg.theta_b == pytest.approx(theta_b, abs=GEOMETRY_TOLERANCE)
        assert (leg.L1, leg.L2, leg.L3) == pytest.approx((0.05, 0.2, 0.28), abs=1e-12)
        assert leg.axis_sign.tolist() == list(signs)
        np.testing.assert_allclose(
            leg.zero_offset, [0, 20 * DEG, -110 * DEG], atol=GEOMETRY_TOLERANCE
        )
        assert hip_depth_below_com(leg, com) == pytest.approx(com[2] + 0.08, abs=1e-12)
        # DH limits are the same on every leg: theta1 +-60, theta2 [-70, 90], theta3 [-170, -10]
        np.testing.assert_allclose(leg.theta_lower, np.array([-60, -70, -170]) * DEG, atol=1e-12)
        np.testing.assert_allclose(leg.theta_upper, np.array([60, 90, -10]) * DEG, atol=1e-12)


def test_mantis_knee_down_direction_per_leg(mantis):
    """Knee-down (DH θ3 < 0) is q3 < 110° on the left legs and q3 > -110° on the mirrored right."""
    for leg in mantis.legs:
        knee = knee_convention(leg)
        right = leg.name[0] == "R"
        assert knee.knee_down_sign == (1 if right else -1)
        assert knee.q_straight == pytest.approx((-110 if right else 110) * DEG, abs=1e-12)
        # every allowed knee value is knee-down on mantis
        np.testing.assert_allclose(knee.q_knee_down, [leg.q_lower[2], leg.q_upper[2]], atol=1e-12)


def test_silo4_variant_discovery_reads_the_xacro_arguments(variant):
    """L2 = 0.3, L3 = 0.35 and hips 0.25 m from the CoG come back from the model."""
    print(format_discovery(variant))
    for leg in variant.legs:
        assert (leg.L2, leg.L3) == pytest.approx((0.3, 0.35), abs=GEOMETRY_TOLERANCE)
        assert np.hypot(*leg.position_hip_in_base[:2]) == pytest.approx(0.25, abs=1e-12)
        assert hip_depth_below_com(leg, variant.position_body_com_in_base) == pytest.approx(0.15)


@pytest.mark.parametrize("which", ["silo4_variant", "mantis"])
def test_closed_form_equals_pinocchio_on_discovered_robots(which, mantis, variant):
    """FK, J, J̇q̇, IK, M, Cq̇, G and rnea agree with Pinocchio on 1000 random in-limit states
    per leg, within the named tolerances of silo4kin.check (what `silo4 check --robot` runs)."""
    robot = mantis if which == "mantis" else variant
    rows = cross_check(robot, n=N_CROSS_CHECK, seed=606)
    print(f"\n{which}\n{format_report(rows)}")
    bad = [r for r in rows if not r.ok]
    assert not bad, bad


def test_cross_check_catches_a_wrong_axis_convention(mantis):
    """Control: with the RF knee's mirrored sign ignored, FK no longer matches Pinocchio."""
    legs = list(mantis.legs)
    legs[1] = dataclasses.replace(legs[1], axis_sign=np.array([1.0, 1.0, 1.0]))
    rows = cross_check(mantis, n=50, seed=1, legs=legs)
    assert any(not r.ok for r in rows if r.leg == "RF" and r.quantity == "fk")


def test_joint_origins_may_slide_along_their_axes(mantis, tmp_path: Path):
    """The same physical leg written with the hip-yaw origin 3 cm higher (pitch origin 3 cm
    lower) and the knee origin 2 cm along its axis gives the same LegGeometry."""
    urdf = MANTIS.read_text()
    start, end = urdf.index("<!-- ============ arm2"), urdf.index("<!-- ============ arm3")
    block = urdf[start:end]  # arm2 = LF
    edits = [
        (
            '<origin xyz="0.2 0.15 -0.08" rpy="0 0 0"/>',
            '<origin xyz="0.2 0.15 -0.05" rpy="0 0 0"/>',
        ),
        ('<origin xyz="0 0.025 0" rpy="0 0 0"/>', '<origin xyz="0 0.025 -0.03" rpy="0 0 0"/>'),
        ('<origin xyz="0 0.05 0" rpy="0 0 0"/>', '<origin xyz="0 0.05 -0.03" rpy="0 0 0"/>'),
        (
            '<origin xyz="0 0.18793852415718168 0.06840402866513374" rpy="0 0 0"/>',
            '<origin xyz="0.02 0.18793852415718168 0.06840402866513374" rpy="0 0 0"/>',
        ),
        ('<origin xyz="0 0 -0.12" rpy="0 0 0"/>', '<origin xyz="-0.02 0 -0.12" rpy="0 0 0"/>'),
        (
            '<origin xyz="0 0 -0.28" rpy="0.3 -0.2 0.5"/>',
            '<origin xyz="-0.02 0 -0.28" rpy="0.3 -0.2 0.5"/>',
        ),
    ]
    for old, new in edits:
        block = _edit(block, old, new)
    urdf = urdf[:start] + block + urdf[end:]
    path = tmp_path / "mantis_slid.urdf"
    path.write_text(urdf)
    slid = load_robot(path)
    a, b = mantis.leg("LF"), slid.leg("LF")
    assert b.joint_names == a.joint_names
    for field in ("position_hip_in_base", "theta_b", "L1", "L2", "L3", "axis_sign", "zero_offset"):
        np.testing.assert_allclose(getattr(b, field), getattr(a, field), atol=1e-12, err_msg=field)
    for la, lb in zip(a.links, b.links):
        np.testing.assert_allclose(lb.com, la.com, atol=1e-12)
        np.testing.assert_allclose(lb.inertia, la.inertia, atol=1e-12)
    assert all(r.ok for r in cross_check(slid, n=100, seed=2))


def test_body_cog_is_the_body_with_its_fixed_links_not_the_legs(mantis):
    """The stability point: root link + mast + lidar (15.5 kg), legs (4 x 1.95 kg) excluded;
    the fixed-base and free-flyer models agree on it."""
    mass, com = body_com(mantis.model)
    assert mass == pytest.approx(mantis.body_mass, abs=1e-12)
    np.testing.assert_allclose(com, mantis.position_body_com_in_base, atol=1e-15)
    assert mantis.total_mass - mantis.body_mass == pytest.approx(4 * 1.95, abs=1e-12)
    assert np.linalg.norm(com) > 0.05  # away from the root frame, on purpose


def test_legs_in_body_com_frame_move_only_the_hips(mantis):
    """Feet relative to the CoG = feet relative to the root minus the CoG; J unchanged."""
    from silo4kin.kinematics import forward_kinematics, jacobian

    com = mantis.position_body_com_in_base
    shifted = legs_in_body_com_frame(mantis.legs, com)
    rng = np.random.default_rng(7)
    for a, b in zip(mantis.legs, shifted):
        q = rng.uniform(a.q_lower, a.q_upper, size=(20, 3))
        np.testing.assert_allclose(
            forward_kinematics(b, q), forward_kinematics(a, q) - com, atol=1e-15
        )
        np.testing.assert_array_equal(jacobian(b, q), jacobian(a, q))
        assert hip_depth_below_com(a, com) == pytest.approx(-b.hip_height, abs=1e-15)


def test_mantis_joint_order_maps_to_pinocchio_by_name(mantis):
    """Our order LF RF LH RH = arm2, arm4, arm3, arm1; q_index points at the same names."""
    assert [n.split("_")[0] for n in mantis.joint_names[::3]] == ["arm2", "arm4", "arm3", "arm1"]
    pin_names = list(mantis.model.names[1:])
    for k, name in enumerate(mantis.joint_names):
        assert pin_names[mantis.q_index[k]] == name


# ----------------------------------------------------------------------------- negatives


def _example_robot_urdf(loader_name: str) -> tuple[Path, str]:
    from example_robot_data import robots_loader

    loader = getattr(robots_loader, loader_name)
    sub = os.path.join(loader.path, loader.urdf_subpath, loader.urdf_filename)
    models = robots_loader.getModelPath(sub)
    # meshes are package://example-robot-data/robots/...: resolve against the share folder
    return Path(models, sub), os.path.dirname(os.path.dirname(models))


@pytest.mark.parametrize("loader_name", ["Solo12Loader", "ANYmalLoader", "HyQLoader"])
def test_mammal_type_quadrupeds_are_not_insect_legs_but_load_as_mammals(loader_name):
    """solo12, anymal, hyq by file: the insect discovery refuses them naming the hip
    ab/adduction; load_robot recognises the mammal family (tests/test_mammal.py)."""
    from silo4kin.discovery import discover_legs

    path, share = _example_robot_urdf(loader_name)
    robot = load_robot(path, package_dirs=[share])
    assert robot.family == "mammal"
    with pytest.raises(
        NotInsectLegError,
        match=r"LF chain: first joint .* is not vertical"
        r".*hip ab/adduction",
    ) as info:
        discover_legs(robot.model)
    print(info.value)


def _silo4_text() -> str:
    return load_robot().urdf_xml


def _edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def _joint(text: str, name: str, old: str, new: str) -> str:
    """Replace ``old`` by ``new`` inside the <joint name=...> element only."""
    start = text.index(f'<joint name="{name}"')
    end = text.index("</joint>", start)
    return text[:start] + _edit(text[start:end], old, new) + text[end:]


MUTATIONS = {
    "continuous knee": (
        lambda s: _edit(s, 'name="LF_knee" type="revolute"', 'name="LF_knee" type="continuous"'),
        r"LF chain .*'LF_knee' is continuous",
    ),
    "prismatic knee": (
        lambda s: _edit(s, 'name="LF_knee" type="revolute"', 'name="LF_knee" type="prismatic"'),
        r"LF chain .*'LF_knee' is prismatic",
    ),
    "leg with 2 joints": (
        lambda s: _edit(s, 'name="RH_knee" type="revolute"', 'name="RH_knee" type="fixed"'),
        r"RH chain \['RH_hip_yaw', 'RH_hip_pitch'\] has 2 joints",
    ),
    "leg with 4 joints": (
        lambda s: _edit(
            s,
            '<joint name="LH_foot_joint" type="fixed">',
            '<joint name="LH_foot_joint" type="revolute"><axis xyz="0 -1 0"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/>',
        ),
        r"LH chain .* has 4 joints",
    ),
    "three legs": (
        lambda s: re.sub(
            r'name="RH_(hip_yaw|hip_pitch|knee)" type="revolute"', r'name="RH_\1" type="fixed"', s
        ),
        r"not a quadruped: found 3 leg chains",
    ),
    "a fifth moving chain": (
        lambda s: _edit(
            s,
            "</robot>",
            '<link name="pan"/><joint name="camera_pan" type="revolute">'
            '<parent link="base_link"/><child link="pan"/><axis xyz="0 0 1"/>'
            '<origin xyz="0.1 0.05 0.2"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>',
        ),
        r"moving joints outside the four legs: \[\['camera_pan'\]\]",
    ),
    "knee not parallel": (
        lambda s: _joint(s, "LF_knee", '<axis xyz="0 -1 0"/>', '<axis xyz="1 -1 0"/>'),
        r"LF chain: knee 'LF_knee' axis .* is not parallel",
    ),
    "pitch not horizontal": (
        lambda s: _joint(s, "RF_hip_pitch", '<axis xyz="0 -1 0"/>', '<axis xyz="0 -1 1"/>'),
        r"RF chain: hip pitch joint 'RF_hip_pitch' axis .* is not horizontal",
    ),
    "foot out of the leg plane": (
        lambda s: _joint(s, "LF_foot_joint", 'xyz="0.24 0 0"', 'xyz="0.24 0.02 0"'),
        r"LF chain: foot frame 'LF_foot' is 0.02 m out of the leg plane",
    ),
    "no coxa": (
        lambda s: _joint(s, "LH_hip_pitch", 'xyz="0.06 0 0"', 'xyz="0 0 0"'),
        r"LH chain: hip pitch 'LH_hip_pitch' axis crosses the hip yaw axis",
    ),
    "no foot link": (
        lambda s: re.sub(
            r'<joint name="LH_foot_joint".*?</joint>|<link name="LH_foot">.*?</link>',
            "",
            s,
            flags=re.S,
        ),
        r"LH chain: the knee 'LH_knee' carries no fixed child link",
    ),
    "knee-up limits only": (
        lambda s: _joint(
            s, "RH_knee", 'lower="-2.9670597283903604" upper="0.0"', 'lower="0.1" upper="2.0"'
        ),
        r"RH chain: knee 'RH_knee' limits \[0.1, 2\] rad allow no knee-down pose",
    ),
    "knee without range": (
        lambda s: _joint(
            s, "RH_knee", 'lower="-2.9670597283903604" upper="0.0"', 'lower="0" upper="0"'
        ),
        r"RH chain .*'RH_knee' has limits \[0.0, 0.0\]",
    ),
}


@pytest.mark.parametrize("fault", list(MUTATIONS))
def test_silo4_with_one_fault_is_refused_naming_the_chain_and_joint(fault, tmp_path: Path):
    """Each broken assumption gives NotInsectLegError naming the leg, joint and rule."""
    mutate, pattern = MUTATIONS[fault]
    path = tmp_path / "faulty.urdf"
    path.write_text(mutate(_silo4_text()))
    with pytest.raises(NotInsectLegError, match=pattern) as info:
        load_robot(path)
    assert str(info.value).startswith("faulty.urdf: ")
    print(f"{fault}: {info.value}")


def test_two_hips_on_one_corner_are_refused():
    """A hip moved to the front-left quadrant: two LF legs."""
    with pytest.raises(NotInsectLegError, match="two hips are LF"):
        load_robot(xacro_args={"theta_b_RH": 1.2})


def test_massless_body_is_refused():
    """The stability point is the body CoG: a body without mass has none."""
    with pytest.raises(RobotDescriptionError, match="has no mass"):
        load_robot(xacro_args={"body_mass": 0.0})


def test_a_free_flyer_model_is_refused(silo4):
    with pytest.raises(NotInsectLegError, match="fixed-base"):
        discover_legs(silo4.model_free_flyer)


def test_not_insect_leg_error_is_a_robot_description_error():
    """The CLI catches RobotDescriptionError (Silo4Error) and exits 2."""
    assert issubclass(NotInsectLegError, RobotDescriptionError)
    assert isinstance(pin.Model(), pin.Model)
