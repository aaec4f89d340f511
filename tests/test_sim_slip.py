"""The physics replay's slip measure compares like with like: the sim's foot-sphere centre with
the planned one (silo4sim.metrics, module docstring "Slip").

The references: the planner's contact points (centre - r n) and its closed-form forward
kinematics of the planned joints (planner/trajectory/ball_clearance.py), against MuJoCo's
forward kinematics of the same joints, which the replay's reference uses; and the measure of
before, the sim centre's xy less the planned contact point's, recomputed here. On a plane n is
constant through a stance and the two measures agree; on a height map the contact point moves
by r dn where the ball passes to another triangle, and only the old measure counts it.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from planner.path.plan_path import plan_path
from planner.terrain.terrain_file import load_terrain
from planner.trajectory.torques import add_torques

pytest.importorskip("example_robot_data")
mujoco = pytest.importorskip("mujoco")

from silo4kin.foot_contact import foot_ball  # noqa: E402
from silo4sim.metrics import Thresholds, measure, stance_slip  # noqa: E402
from silo4sim.model import build_sim_model  # noqa: E402
from silo4sim.replay import SimRecord, reference_at_steps  # noqa: E402
from silo4sim.run import SimResult, simulate  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "terrain"
HEIGHT_M = 0.28
#: Coarser than the default 100: the measures are compared on the same replay, whatever it is.
SAMPLES_PER_UNIT = 20
#: MuJoCo's and the planner's forward kinematics of the same joints agree to this [m] (both
#: evaluate the URDF's transforms in double precision; tests/test_sim_model.py TOL_FK_M).
TOL_FK_M = 1e-9
#: The old and the new slip on a plane agree to this [m]: within a stance the planned centre
#: is the contact point + r n, n constant, so the two differ by the FK agreement and by
#: measure's rounding to 1e-6 m.
PLANE_AGREEMENT_M = 3e-6
#: The synthetic slip added to one stance of a replay [m], above the 5 mm limit.
SYNTHETIC_SLIP_M = 0.006
#: A height map's contact normal turns by a few degrees between triangles: r dn of go2's
#: 22.9 mm ball is millimetres; less than this [m] would show no jump.
MIN_JUMP_M = 1e-3


def _plan(robot, goal_y: float, terrain_name: str | None = None, gait: str = "facing"):
    """go2's plan (with full-load torques) from (0, 0) facing +y to (0, goal_y) [m], and the
    terrain document (None: the flat floor). Gait facing: what auto falls back to for go2 at
    0.28 m (docs/terrain.md)."""
    terrain = load_terrain(EXAMPLES / f"{terrain_name}.yaml") if terrain_name else None
    plan = plan_path(
        robot,
        np.array([[0.0, goal_y]]),
        HEIGHT_M,
        samples_per_unit=SAMPLES_PER_UNIT,
        gait=gait,
        terrain=terrain,
    )
    document = terrain.to_document() if terrain is not None else None
    return add_torques(robot, plan.trajectory, load="total"), document


@pytest.fixture(scope="module")
def flat_run(go2):
    trajectory, _ = _plan(go2, 1.0)
    return trajectory, simulate(go2, trajectory)


@pytest.fixture(scope="module")
def ramp_run(go2):
    """Onto examples/terrain/ramp.yaml's 6 deg plank (its foot at y = 1.004 m)."""
    trajectory, document = _plan(go2, 1.8, "ramp")
    return trajectory, simulate(go2, trajectory, terrain=document)


def _contact_point_slip(result) -> np.ndarray:
    """The measure of before, per leg (4,) [m]: the sim centre's xy less the planned contact
    point's, from where it was after touch-down (silo4sim.metrics.stance_slip)."""
    sm, record, th = result.sim_model, result.record, Thresholds()
    n, ref = record.steps_run, record.reference
    margin = int(round(th.transition_s / sm.settings.timestep_s))
    feet = record.get("foot_position", sm).reshape(n, 4, 3)
    out = []
    for leg in range(4):
        offset = feet[:, leg, :2] - ref.position_foot_in_world[:n, leg, :2]
        slip, _ = stance_slip(offset, ref.contact[:n, leg], margin)
        out.append(slip.max() if slip.size else 0.0)
    return np.array(out)


