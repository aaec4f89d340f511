"""Find the four insect legs of a quadruped in a loaded model, with no names assumed.

An insect-leg quadruped (thesis §2.1, Fig 3.1) is, in the fixed-base Pinocchio model:

* exactly four kinematic chains from the body (the root link and its fixed children) to a leaf,
  each with exactly three 1-dof revolute joints with finite limits, and no other moving joint;
* per chain: the first joint axis vertical in the base frame (hip yaw, θ1), the second and
  third horizontal and parallel (hip pitch θ2, knee θ3), perpendicular to the coxa, and the
  knee and the foot tip in the vertical leg plane through the hip (the DH chain of Table 3.1);
* a foot frame: the deepest fixed child link of the knee's link (the tip).

Legs are named from the hip positions relative to their centroid in the base frame
(x > 0 front, y > 0 left, REP-103) and returned in the thesis order LF, RF, LH, RH (legs 1-4).
Whatever breaks an assumption raises :class:`NotInsectLegError` naming the chain, the joint and
the assumption. ``geometry.extract_leg_geometry`` then derives the numbers and re-validates.

The body's CoG is the static-stability point (§5.1): see :func:`body_com`. Everything in
this module reads the model at q = 0 (the URDF's reference pose).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from .errors import RobotDescriptionError
from .geometry import AXIS_TOLERANCE, LEG_NAMES, LENGTH_TOLERANCE, LegGeometry
from .leg_family import family_of

#: A hip closer than this to the centroid's x (or y) cannot be told front from rear [m].
SIDE_TOLERANCE = 1e-6

#: What discovery hands to :func:`geometry.extract_leg_geometry`, per leg name.
LegNames = dict[str, tuple[tuple[str, str, str], str]]


class NotInsectLegError(RobotDescriptionError):
    """The model is not an insect-leg quadruped; the message names the chain, joint and rule.

    Attributes:
        chain: the leg name ("LF", ...) or joint names of the offending chain, or "" when the
            problem concerns the whole robot (e.g. the number of legs).
    """

    def __init__(self, message: str, chain: str = "") -> None:
        super().__init__(message)
        self.chain = chain


def _vec(v: np.ndarray) -> list[float]:
    """Short rounded list for messages."""
    return [float(x) + 0.0 for x in np.round(v, 4)]


def joint_kind(model: pin.Model, joint_id: int) -> str:
    """'revolute', 'continuous', 'prismatic' or the Pinocchio type name of another joint."""
    short = model.joints[joint_id].shortname()
    if short.startswith("JointModelRUB") or "RevoluteUnbounded" in short:
        return "continuous"
    if short in ("JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned"):
        return "revolute"
    if short in ("JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned"):
        return "prismatic"
    return short.removeprefix("JointModel")


def _label(model: pin.Model, chain: list[int]) -> str:
    """'RH chain [joint names]' from the first joint's corner in the base frame (q = 0)."""
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    x, y = data.oMi[chain[0]].translation[:2]
    names = [model.names[j] for j in chain]
    if abs(x) < SIDE_TOLERANCE or abs(y) < SIDE_TOLERANCE:
        return f"chain {names}"
    return f"{'L' if y > 0 else 'R'}{'F' if x > 0 else 'H'} chain {names}"


def _chains(model: pin.Model) -> list[list[int]]:
    """Joint ids of every chain from the body to a leaf; refuses branching legs."""
    children: dict[int, list[int]] = {j: [] for j in range(model.njoints)}
    for j in range(1, model.njoints):
        children[model.parents[j]].append(j)
    chains = []
    for top in children[0]:
        chain = [top]
        while children[chain[-1]]:
            kids = children[chain[-1]]
            if len(kids) > 1:
                raise NotInsectLegError(
                    f"{_label(model, chain)} branches at {model.names[chain[-1]]!r} into "
                    f"{[model.names[k] for k in kids]}: an insect leg is one serial chain",
                    model.names[top])
            chain.append(kids[0])
        chains.append(chain)
    return chains


def _check_joint_types(model: pin.Model, chain: list[int]) -> None:
    names = [model.names[j] for j in chain]
    label = _label(model, chain)
    for j in chain:
        kind = joint_kind(model, j)
        if kind == "continuous":
            raise NotInsectLegError(
                f"{label}: joint {model.names[j]!r} is continuous (no limits); the "
                "planner needs joint limits: declare it revolute with <limit lower upper>",
                names[0])
        if kind != "revolute":
            raise NotInsectLegError(
                f"{label}: joint {model.names[j]!r} is {kind}; an insect leg has "
                "revolute joints only (hip yaw, hip pitch, knee)", names[0])
        lo = model.lowerPositionLimit[model.joints[j].idx_q]
        hi = model.upperPositionLimit[model.joints[j].idx_q]
        if not (np.isfinite(lo) and np.isfinite(hi) and hi > lo):
            raise NotInsectLegError(
                f"{label}: joint {model.names[j]!r} has limits [{lo}, {hi}]; "
                "a finite range lower < upper is needed", names[0])


