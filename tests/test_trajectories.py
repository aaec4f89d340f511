"""Trajectory profiles (§5.2-5.3): end conditions and derivatives by finite differences."""

import numpy as np
import pytest

from planner.trajectory.profiles import (
    cosine_blend,
    lift,
    quintic_blend,
    quintic_coefficients,
    smooth_lift,
)

#: Central differences with h = 1e-5 on functions with derivatives ~ π^4: error ~ 1e-9.
FD_STEP = 1e-5
FD_TOL = 1e-6


@pytest.mark.parametrize(
    "profile",
    [
        lambda tau, T: cosine_blend(tau, T),
        lambda tau, T: lift(tau, T, 0.12),
        lambda tau, T: quintic_blend(tau, T),
        lambda tau, T: smooth_lift(tau, T, 0.12),
    ],
)
@pytest.mark.parametrize("duration", [1.0, 2.0])
def test_derivatives_match_finite_differences(profile, duration):
    tau = np.linspace(0.05, 0.95, 19)
    p = profile(tau, duration)
    hp = profile(tau + FD_STEP / duration, duration)
    hm = profile(tau - FD_STEP / duration, duration)
    np.testing.assert_allclose(p.ds, (hp.s - hm.s) / (2 * FD_STEP), atol=FD_TOL)
    np.testing.assert_allclose(p.dds, (hp.ds - hm.ds) / (2 * FD_STEP), atol=FD_TOL)


def test_blends_start_and_end_at_rest():
    ends = np.array([0.0, 1.0])
    for p in (cosine_blend(ends, 2.0), quintic_blend(ends, 2.0)):
        np.testing.assert_allclose(p.s, [0.0, 1.0], atol=1e-15)
        np.testing.assert_allclose(p.ds, 0.0, atol=1e-15)
    np.testing.assert_allclose(quintic_blend(ends, 2.0).dds, 0.0, atol=1e-15)
    z = lift(np.array([0.0, 0.5, 1.0]), 1.0, 0.1)
    np.testing.assert_allclose(z.s, [0.0, 0.1, 0.0], atol=1e-15)  # eq 5.4 peaks at h_max
    np.testing.assert_allclose(z.ds[[0, 2]], 0.0, atol=1e-15)


def test_smooth_lift_peaks_at_h_max_and_starts_and_ends_at_rest():
    z = smooth_lift(np.array([0.0, 0.5, 1.0]), 2.0, 0.1)
    np.testing.assert_allclose(z.s, [0.0, 0.1, 0.0], atol=1e-15)
    np.testing.assert_allclose(z.ds, 0.0, atol=1e-15)
    np.testing.assert_allclose(z.dds[[0, 2]], 0.0, atol=1e-15)
    dense = smooth_lift(np.linspace(0, 1, 1001), 1.0, 0.1).s
    assert dense.max() == pytest.approx(0.1) and dense.min() >= 0.0


def test_cosine_acceleration_is_not_zero_at_ends():
    """docs/thesis-notes.md: ẍ(0) = π²(x_f - x_o)/(2 t_f²) for eq 5.2-5.10."""
    assert cosine_blend(np.array([0.0]), 1.0).dds[0] == pytest.approx(np.pi**2 / 2)


def test_quintic_coefficients_eq_5_23_to_5_28_match_the_blend():
    b = quintic_coefficients(0.3, 1.1, 2.0)
    t = np.linspace(0, 2.0, 9)
    poly = sum(b[i] * t**i for i in range(6))
    np.testing.assert_allclose(poly, 0.3 + 0.8 * quintic_blend(t / 2.0, 2.0).s, atol=1e-12)
