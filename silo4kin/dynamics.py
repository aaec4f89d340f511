"""Closed-form Lagrange dynamics of one insect leg with its hip fixed (thesis App. A).

    M(q) q'' + H(q, q') + G(q) = tau                                          (eq A.14)

The thesis's A.15-A.29, corrected (docs/errata.md) and extended to be exact for the URDF
rigid-body model (docs/model.md): each link's inertia is a diagonal tensor
diag(Ixx, Iyy, Izz) about its CM in the DH link frame (x along the link, y along the pitch
axis), and the CM lies on the link's x axis at distance Lcm_i. The thesis keeps only the
pitch-axis inertia (its "planar" model); with Ixx = 0 and Izz = Iyy = I_i (a slender rod,
our URDF) the yaw rate also spins links 2 and 3, which adds I2 cos^2 theta2 +
I3 cos^2(theta2 + theta3) to M11.

Inputs are URDF joint values (N, 3); the DH angles are theta = axis_sign * q + zero_offset,
so M_q = S M_theta S, H_q = S H_theta, G_q = S G_theta with S = diag(axis_sign).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .errors import ClosedFormNotApplicableError
from .geometry import LegGeometry

#: Off-axis CM or products of inertia below this are treated as zero [m or kg m^2];
#: xacro prints origins with ~1e-12 noise after rotations, 1e-9 is well above it.
INERTIA_TOLERANCE = 1e-9


@dataclass(frozen=True)
class LegDynamicsParameters:
    """Scalars of the Lagrange model, read from a :class:`LegGeometry`.

    Attributes:
        m: link masses (m1, m2, m3) [kg].
        lcm: CM distance along each link from its joint (Lcm1, Lcm2, Lcm3) [m].
        inertia_xx, inertia_yy, inertia_zz: diagonal inertia about the CM, DH link frame,
            for (coxa, femur, tibia) [kg m^2].
        L1, L2: coxa and femur lengths [m].
    """

    m: tuple[float, float, float]
    lcm: tuple[float, float, float]
    inertia_xx: tuple[float, float, float]
    inertia_yy: tuple[float, float, float]
    inertia_zz: tuple[float, float, float]
    L1: float
    L2: float

    @classmethod
    def from_leg(cls, leg: LegGeometry) -> LegDynamicsParameters:
        """Read the parameters; raise if the model breaks the closed form's assumptions."""
        for k, link in enumerate(leg.links):
            off_axis = np.abs(link.com[1:])
            # the coxa only yaws: a vertical CM offset does not enter its dynamics
            if k == 0:
                off_axis = off_axis[:1]
            if np.any(off_axis > INERTIA_TOLERANCE):
                raise ClosedFormNotApplicableError(
                    f"leg {leg.name} link {k + 1}: CM {link.com.tolist()} is off the link axis; "
                    "the closed-form Lagrange model needs it on the axis"
                )
            products = link.inertia[np.triu_indices(3, 1)]
            if np.any(np.abs(products) > INERTIA_TOLERANCE):
                raise ClosedFormNotApplicableError(
                    f"leg {leg.name} link {k + 1}: products of inertia {products.tolist()} "
                    "are not zero in the DH link frame"
                )
        return cls(
            m=tuple(float(lk.mass) for lk in leg.links),  # type: ignore[arg-type]
            lcm=tuple(float(lk.com[0]) for lk in leg.links),  # type: ignore[arg-type]
            inertia_xx=tuple(float(lk.inertia[0, 0]) for lk in leg.links),  # type: ignore[arg-type]
            inertia_yy=tuple(float(lk.inertia[1, 1]) for lk in leg.links),  # type: ignore[arg-type]
            inertia_zz=tuple(float(lk.inertia[2, 2]) for lk in leg.links),  # type: ignore[arg-type]
            L1=leg.L1,
            L2=leg.L2,
        )


class _Terms(NamedTuple):
    M: np.ndarray  # (N, 3, 3), DH angles
    dM11: np.ndarray  # (N, 2): dM11/dtheta2, dM11/dtheta3
    dM22: np.ndarray  # (N,): dM22/dtheta3
    dM23: np.ndarray  # (N,): dM23/dtheta3 (= dM32/dtheta3)


