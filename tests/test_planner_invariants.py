"""Property tests: invariants of every plan on every sample (issue 3, docs/design.md "Planner").

hypothesis draws waypoint lists, heights, presets and start headings (seeded, derandomized).
Most plans are sampled at 10 samples per unit to keep CI fast; one test samples at 100.
"""

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from planner import PlanningError, plan_path
from planner.stability.margin import MARGIN_TOLERANCE
from planner.trajectory.sampling import sample_steps
from planner.workspace.layout import feasible_height_range
from silo4kin.foot_contact import foot_contact_offset_m
from silo4kin.legs import forward_kinematics

#: Stance feet are recomputed by FK(IK(...)) and two frame changes: 1e-9 m covers rounding.
STANCE_FIXED_M = 1e-9
#: A swing leg "at rest" at lift-off / touch-down [rad/s]: the profiles' rates vanish there
#: exactly (sin 0, sin π ~ 1e-16), so only rounding through J^-1 remains.
AT_REST_RAD_S = 1e-9
#: Joint-limit slack, as the planner's (workspace.JOINT_LIMIT_TOLERANCE).
LIMIT_RAD = 1e-9
#: Finite differences of q sampled at 1000 per unit (dt = 1e-3): central differences err by
#: dt²/6 |q'''| ~ 2e-7 |q'''|; with |q'''| up to ~1e3 rad/unit³ on a swing at h = 0.6 a
#: relative 1e-3 of the signal's peak plus 1e-3 absolute is a safe, still failing bound
#: (a wrong sign or a missing term shows as O(1) differences).
FD_SAMPLES_PER_UNIT = 1000
FD_REL = 1e-3
FD_ABS = 1e-3

SETTINGS = dict(deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])


def waypoints(max_points=3, radius=1.2):
    point = st.tuples(st.floats(-radius, radius), st.floats(-radius, radius))
    return st.lists(point, min_size=1, max_size=max_points)


def heights(robot, preset):
    lo, hi = feasible_height_range(robot, preset)
    return st.floats(lo, hi)


def check_invariants(robot, plan):
    """All per-sample invariants; returns nothing, fails with a message."""
    tr = plan.trajectory
    assert np.all(np.isfinite(tr.q)) and np.all(np.isfinite(tr.qd))
    assert np.all(np.isfinite(tr.qdd))
    lower = np.concatenate([leg.q_lower for leg in robot.legs]) - LIMIT_RAD
    upper = np.concatenate([leg.q_upper for leg in robot.legs]) + LIMIT_RAD
    assert np.all(tr.q >= lower) and np.all(tr.q <= upper), "joint limits"
    lifted = ~np.all(tr.contact, axis=1)
    assert np.all(tr.contact.sum(axis=1) >= 3), "at most one leg in the air"
    if lifted.any():
        assert tr.margin[lifted].min() >= plan.stability_threshold - MARGIN_TOLERANCE
        assert tr.margin[lifted].min() >= -MARGIN_TOLERANCE
    feet = tr.position_foot_in_world
    offset = foot_contact_offset_m(robot)  # foot frame above a ball's contact point (0: point)
    assert feet[..., 2].min() >= -1e-12, "a foot below the ground"  # feet: contact points
    # feet from the joints (FK in B, then to W) equal the planned feet
    c, s = np.cos(tr.yaw_base_in_world), np.sin(tr.yaw_base_in_world)
    for j, leg in enumerate(robot.legs):
        p = forward_kinematics(leg, tr.q[:, 3 * j : 3 * j + 3])
        world = tr.position_base_in_world + np.stack(
            [c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1], p[:, 2] - offset], axis=1
        )
        np.testing.assert_allclose(world, feet[:, j], atol=STANCE_FIXED_M)
        if offset > 0:
            continue  # a ball rolls in stance: tests/test_round_feet.py checks it does not slip
        # stance feet do not move between consecutive stance samples
        both = tr.contact[1:, j] & tr.contact[:-1, j]
        step = np.abs(np.diff(feet[:, j], axis=0)).max(axis=1)
        assert np.all(step[both] <= STANCE_FIXED_M), f"stance foot {leg.name} slides"
    # swing feet start and end at rest on the ground: footholds at z = 0 (a ball foot's
    # centre at its contact offset, silo4kin/foot_contact.py), and the swinging
    # leg's joint rates are zero at lift-off and touch-down (base still during a transfer,
    # eq 5.5-5.7 vanish at both ends; the next step starts at rest too)
    spu = round((len(tr) - 1) / tr.time_units[-1]) if tr.time_units[-1] > 0 else 1
    legs = [leg.name for leg in robot.legs]
    for st_ in plan.steps:
        if st_.kind == "transfer":
            assert abs(st_.foothold_start_in_world[2] - offset) < 1e-12
            assert abs(st_.foothold_end_in_world[2] - offset) < 1e-12
            j = legs.index(st_.leg)
            for t_edge in (st_.t_start, st_.t_end):
                i = int(round(t_edge * spu))
                assert np.abs(tr.qd[i, 3 * j : 3 * j + 3]).max() < AT_REST_RAD_S, (
                    f"{st_.leg} not at rest at t = {t_edge} units"
                )


