"""The robot's own names of its legs and joints, read from its joint names (docs/outputs.md).

The planner orders legs LF, RF, LH, RH (planner.trajectory.samples.LEGS); a robot's URDF
names them its own way (go2: FL, FR, RL, RR; solo12: FL, FR, HL, HR). One file speaks one
vocabulary: where the joint columns carry the URDF's joint names, the leg columns carry the
URDF's leg prefixes. The rule, from the 12 joint names alone (3 per leg, in leg order):

- a leg's own name is the text before the first ``_`` that its three joint names share
  (``FL_hip_joint``, ``FL_thigh_joint``, ``FL_calf_joint`` -> ``FL``), when every leg has
  one and the four differ; otherwise the planner's names (LF, RF, LH, RH);
- a joint's label is its name without the leg's prefix and a trailing ``_joint``, with
  ``_`` as spaces (``FL_thigh_joint`` -> ``thigh``, ``LF_hip_yaw`` -> ``hip yaw``), when the
  four legs give the same three labels; otherwise ``joint 1``, ``joint 2``, ``joint 3``.

SILO4's joints are ``{LF,RF,LH,RH}_{hip_yaw,hip_pitch,knee}``: its names are the planner's.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from planner.trajectory.samples import LEGS

#: Joints per leg (the joint vector is 3 per leg, in leg order).
JOINTS_PER_LEG = 3


@dataclass(frozen=True)
class LegLabels:
    """Names to show for the legs and joints of one robot.

    Attributes:
        legs: the robot's own leg names, in the planner's leg order (4,).
        joints: the label of each of a leg's 3 joints, in joint order (3,).
    """

    legs: tuple[str, ...]
    joints: tuple[str, ...]

    @classmethod
    def from_joint_names(cls, joint_names: Sequence[str]) -> LegLabels:
        """The labels of a robot whose joint vector has ``joint_names`` (12, leg order)."""
        names = list(joint_names)
        if len(names) != JOINTS_PER_LEG * len(LEGS):
            return cls(tuple(LEGS), _generic_joints())
        per_leg = [names[JOINTS_PER_LEG * i : JOINTS_PER_LEG * (i + 1)] for i in range(len(LEGS))]
        prefixes = [_shared_prefix(leg) for leg in per_leg]
        if any(p is None for p in prefixes) or len(set(prefixes)) != len(LEGS):
            return cls(tuple(LEGS), _generic_joints())
        legs = tuple(str(p) for p in prefixes)
        labels = {tuple(_joint_label(n, p) for n in leg) for leg, p in zip(per_leg, legs)}
        joints = labels.pop() if len(labels) == 1 else _generic_joints()
        return cls(legs, joints)

    def leg(self, planner_leg: str) -> str:
        """The robot's name of the planner's leg ``planner_leg`` (LF, RF, LH or RH)."""
        return self.legs[LEGS.index(planner_leg)]


def _generic_joints() -> tuple[str, ...]:
    return tuple(f"joint {k + 1}" for k in range(JOINTS_PER_LEG))


def _shared_prefix(joint_names: Sequence[str]) -> str | None:
    """The text before the first ``_`` when all of ``joint_names`` share it, else None."""
    heads = {name.split("_", 1)[0] for name in joint_names if "_" in name}
    if len(heads) != 1 or any("_" not in name for name in joint_names):
        return None
    head = heads.pop()
    return head or None


def _joint_label(joint_name: str, prefix: str) -> str:
    """``joint_name`` without ``<prefix>_`` and a trailing ``_joint``, ``_`` as spaces."""
    label = joint_name[len(prefix) + 1 :]
    if label.endswith("_joint") and len(label) > len("_joint"):
        label = label[: -len("_joint")]
    return label.replace("_", " ")
