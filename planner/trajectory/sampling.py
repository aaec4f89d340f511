"""Dense samples of a step list: base pose, feet, joints q, q̇, q̈, contacts, margin, phases.

Per sample (vectorised over blocks of samples; per leg one fused IK / rate solve,
silo4kin.kinematics.joint_motion, for the samples where its foot or the base moves):
    base      body steps: cosine blend (eq 5.13-5.15); rotate steps: quintic blend
              (eq 5.16-5.28) on yaw and position; transfers: still, except in the
              continuous crawl (planner/gaits/crawl.py), where the base moves as in a body step.
    feet (W)  stance feet fixed; swing foot: cosine blend in x, y (eq 5.2-5.3) and the lift
              of eq 5.4 with h_max = Workspace.swing_height_m (eq 5.12).
    feet (B)  u = Rᵀ(p - b); u̇ = Rᵀ(ṗ - ḃ) - ψ̇ S u;
              ü = Rᵀ(p̈ - b̈) - 2ψ̇ S Rᵀ(ṗ - ḃ) - ψ̈ S u - ψ̇² u_xy   (S = [[0, -1], [1, 0]] on x, y)
    joints    q = IK(u) (eq 3.10-3.24), q̇ = J⁻¹u̇ (3.25), q̈ = J⁻¹(ü - J̇q̇) (3.36).
Derivatives are computed per time unit and converted with unit_time_s. The sample at a step
boundary belongs to the later step (τ = 0); the last sample closes the last step (τ = 1).
A foot is out of contact during the whole window [t_start, t_end) of its transfer.

Round feet (silo4kin/foot_contact.py, r > 0) roll during stance: the foot-frame targets
above are those of point feet, and planner/trajectory/rolling_feet.py moves them as the
ball rolls and solves the joints again; ``position_foot_in_world`` is then the contact point
(the foot frame minus the contact offset along z) and the support polygon is that of the
contact points of each sample. Point feet (r = 0) skip that pass.
"""

from __future__ import annotations

import numpy as np

from planner.gaits.steps import Step, StepKind
from planner.stability.margin import margin_to_edges, support_edges
from planner.trajectory.heightmap_rest import heightmap_ground
from planner.trajectory.profiles import cosine_blend, lift, quintic_blend, smooth_lift
from planner.trajectory.rolling_feet import RollingRates, SampledFeet, roll_feet, stance_normals
from planner.trajectory.samples import LEGS, Trajectory
from planner.trajectory.terrain_clearance import swing_height_at
from silo4kin import legs as leg_families
from silo4kin.foot_contact import FootBall, foot_ball
from silo4kin.kinematics import joint_motion as insect_joint_motion


def joint_motion(leg, u, u_d, u_dd, out=None):
    """q, q̇, q̈ of one leg for foot states in B, either family: the insect closed form fills
    ``out`` in place (kinematics.joint_motion, the fast path); a mammal leg goes through
    silo4kin.legs.joint_motion and is copied into ``out``."""
    if leg_families.family_of(leg) is leg_families.INSECT:
        return insect_joint_motion(leg, u, u_d, u_dd, out=out)
    stack = lambda v: np.column_stack(v) if isinstance(v, tuple) else v  # noqa: E731
    motion = leg_families.joint_motion(leg, stack(u), stack(u_d), stack(u_dd))
    if out is not None:
        for dst, src in zip(out, motion[:3]):
            dst[...] = src
    return motion


#: Samples processed together: the temporaries of a block stay in the CPU cache, which makes
#: the element-wise numpy work about twice as fast as on whole trajectories.
BLOCK_SAMPLES = 8192

#: A vector per sample as its x, y, z components, each (n,).
_Xyz = tuple[np.ndarray, np.ndarray, np.ndarray]


def _step_arrays(steps: tuple[Step, ...]) -> dict[str, np.ndarray]:
    swing = np.array([-1 if s.leg is None else LEGS.index(s.leg) for s in steps])
    zero3 = np.zeros(3)
    return {
        "t0": np.array([s.t_start for s in steps]),
        "dur": np.array([s.duration for s in steps]),
        "kind": np.array(
            [{StepKind.TRANSFER: 0, StepKind.BODY: 1, StepKind.ROTATE: 2}[s.kind] for s in steps]
        ),
        "b0": np.array([s.position_base_start_in_world for s in steps]),
        "b1": np.array([s.position_base_end_in_world for s in steps]),
        "y0": np.array([s.yaw_base_start for s in steps]),
        "y1": np.array([s.yaw_base_end for s in steps]),
        "swing": swing,
        "f0": np.array(
            [
                zero3 if s.foothold_start_in_world is None else s.foothold_start_in_world
                for s in steps
            ]
        ),
        "f1": np.array(
            [zero3 if s.foothold_end_in_world is None else s.foothold_end_in_world for s in steps]
        ),
        "feet": np.array([s.position_feet_in_world for s in steps]),
        "label": np.array([s.label or s.kind for s in steps]),
    }


