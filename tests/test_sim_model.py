"""The MuJoCo model against Pinocchio, the servo law, the calibration, and the measures on
synthetic data (silo4sim.model, silo4sim.replay, silo4sim.metrics)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from planner.path.plan_path import plan_path
from planner.trajectory.torques import add_torques
from silo4kin import load_robot
from silo4sim.errors import MujocoModelError
from silo4sim.metrics import (
    Thresholds,
    _judged,
    body_angles,
    measure,
    measure_standing,
    stance_slip,
)
from silo4sim.model import build_sim_model
from silo4sim.replay import initial_qpos, servo_command, stand_still
from silo4sim.settings import SimSettings

mujoco = pytest.importorskip("mujoco")
ROBOTS = Path(__file__).resolve().parent / "robots"
#: Foot positions MuJoCo vs Pinocchio: both evaluate the same URDF transforms in double
#: precision (stack-notes: agreed to 1e-9).
TOL_FK_M = 1e-9


#: A xacro variant of SILO4 (longer femur and tibia, hips further out: tests/test_discovery.py).
VARIANT_ARGS = {"L2": 0.3, "L3": 0.35, "Lb": 0.25}


@pytest.fixture(scope="module", params=["silo4", "mantis", "silo4-variant"])
def robot_and_plan(request):
    robot = {
        "silo4": lambda: load_robot(),
        "mantis": lambda: load_robot(ROBOTS / "mantis.urdf"),
        "silo4-variant": lambda: load_robot(xacro_args=VARIANT_ARGS),
    }[request.param]()
    plan = plan_path(
        robot, np.array([[0.0, 0.5]]), 0.4, start_heading=math.pi / 2, samples_per_unit=20
    )
    return robot, add_torques(robot, plan.trajectory, load="total")


def test_mass_and_feet_agree_with_pinocchio(robot_and_plan):
    """Total mass equals the URDF's; with the plan's first posture on the free base, every
    foot sphere centre sits at the planned foot position (MuJoCo FK vs the planner's)."""
    robot, traj = robot_and_plan
    sm = build_sim_model(robot)
    assert sum(sm.model.body_mass) == pytest.approx(robot.total_mass, rel=1e-12)
    data = mujoco.MjData(sm.model)
    data.qpos[:] = initial_qpos(sm, traj)
    mujoco.mj_forward(sm.model, data)
    feet = np.array([data.site(f"{leg.name}_foot").xpos for leg in robot.legs])
    np.testing.assert_allclose(feet, traj.position_foot_in_world[0], atol=TOL_FK_M)
    com = data.site("body_com").xpos
    np.testing.assert_allclose(com, traj.position_base_in_world[0], atol=TOL_FK_M)


def test_gravity_torques_agree_with_pinocchio(robot_and_plan):
    """Joint gravity torques at rest (qfrc_bias) equal Pinocchio's on the free-flyer model:
    the inertia fix-up only raises rotational inertia, it moves no mass."""
    robot, traj = robot_and_plan
    sm = build_sim_model(robot)
    data = mujoco.MjData(sm.model)
    data.qpos[:] = initial_qpos(sm, traj)
    mujoco.mj_forward(sm.model, data)
    dof = [sm.model.jnt_dofadr[sm.model.joint(n).id] for n in sm.joint_names]
    model_ff = robot.model_free_flyer
    q = pin.neutral(model_ff)
    q[:7] = np.r_[data.qpos[:3], data.qpos[4:7], data.qpos[3]]  # w x y z -> x y z w
    for name, value in zip(sm.joint_names, data.qpos[sm.qpos_adr]):
        q[model_ff.joints[model_ff.getJointId(name)].idx_q] = value
    g = pin.computeGeneralizedGravity(model_ff, model_ff.createData(), q)
    g_joint = [g[model_ff.joints[model_ff.getJointId(n)].idx_v] for n in sm.joint_names]
    np.testing.assert_allclose(data.qfrc_bias[dof], g_joint, atol=1e-9)


def test_servo_is_pd_plus_feedforward_clamped(robot_and_plan):
    """actuator force = kp (q_ref - q) + kd (q̇_ref - q̇) + tau_ff, clamped to the effort
    limit, for the command u of servo_command (random states, one clamped on purpose)."""
    robot, traj = robot_and_plan
    sm = build_sim_model(robot)
    rng = np.random.default_rng(7)
    data = mujoco.MjData(sm.model)
    data.qpos[:] = initial_qpos(sm, traj)
    dof = [sm.model.jnt_dofadr[sm.model.joint(n).id] for n in sm.joint_names]
    q = data.qpos[sm.qpos_adr] + rng.normal(0, 0.01, 12)
    qd = rng.normal(0, 0.5, 12)
    data.qpos[sm.qpos_adr] = q
    data.qvel[dof] = qd
    q_ref, qd_ref = q + rng.normal(0, 0.005, 12), rng.normal(0, 0.5, 12)
    tau_ff = rng.normal(0, 5, 12)
    tau_ff[0] = 10 * sm.effort_limit[0]
    ref = type("R", (), {"q": q_ref, "qd": qd_ref, "tau": tau_ff})()
    data.ctrl[:] = servo_command(sm, ref)
    mujoco.mj_forward(sm.model, data)
    expected = np.clip(
        sm.kp * (q_ref - q) + sm.kd * (qd_ref - qd) + tau_ff, -sm.effort_limit, sm.effort_limit
    )
    np.testing.assert_allclose(data.actuator_force, expected, rtol=1e-9, atol=1e-9)
    assert data.actuator_force[0] == pytest.approx(sm.effort_limit[0])


def test_calibration_standing_still_moves_less_than_1_mm(robot_and_plan):
    """Holding the first posture for 3 s: CoG and feet move < 1 mm (issue 10)."""
    robot, traj = robot_and_plan
    sm = build_sim_model(robot)
    cal = measure_standing(sm, stand_still(sm, traj, 3.0))
    assert cal["ok"] and cal["base_drift_m"] < 1e-3 and cal["foot_slip_m"] < 1e-3
    assert cal["seconds"] == pytest.approx(3.0)


def test_calibration_catches_soft_contacts(robot_and_plan):
    """The calibration can fail: MuJoCo's default soft contact (solref 0.02 s, solimp 0.9)
    lets the standing robot sink by several mm."""
    robot, traj = robot_and_plan
    sm = build_sim_model(
        robot, SimSettings(contact_timeconst_s=0.02, contact_impedance=(0.9, 0.95, 0.001))
    )
    cal = measure_standing(sm, stand_still(sm, traj, 3.0))
    assert not cal["ok"] and cal["base_drift_m"] > 2e-3


def test_a_failed_calibration_blames_the_simulation_and_skips_the_replay(silo4):
    """simulate() with soft contacts: not walking, the reason says the simulation is wrong,
    and no plan figure is given."""
    from silo4sim.run import simulate

    plan = plan_path(silo4, np.array([[0.0, 0.5]]), 0.4, samples_per_unit=20)
    traj = add_torques(silo4, plan.trajectory, load="total")
    result = simulate(
        silo4,
        traj,
        settings=SimSettings(contact_timeconst_s=0.02, contact_impedance=(0.9, 0.95, 0.001)),
    )
    doc = result.metrics
    assert not doc["walks"] and not doc["calibration"]["ok"]
    assert "the simulation, not the plan, is wrong" in doc["reasons"][0]
    assert result.record is None and "drift_max_m" not in doc and result.arrays() == {}


def test_a_failed_calibration_of_a_plan_starting_in_swing_blames_the_plan(silo4):
    """A plan whose first sample has a foot in swing has no rest posture to calibrate on
    (issue 21: its torques leave that foot unloaded on the floor): the reason says so."""
    from dataclasses import replace

    from silo4sim.run import simulate

    plan = plan_path(silo4, np.array([[0.0, 0.5]]), 0.4, samples_per_unit=20)
    traj = add_torques(silo4, plan.trajectory, load="total")
    contact = traj.contact.copy()
    contact[0, 2] = False
    result = simulate(
        silo4,
        replace(traj, contact=contact),
        settings=SimSettings(contact_timeconst_s=0.02, contact_impedance=(0.9, 0.95, 0.001)),
    )
    reason = result.metrics["reasons"][0]
    assert "does not start at rest on four feet (LH in swing" in reason
    assert "the plan, not the simulation, is wrong" in reason


def test_a_urdf_mujoco_refuses_names_the_element(tmp_path):
    """A collision mesh whose file is missing: MujocoModelError quoting MuJoCo's message,
    which names the file."""
    robot = load_robot()
    broken = robot.urdf_xml.replace(
        '<link name="base_link">',
        '<link name="base_link"><collision><geometry><mesh filename="'
        f'{tmp_path}/no_such_body.stl"/></geometry></collision>',
        1,
    )
    with pytest.raises(MujocoModelError, match="no_such_body.stl"):
        build_sim_model(replace(robot, urdf_xml=broken))


def test_body_angles_of_known_rotations():
    """Roll, pitch, yaw and tilt of quaternions built from known angles (Z-Y-X)."""
    roll, pitch, yaw = 0.1, -0.2, 2.5
    rot = pin.rpy.rpyToMatrix(roll, pitch, yaw)
    x, y, z, w = pin.Quaternion(rot).coeffs()
    angles = body_angles(np.array([[w, x, y, z]]))
    assert angles["roll"][0] == pytest.approx(roll, abs=1e-12)
    assert angles["pitch"][0] == pytest.approx(pitch, abs=1e-12)
    assert angles["yaw"][0] == pytest.approx(yaw, abs=1e-12)
    assert angles["tilt"][0] == pytest.approx(math.acos(rot[2, 2]), abs=1e-12)


def test_stance_slip_measures_from_touchdown_and_ignores_transitions():
    """Two stances: the first foot drifts 3 mm inside its judged window, the second jumps
    10 mm only within the transition margin (not judged) -> slips (0.003, 0)."""
    stance = np.zeros(100, dtype=bool)
    stance[10:40] = stance[60:90] = True
    xy = np.zeros((100, 2))
    xy[10:40, 0] = np.linspace(0.0, 0.003, 30)
    xy[10:40, 0] -= xy[15, 0]  # relative to the judged start: 5 steps after touch-down
    xy[60:64, 1] = 0.010
    slip, starts = stance_slip(xy, stance, margin=5)
    assert list(starts) == [15, 65]
    assert slip[0] == pytest.approx(xy[34, 0] - xy[15, 0]) and slip[1] == 0.0
    mask, s0, s1 = _judged(stance, 5)
    assert mask.sum() == 40 and list(s1) == [35, 85]


def test_thresholds_defaults_are_the_issue_defaults():
    th = Thresholds()
    assert (th.drift_m, th.slip_m, th.yaw_deg, th.tilt_deg) == (0.020, 0.005, 5.0, 20.0)


def _synthetic_record(sm, n: int = 1000):  # noqa: ANN001, ANN202
    """A standing reference and sensors that read exactly what the plan asks (dt = 1 ms)."""
    from silo4sim.replay import Reference, SimRecord

    dt = sm.settings.timestep_s
    contact = np.ones((n, 4), dtype=bool)
    contact[300:700, 0] = False  # LF swings, 50 mm high
    feet = np.zeros((n, 4, 3))
    feet[300:700, 0, 2] = 0.05
    ref = Reference(
        t=np.arange(n) * dt,
        q=np.zeros((n, 12)),
        qd=np.zeros((n, 12)),
        tau=np.zeros((n, 12)),
        position_base_in_world=np.tile([0, 0, 0.4], (n, 1)),
        yaw_base_in_world=np.zeros(n),
        contact=contact,
        position_foot_in_world=feet,
        position_ball_centre_in_world=feet,  # SILO4's point feet: the foot point itself
    )
    sensors = np.zeros((n, sm.model.nsensordata))
    sensors[:, sm.sensor["body_position"]] = [0, 0, 0.4]
    sensors[:, sm.sensor["body_quat"]] = [1, 0, 0, 0]
    sensors[:, sm.sensor["foot_force"]] = np.where(contact, 50.0, 0.0)
    return ref, sensors, SimRecord


def test_measure_counts_scuffs_lost_contacts_strikes_and_limits(silo4):
    """Synthetic sensors with known events -> the figures name them with their durations:
    LF scuffs 50 ms mid-swing, RF loses contact 100 ms, the body touches for 21 ms, LF hip
    yaw sits at its effort limit 100 ms, the CoG drifts 30 mm -> does not walk."""
    sm = build_sim_model(silo4)
    ref, sensors, SimRecord = _synthetic_record(sm)
    foot = sm.sensor["foot_force"].start
    sensors[400:450, foot + 0] = 5.0
    sensors[100:200, foot + 1] = 0.0
    sensors[800:821, sm.sensor["body_force"].start + sm.contact_bodies.index("base_link")] = 10
    sensors[500:600, sm.sensor["tau"].start] = sm.effort_limit[0]
    sensors[:, sm.sensor["body_position"].start] = np.linspace(0, 0.03, len(ref.t))
    doc = measure(sm, SimRecord(reference=ref, sensors=sensors, steps_run=len(ref.t)))
    assert doc["scuff_s"] == {"LF": 0.05, "RF": 0.0, "LH": 0.0, "RH": 0.0}
    assert doc["missing_contact_s"]["RF"] == pytest.approx(0.1)
    assert doc["stances_missing_contact"] == 1
    assert doc["non_foot_contacts"] == {"base_link": {"seconds": 0.021, "first_s": 0.8}}
    assert doc["effort_limit_s"][sm.joint_names[0]] == pytest.approx(0.1)
    assert doc["drift_max_m"] == pytest.approx(0.03) and not doc["fell"]
    assert not doc["walks"] and len(doc["reasons"]) == 2


def test_measure_sees_a_fall_and_a_clean_stand(silo4):
    """The same reference read back exactly walks; tilted 30 deg at the end it has fallen."""
    sm = build_sim_model(silo4)
    ref, sensors, SimRecord = _synthetic_record(sm)
    doc = measure(sm, SimRecord(reference=ref, sensors=sensors, steps_run=len(ref.t)))
    assert doc["walks"] and doc["drift_max_m"] == 0.0 and doc["scuff_s"]["LF"] == 0.0
    half = math.radians(30) / 2
    sensors[900:, sm.sensor["body_quat"]] = [math.cos(half), math.sin(half), 0, 0]
    doc = measure(sm, SimRecord(reference=ref, sensors=sensors, steps_run=len(ref.t)))
    assert doc["fell"] and doc["fell_at_s"] == pytest.approx(0.9)
    assert doc["max_roll_deg"] == pytest.approx(30.0) and not doc["walks"]
