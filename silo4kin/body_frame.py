"""The body's CoG, the static-stability point (thesis §5.1), and the legs measured from it
(the planner's frame B sits at the body CoG; a URDF's root frame need not)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .errors import RobotDescriptionError
from .geometry import LegGeometry
from .leg_family import family_of


def body_com(model: pin.Model) -> tuple[float, np.ndarray]:
    """Mass [kg] and CoG in the base frame [m, (3,)] of the body alone.

    The body is the root link with every link fixed to it (Pinocchio merges them into the
    root's inertia: a sensor mast counts, the legs do not). Raises if the body has no mass.
    """
    inertia = model.inertias[0]
    if inertia.mass <= 0.0:
        raise RobotDescriptionError(
            f"the body (root link {model.frames[1].name!r} and its fixed children) has no mass; "
            "its CoG is the static-stability point, so give the root link an <inertial>"
        )
    return float(inertia.mass), np.array(inertia.lever)


def hip_depth_below_com(leg: LegGeometry, position_body_com_in_base: np.ndarray) -> float:
    """Lz: how far the hip axis sits below the body CoG [m] (thesis Table 3.1: 0.15 m)."""
    return float(position_body_com_in_base[2] - leg.position_hip_in_base[2])


def legs_in_body_com_frame(
    legs: tuple[LegGeometry, ...], position_body_com_in_base: np.ndarray
) -> tuple[LegGeometry, ...]:
    """The same legs with hip positions measured from the body CoG (axes unchanged).

    The planner's frame B sits at the CoG (docs/design.md); a URDF's root frame need not (mantis:
    4.5 cm behind and 4.2 cm below it). Only ``position_hip_in_base`` changes, so FK/IK of
    these legs give foot positions relative to the CoG; joint values, Jacobians and dynamics
    are unchanged. To draw the robot, place the URDF root at
    ``position_com_in_world - R_world_base @ position_body_com_in_base``.

    Mammal legs (mammal.MammalLegGeometry) also carry their pitch and knee points and link
    CMs at q = 0 in the base frame; those move by the same offset.
    """
    com = np.asarray(position_body_com_in_base, dtype=float)
    return tuple(family_of(leg).moved_by(leg, com) for leg in legs)
