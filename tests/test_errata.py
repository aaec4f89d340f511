"""Each suspected thesis misprint, confirmed or refuted against Pinocchio (docs/errata.md).

For every item: the printed form is evaluated (tests/thesis_printed.py), compared with
Pinocchio on the same model, and the difference is shown to be exactly the predicted one.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest
import thesis_printed as P

from silo4kin import dynamics as D
from silo4kin import kinematics as K
from silo4kin.geometry import LinkInertia

#: Exact identities between printed and reference terms: O(1) quantities, rounding only.
IDENTITY_TOLERANCE = 1e-10


def _thesis_axes(leg):
    """Leg data in the thesis's frame (x right, y forward): theta_b + pi/2, Lb, Lz."""
    return leg.theta_b + np.pi / 2, float(np.hypot(*leg.position_hip_in_base[:2])), -leg.hip_height


def _foot_in_thesis_axes(p_base):
    """REP-103 (x forward, y left) -> thesis (x right, y forward): (xt, yt) = (-y, x)."""
    return -p_base[:, 1], p_base[:, 0], p_base[:, 2]


# ---------------------------------------------------------------- inverse kinematics --


def test_eq_3_10_unwrapped_puts_theta1_out_of_range_for_legs_1_and_3(silo4, pin_reference):
    """Confirmed: printed theta1 = atan2(...) - theta_b exceeds ±pi for thesis legs 1 and 3
    (theta_b = ±3pi/4) on valid in-limit poses; wrapped to (-pi, pi] it is the true angle."""
    out_of_range = {}
    for k, leg in enumerate(silo4.legs):
        theta_b, Lb, _ = _thesis_axes(leg)
        x, y, _ = _foot_in_thesis_axes(pin_reference.foot[:, k])
        printed = P.theta1_eq_3_10(x, y, Lb, theta_b)
        true = pin_reference.q[:, 3 * k]
        wrapped = np.arctan2(np.sin(printed), np.cos(printed))
        # unique where the foot is outside the yaw axis (else theta1 +- pi, same foot)
        outside = K.singularity_distance(leg, pin_reference.q[:, 3 * k : 3 * k + 3]).radial_m > 0
        assert np.abs(wrapped - true)[outside].max() < IDENTITY_TOLERANCE
        out_of_range[leg.name] = int(np.sum(np.abs(printed[outside]) > np.pi))
    assert out_of_range["LF"] > 100 and out_of_range["LH"] > 100  # thesis legs 1 and 3
    assert out_of_range["RF"] == 0 and out_of_range["RH"] == 0  # thesis legs 2 and 4


def test_eq_3_24_printed_division_by_theta2_is_wrong(silo4, pin_reference):
    """Confirmed: theta3 = atan2(...)/theta2 is wrong; atan2(...) - theta2 is the knee angle."""
    leg = silo4.legs[0]
    theta_b, Lb, Lz = _thesis_axes(leg)
    x, y, z = _foot_in_thesis_axes(pin_reference.foot[:, 0])
    t1, t2, t3 = pin_reference.q[:, 0:3].T
    printed = P.theta3_eq_3_24(x, y, z, Lb, Lz, leg.L1, leg.L2, theta_b, t1, t2)
    corrected = printed * t2 - t2
    corrected = np.arctan2(np.sin(corrected), np.cos(corrected))
    assert np.abs(corrected - t3).max() < 1e-9
    assert np.median(np.abs(printed - t3)) > 0.5


