"""Joint torques of a planned trajectory (thesis App. A.2), glue to silo4kin.joint_torques.

    traj = add_torques(robot, traj)               # tau = motion + support, parts kept
    traj = add_torques(robot, traj, load="body")  # the thesis's model: feet carry the body

The default load is the whole robot, floating: whole-body inverse dynamics of the plan's
motion, the base's acceleration and the swinging legs' reactions carried by the stance feet
with 3-D forces (planner/trajectory/floating_torques.py; at rest the quasi-static split of
silo4kin.joint_torques' load "total"); ``load="body"`` is App. A's model, the thesis's.
With the whole robot the feet also pass the load on over LOAD_TRANSFER_S at every contact
change (silo4kin/load_transfer.py: the reactions, and the support torques, are continuous
through touchdowns and lift-offs); the body load keeps App. A's split of each sample on its
own. ``transfer_s`` sets the transfer time either way (0: App. A's).
    traj.tau_parts["motion"], traj.tau_parts["support"]   # (N, 12) each, for Figs A.2 / A.3
"""

from __future__ import annotations

import numpy as np

from planner.trajectory.floating_torques import floating_torques
from planner.trajectory.samples import Trajectory, position_foot_in_base
from silo4kin.errors import Silo4Error
from silo4kin.joint_torques import JointTorques, Load, Method, joint_torques
from silo4kin.load_transfer import LOAD_TRANSFER_S, load_shares
from silo4kin.memo import memo_of
from silo4kin.robot import STANDARD_GRAVITY, Robot


def transfer_time_s(load: str, transfer_s: float | None = None) -> float:
    """The load transfer time [s] of a load model: ``transfer_s`` when given, else
    LOAD_TRANSFER_S for the whole robot and 0 (App. A's split) for the body."""
    if transfer_s is not None:
        return float(transfer_s)
    return LOAD_TRANSFER_S if load == "total" else 0.0


def trajectory_torques(
    robot: Robot,
    trajectory: Trajectory,
    *,
    load: Load = "total",
    gravity: float = STANDARD_GRAVITY,
    method: Method = "rnea",
    transfer_s: float | None = None,
) -> JointTorques:
    """Motion and support torques of every sample of a plan (the split, with reactions),
    the load passed between the feet over :func:`transfer_time_s`.

    ``method``: App. A's leg-motion model (load "body"); load "total" is the floating robot
    (planner/trajectory/floating_torques.py), Pinocchio's free-flyer RNEA only.

    The result is kept in the trajectory's memo for the robot and options (a Trajectory is
    immutable; the arrays returned are read-only): gait "auto" computes a crawl's torques
    for its limit check, and the outputs then ask for the same ones."""
    transfer = transfer_time_s(load, transfer_s)
    memo = memo_of(trajectory)
    key = ("torques", id(robot), load, float(gravity), method, transfer)
    hit = memo.get(key)
    if hit is not None and hit[0] is robot:
        return hit[1]
    if tuple(trajectory.joint_names) != tuple(robot.joint_names):
        raise Silo4Error(
            f"trajectory joints {list(trajectory.joint_names)} differ from the "
            f"robot's {robot.joint_names}"
        )
    if load == "total":
        if method != "rnea":
            raise Silo4Error(
                f"method {method!r} is App. A's per-leg model (load 'body'); the floating "
                "robot's torques (load 'total') are Pinocchio's free-flyer RNEA"
            )
        jt = floating_torques(robot, trajectory, gravity=gravity, transfer_s=transfer).torques
    else:
        jt = fixed_hip_torques(robot, trajectory, load, gravity, method, transfer)
    for array in (jt.motion, jt.support, jt.total, jt.reactions, jt.unloadable, jt.corrected):
        array.setflags(write=False)
    memo[key] = (robot, jt)
    return jt


def fixed_hip_torques(
    robot: Robot,
    trajectory: Trajectory,
    load: Load,
    gravity: float,
    method: Method,
    transfer: float,
) -> JointTorques:
    """App. A's torques of a plan: each leg on a fixed hip, vertical reactions carrying ``load``
    (silo4kin.joint_torques), the load passed on over ``transfer`` [s]: load "body"'s model
    and, with load "total", the feed-forward of the physics replay until round 20."""
    # silo4kin measures feet from the URDF root; the trajectory's base B is the body CoG,
    # which sits at position_body_com_in_base in the root frame (zero for SILO4).
    feet_in_root = position_foot_in_base(trajectory) + robot.position_body_com_in_base
    return joint_torques(
        robot,
        trajectory.q,
        trajectory.qd,
        trajectory.qdd,
        trajectory.contact,
        position_foot_in_base=feet_in_root,
        load=load,
        gravity=gravity,
        method=method,
        share=load_shares(trajectory.contact, trajectory.t, transfer) if transfer > 0 else None,
    )


def add_torques(
    robot: Robot,
    trajectory: Trajectory,
    *,
    load: Load = "total",
    gravity: float = STANDARD_GRAVITY,
    method: Method = "rnea",
    transfer_s: float | None = None,
) -> Trajectory:
    """A copy of the trajectory with tau (N, 12) and tau_parts {"motion", "support"}; the
    load passed between the feet over :func:`transfer_time_s` of ``load``, ``transfer_s``.

    Raises:
        SupportError: a sample has fewer than three stance feet (names the sample).
        Silo4Error: a sample's load cannot be carried without a foot pulling (the CoG
            projection is outside the support polygon: the plan is not statically stable).
    """
    jt = trajectory_torques(
        robot, trajectory, load=load, gravity=gravity, method=method, transfer_s=transfer_s
    )
    if np.any(jt.unloadable):
        k = int(np.flatnonzero(jt.unloadable)[0])
        margins = trajectory.margin_com if load == "total" else trajectory.margin_body
        if margins is None:
            margins = trajectory.margin
        point = "whole-robot CoM" if load == "total" else "body CoG"
        raise Silo4Error(
            f"sample {k} (t = {trajectory.t[k]:.3f} s): the stance feet cannot carry the "
            f"load ({load}) without pulling ({point} outside the support polygon by "
            f"{-margins[k] * 1000:.1f} mm); {int(jt.unloadable.sum())} such samples"
        )
    return trajectory.with_torques(jt.total, parts={"motion": jt.motion, "support": jt.support})
