"""The whole-robot CoM over a leg's swing, the configurations the step builder checks.

:func:`swing_com_in_world` (base standing) and :func:`moving_swing_com_in_world` (base moving,
the continuous crawl) put the three stance legs and the n swing configurations through one
vectorised knee-down IK and link-moment pass (:func:`leg_moments`, insect legs) or each leg's
own IK (:func:`leg_moments_any`, other families); planner.model.PlanningModel memoises them
per model. tests/test_com.py checks them against silo4kin's IK and silo4kin.com.
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from planner.trajectory.profiles import cosine_blend, lift, quintic_blend, smooth_lift
from silo4kin import legs as leg_families
from silo4kin import mammal
from silo4kin.com import leg_mass_moment_in_base
from silo4kin.frames import rotation_z
from silo4kin.knee_down_ik import IK_COS_SLACK
from silo4kin.leg_family import INSECT, MAMMAL, family_of
from silo4kin.mammal_constants import MammalConstants
from silo4kin.memo import memoised

if TYPE_CHECKING:
    from planner.model import PlanningModel

#: Row patterns kept per :class:`LegConstants` (a planner run asks for a few).
ROW_MEMO_SIZE = 256


class LegConstants(NamedTuple):
    """Per-leg numbers of :func:`leg_moments`, each indexed by leg (4, ...), with the memo of
    their gathered rows (:func:`rows_of`)."""

    hip: np.ndarray  # (4, 3) hip in B [m]
    length: np.ndarray  # (4, 3) L1, L2, L3 [m]
    mass: np.ndarray  # (4, 3) link masses [kg]
    com: np.ndarray  # (4, 3, 3) link CMs in their DH frames [m]
    row_memo: dict  # leg index bytes -> _Rows

    @classmethod
    def of(cls, legs: tuple) -> LegConstants:
        """The constants of insect legs ``legs``."""
        return cls(
            hip=np.array([g.position_hip_in_base for g in legs], dtype=float),
            length=np.array([(g.L1, g.L2, g.L3) for g in legs], dtype=float),
            mass=np.array([[lk.mass for lk in g.links] for g in legs], dtype=float),
            com=np.array([[lk.com for lk in g.links] for g in legs], dtype=float),
            row_memo={},
        )


@lru_cache(maxsize=8)
def _moving_swing_profile(
    n: int, swing_height_m: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(quintic blend (n, 1), smooth lift [m] (n,), leg rows (4 n,)) of
    moving_swing_com_in_world's n configurations, read-only (the same for every swing)."""
    tau = np.linspace(0.0, 1.0, n)
    out = (
        quintic_blend(tau, 1.0).s[:, None],
        smooth_lift(tau, 1.0, swing_height_m).s,
        np.tile(np.arange(4), n),
    )
    for array in out:
        array.setflags(write=False)
    return out


def swing_com_in_world(
    model: PlanningModel,
    position_base_in_world: np.ndarray,
    yaw: float,
    position_feet_in_world: np.ndarray,
    leg: int,
    foothold_end_in_world: np.ndarray,
    swing_height_m: float,
    n: int,
    smooth: bool = False,
) -> np.ndarray:
    """PlanningModel.swing_com_in_world without its memo: CoM (x, y) in W [m], (n, 2)."""
    tau = np.linspace(0.0, 1.0, n)
    rot_t = rotation_z(yaw).T
    base = np.asarray(position_base_in_world, dtype=float)
    feet = np.asarray(position_feet_in_world, dtype=float)
    start = feet[leg]
    delta = np.asarray(foothold_end_in_world, dtype=float) - start
    blend, rise = (quintic_blend, smooth_lift) if smooth else (cosine_blend, lift)
    path = start + delta * blend(tau, 1.0).s[:, None]
    path[:, 2] += rise(tau, 1.0, swing_height_m).s
    stance = [k for k in range(4) if k != leg]
    rows = np.concatenate([stance, np.full(n, leg)])
    targets = (np.vstack([feet[stance], path]) - base) @ rot_t.T  # in B
    if model.leg_family is INSECT:
        moment = leg_moments(model.leg_constants, rows, targets)
    else:
        moment = leg_moments_any(model.legs, rows, targets)
    offset = (moment[:3].sum(axis=0) + moment[3:]) / model.total_mass
    return base[:2] + offset[:, :2] @ rot_t[:2, :2]


