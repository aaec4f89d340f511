"""Plans do not depend on the CPU's SIMD path (planner/ties.py).

numpy computes on AVX2 or AVX-512 paths by CPU; their results differ in the last bits. The
planner's discrete choices compare rounded scores, so a tie in exact arithmetic stays a tie.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from golden_plans import fingerprint_differences, load_golden, plan_fingerprint, robot_loader

from planner.gaits.creep_spin import choose_spin_order
from planner.gaits.omni import nearest_axis
from planner.ties import tie_key

TESTS = Path(__file__).parent
#: Golden cases whose contact sequence or length followed the SIMD path before the ties were
#: rounded (measured on an AVX-512 machine: a spin order, a 45 deg travel direction).
FLIPPED_BEFORE = ("straight_h0.2_thesis", "straight_h0.6_default", "random_silo4_4")


def _ulps(x: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """x with every value moved by -2..2 ulps."""
    x = np.asarray(x, dtype=float)
    return x + rng.integers(-2, 3, x.shape) * np.spacing(np.abs(x) + 1e-300)


def test_tie_key_rounds_to_a_nanounit_and_folds_negative_zero() -> None:
    assert tie_key(0.1 + 0.2) == tie_key(0.3)
    assert math.copysign(1.0, tie_key(-1e-17)) == 1.0
    assert tie_key(1.0000000004) == 1.0 and tie_key(1.000000001) > 1.0


def test_a_diagonal_direction_picks_the_same_axis_under_noise() -> None:
    """At 45 deg between +x and +y the first axis of AXIS_TIE_ORDER wins (+y), whatever
    the last bits of u are."""
    rng = np.random.default_rng(1)
    for u, axis in (([1.0, 1.0], "+y"), ([1.0, -1.0], "-y"), ([-1.0, 1.0], "+y")):
        u = np.array(u) * math.sqrt(0.5)
        assert {nearest_axis(_ulps(u, rng)) for _ in range(50)} == {axis}
    assert nearest_axis(np.array([0.8, 0.6])) == "+x"
    assert nearest_axis(np.array([0.6, 0.8])) == "+y"


def test_a_symmetric_spin_picks_one_leg_order_under_noise() -> None:
    """A stance mirrored about both body axes turning about its centre: many leg orders tie
    in exact arithmetic; the same one wins on every draw of last-bit noise."""
    feet = np.array([[0.35, 0.3], [0.35, -0.3], [-0.35, 0.3], [-0.35, -0.3]])
    c, s = math.cos(0.1), math.sin(0.1)
    targets = feet @ np.array([[c, s], [-s, c]])
    rng = np.random.default_rng(3)
    orders = {
        choose_spin_order(_ulps(feet, rng), _ulps(targets, rng), _ulps(np.zeros(2), rng), 0.05)
        for _ in range(30)
    }
    assert len(orders) == 1


def _dispatched_features() -> list[str]:
    from numpy._core import _multiarray_umath as umath

    return [f for f in umath.__cpu_dispatch__ if umath.__cpu_features__.get(f)]


@pytest.mark.skipif(not _dispatched_features(), reason="numpy runs its baseline path here only")
def test_plans_are_the_same_on_numpy_baseline_simd_path() -> None:
    """The golden cases that used to flip plan to the same fingerprint with every SIMD
    extension numpy dispatches to on this CPU switched off (NPY_DISABLE_CPU_FEATURES: the
    path of a CPU without them) as in this process."""
    cases = {c["name"]: c for c in load_golden()}
    script = (
        "import json, sys; sys.path.insert(0, sys.argv[1]);"
        "from golden_plans import load_golden, plan_fingerprint, robot_loader;"
        "get = robot_loader(); cases = {c['name']: c for c in load_golden()};"
        "print(json.dumps({n: plan_fingerprint(cases[n], get(cases[n]['robot']))"
        " for n in sys.argv[2:]}))"
    )
    env = dict(os.environ, NPY_DISABLE_CPU_FEATURES=" ".join(_dispatched_features()))
    out = subprocess.run(
        [sys.executable, "-c", script, str(TESTS), *FLIPPED_BEFORE],
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    other = json.loads(out.stdout)
    get = robot_loader()
    for name in FLIPPED_BEFORE:
        here = plan_fingerprint(cases[name], get(cases[name]["robot"]))
        assert fingerprint_differences(other[name], here) == [], name
