"""Time profiles of the thesis trajectories (§5.2-5.3), vectorised over samples.

Every profile maps normalised phase time τ = (t - t_o) / t_f in [0, 1] to a blend s(τ) and
its time derivatives; a coordinate then moves as p(t) = p_o + (p_f - p_o) s. Derivatives are
per time unit (the planner's t_l); divide by unit_time_s (and its square) for seconds.

    cosine   eq 5.2-5.3, 5.5-5.6, 5.8-5.9 (swing x, y) and 5.13-5.15 (body translation):
             s = (1 - cos πτ)/2, ds/dt = (π/2t_f) sin πτ, d²s/dt² = (π²/2t_f²) cos πτ.
             Velocity is zero at both ends; the acceleration is not (docs/thesis-notes.md).
    lift     eq 5.4, 5.7, 5.10 (swing z): z = (h_max/2)(1 - cos 2πτ) + z_o.
    lift5    the smooth swing lift of the default's omnidirectional gait (not in the thesis):
             z = 64 h_max τ³(1 - τ)³ + z_o, peak h_max at τ = 1/2; velocity and acceleration
             zero at both ends, so with quintic x, y (below) q̈ is continuous at touch-down.
    quintic  eq 5.16-5.28 with t_o = 0: s = 10τ³ - 15τ⁴ + 6τ⁵; zero velocity and
             acceleration at both ends. The planner applies it to the base yaw (and any CoG
             return) of the spinning gait's body rotation, then solves IK per stance leg
             (the consistent spin, docs/thesis-notes.md), rather than to the joints directly.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Profile(NamedTuple):
    """A blend and its time derivatives, each shape (N,).

    Attributes:
        s: blend value (0 -> 1 for cosine/quintic; lift height for lift) [dimensionless or m].
        ds: first time derivative [1/unit or m/unit].
        dds: second time derivative [1/unit^2 or m/unit^2].
    """

    s: np.ndarray
    ds: np.ndarray
    dds: np.ndarray


def cosine_blend(tau: np.ndarray, duration: np.ndarray | float) -> Profile:
    """Eq 5.2/5.5/5.8 (and 5.13-5.15) as a 0 -> 1 blend; duration t_f [units]."""
    tau = np.asarray(tau, dtype=float)
    w = np.pi / np.asarray(duration, dtype=float)
    return Profile(
        0.5 * (1.0 - np.cos(np.pi * tau)),
        0.5 * w * np.sin(np.pi * tau),
        0.5 * w * w * np.cos(np.pi * tau),
    )


def lift(tau: np.ndarray, duration: np.ndarray | float, h_max: float) -> Profile:
    """Swing-foot height above its start, eq 5.4, 5.7, 5.10 [m, m/unit, m/unit^2]."""
    tau = np.asarray(tau, dtype=float)
    w = np.pi / np.asarray(duration, dtype=float)
    return Profile(
        0.5 * h_max * (1.0 - np.cos(2.0 * np.pi * tau)),
        h_max * w * np.sin(2.0 * np.pi * tau),
        2.0 * h_max * w * w * np.cos(2.0 * np.pi * tau),
    )


def smooth_lift(tau: np.ndarray, duration: np.ndarray | float, h_max: float) -> Profile:
    """Swing-foot height above its start with zero velocity and acceleration at lift-off and
    touch-down (module docstring, lift5) [m, m/unit, m/unit^2]."""
    tau = np.asarray(tau, dtype=float)
    tf = np.asarray(duration, dtype=float)
    u, v = tau * (1.0 - tau), 1.0 - 2.0 * tau
    return Profile(
        64.0 * h_max * u**3,
        192.0 * h_max * u * u * v / tf,
        192.0 * h_max * (2.0 * u * v * v - 2.0 * u * u) / (tf * tf),
    )


def quintic_blend(tau: np.ndarray, duration: np.ndarray | float) -> Profile:
    """Eq 5.16 with the coefficients 5.23-5.28 (p_o = 0, p_f = 1, t_o = 0)."""
    tau = np.asarray(tau, dtype=float)
    tf = np.asarray(duration, dtype=float)
    t2 = tau * tau
    return Profile(
        t2 * tau * (10.0 - 15.0 * tau + 6.0 * t2),
        30.0 * t2 * (1.0 - 2.0 * tau + t2) / tf,
        60.0 * tau * (1.0 - 3.0 * tau + 2.0 * t2) / (tf * tf),
    )


def quintic_coefficients(p_o: float, p_f: float, t_f: float) -> np.ndarray:
    """b_0 .. b_5 of eq 5.23-5.28 (t_o = 0), shape (6,); for tests and reference."""
    d = p_f - p_o
    return np.array([p_o, 0.0, 0.0, 10.0 * d / t_f**3, -15.0 * d / t_f**4, 6.0 * d / t_f**5])
