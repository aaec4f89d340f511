"""A mammal leg's geometry (silo4kin/mammal_geometry.py) read from a fixed-base Pinocchio model
at q = 0, checked against the family's assumptions (HAA along x, parallel pitch axes
perpendicular to x, thigh and shank of non-zero length); the rest pose picks the knee
branch and the foot's side of the HAA axis (silo4kin/mammal.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pinocchio as pin

from .errors import RobotDescriptionError
from .mammal import branch_of, foot_side_of
from .mammal_geometry import MammalLegGeometry

#: Cosine tolerance on "axis along x / perpendicular / parallel" (as geometry.AXIS_TOLERANCE).
AXIS_TOLERANCE = 1e-6
#: Lengths below this are zero [m].
LENGTH_TOLERANCE = 1e-9


def extract_mammal_leg_geometry(
    model: pin.Model,
    name: str,
    joint_names: tuple[str, str, str],
    foot_frame: str,
    q_rest: np.ndarray | None = None,
) -> MammalLegGeometry:
    """Build a :class:`MammalLegGeometry` from a fixed-base Pinocchio model at q = 0.

    Args:
        model: fixed-base model whose root is the base frame (REP-103).
        name: leg name; joint_names: (HAA, HFE, KFE) URDF names; foot_frame: the foot frame.
        q_rest: the leg's rest (standing) joint values [rad] (3,), which pick the knee branch;
            default the middle of the joint limits.

    Raises:
        RobotDescriptionError: the chain is not a mammal leg (first axis not along x, pitch
            axes not parallel or not perpendicular to x, zero-length thigh or shank).
    """
    jids = [model.getJointId(jn) for jn in joint_names]
    data = model.createData()
    q0 = pin.neutral(model)
    pin.framesForwardKinematics(model, data, q0)
    pin.computeJointJacobians(model, data, q0)
    points = [data.oMi[j].translation.copy() for j in jids]
    foot = data.oMf[model.getFrameId(foot_frame)].translation.copy()
    axes = [data.J[3:, model.joints[j].idx_v].copy() for j in jids]
    x_hat = np.array([1.0, 0.0, 0.0])
    if abs(abs(axes[0] @ x_hat) - 1.0) > AXIS_TOLERANCE:
        raise RobotDescriptionError(
            f"leg {name}: first joint {joint_names[0]!r} axis {np.round(axes[0], 6).tolist()} is "
            "not along the body's x axis (hip ab/adduction of a mammal leg)"
        )
    e_a = axes[1] / np.linalg.norm(axes[1])
    if abs(e_a @ x_hat) > AXIS_TOLERANCE:
        raise RobotDescriptionError(
            f"leg {name}: hip flexion {joint_names[1]!r} axis {np.round(e_a, 6).tolist()} is not "
            "perpendicular to the body's x axis"
        )
    knee_cos = float(axes[2] @ e_a)
    if abs(abs(knee_cos) - 1.0) > AXIS_TOLERANCE:
        raise RobotDescriptionError(
            f"leg {name}: knee {joint_names[2]!r} axis {np.round(axes[2], 6).tolist()} is not "
            f"parallel to the hip flexion axis {np.round(e_a, 6).tolist()}"
        )
    e_n = np.cross(x_hat, e_a)

    def planar(v: np.ndarray) -> np.ndarray:
        return np.array([v @ x_hat, v @ e_n])

    thigh, shank = planar(points[2] - points[1]), planar(foot - points[2])
    for vec, what in ((thigh, "thigh (hip flexion to knee)"), (shank, "shank (knee to foot)")):
        if np.linalg.norm(vec) < LENGTH_TOLERANCE:
            raise RobotDescriptionError(f"leg {name}: the {what} has zero length in the leg plane")
    idx_q = [model.joints[j].idx_q for j in jids]
    q_lower = model.lowerPositionLimit[idx_q].copy()
    q_upper = model.upperPositionLimit[idx_q].copy()
    rest = 0.5 * (q_lower + q_upper) if q_rest is None else np.asarray(q_rest, dtype=float)
    leg = MammalLegGeometry(
        name=name,
        joint_names=tuple(joint_names),  # type: ignore[arg-type]
        foot_frame=foot_frame,
        position_hip_in_base=points[0],
        axis_pitch_in_base=e_a,
        abduction_sign=float(np.sign(axes[0] @ x_hat)),
        knee_sign=float(np.sign(knee_cos)),
        lateral_offset=float(e_a @ (foot - points[0])),
        offset_pitch_in_plane=planar(points[1] - points[0]),
        thigh_in_plane=thigh,
        shank_in_plane=shank,
        q_lower=q_lower,
        q_upper=q_upper,
        knee_branch=1,
        foot_below_sign=-1.0,
        position_pitch_in_base=points[1],
        position_knee_in_base=points[2],
        link_masses=np.array([model.inertias[j].mass for j in jids]),
        link_coms_at_zero=np.array([data.oMi[j].act(model.inertias[j].lever) for j in jids]),
        axis_misalignment_rad=float(
            max(
                np.linalg.norm(np.cross(axes[0], x_hat)),
                abs(e_a @ x_hat),
                np.linalg.norm(np.cross(axes[2], e_a)) / np.linalg.norm(axes[2]),
            )
        ),
    )
    # the rest pose picks the knee branch and the side of the HAA axis the foot is on
    return replace(
        leg,
        knee_branch=int(branch_of(leg, rest[2])),
        foot_below_sign=float(foot_side_of(leg, rest)),
    )
