"""Load a robot: xacro -> URDF -> Pinocchio models (fixed base, free flyer, visuals) + legs.

    robot = load_robot()                                  # SILO4 from urdf/silo4.urdf.xacro
    robot = load_robot(xacro_args={"L3": 0.3})            # a variant, one argument away
    robot = load_robot("my_robot.urdf")                   # a plain URDF

The file is read and expanded by silo4kin/robot_files.py (xacro: silo4kin/xacro_files.py); the
legs are found from the geometry (silo4kin/discovery.py) and measured (geometry.py, mammal.py).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import pinocchio as pin

from .body_frame import body_com
from .discovery import (
    MAMMAL,
    NotInsectLegError,
    discover_legs,
    discover_mammal_legs,
    leg_family,
)
from .errors import RobotDescriptionError
from .geometry import LEG_NAMES, LegGeometry, extract_leg_geometry
from .knee_convention import knee_convention
from .mammal import MammalLegGeometry
from .mammal_extract import extract_mammal_leg_geometry
from .memo import memoised
from .robot_files import DEFAULT_XACRO, STANDARD_GRAVITY, build_models, read_robot_description
from .robot_library import (
    SILO4,
    RobotSource,
    canonical_robot_name,
    looks_like_name,
    resolve_example_robot,
)
from .shapes import tibia_radii_m

#: DEFAULT_XACRO and STANDARD_GRAVITY (defined in robot_files.py) are served from here too.
__all__ = ["DEFAULT_XACRO", "STANDARD_GRAVITY", "Robot", "load_robot", "silo4_leg_names"]

#: Joint naming convention of docs/design.md: {leg}_{hip_yaw,hip_pitch,knee}, foot frame {leg}_foot.
JOINT_SUFFIXES: tuple[str, str, str] = ("hip_yaw", "hip_pitch", "knee")


@dataclass(frozen=True, eq=False)
class Robot:
    """A loaded insect-leg quadruped.

    Attributes:
        name: robot name from the URDF.
        urdf_xml: the expanded URDF text.
        model: fixed-base Pinocchio model, nq = 12; its root frame is the URDF's root link
            (for SILO4 the body CoG; for other robots see position_body_com_in_base).
        model_free_flyer: the same robot on a free-flyer joint, nq = 19.
        visual_model: visual geometry of the fixed-base model.
        legs: leg geometry in array order LF, RF, LH, RH.
        source: file the robot was loaded from, or None.
        xacro_args: the xacro arguments used (strings).
        family: leg family, "insect" (vertical first axis, the thesis's) or "mammal" (hip
            ab/adduction about x first); legs are LegGeometry or MammalLegGeometry.
        library_name: the name it was loaded by (``load_robot("go2")``), or None.
    """

    name: str
    urdf_xml: str = field(repr=False)
    model: pin.Model = field(repr=False)
    model_free_flyer: pin.Model = field(repr=False)
    visual_model: pin.GeometryModel = field(repr=False)
    legs: tuple[LegGeometry, ...] = field(repr=False)
    source: Path | None = None
    xacro_args: Mapping[str, str] = field(default_factory=dict)
    family: str = "insect"
    library_name: str | None = None
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __getstate__(self) -> dict:
        """Pickled without the memo (results computed from the robot, some of them Pinocchio
        objects that do not pickle, e.g. the RNEA's ModelPool): the copy rebuilds them."""
        state = dict(self.__dict__)
        state["_memo"] = {}
        return state

    @property
    def joint_names(self) -> list[str]:
        """The 12 actuated joint names in array order (leg by leg, yaw/pitch/knee)."""
        return [jn for leg in self.legs for jn in leg.joint_names]

    @property
    def q_index(self) -> np.ndarray:
        """Index into the fixed-base model's q of each of our 12 joints, shape (12,).

        Pinocchio orders joints by name, not by file: always map through this. Computed
        once per robot (its memo; read-only: every batch of torques maps through it).
        """

        def compute() -> np.ndarray:
            idx = np.array(
                [self.model.joints[self.model.getJointId(n)].idx_q for n in self.joint_names]
            )
            idx.setflags(write=False)
            return idx

        return memoised(self._memo, "q_index", compute)

    @property
    def body_mass(self) -> float:
        """Mass of the base link alone [kg]."""
        return float(self.model_free_flyer.inertias[1].mass)

    @property
    def total_mass(self) -> float:
        """Body plus legs [kg]."""
        return float(pin.computeTotalMass(self.model_free_flyer))

    @property
    def position_body_com_in_base(self) -> np.ndarray:
        """Body (base link) centre of mass in the base frame [m], shape (3,)."""
        return np.array(self.model_free_flyer.inertias[1].lever)

    def to_pinocchio_q(self, q: np.ndarray) -> np.ndarray:
        """Our joint order (..., 12) -> Pinocchio fixed-base order (..., 12)."""
        q = np.asarray(q, dtype=float)
        out = np.empty_like(q)
        out[..., self.q_index] = q
        return out

    def from_pinocchio_q(self, q_pin: np.ndarray) -> np.ndarray:
        """Pinocchio fixed-base order (..., 12) -> our joint order (..., 12)."""
        return np.asarray(q_pin, dtype=float)[..., self.q_index]

    def leg(self, name: str) -> LegGeometry:
        """Leg by name; raises with the valid names."""
        for leg in self.legs:
            if leg.name == name:
                return leg
        raise RobotDescriptionError(f"no leg {name!r}; legs are {[leg.name for leg in self.legs]}")


def silo4_leg_names(model: pin.Model) -> dict[str, tuple[tuple[str, str, str], str]]:
    """Legs by the SILO4 naming convention: {leg}_{hip_yaw,hip_pitch,knee}, frame {leg}_foot.

    ``load_robot`` no longer uses this (it discovers legs from the geometry,
    :func:`silo4kin.discovery.discover_legs`); kept to check that both agree on SILO4.
    """
    legs = {}
    for leg in LEG_NAMES:
        names = tuple(f"{leg}_{s}" for s in JOINT_SUFFIXES)
        missing = [n for n in names if not model.existJointName(n)]
        if missing:
            found = [n for n in model.names[1:]]
            raise RobotDescriptionError(
                f"leg {leg}: expected joints {list(names)}, missing {missing}; "
                f"the model has joints {found}"
            )
        legs[leg] = (names, f"{leg}_foot")
    return legs  # type: ignore[return-value]


def load_robot(
    path: str | Path | None = None,
    xacro_args: Mapping[str, object] | None = None,
    package_dirs: list[str] | None = None,
) -> Robot:
    """Load a quadruped of a supported leg family; legs are discovered from the geometry.

    Args:
        path: ``.urdf`` or ``.urdf.xacro`` file, or a robot name (``"silo4"``, or an
            example-robot-data quadruped such as ``"go2"``: robot_library.py); default
            ``urdf/silo4.urdf.xacro``.
        xacro_args: xacro argument overrides, e.g. ``{"L3": 0.3}``.
        package_dirs: folders to resolve mesh paths against.

    Raises:
        NotInsectLegError: the robot is not an insect-leg quadruped (the message names the
            chain, the joint and the broken assumption; docs/robots.md).
        RobotDescriptionError: missing/malformed file, unknown argument, body without mass.
    """
    named: RobotSource | None = None
    if path is not None and isinstance(path, str) and looks_like_name(path):
        if canonical_robot_name(path) == SILO4:
            path = None
        else:
            named = resolve_example_robot(path)
            path = named.urdf
            package_dirs = [*named.package_dirs, *(package_dirs or [])]
    src = Path(path) if path is not None else DEFAULT_XACRO
    urdf_xml = read_robot_description(src, xacro_args, package_dirs or ())
    model, model_ff, visual = build_models(urdf_xml, package_dirs)
    try:
        family = leg_family(model)
        legs: tuple[LegGeometry, ...] | tuple[MammalLegGeometry, ...]
        if family == MAMMAL:
            rest = _reference_posture(model, named)
            legs = tuple(
                extract_mammal_leg_geometry(
                    model,
                    leg,
                    names,
                    foot,
                    None
                    if rest is None
                    else rest[[model.joints[model.getJointId(n)].idx_q for n in names]],
                )
                for leg, (names, foot) in discover_mammal_legs(model).items()
            )
        else:
            found = discover_legs(model)
            legs = tuple(
                extract_leg_geometry(model, leg, names, foot)
                for leg, (names, foot) in found.items()
            )
            for leg in legs:
                knee_convention(leg)  # refuses a knee that cannot bend down
            radii = tibia_radii_m(urdf_xml, [leg.joint_names[2] for leg in legs])
            legs = tuple(replace(leg, tibia_radius_m=radii[leg.joint_names[2]]) for leg in legs)
        body_com(model)  # refuses a massless body: its CoG is the stability point
        check_leg_scale(model, legs)
    except RobotDescriptionError as exc:
        raise type(exc)(f"{src.name}: {exc}", *_extra_args(exc)) from exc
    return Robot(
        name=model.name,
        urdf_xml=urdf_xml,
        model=model,
        model_free_flyer=model_ff,
        visual_model=visual,
        legs=legs,  # type: ignore[arg-type]
        source=src,
        xacro_args={k: str(v) for k, v in (xacro_args or {}).items()},
        family=family,
        library_name=named.name if named else None,
    )


#: Longest plausible leg, hip joint to foot along the chain [m]: a longer one is a URDF
#: exported in millimetres (or centimetres), or a xacro argument given in them; planning
#: such a giant would search for minutes.
MAX_PLAUSIBLE_LEG_LENGTH_M = 10.0


def leg_length_m(model: pin.Model, joint_names: tuple[str, ...], foot_frame: str) -> float:
    """Length of a leg at q = 0 [m]: the polyline through its joint origins to the foot."""
    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    points = [data.oMi[model.getJointId(n)].translation for n in joint_names]
    points.append(data.oMf[model.getFrameId(foot_frame)].translation)
    return float(sum(np.linalg.norm(b - a) for a, b in zip(points, points[1:])))


def check_leg_scale(model: pin.Model, legs: tuple[LegGeometry | MammalLegGeometry, ...]) -> None:
    """Refuse legs longer than MAX_PLAUSIBLE_LEG_LENGTH_M, naming the likely unit slip.

    Raises:
        RobotDescriptionError: "leg length 240 m: did you give millimetres?".
    """
    longest = max(leg_length_m(model, leg.joint_names, leg.foot_frame) for leg in legs)
    if longest <= MAX_PLAUSIBLE_LEG_LENGTH_M:
        return
    unit = "millimetres" if longest >= 20.0 else "centimetres"  # 20 m: a 2 cm leg in mm
    raise RobotDescriptionError(
        f"leg length {longest:.4g} m: did you give {unit}? lengths in a URDF and in xacro "
        f"arguments are in metres (a leg longer than {MAX_PLAUSIBLE_LEG_LENGTH_M:g} m is "
        "refused)"
    )


def _reference_posture(model: pin.Model, named: RobotSource | None) -> np.ndarray | None:
    """The SRDF's standing configuration of a named robot (fixed-base q, Pinocchio order)."""
    if named is None or named.srdf is None or named.reference_posture is None:
        return None
    try:
        pin.loadReferenceConfigurations(model, str(named.srdf), False)
        return np.array(model.referenceConfigurations[named.reference_posture])
    except (RuntimeError, ValueError, KeyError, IndexError):
        return None  # no usable standing pose: the knee branch comes from the limits


def _extra_args(exc: RobotDescriptionError) -> tuple[object, ...]:
    """Constructor arguments after the message, to re-raise an error with the file name."""
    return (exc.chain,) if isinstance(exc, NotInsectLegError) else ()
