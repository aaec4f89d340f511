"""The thesis's equations exactly as printed, in DH angles, for the errata tests.

Nothing in the toolkit imports this: it exists so that tests/test_errata.py can show, for
each suspected misprint, that the printed form disagrees with Pinocchio and by how much.
Symbols as in App. A: m_i, Lcm_i, J_i (= link inertia I_i), L1, L2, g.
"""

from __future__ import annotations

import numpy as np


def theta1_eq_3_10(x, y, Lb, theta_b):
    """eq 3.10 as printed: no wrapping."""
    return np.arctan2(y - Lb * np.sin(theta_b), x - Lb * np.cos(theta_b)) - theta_b


def abc_eq_3_14_3_16(x, y, z, Lb, Lz, L1, L2, L3, theta_b, theta1):
    """A, B, C of eq 3.14-3.16."""
    s, c = np.sin(theta_b + theta1), np.cos(theta_b + theta1)
    dx, dy = x - Lb * np.cos(theta_b), y - Lb * np.sin(theta_b)
    A = 2 * L2 * dy * s + 2 * L2 * dx * c - 2 * L2 * L1
    B = 2 * L2 * (z + Lz)
    C = (
        c**2 * dx**2
        + 2 * dx * dy * s * c
        - 2 * L1 * dx * c
        - L3**2
        + s**2 * dy**2
        - 2 * L1 * dy * s
        + L1**2
        + (z + Lz) ** 2
        + L2**2
    )
    return A, B, C


def theta2_eq_3_21_3_22(A, B, C, sign=+1.0):
    """eq 3.21-3.22: tan(theta2/2) = (2B ± sqrt(4B^2 - 4C^2 + 4A^2)) / (2(C + A))."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (2 * B + sign * np.sqrt(4 * B**2 - 4 * C**2 + 4 * A**2)) / (2 * (C + A))
    return 2 * np.arctan(t)


def theta3_eq_3_24(x, y, z, Lb, Lz, L1, L2, theta_b, theta1, theta2):
    """eq 3.24 as printed: atan2(num, den) / theta2."""
    num = z + Lz - L2 * np.sin(theta2)
    den = (
        (x - Lb * np.cos(theta_b)) * np.cos(theta_b + theta1)
        + (y - Lb * np.sin(theta_b)) * np.sin(theta_b + theta1)
        - L1
        - L2 * np.cos(theta2)
    )
    return np.arctan2(num, den) / theta2


def j33_eq_3_45(L3, t2, t3, td2, td3):
    """eq 3.45 as printed, labelled J(3,3)."""
    return -L3 * np.sin(t2 + t3) * (td2 + td3)


def mass_matrix_printed(m, lcm, J, L1, L2, t2, t3):
    """eq A.15-A.23 as printed; returns (N, 3, 3)."""
    m1, m2, m3 = m
    l1, l2, l3 = lcm
    J1, J2, J3 = J
    n = np.shape(t2)[0]
    M = np.zeros((n, 3, 3))
    M[:, 0, 0] = (
        (2 * m2 * L1 * l2 + 2 * m3 * L1 * L2) * np.cos(t2)
        + m3 * L2 * l3 * np.cos(t3)
        + 2 * m3 * L1 * l3 * np.cos(t2 + t3)
        + m3 * L2 * l3 * np.cos(t3 + 2 * t2)
        + (0.5 * m3 * L2**2 + 0.5 * m2 * l2**2) * np.cos(2 * t2)
        + (0.5 * m3 * l3) ** 2 * np.cos(2 * t2 + 2 * t3)
        + m2 * L1**2
        + m3 * L1**2
        + 0.5 * m3 * l3**2
        + 0.5 * m3 * L2**2
        + m1 * L1**2
        + J1
        + 0.5 * m2 * l2**2
    )  # A.15
    M[:, 1, 1] = (
        2 * m3 * L2 * l3 * np.cos(t3) + m3 * L2**2 + m3 * l3**2 + J2 + m2 * l2**2 + 2 * m3 * L2
    )  # A.19
    M[:, 1, 2] = m3 * L2 * l3 * np.cos(t3) + m3 * l3**2  # A.20
    M[:, 2, 1] = m2 * L2 * l3 * np.cos(t3) + m3 * l3**2  # A.22
    M[:, 2, 2] = J3 + m3 * l3**2  # A.23
    return M


def coriolis_printed(m, lcm, L1, L2, t2, t3, td1, td2, td3):
    """eq A.27-A.29 as printed; returns (N, 3)."""
    _, m2, m3 = m
    _, l2, l3 = lcm
    s = np.sin
    H1 = td1 * td2 * (
        (-m3 * L2**2 - m2 * l2**2) * s(2 * t2)
        - (2 * m2 * L1 * l2 + 2 * m3 * L1 * L2) * s(t2)
        - 2 * m3 * L1 * l3 * s(t2 + t3)
        - m3 * l3**2 * s(2 * t2 + 2 * t3)
        - 2 * m3 * L2 * l3 * s(t3 + 2 * t2)
    ) + td1 * td3 * (
        -4 * m3 * L1 * l3 * s(t2 + t3)
        - m3 * l3**2 * s(2 * t2 + 2 * t3)
        - m3 * L2 * l3 * s(t3 + 2 * t2)
        - m3 * L2 * l3 * s(t3)
    )
    H2 = (
        td1**2
        * (
            0.5 * m3 * l3**2 * s(2 * t2 + 2 * t3)
            + (0.5 * m3 * L2**2 + 0.5 * m2 * l2**2) * s(2 * t2)
            + m3 * L2 * l3 * s(t3 + 2 * t2)
            + (m2 * l2 * L1 + m3 * L1 * L2) * s(t2)
            + m3 * L1 * l3 * s(t2 + t3)
        )
        - td2 * td3 * 2 * m3 * L2 * l3 * s(t3)
        - td3**2 * m3 * L2 * l3 * s(t3)
    )
    H3 = td2**2 * m3 * L2 * l3 * s(t3) + td1**2 * (
        0.5 * m3 * l3**2 * s(2 * t2 + 2 * t3)
        + 0.5 * m3 * l3 * L2 * s(2 * t2 + t3)
        + 0.5 * m3 * l3 * L2 * s(t3)
        + m3 * L1 * l3 * s(t2 + t3)
    )
    return np.stack([H1, H2, H3], axis=1)


def gravity_printed(m, lcm, L2, g, t2, t3):
    """eq A.24-A.26 as printed; returns (N, 3)."""
    _, m2, m3 = m
    _, l2, l3 = lcm
    G2 = (m2 * g * l2 + m3 * g * L2) * np.cos(t2) + m3 * g * l3 * np.cos(t2 + t3)
    G3 = m3 * g * l3 * np.cos(t2 + t3)
    return np.stack([np.zeros_like(t2), G2, G3], axis=1)
