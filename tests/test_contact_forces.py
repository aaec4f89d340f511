"""Contact forces with headroom (planner/stability/contact_forces.py).

The independent reference for the ground force is Pinocchio's free-flyer RNEA of the whole
robot: with no contact forces in the model, the wrench it asks of the floating base is what
the ground must supply.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner import PlanningError, plan_path
from planner.model import planning_model
from planner.outputs.pipeline import RunRequest, plan_run
from planner.presets import PRESETS
from planner.stability.contact_forces import ContactForceCheck
from planner.stability.contact_rule import MIN_NORMAL_LOAD_FRACTION, ContactForceRule
from planner.trajectory.limits import retime
from silo4kin.robot import STANDARD_GRAVITY

#: The ground force from CoM central differences vs RNEA with the plan's analytic q̈ and
#: central differences of the base [N]: both differences err by ~dt²/6 |x'''| (dt = 0.005 s
#: at STRAIGHT_SAMPLES_PER_UNIT), < 0.05 N here; 0.5 N is 0.1 % of SILO4's weight and a
#: tenth of what the legs' own motion adds to the body's m a (checked below, so the
#: comparison can fail).
FORCE_TOLERANCE_N = 0.5
STRAIGHT = np.array([[0.0, 1.0], [1.0, 1.0], [0.0, 2.0], [0.0, 3.0]])
#: Samples per unit of the straight plan: the crawl that keeps the effort budget at h 0.2 m
#: (planner/gaits/load_caps.py), retimed to 0.5 s a unit, has base accelerations whose
#: central differences err by 0.70 N at 100 samples a unit (0.16 N at 200): the sampling,
#: not the force model, so the plan is sampled finer rather than the tolerance loosened.
STRAIGHT_SAMPLES_PER_UNIT = 200
#: Every RNEA_STRIDE-th interior sample is compared (~1000 RNEA calls).
RNEA_STRIDE = 14


@pytest.fixture(scope="module")
def straight(silo4):
    return plan_path(
        silo4,
        STRAIGHT,
        0.2,
        start_heading=np.pi / 2,
        samples_per_unit=STRAIGHT_SAMPLES_PER_UNIT,
    )


def _rnea_ground_force(robot, tr) -> np.ndarray:
    """Ground force (N, 3) in W from pin.rnea on the free-flyer model (yaw constant)."""
    model = robot.model_free_flyer.copy()
    model.gravity.linear = np.array([0.0, 0.0, -STANDARD_GRAVITY])
    data = model.createData()
    yaw = tr.yaw_base_in_world[0]
    rotation = pin.utils.rpyToMatrix(0.0, 0.0, yaw)
    quat = pin.Quaternion(rotation).coeffs()  # x, y, z, w
    root = tr.position_base_in_world - rotation @ robot.position_body_com_in_base
    vel = np.gradient(root, tr.t, axis=0)
    acc = np.gradient(vel, tr.t, axis=0)
    idx_q = [model.joints[model.getJointId(n)].idx_q for n in robot.joint_names]
    idx_v = [model.joints[model.getJointId(n)].idx_v for n in robot.joint_names]
    out = np.empty((len(tr), 3))
    for i in range(len(tr)):
        q, v, a = np.zeros(model.nq), np.zeros(model.nv), np.zeros(model.nv)
        q[:3], q[3:7], q[idx_q] = root[i], quat, tr.q[i]
        v[:3], v[idx_v] = rotation.T @ vel[i], tr.qd[i]
        a[:3], a[idx_v] = rotation.T @ acc[i], tr.qdd[i]  # ω = 0: spatial = classical
        out[i] = rotation @ pin.rnea(model, data, q, v, a)[:3]
    return out


def test_ground_force_and_friction_demand_match_free_flyer_rnea(silo4, straight):
    """m (c̈ + g ẑ) of the sampled CoM equals the free-flyer RNEA's base force, and so does
    the friction demand |F_xy| / F_z, away from step boundaries (where c̈ jumps)."""
    tr = straight.trajectory
    yaw = tr.yaw_base_in_world
    assert np.ptp(yaw) < 1e-12, "the reference below assumes a constant heading"
    model = planning_model(silo4)
    forces = ContactForceCheck(ContactForceRule(), model, STANDARD_GRAVITY).forces(tr)
    boundaries = np.array([s.t_start for s in straight.steps] + [straight.steps[-1].t_end])
    dt = tr.time_units[1] - tr.time_units[0]
    interior = np.min(np.abs(tr.time_units[:, None] - boundaries[None]), axis=1) > 2.5 * dt
    rows = np.flatnonzero(interior)[::RNEA_STRIDE]
    reference = _rnea_ground_force(silo4, tr)[rows]
    ours = forces.force_in_world[rows]
    assert np.abs(ours - reference).max() <= FORCE_TOLERANCE_N
    demand_ref = np.hypot(reference[:, 0], reference[:, 1]) / reference[:, 2]
    assert np.abs(forces.friction_demand[rows] - demand_ref).max() <= FORCE_TOLERANCE_N / 400
    assert forces.friction_demand.max() > 0.05  # the crawl accelerates the body
    # the body alone (m times the base's acceleration) misses the legs' motion by more; at
    # 1 s a unit the legs' share is 4.8 N at most since the paced body phases
    # (planner/gaits/body_pace.py), so it is shown on the plan retimed to 0.5 s a unit
    # (accelerations x 4), where the check must not miss it either
    fast = retime(tr, 0.5)
    fast_reference = _rnea_ground_force(silo4, fast)[rows]
    fast_forces = ContactForceCheck(ContactForceRule(), model, STANDARD_GRAVITY).forces(fast)
    assert np.abs(fast_forces.force_in_world[rows] - fast_reference).max() <= FORCE_TOLERANCE_N
    base_acc = np.gradient(np.gradient(fast.position_base_in_world, fast.t, axis=0), fast.t, axis=0)
    body_only = model.total_mass * base_acc[rows, :2]
    assert np.abs(body_only - fast_reference[:, :2]).max() > 10 * FORCE_TOLERANCE_N
    # the normal loads carry F_z and sum to it in every sample
    np.testing.assert_allclose(forces.normal_n.sum(axis=1), forces.force_in_world[:, 2], rtol=1e-9)


def _run(robot, preset, height_m=0.2, **options):
    """The straight path (at h 0.2 m unless ``height_m``) through the run pipeline, torques
    within the URDF effort itself: at 0.2 m its RF hip pitch needs 51.5 N m standing still,
    over the default preset's 0.85 budget (51.0 N m), which would refuse it before the
    contact forces are looked at."""
    return plan_run(
        robot,
        STRAIGHT,
        height_m,
        RunRequest(torque_headroom=1.0),
        start_heading=np.pi / 2,
        workspace=preset,
        **options,
    )


def test_friction_beyond_mu_plan_is_refused_naming_foot_and_time(silo4):
    """A mu_plan below the crawl's demand refuses the run with the foot, time and step. At
    0.4 m, where the default plans this path with the crawl (at 0.2 m the crawl's lift of RH
    at the last waypoint is out of reach on some machines: docs/results.md)."""
    _run(silo4, PRESETS["default"], height_m=0.4, gait="crawl")  # plans at the default mu
    strict = PRESETS["default"]._replace(contact_forces=ContactForceRule(friction=0.02))
    with pytest.raises(
        PlanningError, match=r"stance foot (LF|RF|LH|RH): friction demand .* at t = .*crawl"
    ):
        _run(silo4, strict, height_m=0.4, gait="crawl")


def test_min_normal_load_refuses_the_default_straight_path(silo4):
    """At 5 % of the weight the crawl's three-foot stances are refused (its 0.02 m margin
    leaves the foot opposite an edge < 5 % of the weight), so the rule is off by default."""
    assert PRESETS["default"].contact_forces.min_normal_fraction is None
    rule = ContactForceRule(min_normal_fraction=MIN_NORMAL_LOAD_FRACTION)
    loaded = PRESETS["default"]._replace(contact_forces=rule)
    with pytest.raises(PlanningError, match=r"stance foot (LF|RF|LH|RH): normal load .* N <"):
        _run(silo4, loaded)
    _run(silo4, PRESETS["default"])  # the default rule keeps the plan


def test_a_plan_whose_feet_would_lift_off_is_refused(silo4, straight):
    """At a tiny unit time the CoM's downward acceleration beats g: F_z <= 0 is refused."""
    from planner.trajectory.limits import retime

    fast = retime(straight.trajectory, 0.02)
    check = ContactForceCheck(ContactForceRule(), planning_model(silo4), STANDARD_GRAVITY)
    forces = check.forces(fast)
    assert np.any(forces.force_in_world[:, 2] <= 0)
    assert check.first_violation(fast) is not None


def test_standing_loads_sum_to_the_weight(silo4, straight):
    """With no acceleration (a still robot: the first samples repeated) F = m g ẑ."""
    tr = straight.trajectory.head(1)
    model = planning_model(silo4)
    still = ContactForceCheck(ContactForceRule(), model, STANDARD_GRAVITY).forces(tr)
    np.testing.assert_allclose(
        still.force_in_world[0], [0.0, 0.0, model.total_mass * STANDARD_GRAVITY], rtol=1e-12
    )
    assert still.friction_demand[0] == 0.0
