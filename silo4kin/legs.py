"""One interface to the leg families: insect (kinematics.py) and mammal (mammal.py).

The planner, the torques and the reachable-set workspace call these functions with whatever
leg a robot has; each asks the leg's :class:`~silo4kin.leg_family.LegFamily` for its closed
form. Shapes and units are those of the family modules: q (N, 3) [rad], positions in the base
frame (N, 3) [m], Jacobians (N, 3, 3) [m/rad]. ``LEG_NAMES`` is the one leg order.
"""

from __future__ import annotations

import numpy as np

from . import kinematics
from .geometry import LEG_NAMES, LegGeometry
from .leg_family import INSECT, MAMMAL, LegFamily, family_of
from .mammal import MammalLegGeometry

#: Any leg a loaded Robot can have.
AnyLeg = LegGeometry | MammalLegGeometry

__all__ = [
    "INSECT",
    "LEG_NAMES",
    "MAMMAL",
    "AnyLeg",
    "LegFamily",
    "family_of",
    "forward_kinematics",
    "inverse_kinematics",
    "jacobian",
    "jacobian_derivative_times_velocity",
    "joint_motion",
]


def forward_kinematics(leg: AnyLeg, q: np.ndarray) -> np.ndarray:
    """Foot position in the base frame [m], (..., 3)."""
    return family_of(leg).forward_kinematics(leg, q)


def jacobian(leg: AnyLeg, q: np.ndarray) -> np.ndarray:
    """∂p_foot/∂q in the base frame [m/rad], (..., 3, 3)."""
    return family_of(leg).jacobian(leg, q)


def jacobian_derivative_times_velocity(leg: AnyLeg, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """J̇ q̇ [m/s²], (..., 3)."""
    return family_of(leg).jacobian_derivative_times_velocity(leg, q, qd)


def inverse_kinematics(leg: AnyLeg, position_foot_in_base: np.ndarray) -> kinematics.IKResult:
    """The family's standing branch (insect: knee-down; mammal: the rest pose's branch).

    Joint limits are not applied (callers check them); unreachable targets give NaN.
    """
    return family_of(leg).inverse_kinematics(leg, position_foot_in_base)


def joint_motion(
    leg: AnyLeg,
    position_foot_in_base: np.ndarray,
    velocity_foot_in_base: np.ndarray,
    acceleration_foot_in_base: np.ndarray,
) -> kinematics.JointMotion:
    """q = IK(p), q̇ = J⁻¹ṗ, q̈ = J⁻¹(p̈ - J̇q̇) for (N, 3) stacks of foot states."""
    return family_of(leg).joint_motion(
        leg, position_foot_in_base, velocity_foot_in_base, acceleration_foot_in_base
    )
