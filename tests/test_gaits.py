"""Creeping and spinning gaits (§4.2): sequences, closure, stability, spin counts."""

import math

import numpy as np
import pytest

from planner.gaits import (
    DIRECTIONS,
    creep_half_cycle,
    creep_pairs,
    creep_stance_in_base,
    rotation_z,
    spin,
    spin_cycles,
    thesis_spin_cycles,
    transition_from_spin,
    transition_to_spin,
)
from planner.steps import StepBuilder
from planner.workspace import workspace_for

#: Positions are sums of a few products of ~0.5 m numbers: 1e-12 m is far above rounding.
EXACT_M = 1e-12
THESIS_ORDER = {"+x": ["RH", "RF", "LH", "LF"], "-x": ["LF", "LH", "RF", "RH"],
                "-y": ["LH", "RH", "LF", "RF"], "+y": ["RF", "LF", "RH", "LH"]}


def _builder(ws, direction="+x", yaw=0.3, threshold=None):
    base = np.array([0.1, -0.2, ws.height])
    feet = base + (rotation_z(yaw) @ creep_stance_in_base(ws, direction, 0).T).T
    return StepBuilder(base, yaw, feet,
                       ws.stability_threshold_m if threshold is None else threshold)


@pytest.mark.parametrize("direction", list(DIRECTIONS))
def test_creep_sequence_is_4_2_B_3_1_B_relabelled(silo4, direction):
    """§4.2.1 prints the leg order for each direction; thesis legs 1-4 = LF, RF, LH, RH."""
    ws = workspace_for(silo4, 0.39, "thesis")
    b = _builder(ws, direction)
    creep_half_cycle(b, ws, direction, creep_half_cycle(b, ws, direction, 0))
    kinds = [s.kind for s in b.steps]
    assert kinds == ["transfer", "transfer", "body"] * 2
    assert [s.leg for s in b.steps if s.kind == "transfer"] == THESIS_ORDER[direction]
    assert b.t == 8.0                                           # 8 units, β = 7/8


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
    assert len(transfers) == 4 * len(orders) + 4                 # + 2 + 2 transitions


def test_thesis_preset_spin_has_no_shifts_and_default_keeps_margin(silo4):
    ws_t = workspace_for(silo4, 0.39, "thesis")
    b = _builder(ws_t)
    transition_to_spin(b, ws_t, "+x", 0)
    spin(b, ws_t, math.pi / 3)
    assert b.n_shifts == 0                     # thesis: 6 units per cycle, margin 0 accepted
    ws = workspace_for(silo4, 0.39)
    b = _builder(ws)
    transition_to_spin(b, ws, "+x", 0)
    spin(b, ws, math.pi / 3)
    for s in b.steps:
        if s.kind == "transfer":
            b2 = StepBuilder(s.position_base_start_in_world, s.yaw_base_start,
                             s.position_feet_in_world, 0.0)
            assert b2.lift_margin(["LF", "RF", "LH", "RH"].index(s.leg)) >= 0.02 - 1e-9
