"""The creeping gait's body phases and the builder's shift steps are paced so that their
acceleration keeps the zero-moment point within the stability margin of the CoG
(planner/gaits/body_pace.py, issue 21).

The invariant is checked on the sampled plan, not on the rule's own arithmetic: over every
"creep body" and "shift" step of an omnidirectional-gait plan, h |c̈_xy| / g of the sampled
base (at the plan's unit time of 1 s) stays within the plan's stability threshold."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner import plan_path
from planner.gaits.body_pace import (
    CREEP_BODY_LABEL,
    GRAVITY,
    PACE_GRID_UNITS,
    body_units,
    zmp_excursion_m,
)


def test_body_units_keeps_the_excursion_within_the_margin_on_its_grid():
    for d, h, s, n0 in [(0.24, 0.5, 0.02, 1.0), (0.05, 0.4, 0.02, 1.0), (0.3, 0.3, 0.01, 2.0)]:
        n = body_units(d, h, s, n0)
        assert n >= n0
        assert zmp_excursion_m(d, h, n) <= s + 1e-12
        if n > n0:  # no longer than the grid asks
            assert n % PACE_GRID_UNITS == pytest.approx(0.0, abs=1e-12)
            assert zmp_excursion_m(d, h, n - PACE_GRID_UNITS) > s or n - PACE_GRID_UNITS < n0
    # anymal corpus case 17's body phase (0.24 m at h 0.5 m): 1 unit put the ZMP 7 cm off
    assert zmp_excursion_m(0.24, 0.5, 1.0) == pytest.approx(0.0706, abs=1e-3)
    assert body_units(0.24, 0.5, 0.02, 1.0) == 2.0
    # no margin asked (the thesis preset's threshold 0), no move: the gait's own time
    assert body_units(0.24, 0.5, 0.0, 1.0) == 1.0
    assert body_units(0.0, 0.5, 0.02, 1.0) == 1.0


def test_quintic_peak_is_the_sampled_peak():
    from planner.gaits.body_pace import QUINTIC_PEAK_ACCELERATION
    from planner.trajectory.profiles import quintic_blend

    tau = np.linspace(0.0, 1.0, 200001)
    assert np.abs(quintic_blend(tau, 1.0).dds).max() == pytest.approx(
        QUINTIC_PEAK_ACCELERATION, rel=1e-9
    )


@pytest.mark.parametrize("height", [0.4, 0.55])
def test_creep_body_phases_keep_the_zmp_within_the_threshold(silo4, height):
    plan = plan_path(silo4, [(0.0, 0.0), (0.0, 1.2)], height, gait="creep")
    traj = plan.trajectory
    spu = 100
    t = np.asarray(traj.t) - traj.t[0]
    base = np.asarray(traj.position_base_in_world)
    acc = np.gradient(np.gradient(base[:, :2], t, axis=0), t, axis=0)
    bodies = [s for s in plan.steps if s.label in (CREEP_BODY_LABEL, "shift")]
    assert bodies
    paced = 0
    for s in bodies:
        lo, hi = int(round(s.t_start * spu)), int(round(s.t_end * spu))
        rows = slice(lo + 2, hi - 1)  # the finite differences stay inside the step
        feet_z = np.asarray(traj.position_foot_in_world)[lo, :, 2].mean()
        h = float(base[lo, 2] - feet_z)
        excursion = h * np.linalg.norm(acc[rows], axis=1).max() / GRAVITY
        assert excursion <= plan.stability_threshold * (1 + 1e-3) + 1e-6, (s, excursion)
        paced += s.duration > 1.0
        d = float(np.hypot(*(s.position_base_end_in_world - s.position_base_start_in_world)[:2]))
        assert math.isclose(
            excursion, zmp_excursion_m(d, h, s.duration), rel_tol=2e-3, abs_tol=1e-5
        )
    assert paced  # the rule lengthened at least one body phase of this path


def test_anymal_tall_shifts_are_paced(anymal):
    """anymal at 0.61 m (corpus case #29's height and first leg): its shift steps of up to
    0.11 m put the ZMP 39.5 mm off the CoG in 1 unit before the rule."""
    robot = anymal
    plan = plan_path(robot, [(0.0, 0.0), (0.13, -0.39)], 0.6136, gait="creep", start_heading=0.68)
    traj = plan.trajectory
    spu = 100
    t = np.asarray(traj.t) - traj.t[0]
    base = np.asarray(traj.position_base_in_world)
    acc = np.gradient(np.gradient(base[:, :2], t, axis=0), t, axis=0)
    shifts = [s for s in plan.steps if s.label in (CREEP_BODY_LABEL, "shift")]
    assert any(s.label == "shift" and s.duration > 1.0 for s in shifts)
    for s in shifts:
        lo, hi = int(round(s.t_start * spu)), int(round(s.t_end * spu))
        # the contact points: the ball's centres less its radius
        h = float(base[lo, 2] - np.asarray(traj.position_foot_in_world)[lo, :, 2].mean())
        excursion = h * np.linalg.norm(acc[lo + 2 : hi - 1], axis=1).max() / GRAVITY
        assert excursion <= plan.stability_threshold * (1 + 1e-3) + 1e-6, (s.label, excursion)
