"""One interface to the leg families: insect (kinematics.py) and mammal (mammal.py).

The planner, the torques and the reachable-set workspace call these functions with whatever
leg a robot has; each dispatches on the leg's geometry type to that family's closed form.
Shapes and units are those of the family modules: q (N, 3) [rad], positions in the base
frame (N, 3) [m], Jacobians (N, 3, 3) [m/rad].
"""

from __future__ import annotations

import numpy as np

from . import kinematics, mammal
from .geometry import LegGeometry
from .mammal import MammalLegGeometry

#: Any leg a loaded Robot can have.
AnyLeg = LegGeometry | MammalLegGeometry


def family(leg: AnyLeg) -> str:
    """``"insect"`` or ``"mammal"``."""
    return "mammal" if isinstance(leg, MammalLegGeometry) else "insect"


def forward_kinematics(leg: AnyLeg, q: np.ndarray) -> np.ndarray:
    """Foot position in the base frame [m], (..., 3)."""
    if isinstance(leg, MammalLegGeometry):
        return mammal.forward_kinematics(leg, q)
    return kinematics.forward_kinematics(leg, q)


def jacobian(leg: AnyLeg, q: np.ndarray) -> np.ndarray:
    """∂p_foot/∂q in the base frame [m/rad], (..., 3, 3)."""
    if isinstance(leg, MammalLegGeometry):
        return mammal.jacobian(leg, q)
    return kinematics.jacobian(leg, q)


def jacobian_derivative_times_velocity(leg: AnyLeg, q: np.ndarray, qd: np.ndarray
                                       ) -> np.ndarray:
    """J̇ q̇ [m/s²], (..., 3)."""
    if isinstance(leg, MammalLegGeometry):
        return mammal.jacobian_derivative_times_velocity(leg, q, qd)
    return np.einsum("...ij,...j->...i", kinematics.jacobian_derivative(leg, q, qd), qd)


def inverse_kinematics(leg: AnyLeg, position_foot_in_base: np.ndarray) -> kinematics.IKResult:
    """The family's standing branch (insect: knee-down; mammal: the rest pose's branch).

    Joint limits are not applied (callers check them); unreachable targets give NaN.
    """
    if isinstance(leg, MammalLegGeometry):
        ik = mammal.inverse_kinematics(leg, position_foot_in_base)
        return kinematics.IKResult(ik.q, ik.reachable)
    return kinematics.inverse_kinematics_masked(leg, position_foot_in_base)


def joint_motion(leg: AnyLeg, position_foot_in_base: np.ndarray,
                 velocity_foot_in_base: np.ndarray, acceleration_foot_in_base: np.ndarray
                 ) -> kinematics.JointMotion:
    """q = IK(p), q̇ = J⁻¹ṗ, q̈ = J⁻¹(p̈ - J̇q̇) for (N, 3) stacks of foot states."""
    if isinstance(leg, MammalLegGeometry):
        return kinematics.JointMotion(*mammal.joint_motion(
            leg, position_foot_in_base, velocity_foot_in_base, acceleration_foot_in_base))
    return kinematics.joint_motion(leg, position_foot_in_base, velocity_foot_in_base,
                                   acceleration_foot_in_base)