def _foot_in_base(
    foot: np.ndarray,
    foot_d: np.ndarray,
    foot_dd: np.ndarray,
    base: np.ndarray,
    base_d: np.ndarray,
    base_dd: np.ndarray,
    yaw: np.ndarray,
    yaw_d: np.ndarray,
    yaw_dd: np.ndarray,
) -> tuple[_Xyz, _Xyz, _Xyz]:
    """u, u̇, ü of the module docstring (each a 3-tuple of (n,) [m, m/unit, m/unit²]) from the
    foot and base in W (n, 3) and the base yaw ψ, ψ̇, ψ̈ (n,)."""
    cy, sy = np.cos(yaw), np.sin(yaw)

    def to_base(v: np.ndarray) -> _Xyz:  # Rᵀ v
        return cy * v[:, 0] + sy * v[:, 1], -sy * v[:, 0] + cy * v[:, 1], v[:, 2]

    u = to_base(foot - base)
    rd = to_base(foot_d - base_d)  # Rᵀ(ṗ - ḃ)
    rdd = to_base(foot_dd - base_dd)  # Rᵀ(p̈ - b̈)
    u_d = (rd[0] + yaw_d * u[1], rd[1] - yaw_d * u[0], rd[2])  # - ψ̇ S u
    u_dd = (
        rdd[0] + 2.0 * yaw_d * rd[1] + yaw_dd * u[1] - yaw_d * yaw_d * u[0],
        rdd[1] - 2.0 * yaw_d * rd[0] - yaw_dd * u[0] - yaw_d * yaw_d * u[1],
        rdd[2],
    )
    return u, u_d, u_dd


def _joints_at_step_start(robot, a: dict[str, np.ndarray]) -> list[np.ndarray]:
    """q, q̇, q̈ of each leg at each step's start pose with the base and feet at rest (q̇ = q̈
    = 0 unless unreachable), per leg (3, 3, S): [q/q̇/q̈, joint, step]. These are the samples
    of a stance leg during another leg's transfer, computed by the same formulas."""
    zero, zero3 = np.zeros(len(a["t0"])), np.zeros((len(a["t0"]), 3))
    return [
        np.stack(
            joint_motion(
                leg_geo,
                *_foot_in_base(
                    a["feet"][:, j], zero3, zero3, a["b0"], zero3, zero3, a["y0"], zero, zero
                ),
            )[:3]
        )
        .transpose(0, 2, 1)
        .copy()
        for j, leg_geo in enumerate(robot.legs)
    ]