def test_eq_3_21_plus_root_is_knee_down_but_divides_by_zero_at_a_plus_c_zero(silo4, pin_reference):
    """Confirmed: the '+' root of 3.21 is the knee-down theta2 wherever A + C != 0, and the
    printed formula gives NaN when A + C = 0 while the atan2/acos IK returns the pose."""
    leg = silo4.legs[1]
    theta_b, Lb, Lz = _thesis_axes(leg)
    x, y, z = _foot_in_thesis_axes(pin_reference.foot[:, 1])
    t1, t2, _ = pin_reference.q[:, 3:6].T
    A, B, C = P.abc_eq_3_14_3_16(x, y, z, Lb, Lz, leg.L1, leg.L2, leg.L3, theta_b, t1)
    assert np.abs(A * np.cos(t2) + B * np.sin(t2) - C).max() < IDENTITY_TOLERANCE  # eq 3.17
    ok = np.abs(A + C) > 1e-6
    plus = P.theta2_eq_3_21_3_22(A[ok], B[ok], C[ok], +1.0)
    assert np.abs(np.arctan2(np.sin(plus - t2[ok]), np.cos(plus - t2[ok]))).max() < 1e-6
    # A + C = 0: femur pointing back along the leg would reach the target (theta2 = pi
    # solves 3.17). Foot below the hip near the yaw axis:
    phi = -np.pi / 6
    r, zz = -leg.L2 + leg.L3 * np.cos(phi), leg.L3 * np.sin(phi)
    rho = leg.L1 + r
    p_base = leg.position_hip_in_base + np.array(
        [rho * np.cos(leg.theta_b), rho * np.sin(leg.theta_b), zz]
    )
    xs, ys, zs = _foot_in_thesis_axes(p_base[None, :])
    A0, B0, C0 = P.abc_eq_3_14_3_16(xs, ys, zs, Lb, Lz, leg.L1, leg.L2, leg.L3, theta_b, 0.0)
    assert abs(A0[0] + C0[0]) < 1e-12
    # '+' root: (2B + |2B|) / 2(A + C) = 0 / 0 for B < 0; rounding returns theta2 = 0
    printed = P.theta2_eq_3_21_3_22(A0, B0, C0, +1.0)[0]
    q = K.inverse_kinematics(leg, p_base)
    assert np.all(np.isfinite(q)) and q[2] < 0
    assert q[1] == pytest.approx(phi, abs=1e-9)
    assert not np.isfinite(printed) or abs(printed - q[1]) > 0.5
    assert np.abs(K.forward_kinematics(leg, q) - p_base).max() < 1e-12


def test_eq_3_45_is_the_jacobian_derivative_entry_not_j33(silo4, pin_reference):
    """Confirmed: 3.45 equals dJ(3,3)/dt (Pinocchio-checked jacobian_derivative), not J(3,3)."""
    leg = silo4.legs[2]
    q, v = pin_reference.q[:, 6:9], pin_reference.v[:, 6:9]
    printed = P.j33_eq_3_45(leg.L3, q[:, 1], q[:, 2], v[:, 1], v[:, 2])
    assert np.abs(printed - K.jacobian_derivative(leg, q, v)[:, 2, 2]).max() < IDENTITY_TOLERANCE
    assert np.abs(printed - K.jacobian(leg, q)[:, 2, 2]).max() > 0.1


def test_foot_position_of_section_3_1_is_in_the_body_frame(silo4, pin_reference):
    """Confirmed: p of eq 3.3-3.5 is w.r.t. the body CoG frame (it contains Lb and Lz),
    not 'the CoG of the leg' or the hip frame: it equals Pinocchio's foot in base_link."""
    p = K.forward_kinematics(silo4.legs[3], pin_reference.q[:, 9:12])
    assert np.abs(p - pin_reference.foot[:, 3]).max() < 1e-12


# ---------------------------------------------------------------- Lagrange dynamics --


@pytest.fixture(scope="module")
def planar_thesis_model(silo4):
    """The thesis's own modelling assumption: links 2, 3 rotate only about the pitch axis
    ("planar": I about the pitch axis only), link 1 about the yaw axis. Pinocchio model with
    those inertias and the matching LegGeometry; SILO4 numbers read from the loaded model."""
    model = pin.Model(silo4.model)
    legs = []
    for leg in silo4.legs:
        links = []
        for k, (jn, link) in enumerate(zip(leg.joint_names, leg.links)):
            scalar = link.inertia[2, 2] if k == 0 else link.inertia[1, 1]
            diag = np.diag([0.0, 0.0, scalar]) if k == 0 else np.diag([0.0, scalar, 0.0])
            jid = model.getJointId(jn)
            old = model.inertias[jid]
            model.inertias[jid] = pin.Inertia(old.mass, old.lever, diag)  # link = joint frame
            links.append(LinkInertia(link.mass, link.com, diag))
        legs.append(dataclasses.replace(leg, links=tuple(links)))
    return model, legs