def _per_leg(doc: dict) -> np.ndarray:
    return np.array(list(doc["slip_per_leg_m"].values()))


def _stance_normal_xy(result) -> np.ndarray:
    """(planned centre - planned contact point) xy per step (S, 4, 2) [m]: r n_xy in stance."""
    ref = result.record.reference
    return (ref.position_ball_centre_in_world - ref.position_foot_in_world)[..., :2]


def test_planned_ball_centres_are_the_contact_points_r_along_the_normal(go2, flat_run, ramp_run):
    """At every plan sample, the planned centres of the replay's reference (MuJoCo's FK of
    the planned joints) are the planner's (its closed-form FK of the same joints) and the
    planned contact point + r n: n = z on the floor and in the swing, the plank's normal in
    a stance on the ramp; and the reference interpolates them at the steps."""
    from planner.model import planning_robot
    from planner.trajectory.ball_clearance import ball_centres_in_world
    from silo4sim.replay import planned_foot_sites

    r = foot_ball(go2).rolling_radius_m
    a = np.radians(6.0)
    plank = np.array([0.0, -np.sin(a), np.cos(a)])
    for trajectory, result in (flat_run, ramp_run):
        rows = np.arange(len(trajectory))
        centres = planned_foot_sites(result.sim_model, trajectory, rows)
        planner_centres = ball_centres_in_world(planning_robot(go2).legs, trajectory)
        np.testing.assert_allclose(centres, planner_centres, rtol=0, atol=TOL_FK_M)
        offset = centres - trajectory.position_foot_in_world
        on_plank = trajectory.contact & (offset[..., 1] < -0.5 * r * np.sin(a))
        expected = np.where(on_plank[..., None], r * plank, [0.0, 0.0, r])
        np.testing.assert_allclose(offset, expected, rtol=0, atol=TOL_FK_M)
        ref = result.record.reference
        t_plan = trajectory.t - trajectory.t[0]
        steps = np.flatnonzero(np.isin(np.round(ref.t, 9), np.round(t_plan, 9)))
        at = np.searchsorted(t_plan, ref.t[steps] - 1e-9)
        np.testing.assert_allclose(
            ref.position_ball_centre_in_world[steps], centres[at], rtol=0, atol=TOL_FK_M
        )
    assert on_plank.sum() > 100  # the ramp's stances stood on the plank


@pytest.mark.parametrize("run", ["flat_run", "ramp_run"])
def test_on_a_plane_the_slip_is_the_contact_point_slip(run, request):
    """On the floor and on a ramp the planned centre stands r n from the planned contact
    point with n constant through each stance, so the measure's slip of every leg equals the
    contact point's of before, to PLANE_AGREEMENT_M; and the feet do slip measurably (the
    comparison is not of zeros)."""
    _, result = request.getfixturevalue(run)
    new, old = _per_leg(result.metrics), _contact_point_slip(result)
    np.testing.assert_allclose(new, old, rtol=0, atol=PLANE_AGREEMENT_M)
    assert new.max() > 1e-4


def _with_foot_shifted(result, leg: int, shift_xy) -> tuple[SimRecord, int, int]:
    """The replay's record with foot ``leg``'s sensed centre moved by ``shift_xy`` [m] from
    the middle of its longest judged stance to that stance's end (a slip in one stance)."""
    sm, record, th = result.sim_model, result.record, Thresholds()
    ref = record.reference
    contact = ref.contact[: record.steps_run, leg]
    padded = np.diff(np.concatenate([[0], contact.astype(int), [0]]))
    starts, ends = np.flatnonzero(padded == 1), np.flatnonzero(padded == -1)
    k = int(np.argmax(ends - starts))
    start, end = int(starts[k]), int(ends[k])
    margin = int(round(th.transition_s / sm.settings.timestep_s))
    assert end - start > 4 * margin
    sensors = record.sensors.copy()
    columns = sm.sensor["foot_position"].start + 3 * leg + np.arange(2)
    middle = (start + end) // 2
    sensors[middle:end, columns[0]] += shift_xy[0]
    sensors[middle:end, columns[1]] += shift_xy[1]
    return replace(record, sensors=sensors), start, end