def swing_zmp_in_world(
    model: PlanningModel,
    position_base_in_world: np.ndarray,
    yaw: float,
    position_feet_in_world: np.ndarray,
    leg: int,
    foothold_end_in_world: np.ndarray,
    swing: SwingTiming,
    n: int,
) -> np.ndarray:
    """The zero-moment point (x, y) in W [m], (n, 2), over the swing of ``leg`` with the base
    standing (:func:`swing_com_in_world`'s swing, on the profiles and at the unit time the
    samples will have, ``swing``): the whole-robot CoM c (n, 3) at n evenly spaced τ, its
    acceleration c̈ by central differences in time (as planner/stability/contact_forces.py
    differences the samples) and z = c_xy - (c_z - ground) c̈_xy / (g + c̈_z), the ground
    the stance feet's contact points. The swing leg's own acceleration moves it off the CoM
    (anymal at 1 s a unit: up to 33 mm at the top of a 0.17 m lift, docs/physics.md). NaN
    rows where a foot is out of reach."""
    return swing_com_and_zmp_in_world(
        model,
        position_base_in_world,
        yaw,
        position_feet_in_world,
        leg,
        foothold_end_in_world,
        swing,
        n,
    )[1]


def swing_com_and_zmp_in_world(
    model: PlanningModel,
    position_base_in_world: np.ndarray,
    yaw: float,
    position_feet_in_world: np.ndarray,
    leg: int,
    foothold_end_in_world: np.ndarray,
    swing: SwingTiming,
    n: int,
) -> tuple[np.ndarray, np.ndarray]:
    """(whole-robot CoM (x, y) in W [m], (n, 2); its zero-moment point (x, y) in W [m],
    (n, 2)) over the swing of :func:`swing_zmp_in_world`, on the same τ."""
    tau = np.linspace(0.0, 1.0, n)
    rot = rotation_z(yaw)
    base = np.asarray(position_base_in_world, dtype=float)
    feet = np.asarray(position_feet_in_world, dtype=float)
    start = feet[leg]
    blend = (quintic_blend if swing.smooth else cosine_blend)(tau, 1.0).s
    height = (smooth_lift if swing.smooth else lift)(tau, 1.0, swing.height_m).s
    path = start + (np.asarray(foothold_end_in_world, dtype=float) - start) * blend[:, None]
    path[:, 2] += height
    stance = [k for k in range(4) if k != leg]
    rows = np.concatenate([stance, np.full(n, leg)])
    targets = (np.vstack([feet[stance], path]) - base) @ rot  # in B
    if model.leg_family is INSECT:
        moment = leg_moments(model.leg_constants, rows, targets)
    else:
        moment = leg_moments_any(model.legs, rows, targets)
    offset = (moment[:3].sum(axis=0) + moment[3:]) / model.total_mass
    com = base + offset @ rot.T
    t_s = tau * swing.unit_time_s
    acc = np.gradient(np.gradient(com, t_s, axis=0), t_s, axis=0)
    ground = float(np.mean(feet[stance, 2])) - swing.contact_offset_m
    k = (com[:, 2] - ground) / (swing.gravity + acc[:, 2])
    return com[:, :2], com[:, :2] - k[:, None] * acc[:, :2]


class SwingTiming(NamedTuple):
    """How a still-base swing is sampled for :func:`swing_zmp_in_world`: swing height [m],
    the gait's profiles (``smooth``: quintic and smooth lift, else the thesis's cosine and
    eq 5.4), the unit time [s], the foot ball's contact offset (foothold z - contact z) [m],
    gravity [m/s²]."""

    height_m: float
    smooth: bool
    unit_time_s: float
    contact_offset_m: float
    gravity: float


