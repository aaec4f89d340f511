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

from .geometry import LegGeometry


def leg_mass(leg: LegGeometry) -> float:
    """Mass of the leg's three links [kg]."""
    return float(sum(link.mass for link in leg.links))


def leg_mass_moment_in_base(leg: LegGeometry, q: np.ndarray) -> np.ndarray:
    """Σ m_i c_i over the leg's links, c_i the link CM in the base frame [kg m], (N, 3).

    Args:
        q: the leg's joint values (hip yaw, hip pitch, knee) [rad], shape (N, 3).
    """
    q = np.asarray(q, dtype=float)
    theta = leg.joint_to_dh(q)
    phi = leg.theta_b + theta[:, 0]
    c, s = np.cos(phi), np.sin(phi)
    zeros = np.zeros_like(c)
    r = np.stack([c, s, zeros], axis=1)                      # radial (N, 3)
    t = np.stack([-s, c, zeros], axis=1)                     # z × r
    z = np.array([0.0, 0.0, 1.0])
    c2, s2 = np.cos(theta[:, 1]), np.sin(theta[:, 1])
    c23, s23 = np.cos(theta[:, 1] + theta[:, 2]), np.sin(theta[:, 1] + theta[:, 2])
    x_femur = c2[:, None] * r + s2[:, None] * z
    x_tibia = c23[:, None] * r + s23[:, None] * z
    hip = np.asarray(leg.position_hip_in_base, dtype=float)
    origin_femur = hip + leg.L1 * r
    origin_tibia = origin_femur + leg.L2 * x_femur
    frames = ((hip + zeros[:, None], r, t), (origin_femur, x_femur, -t),
              (origin_tibia, x_tibia, -t))
    moment = np.zeros((q.shape[0], 3))
    for link, (origin, x_axis, y_axis) in zip(leg.links, frames):
        z_axis = np.cross(x_axis, y_axis)
        com = link.com
        position = origin + com[0] * x_axis + com[1] * y_axis + com[2] * z_axis
        moment += link.mass * position
    return moment


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
