"""Creeping and spinning gaits (§4.2): sequences, closure, stability, spin counts."""

import math

import numpy as np
import pytest

from planner.gaits.builder import StepBuilder
from planner.gaits.creep_spin import (
    CRAB_MAX_RAD,
    CRAB_STEP_RAD,
    DIRECTIONS,
    crab_limit_rad,
    creep_half_cycle,
    creep_pairs,
    creep_stance_in_base,
    foothold_in_base,
    spin,
    spin_cycles,
    thesis_spin_cycles,
    transition_from_spin,
    transition_to_spin,
)
from planner.stability.margin import triangle_margin_xy
from planner.stability.shifts import closest_point_with_margin
from planner.workspace.footholds import CRAB_ROOM_RAD
from planner.workspace.layout import feasible_height_range, workspace_for
from silo4kin.frames import rotation_z

#: Positions are sums of a few products of ~0.5 m numbers: 1e-12 m is far above rounding.
EXACT_M = 1e-12
THESIS_ORDER = {
    "+x": ["RH", "RF", "LH", "LF"],
    "-x": ["LF", "LH", "RF", "RH"],
    "-y": ["LH", "RH", "LF", "RF"],
    "+y": ["RF", "LF", "RH", "LH"],
}


def _builder(ws, direction="+x", yaw=0.3, threshold=None):
    base = np.array([0.1, -0.2, ws.height])
    feet = base + (rotation_z(yaw) @ creep_stance_in_base(ws, direction, 0).T).T
    return StepBuilder(
        base, yaw, feet, ws.stability_threshold_m if threshold is None else threshold
    )


@pytest.mark.parametrize("direction", list(DIRECTIONS))
def test_creep_sequence_is_4_2_B_3_1_B_relabelled(silo4, direction):
    """§4.2.1 prints the leg order for each direction; thesis legs 1-4 = LF, RF, LH, RH."""
    ws = workspace_for(silo4, 0.39, "thesis")
    b = _builder(ws, direction)
    creep_half_cycle(b, ws, direction, creep_half_cycle(b, ws, direction, 0))
    kinds = [s.kind for s in b.steps]
    assert kinds == ["transfer", "transfer", "body"] * 2
    assert [s.leg for s in b.steps if s.kind == "transfer"] == THESIS_ORDER[direction]
    assert b.t == 8.0  # 8 units, β = 7/8


@pytest.mark.parametrize("preset", ["default", "thesis"])
@pytest.mark.parametrize("direction", list(DIRECTIONS))
@pytest.mark.parametrize("height", [0.2, 0.39, 0.6])
def test_creep_cycle_closes_and_moves_one_stride(silo4, preset, direction, height):
    """After a whole cycle the feet sit where they started relative to the body, the body
    moved λ along the direction, and no shift was needed (margins above threshold)."""
    ws = workspace_for(silo4, height, preset)
    b = _builder(ws, direction)
    start_rel = b.feet - b.base
    base0 = b.base.copy()
    creep_half_cycle(b, ws, direction, creep_half_cycle(b, ws, direction, 0))
    np.testing.assert_allclose(b.feet - b.base, start_rel, atol=EXACT_M)
    d = DIRECTIONS[direction]
    moved = rotation_z(0.3).T @ (b.base - base0)
    np.testing.assert_allclose(moved[:2], d * ws.stride_along(d), atol=EXACT_M)
    assert b.n_shifts == 0


def test_creep_pairs_rear_first(silo4):
    ws = workspace_for(silo4, 0.4)
    assert creep_pairs(ws, "+x") == ((3, 1), (2, 0))


def test_spin_cycle_counts_both_ways(silo4):
    ws = workspace_for(silo4, 0.2)
    assert spin_cycles(ws, 0.0) == 0
    assert spin_cycles(ws, ws.psi_max_rad) == 1
    assert spin_cycles(ws, -1.01 * ws.psi_max_rad) == 2
    assert thesis_spin_cycles(math.radians(97.7)) == 2
    assert thesis_spin_cycles(math.radians(80)) == 1
    assert thesis_spin_cycles(math.radians(200)) == 4


