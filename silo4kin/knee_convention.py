"""Which URDF knee values bend an insect leg's knee down (thesis knee-down: DH θ3 in (-π, 0))."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .geometry import LegGeometry
from .leg_chains import NotInsectLegError


@dataclass(frozen=True)
class KneeConvention:
    """Which URDF knee values bend the knee down (thesis knee-down: DH θ3 in (-π, 0)).

    Attributes:
        q_straight: URDF knee value where the tibia is in line with the femur (θ3 = 0) [rad].
        knee_down_sign: +1 or -1: knee-down ⇔ knee_down_sign * (q3 - q_straight) in (0, π).
        q_knee_down: the part of the knee's limits that is knee-down, URDF values [rad], (2,).
    """

    q_straight: float
    knee_down_sign: int
    q_knee_down: np.ndarray


def knee_convention(leg: LegGeometry) -> KneeConvention:
    """Knee-down direction of one leg's URDF knee; refuses a knee that cannot bend down."""
    s = float(leg.axis_sign[2])
    q_straight = float(leg.dh_to_joint(np.zeros(3))[2])
    lo = max(float(leg.theta_lower[2]), -np.pi)
    hi = min(float(leg.theta_upper[2]), 0.0)
    if hi <= lo:
        raise NotInsectLegError(
            f"{leg.name} chain: knee {leg.joint_names[2]!r} limits [{leg.q_lower[2]:.4g}, "
            f"{leg.q_upper[2]:.4g}] rad allow no knee-down pose (DH θ3 in (-π, 0), reached for "
            f"{'q3 < ' if s > 0 else 'q3 > '}{q_straight:.4g} rad)",
            leg.name,
        )
    q = np.sort(leg.dh_to_joint(np.array([[0.0, 0.0, lo], [0.0, 0.0, hi]]))[:, 2])
    return KneeConvention(q_straight=q_straight, knee_down_sign=int(-s), q_knee_down=q)
