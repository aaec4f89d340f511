"""What the mammal-leg closed form (silo4kin/mammal.py) knows about one leg: the HAA point and
pitch axis, the planar offsets of the thigh and shank, signs, limits, knee branch and link
masses, all read from the model at q = 0 (silo4kin/mammal_extract.py)."""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class MammalLegGeometry:
    """Everything the mammal-leg closed form needs about one leg (shapes in brackets).

    Attributes:
        name: leg name ("LF", "RF", "LH", "RH").
        joint_names: URDF names of (hip ab/ad, hip flexion, knee) joints.
        foot_frame: frame at the foot (for a ball foot: the ball's centre).
        position_hip_in_base: a point on the HAA axis (its joint origin) in the base frame [m] (3,).
        axis_pitch_in_base: HFE axis e_a at q1 = 0, unit, ⊥ x̂ (3,).
        abduction_sign: s1: the HAA axis is s1·x̂.
        knee_sign: s3: the knee axis is s3·e_a.
        lateral_offset: d = e_a·(p_foot - p1) [m].
        offset_pitch_in_plane: c0, HFE point in the leg plane relative to p1 [m] (2,).
        thigh_in_plane: u, HFE point to knee point [m] (2,).
        shank_in_plane: w, knee point to foot [m] (2,).
        q_lower, q_upper: joint limits, URDF values [rad] (3,).
        knee_branch: σ = +1 or -1, the IK branch the robot's rest pose uses.
        foot_below_sign: sign of the planar n coordinate of the rest pose's foot (-1: below).
        axis_misalignment_rad: how far the URDF's axes are from the ideal (HAA along x, pitch
            axes parallel and ⊥ x) [rad]; the closed form assumes 0 (check.py's tolerance).
        position_pitch_in_base, position_knee_in_base: HFE and KFE joint origins at q = 0 [m] (3,).
        link_masses: masses of (hip, thigh, shank) with their fixed children [kg] (3,).
        link_coms_at_zero: their centres of mass at q = 0 in the base frame [m] (3, 3).
    """

    name: str
    joint_names: tuple[str, str, str]
    foot_frame: str
    position_hip_in_base: np.ndarray
    axis_pitch_in_base: np.ndarray
    abduction_sign: float
    knee_sign: float
    lateral_offset: float
    offset_pitch_in_plane: np.ndarray
    thigh_in_plane: np.ndarray
    shank_in_plane: np.ndarray
    q_lower: np.ndarray
    q_upper: np.ndarray
    knee_branch: int
    foot_below_sign: float
    axis_misalignment_rad: float = 0.0
    position_pitch_in_base: np.ndarray = field(default_factory=lambda: np.zeros(3))
    position_knee_in_base: np.ndarray = field(default_factory=lambda: np.zeros(3))
    link_masses: np.ndarray = field(default_factory=lambda: np.zeros(3))
    link_coms_at_zero: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    family = "mammal"

    @property
    def size_m(self) -> float:
        """Sum of the leg's offsets and link lengths [m] (a scale for tolerances)."""
        return float(
            abs(self.lateral_offset)
            + np.linalg.norm(self.offset_pitch_in_plane)
            + np.linalg.norm(self.thigh_in_plane)
            + np.linalg.norm(self.shank_in_plane)
        )

    @functools.cached_property
    def axis_normal_in_base(self) -> np.ndarray:
        """e_n = x̂ × e_a at q1 = 0 (3,), read-only; computed once per leg (every call of
        the leg's kinematics reads it: 273 k np.cross calls in go2's height search)."""
        out = np.cross([1.0, 0.0, 0.0], self.axis_pitch_in_base)
        out.setflags(write=False)
        return out

    @property
    def signs(self) -> np.ndarray:
        """θ = signs * q, shape (3,)."""
        return np.array([self.abduction_sign, 1.0, self.knee_sign])

    @property
    def reach(self) -> tuple[float, float]:
        """(min, max) planar distance from the HFE point to the foot [m]."""
        a = float(np.linalg.norm(self.thigh_in_plane))
        b = float(np.linalg.norm(self.shank_in_plane))
        return abs(a - b), a + b
