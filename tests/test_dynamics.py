"""Closed-form Lagrange leg dynamics (App. A, corrected) against Pinocchio's crba,
computeCoriolisMatrix, computeGeneralizedGravity and rnea (fixed base, one leg's joints)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from silo4kin import ClosedFormNotApplicableError
from silo4kin import dynamics as D
from silo4kin.check import MASS_TOLERANCE, TORQUE_TOLERANCE

LEGS = range(4)
G = 9.81
#: Finite differences of M along q' (step 1e-6): M entries O(1), error ~ 1e-10.
FD_STEP = 1e-6
FD_TOLERANCE = 1e-8


def _sl(k: int) -> slice:
    return slice(3 * k, 3 * k + 3)


@pytest.mark.parametrize("k", LEGS)
def test_mass_matrix_equals_crba(silo4, pin_reference, k):
    M = D.mass_matrix(silo4.legs[k], pin_reference.q[:, _sl(k)])
    assert np.abs(M - pin_reference.mass[:, _sl(k), _sl(k)]).max() < MASS_TOLERANCE


def test_legs_are_decoupled_in_the_fixed_base_mass_matrix(pin_reference):
    """Off-leg blocks of crba are zero: each leg can be treated alone, hip fixed (App. A)."""
    M = pin_reference.mass.copy()
    for k in LEGS:
        M[:, _sl(k), _sl(k)] = 0.0
    assert np.abs(M).max() == 0.0


@pytest.mark.parametrize("k", LEGS)
def test_coriolis_vector_equals_pinocchio_c_times_v(silo4, pin_reference, k):
    H = D.coriolis_vector(silo4.legs[k], pin_reference.q[:, _sl(k)], pin_reference.v[:, _sl(k)])
    assert np.abs(H - pin_reference.coriolis[:, _sl(k)]).max() < TORQUE_TOLERANCE


@pytest.mark.parametrize("k", LEGS)
def test_gravity_equals_pinocchio(silo4, pin_reference, k):
    Gq = D.gravity_vector(silo4.legs[k], pin_reference.q[:, _sl(k)], G)
    assert np.abs(Gq - pin_reference.gravity[:, _sl(k)]).max() < TORQUE_TOLERANCE


@pytest.mark.parametrize("k", LEGS)
def test_inverse_dynamics_equals_rnea(silo4, pin_reference, k):
    sl = _sl(k)
    tau = D.inverse_dynamics(
        silo4.legs[k], pin_reference.q[:, sl], pin_reference.v[:, sl], pin_reference.a[:, sl], G
    )
    assert np.abs(tau - pin_reference.rnea[:, sl]).max() < TORQUE_TOLERANCE


@pytest.mark.parametrize("k", LEGS)
def test_coriolis_is_consistent_with_mass_matrix_derivatives(silo4, pin_reference, k):
    """Lagrange: H = dM/dt q' - 1/2 d(q'^T M q')/dq, both by finite differences of M."""
    leg = silo4.legs[k]
    q, v = pin_reference.q[:200, _sl(k)], pin_reference.v[:200, _sl(k)]
    Mdot = (D.mass_matrix(leg, q + FD_STEP * v) - D.mass_matrix(leg, q - FD_STEP * v)) / (
        2 * FD_STEP
    )
    grad = np.empty_like(q)
    for i in range(3):
        dq = np.zeros(3)
        dq[i] = FD_STEP
        dM = (D.mass_matrix(leg, q + dq) - D.mass_matrix(leg, q - dq)) / (2 * FD_STEP)
        grad[:, i] = np.einsum("ni,nij,nj->n", v, dM, v)
    H_fd = np.einsum("nij,nj->ni", Mdot, v) - 0.5 * grad
    assert np.abs(D.coriolis_vector(leg, q, v) - H_fd).max() < FD_TOLERANCE


def test_mass_matrix_is_symmetric_positive_definite(silo4, pin_reference):
    for k in LEGS:
        M = D.mass_matrix(silo4.legs[k], pin_reference.q[:, _sl(k)])
        assert np.abs(M - np.transpose(M, (0, 2, 1))).max() == 0.0
        assert np.linalg.eigvalsh(M).min() > 0.0


def test_closed_form_refuses_an_off_axis_centre_of_mass(silo4):
    leg = silo4.legs[0]
    femur = dataclasses.replace(leg.links[1], com=np.array([0.13, 0.0, 0.01]))
    bent = dataclasses.replace(leg, links=(leg.links[0], femur, leg.links[2]))
    with pytest.raises(ClosedFormNotApplicableError, match="off the link axis"):
        D.mass_matrix(bent, np.zeros(3))


def test_a_perturbed_mass_makes_the_dynamics_check_fail(silo4, pin_reference):
    """The check can fail: +10 g on one tibia shows in M, G and rnea."""
    leg = silo4.legs[2]
    tibia = dataclasses.replace(leg.links[2], mass=leg.links[2].mass + 0.01)
    heavy = dataclasses.replace(leg, links=(leg.links[0], leg.links[1], tibia))
    sl = _sl(2)
    q = pin_reference.q[:, sl]
    assert np.abs(D.mass_matrix(heavy, q) - pin_reference.mass[:, sl, sl]).max() > 1e-4
    assert np.abs(D.gravity_vector(heavy, q, G) - pin_reference.gravity[:, sl]).max() > 1e-3
