"""Dense samples of a step list: base pose, feet, joints q, q̇, q̈, contacts, margin, phases.

Per sample (vectorised over all N samples, one IK call per leg):
    base      body steps: cosine blend (eq 5.13-5.15); rotate steps: quintic blend
              (eq 5.16-5.28) on yaw and position; transfers: still.
    feet (W)  stance feet fixed; swing foot: cosine blend in x, y (eq 5.2-5.3) and the lift
              of eq 5.4 with h_max = Workspace.swing_height_m (eq 5.12).
    feet (B)  u = Rᵀ(p - b); u̇ = Rᵀ(ṗ - ḃ) - ψ̇ S u;
              ü = Rᵀ(p̈ - b̈) - 2ψ̇ S Rᵀ(ṗ - ḃ) - ψ̈ S u - ψ̇² u_xy   (S = [[0, -1], [1, 0]] on x, y)
    joints    q = IK(u) (eq 3.10-3.24), q̇ = J⁻¹u̇ (3.25), q̈ = J⁻¹(ü - J̇q̇) (3.36).
Derivatives are computed per time unit and converted with unit_time_s. The sample at a step
boundary belongs to the later step (τ = 0); the last sample closes the last step (τ = 1).
A foot is out of contact during the whole window [t_start, t_end) of its transfer.
"""

from __future__ import annotations

import numpy as np

from silo4kin.kinematics import inverse_kinematics_masked, jacobian, jacobian_derivative

from .stability import support_margin
from .steps import Step
from .trajectories import cosine_blend, lift, quintic_blend
from .trajectory import Trajectory


#: A non-singular stand-in [rad] for unreachable rows, so the batched solves never fail.
_SAFE_Q = np.array([0.0, 0.0, -np.pi / 2])


def _inverse_solver(jac: np.ndarray):
    """x = J⁻¹ b for a batch of 3x3 J (N, 3, 3) by Cramer's rule (faster than a batched LU
    for 3x3): x_i = b · (c_j × c_k) / det with the columns c of J."""
    c0, c1, c2 = jac[:, :, 0], jac[:, :, 1], jac[:, :, 2]
    r0, r1, r2 = np.cross(c1, c2), np.cross(c2, c0), np.cross(c0, c1)
    inv_det = 1.0 / np.einsum("ni,ni->n", c0, r0)

    def solve(b: np.ndarray) -> np.ndarray:
        return np.stack([np.einsum("ni,ni->n", b, r) for r in (r0, r1, r2)], 1) * inv_det[:, None]
    return solve


def _step_arrays(steps: tuple[Step, ...]) -> dict[str, np.ndarray]:
    legs = ("LF", "RF", "LH", "RH")
    swing = np.array([-1 if s.leg is None else legs.index(s.leg) for s in steps])
    zero3 = np.zeros(3)
    return {
        "t0": np.array([s.t_start for s in steps]),
        "dur": np.array([s.duration for s in steps]),
        "kind": np.array([{"transfer": 0, "body": 1, "rotate": 2}[s.kind] for s in steps]),
        "b0": np.array([s.position_base_start_in_world for s in steps]),
        "b1": np.array([s.position_base_end_in_world for s in steps]),
        "y0": np.array([s.yaw_base_start for s in steps]),
        "y1": np.array([s.yaw_base_end for s in steps]),
        "swing": swing,
        "f0": np.array([zero3 if s.foothold_start_in_world is None
                        else s.foothold_start_in_world for s in steps]),
        "f1": np.array([zero3 if s.foothold_end_in_world is None
                        else s.foothold_end_in_world for s in steps]),
        "feet": np.array([s.position_feet_in_world for s in steps]),
        "label": np.array([s.label or s.kind for s in steps]),
    }


