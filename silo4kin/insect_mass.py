"""An insect leg's first mass moment Σ m_i c_i in the base frame, closed form, vectorised.

For one insect leg at joint values q (URDF), with φ = θb + θ1 the leg's yaw in the base
frame, r = (cos φ, sin φ, 0) its radial direction, t = z × r and the DH angles θ of
geometry.LegGeometry, the DH link frames (x along the link, y along the link joint's
positive axis; geometry.LinkInertia) are, in the base frame:

    coxa   origin hip,                             x = r,                         y = t
    femur  origin hip + L1 r,                      x = cos θ2 r + sin θ2 z,        y = -t
    tibia  origin femur + L2 x_femur,              x = cos θ23 r + sin θ23 z,      y = -t
    (θ23 = θ2 + θ3, z_link = x × y)

(the forward kinematics of eq 3.5 with each link's CM instead of the foot). The whole-robot
CoM built on it (silo4kin/com.py) is cross-checked against ``pin.centerOfMass`` on random
states (tests/test_com.py).
"""

from __future__ import annotations

import numpy as np

from .geometry import LegGeometry


def insect_leg_mass_moment_in_base(leg: LegGeometry, q: np.ndarray) -> np.ndarray:
    """Σ m_i c_i over an insect leg's links in the base frame [kg m], (N, 3).

    With the link frames of the module docstring (z_femur = sin θ2 r - cos θ2 z, z_tibia
    likewise with θ23) and a link CM (cx, cy, cz) in its frame, the moment is
    M_leg hip + A_r r + A_t t + A_z z with, summed over the links (m_i times):
    coxa (cx, cy, cz); femur (L1 + cx c2 + cz s2, -cy, cx s2 - cz c2); tibia
    (L1 + L2 c2 + cx c23 + cz s23, -cy, L2 s2 + cx s23 - cz c23).

    Args:
        q: the leg's joint values (hip yaw, hip pitch, knee) [rad], shape (N, 3).
    """
    q = np.asarray(q, dtype=float)
    theta = leg.joint_to_dh(q)
    phi = leg.theta_b + theta[:, 0]
    c, s = np.cos(phi), np.sin(phi)
    c2, s2 = np.cos(theta[:, 1]), np.sin(theta[:, 1])
    c23, s23 = np.cos(theta[:, 1] + theta[:, 2]), np.sin(theta[:, 1] + theta[:, 2])
    (m1, k1), (m2, k2), (m3, k3) = ((lk.mass, lk.com) for lk in leg.links)
    a_r = (
        m1 * k1[0]
        + m2 * (leg.L1 + k2[0] * c2 + k2[2] * s2)
        + m3 * (leg.L1 + leg.L2 * c2 + k3[0] * c23 + k3[2] * s23)
    )
    a_t = m1 * k1[1] - m2 * k2[1] - m3 * k3[1]
    a_z = (
        m1 * k1[2] + m2 * (k2[0] * s2 - k2[2] * c2) + m3 * (leg.L2 * s2 + k3[0] * s23 - k3[2] * c23)
    )
    hip = np.asarray(leg.position_hip_in_base, dtype=float) * (m1 + m2 + m3)
    out = np.empty((q.shape[0], 3))
    out[:, 0] = hip[0] + a_r * c - a_t * s
    out[:, 1] = hip[1] + a_r * s + a_t * c
    out[:, 2] = hip[2] + a_z
    return out
