"""The planning model: the robot as the planner sees it, built once per robot.

The planner works in the body-CoG frame B (docs/notation.md): x forward, y left, z up, origin
at the base link's centre of mass. A URDF's root need not be there (tests/robots/mantis.urdf:
4.5 cm behind and 4.2 cm below it), so :class:`PlanningModel` owns

- ``robot``: the loaded :class:`~silo4kin.robot.Robot` (URDF root frame), for torques,
  Pinocchio and outputs;
- ``legs``: the leg geometry with the hips measured from the body CoG (joint values are
  unchanged), which every planner function uses;
- the masses and :meth:`com_offset_in_base`: the whole-robot CoM measured from the body CoG
  for given joint values (silo4kin.com, cross-checked against pin.centerOfMass), the point
  the default policy keeps inside the support polygon; :func:`planning_robot` is the frame
  change itself;
- :meth:`swing_com_in_world`: the whole-robot CoM over a leg's swing at a given base pose,
  the configurations the step builder checks before it accepts a transfer;
  :meth:`moving_swing_com_in_world` the same while the base moves (the continuous crawl).

:func:`planning_model` is cached per robot object, so the planner's caches keyed on it stay
warm across plans. :func:`~planner.path.plan_path` takes a Robot (URDF frame) or a
PlanningModel and converts with :func:`as_planning_model`; the workspace and sampling
functions it calls get ``planning_robot`` (the workspace's public functions accept either
frame and convert with it).
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any, NamedTuple

import numpy as np

from planner.trajectory.profiles import cosine_blend, lift, quintic_blend, smooth_lift
from silo4kin import legs as leg_families
from silo4kin.body_frame import legs_in_body_com_frame
from silo4kin.com import leg_mass_moment_in_base, legs_com_offset
from silo4kin.frames import rotation_z
from silo4kin.kinematics import knee_down_dh_angles
from silo4kin.leg_family import INSECT, LegFamily, family_of
from silo4kin.robot import Robot

#: Configurations of a swing checked per transfer (τ = 0 .. 1, evenly spaced). S_m along a
#: straight segment is concave (a minimum of linear functions), so between two checked
#: configurations 1 % of a swing apart it can dip below both only by the curvature of the
#: CoM path: measured 3e-7 m (circle at h = 0.6 m sampled at 1000 instead of 100 per unit).
SWING_CHECK_SAMPLES = 101


@dataclass(frozen=True, eq=False)
class PlanningModel:
    """A robot in the planning frame B (module docstring).

    Attributes:
        robot: the loaded robot (URDF root frame).
        planning_robot: the same robot with ``legs`` in B (what IK and sampling use).
        legs: leg geometry, hips in B, order LF, RF, LH, RH.
        total_mass: body + legs [kg].
        body_mass: base link [kg].
        position_body_com_in_root: the origin of B in the URDF root frame [m], (3,).
    """

    robot: Robot
    planning_robot: Robot
    legs: tuple
    total_mass: float
    body_mass: float
    position_body_com_in_root: np.ndarray

    @property
    def name(self) -> str:
        """The robot's name."""
        return self.robot.name

    def com_offset_in_base(self, q: np.ndarray) -> np.ndarray:
        """Whole-robot CoM minus body CoM in B [m], (N, 3), for joint values q (N, 12) [rad]."""
        return legs_com_offset(self.legs, q, self.total_mass)

    def com_in_world(self, q: np.ndarray, position_base_in_world: np.ndarray,
                     yaw_base_in_world: np.ndarray) -> np.ndarray:
        """Whole-robot CoM in W [m], (N, 3): base (N, 3) [m] + R_z(yaw) (N,) [rad] x offset."""
        off = self.com_offset_in_base(q)
        c, s = np.cos(yaw_base_in_world), np.sin(yaw_base_in_world)
        out = np.array(position_base_in_world, dtype=float, copy=True)
        out[:, 0] += c * off[:, 0] - s * off[:, 1]
        out[:, 1] += s * off[:, 0] + c * off[:, 1]
        out[:, 2] += off[:, 2]
        return out

    def swing_com_in_world(self, position_base_in_world: np.ndarray, yaw: float,
                           position_feet_in_world: np.ndarray, leg: int,
                           foothold_end_in_world: np.ndarray, swing_height_m: float,
                           n: int = SWING_CHECK_SAMPLES) -> np.ndarray:
        """Whole-robot CoM (x, y) in W [m], (n, 2), over the swing of ``leg`` from its foot in
        ``position_feet_in_world`` (4, 3) [m] to ``foothold_end_in_world`` (3,) [m] with the
        base standing at (3,) [m], yaw [rad]: the swing path of planner/trajectory/sampling.py (cosine
        blend in x, y, lift of eq 5.4 by ``swing_height_m``) at n evenly spaced τ. NaN rows
        where a foot is out of reach (the sample verification reports those).

        The step builder calls this for every transfer, so the three stance legs and the n
        swing configurations go through one vectorised knee-down IK and CoM pass
        (:func:`_leg_moments`); tests/test_com.py checks it against silo4kin's IK and
        silo4kin.com on random swings. Memoised on the exact inputs (issue 14: the ditch's
        route search plans the same approach for every crossing angle); the result is
        read-only."""
        return _memoised(self, (
            np.asarray(position_base_in_world, dtype=float).tobytes(), float(yaw),
            np.asarray(position_feet_in_world, dtype=float).tobytes(), int(leg),
            np.asarray(foothold_end_in_world, dtype=float).tobytes(),
            float(swing_height_m), int(n)),
            lambda: (self._swing_com_in_world(position_base_in_world, yaw,
                                              position_feet_in_world, leg,
                                              foothold_end_in_world, swing_height_m, n),))[0]

    def _swing_com_in_world(self, position_base_in_world: np.ndarray, yaw: float,
                            position_feet_in_world: np.ndarray, leg: int,
                            foothold_end_in_world: np.ndarray, swing_height_m: float,
                            n: int) -> np.ndarray:
        """swing_com_in_world without its memo."""
        tau = np.linspace(0.0, 1.0, n)
        rot_t = rotation_z(yaw).T
        base = np.asarray(position_base_in_world, dtype=float)
        feet = np.asarray(position_feet_in_world, dtype=float)
        start = feet[leg]
        delta = np.asarray(foothold_end_in_world, dtype=float) - start
        path = start + delta * cosine_blend(tau, 1.0).s[:, None]
        path[:, 2] += lift(tau, 1.0, swing_height_m).s
        stance = [k for k in range(4) if k != leg]
        rows = np.concatenate([stance, np.full(n, leg)])
        targets = (np.vstack([feet[stance], path]) - base) @ rot_t.T           # in B
        if self.leg_family is INSECT:
            moment = _leg_moments(self._leg_constants, rows, targets)
        else:
            moment = _leg_moments_any(self.legs, rows, targets)
        offset = (moment[:3].sum(axis=0) + moment[3:]) / self.total_mass
        return base[:2] + offset[:, :2] @ rot_t[:2, :2]

    def moving_swing_com_in_world(self, position_base_start_in_world: np.ndarray,
                                  position_base_end_in_world: np.ndarray, yaw: float,
                                  position_feet_in_world: np.ndarray, leg: int,
                                  foothold_end_in_world: np.ndarray, swing_height_m: float,
                                  n: int = SWING_CHECK_SAMPLES) -> tuple[np.ndarray,
                                                                         np.ndarray]:
        """(CoM (n, 2), base (n, 2)) in W [m] over the swing of ``leg`` while the base moves
        from its start to its end (3,) [m] (the continuous crawl, planner/gaits/crawl.py): base
        and swing foot x, y on the quintic of eq 5.16, the lift of trajectories.smooth_lift,
        as planner/trajectory/sampling.py samples them (smooth profiles), every leg's IK at each of the
        n configurations. NaN rows where a foot is out of reach. Memoised on the exact
        inputs as :meth:`swing_com_in_world` (the ditch's route search crawls the same
        approach for every crossing angle); the results are read-only."""
        return _memoised(self, (
            "moving", np.asarray(position_base_start_in_world, dtype=float).tobytes(),
            np.asarray(position_base_end_in_world, dtype=float).tobytes(), float(yaw),
            np.asarray(position_feet_in_world, dtype=float).tobytes(), int(leg),
            np.asarray(foothold_end_in_world, dtype=float).tobytes(),
            float(swing_height_m), int(n)),
            lambda: self._moving_swing_com_in_world(
                position_base_start_in_world, position_base_end_in_world, yaw,
                position_feet_in_world, leg, foothold_end_in_world, swing_height_m, n))

    def _moving_swing_com_in_world(self, position_base_start_in_world: np.ndarray,
                                   position_base_end_in_world: np.ndarray, yaw: float,
                                   position_feet_in_world: np.ndarray, leg: int,
                                   foothold_end_in_world: np.ndarray, swing_height_m: float,
                                   n: int) -> tuple[np.ndarray, np.ndarray]:
        """moving_swing_com_in_world without its memo."""
        blend, height, rows = _moving_swing_profile(n, float(swing_height_m))
        rot_t = rotation_z(yaw).T
        b0 = np.asarray(position_base_start_in_world, dtype=float)
        base = b0 + (np.asarray(position_base_end_in_world, float) - b0) * blend
        feet = np.repeat(np.asarray(position_feet_in_world, float)[None], n, axis=0)
        start = feet[0, leg].copy()
        feet[:, leg] = start + (np.asarray(foothold_end_in_world, float) - start) * blend
        feet[:, leg, 2] += height
        targets = ((feet - base[:, None, :]) @ rot_t.T).reshape(-1, 3)       # in B
        if self.leg_family is INSECT:
            moment = _leg_moments(self._leg_constants, rows, targets, horizontal=True)
        else:
            moment = _leg_moments_any(self.legs, rows, targets)
        offset = moment.reshape(n, 4, 3).sum(axis=1) / self.total_mass
        return base[:, :2] + offset[:, :2] @ rot_t[:2, :2], base[:, :2].copy()

    @property
    def leg_family(self) -> LegFamily:
        """The robot's :class:`~silo4kin.leg_family.LegFamily` (insect for no legs)."""
        return family_of(self.legs[0]) if self.legs else INSECT

    @property
    def family(self) -> str:
        """The name of :attr:`leg_family`, "insect" or "mammal" (for outputs)."""
        return self.leg_family.name

    @property
    def _leg_constants(self) -> _LegConstants:
        return _leg_constants(self)


