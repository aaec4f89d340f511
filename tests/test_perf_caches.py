"""The caches and memos change no result: the one-pass IK of all legs equals one call per leg
bit for bit, the memos return what the uncached functions compute, the ditch route search
decides every route as planning it to the end does, and stride_at is workspace_for's stride."""

from __future__ import annotations

import numpy as np
import pytest

from planner.errors import PlannerInputError
from planner.stability import swing_com
from planner.workspace.layout import (
    SPIN_THETA1_RESERVE,
    planning_robot,
    reachable_in_limits,
    reachable_in_limits_of_legs,
    stride_at,
    workspace_for,
)
from silo4kin.kinematics import forward_kinematics


def _targets_near_limits(legs, rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(leg index (n,), targets (n, 3) [m]): half at the FK of joint values on or just past a
    limit (where a rounding difference would flip the answer), half random around the hip."""
    idx = rng.integers(0, len(legs), n)
    pts = np.empty((n, 3))
    for k, leg in enumerate(legs):
        rows = np.flatnonzero(idx == k)
        q = rng.uniform(leg.q_lower, leg.q_upper, (rows.size, 3))
        edge = rng.integers(0, 3, rows.size)
        at = rng.choice([0, 1], rows.size)
        bound = np.where(at[:, None] == 0, leg.q_lower, leg.q_upper)
        q[np.arange(rows.size), edge] = bound[np.arange(rows.size), edge] + rng.choice(
            [-1e-9, 0.0, 1e-9, 1e-6], rows.size
        )
        near = forward_kinematics(leg, q)
        far = leg.position_hip_in_base + rng.uniform(-0.8, 0.8, (rows.size, 3))
        pts[rows] = np.where(rng.random(rows.size)[:, None] < 0.5, near, far)
    return idx, pts


@pytest.mark.parametrize("robot_file", [None, "tests/robots/mantis.urdf"])
def test_one_pass_ik_equals_one_call_per_leg(robot_file) -> None:
    """reachable_in_limits_of_legs == reachable_in_limits leg by leg, for targets on the
    joint limits, with and without the θ1 reserve and the memo (a test that could fail: the
    answers are mixed, not all True)."""
    from silo4kin import load_robot

    robot = planning_robot(load_robot() if robot_file is None else load_robot(robot_file))
    rng = np.random.default_rng(14)
    answers = []
    for trial in range(40):
        idx, pts = _targets_near_limits(robot.legs, rng, int(rng.integers(1, 400)))
        reserve = float(rng.choice([0.0, SPIN_THETA1_RESERVE]))
        expected = np.zeros(len(pts), dtype=bool)
        for k, leg in enumerate(robot.legs):
            expected[idx == k] = reachable_in_limits(leg, pts[idx == k], reserve)
        got = reachable_in_limits_of_legs(robot.legs, idx, pts, reserve)
        assert np.array_equal(got, expected), trial
        answers.append(expected)
    both = np.concatenate(answers)
    assert 0.1 < both.mean() < 0.9


@pytest.mark.parametrize("robot_name", [None, "tests/robots/mantis.urdf", "go2"])
def test_one_pass_joint_values_equal_one_ik_call_per_leg(robot_name) -> None:
    """joint_values_of_legs == silo4kin.legs.inverse_kinematics leg by leg, bit for bit (NaN
    where out of reach), on insect legs and a mammal's."""
    from planner.workspace.layout import joint_values_of_legs
    from silo4kin import load_robot
    from silo4kin.legs import inverse_kinematics

    if robot_name == "go2":
        pytest.importorskip("example_robot_data")
    robot = planning_robot(load_robot() if robot_name is None else load_robot(robot_name))
    rng = np.random.default_rng(15)
    for trial in range(10):
        if robot_name == "go2":  # _targets_near_limits' FK is the insect closed form
            idx = rng.integers(0, 4, 200)
            hips = np.array([leg.position_hip_in_base for leg in robot.legs])
            pts = hips[idx] + rng.uniform(-0.45, 0.45, (200, 3))
        else:
            idx, pts = _targets_near_limits(robot.legs, rng, int(rng.integers(1, 300)))
        q, ok = joint_values_of_legs(robot.legs, idx, pts)
        for k, leg in enumerate(robot.legs):
            res = inverse_kinematics(leg, pts[idx == k])
            assert np.array_equal(q[idx == k], res.q, equal_nan=True), trial
            assert np.array_equal(ok[idx == k], res.reachable), trial
        assert 0 < ok.mean() < 1


@pytest.mark.parametrize("robot_name", [None, "tests/robots/mantis.urdf", "go2"])
def test_joint_values_in_limits_equal_the_two_calls(robot_name) -> None:
    """joint_values_in_limits_of_legs == (joint_values_of_legs, reachable_in_limits_of_legs)
    of the same targets, bit for bit, on insect legs and a mammal's."""
    from planner.workspace.layout import joint_values_of_legs
    from planner.workspace.reach_check import joint_values_in_limits_of_legs
    from silo4kin import load_robot

    if robot_name == "go2":
        pytest.importorskip("example_robot_data")
    robot = planning_robot(load_robot() if robot_name is None else load_robot(robot_name))
    rng = np.random.default_rng(16)
    for trial in range(10):
        if robot_name == "go2":
            idx = rng.integers(0, 4, 200)
            hips = np.array([leg.position_hip_in_base for leg in robot.legs])
            pts = hips[idx] + rng.uniform(-0.45, 0.45, (200, 3))
        else:
            idx, pts = _targets_near_limits(robot.legs, rng, int(rng.integers(1, 300)))
        q, in_limits = joint_values_in_limits_of_legs(robot.legs, idx, pts)
        q_ref, _ = joint_values_of_legs(robot.legs, idx, pts)
        assert np.array_equal(q, q_ref, equal_nan=True), trial
        assert np.array_equal(in_limits, reachable_in_limits_of_legs(robot.legs, idx, pts))
        assert 0 < in_limits.mean() < 1


@pytest.mark.parametrize("robot_name", [None, "tests/robots/mantis.urdf", "go2"])
def test_tibia_clearance_of_rows_equals_leg_by_leg(robot_name) -> None:
    """tibia_clearance_of_rows (all rows in one pass) == the capsule's closed form leg by leg
    (LegGeometry.joint_to_dh, knee and capsule end heights), bit for bit; NaN for a leg of
    another family or a NaN joint value."""
    from planner.trajectory.clearance import TIBIA_FOOT_GAP_M, tibia_clearance_of_rows
    from silo4kin import load_robot
    from silo4kin.leg_family import INSECT, family_of

    if robot_name == "go2":
        pytest.importorskip("example_robot_data")
    legs = planning_robot(load_robot() if robot_name is None else load_robot(robot_name)).legs
    rng = np.random.default_rng(17)
    for n in (1, 3, 8, 9, 100, 1001):
        idx = rng.integers(0, len(legs), n)
        q = rng.uniform(-3.0, 3.0, (n, 3))
        q[rng.random(n) < 0.1] = np.nan
        height = rng.uniform(0.1, 0.6, n) if n % 2 else 0.4
        want = np.full(n, np.nan)
        for k, leg in enumerate(legs):
            rows = np.flatnonzero(idx == k)
            if not rows.size or family_of(leg) is not INSECT:
                continue
            theta = leg.joint_to_dh(q[rows])
            knee_z = leg.position_hip_in_base[2] + leg.L2 * np.sin(theta[:, 1])
            end_z = knee_z + (leg.L3 - TIBIA_FOOT_GAP_M) * np.sin(theta[:, 1] + theta[:, 2])
            want[rows] = np.minimum(knee_z, end_z) - leg.tibia_radius_m
        got = tibia_clearance_of_rows(legs, idx, q, height)
        assert np.array_equal(got, want + height, equal_nan=True), n


def test_omni_reach_check_equals_one_call_per_leg(silo4) -> None:
    """omni._reachable (one IK pass, memoised) == the check leg by leg with
    reachable_in_limits and tibias_clear, on random half cycles, before and after its memo
    holds them."""
    from planner.gaits.omni import RESERVE_DIRECTIONS, SHIFT_RESERVE_M, _reachable
    from planner.gaits.tibia_reach import tibias_clear

    robot = planning_robot(silo4)
    ws = workspace_for(silo4, 0.3)
    shifts = np.vstack([np.zeros(3), SHIFT_RESERVE_M * RESERVE_DIRECTIONS])
    rng = np.random.default_rng(7)
    answers = []
    for _ in range(60):
        pair = tuple(sorted(rng.choice(4, 2, replace=False).tolist()))
        off = rng.uniform(-0.3, 0.3, (4, 2))
        angle = rng.uniform(-np.pi, np.pi)
        u = np.array([np.cos(angle), np.sin(angle)])
        t = float(rng.uniform(0.0, 0.3))
        expected = True
        for k, leg in enumerate(robot.legs):
            mid = ws.position_mid_in_base[k]
            if k in pair:
                p = mid + np.array([t * u[0], t * u[1], 0.0])
                pts = [p, p + np.array([0.0, 0.0, ws.swing_height_m])]
            else:
                pts = [
                    mid + np.array([off[k, 0] - s * u[0], off[k, 1] - s * u[1], 0.0])
                    for s in (0.0, 0.5 * t, t)
                ]
            expected &= bool(
                reachable_in_limits(leg, (np.array(pts)[:, None, :] + shifts).reshape(-1, 3)).all()
            )
            # the tibia rule at the step's own footholds and body positions (unshifted)
            ground = np.array(pts[:1] if k in pair else pts)
            expected &= bool(tibias_clear(robot.legs, ws, np.full(len(ground), k), ground).all())
        for _ in range(2):
            assert _reachable(robot.legs, ws, pair, off, u, t) == expected
        answers.append(expected)
    assert any(answers) and not all(answers)


def test_swing_com_memo_equals_uncached(silo4) -> None:
    """PlanningModel.swing_com_in_world (memoised) == its uncached computation, also after a
    hit, and the shared result is read-only."""
    from planner.model import as_planning_model

    model = as_planning_model(silo4)
    ws = workspace_for(silo4, 0.3)
    base = np.array([0.01, -0.02, 0.3])
    feet = np.column_stack([ws.position_mid_in_base[:, :2] + base[:2], np.zeros(4)])
    for leg in range(4):
        end = feet[leg] + np.array([0.1, 0.05, 0.0])
        direct = swing_com.swing_com_in_world(model, base, 0.2, feet, leg, end, 0.1, 7)
        for _ in range(2):
            got = model.swing_com_in_world(base, 0.2, feet, leg, end, 0.1, n=7)
            assert np.array_equal(got, direct)
        with pytest.raises(ValueError):
            got[0, 0] = 0.0
    other = model.swing_com_in_world(base, 0.2, feet, 0, feet[0] + 0.1, 0.1, n=7)
    assert not np.array_equal(
        other, model.swing_com_in_world(base, 0.2, feet, 1, feet[1] + 0.1, 0.1, n=7)
    )


def test_moving_swing_com_memo_equals_uncached(silo4) -> None:
    """PlanningModel.moving_swing_com_in_world (memoised: the crawl's swings) == its uncached
    computation, also after a hit; results read-only; another base end, another answer."""
    from planner.model import as_planning_model

    model = as_planning_model(silo4)
    ws = workspace_for(silo4, 0.3)
    b0, b1 = np.array([0.01, -0.02, 0.3]), np.array([0.06, 0.01, 0.3])
    feet = np.column_stack([ws.position_mid_in_base[:, :2] + b0[:2], np.zeros(4)])
    for leg in range(4):
        end = feet[leg] + np.array([0.1, 0.05, 0.0])
        com0, base0 = swing_com.moving_swing_com_in_world(
            model, b0, b1, 0.2, feet, leg, end, 0.1, 7
        )
        for _ in range(2):
            com, base = model.moving_swing_com_in_world(b0, b1, 0.2, feet, leg, end, 0.1, n=7)
            assert np.array_equal(com, com0, equal_nan=True) and np.array_equal(base, base0)
        with pytest.raises(ValueError):
            com[0, 0] = 0.0
        with pytest.raises(ValueError):
            base[0, 0] = 0.0
    other, _ = model.moving_swing_com_in_world(b0, b1 + 0.01, 0.2, feet, 0, feet[0] + 0.1, 0.1, n=7)
    assert not np.array_equal(
        other, model.moving_swing_com_in_world(b0, b1, 0.2, feet, 0, feet[0] + 0.1, 0.1, n=7)[0]
    )


def test_stride_at_is_the_workspace_stride(silo4) -> None:
    """stride_at == workspace_for(...).stride_m across the range (both presets), and it
    refuses the heights workspace_for refuses."""
    for preset in ("thesis", "default"):
        for h in np.linspace(0.2, 0.6, 9):
            assert (
                stride_at(silo4, float(h), preset)
                == workspace_for(silo4, float(h), preset).stride_m
            )
    for bad in (0.01, float("nan")):
        with pytest.raises(PlannerInputError):
            stride_at(silo4, bad, "thesis")
    with pytest.raises(PlannerInputError):
        stride_at(silo4, 0.3, "square")


@pytest.mark.parametrize("preset,width,every", [("default", 0.25, 9), ("thesis", 0.15, 3)])
def test_ditch_guard_decides_routes_as_planning_them_to_the_end(
    silo4, preset, width, every
) -> None:
    """The ditch's terrain abandons a candidate gait at its first foothold in the ditch:
    every route whose full plan clears the ditch is accepted on that terrain too
    (before the crawl: the whole search, 884 routes, 0 differ; here a sample), the guard
    may accept more (a slower gait that clears, where the faster one steps in), and a route
    the terrain lets through has no foothold in the ditch."""
    from planner.path.plan_path import plan_path
    from planner.studies.ditch import (
        DITCH_NEAR_EDGE_M,
        FOOT_CLEARANCE_M,
        START_HEADING_RAD,
        Ditch,
        _candidate_routes,
        _route_clears,
        _stride,
        footholds_in_world,
    )
    from silo4kin.errors import Silo4Error

    ditch = Ditch(DITCH_NEAR_EDGE_M, width)
    terrain = ditch.terrain(FOOT_CLEARANCE_M)
    options = dict(start_heading=START_HEADING_RAD, workspace=preset, samples_per_unit=1)
    decisions = []
    for _, route in _candidate_routes(ditch, _stride(silo4, 0.3, preset))[::every]:
        try:
            plan = plan_path(silo4, route, 0.3, **options)
            full = _route_clears(plan.trajectory, ditch, FOOT_CLEARANCE_M)
        except Silo4Error:
            full = False
        try:
            guarded = plan_path(silo4, route, 0.3, terrain=terrain, **options)
        except Silo4Error:  # FootholdRefused, PlanningError
            fast = False
        else:
            assert (
                np.min(ditch.clearance(footholds_in_world(guarded.trajectory))) >= FOOT_CLEARANCE_M
            )
            fast = _route_clears(guarded.trajectory, ditch, FOOT_CLEARANCE_M)
        assert fast or not full, route.tolist()
        decisions.append(full)
    if preset == "thesis":
        assert any(decisions) and not all(decisions)  # the sample holds both outcomes


def test_foothold_check_must_be_callable(silo4) -> None:
    """plan_path refuses a foothold_check that is not a function, as a PlannerInputError."""
    from planner.path.plan_path import plan_path

    with pytest.raises(PlannerInputError, match="foothold_check"):
        plan_path(silo4, [[0.0, 0.5]], 0.3, foothold_check=0.5, samples_per_unit=1)


@pytest.mark.parametrize("gait", ["creep", "crawl"])
def test_foothold_check_sees_every_placed_foothold(silo4, gait) -> None:
    """The check is called once per transfer of the gait, with the foothold the step records
    (gait "auto" builds both gaits, so it sees the crawl's and the creep's)."""
    from planner.path.plan_path import plan_path

    seen: list[np.ndarray] = []
    plan = plan_path(
        silo4,
        [[0.0, 1.0]],
        0.3,
        samples_per_unit=1,
        gait=gait,
        foothold_check=lambda foot: seen.append(np.array(foot)),
    )
    assert plan.gait == ("crawl" if gait == "crawl" else "creep")
    placed = [s.foothold_end_in_world for s in plan.steps if s.foothold_end_in_world is not None]
    assert len(placed) > 4 and len(seen) == len(placed)
    assert all(np.array_equal(a, b) for a, b in zip(seen, placed))


def _same_plan(a, b) -> None:
    """Two plans with the same steps and samples, bit for bit."""
    assert a.gait == b.gait and len(a.steps) == len(b.steps)
    for s, t in zip(a.steps, b.steps):
        assert (s.label, s.leg, s.t_start, s.t_end) == (t.label, t.leg, t.t_start, t.t_end)
        assert np.array_equal(s.position_base_end_in_world, t.position_base_end_in_world)
    for name in ("q", "position_base_in_world", "position_foot_in_world", "margin"):
        assert np.array_equal(getattr(a.trajectory, name), getattr(b.trajectory, name)), name


@pytest.mark.parametrize(
    "gait,preset", [("crawl", "default"), ("creep", "default"), ("auto", "thesis")]
)
def test_first_walk_memo_replays_the_walk(silo4, gait, preset) -> None:
    """Two routes with one approach: the second replays the first segment from the memo and
    is the plan planned with an empty memo; a check that refuses a foothold of the approach
    on the replay gets what it gets without the memo (the segment walked for real)."""
    from planner.errors import FootholdRefused
    from planner.gaits.first_walk import FirstWalkMemo
    from planner.path.plan_path import plan_path

    memo = FirstWalkMemo()
    options = dict(start_heading=np.pi / 2, samples_per_unit=5, gait=gait, workspace=preset)
    approach = [0.2, 0.9]
    plan_path(silo4, [approach, [0.6, 2.4]], 0.3, first_walk_memo=memo, **options)
    assert memo.hits == 0 and memo.entries
    replayed = plan_path(silo4, [approach, [-0.3, 2.5]], 0.3, first_walk_memo=memo, **options)
    assert memo.hits == 1
    fresh = plan_path(silo4, [approach, [-0.3, 2.5]], 0.3, **options)
    _same_plan(replayed, fresh)

    # a check refusing a foothold of the memoised approach: the walk is not replayed
    placed = [
        s.foothold_end_in_world
        for s in fresh.steps
        if s.foothold_end_in_world is not None and s.t_end <= fresh.time_reached_units[0] + 1e-9
    ]
    banned = placed[len(placed) // 2]

    def refuse(foot) -> None:
        if np.allclose(foot, banned, atol=1e-12):
            raise ValueError("refused")

    outcomes = []
    for shared in (memo, None):
        try:
            outcomes.append(
                plan_path(
                    silo4,
                    [approach, [-0.3, 2.5]],
                    0.3,
                    foothold_check=refuse,
                    first_walk_memo=shared,
                    **options,
                )
            )
        except FootholdRefused as exc:
            outcomes.append(str(exc))
    assert memo.hits == 1
    if isinstance(outcomes[0], str):
        assert outcomes[0] == outcomes[1]
    else:
        _same_plan(*outcomes)
        assert not any(
            np.allclose(f, banned, atol=1e-12)
            for f in (s.foothold_end_in_world for s in outcomes[0].steps)
            if f is not None
        )


def _reach_ok_one_leg_at_a_time(legs, ws, leg, off, u, t, r) -> bool:
    """The crawl's reach check of one advance t [m] one leg and advance at a time: the points of
    each leg, then one reachable_in_limits call per leg."""
    from planner.workspace.layout import RESERVE_DIRECTIONS, SHIFT_RESERVE_M

    shifts = np.vstack([np.zeros(3), SHIFT_RESERVE_M * RESERVE_DIRECTIONS])
    for k, geo in enumerate(legs):
        mid = ws.position_mid_in_base[k]
        if k == leg:
            p = mid + np.array([r * u[0], r * u[1], 0.0])
            start = mid + np.array([off[k, 0], off[k, 1], 0.0])
            lift = np.array([0.0, 0.0, ws.swing_height_m])
            pts = [p, p + lift, 0.5 * (start + p) + lift]
        else:
            pts = [
                mid + np.array([off[k, 0] - s * u[0], off[k, 1] - s * u[1], 0.0])
                for s in (0.0, 0.5 * t, t)
            ]
        if not reachable_in_limits(geo, (np.array(pts)[:, None, :] + shifts).reshape(-1, 3)).all():
            return False
    return True


def test_crawl_reach_check_of_many_advances_equals_one_each(silo4) -> None:
    """The crawl's reach check of T advances in one IK pass gives, for each, what checking
    that advance alone, leg by leg, gives (so the bisection accepts the same candidate)."""
    from planner.gaits.crawl_reach import feet_reachable
    from planner.path.plan_path import robot_in_body_com_frame

    robot = robot_in_body_com_frame(silo4)
    rng = np.random.default_rng(7)
    mixed = 0
    for h in (0.2, 0.4, 0.6):
        ws = workspace_for(robot, h, "default")
        for _ in range(150):
            leg = int(rng.integers(-1, 4))
            leg = None if leg < 0 else leg
            off = rng.uniform(-0.3, 0.3, (4, 2))
            a = rng.uniform(0, 2 * np.pi)
            u = np.array([np.cos(a), np.sin(a)])
            advances = [0.8 * 0.5**k for k in range(12)] + [0.0]
            r = float(rng.uniform(0.0, 0.2))
            many = feet_reachable(robot.legs, ws, leg, off, u, advances, r)
            one = [_reach_ok_one_leg_at_a_time(robot.legs, ws, leg, off, u, t, r) for t in advances]
            assert many.tolist() == one
            mixed += len(set(one)) == 2
    assert mixed >= 5  # the sample holds advances on both sides of the reach


def test_a_gait_slower_than_the_one_in_hand_is_not_built_to_its_end(silo4) -> None:
    """gait "auto" builds the creeping gait only until its steps reach the crawl's time: the
    builder raises at the first step ending at or after its time limit, and the gait turns
    it into NotFaster, the answer building every step gives."""
    from planner.gaits.base import NotFaster, PlanRequest
    from planner.gaits.builder import StepBuilder, TimeLimitReached
    from planner.gaits.without_turning import OmniCreep
    from planner.model import as_planning_model
    from planner.path.plan_path import plan_path
    from planner.presets import preset_for
    from planner.terrain.base import FlatGround

    b = StepBuilder(np.zeros(3), 0.0, np.zeros((4, 3)), 0.0)
    b.time_limit = 2.0
    b.body(np.zeros(3), 0.0, 1.0, "body", "one")
    with pytest.raises(TimeLimitReached):
        b.body(np.zeros(3), 0.0, 1.0, "body", "two")

    creep = plan_path(silo4, [[0.0, 1.2]], 0.4, gait="creep", samples_per_unit=2)
    total = creep.steps[-1].t_end
    request = PlanRequest(
        as_planning_model(silo4),
        preset_for("default"),
        creep.workspace,
        np.array([[0.0, 1.2]]),
        np.pi / 2,
        creep.tolerance,
        creep.stability_threshold,
        2,
        1.0,
        FlatGround(),
    )
    with pytest.raises(NotFaster) as stopped:
        OmniCreep().plan(request, slower_than=0.5 * total)
    assert 0.5 * total <= stopped.value.args[0] < total  # stopped on the way
    with pytest.raises(NotFaster):
        OmniCreep().plan(request, slower_than=total)
    same = OmniCreep().plan(request, slower_than=total + 0.5)
    assert same.steps[-1].t_end == total


@pytest.mark.parametrize("robot_file", [None, "tests/robots/mantis.urdf"])
def test_height_check_without_the_whole_range_agrees_with_it(robot_file) -> None:
    """_inside_feasible_run (the height check of workspace_for without the whole feasible
    range) says True only for heights inside feasible_height_range, and says it for the
    range's inside away from its ends (the range's scan is then not needed)."""
    from planner.workspace.layout import _inside_feasible_run, feasible_height_range
    from silo4kin import load_robot

    robot = planning_robot(load_robot() if robot_file is None else load_robot(robot_file))
    for preset in ("thesis", "default"):
        lo, hi = feasible_height_range(robot, preset)
        heights = np.concatenate(
            [
                np.linspace(lo - 0.05, hi + 0.05, 41),
                [lo, hi, lo - 1e-4, hi + 1e-4, np.nextafter(hi, 1.0)],
            ]
        )
        said = [bool(_inside_feasible_run(robot, float(h), preset)) for h in heights]
        for h, yes in zip(heights, said):
            assert not yes or lo <= h <= hi, (preset, h)
        inner = [yes for h, yes in zip(heights, said) if lo + 0.01 <= h <= hi - 0.02]
        assert inner and all(inner), preset
