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
  :meth:`moving_swing_com_in_world` the same while the base moves (the continuous crawl),
  both computed by planner/stability/swing_com.py and memoised on the model.

:func:`planning_model` and :func:`planning_robot` are kept on the robot object (its memo,
silo4kin.memo), so the planner's caches on them stay warm across plans.
:func:`~planner.path.plan_path` takes a Robot (URDF frame) or a PlanningModel and converts
with :func:`as_planning_model`; the workspace and sampling functions it calls get
``planning_robot`` (the workspace's public functions accept either frame and convert with it).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np

from planner.stability import swing_com
from planner.stability.swing_com import LegConstants
from silo4kin.body_frame import legs_in_body_com_frame
from silo4kin.com import legs_com_offset
from silo4kin.leg_family import INSECT, LegFamily, family_of
from silo4kin.memo import memo_of, memoised
from silo4kin.robot import Robot

#: Configurations of a swing checked per transfer (τ = 0 .. 1, evenly spaced). S_m along a
#: straight segment is concave (a minimum of linear functions), so between two checked
#: configurations 1 % of a swing apart it can dip below both only by the curvature of the
#: CoM path: measured 3e-7 m (circle at h = 0.6 m sampled at 1000 instead of 100 per unit).
SWING_CHECK_SAMPLES = 101
#: Entries of a PlanningModel's swing-CoM memo (~0.3 kB each).
SWING_COM_MEMO_SIZE = 8192


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
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    @property
    def name(self) -> str:
        """The robot's name."""
        return self.robot.name

    def com_offset_in_base(self, q: np.ndarray) -> np.ndarray:
        """Whole-robot CoM minus body CoM in B [m], (N, 3), for joint values q (N, 12) [rad]."""
        return legs_com_offset(self.legs, q, self.total_mass)

    def com_in_world(
        self, q: np.ndarray, position_base_in_world: np.ndarray, yaw_base_in_world: np.ndarray
    ) -> np.ndarray:
        """Whole-robot CoM in W [m], (N, 3): base (N, 3) [m] + R_z(yaw) (N,) [rad] x offset."""
        off = self.com_offset_in_base(q)
        c, s = np.cos(yaw_base_in_world), np.sin(yaw_base_in_world)
        out = np.array(position_base_in_world, dtype=float, copy=True)
        out[:, 0] += c * off[:, 0] - s * off[:, 1]
        out[:, 1] += s * off[:, 0] + c * off[:, 1]
        out[:, 2] += off[:, 2]
        return out

    def swing_com_in_world(
        self,
        position_base_in_world: np.ndarray,
        yaw: float,
        position_feet_in_world: np.ndarray,
        leg: int,
        foothold_end_in_world: np.ndarray,
        swing_height_m: float,
        n: int = SWING_CHECK_SAMPLES,
        smooth: bool = False,
    ) -> np.ndarray:
        """Whole-robot CoM (x, y) in W [m], (n, 2), over the swing of ``leg`` from its foot in
        ``position_feet_in_world`` (4, 3) [m] to ``foothold_end_in_world`` (3,) [m] with the
        base standing at (3,) [m], yaw [rad]: the swing path of
        planner/trajectory/sampling.py (cosine blend in x, y, lift of eq 5.4 by
        ``swing_height_m``; with ``smooth`` the quintic of eq 5.16 and the smooth lift, as
        the smooth gaits are sampled) at n evenly spaced τ. NaN rows where a foot is out of
        reach (the sample verification reports those).

        The step builder calls this for every transfer (planner/stability/swing_com.py: one
        vectorised IK and CoM pass). Memoised on the model for the exact inputs (the ditch's
        route search plans the same approach for every crossing angle); the result is
        read-only."""
        key = _swing_key(
            "standing smooth" if smooth else "standing",
            position_base_in_world,
            yaw,
            position_feet_in_world,
            leg,
            foothold_end_in_world,
            float(swing_height_m),
            n,
        )
        return self._memoised(
            key,
            lambda: (
                swing_com.swing_com_in_world(
                    self,
                    position_base_in_world,
                    yaw,
                    position_feet_in_world,
                    leg,
                    foothold_end_in_world,
                    swing_height_m,
                    n,
                    smooth,
                ),
            ),
        )[0]

    def moving_swing_com_in_world(
        self,
        position_base_start_in_world: np.ndarray,
        position_base_end_in_world: np.ndarray,
        yaw: float,
        position_feet_in_world: np.ndarray,
        leg: int,
        foothold_end_in_world: np.ndarray,
        swing_height_m: float,
        n: int = SWING_CHECK_SAMPLES,
    ) -> tuple[np.ndarray, np.ndarray]:
        """(CoM (n, 2), base (n, 2)) in W [m] over the swing of ``leg`` while the base moves
        from its start to its end (3,) [m] (the continuous crawl, planner/gaits/crawl.py):
        base and swing foot x, y on the quintic of eq 5.16, the lift of
        trajectories.smooth_lift, as planner/trajectory/sampling.py samples them (smooth
        profiles), every leg's IK at each of the n configurations. NaN rows where a foot is
        out of reach. Memoised as :meth:`swing_com_in_world`; the results are read-only."""
        key = (
            "moving",
            np.asarray(position_base_start_in_world, dtype=float).tobytes(),
            np.asarray(position_base_end_in_world, dtype=float).tobytes(),
            float(yaw),
            np.asarray(position_feet_in_world, dtype=float).tobytes(),
            int(leg),
            np.asarray(foothold_end_in_world, dtype=float).tobytes(),
            float(swing_height_m),
            int(n),
        )
        return self._memoised(
            key,
            lambda: swing_com.moving_swing_com_in_world(
                self,
                position_base_start_in_world,
                position_base_end_in_world,
                yaw,
                position_feet_in_world,
                leg,
                foothold_end_in_world,
                swing_height_m,
                n,
            ),
        )

    def swing_zmp_in_world(
        self,
        position_base_in_world: np.ndarray,
        yaw: float,
        position_feet_in_world: np.ndarray,
        leg: int,
        foothold_end_in_world: np.ndarray,
        swing: swing_com.SwingTiming,
        n: int = SWING_CHECK_SAMPLES,
    ) -> np.ndarray:
        """The zero-moment point (x, y) in W [m], (n, 2), over the swing of ``leg`` with the
        base standing (planner/stability/swing_com.py swing_zmp_in_world), memoised as
        :meth:`swing_com_in_world`; read-only."""
        key = _swing_key(
            "zmp",
            position_base_in_world,
            yaw,
            position_feet_in_world,
            leg,
            foothold_end_in_world,
            tuple(swing),
            n,
        )
        return self._memoised(
            key,
            lambda: (
                swing_com.swing_zmp_in_world(
                    self,
                    position_base_in_world,
                    yaw,
                    position_feet_in_world,
                    leg,
                    foothold_end_in_world,
                    swing,
                    n,
                ),
            ),
        )[0]

    def swing_zmp_excursion_m(
        self,
        position_base_in_world: np.ndarray,
        yaw: float,
        position_feet_in_world: np.ndarray,
        leg: int,
        foothold_end_in_world: np.ndarray,
        swing: swing_com.SwingTiming,
        n: int = SWING_CHECK_SAMPLES,
    ) -> float:
        """Largest distance [m] of the zero-moment point from the whole-robot CoM's ground
        projection over the swing of :meth:`swing_zmp_in_world` (the dynamic part the swing's
        accelerations add, planner/gaits/swing_pace.py), memoised as it; NaN where a foot is
        out of reach."""
        key = _swing_key(
            "zmp excursion",
            position_base_in_world,
            yaw,
            position_feet_in_world,
            leg,
            foothold_end_in_world,
            tuple(swing),
            n,
        )

        def compute() -> tuple:
            com, zmp = swing_com.swing_com_and_zmp_in_world(
                self,
                position_base_in_world,
                yaw,
                position_feet_in_world,
                leg,
                foothold_end_in_world,
                swing,
                n,
            )
            return (np.array(np.max(np.linalg.norm(zmp - com, axis=1))),)

        return float(self._memoised(key, compute)[0])

    def _memoised(self, key: tuple, compute: Any) -> Any:
        """``compute()`` (a tuple of arrays, made read-only) from the model's memo."""

        def read_only() -> tuple:
            result = compute()
            for array in result:
                array.setflags(write=False)
            return result

        return memoised(self._memo, key, read_only, SWING_COM_MEMO_SIZE)

    @property
    def leg_family(self) -> LegFamily:
        """The robot's :class:`~silo4kin.leg_family.LegFamily` (insect for no legs)."""
        return family_of(self.legs[0]) if self.legs else INSECT

    @property
    def family(self) -> str:
        """The name of :attr:`leg_family`, "insect" or "mammal" (for outputs)."""
        return self.leg_family.name

    @cached_property
    def leg_constants(self) -> LegConstants:
        """The insect legs' constants of planner/stability/swing_com.leg_moments."""
        return LegConstants.of(self.legs)


def planning_robot(robot: Robot) -> Robot:
    """The robot with its hips measured from the body CoG, the frame B the planner works in
    (design.md): the one implementation of the frame change. For SILO4 the URDF root is the
    CoG and the robot is returned unchanged; for another URDF (tests/robots/mantis.urdf: CoG
    4.5 cm ahead of and 4.2 cm above the root) only the legs' points in B move
    (LegFamily.moved_by), joint values are unaffected.

    Idempotent: a robot this function returned is returned as it is, so every public
    function of the planner can take either and they all mean the same heights. Kept in the
    robot's memo, so the workspace caches on it stay warm across plans."""
    return memoised(memo_of(robot), "planning_robot", lambda: _shifted(robot))


def _shifted(robot: Robot) -> Robot:
    com = np.asarray(robot.position_body_com_in_base, dtype=float)
    if not np.any(com):
        return robot
    shifted = replace(robot, legs=legs_in_body_com_frame(robot.legs, com))
    memo_of(shifted)["planning_robot"] = shifted
    return shifted


def planning_model(robot: Robot) -> PlanningModel:
    """The :class:`PlanningModel` of a robot, kept in the robot's memo.

    Either leg family: insect legs use the fused closed form of
    planner/stability/swing_com.leg_moments, mammal legs their own IK and mass moments
    (silo4kin.legs, silo4kin.mammal).
    """

    def build() -> PlanningModel:
        framed = planning_robot(robot)
        return PlanningModel(
            robot=robot,
            planning_robot=framed,
            legs=tuple(framed.legs),
            total_mass=float(robot.total_mass),
            body_mass=float(robot.body_mass),
            position_body_com_in_root=np.array(robot.position_body_com_in_base, dtype=float),
        )

    return memoised(memo_of(robot), "planning_model", build)


def as_planning_model(robot_or_model: Robot | PlanningModel) -> PlanningModel:
    """A PlanningModel from either a Robot (URDF frame) or a PlanningModel (returned as is)."""
    if isinstance(robot_or_model, PlanningModel):
        return robot_or_model
    return planning_model(robot_or_model)


def _swing_key(
    kind: str,
    position_base_in_world: np.ndarray,
    yaw: float,
    position_feet_in_world: np.ndarray,
    leg: int,
    foothold_end_in_world: np.ndarray,
    swing: object,
    n: int,
) -> tuple:
    """The memo key of a standing-base swing query (``kind``: "standing" CoM, "zmp" or "zmp
    excursion";
    ``swing``: its swing height or timing, hashable)."""
    return (
        kind,
        np.asarray(position_base_in_world, dtype=float).tobytes(),
        float(yaw),
        np.asarray(position_feet_in_world, dtype=float).tobytes(),
        int(leg),
        np.asarray(foothold_end_in_world, dtype=float).tobytes(),
        swing,
        int(n),
    )