@lru_cache(maxsize=8)
def _moving_swing_profile(n: int, swing_height_m: float
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(quintic blend (n, 1), smooth lift [m] (n,), leg rows (4 n,)) of
    moving_swing_com_in_world's n configurations, read-only (the same for every swing)."""
    tau = np.linspace(0.0, 1.0, n)
    out = (quintic_blend(tau, 1.0).s[:, None], smooth_lift(tau, 1.0, swing_height_m).s,
           np.tile(np.arange(4), n))
    for array in out:
        array.setflags(write=False)
    return out


#: Entries of PlanningModel.swing_com_in_world's memo (~0.3 kB each).
SWING_COM_MEMO_SIZE = 8192
_SWING_COM_MEMO: dict[tuple, tuple[PlanningModel, Any]] = {}   # key -> (model, result)


def _memoised(model: Any, key: tuple, compute: Callable[[], tuple]) -> tuple:
    """``compute()`` (a tuple of arrays, made read-only) for ``model`` (a PlanningModel, or
    the _LegConstants of :func:`_rows_of`) and ``key``, from the
    memo when it holds them (keys carry id(model); an id is only unique while alive, so the
    entry keeps the model and is checked against it)."""
    full = (id(model), *key)
    hit = _SWING_COM_MEMO.get(full)
    if hit is None or hit[0] is not model:
        if len(_SWING_COM_MEMO) >= SWING_COM_MEMO_SIZE:
            _SWING_COM_MEMO.clear()
        result = compute()
        for array in result:
            array.setflags(write=False)
        hit = _SWING_COM_MEMO[full] = (model, result)
    return hit[1]


class _LegConstants(NamedTuple):
    """Per-leg numbers of :func:`_leg_moments`, each indexed by leg (4, ...)."""

    hip: np.ndarray        # (4, 3) hip in B [m]
    length: np.ndarray     # (4, 3) L1, L2, L3 [m]
    mass: np.ndarray       # (4, 3) link masses [kg]
    com: np.ndarray        # (4, 3, 3) link CMs in their DH frames [m]


@lru_cache(maxsize=16)
def _leg_constants(model: PlanningModel) -> _LegConstants:
    legs = model.legs
    return _LegConstants(
        hip=np.array([g.position_hip_in_base for g in legs], dtype=float),
        length=np.array([(g.L1, g.L2, g.L3) for g in legs], dtype=float),
        mass=np.array([[lk.mass for lk in g.links] for g in legs], dtype=float),
        com=np.array([[lk.com for lk in g.links] for g in legs], dtype=float))


def _leg_moments(const: _LegConstants, leg: np.ndarray, position_foot_in_base: np.ndarray,
                 horizontal: bool = False) -> np.ndarray:
    """Σ m_i c_i [kg m], (R, 3), of leg ``leg[i]`` with its foot at row i of
    ``position_foot_in_base`` (R, 3) [m], knee down: silo4kin.kinematics.knee_down_dh_angles
    (θ2, θ3; of the leg's yaw φ = θb + θ1 only cos φ = x/ρ, sin φ = y/ρ enter) and the link moments of
    silo4kin.com.leg_mass_moment_in_base, for several legs in one pass. With
    ``horizontal`` the z column is left at its hip term (the callers that set it read x, y
    only)."""
    g = _rows_of(const, leg)
    rel = position_foot_in_base - g.hip
    rho = np.hypot(rel[:, 0], rel[:, 1])
    c, s = rel[:, 0] / rho, rel[:, 1] / rho
    theta = knee_down_dh_angles(rel, 0.0, g.l1, g.l2, g.l3).q     # NaN out of reach
    theta2, theta3 = theta[:, 1], theta[:, 2]
    c2, s2 = np.cos(theta2), np.sin(theta2)
    c23, s23 = np.cos(theta2 + theta3), np.sin(theta2 + theta3)
    a_r = (g.m0_k00 + g.m1 * (g.l1 + g.k10 * c2 + g.k12 * s2)
           + g.m2 * (g.l1 + g.l2 * c2 + g.k20 * c23 + g.k22 * s23))
    out = g.hip_moment.copy()
    out[:, 0] += a_r * c - g.a_t * s
    out[:, 1] += a_r * s + g.a_t * c
    if not horizontal:
        out[:, 2] += (g.m0_k02 + g.m1 * (g.k10 * s2 - g.k12 * c2)
                      + g.m2 * (g.l2 * s2 + g.k20 * s23 - g.k22 * c23))
    return out


class _Rows(NamedTuple):
    """:class:`_LegConstants` gathered for the rows of one :func:`_leg_moments` call, with the
    products that do not depend on the targets formed once (the same operands in the same
    order as forming them per call: the same values)."""

    hip: np.ndarray
    l1: np.ndarray
    l2: np.ndarray
    l3: np.ndarray
    m1: np.ndarray
    m2: np.ndarray
    k10: np.ndarray
    k12: np.ndarray
    k20: np.ndarray
    k22: np.ndarray
    m0_k00: np.ndarray       # m0 * k00
    m0_k02: np.ndarray       # m0 * k02
    a_t: np.ndarray          # m0 k01 - m1 k11 - m2 k21
    hip_moment: np.ndarray   # hip * (m0 + m1 + m2)


def _rows_of(const: _LegConstants, leg: np.ndarray) -> _Rows:
    """:class:`_Rows` of ``const`` for the leg indices ``leg`` (R,), memoised (a planner run
    asks for a few row patterns thousands of times: the n configurations of a swing)."""
    leg = np.asarray(leg)
    return _memoised(const, ("rows", leg.tobytes()), lambda: _gathered_rows(const, leg))


def _gathered_rows(const: _LegConstants, leg: np.ndarray) -> _Rows:
    """_rows_of without its memo."""
    l1, l2, l3 = const.length[leg].T
    m = const.mass[leg]
    k = const.com[leg]
    return _Rows(hip=const.hip[leg], l1=l1, l2=l2, l3=l3, m1=m[:, 1], m2=m[:, 2], k10=k[:, 1, 0],
                 k12=k[:, 1, 2], k20=k[:, 2, 0], k22=k[:, 2, 2], m0_k00=m[:, 0] * k[:, 0, 0],
                 m0_k02=m[:, 0] * k[:, 0, 2],
                 a_t=m[:, 0] * k[:, 0, 1] - m[:, 1] * k[:, 1, 1] - m[:, 2] * k[:, 2, 1],
                 hip_moment=const.hip[leg] * m.sum(axis=1)[:, None])


def _leg_moments_any(legs: tuple, leg: np.ndarray, position_foot_in_base: np.ndarray
                     ) -> np.ndarray:
    """Σ m_i c_i [kg m], (R, 3), as :func:`_leg_moments`, for legs of any family: the
    family's IK (silo4kin.legs) then silo4kin.com.leg_mass_moment_in_base, leg by leg."""
    out = np.full((leg.size, 3), np.nan)
    for k, geo in enumerate(legs):
        rows = np.flatnonzero(leg == k)
        if rows.size:
            q = leg_families.inverse_kinematics(geo, position_foot_in_base[rows]).q
            out[rows] = leg_mass_moment_in_base(geo, q)
    return out


_PLANNING_ROBOTS: weakref.WeakSet = weakref.WeakSet()


@lru_cache(maxsize=16)
def _shifted(robot: Robot) -> Robot:
    com = np.asarray(robot.position_body_com_in_base, dtype=float)
    shifted = replace(robot, legs=legs_in_body_com_frame(robot.legs, com)) if np.any(com) \
        else robot
    _PLANNING_ROBOTS.add(shifted)
    return shifted


def planning_robot(robot: Robot) -> Robot:
    """The robot with its hips measured from the body CoG, the frame B the planner works in
    (design.md): the one implementation of the frame change. For SILO4 the URDF root is the
    CoG and the robot is returned unchanged; for another URDF (tests/robots/mantis.urdf: CoG
    4.5 cm ahead of and 4.2 cm above the root) only the legs' points in B move
    (LegFamily.moved_by), joint values are unaffected.

    Idempotent: a robot this function returned is returned as it is, so every public
    function of the planner can take either and they all mean the same heights. Cached per
    robot object, so the workspace caches keyed on it stay warm across plans."""
    if robot in _PLANNING_ROBOTS:
        return robot
    return _shifted(robot)


@lru_cache(maxsize=16)
def planning_model(robot: Robot) -> PlanningModel:
    """The :class:`PlanningModel` of a robot, cached per robot object.

    Either leg family: insect legs use the fused closed form of :func:`_leg_moments`, mammal
    legs their own IK and mass moments (silo4kin.legs, silo4kin.mammal).
    """
    framed = planning_robot(robot)
    return PlanningModel(robot=robot, planning_robot=framed, legs=tuple(framed.legs),
                         total_mass=float(robot.total_mass), body_mass=float(robot.body_mass),
                         position_body_com_in_root=np.array(robot.position_body_com_in_base,
                                                            dtype=float))


def as_planning_model(robot_or_model: Robot | PlanningModel) -> PlanningModel:
    """A PlanningModel from either a Robot (URDF frame) or a PlanningModel (returned as is)."""
    if isinstance(robot_or_model, PlanningModel):
        return robot_or_model
    return planning_model(robot_or_model)
