"""Whole-robot centre of mass from the closed-form kinematics, vectorised over samples.

The robot's CoM is (m_b c_b + Σ_legs Σ_links m_i c_i) / M with the body CoM c_b (base link)
and M the total mass; each leg's Σ m_i c_i comes from its family (silo4kin/leg_family.py:
silo4kin/insect_mass.py for insect legs, silo4kin/mammal.py for mammal legs). It is
cross-checked against ``pin.centerOfMass`` on random states (tests/test_com.py).
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
    an insect leg to silo4kin.insect_mass.insect_leg_mass_moment_in_base)."""
    return leg_family.family_of(leg).mass_moment_in_base(leg, q)


def center_of_mass_closed_form(robot, q: np.ndarray) -> np.ndarray:
    """Whole-robot CoM in the base frame (the URDF root) [m], shape (N, 3).

    Args:
        robot: a silo4kin Robot (legs, body mass and body CoM, total mass).
        q: joint values in our order [rad], shape (N, 12) (or (12,), giving (1, 3)).
    """
    q = np.atleast_2d(np.asarray(q, dtype=float))
    moment = robot.body_mass * np.asarray(robot.position_body_com_in_base, dtype=float) + np.zeros(
        (q.shape[0], 3)
    )
    for k, leg in enumerate(robot.legs):
        moment += leg_mass_moment_in_base(leg, q[:, 3 * k : 3 * k + 3])
    return moment / robot.total_mass


def legs_com_offset(legs: tuple[LegGeometry, ...], q: np.ndarray, total_mass: float) -> np.ndarray:
    """Σ over legs of m_i c_i / M [m], (N, 3): the whole-robot CoM measured from the body CoM
    when the legs' hips are given relative to the body CoM (the planning frame) and the
    body CoM is the frame's origin. ``q`` (N, 12) [rad], ``total_mass`` M [kg]."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    moment = np.zeros((q.shape[0], 3))
    for k, leg in enumerate(legs):
        moment += leg_mass_moment_in_base(leg, q[:, 3 * k : 3 * k + 3])
    return moment / total_mass