def _terms(p: LegDynamicsParameters, theta: np.ndarray) -> _Terms:
    m1, m2, m3 = p.m
    l1, l2, l3 = p.lcm
    ixx, iyy, izz = p.inertia_xx, p.inertia_yy, p.inertia_zz
    t2, t3 = theta[:, 1], theta[:, 2]
    c2, s2, c3, s3 = np.cos(t2), np.sin(t2), np.cos(t3), np.sin(t3)
    c23, s23 = np.cos(t2 + t3), np.sin(t2 + t3)
    r2 = p.L1 + l2 * c2  # horizontal distance of CM2 from the yaw axis
    r3 = p.L1 + p.L2 * c2 + l3 * c23  # horizontal distance of CM3 from the yaw axis
    n = theta.shape[0]
    M = np.zeros((n, 3, 3))
    # eq A.15 (corrected): every link's yaw inertia about the hip-yaw axis
    M[:, 0, 0] = (
        izz[0]
        + m1 * l1**2
        + m2 * r2**2
        + ixx[1] * s2**2
        + izz[1] * c2**2
        + m3 * r3**2
        + ixx[2] * s23**2
        + izz[2] * c23**2
    )
    # eq A.19 (without the spurious 2 m3 L2; with I3 from the tibia's pitch rate, A.2)
    M[:, 1, 1] = iyy[1] + m2 * l2**2 + iyy[2] + m3 * (p.L2**2 + l3**2 + 2 * p.L2 * l3 * c3)
    # eq A.20 / A.22 (both m3; plus I3)
    M[:, 1, 2] = M[:, 2, 1] = iyy[2] + m3 * (l3**2 + p.L2 * l3 * c3)
    # eq A.23
    M[:, 2, 2] = iyy[2] + m3 * l3**2
    dM11_2 = (
        -2 * m2 * r2 * l2 * s2
        + 2 * (ixx[1] - izz[1]) * s2 * c2
        - 2 * m3 * r3 * (p.L2 * s2 + l3 * s23)
        + 2 * (ixx[2] - izz[2]) * s23 * c23
    )
    dM11_3 = -2 * m3 * r3 * l3 * s23 + 2 * (ixx[2] - izz[2]) * s23 * c23
    return _Terms(
        M, np.stack([dM11_2, dM11_3], axis=1), -2 * m3 * p.L2 * l3 * s3, -m3 * p.L2 * l3 * s3
    )


def _prep(leg: LegGeometry, q: np.ndarray) -> tuple[np.ndarray, bool]:
    q = np.asarray(q, dtype=float)
    single = q.ndim == 1
    return leg.joint_to_dh(q[None, :] if single else q), single


def mass_matrix(leg: LegGeometry, q: np.ndarray) -> np.ndarray:
    """Joint-space mass matrix M(q), eq A.15-A.23 (corrected) [kg m^2], (N, 3, 3) or (3, 3)."""
    theta, single = _prep(leg, q)
    M = _terms(LegDynamicsParameters.from_leg(leg), theta).M
    s = leg.axis_sign
    M = M * s[None, :, None] * s[None, None, :]
    return M[0] if single else M


def coriolis_vector(leg: LegGeometry, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Coriolis and centrifugal torques H(q, q') = C(q, q') q', eq A.27-A.29 (corrected).

    From Lagrange: H_i = sum_j dM_ij/dt q'_j - 1/2 q'^T (dM/dq_i) q'.

    Returns:
        H [N m], shape (N, 3) or (3,).
    """
    theta, single = _prep(leg, q)
    qd = np.asarray(qd, dtype=float)
    td = leg.axis_sign * (qd[None, :] if single else qd)
    t = _terms(LegDynamicsParameters.from_leg(leg), theta)
    w1, w2, w3 = td[:, 0], td[:, 1], td[:, 2]
    a2, a3 = t.dM11[:, 0], t.dM11[:, 1]
    H = np.empty_like(theta)
    H[:, 0] = w1 * (a2 * w2 + a3 * w3)  # eq A.27
    H[:, 1] = t.dM22 * w2 * w3 + t.dM23 * w3**2 - 0.5 * a2 * w1**2  # eq A.28
    H[:, 2] = -0.5 * a3 * w1**2 - 0.5 * t.dM22 * w2**2  # eq A.29
    H *= leg.axis_sign
    return H[0] if single else H


def gravity_vector(leg: LegGeometry, q: np.ndarray, gravity: float) -> np.ndarray:
    """Gravity torques G(q), eq A.24-A.26, for gravity g [m/s^2] along -z of the base.

    Returns:
        G [N m], shape (N, 3) or (3,).
    """
    theta, single = _prep(leg, q)
    p = LegDynamicsParameters.from_leg(leg)
    _, m2, m3 = p.m
    _, l2, l3 = p.lcm
    c2, c23 = np.cos(theta[:, 1]), np.cos(theta[:, 1] + theta[:, 2])
    G = np.zeros_like(theta)
    G[:, 1] = gravity * ((m2 * l2 + m3 * p.L2) * c2 + m3 * l3 * c23)  # eq A.25
    G[:, 2] = gravity * m3 * l3 * c23  # eq A.26
    G *= leg.axis_sign
    return G[0] if single else G


def inverse_dynamics(
    leg: LegGeometry, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, gravity: float
) -> np.ndarray:
    """tau = M(q) q'' + H(q, q') + G(q), eq A.14, hip fixed in an inertial frame.

    Args:
        q, qd, qdd: joint values [rad], velocities [rad/s], accelerations [rad/s^2], (N, 3).
        gravity: magnitude of gravity along -z of the base [m/s^2].

    Returns:
        tau [N m], shape (N, 3) or (3,).
    """
    M = mass_matrix(leg, q)
    return (
        np.einsum("...ij,...j->...i", M, np.asarray(qdd, dtype=float))
        + coriolis_vector(leg, q, qd)
        + gravity_vector(leg, q, gravity)
    )
