"""Whether the default workspace's creeping stances keep the joints' effort budget.

The run refuses a plan whose static torque (q̇ = q̈ = 0, eq A.14 + A.34) breaks the effort
budget, the preset's torque headroom x URDF effort (planner/trajectory/limits.py: "no unit
time helps"). A stance foot's static joint torque is its share of the weight times its lever
(Jᵀ of the foot's vertical reaction) plus its own links' gravity; the share is set by where
the CoG stands in the support (three feet: its barycentric coordinates), the lever by where
the foot stands from its hip. The workspace chooses both: the centres (position 2) and the
stride place the feet, and the stability shifts place the CoG just inside the margin, close
to the edge between two feet, which then carry ~half the weight each (issue 21: SILO4's rear
hip pitch at 1.02-1.16 x its budget of 0.85 x 60 N m at h 0.22-0.38 m, phasmid's even on
four feet at h 0.168 m).

So the layout (planner/workspace/foothold_layout.py) asks :func:`creep_stances_keep` of a
candidate (centres, strides λ_x, λ_y scaled together): the creeping cycle along each body
axis (TRAVEL_DIRECTIONS; the four lifts of planner/workspace/footholds.creep_lift_triangles,
rear leg of a pair first, FRONT_FIRST), and at each lift the stances the gait passes
through:

- four feet, the CoG at its nominal position (the body between phases);
- four feet, the CoG shifted for the lift: planner/stability/shifts.shift_for_margin from the
  nominal CoG to margin threshold + SHIFT_EXTRA_M (the builder's shift, _shifted_base);
- three feet (the lifted leg off the ground), the CoG there, the leg at the swing's start
  and at its end (its own mass moves the CoM by a stride's share);
- four feet after the touch-down (the lifted foot a stride ahead), the CoG there.

The whole-robot CoM is what the default keeps in the support and what the feet carry
(load "total"): the body is placed so that the CoM, legs included, lands on the CoG point
(two fixed-point rounds; the legs move the CoM by millimetres). Each stance's joint values
come from the closed-form IK of its feet seen from that body; a stance with a foot out of
reach there is not judged (the gait cannot stand in it: its builder refuses the lift, and the
layout's reach check, with SHIFT_RESERVE_M of shift, sizes the strides for reach). The
torques are those of silo4kin.joint_torques at rest with load "total" (the run's), computed
in the planning frame B: :func:`static_torques` (equal to joint_torques on the URDF robot,
tests/test_stance_budget.py).

It is a design rule of the layout, not a proof for every plan: the path follower's crawl
and turns move the CoG elsewhere, and the run's check on every sample has the last word.
"""

from __future__ import annotations

import numpy as np

from planner.stability.shifts import SHIFT_EXTRA_M, shift_for_margin
from planner.ties import tie_key
from planner.trajectory.limits import urdf_limits
from planner.workspace.footholds import creep_pairs_from_hips
from planner.workspace.reach_check import joint_values_of_legs
from silo4kin.com import legs_com_offset
from silo4kin.joint_torques import motion_torques, support_torques
from silo4kin.robot import STANDARD_GRAVITY
from silo4kin.support import support_reactions

#: Travel directions of the creeping stances checked, (4, 2): along the body axes, where the
#: omnidirectional gait (planner/gaits/omni.py) starts and ends, from and to its creeping
#: stance. Its off-axis directions put the feet elsewhere on their ellipses; the 16
#: directions of 22.5 deg cut SILO4's λ_x at h 0.22 m from 0.49 to 0.28 m (four times the
#: work): not taken, the run's check covers them.
TRAVEL_DIRECTIONS = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])

#: Whether the stances of a pair's front leg lifting first are checked too. The creeping
#: gait lifts the rear leg first; the omnidirectional gait may lift the front one first
#: (from the creeping stance towards a direction across it: issue 21's SILO4 case at
#: h 0.22 m, RF lifting with RH a half stride behind its centre, RH_hip_pitch 1.16 x its
#: budget at the nearest shift). Checking those stances here, with the nearest shift, cut
#: SILO4's λ_x at h 0.2 m from 0.498 to 0.284 m (its centres cannot move in: the knee's
#: fold bounds the reachable set there), which breaks Chapter 6's 0.7 x the thesis's time;
#: the builder's shift now moves the CoM where the stance legs keep the budget instead
#: (planner/gaits/load_caps.py), which keeps those lifts on SILO4's corpus paths.
FRONT_FIRST = False

#: Fixed-point rounds placing the body so that the whole-robot CoM lands on the CoG point.
COM_ROUNDS = 2


def budget_nm(robot, headroom: float) -> np.ndarray:
    """The effort budget (12,) [N m] of ``robot``'s joints: ``headroom`` x URDF effort."""
    return float(headroom) * urdf_limits(robot)[1]


