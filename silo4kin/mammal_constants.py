"""The numbers of a mammal leg's closed forms (silo4kin/mammal.py) that its IK and mass
moment read, of one leg or stacked per row for targets of several legs (one pass)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .mammal_geometry import MammalLegGeometry
from .memo import memo_of, memoised


class MammalConstants(NamedTuple):
    """The numbers :func:`inverse_kinematics` and :func:`leg_mass_moment_in_base` read, of one
    leg (:meth:`of_leg`: shapes as in MammalLegGeometry) or stacked per row for targets of
    several legs (:meth:`of_rows`: a leading axis R, gathered from :meth:`of_leg`'s values, so
    the same numbers bit for bit)."""

    position_hip_in_base: np.ndarray  # p1 [m] (3,) | (R, 3)
    axis_pitch_in_base: np.ndarray  # e_a (3,) | (R, 3)
    axis_normal_in_base: np.ndarray  # e_n (3,) | (R, 3)
    lateral_offset: np.ndarray  # d [m] () | (R,)
    offset_pitch_in_plane: np.ndarray  # c0 [m] (2,) | (R, 2)
    thigh_in_plane: np.ndarray  # u [m] (2,) | (R, 2)
    shank_in_plane: np.ndarray  # w [m] (2,) | (R, 2)
    thigh_length: np.ndarray  # |u| [m] () | (R,)
    shank_length: np.ndarray  # |w| [m] () | (R,)
    thigh_angle: np.ndarray  # α_u = atan2(u) [rad] () | (R,)
    shank_angle: np.ndarray  # α_w [rad] () | (R,)
    signs: np.ndarray  # θ = signs * q (3,) | (R, 3)
    q_lower: np.ndarray  # [rad] (3,) | (R, 3)
    q_upper: np.ndarray  # [rad] (3,) | (R, 3)
    knee_branch: np.ndarray  # σ () | (R,)
    foot_below_sign: np.ndarray  # () | (R,)
    position_pitch_in_base: np.ndarray  # p2 [m] (3,) | (R, 3)
    position_knee_in_base: np.ndarray  # p3 [m] (3,) | (R, 3)
    link_masses: np.ndarray  # [kg] (3,) | (R, 3)
    link_mass_total: np.ndarray  # [kg] (1,) | (R, 1)
    link_coms_at_zero: np.ndarray  # [m] (3, 3) | (R, 3, 3)

    @classmethod
    def of_leg(cls, leg: MammalLegGeometry) -> MammalConstants:
        """One leg's constants, kept in the leg's memo (read-only)."""
        return memoised(memo_of(leg), "mammal_constants", lambda: cls._computed(leg))

    @classmethod
    def _computed(cls, leg: MammalLegGeometry) -> MammalConstants:
        """of_leg without its memo."""
        u, w = leg.thigh_in_plane, leg.shank_in_plane
        masses = np.array(leg.link_masses, dtype=float)
        out = cls(
            np.array(leg.position_hip_in_base, dtype=float),
            np.array(leg.axis_pitch_in_base, dtype=float),
            leg.axis_normal_in_base,
            np.array(leg.lateral_offset, dtype=float),
            np.array(leg.offset_pitch_in_plane, dtype=float),
            np.array(u, dtype=float),
            np.array(w, dtype=float),
            np.array(float(np.linalg.norm(u))),
            np.array(float(np.linalg.norm(w))),
            np.array(np.arctan2(u[1], u[0])),
            np.array(np.arctan2(w[1], w[0])),
            leg.signs,
            np.array(leg.q_lower, dtype=float),
            np.array(leg.q_upper, dtype=float),
            np.array(leg.knee_branch, dtype=float),
            np.array(leg.foot_below_sign, dtype=float),
            np.array(leg.position_pitch_in_base, dtype=float),
            np.array(leg.position_knee_in_base, dtype=float),
            masses,
            np.array([masses.sum()]),
            np.array(leg.link_coms_at_zero, dtype=float),
        )
        for array in out:
            array.setflags(write=False)
        return out

    @classmethod
    def of_rows(cls, legs: tuple[MammalLegGeometry, ...], leg_index: np.ndarray) -> MammalConstants:
        """Row i holds the constants of leg ``legs[leg_index[i]]``, (R, ...)."""
        per_leg = [cls.of_leg(leg) for leg in legs]
        idx = np.asarray(leg_index)
        return cls(*(np.stack(values)[idx] for values in zip(*per_leg)))