def _params(leg):
    p = D.LegDynamicsParameters.from_leg(leg)
    scalar = (p.inertia_zz[0], p.inertia_yy[1], p.inertia_yy[2])
    return p, scalar


def _pinocchio_leg_terms(silo4, model, q12, v12, k):
    data = model.createData()
    idx = silo4.q_index[3 * k : 3 * k + 3]
    Ms, Hs, Gs = [], [], []
    for q, v in zip(q12, v12):
        qp, vp = silo4.to_pinocchio_q(q), silo4.to_pinocchio_q(v)
        M = pin.crba(model, data, qp)
        M = np.triu(M) + np.triu(M, 1).T
        Ms.append(M[np.ix_(idx, idx)])
        Hs.append((pin.computeCoriolisMatrix(model, data, qp, vp) @ vp)[idx])
        Gs.append(pin.computeGeneralizedGravity(model, data, qp)[idx])
    return np.array(Ms), np.array(Hs), np.array(Gs)


def test_corrected_closed_form_equals_pinocchio_on_the_planar_model(
    silo4, pin_reference, planar_thesis_model
):
    """Our corrected A.14-A.29 with the thesis's planar inertias equals Pinocchio exactly."""
    model, legs = planar_thesis_model
    q, v = pin_reference.q[:300], pin_reference.v[:300]
    M, H, G = _pinocchio_leg_terms(silo4, model, q, v, 0)
    assert np.abs(D.mass_matrix(legs[0], q[:, :3]) - M).max() < 1e-12
    assert np.abs(D.coriolis_vector(legs[0], q[:, :3], v[:, :3]) - H).max() < 1e-10
    assert np.abs(D.gravity_vector(legs[0], q[:, :3], 9.81) - G).max() < 1e-10


def test_printed_mass_matrix_differs_from_pinocchio_exactly_by_the_misprints(
    silo4, pin_reference, planar_thesis_model
):
    """Confirmed, term by term, on the thesis's planar model:
    A.15: (1/2 m3 Lcm3)^2 cos(2t2+2t3) should be 1/2 m3 Lcm3^2 cos(...); m1 L1^2 -> m1 Lcm1^2.
    A.19: spurious + 2 m3 L2; A.2: the tibia's rotation is I3 (t2' + t3')^2, so M22, M23,
    M32 each lack + I3. A.22: m2 should be m3. A.23 and the zero entries are right."""
    model, legs = planar_thesis_model
    q, v = pin_reference.q[:300], pin_reference.v[:300]
    M_pin, _, _ = _pinocchio_leg_terms(silo4, model, q, v, 0)
    p, (J1, J2, J3) = _params(legs[0])
    m1, m2, m3 = p.m
    l1, _, l3 = p.lcm
    t2, t3 = q[:, 1], q[:, 2]
    M_printed = P.mass_matrix_printed(p.m, p.lcm, (J1, J2, J3), p.L1, p.L2, t2, t3)
    diff = M_printed - M_pin
    expected_11 = ((0.5 * m3 * l3) ** 2 - 0.5 * m3 * l3**2) * np.cos(2 * t2 + 2 * t3) + m1 * (
        p.L1**2 - l1**2
    )
    assert np.abs(diff[:, 0, 0] - expected_11).max() < IDENTITY_TOLERANCE
    assert np.abs(expected_11).max() > 0.005  # the misprint matters: ~5 % of M11
    assert np.abs(diff[:, 1, 1] - (2 * m3 * p.L2 - J3)).max() < IDENTITY_TOLERANCE
    assert np.abs(diff[:, 1, 2] - (-J3)).max() < IDENTITY_TOLERANCE
    assert (
        np.abs(diff[:, 2, 1] - ((m2 - m3) * p.L2 * l3 * np.cos(t3) - J3)).max() < IDENTITY_TOLERANCE
    )
    assert np.abs(diff[:, 2, 2]).max() < IDENTITY_TOLERANCE  # A.23 right
    assert np.abs(diff[:, 0, 1:]).max() < IDENTITY_TOLERANCE  # A.16-A.18, A.21 right
    # the printed M22 at q = (0, 0, -pi/2): 0.398 kg m^2 against 0.106 (docs/thesis-notes.md)
    at = P.mass_matrix_printed(
        p.m, p.lcm, (J1, J2, J3), p.L1, p.L2, np.array([0.0]), np.array([-np.pi / 2])
    )[0, 1, 1]
    assert at == pytest.approx(0.398, abs=1e-3)
    assert at - 2 * m3 * p.L2 + J3 == pytest.approx(0.106, abs=1e-3)