def moving_swing_com_in_world(
    model: PlanningModel,
    position_base_start_in_world: np.ndarray,
    position_base_end_in_world: np.ndarray,
    yaw: float,
    position_feet_in_world: np.ndarray,
    leg: int,
    foothold_end_in_world: np.ndarray,
    swing_height_m: float,
    n: int,
) -> tuple[np.ndarray, np.ndarray]:
    """PlanningModel.moving_swing_com_in_world without its memo: (CoM (n, 2), base (n, 2))
    in W [m]."""
    blend, height, rows = _moving_swing_profile(n, float(swing_height_m))
    rot = rotation_z(yaw)
    b0 = np.asarray(position_base_start_in_world, dtype=float)
    base = b0 + (np.asarray(position_base_end_in_world, float) - b0) * blend
    feet = np.asarray(position_feet_in_world, float)
    swing = feet[leg] + (np.asarray(foothold_end_in_world, float) - feet[leg]) * blend
    swing[:, 2] += height
    rel = feet - base[:, None, :]  # (n, 4, 3) feet - base in W [m]
    rel[:, leg] = swing - base
    targets = (rel @ rot).reshape(-1, 3)  # in B
    if model.leg_family is INSECT:
        moment = leg_moments(model.leg_constants, rows, targets, horizontal=True)
    else:
        moment = leg_moments_any(model.legs, rows, targets)
    offset = moment.reshape(n, 4, 3).sum(axis=1) / model.total_mass
    return base[:, :2] + offset[:, :2] @ rot.T[:2, :2], base[:, :2].copy()


def leg_moments(
    const: LegConstants,
    leg: np.ndarray,
    position_foot_in_base: np.ndarray,
    horizontal: bool = False,
) -> np.ndarray:
    """Σ m_i c_i [kg m], (R, 3), of leg ``leg[i]`` with its foot at row i of
    ``position_foot_in_base`` (R, 3) [m], knee down, for several legs in one pass: the θ2, θ3
    of silo4kin.knee_down_ik.knee_down_terms (eq 3.11-3.24; of the leg's yaw φ = θb + θ1
    only cos φ = x/ρ, sin φ = y/ρ enter, so θ1 is not formed) and the link moments of
    silo4kin.com.leg_mass_moment_in_base. NaN rows (x, y; z too without ``horizontal``)
    where a foot is out of reach. With ``horizontal`` the z column is left at its hip term
    (the callers that set it read x, y only). The same operations in the same order as
    knee_down_dh_angles then the moments, with the squares of the lengths formed once per
    row pattern (:class:`_Rows`): the same values, bit for bit (tests/test_speed_kernels.py)."""
    g = rows_of(const, leg)
    rel = position_foot_in_base - g.hip
    x, y, z = rel[:, 0], rel[:, 1], rel[:, 2]
    rho = np.hypot(x, y)
    c, s = x / rho, y / rho
    # knee_down_terms without θ1: r, cos θ3, θ3 = -acos, θ2 = atan2(z kx - r ky, r kx + z ky)
    r = np.sqrt(x * x + y * y) - g.l1
    cos3 = (r * r + z * z - g.l2_sq - g.l3_sq) / g.two_l2_l3
    reachable = np.abs(cos3) <= 1.0 + IK_COS_SLACK
    c3 = np.minimum(np.maximum(cos3, -1.0), 1.0)  # np.clip, with less overhead
    theta3 = -np.arccos(c3)
    kx, ky = g.l2 + g.l3 * c3, g.l3 * -np.sqrt(1.0 - c3 * c3)
    theta2 = np.arctan2(z * kx - r * ky, r * kx + z * ky)
    if not reachable.all():
        theta2[~reachable] = np.nan
        theta3[~reachable] = np.nan
    c2, s2 = np.cos(theta2), np.sin(theta2)
    c23, s23 = np.cos(theta2 + theta3), np.sin(theta2 + theta3)
    a_r = (
        g.m0_k00
        + g.m1 * (g.l1 + g.k10 * c2 + g.k12 * s2)
        + g.m2 * (g.l1 + g.l2 * c2 + g.k20 * c23 + g.k22 * s23)
    )
    out = g.hip_moment.copy()
    out[:, 0] += a_r * c - g.a_t * s
    out[:, 1] += a_r * s + g.a_t * c
    if not horizontal:
        out[:, 2] += (
            g.m0_k02
            + g.m1 * (g.k10 * s2 - g.k12 * c2)
            + g.m2 * (g.l2 * s2 + g.k20 * s23 - g.k22 * c23)
        )
    return out


