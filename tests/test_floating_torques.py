"""The default torques (load "total"): whole-body inverse dynamics of the floating robot
(planner/trajectory/floating_torques.py).

Checked sample by sample against Pinocchio's free-flyer RNEA with our 3-D contact forces as
external forces at the contact points (a ball foot's below its centre): the base wrench
vanishes and the joint torques are ours. The base's rates from the samples against their
analytic values; at rest the torques are the quasi-static ones (silo4kin.joint_torques load
"total"); a retimed plan's torques split into static + dynamic / T² as the limits assume.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner.trajectory.floating_torques import base_rates, floating_torques
from planner.trajectory.limits import at_rest, retime
from planner.trajectory.samples import Trajectory
from silo4kin import legs as leg_families
from silo4kin.foot_contact import foot_ball
from silo4kin.joint_torques import feet_in_base, joint_torques
from silo4kin.robot import Robot, load_robot

N_SAMPLES = 400
#: Equilibrium residual [N, N m]: a 6 x 6 solve and RNEA of O(100-500 N) loads, rounding only.
EQUILIBRIUM_TOLERANCE = 1e-8


def _stance_q(robot: Robot, height_m: float) -> np.ndarray:
    """Joint values (12,) with every foot frame below its hip at ``height_m`` under the root."""
    q = np.empty(12)
    for k, leg in enumerate(robot.legs):
        hip = np.asarray(leg.position_hip_in_base, dtype=float)
        p = np.array([[hip[0], hip[1] + 0.03 * np.sign(hip[1]), -height_m]])
        q[3 * k : 3 * k + 3] = leg_families.inverse_kinematics(leg, p).q[0]
    return q


def _moving_trajectory(robot: Robot, contact: np.ndarray, seed: int) -> tuple[Trajectory, dict]:
    """A trajectory whose base moves and yaws (analytic rates returned beside it) and whose
    joints oscillate about a stance; contact points the foot frames minus the ball radius."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 4.0, N_SAMPLES)
    tc = t[:, None]
    q0 = _stance_q(robot, 0.25 if robot.family == "mammal" else 0.35)
    a, w, phi = rng.uniform(0.02, 0.1, 12), rng.uniform(0.5, 3.0, 12), rng.uniform(0, 6, 12)
    q = q0 + a * np.sin(w * tc + phi)
    qd = a * w * np.cos(w * tc + phi)
    qdd = -a * w**2 * np.sin(w * tc + phi)
    base = np.stack([0.1 * t + 0.02 * t**2, 0.05 * t, 0.3 + 0.01 * np.sin(2 * t)], axis=1)
    base_d = np.stack([0.1 + 0.04 * t, np.full_like(t, 0.05), 0.02 * np.cos(2 * t)], axis=1)
    base_dd = np.stack([np.full_like(t, 0.04), 0 * t, -0.04 * np.sin(2 * t)], axis=1)
    yaw, yaw_d, yaw_dd = 0.3 + 0.2 * t + 0.05 * t**2, 0.2 + 0.1 * t, np.full_like(t, 0.1)
    # the trajectory's base is the body CoG: the root plus the CoG offset turned by yaw
    com = np.asarray(robot.position_body_com_in_base)
    c, s = np.cos(yaw), np.sin(yaw)
    cog = base + np.stack([c * com[0] - s * com[1], s * com[0] + c * com[1], 0 * t + com[2]], 1)
    centre = feet_in_base(robot, q)  # foot frames in the root frame
    radius = foot_ball(robot).radius_m
    world = np.stack(
        [
            base[:, None, 0] + c[:, None] * centre[..., 0] - s[:, None] * centre[..., 1],
            base[:, None, 1] + s[:, None] * centre[..., 0] + c[:, None] * centre[..., 1],
            base[:, None, 2] + centre[..., 2] - radius,
        ],
        axis=2,
    )
    traj = Trajectory(
        t=t,
        unit_time_s=1.0,
        position_base_in_world=cog,
        yaw_base_in_world=yaw,
        joint_names=tuple(robot.joint_names),
        q=q,
        qd=qd,
        qdd=qdd,
        position_foot_in_world=world,
        contact=np.broadcast_to(contact, (N_SAMPLES, 4)).copy(),
        margin=np.ones(N_SAMPLES),
        phase=np.full(N_SAMPLES, "body"),
    )
    rates = dict(base=base, base_d=base_d, base_dd=base_dd, yaw_d=yaw_d, yaw_dd=yaw_dd)
    return traj, rates


@pytest.fixture(scope="module", params=["silo4", "go2"])
def robot(request) -> Robot:
    if request.param == "go2":
        pytest.importorskip("example_robot_data")
    return load_robot(request.param)