@pytest.mark.parametrize("preset", ["default", "thesis"])
@pytest.mark.parametrize("psi_deg", [-170.0, -40.0, 5.0, 90.0])
def test_spin_turns_about_the_cog_and_returns_to_the_stance(silo4, preset, psi_deg):
    """The consistent spin: feet end at the creeping stance rotated by ψ about the nominal
    CoG, the nominal CoG ends where it started (the next body phase absorbs a shift), and
    every lift keeps S_m >= threshold."""
    ws = workspace_for(silo4, 0.4, preset)
    b = _builder(ws)
    base0, yaw0 = b.base.copy(), b.yaw
    psi = math.radians(psi_deg)
    transition_to_spin(b, ws, "+x", 0)
    orders = spin(b, ws, psi)
    transition_from_spin(b, ws, "+x")
    assert len(orders) == spin_cycles(ws, psi)
    assert all(sorted(o) == [0, 1, 2, 3] for o in orders)
    np.testing.assert_allclose(b.nominal_base, base0, atol=EXACT_M)  # shifts: see steps.py
    assert np.hypot(*(b.base - base0)[:2]) < 0.1
    assert b.yaw == pytest.approx(yaw0 + psi, abs=EXACT_M)
    expected = base0 + (rotation_z(yaw0 + psi) @ creep_stance_in_base(ws, "+x", 0).T).T
    np.testing.assert_allclose(b.feet, expected, atol=EXACT_M)
    rotates = [s for s in b.steps if s.kind == "rotate"]
    assert [s.duration for s in rotates] == [2.0] * len(orders)
    transfers = [s for s in b.steps if s.kind == "transfer"]
    assert len(transfers) == 4 * len(orders) + 4  # + 2 + 2 transitions


def test_thesis_preset_spin_has_no_shifts_and_default_keeps_margin(silo4):
    ws_t = workspace_for(silo4, 0.39, "thesis")
    b = _builder(ws_t)
    transition_to_spin(b, ws_t, "+x", 0)
    spin(b, ws_t, math.pi / 3)
    assert b.n_shifts == 0  # thesis: 6 units per cycle, margin 0 accepted
    ws = workspace_for(silo4, 0.39)
    b = _builder(ws)
    transition_to_spin(b, ws, "+x", 0)
    spin(b, ws, math.pi / 3)
    for s in b.steps:
        if s.kind == "transfer":
            b2 = StepBuilder(
                s.position_base_start_in_world, s.yaw_base_start, s.position_feet_in_world, 0.0
            )
            assert b2.lift_margin(["LF", "RF", "LH", "RH"].index(s.leg)) >= 0.02 - 1e-9


@pytest.mark.parametrize("crab_deg", [-20.0, 12.0])
def test_crab_half_cycles_walk_at_the_crab_angle(silo4, crab_deg):
    """A crab cycle (thesis §4.1) moves the body λ along the turned direction and the feet
    land on the turned footholds: after a whole cycle from the axis stance, the two pairs
    sit at the turned rear / position 2 relative to the body."""
    ws = workspace_for(silo4, 0.4)
    b = _builder(ws)
    base0, crab = b.base.copy(), math.radians(crab_deg)
    creep_half_cycle(b, ws, "+x", creep_half_cycle(b, ws, "+x", 0, crab), crab)
    moved = rotation_z(0.3).T @ (b.base - base0)
    np.testing.assert_allclose(
        moved[:2], ws.stride_m * np.array([math.cos(crab), math.sin(crab)]), atol=EXACT_M
    )
    rel = (rotation_z(0.3).T @ (b.feet - b.base).T).T
    expected = [
        foothold_in_base(ws, k, "+x", "rear" if k in (3, 1) else "mid", crab) for k in range(4)
    ]
    np.testing.assert_allclose(rel, expected, atol=EXACT_M)
    assert b.n_shifts == 0
    np.testing.assert_array_equal(
        foothold_in_base(ws, 0, "+x", "front", 0.0), foothold_in_base(ws, 0, "+x", "front")
    )