class _Rows(NamedTuple):
    """:class:`LegConstants` gathered for the rows of one :func:`leg_moments` call, with the
    products that do not depend on the targets formed once (the same operands in the same
    order as forming them per call: the same values)."""

    hip: np.ndarray
    l1: np.ndarray
    l2: np.ndarray
    l3: np.ndarray
    l2_sq: np.ndarray  # l2 * l2
    l3_sq: np.ndarray  # l3 * l3
    two_l2_l3: np.ndarray  # 2 l2 l3
    m1: np.ndarray
    m2: np.ndarray
    k10: np.ndarray
    k12: np.ndarray
    k20: np.ndarray
    k22: np.ndarray
    m0_k00: np.ndarray  # m0 * k00
    m0_k02: np.ndarray  # m0 * k02
    a_t: np.ndarray  # m0 k01 - m1 k11 - m2 k21
    hip_moment: np.ndarray  # hip * (m0 + m1 + m2)


def rows_of(const: LegConstants, leg: np.ndarray) -> _Rows:
    """:class:`_Rows` of ``const`` for the leg indices ``leg`` (R,), memoised in
    ``const.row_memo`` (a planner run asks for a few row patterns thousands of times: the n
    configurations of a swing); read-only."""
    leg = np.asarray(leg)
    return memoised(
        const.row_memo, leg.tobytes(), lambda: _gathered_rows(const, leg), ROW_MEMO_SIZE
    )


def _gathered_rows(const: LegConstants, leg: np.ndarray) -> _Rows:
    """rows_of without its memo."""
    l1, l2, l3 = const.length[leg].T
    m = const.mass[leg]
    k = const.com[leg]
    rows = _Rows(
        hip=const.hip[leg],
        l1=l1,
        l2=l2,
        l3=l3,
        l2_sq=l2 * l2,
        l3_sq=l3 * l3,
        two_l2_l3=2.0 * l2 * l3,
        m1=m[:, 1],
        m2=m[:, 2],
        k10=k[:, 1, 0],
        k12=k[:, 1, 2],
        k20=k[:, 2, 0],
        k22=k[:, 2, 2],
        m0_k00=m[:, 0] * k[:, 0, 0],
        m0_k02=m[:, 0] * k[:, 0, 2],
        a_t=m[:, 0] * k[:, 0, 1] - m[:, 1] * k[:, 1, 1] - m[:, 2] * k[:, 2, 1],
        hip_moment=const.hip[leg] * m.sum(axis=1)[:, None],
    )
    for array in rows:
        array.setflags(write=False)
    return rows


def leg_moments_any(legs: tuple, leg: np.ndarray, position_foot_in_base: np.ndarray) -> np.ndarray:
    """Σ m_i c_i [kg m], (R, 3), as :func:`leg_moments`, for legs of any family: the
    family's IK (silo4kin.legs) then silo4kin.com.leg_mass_moment_in_base; mammal legs all
    rows in one pass (silo4kin.mammal_constants.MammalConstants.of_rows: the same values as leg by
    leg), other legs leg by leg."""
    if legs and all(family_of(geo) is MAMMAL for geo in legs):
        stacked = MammalConstants.of_rows(legs, leg)
        return mammal.leg_mass_moment_in_base(
            stacked, mammal.inverse_kinematics(stacked, position_foot_in_base).q
        )
    out = np.full((leg.size, 3), np.nan)
    for k, geo in enumerate(legs):
        rows = np.flatnonzero(leg == k)
        if rows.size:
            q = leg_families.inverse_kinematics(geo, position_foot_in_base[rows]).q
            out[rows] = leg_mass_moment_in_base(geo, q)
    return out