def test_printed_coriolis_differs_only_in_the_a27_coefficient(
    silo4, pin_reference, planar_thesis_model
):
    """Confirmed: A.27's t1' t3' term -4 m3 L1 Lcm3 sin(t2+t3) should be -2; A.28, A.29 right."""
    model, legs = planar_thesis_model
    q, v = pin_reference.q[:300], pin_reference.v[:300]
    _, H_pin, G_pin = _pinocchio_leg_terms(silo4, model, q, v, 0)
    p, _ = _params(legs[0])
    _, _, m3 = p.m
    l3 = p.lcm[2]
    H_printed = P.coriolis_printed(
        p.m, p.lcm, p.L1, p.L2, q[:, 1], q[:, 2], v[:, 0], v[:, 1], v[:, 2]
    )
    expected = -2 * m3 * p.L1 * l3 * np.sin(q[:, 1] + q[:, 2]) * v[:, 0] * v[:, 2]
    assert np.abs(H_printed[:, 0] - H_pin[:, 0] - expected).max() < IDENTITY_TOLERANCE
    assert np.abs(H_printed[:, 1:] - H_pin[:, 1:]).max() < IDENTITY_TOLERANCE
    G_printed = P.gravity_printed(p.m, p.lcm, p.L2, 9.81, q[:, 1], q[:, 2])
    assert np.abs(G_printed - G_pin).max() < IDENTITY_TOLERANCE  # A.24-A.26 right


def test_rod_inertia_adds_yaw_terms_the_planar_model_neglects(silo4):
    """With the URDF's rod tensors M11 gains I2 cos^2 t2 + I3 cos^2(t2+t3): +18 % at
    q = (0, 0, -pi/2) (docs/thesis-notes.md), the size of what the planar model neglects."""
    leg = silo4.legs[0]
    q = np.array([[0.0, 0.0, -np.pi / 2]])
    planar = dataclasses.replace(
        leg,
        links=tuple(
            dataclasses.replace(lk, inertia=np.diag([0.0, lk.inertia[1, 1], 0.0])) if i else lk
            for i, lk in enumerate(leg.links)
        ),
    )
    rod, flat = D.mass_matrix(leg, q)[0, 0, 0], D.mass_matrix(planar, q)[0, 0, 0]
    assert rod - flat == pytest.approx(leg.links[1].inertia[2, 2], abs=1e-12)  # cos(-pi/2) = 0
    assert (rod - flat) / flat == pytest.approx(0.18, abs=0.01)


# ---------------------------------------------------------------- support torques --