def test_crab_limit_keeps_the_shift_reserve(silo4):
    """The crab limit is where the turned footholds stop being reachable with the body
    displaced by the shift reserve. The default workspace fits its x strides turned by
    ±footholds.CRAB_ROOM_RAD (= CRAB_MAX_RAD), so the planner's cap holds at every height,
    and the reach-limited strides (low heights) leave little beyond it: one step past the
    limit fails."""
    assert CRAB_ROOM_RAD == pytest.approx(CRAB_MAX_RAD)
    cap = math.radians(30.0)
    lo, hi = feasible_height_range(silo4, "default")
    for h in (lo, 0.2, 0.4, 0.6, hi):
        assert crab_limit_rad(silo4, workspace_for(silo4, h)) == pytest.approx(CRAB_MAX_RAD)
    lim = crab_limit_rad(silo4, workspace_for(silo4, 0.2), cap)
    assert CRAB_MAX_RAD <= lim < cap - 1e-9
    assert crab_limit_rad(silo4, workspace_for(silo4, 0.2), lim + CRAB_STEP_RAD) == pytest.approx(
        lim
    )


def test_closest_point_with_margin_is_the_nearest_point_of_the_shrunk_triangles():
    """Property (seeded random triangles and points): the point returned has S_m >= target
    in every triangle, and no grid point with that margin is nearer; None exactly when the
    shrunk triangles do not meet (checked against a dense grid)."""
    rng = np.random.default_rng(7)
    for _ in range(30):
        tris = [tuple(map(tuple, rng.uniform(-0.5, 0.5, (3, 2)))) for _ in range(2)]
        p = tuple(rng.uniform(-0.5, 0.5, 2))
        q = closest_point_with_margin(tris, p, 0.02)
        xs = np.linspace(-0.5, 0.5, 201)
        grid = [(x, y) for x in xs for y in xs]
        good = [g for g in grid if min(triangle_margin_xy(*t, g) for t in tris) >= 0.02]
        if q is None:
            assert not good
            continue
        assert min(triangle_margin_xy(*t, q) for t in tris) >= 0.02 - 1e-9
        if good:
            nearest = min(math.hypot(g[0] - p[0], g[1] - p[1]) for g in good)
            assert math.hypot(q[0] - p[0], q[1] - p[1]) <= nearest + 1e-9


def test_folded_shifts_keep_the_margin_and_save_the_shift_steps(silo4):
    """With fold_shifts, a spin after a creeping body phase has no shift step: the body phase
    (or the spin rotation) ends where every lift up to the next body step keeps S_m >=
    threshold, the steps stay contiguous, and the nominal pose is unchanged."""
    ws = workspace_for(silo4, 0.4)
    plain, folded = _builder(ws), _builder(ws)
    folded.fold_shifts = True
    for b in (plain, folded):
        creep_half_cycle(b, ws, "+x", 0)
        spin(b, ws, math.radians(30.0))
    assert plain.n_shifts > 0 and folded.n_shifts == 0 and folded.n_folded > 0
    assert folded.t < plain.t
    np.testing.assert_allclose(folded.nominal_base, plain.nominal_base, atol=EXACT_M)
    np.testing.assert_allclose(folded.feet, plain.feet, atol=EXACT_M)
    for s in folded.steps:
        if s.kind == "transfer":
            b2 = StepBuilder(
                s.position_base_start_in_world, s.yaw_base_start, s.position_feet_in_world, 0.0
            )
            assert b2.lift_margin(["LF", "RF", "LH", "RH"].index(s.leg)) >= 0.02 - 1e-9
    for a, c in zip(folded.steps, folded.steps[1:]):
        np.testing.assert_array_equal(a.position_base_end_in_world, c.position_base_start_in_world)