@pytest.mark.parametrize("contact", [(1, 1, 1, 1), (1, 0, 1, 1)])
def test_the_floating_robot_is_in_equilibrium_against_pinocchio(robot, contact) -> None:
    """Pinocchio's free-flyer RNEA, base and joints moving as the samples, with our forces as
    external forces at the contact points: zero base wrench and our joint torques."""
    traj, _ = _moving_trajectory(robot, np.array(contact, bool), seed=5)
    out = floating_torques(robot, traj, transfer_s=0.0)
    assert out.wrench_residual.max() < EQUILIBRIUM_TOLERANCE
    model = robot.model_free_flyer
    data = model.createData()
    idx_q = np.array([model.joints[model.getJointId(j)].idx_q for j in robot.joint_names])
    idx_v = np.array([model.joints[model.getJointId(j)].idx_v for j in robot.joint_names])
    v_cog, a_cog = base_rates(traj)
    com = np.asarray(robot.position_body_com_in_base)
    feet = [model.getFrameId(leg.foot_frame) for leg in robot.legs]
    parents = [model.frames[f].parentJoint for f in feet]
    worst_base, worst_joint = 0.0, 0.0
    for i in range(0, N_SAMPLES, 13):
        yaw = traj.yaw_base_in_world[i]
        rz = pin.utils.rpyToMatrix(0.0, 0.0, yaw)
        q = np.zeros(model.nq)
        q[:3] = traj.position_base_in_world[i] - rz @ com
        q[3:7] = pin.Quaternion(rz).coeffs()
        q[idx_q] = traj.q[i]
        v, a = np.zeros(model.nv), np.zeros(model.nv)
        omega = np.array([0.0, 0.0, v_cog[i, 5]])
        v[:3] = v_cog[i, :3] - np.cross(omega, com)
        v[5] = v_cog[i, 5]
        a[:3] = a_cog[i, :3] - np.cross([0.0, 0.0, a_cog[i, 5]], com)
        a[5] = a_cog[i, 5]
        v[idx_v], a[idx_v] = traj.qd[i], traj.qdd[i]
        pin.forwardKinematics(model, data, q)
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        for k in range(4):
            if not traj.contact[i, k]:
                continue
            joint = data.oMi[parents[k]]
            f_world = rz @ out.force_foot_in_base[i, k]
            force = joint.rotation.T @ f_world
            lever = joint.rotation.T @ (traj.position_foot_in_world[i, k] - joint.translation)
            fext[parents[k]] = pin.Force(force, np.cross(lever, force))
        tau = pin.rnea(model, data, q, v, a, fext)
        worst_base = max(worst_base, float(np.abs(tau[:6]).max()))
        worst_joint = max(worst_joint, float(np.abs(tau[idx_v] - out.torques.total[i]).max()))
    assert worst_base < EQUILIBRIUM_TOLERANCE
    assert worst_joint < EQUILIBRIUM_TOLERANCE
    # the floating robot's torques differ from App. A's fixed hips: the base moves
    fixed = joint_torques(robot, traj.q, traj.qd, traj.qdd, traj.contact, load="total")
    assert np.abs(out.torques.total - fixed.total).max() > 0.01
    assert np.all(out.force_foot_in_base[~traj.contact] == 0.0)


def test_base_rates_from_the_samples_match_their_analytic_values(robot) -> None:
    """Central differences over 400 samples in 4 s: O(Δt²), well under 1e-3 of the rates."""
    traj, exact = _moving_trajectory(robot, np.ones(4, bool), seed=7)
    v, a = base_rates(traj)
    yaw = traj.yaw_base_in_world
    com = np.asarray(robot.position_body_com_in_base)
    c, s = np.cos(yaw), np.sin(yaw)
    # the CoG's velocity (the samples' base) in the base's axes
    cog_d = exact["base_d"] + exact["yaw_d"][:, None] * np.stack(
        [-s * com[0] - c * com[1], c * com[0] - s * com[1], 0 * yaw], 1
    )
    local = np.stack([c * cog_d[:, 0] + s * cog_d[:, 1], -s * cog_d[:, 0] + c * cog_d[:, 1]], 1)
    assert np.abs(v[:, :2] - local).max() < 1e-3 * np.abs(local).max()
    assert np.abs(v[:, 5] - exact["yaw_d"]).max() < 1e-4
    assert np.abs(a[:, 5] - exact["yaw_dd"]).max() < 1e-3
    rest_v, rest_a = base_rates(at_rest(traj))
    assert not rest_v.any() and not rest_a.any()


def test_at_rest_the_torques_are_the_quasi_static_ones(robot) -> None:
    traj, _ = _moving_trajectory(robot, np.ones(4, bool), seed=9)
    still = at_rest(traj)
    out = floating_torques(robot, still, transfer_s=0.0)
    zero = np.zeros_like(traj.q)
    centre = feet_in_base(robot, traj.q)
    radius = foot_ball(robot).radius_m
    ref = joint_torques(
        robot,
        traj.q,
        zero,
        zero,
        traj.contact,
        position_foot_in_base=centre - np.array([0.0, 0.0, radius]),
        load="total",
    )
    assert np.abs(out.torques.total - ref.total).max() < 1e-9
    assert np.abs(out.force_foot_in_base[..., :2]).max() < 1e-9


def test_retimed_torques_split_into_static_and_dynamic_parts(robot) -> None:
    """τ(T) = τ_static + τ_dyn / T² (planner/trajectory/limits.py) holds for the floating
    robot: every dynamic term, the base's included, scales with 1 / T²."""
    traj, _ = _moving_trajectory(robot, np.ones(4, bool), seed=11)
    still = floating_torques(robot, at_rest(traj)).torques.total
    dyn = floating_torques(robot, traj).torques.total - still
    slow = floating_torques(robot, retime(traj, 2.5)).torques.total
    assert np.abs(slow - (still + dyn / 2.5**2)).max() < 1e-8