def test_a32_a34_printed_weight_sign_gives_the_wrong_holding_torque(silo4):
    """Confirmed: with W = (0, 0, -m_b g) as printed (A.32), F of A.33 are negative and
    tau = J^T(-F) (A.34) has the opposite sign of the torque Pinocchio needs to hold the
    body. With W = (0, 0, +m_b g) the F are the upward reactions and A.34 is right."""
    model = silo4.model
    data = model.createData()
    q = np.zeros(12)
    stance = [0, 1, 2]  # RH in the air
    for k in range(4):
        q[3 * k : 3 * k + 3] = [0.0, -0.3, -1.2]
    q[6] = 0.6  # LH foot swung towards the right: CoG inside
    feet = np.array([K.forward_kinematics(silo4.legs[k], q[3 * k : 3 * k + 3]) for k in stance])
    A = np.vstack([feet[:, 0], feet[:, 1], np.ones(3)])  # eq A.30 with three feet
    weight = silo4.body_mass * 9.81
    F_printed = np.linalg.solve(A, np.array([0.0, 0.0, -weight]))  # eq A.32-A.33 printed
    F_up = np.linalg.solve(A, np.array([0.0, 0.0, weight]))
    assert np.all(F_printed < 0) and np.all(F_up > 0)
    # Pinocchio: static legs with upward reactions F_up at the feet, gravity removed.
    fext = [pin.Force.Zero() for _ in range(model.njoints)]
    pin.framesForwardKinematics(model, data, silo4.to_pinocchio_q(q))
    for j, k in enumerate(stance):
        leg = silo4.legs[k]
        jid = model.getJointId(leg.joint_names[2])
        force_world = np.array([0.0, 0.0, F_up[j]])
        oMi = data.oMi[jid]
        f_local = oMi.rotation.T @ force_world
        lever = oMi.rotation.T @ (feet[j] - oMi.translation)
        fext[jid] = pin.Force(f_local, np.cross(lever, f_local))
    qp = silo4.to_pinocchio_q(q)
    zero = np.zeros(12)
    tau_pin = silo4.from_pinocchio_q(
        pin.rnea(model, data, qp, zero, zero, fext) - pin.computeGeneralizedGravity(model, data, qp)
    )
    for j, k in enumerate(stance):
        J = K.jacobian(silo4.legs[k], q[3 * k : 3 * k + 3])
        printed = J.T @ (-np.array([0.0, 0.0, F_printed[j]]))
        corrected = J.T @ (-np.array([0.0, 0.0, F_up[j]]))
        ours = tau_pin[3 * k : 3 * k + 3]
        assert np.abs(corrected - ours).max() < 1e-9
        assert np.abs(printed + ours).max() < 1e-9
        assert np.abs(ours).max() > 1.0


# ---------------------------------------------------------------- workspace numbers --


def test_section_4_2_1_x_max_at_h_0_39_is_0_3677_not_0_3726(silo4):
    """Confirmed: q = (0, 0, -pi/2) at h = 0.39 puts the foot at x_max = y_max = 0.3677 m
    (eq 3.5), stride 0.3677 - 0.155 = 0.2127 m, not the printed 0.3726 / 0.2176."""
    leg = silo4.legs[0]  # thesis leg 1
    p = K.forward_kinematics(leg, np.array([0.0, 0.0, -np.pi / 2]))
    assert p[2] == pytest.approx(-0.39, abs=1e-12)  # foot 0.39 m below the CoG
    assert abs(p[0]) == pytest.approx(0.3677, abs=5e-5)
    assert abs(p[1]) == pytest.approx(0.3677, abs=5e-5)
    assert abs(p[0]) - 0.155 == pytest.approx(0.2127, abs=5e-5)
    assert abs(abs(p[0]) - 0.3726) > 4e-3


def test_eq_4_4_hips_are_at_lb_cos_45_not_0_155(silo4):
    """Refined: the hips sit at ±Lb cos 45° = ±0.15556 m, 0.56 mm from the printed ±0.155."""
    for leg in silo4.legs:
        assert np.abs(leg.position_hip_in_base[:2]) == pytest.approx([0.155563, 0.155563], abs=1e-6)
