"""Leg geometry in the thesis's DH convention, extracted from a loaded Pinocchio model.

The closed form (kinematics.py, dynamics.py) never repeats a robot number: everything it uses
comes from a :class:`LegGeometry` built here from the model's joint placements, axes, limits
and inertias at q = 0. Change a xacro argument or the URDF and both the closed form and
Pinocchio change together.

DH convention (thesis Table 3.1, mapped to REP-103, docs/notation.md): for one leg

    position_foot_in_base = position_hip_in_base
        + Rz(theta_b + theta1) @ [L1 + L2 cos(theta2) + L3 cos(theta2 + theta3),
                                  0,
                                  L2 sin(theta2) + L3 sin(theta2 + theta3)]        (eq 3.5)

URDF joint values q relate to the DH angles by ``theta = axis_sign * q + zero_offset``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from .errors import RobotDescriptionError
from .shapes import DEFAULT_TIBIA_RADIUS_M

#: Leg names in array order (thesis legs 1, 2, 3, 4).
LEG_NAMES: tuple[str, ...] = ("LF", "RF", "LH", "RH")

#: Tolerance on "is this axis vertical / horizontal / parallel" [dimensionless, cosine].
#: URDF origins are printed with ~1e-9 relative precision by xacro; 1e-6 is far above that
#: and far below any real design deviation.
AXIS_TOLERANCE = 1e-6
#: Tolerance on geometric coincidences, e.g. hip-pitch joint at the hip-yaw height [m].
LENGTH_TOLERANCE = 1e-9


@dataclass(frozen=True)
class LinkInertia:
    """Inertial data of one leg link in its DH link frame.

    The DH link frame has x along the link (joint to next joint), y along the joint axis of
    the link's own joint as it turns positively in DH terms (for the coxa: z up, y = z × x),
    origin at the link's joint.

    Attributes:
        mass: link mass [kg].
        com: centre of mass in the DH link frame [m], shape (3,).
        inertia: inertia tensor about the CM, in the DH link frame [kg m^2], shape (3, 3).
    """

    mass: float
    com: np.ndarray
    inertia: np.ndarray


@dataclass(frozen=True)
class LegGeometry:
    """Everything the closed form needs about one insect leg.

    Attributes:
        name: leg name, e.g. "LF".
        joint_names: URDF names of (hip yaw, hip pitch, knee) joints.
        foot_frame: name of the frame at the foot tip.
        position_hip_in_base: hip-yaw joint position in the base frame [m], shape (3,).
        theta_b: leg rest direction at theta1 = 0, yaw in the base frame [rad] (thesis θb - π/2).
        L1: coxa length, hip-yaw axis to hip-pitch axis [m].
        L2: femur length [m].
        L3: tibia length, knee axis to foot tip [m].
        axis_sign: DH angle sign per joint, shape (3,): theta = axis_sign * q + zero_offset.
        zero_offset: DH angle at q = 0 per joint [rad], shape (3,).
        q_lower: lower joint limits, URDF values [rad], shape (3,).
        q_upper: upper joint limits, URDF values [rad], shape (3,).
        links: inertial data of (coxa, femur, tibia) in DH link frames.
        tibia_radius_m: radius of the tibia's round collision (or visual) shape [m]
            (silo4kin.shapes.tibia_radii_m; load_robot sets it from the URDF), the capsule
            the planner's clearance rule and the physics replay both use.
    """

    name: str
    joint_names: tuple[str, str, str]
    foot_frame: str
    position_hip_in_base: np.ndarray
    theta_b: float
    L1: float
    L2: float
    L3: float
    axis_sign: np.ndarray
    zero_offset: np.ndarray
    q_lower: np.ndarray
    q_upper: np.ndarray
    links: tuple[LinkInertia, LinkInertia, LinkInertia]
    tibia_radius_m: float = DEFAULT_TIBIA_RADIUS_M
    #: results computed from this leg (and the legs it is planned with): silo4kin.memo
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    @property
    def hip_height(self) -> float:
        """Height of the hip axis above the base origin [m] (thesis -Lz)."""
        return float(self.position_hip_in_base[2])

    @property
    def reach(self) -> tuple[float, float]:
        """(min, max) distance from the hip-pitch axis to the foot [m]."""
        return abs(self.L2 - self.L3), self.L2 + self.L3

    @property
    def theta_lower(self) -> np.ndarray:
        """Lower joint limits as DH angles [rad], shape (3,)."""
        a = self.axis_sign * self.q_lower + self.zero_offset
        b = self.axis_sign * self.q_upper + self.zero_offset
        return np.minimum(a, b)

    @property
    def theta_upper(self) -> np.ndarray:
        """Upper joint limits as DH angles [rad], shape (3,)."""
        a = self.axis_sign * self.q_lower + self.zero_offset
        b = self.axis_sign * self.q_upper + self.zero_offset
        return np.maximum(a, b)

    def joint_to_dh(self, q: np.ndarray) -> np.ndarray:
        """URDF joint values (..., 3) [rad] -> DH angles (..., 3) [rad]."""
        return self.axis_sign * np.asarray(q, dtype=float) + self.zero_offset

    def dh_to_joint(self, theta: np.ndarray) -> np.ndarray:
        """DH angles (..., 3) [rad] -> URDF joint values (..., 3) [rad]."""
        return (np.asarray(theta, dtype=float) - self.zero_offset) * self.axis_sign


def _unit(v: np.ndarray) -> np.ndarray:
    n = float(np.linalg.norm(v))
    if n < LENGTH_TOLERANCE:
        raise RobotDescriptionError(f"zero-length vector {v.tolist()} where a link was expected")
    return v / n


def extract_leg_geometry(
    model: pin.Model, name: str, joint_names: tuple[str, str, str], foot_frame: str
) -> LegGeometry:
    """Build a :class:`LegGeometry` from a fixed-base Pinocchio model at q = 0.

    Args:
        model: fixed-base model whose root is the body (base) frame.
        name: leg name.
        joint_names: URDF names of the hip-yaw, hip-pitch and knee joints.
        foot_frame: name of the foot-tip frame.

    Raises:
        RobotDescriptionError: a joint or frame is missing, or the chain is not an insect
            leg (vertical first axis, two horizontal parallel axes, links in one plane).
    """
    for jn in joint_names:
        if not model.existJointName(jn):
            raise RobotDescriptionError(f"leg {name}: joint {jn!r} not found in the model")
    if not model.existFrame(foot_frame):
        raise RobotDescriptionError(f"leg {name}: foot frame {foot_frame!r} not found")
    jids = [model.getJointId(jn) for jn in joint_names]
    for jid, jn in zip(jids, joint_names):
        if model.nqs[jid] != 1 or model.nvs[jid] != 1:
            raise RobotDescriptionError(
                f"leg {name}: joint {jn!r} is not a 1-dof revolute joint "
                f"({model.joints[jid].shortname()})"
            )
    if model.parents[jids[1]] != jids[0] or model.parents[jids[2]] != jids[1]:
        raise RobotDescriptionError(f"leg {name}: joints {joint_names} are not one serial chain")

    data = model.createData()
    q0 = pin.neutral(model)
    pin.framesForwardKinematics(model, data, q0)
    pin.computeJointJacobians(model, data, q0)
    fid = model.getFrameId(foot_frame)
    if model.frames[fid].parentJoint != jids[2]:
        raise RobotDescriptionError(
            f"leg {name}: foot frame {foot_frame!r} is not carried by knee joint {joint_names[2]!r}"
        )

    positions = [data.oMi[j].translation.copy() for j in jids]
    position_foot = data.oMf[fid].translation.copy()
    axes = [data.J[3:, model.joints[j].idx_v].copy() for j in jids]  # world = base (fixed base)

    z = np.array([0.0, 0.0, 1.0])
    if abs(abs(axes[0] @ z) - 1.0) > AXIS_TOLERANCE:
        raise RobotDescriptionError(
            f"leg {name}: first joint {joint_names[0]!r} axis {np.round(axes[0], 6).tolist()} "
            "is not vertical: this is not an insect leg (hip ab/adduction leg?)"
        )
    # A URDF may put a joint's origin anywhere on its axis (a yaw motor mounted above the
    # coxa, a femur origin beside it): the DH points are where the axes meet the leg plane.
    # hip: the yaw axis at the pitch axis's height; pitch and knee points: their axes'
    # intersections with the vertical plane through the yaw axis normal to the pitch axis.
    # For origins already in the plane (SILO4) these are the joint origins themselves.
    if abs(axes[1] @ z) > AXIS_TOLERANCE:
        raise RobotDescriptionError(
            f"leg {name}: joint {joint_names[1]!r} axis {np.round(axes[1], 6).tolist()} "
            "is not horizontal"
        )
    positions[0] = positions[0] + ((positions[1] - positions[0]) @ z) * z
    normal = _unit(axes[1] - (axes[1] @ z) * z)
    for k in (1, 2):
        positions[k] = positions[k] - ((positions[k] - positions[0]) @ normal) * normal
    coxa = positions[1] - positions[0]
    if np.linalg.norm(coxa) < LENGTH_TOLERANCE:
        raise RobotDescriptionError(
            f"leg {name}: the hip pitch axis crosses the hip yaw axis (no coxa, L1 = 0); "
            "the DH model (Table 3.1) needs L1 > 0"
        )
    radial = _unit(coxa)
    theta_b = float(np.arctan2(radial[1], radial[0]))
    # DH pitch axis: rotating positively about it lifts the radial direction: -(z x radial).
    pitch_axis = -np.cross(z, radial)
    axis_sign = np.empty(3)
    axis_sign[0] = np.sign(axes[0] @ z)
    for k in (1, 2):
        c = axes[k] @ pitch_axis
        if abs(abs(c) - 1.0) > AXIS_TOLERANCE:
            raise RobotDescriptionError(
                f"leg {name}: joint {joint_names[k]!r} axis {np.round(axes[k], 6).tolist()} "
                f"is not horizontal and perpendicular to the coxa (expected ±"
                f"{np.round(pitch_axis, 6).tolist()})"
            )
        axis_sign[k] = np.sign(c)

    femur = positions[2] - positions[1]
    tibia = position_foot - positions[2]
    if abs(tibia @ pitch_axis) > LENGTH_TOLERANCE:
        raise RobotDescriptionError(
            f"leg {name}: foot frame {foot_frame!r} leaves the leg plane by "
            f"{tibia @ pitch_axis:.3g} m"
        )
    # In-plane angles at q = 0, measured like DH theta (positive = up from radial).
    angle_femur = float(np.arctan2(femur @ z, femur @ radial))
    angle_tibia = float(np.arctan2(tibia @ z, tibia @ radial))
    zero_offset = np.array([0.0, angle_femur, angle_tibia - angle_femur])
    zero_offset[2] = float(np.arctan2(np.sin(zero_offset[2]), np.cos(zero_offset[2])))

    # Link inertias in the DH link frames at q = 0.
    links = []
    link_dirs = (radial, _unit(femur), _unit(tibia))
    link_y = (np.cross(z, radial), pitch_axis, pitch_axis)
    for jid, x_axis, y_axis, jpos in zip(jids, link_dirs, link_y, positions):
        rotation_link_in_base = np.column_stack([x_axis, y_axis, np.cross(x_axis, y_axis)])
        rotation_joint_in_base = data.oMi[jid].rotation
        inertia = model.inertias[jid]
        com_in_base = rotation_joint_in_base @ inertia.lever + data.oMi[jid].translation
        r = rotation_link_in_base.T @ rotation_joint_in_base
        links.append(
            LinkInertia(
                mass=float(inertia.mass),
                com=rotation_link_in_base.T @ (com_in_base - jpos),
                inertia=r @ inertia.inertia @ r.T,
            )
        )

    idx_q = [model.joints[j].idx_q for j in jids]
    return LegGeometry(
        name=name,
        joint_names=tuple(joint_names),  # type: ignore[arg-type]
        foot_frame=foot_frame,
        position_hip_in_base=positions[0],
        theta_b=theta_b,
        L1=float(np.linalg.norm(coxa)),
        L2=float(np.linalg.norm(femur)),
        L3=float(np.linalg.norm(tibia)),
        axis_sign=axis_sign,
        zero_offset=zero_offset,
        q_lower=model.lowerPositionLimit[idx_q].copy(),
        q_upper=model.upperPositionLimit[idx_q].copy(),
        links=(links[0], links[1], links[2]),
    )