def sample_steps(
    robot,
    steps: tuple[Step, ...],
    swing_height_m: float | np.ndarray,
    samples_per_unit: int = 100,
    unit_time_s: float = 1.0,
    *,
    model=None,
    stability_point: str = "body",
    smooth: bool = False,
    foot: FootBall | None = None,
    terrain=None,
) -> Trajectory:
    """Sample a step list into a :class:`Trajectory` (module docstring).

    ``robot`` has its legs in the planning frame B (PlanningModel.planning_robot).
    ``margin_body`` is S_m of the body CoG; with a ``model`` (planner.model.PlanningModel)
    ``margin_com`` is S_m of the whole-robot CoM from the sampled joint values (else NaN);
    ``margin`` is the one named by ``stability_point`` ("body" or "com").
    ``smooth`` replaces the thesis's cosine blends (body translation, swing x, y) by the
    quintic of eq 5.16 and the swing lift by trajectories.smooth_lift: every step then starts
    and ends with zero velocity and acceleration, so q̇ and q̈ are continuous at every phase
    boundary (the default's omnidirectional gait, planner/gaits/omni.py).
    ``foot`` is the robot's foot ball (default silo4kin.foot_contact.foot_ball(robot)); a
    ball that rolls gets the rolling pass of the module docstring; on ``terrain`` (a
    TerrainMap) a stance ball rolls on the plane of the surface under it, its contact point
    the centre minus r n (planner/trajectory/rolling_feet.py).

    Joint values of unreachable targets are NaN here; the caller verifies them. The samples
    are computed in blocks of BLOCK_SAMPLES. Within a step the stance set is constant, so
    the support polygon's edge lines are found once per step (stability.py), and in a
    transfer the base and the stance feet stand still, so the stance legs' joints are solved
    once per step (zero rates) and only the swing leg per sample (the crawl's transfers,
    whose base moves, solve every leg per sample).
    """
    a = _step_arrays(steps)
    total = float(steps[-1].t_end)
    n = int(round(total * samples_per_unit)) + 1
    t_units = np.arange(n) / samples_per_unit
    k = np.clip(np.searchsorted(a["t0"], t_units, side="right") - 1, 0, len(steps) - 1)
    base = np.empty((n, 3))
    yaw = np.empty(n)
    feet = np.empty((n, 4, 3))
    q, qd, qdd = np.empty((n, 12)), np.empty((n, 12)), np.empty((n, 12))
    block = np.empty((3, 12, BLOCK_SAMPLES))  # q, q̇, q̈ of a block, joint-major
    margin = np.empty(n)
    legs = np.arange(4)
    contact_steps = a["swing"][:, None] != legs  # (S, 4)
    edges = support_edges(a["feet"][..., :2], contact_steps)
    base_moves = (a["kind"] != 0) | np.any(a["b1"] != a["b0"], axis=1)  # (S,)
    moves = base_moves[:, None] | (a["swing"][:, None] == legs)  # (S, 4)
    still = _joints_at_step_start(robot, a)
    foot = foot_ball(robot) if foot is None else foot
    rolling = RollingRates(n) if foot.rolls else None
    for lo in range(0, n, BLOCK_SAMPLES):
        rows = slice(lo, min(lo + BLOCK_SAMPLES, n))
        kb = k[rows]
        dur = a["dur"][kb]
        tau = np.clip((t_units[rows] - a["t0"][kb]) / dur, 0.0, 1.0)
        kind = a["kind"][kb]
        # base pose (eq 5.13-5.15 body, 5.16-5.28 rotate) and its derivatives per unit
        quin_p = quintic_blend(tau, dur)
        cos_p = quin_p if smooth else cosine_blend(tau, dur)
        # a transfer's base moves only in the crawl (b1 != b0); elsewhere db = 0 below
        s = np.where(kind == 2, quin_p.s, cos_p.s)
        ds = np.where(kind == 2, quin_p.ds, cos_p.ds)
        dds = np.where(kind == 2, quin_p.dds, cos_p.dds)
        db = a["b1"][kb] - a["b0"][kb]
        base_b = a["b0"][kb] + db * s[:, None]
        base_d = db * ds[:, None]
        base_dd = db * dds[:, None]
        dy = a["y1"][kb] - a["y0"][kb]
        yaw_b, yaw_d, yaw_dd = a["y0"][kb] + dy * s, dy * ds, dy * dds
        base[rows], yaw[rows] = base_b, yaw_b
        margin[rows] = margin_to_edges(edges, kb, base_b[:, :2])
        # feet in W: stance feet fixed, swing foot eq 5.2-5.4 with h_max (eq 5.12)
        feet_b = a["feet"][kb]  # (n_b, 4, 3)
        feet_d = np.zeros_like(feet_b)
        feet_dd = np.zeros_like(feet_b)
        swing = a["swing"][kb]
        idx = np.flatnonzero(swing >= 0)
        if idx.size:
            leg, ks = swing[idx], kb[idx]
            df = a["f1"][ks] - a["f0"][ks]
            c = (quintic_blend if smooth else cosine_blend)(tau[idx], dur[idx])
            h_max = swing_height_at(swing_height_m, ks)  # per step over a terrain file
            z = (smooth_lift if smooth else lift)(tau[idx], dur[idx], h_max)
            feet_b[idx, leg] = a["f0"][ks] + df * c.s[:, None]
            feet_d[idx, leg] = df * c.ds[:, None]
            feet_dd[idx, leg] = df * c.dds[:, None]
            feet_b[idx, leg, 2] += z.s
            feet_d[idx, leg, 2] += z.ds
            feet_dd[idx, leg, 2] += z.dds
            if rolling is not None:
                rolling.swing_blend(rows, idx, c)
        feet[rows] = feet_b
        if rolling is not None:
            rolling.keep(rows, feet_d, feet_dd, base_d, base_dd, yaw_d, yaw_dd)
        # joints (eq 3.10-3.24, 3.25, 3.36) of the samples where the foot or the base moves
        for j, leg_geo in enumerate(robot.legs):
            out = block[:, 3 * j : 3 * j + 3, : len(kb)]  # (3, 3, n_b) view
            move = moves[kb, j]
            if move.all():
                u, u_d, u_dd = _foot_in_base(
                    feet_b[:, j],
                    feet_d[:, j],
                    feet_dd[:, j],
                    base_b,
                    base_d,
                    base_dd,
                    yaw_b,
                    yaw_d,
                    yaw_dd,
                )
                joint_motion(leg_geo, u, u_d, u_dd, out=(out[0].T, out[1].T, out[2].T))
                continue
            at_rest = np.flatnonzero(~move)
            k_rest = kb[at_rest]
            m = np.flatnonzero(move)
            motion = joint_motion(
                leg_geo,
                *_foot_in_base(
                    feet_b[m, j],
                    feet_d[m, j],
                    feet_dd[m, j],
                    base_b[m],
                    base_d[m],
                    base_dd[m],
                    yaw_b[m],
                    yaw_d[m],
                    yaw_dd[m],
                ),
            )
            for d in range(3):  # q, q̇, q̈
                for col in range(3):  # joint of the leg
                    row = out[d, col]
                    row[at_rest] = still[j][d, col][k_rest]
                    row[m] = motion[d][:, col]
        for dst, src in zip((q, qd, qdd), block):
            dst[rows] = src[:, : len(kb)].T
    contact = contact_steps[k]
    if rolling is not None:
        q, qd, qdd, feet = _roll(
            robot, foot, rolling, feet, base, yaw, contact, samples_per_unit, terrain
        )
        edges, edge_row = support_edges(feet[..., :2], contact), np.arange(n)  # per sample
        margin = margin_to_edges(edges, edge_row, base[:, :2])
    else:
        edge_row = k
    if model is not None:
        com = model.com_in_world(q, base, yaw)
        margin_com = margin_to_edges(edges, edge_row, com[:, :2])
    else:
        margin_com = np.full(n, np.nan)
    criterion = margin_com if str(stability_point) == "com" else margin
    return Trajectory(
        t=t_units * unit_time_s,
        unit_time_s=float(unit_time_s),
        position_base_in_world=base,
        yaw_base_in_world=yaw,
        joint_names=tuple(robot.joint_names),
        q=q,
        qd=qd / unit_time_s,
        qdd=qdd / unit_time_s**2,
        position_foot_in_world=feet,
        contact=contact,
        margin=criterion,
        phase=a["label"][k],
        margin_com=margin_com,
        margin_body=margin,
    )