def static_torques(
    robot, q: np.ndarray, position_foot_in_base: np.ndarray, contact: np.ndarray
) -> np.ndarray:
    """Static joint torques (N, 12) [N m] with load "total" (the whole robot carried by the
    stance feet, eq A.14 + A.34 at q̇ = q̈ = 0) of ``robot`` in the planning frame B (legs'
    hips from the body CoG), joint values ``q`` (N, 12) [rad], feet (N, 4, 3) [m] in B,
    stance flags ``contact`` (N, 4): silo4kin.joint_torques.joint_torques of the URDF robot,
    its CoM taken in B."""
    q = np.asarray(q, dtype=float)
    com = legs_com_offset(tuple(robot.legs), q, float(robot.total_mass))[:, :2]
    rel = np.asarray(position_foot_in_base, dtype=float)[:, :, :2] - com[:, None, :]
    weight = float(robot.total_mass) * STANDARD_GRAVITY
    reactions = support_reactions(rel, np.asarray(contact, dtype=bool), weight).force
    zeros = np.zeros_like(q)
    return motion_torques(robot, q, zeros, zeros) + support_torques(robot, q, reactions)


def creep_stances(
    position_hip_in_base: np.ndarray,
    position_mid_in_base: np.ndarray,
    stride_m: float,
    direction: np.ndarray,
    target_m: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The stances of a creeping cycle along ``direction`` (unit (2,)) with stride
    ``stride_m`` [m], the pairs of its nearest body axis swinging (as the omnidirectional
    gait's, planner/gaits/omni.py; module docstring): (feet (K, 4, 3) [m] in the nominal body frame,
    stance flags (K, 4), CoG points (K, 2) [m]); a lift whose triangle has no point with
    margin ``target_m`` [m] adds only its nominal four-foot stance (stability is the
    stride's other test, footholds.stable_stride)."""
    d = np.asarray(direction, dtype=float)[:2]
    mid = np.asarray(position_mid_in_base, dtype=float)
    axes = np.array([[0.0, 1.0], [0.0, -1.0], [1.0, 0.0], [-1.0, 0.0]])  # omni.AXIS_TIE_ORDER
    axis = axes[int(np.argmax([tie_key(float(a @ d)) for a in axes]))]
    first, second = creep_pairs_from_hips(position_hip_in_base, axis)
    step = np.array([d[0], d[1], 0.0]) * 0.5 * stride_m
    feet_out, contact_out, cog_out = [], [], []
    all_feet = np.ones(4, dtype=bool)

    def add(feet: np.ndarray, lifted: int | None, cog: np.ndarray) -> None:
        contact = all_feet.copy()
        if lifted is not None:
            contact[lifted] = False
        feet_out.append(feet.copy())
        contact_out.append(contact)
        cog_out.append(np.asarray(cog, dtype=float))

    pairs = (first, second) + ((first[::-1], second[::-1]) if FRONT_FIRST else ())
    for pair in pairs:
        feet = mid.copy()
        feet[list(pair)] -= step
        for a in pair:
            add(feet, None, np.zeros(2))
            support = feet[[k for k in range(4) if k != a], :2]
            cog = shift_for_margin(support, np.zeros(2), target_m)
            if cog is not None:
                add(feet, None, cog)
                add(feet, a, cog)
            feet[a] = mid[a] + step
            if cog is not None:
                add(feet, a, cog)  # the swing's end: the leg's mass moved ahead
                add(feet, None, cog)
    return np.array(feet_out), np.array(contact_out), np.array(cog_out)


def stance_peaks(robot, feet: np.ndarray, contact: np.ndarray, cog: np.ndarray) -> np.ndarray:
    """|static torque| (K, 12) [N m] of each stance (feet (K, 4, 3) [m] in the nominal body
    frame, flags (K, 4), CoG points (K, 2) [m]) with the body placed so that the whole-robot
    CoM lands on its CoG point (COM_ROUNDS); 0 where a foot is out of reach (module
    docstring)."""
    legs = tuple(robot.legs)
    k = len(feet)
    body = np.zeros((k, 3))
    body[:, :2] = cog
    idx = np.tile(np.arange(4), k)
    q = np.zeros((k, 12))
    reached = np.zeros(k, dtype=bool)
    for _ in range(COM_ROUNDS + 1):
        rel = feet - body[:, None, :]
        q_legs, ok = joint_values_of_legs(legs, idx, rel.reshape(-1, 3))
        q = q_legs.reshape(k, 12)
        reached = ok.reshape(k, 4).all(axis=1) & np.all(np.isfinite(q), axis=1)
        q = np.where(np.isfinite(q), q, 0.0)
        com = legs_com_offset(legs, q, float(robot.total_mass))[:, :2]
        body[:, :2] = cog - com
    rel = feet - body[:, None, :]
    out = np.zeros((k, 12))
    rows = np.flatnonzero(reached)
    if rows.size:
        out[rows] = np.abs(static_torques(robot, q[rows], rel[rows], contact[rows]))
    return out


def ellipse_stride(extents_m: np.ndarray, direction: np.ndarray) -> float:
    """The stride [m] along unit ``direction`` (2,) of the omnidirectional gait's foothold
    ellipse (planner/gaits/foothold_ellipse.py): its diameter along it, semi-axes
    extents_m / 2 = (λ_x / 2, λ_y / 2); λ_x along x, λ_y along y, 0 across a zero extent."""
    ax, ay = 0.5 * float(extents_m[0]), 0.5 * float(extents_m[1])
    ux, uy = float(direction[0]), float(direction[1])
    if (ax <= 0.0 and abs(ux) > 1e-12) or (ay <= 0.0 and abs(uy) > 1e-12):
        return 0.0
    q = (ux / ax) ** 2 if ax > 0.0 else 0.0
    q += (uy / ay) ** 2 if ay > 0.0 else 0.0
    return 2.0 / float(np.sqrt(q)) if q > 0.0 else 0.0


def creep_stances_keep(
    robot,
    position_mid_in_base: np.ndarray,
    extents_m: np.ndarray,
    threshold_m: float,
    budget: np.ndarray,
    directions: np.ndarray = TRAVEL_DIRECTIONS,
) -> np.ndarray:
    """(S,) bool: whether the creeping stances (module docstring) with each of the extents
    ``extents_m`` (S, 2) [m] (λ_x, λ_y), along every one of ``directions`` (D, 2) with the
    stride :func:`ellipse_stride`, keep every joint within ``budget`` (12,) [N m];
    ``robot`` in the planning frame, centres ``position_mid_in_base`` (4, 3) [m] on the
    ground, the lifts shifted to margin ``threshold_m`` + SHIFT_EXTRA_M."""
    hips = np.array([leg.position_hip_in_base for leg in robot.legs], dtype=float)
    extents = np.atleast_2d(np.asarray(extents_m, dtype=float))
    parts = [
        creep_stances(
            hips, position_mid_in_base, ellipse_stride(lam, d), d, threshold_m + SHIFT_EXTRA_M
        )
        for lam in extents
        for d in directions
    ]
    counts = [len(p[0]) for p in parts]
    peaks = stance_peaks(
        robot,
        np.concatenate([p[0] for p in parts]),
        np.concatenate([p[1] for p in parts]),
        np.concatenate([p[2] for p in parts]),
    )
    ok = np.all(peaks <= budget, axis=1)
    per = np.split(ok, np.cumsum(counts)[:-1])
    d = len(directions)
    return np.array([all(np.all(per[i * d + j]) for j in range(d)) for i in range(len(extents))])


def budget_scale(
    robot,
    position_mid_in_base: np.ndarray,
    extents_m: np.ndarray,
    threshold_m: float,
    budget: np.ndarray,
    samples: int = 16,
) -> float:
    """Largest factor f in [0, 1] on the extents ``extents_m`` (2,) [m] whose creeping
    stances keep the budget (:func:`creep_stances_keep`); -1 when none does, not even
    f = 0 (every foot at its centre). Like footholds.stable_stride the factors are scanned
    from 1 down (the torques need not be monotonic in the stride), on a grid of
    ``samples``, and then again between the first passing one and the failing one above it
    (to 1 / samples²: 2 mm of SILO4's stride).

    The full extents (f = 1) are judged alone first: where they keep the budget (every
    height of SILO4's range, most of any robot's) the scan ends there, and the other
    factors' stances (15 of 16: ~94 % of the torques) are not built. Each stance's torques
    are its own (row by row), so the answer is the batch's."""
    lam = np.asarray(extents_m, dtype=float)

    def ok(factors: np.ndarray) -> np.ndarray:
        return creep_stances_keep(
            robot, position_mid_in_base, factors[:, None] * lam[None], threshold_m, budget
        )

    grid = np.linspace(1.0, 0.0, samples)
    if ok(grid[:1])[0]:
        return 1.0
    passing = np.flatnonzero(ok(grid[1:])) + 1 if grid.size > 1 else np.zeros(0, dtype=int)
    if passing.size == 0:
        return -1.0
    i = int(passing[0])
    fine = np.linspace(float(grid[i - 1]), float(grid[i]), samples + 1)[1:]
    return float(fine[int(np.argmax(ok(fine)))])
