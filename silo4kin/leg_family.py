"""The leg families as objects: what differs between an insect leg and a mammal leg.

A robot's legs are all of one family (silo4kin.discovery decides from the first joint axis):

- insect (the thesis's, :class:`LegGeometry`): hip yaw about the vertical, then two pitches;
  closed form in kinematics.py, knee-down IK;
- mammal (:class:`MammalLegGeometry`): hip ab/adduction about x, then two pitches; closed
  form in mammal.py, the IK branch of the rest pose.

Code that must behave differently per family asks the leg's :class:`LegFamily`
(:func:`family_of`) instead of comparing names. ``Robot.family`` stays the family's name
(a string) for outputs and users.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Protocol

import numpy as np

from . import insect_mass, kinematics, mammal
from .geometry import LegGeometry
from .mammal import MammalLegGeometry


class LegFamily(Protocol):
    """What a leg family provides (shapes: q (N, 3) [rad], positions in B (N, 3) [m]).

    Attributes:
        name: "insect" or "mammal" (Robot.family, the outputs).
        has_hip_yaw: whether the first joint turns the leg about the vertical (then the
            thesis's square workspace and a hip-yaw reserve apply).
    """

    name: str
    has_hip_yaw: bool

    def forward_kinematics(self, leg: Any, q: np.ndarray) -> np.ndarray:
        """Foot position in B [m], (..., 3)."""

    def jacobian(self, leg: Any, q: np.ndarray) -> np.ndarray:
        """∂p_foot/∂q in B [m/rad], (..., 3, 3)."""

    def jacobian_derivative_times_velocity(
        self, leg: Any, q: np.ndarray, qd: np.ndarray
    ) -> np.ndarray:
        """J̇ q̇ [m/s²], (..., 3)."""

    def inverse_kinematics(
        self, leg: Any, position_foot_in_base: np.ndarray
    ) -> kinematics.IKResult:
        """The standing branch; no joint limits applied; NaN where out of reach."""

    def joint_motion(
        self,
        leg: Any,
        position_foot_in_base: np.ndarray,
        velocity_foot_in_base: np.ndarray,
        acceleration_foot_in_base: np.ndarray,
    ) -> kinematics.JointMotion:
        """q, q̇, q̈ for (N, 3) stacks of foot states."""

    def mass(self, leg: Any) -> float:
        """Mass of the leg's three links [kg]."""

    def mass_moment_in_base(self, leg: Any, q: np.ndarray) -> np.ndarray:
        """Σ m_i c_i over the leg's links in B [kg m], (N, 3)."""

    def moved_by(self, leg: Any, offset_in_base: np.ndarray) -> Any:
        """The leg with every point it stores in B moved by ``-offset_in_base`` (3,) [m]:
        the same leg measured from a base origin at ``offset_in_base``."""

    def highest_body_height_m(self, leg: Any) -> float:
        """Hip depth below the base origin plus the longest reach below the hip [m]: no
        body height above it can stand on this leg."""


class InsectFamily:
    """Insect legs: silo4kin.kinematics (knee-down) and silo4kin.com's closed form."""

    name = "insect"
    has_hip_yaw = True

    def forward_kinematics(self, leg: LegGeometry, q: np.ndarray) -> np.ndarray:
        return kinematics.forward_kinematics(leg, q)

    def jacobian(self, leg: LegGeometry, q: np.ndarray) -> np.ndarray:
        return kinematics.jacobian(leg, q)

    def jacobian_derivative_times_velocity(
        self, leg: LegGeometry, q: np.ndarray, qd: np.ndarray
    ) -> np.ndarray:
        return np.einsum("...ij,...j->...i", kinematics.jacobian_derivative(leg, q, qd), qd)

    def inverse_kinematics(
        self, leg: LegGeometry, position_foot_in_base: np.ndarray
    ) -> kinematics.IKResult:
        return kinematics.inverse_kinematics_masked(leg, position_foot_in_base)

    def joint_motion(
        self,
        leg: LegGeometry,
        position_foot_in_base: np.ndarray,
        velocity_foot_in_base: np.ndarray,
        acceleration_foot_in_base: np.ndarray,
    ) -> kinematics.JointMotion:
        return kinematics.joint_motion(
            leg, position_foot_in_base, velocity_foot_in_base, acceleration_foot_in_base
        )

    def mass(self, leg: LegGeometry) -> float:
        return float(sum(link.mass for link in leg.links))

    def mass_moment_in_base(self, leg: LegGeometry, q: np.ndarray) -> np.ndarray:
        return insect_mass.insect_leg_mass_moment_in_base(leg, q)

    def moved_by(self, leg: LegGeometry, offset_in_base: np.ndarray) -> LegGeometry:
        return replace(leg, position_hip_in_base=leg.position_hip_in_base - offset_in_base)

    def highest_body_height_m(self, leg: LegGeometry) -> float:
        return -leg.hip_height + leg.L2 + leg.L3


class MammalFamily:
    """Mammal legs: silo4kin.mammal (the rest pose's IK branch)."""

    name = "mammal"
    has_hip_yaw = False

    def forward_kinematics(self, leg: MammalLegGeometry, q: np.ndarray) -> np.ndarray:
        return mammal.forward_kinematics(leg, q)

    def jacobian(self, leg: MammalLegGeometry, q: np.ndarray) -> np.ndarray:
        return mammal.jacobian(leg, q)

    def jacobian_derivative_times_velocity(
        self, leg: MammalLegGeometry, q: np.ndarray, qd: np.ndarray
    ) -> np.ndarray:
        return mammal.jacobian_derivative_times_velocity(leg, q, qd)

    def inverse_kinematics(
        self, leg: MammalLegGeometry, position_foot_in_base: np.ndarray
    ) -> kinematics.IKResult:
        ik = mammal.inverse_kinematics(leg, position_foot_in_base)
        return kinematics.IKResult(ik.q, ik.reachable)

    def joint_motion(
        self,
        leg: MammalLegGeometry,
        position_foot_in_base: np.ndarray,
        velocity_foot_in_base: np.ndarray,
        acceleration_foot_in_base: np.ndarray,
    ) -> kinematics.JointMotion:
        return kinematics.JointMotion(
            *mammal.joint_motion(
                leg, position_foot_in_base, velocity_foot_in_base, acceleration_foot_in_base
            )
        )

    def mass(self, leg: MammalLegGeometry) -> float:
        return float(np.sum(leg.link_masses))

    def mass_moment_in_base(self, leg: MammalLegGeometry, q: np.ndarray) -> np.ndarray:
        return mammal.leg_mass_moment_in_base(leg, q)

    def moved_by(self, leg: MammalLegGeometry, offset_in_base: np.ndarray) -> MammalLegGeometry:
        return replace(
            leg,
            position_hip_in_base=leg.position_hip_in_base - offset_in_base,
            position_pitch_in_base=leg.position_pitch_in_base - offset_in_base,
            position_knee_in_base=leg.position_knee_in_base - offset_in_base,
            link_coms_at_zero=leg.link_coms_at_zero - offset_in_base,
        )

    def highest_body_height_m(self, leg: MammalLegGeometry) -> float:
        return -float(leg.position_hip_in_base[2]) + 0.0 + leg.size_m


INSECT: LegFamily = InsectFamily()
MAMMAL: LegFamily = MammalFamily()
#: The families by name (Robot.family).
FAMILIES: dict[str, LegFamily] = {INSECT.name: INSECT, MAMMAL.name: MAMMAL}


def family_of(leg: Any) -> LegFamily:
    """The :class:`LegFamily` of a leg geometry (by its type)."""
    return MAMMAL if isinstance(leg, MammalLegGeometry) else INSECT