def _roll(robot, foot: FootBall, arrays: RollingRates, feet, base, yaw, contact, spu: int, terrain):
    """q, q̇, q̈ (N, 12) per unit and the contact points (N, 4, 3) of rolling feet: the
    ball centre minus r n in stance (n the surface normal, ẑ on level ground; on a height
    map the contact normal of the triangle the ball touches, so the point of the map nearest
    the centre: planner/trajectory/heightmap_rest.py), minus r ẑ in the swing."""
    normal = stance_normals(terrain, feet, contact)
    ground = heightmap_ground(terrain, foot.rolling_radius_m)

    def solve(j: int, target, target_d, target_dd):
        u = _foot_in_base(
            target, target_d, target_dd, base, arrays.base_d, arrays.base_dd,
            yaw, arrays.yaw_d, arrays.yaw_dd,
        )  # fmt: skip
        motion = joint_motion(robot.legs[j], *u)
        return motion[0], motion[1], motion[2]

    sampled = SampledFeet(
        feet=feet,
        feet_d=arrays.feet_d,
        feet_dd=arrays.feet_dd,
        swing_s=arrays.swing_s,
        swing_ds=arrays.swing_ds,
        swing_dds=arrays.swing_dds,
        yaw=yaw,
        yaw_d=arrays.yaw_d,
        contact=contact,
        dt_units=1.0 / spu,
        normal=normal,
        yaw_dd=arrays.yaw_dd,
        ground=ground,
    )
    q, qd, qdd, targets = roll_feet(robot.legs, foot, sampled, solve)
    contact_points = targets.copy()
    if ground is not None:  # a height map: the point of the triangles each ball touches
        normal = np.tile([0.0, 0.0, 1.0], (*contact.shape, 1)) if normal is None else normal
        with np.errstate(invalid="ignore"):
            _, touching = ground(targets[contact])
        known = np.isfinite(touching).all(axis=1)
        stance_normal = normal[contact]
        stance_normal[known] = touching[known]
        normal = normal.copy()
        normal[contact] = stance_normal
    if normal is None:
        contact_points[..., 2] -= foot.contact_offset_m
    else:
        contact_points -= foot.contact_offset_m * normal
    return q, qd, qdd, contact_points