def _foot_frame(model: pin.Model, knee: int, leg: str) -> str:
    """Deepest BODY frame rigidly attached to the knee's link (ties: farthest from the knee)."""
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    best: tuple[int, float, str] | None = None
    for fid, frame in enumerate(model.frames):
        if frame.parentJoint != knee or frame.type != pin.FrameType.BODY:
            continue
        depth, f = 0, fid
        while model.frames[f].type != pin.FrameType.JOINT:
            f = model.frames[f].parentFrame
            depth += 1
        distance = float(np.linalg.norm(data.oMf[fid].translation - data.oMi[knee].translation))
        key = (depth, distance, frame.name)
        if best is None or key[:2] > best[:2]:
            best = key
    if best is None or best[1] < LENGTH_TOLERANCE:
        raise NotInsectLegError(
            f"{leg} chain: the knee {model.names[knee]!r} carries no fixed child link away from "
            "the knee axis to mark the foot tip; add a fixed <link> at the tip of the tibia", leg)
    return best[2]


def _named_chains(model: pin.Model) -> tuple[dict[str, list[int]], pin.Data]:
    """Four chains of three limited revolute joints, named LF RF LH RH from the hips' centroid.

    Returns the chains by leg name and the model's data at q = 0 (placements and Jacobians).
    """
    if model.njoints > 1 and model.nqs[1] == 7:
        raise NotInsectLegError("pass the fixed-base model, not one with a free-flyer root")
    chains = _chains(model)
    legs3 = [c for c in chains if len(c) == 3]
    others = [c for c in chains if len(c) != 3]
    if len(legs3) == 4 and others:
        raise NotInsectLegError(
            f"moving joints outside the four legs: {[[model.names[j] for j in c] for c in others]}"
            "; a quadruped of a supported family has only its 12 leg joints (make the others "
            "fixed)")
    if others:
        chain, n = others[0], len(others[0])
        raise NotInsectLegError(
            f"{_label(model, chain)} has {n} joint{'s' if n != 1 else ''}; a supported leg has 3 "
            "(insect: hip yaw, hip pitch, knee; mammal: hip ab/adduction, hip flexion, knee)",
            model.names[chain[0]])
    if len(chains) != 4:
        raise NotInsectLegError(
            f"found {len(chains)} leg chain(s) from the body "
            f"{[[model.names[j] for j in c] for c in chains]}; a quadruped has 4")
    for chain in chains:
        _check_joint_types(model, chain)

    data = model.createData()
    q0 = pin.neutral(model)
    pin.forwardKinematics(model, data, q0)
    pin.computeJointJacobians(model, data, q0)
    hips = np.array([data.oMi[c[0]].translation for c in chains])
    relative = hips - hips.mean(axis=0)
    by_name: dict[str, list[int]] = {}
    for chain, rel in zip(chains, relative):
        if abs(rel[0]) < SIDE_TOLERANCE or abs(rel[1]) < SIDE_TOLERANCE:
            raise NotInsectLegError(
                f"hip joint {model.names[chain[0]]!r} at {_vec(data.oMi[chain[0]].translation)} m "
                "is neither clearly front/rear nor left/right of the hips' centre "
                f"{_vec(hips.mean(axis=0))} m", model.names[chain[0]])
        name = ("L" if rel[1] > 0 else "R") + ("F" if rel[0] > 0 else "H")
        if name in by_name:
            raise NotInsectLegError(
                f"two hips are {name} of the hips' centre: {model.names[by_name[name][0]]!r} and "
                f"{model.names[chain[0]]!r} (hips at {[_vec(h) for h in hips]} m); "
                "an insect-leg quadruped has one leg per body corner", name)
        by_name[name] = chain

    return by_name, data


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
    by_name, data = _named_chains(model)
    legs: LegNames = {}
    for name in LEG_NAMES:
        chain = by_name[name]
        _check_axes(model, data, name, chain)
        foot = _foot_frame(model, chain[2], name)
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
    by_name, data = _named_chains(model)
    first = _axis(model, data, by_name["LF"][0])
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
    by_name, data = _named_chains(model)
    x = np.array([1.0, 0.0, 0.0])
    legs: LegNames = {}
    for name in LEG_NAMES:
        chain = by_name[name]
        names = [model.names[j] for j in chain]
        axes = [_axis(model, data, j) for j in chain]
        if abs(abs(axes[0] @ x) - 1.0) > AXIS_TOLERANCE:
            raise NotInsectLegError(
                f"{name} chain: first joint {names[0]!r} axis {_vec(axes[0])} is not along the "
                "body's x axis, unlike the LF leg (a mammal leg's first joint is a hip "
                "ab/adduction about x)", name)
        if abs(axes[1] @ x) > AXIS_TOLERANCE:
            raise NotInsectLegError(
                f"{name} chain: hip flexion {names[1]!r} axis {_vec(axes[1])} is not "
                "perpendicular to the body's x axis", name)
        if abs(abs(axes[1] @ axes[2]) - 1.0) > AXIS_TOLERANCE:
            raise NotInsectLegError(
                f"{name} chain: knee {names[2]!r} axis {_vec(axes[2])} is not parallel to the "
                f"hip flexion {names[1]!r} axis {_vec(axes[1])}", name)
        legs[name] = (tuple(names), _foot_frame(model, chain[2], name))  # type: ignore[assignment]
    return legs


