"""The four leg chains of a fixed-base model, named from the hips and with their foot frames.

A quadruped of a supported family has, in the fixed-base Pinocchio model, exactly four
kinematic chains from the body (the root link and its fixed children) to a leaf, each with
exactly three 1-dof revolute joints with finite limits, and no other moving joint; each
knee's link carries a foot frame, the deepest fixed child link (the tip). Legs are named
from the hip positions relative to their centroid in the base frame (x > 0 front, y > 0
left, REP-103). Whatever breaks an assumption raises :class:`NotInsectLegError` naming the
chain, the joint and the assumption. Everything here reads the model at q = 0.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .errors import RobotDescriptionError
from .geometry import LENGTH_TOLERANCE

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


def rounded(v: np.ndarray) -> list[float]:
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
                    model.names[top],
                )
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
                names[0],
            )
        if kind != "revolute":
            raise NotInsectLegError(
                f"{label}: joint {model.names[j]!r} is {kind}; an insect leg has "
                "revolute joints only (hip yaw, hip pitch, knee)",
                names[0],
            )
        lo = model.lowerPositionLimit[model.joints[j].idx_q]
        hi = model.upperPositionLimit[model.joints[j].idx_q]
        if not (np.isfinite(lo) and np.isfinite(hi) and hi > lo):
            raise NotInsectLegError(
                f"{label}: joint {model.names[j]!r} has limits [{lo}, {hi}]; "
                "a finite range lower < upper is needed",
                names[0],
            )


def foot_frame(model: pin.Model, knee: int, leg: str) -> str:
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
            "the knee axis to mark the foot tip; add a fixed <link> at the tip of the tibia",
            leg,
        )
    return best[2]


def _check_four_chains(model: pin.Model) -> None:
    """Refuse a robot whose body carries fewer than four chains (an arm, a humanoid) as not
    a quadruped, before any leg is examined (more than four: a quadruped with an extra moving
    joint is told which, :func:`named_leg_chains`)."""
    tops = [j for j in range(1, model.njoints) if model.parents[j] == 0]
    if len(tops) < 4:
        names = [model.names[j] for j in tops]
        raise NotInsectLegError(
            f"not a quadruped: found {len(tops)} leg chain{'s' if len(tops) != 1 else ''} "
            f"from the body (starting at joints {names[:8]}); a quadruped has 4 legs"
        )


def named_leg_chains(model: pin.Model) -> tuple[dict[str, list[int]], pin.Data]:
    """Four chains of three limited revolute joints, named LF RF LH RH from the hips' centroid.

    Returns the chains by leg name and the model's data at q = 0 (placements and Jacobians).
    """
    if model.njoints > 1 and model.nqs[1] == 7:
        raise NotInsectLegError("pass the fixed-base model, not one with a free-flyer root")
    _check_four_chains(model)
    chains = _chains(model)
    legs3 = [c for c in chains if len(c) == 3]
    others = [c for c in chains if len(c) != 3]
    if len(legs3) == 4 and others:
        raise NotInsectLegError(
            f"moving joints outside the four legs: {[[model.names[j] for j in c] for c in others]}"
            "; a quadruped of a supported family has only its 12 leg joints (make the others "
            "fixed)"
        )
    if others:
        chain, n = others[0], len(others[0])
        raise NotInsectLegError(
            f"{_label(model, chain)} has {n} joint{'s' if n != 1 else ''}; a supported leg has 3 "
            "(insect: hip yaw, hip pitch, knee; mammal: hip ab/adduction, hip flexion, knee)",
            model.names[chain[0]],
        )
    if len(chains) != 4:
        raise NotInsectLegError(
            f"not a quadruped: found {len(chains)} leg chains from the body "
            f"{[[model.names[j] for j in c] for c in chains]}; a quadruped has 4"
        )
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
                f"hip joint {model.names[chain[0]]!r} at "
                f"{rounded(data.oMi[chain[0]].translation)} m is neither clearly "
                "front/rear nor left/right of the hips' centre "
                f"{rounded(hips.mean(axis=0))} m",
                model.names[chain[0]],
            )
        name = ("L" if rel[1] > 0 else "R") + ("F" if rel[0] > 0 else "H")
        if name in by_name:
            raise NotInsectLegError(
                f"two hips are {name} of the hips' centre: {model.names[by_name[name][0]]!r} and "
                f"{model.names[chain[0]]!r} (hips at {[rounded(h) for h in hips]} m); "
                "an insect-leg quadruped has one leg per body corner",
                name,
            )
        by_name[name] = chain

    return by_name, data


def joint_axis_in_base(model: pin.Model, data: pin.Data, joint_id: int) -> np.ndarray:
    """Unit axis (3,) of joint ``joint_id`` in the base frame at q = 0 (``data`` from
    :func:`named_leg_chains`)."""
    return np.array(data.J[3:, model.joints[joint_id].idx_v])
