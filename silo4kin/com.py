"""Whole-robot centre of mass from the closed-form kinematics, vectorised over samples.

For one insect leg at joint values q (URDF), with φ = θb + θ1 the leg's yaw in the base
frame, r = (cos φ, sin φ, 0) its radial direction, t = z × r and the DH angles θ of
geometry.LegGeometry, the DH link frames (x along the link, y along the link joint's
positive axis; geometry.LinkInertia) are, in the base frame:

    coxa   origin hip,                             x = r,                         y = t
    femur  origin hip + L1 r,                      x = cos θ2 r + sin θ2 z,        y = -t
    tibia  origin femur + L2 x_femur,              x = cos θ23 r + sin θ23 z,      y = -t
    (θ23 = θ2 + θ3, z_link = x × y)

(the forward kinematics of eq 3.5 with each link's CM instead of the foot). The robot's CoM
is (m_b c_b + Σ_links m_i c_i) / M with the body CoM c_b (base link) and M the total mass.
It is cross-checked against ``pin.centerOfMass`` on random states (tests/test_com.py).
"""

from __future__ import annotations

import numpy as np

from . import leg_family
from .geometry import LegGeometry


def leg_mass(leg) -> float:
    """Mass of the leg's three links [kg] (either family: silo4kin.leg_family)."""
    return leg_family.family_of(leg).mass(leg)


def leg_mass_moment_in_base(leg, q: np.ndarray) -> np.ndarray:
    """Σ m_i c_i over the leg's links, c_i the link CM in the base frame [kg m], (N, 3), of a
    leg of either family (silo4kin.leg_family: a mammal leg goes to
    mammal.leg_mass_moment_in_base, tested against pin.centerOfMass in tests/test_mammal.py;
    an insect leg to :func:`insect_leg_mass_moment_in_base`)."""
    return leg_family.family_of(leg).mass_moment_in_base(leg, q)


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
    a_r = (m1 * k1[0] + m2 * (leg.L1 + k2[0] * c2 + k2[2] * s2)
           + m3 * (leg.L1 + leg.L2 * c2 + k3[0] * c23 + k3[2] * s23))
    a_t = m1 * k1[1] - m2 * k2[1] - m3 * k3[1]
    a_z = (m1 * k1[2] + m2 * (k2[0] * s2 - k2[2] * c2)
           + m3 * (leg.L2 * s2 + k3[0] * s23 - k3[2] * c23))
    hip = np.asarray(leg.position_hip_in_base, dtype=float) * (m1 + m2 + m3)
    out = np.empty((q.shape[0], 3))
    out[:, 0] = hip[0] + a_r * c - a_t * s
    out[:, 1] = hip[1] + a_r * s + a_t * c
    out[:, 2] = hip[2] + a_z
    return out


def center_of_mass_closed_form(robot, q: np.ndarray) -> np.ndarray:
    """Whole-robot CoM in the base frame (the URDF root) [m], shape (N, 3).

    Args:
        robot: a silo4kin Robot (legs, body mass and body CoM, total mass).
        q: joint values in our order [rad], shape (N, 12) (or (12,), giving (1, 3)).
    """
    q = np.atleast_2d(np.asarray(q, dtype=float))
    moment = robot.body_mass * np.asarray(robot.position_body_com_in_base, dtype=float) \
        + np.zeros((q.shape[0], 3))
    for k, leg in enumerate(robot.legs):
        moment += leg_mass_moment_in_base(leg, q[:, 3 * k:3 * k + 3])
    return moment / robot.total_mass


def legs_com_offset(legs: tuple[LegGeometry, ...], q: np.ndarray, total_mass: float
                    ) -> np.ndarray:
    """Σ over legs of m_i c_i / M [m], (N, 3): the whole-robot CoM measured from the body CoM
    when the legs' hips are given relative to the body CoM (the planning frame) and the
    body CoM is the frame's origin. ``q`` (N, 12) [rad], ``total_mass`` M [kg]."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    moment = np.zeros((q.shape[0], 3))
    for k, leg in enumerate(legs):
        moment += leg_mass_moment_in_base(leg, q[:, 3 * k:3 * k + 3])
    return moment / total_mass