def _axis(model: pin.Model, data: pin.Data, joint_id: int) -> np.ndarray:
    return np.array(data.J[3:, model.joints[joint_id].idx_v])


def _check_axes(model: pin.Model, data: pin.Data, leg: str, chain: list[int]) -> None:
    z = np.array([0.0, 0.0, 1.0])
    names = [model.names[j] for j in chain]
    axes = [_axis(model, data, j) for j in chain]
    if abs(abs(axes[0] @ z) - 1.0) > AXIS_TOLERANCE:
        hint = (" — this looks like a hip ab/adduction leg (mammal type)"
                if abs(axes[0] @ z) < AXIS_TOLERANCE else "")
        raise NotInsectLegError(
            f"{leg} chain: first joint {names[0]!r} axis {_vec(axes[0])} is not vertical in the "
            f"base frame{hint}; an insect leg's first joint is a hip yaw about z", leg)
    for k, what in ((1, "hip pitch"), (2, "knee")):
        if abs(axes[k] @ z) > AXIS_TOLERANCE:
            raise NotInsectLegError(
                f"{leg} chain: {what} joint {names[k]!r} axis {_vec(axes[k])} is not horizontal "
                "in the base frame", leg)
    if abs(abs(axes[1] @ axes[2]) - 1.0) > AXIS_TOLERANCE:
        raise NotInsectLegError(
            f"{leg} chain: knee {names[2]!r} axis {_vec(axes[2])} is not parallel to the hip "
            f"pitch {names[1]!r} axis {_vec(axes[1])}", leg)
    # joint origins may slide along their axes (geometry.extract_leg_geometry): the coxa
    # is the horizontal offset of the pitch axis from the yaw axis, across the pitch axis
    normal = axes[1] / np.linalg.norm(axes[1])
    offset = data.oMi[chain[1]].translation - data.oMi[chain[0]].translation
    coxa = offset - (offset @ z) * z - (offset @ normal) * normal
    if np.linalg.norm(coxa) < LENGTH_TOLERANCE:
        raise NotInsectLegError(
            f"{leg} chain: hip pitch {names[1]!r} axis crosses the hip yaw axis (no coxa, "
            "L1 = 0); the DH model of Table 3.1 needs a horizontal coxa before the pitch joint",
            leg)


def _check_leg_plane(model: pin.Model, data: pin.Data, leg: str, chain: list[int],
                     foot: str) -> None:
    """The foot tip lies in the vertical plane through the yaw axis, normal to the pitch axis."""
    pin.updateFramePlacements(model, data)
    hip = data.oMi[chain[0]].translation
    normal = _axis(model, data, chain[1])
    off = float((data.oMf[model.getFrameId(foot)].translation - hip) @ normal)
    if abs(off) > LENGTH_TOLERANCE:
        raise NotInsectLegError(
            f"{leg} chain: foot frame {foot!r} is {abs(off):.4g} m out of the leg plane (the "
            "vertical plane through the hip yaw axis, normal to the pitch and knee axes)", leg)


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
            f"{'q3 < ' if s > 0 else 'q3 > '}{q_straight:.4g} rad)", leg.name)
    q = np.sort(leg.dh_to_joint(np.array([[0.0, 0.0, lo], [0.0, 0.0, hi]]))[:, 2])
    return KneeConvention(q_straight=q_straight, knee_down_sign=int(-s), q_knee_down=q)


def body_com(model: pin.Model) -> tuple[float, np.ndarray]:
    """Mass [kg] and CoG in the base frame [m, (3,)] of the body alone.

    The body is the root link with every link fixed to it (Pinocchio merges them into the
    root's inertia: a sensor mast counts, the legs do not). Raises if the body has no mass.
    """
    inertia = model.inertias[0]
    if inertia.mass <= 0.0:
        raise RobotDescriptionError(
            f"the body (root link {model.frames[1].name!r} and its fixed children) has no mass; "
            "its CoG is the static-stability point, so give the root link an <inertial>")
    return float(inertia.mass), np.array(inertia.lever)


def hip_depth_below_com(leg: LegGeometry, position_body_com_in_base: np.ndarray) -> float:
    """Lz: how far the hip axis sits below the body CoG [m] (thesis Table 3.1: 0.15 m)."""
    return float(position_body_com_in_base[2] - leg.position_hip_in_base[2])


def legs_in_body_com_frame(legs: tuple[LegGeometry, ...],
                           position_body_com_in_base: np.ndarray) -> tuple[LegGeometry, ...]:
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
        f"body CoG in base {_vec(com)} m",
    ]
    for leg in legs:
        knee = knee_convention(leg)
        lines += [
            f"{leg.name}: joints {list(leg.joint_names)}, foot {leg.foot_frame!r}",
            f"    hip in base {_vec(leg.position_hip_in_base)} m, theta_b "
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
