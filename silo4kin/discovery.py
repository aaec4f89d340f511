"""Find the four insect legs of a quadruped in a loaded model, with no names assumed.

An insect-leg quadruped (thesis §2.1, Fig 3.1) is, in the fixed-base Pinocchio model:

* exactly four kinematic chains from the body (the root link and its fixed children) to a leaf,
  each with exactly three 1-dof revolute joints with finite limits, and no other moving joint;
* per chain: the first joint axis vertical in the base frame (hip yaw, θ1), the second and
  third horizontal and parallel (hip pitch θ2, knee θ3), perpendicular to the coxa, and the
  knee and the foot tip in the vertical leg plane through the hip (the DH chain of Table 3.1);
* a foot frame: the deepest fixed child link of the knee's link (the tip).

The chains and their names come from silo4kin/leg_chains.py; this module checks each
family's axes and returns the legs in the thesis order LF, RF, LH, RH (legs 1-4). Whatever
breaks an assumption raises :class:`NotInsectLegError` naming the chain, the joint and the
assumption. ``geometry.extract_leg_geometry`` then derives the numbers and re-validates.
Everything in this module reads the model at q = 0 (the URDF's reference pose).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .body_frame import hip_depth_below_com
from .geometry import AXIS_TOLERANCE, LEG_NAMES, LENGTH_TOLERANCE, LegGeometry
from .knee_convention import knee_convention
from .leg_chains import (
    LegNames,
    NotInsectLegError,
    foot_frame,
    joint_axis_in_base,
    named_leg_chains,
    rounded,
)

__all__ = [
    "INSECT",
    "MAMMAL",
    "NotInsectLegError",
    "discover_legs",
    "discover_mammal_legs",
    "format_discovery",
    "leg_family",
]


def discover_legs(model: pin.Model) -> LegNames:
    """The four insect legs of a fixed-base model, in the thesis order LF, RF, LH, RH.

    Args:
        model: fixed-base Pinocchio model; its root frame is the base frame B (REP-103).

    Returns:
        {leg name: ((hip-yaw joint, hip-pitch joint, knee joint), foot frame)}.

    Raises:
        NotInsectLegError: not four chains of three limited revolute joints, a chain whose
            axes or geometry break the insect-leg assumptions, or hips that do not sit one per
            body corner.
    """
    by_name, data = named_leg_chains(model)
    legs: LegNames = {}
    for name in LEG_NAMES:
        chain = by_name[name]
        _check_axes(model, data, name, chain)
        foot = foot_frame(model, chain[2], name)
        _check_leg_plane(model, data, name, chain, foot)
        legs[name] = (tuple(model.names[j] for j in chain), foot)
    return legs


#: Leg families recognised from the geometry (docs/robots.md).
INSECT = "insect"
MAMMAL = "mammal"


def leg_family(model: pin.Model) -> str:
    """``"mammal"`` when the LF leg's first joint axis is the body's x axis, else ``"insect"``.

    Only the first axis decides; :func:`discover_legs` / :func:`discover_mammal_legs` then
    check every leg against the family's assumptions and refuse with the broken one.
    """
    by_name, data = named_leg_chains(model)
    first = joint_axis_in_base(model, data, by_name["LF"][0])
    return MAMMAL if abs(abs(first[0]) - 1.0) <= AXIS_TOLERANCE else INSECT


def discover_mammal_legs(model: pin.Model) -> LegNames:
    """The four mammal legs of a fixed-base model, in the order LF, RF, LH, RH.

    A mammal leg: hip ab/adduction about the body's x axis, then hip flexion and knee about
    parallel axes perpendicular to x (Solo12, Go2, ANYmal, HyQ...).

    Returns:
        {leg name: ((HAA joint, HFE joint, KFE joint), foot frame)}.

    Raises:
        NotInsectLegError: a chain that breaks the mammal-leg assumptions (naming the joint).
    """
    by_name, data = named_leg_chains(model)
    x = np.array([1.0, 0.0, 0.0])
    legs: LegNames = {}
    for name in LEG_NAMES:
        chain = by_name[name]
        names = [model.names[j] for j in chain]
        axes = [joint_axis_in_base(model, data, j) for j in chain]
        if abs(abs(axes[0] @ x) - 1.0) > AXIS_TOLERANCE:
            raise NotInsectLegError(
                f"{name} chain: first joint {names[0]!r} axis {rounded(axes[0])} is not along the "
                "body's x axis, unlike the LF leg (a mammal leg's first joint is a hip "
                "ab/adduction about x)",
                name,
            )
        if abs(axes[1] @ x) > AXIS_TOLERANCE:
            raise NotInsectLegError(
                f"{name} chain: hip flexion {names[1]!r} axis {rounded(axes[1])} is not "
                "perpendicular to the body's x axis",
                name,
            )
        if abs(abs(axes[1] @ axes[2]) - 1.0) > AXIS_TOLERANCE:
            raise NotInsectLegError(
                f"{name} chain: knee {names[2]!r} axis {rounded(axes[2])} is not parallel to the "
                f"hip flexion {names[1]!r} axis {rounded(axes[1])}",
                name,
            )
        legs[name] = (tuple(names), foot_frame(model, chain[2], name))
    return legs


def _check_axes(model: pin.Model, data: pin.Data, leg: str, chain: list[int]) -> None:
    z = np.array([0.0, 0.0, 1.0])
    names = [model.names[j] for j in chain]
    axes = [joint_axis_in_base(model, data, j) for j in chain]
    if abs(abs(axes[0] @ z) - 1.0) > AXIS_TOLERANCE:
        hint = (
            " — this looks like a hip ab/adduction leg (mammal type)"
            if abs(axes[0] @ z) < AXIS_TOLERANCE
            else ""
        )
        raise NotInsectLegError(
            f"{leg} chain: first joint {names[0]!r} axis {rounded(axes[0])} is not vertical in the "
            f"base frame{hint}; an insect leg's first joint is a hip yaw about z",
            leg,
        )
    for k, what in ((1, "hip pitch"), (2, "knee")):
        if abs(axes[k] @ z) > AXIS_TOLERANCE:
            raise NotInsectLegError(
                f"{leg} chain: {what} joint {names[k]!r} axis {rounded(axes[k])} is not horizontal "
                "in the base frame",
                leg,
            )
    if abs(abs(axes[1] @ axes[2]) - 1.0) > AXIS_TOLERANCE:
        raise NotInsectLegError(
            f"{leg} chain: knee {names[2]!r} axis {rounded(axes[2])} is not parallel to the hip "
            f"pitch {names[1]!r} axis {rounded(axes[1])}",
            leg,
        )
    # joint origins may slide along their axes (geometry.extract_leg_geometry): the coxa
    # is the horizontal offset of the pitch axis from the yaw axis, across the pitch axis
    normal = axes[1] / np.linalg.norm(axes[1])
    offset = data.oMi[chain[1]].translation - data.oMi[chain[0]].translation
    coxa = offset - (offset @ z) * z - (offset @ normal) * normal
    if np.linalg.norm(coxa) < LENGTH_TOLERANCE:
        raise NotInsectLegError(
            f"{leg} chain: hip pitch {names[1]!r} axis crosses the hip yaw axis (no coxa, "
            "L1 = 0); the DH model of Table 3.1 needs a horizontal coxa before the pitch joint",
            leg,
        )


def _check_leg_plane(
    model: pin.Model, data: pin.Data, leg: str, chain: list[int], foot: str
) -> None:
    """The foot tip lies in the vertical plane through the yaw axis, normal to the pitch axis."""
    pin.updateFramePlacements(model, data)
    hip = data.oMi[chain[0]].translation
    normal = joint_axis_in_base(model, data, chain[1])
    off = float((data.oMf[model.getFrameId(foot)].translation - hip) @ normal)
    if abs(off) > LENGTH_TOLERANCE:
        raise NotInsectLegError(
            f"{leg} chain: foot frame {foot!r} is {abs(off):.4g} m out of the leg plane (the "
            "vertical plane through the hip yaw axis, normal to the pitch and knee axes)",
            leg,
        )


def format_discovery(robot: object) -> str:
    """A plain-text table of what discovery found for a loaded ``Robot`` (docs/robots.md).

    Angles in degrees (user interface), lengths in metres.
    """
    legs: tuple[LegGeometry, ...] = robot.legs  # type: ignore[attr-defined]
    com = robot.position_body_com_in_base  # type: ignore[attr-defined]
    deg = np.degrees
    lines = [
        f"robot {robot.name!r}: root link {robot.model.frames[1].name!r}, "  # type: ignore
        f"body {robot.body_mass:.4g} kg, total {robot.total_mass:.4g} kg, "  # type: ignore
        f"body CoG in base {rounded(com)} m",
    ]
    for leg in legs:
        knee = knee_convention(leg)
        lines += [
            f"{leg.name}: joints {list(leg.joint_names)}, foot {leg.foot_frame!r}",
            f"    hip in base {rounded(leg.position_hip_in_base)} m, theta_b "
            f"{deg(leg.theta_b):.2f} deg, L1 L2 L3 {leg.L1:.4g} {leg.L2:.4g} {leg.L3:.4g} m, "
            f"Lz {hip_depth_below_com(leg, com):.4g} m",
            f"    axis_sign {leg.axis_sign.astype(int).tolist()}, zero_offset "
            f"{[round(float(x), 2) + 0.0 for x in deg(leg.zero_offset)]} deg, knee-down: "
            f"q3 {'>' if knee.knee_down_sign > 0 else '<'} {deg(knee.q_straight):.2f} deg, "
            f"within limits {[round(float(x), 2) for x in deg(knee.q_knee_down)]} deg",
            f"    limits q_lower {[round(float(x), 2) for x in deg(leg.q_lower)]} deg, "
            f"q_upper {[round(float(x), 2) for x in deg(leg.q_upper)]} deg",
        ]
    return "\n".join(lines)