def test_a_foot_that_slides_6_mm_in_a_stance_is_reported(flat_run):
    """The replay on the floor, with one stance of LH moved 6 mm (3.6, -4.8) mm halfway
    through: the measure reports LH's slip as 6 mm to within that leg's own slip in the
    replay, and the plan no longer walks for a foot slip."""
    _, result = flat_run
    leg, shift = 2, SYNTHETIC_SLIP_M * np.array([0.6, -0.8])
    record, _, _ = _with_foot_shifted(result, leg, shift)
    doc = measure(result.sim_model, record)
    before = _per_leg(result.metrics)[leg]
    assert abs(_per_leg(doc)[leg] - SYNTHETIC_SLIP_M) <= before + 1e-6
    assert not doc["walks"] and any(r.startswith("foot slip") for r in doc["reasons"])


@pytest.fixture(scope="module")
def rough_followed(go2):
    """go2 across the first metre of examples/terrain/rough.yaml (gait plain, what auto
    falls back to there) and a replay that follows the plan exactly: every sensor reads the
    reference (the sphere centres the planned ones, full contact force in stance)."""
    trajectory, document = _plan(go2, 1.5, "rough", gait="plain")
    sm = build_sim_model(go2, terrain=document)
    ref = reference_at_steps(sm, trajectory, sm.settings.settle_s)
    n = ref.t.shape[0]
    sensors = np.zeros((n, sm.model.nsensordata))
    yaw = ref.yaw_base_in_world
    sensors[:, sm.sensor["body_position"]] = ref.position_base_in_world
    sensors[:, sm.sensor["body_quat"]] = np.column_stack(
        [np.cos(yaw / 2), np.zeros(n), np.zeros(n), np.sin(yaw / 2)]
    )
    sensors[:, sm.sensor["q"]] = ref.q
    sensors[:, sm.sensor["tau"]] = ref.tau
    sensors[:, sm.sensor["foot_position"]] = ref.position_ball_centre_in_world.reshape(n, 12)
    sensors[:, sm.sensor["foot_force"]] = np.where(ref.contact, 50.0, 0.0)
    record = SimRecord(reference=ref, sensors=sensors, steps_run=n)
    return SimResult(metrics=measure(sm, record), record=record, sim_model=sm)


def test_on_a_height_map_the_contact_point_jumps_and_the_centre_does_not(rough_followed):
    """A robot that follows the plan exactly on rough.yaml: its planned r n changes by
    millimetres within a stance where the ball passes from one triangle to the next, and the
    measure of before reports exactly that change as slip (the largest per leg, in the judged
    part of each stance); the measure reports no slip, and the robot walks."""
    result = rough_followed
    doc = result.metrics
    assert doc["walks"] and doc["slip_max_m"] == 0.0, doc["reasons"]
    old = _contact_point_slip(result)
    assert old.max() > MIN_JUMP_M
    sm, ref, th = result.sim_model, result.record.reference, Thresholds()
    margin = int(round(th.transition_s / sm.settings.timestep_s))
    r_n = _stance_normal_xy(result)
    jumps = [stance_slip(r_n[:, leg], ref.contact[:, leg], margin)[0].max() for leg in range(4)]
    np.testing.assert_allclose(old, jumps, rtol=0, atol=1e-12)


def test_a_foot_that_slides_6_mm_on_the_height_map_is_reported(rough_followed):
    """The exactly followed plan on rough.yaml with one stance of RF moved 6 mm: the measure
    reports 6 mm (nothing else moves) and a foot slip."""
    record, _, _ = _with_foot_shifted(rough_followed, 1, (0.0, SYNTHETIC_SLIP_M))
    doc = measure(rough_followed.sim_model, record)
    assert doc["slip_per_leg_m"]["RF"] == pytest.approx(SYNTHETIC_SLIP_M, abs=1e-6)
    assert not doc["walks"] and doc["reasons"][0].startswith("foot slip")


def test_point_feet_are_measured_at_the_planned_foot_point(silo4):
    """SILO4's feet are points: the planned centre is the planned foot point itself."""
    plan = plan_path(silo4, np.array([[0.0, 0.3]]), 0.4, samples_per_unit=SAMPLES_PER_UNIT)
    sm = build_sim_model(silo4)
    ref = reference_at_steps(sm, plan.trajectory, 0.1)
    np.testing.assert_allclose(
        ref.position_ball_centre_in_world, ref.position_foot_in_world, rtol=0, atol=TOL_FK_M
    )