def check_finite_differences(robot, plan):
    """q̇ and q̈ of the planner equal central differences of q (sampled finely)."""
    tr = sample_steps(
        robot,
        plan.steps,
        plan.workspace.swing_height_m,
        FD_SAMPLES_PER_UNIT,
        smooth=plan.gait in ("creep", "crawl"),
    )
    dt = 1.0 / FD_SAMPLES_PER_UNIT
    boundaries = np.array([s.t_start for s in plan.steps] + [plan.steps[-1].t_end])
    t = tr.time_units
    interior = np.min(np.abs(t[:, None] - boundaries[None]), axis=1) > 1.5 * dt
    inner = interior[1:-1]
    fd_qd = (tr.q[2:] - tr.q[:-2]) / (2 * dt)
    fd_qdd = (tr.qd[2:] - tr.qd[:-2]) / (2 * dt)
    err_qd = np.abs(fd_qd - tr.qd[1:-1])[inner]
    err_qdd = np.abs(fd_qdd - tr.qdd[1:-1])[inner]
    assert err_qd.max() <= FD_REL * np.abs(tr.qd).max() + FD_ABS
    assert err_qdd.max() <= FD_REL * np.abs(tr.qdd).max() + FD_ABS


@settings(max_examples=250, **SETTINGS)
@given(data=st.data())
def test_default_plans_satisfy_every_invariant(silo4, data):
    """Random waypoints, heights and headings (default preset): stance feet fixed in W,
    S_m >= threshold > 0 on every lift, joints within limits, no NaN, feet above ground."""
    h = data.draw(heights(silo4, "default"))
    heading = data.draw(st.floats(-np.pi, np.pi))
    wp = data.draw(waypoints())
    plan = plan_path(silo4, wp, h, start_heading=heading, samples_per_unit=10)
    assert plan.stability_threshold > 0
    check_invariants(silo4, plan)


@settings(max_examples=200, **SETTINGS)
@given(data=st.data())
def test_thesis_plans_satisfy_every_invariant(silo4, data):
    """Thesis preset: same invariants, with the thesis's threshold 0 (never below 0)."""
    h = data.draw(heights(silo4, "thesis"))
    wp = data.draw(waypoints())
    tol = data.draw(st.sampled_from([None, 0.15]))
    plan = plan_path(silo4, wp, h, workspace="thesis", tolerance=tol, samples_per_unit=10)
    check_invariants(silo4, plan)


@settings(max_examples=40, **SETTINGS)
@given(data=st.data())
def test_full_rate_plans_and_finite_differences(silo4, data):
    """At 100 samples per unit the invariants hold, and q̇, q̈ agree with finite
    differences of q (resampled at 1000 per unit, away from phase boundaries)."""
    preset = data.draw(st.sampled_from(["default", "thesis"]))
    h = data.draw(heights(silo4, preset))
    wp = data.draw(waypoints(max_points=2, radius=0.8))
    plan = plan_path(silo4, wp, h, workspace=preset)
    check_invariants(silo4, plan)
    if plan.steps:
        check_finite_differences(silo4, plan)


@settings(max_examples=20, **SETTINGS)
@given(data=st.data())
def test_impossible_margin_is_refused_with_the_waypoint(silo4, data):
    """A threshold no support triangle can give raises PlanningError naming the waypoint;
    no plan (and so no unstable sample) comes out."""
    wp = data.draw(waypoints())
    h = data.draw(heights(silo4, "default"))
    try:
        plan = plan_path(silo4, wp, h, stability_threshold=0.4, samples_per_unit=5)
    except PlanningError as err:
        assert err.waypoint_index is not None
        assert f"waypoint {err.waypoint_index}" in str(err)
    else:
        assert plan.steps == ()  # nothing to do: every waypoint already reached