def sample_steps(robot, steps: tuple[Step, ...], swing_height_m: float,
                 samples_per_unit: int = 100, unit_time_s: float = 1.0) -> Trajectory:
    """Sample a step list into a :class:`Trajectory` (module docstring).

    Joint values of unreachable targets are NaN here; the caller verifies them.
    """
    a = _step_arrays(steps)
    total = float(steps[-1].t_end)
    n = int(round(total * samples_per_unit)) + 1
    t_units = np.arange(n) / samples_per_unit
    k = np.clip(np.searchsorted(a["t0"], t_units, side="right") - 1, 0, len(steps) - 1)
    dur = a["dur"][k]
    tau = np.clip((t_units - a["t0"][k]) / dur, 0.0, 1.0)
    kind = a["kind"][k]

    cos_p, quin_p = cosine_blend(tau, dur), quintic_blend(tau, dur)
    s = np.where(kind == 1, cos_p.s, np.where(kind == 2, quin_p.s, 0.0))
    ds = np.where(kind == 1, cos_p.ds, np.where(kind == 2, quin_p.ds, 0.0))
    dds = np.where(kind == 1, cos_p.dds, np.where(kind == 2, quin_p.dds, 0.0))
    db = a["b1"][k] - a["b0"][k]
    base = a["b0"][k] + db * s[:, None]
    base_d = db * ds[:, None]
    base_dd = db * dds[:, None]
    dy = a["y1"][k] - a["y0"][k]
    yaw, yaw_d, yaw_dd = a["y0"][k] + dy * s, dy * ds, dy * dds

    feet = a["feet"][k].copy()                       # (N, 4, 3)
    feet_d = np.zeros_like(feet)
    feet_dd = np.zeros_like(feet)
    swing = a["swing"][k]
    idx = np.flatnonzero(swing >= 0)
    if idx.size:
        leg = swing[idx]
        df = a["f1"][k[idx]] - a["f0"][k[idx]]
        c = cosine_blend(tau[idx], dur[idx])
        z = lift(tau[idx], dur[idx], swing_height_m)
        feet[idx, leg] = a["f0"][k[idx]] + df * c.s[:, None]
        feet_d[idx, leg] = df * c.ds[:, None]
        feet_dd[idx, leg] = df * c.dds[:, None]
        feet[idx, leg, 2] += z.s
        feet_d[idx, leg, 2] += z.ds
        feet_dd[idx, leg, 2] += z.dds
    contact = np.ones((n, 4), dtype=bool)
    contact[idx, swing[idx]] = False

    # world -> base frame (rotation about z only)
    cy, sy = np.cos(yaw)[:, None], np.sin(yaw)[:, None]

    def to_base(v: np.ndarray) -> np.ndarray:
        out = v.copy()
        out[..., 0] = cy * v[..., 0] + sy * v[..., 1]
        out[..., 1] = -sy * v[..., 0] + cy * v[..., 1]
        return out

    def s_op(v: np.ndarray) -> np.ndarray:             # S v on x, y; zero z
        out = np.zeros_like(v)
        out[..., 0], out[..., 1] = -v[..., 1], v[..., 0]
        return out

    rel = feet - base[:, None, :]
    rel_d = feet_d - base_d[:, None, :]
    rel_dd = feet_dd - base_dd[:, None, :]
    u = to_base(rel)
    rd_b = to_base(rel_d)
    wd, wdd = yaw_d[:, None, None], yaw_dd[:, None, None]
    u_d = rd_b - wd * s_op(u)
    u_xy = u.copy()
    u_xy[..., 2] = 0.0
    u_dd = to_base(rel_dd) - 2.0 * wd * s_op(rd_b) - wdd * s_op(u) - wd * wd * u_xy

    q = np.empty((n, 12))
    qd = np.empty((n, 12))
    qdd = np.empty((n, 12))
    for j, leg_geo in enumerate(robot.legs):
        qj = inverse_kinematics_masked(leg_geo, u[:, j]).q
        ok = np.all(np.isfinite(qj), axis=1)
        qs = np.where(ok[:, None], qj, _SAFE_Q)   # unreachable rows: NaN below, no LinAlgError
        solve = _inverse_solver(jacobian(leg_geo, qs))
        qdj = solve(u_d[:, j])                                          # eq 3.25
        jd = jacobian_derivative(leg_geo, qs, qdj)
        qddj = solve(u_dd[:, j] - np.einsum("nij,nj->ni", jd, qdj))     # eq 3.36
        q[:, 3 * j:3 * j + 3] = qj
        qd[:, 3 * j:3 * j + 3] = np.where(ok[:, None], qdj, np.nan)
        qdd[:, 3 * j:3 * j + 3] = np.where(ok[:, None], qddj, np.nan)

    margin = support_margin(feet[..., :2], contact, base[:, :2])
    return Trajectory(
        t=t_units * unit_time_s, unit_time_s=float(unit_time_s),
        position_base_in_world=base, yaw_base_in_world=yaw,
        joint_names=tuple(robot.joint_names), q=q, qd=qd / unit_time_s,
        qdd=qdd / unit_time_s**2, position_foot_in_world=feet, contact=contact,
        margin=margin, phase=a["label"][k])
