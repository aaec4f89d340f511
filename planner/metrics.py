"""Plan metrics (thesis Ch. 6): time, distance, speed, normalised error E_n (eq 6.1), margins,
peak joint rates, gait counts, and the thesis's time count for the same decisions.

    normalized_time      t / t_l at the end of the plan [units].
    distance_m           length of the nominal CoG path (creeping body phases) [m], as the
                         thesis counts it; cog_path_length_m adds the stability shifts
                         (length of the sampled CoG path in the ground plane).
    average_speed        distance_m / normalized_time [m per unit].
    normalized_error_m   eq 6.1: mean over waypoints of |allowed - desired|, with "allowed" the
                         nominal CoG when the planner was done with the waypoint [m].
    min_stability_margin_m   smallest S_m while a leg is in the air [m].
    thesis_time_units    the same decisions counted the thesis's way: 8 units per creeping
                         cycle (half cycles 4), 2 + 6 n + 2 per turn with n from the thesis's
                         halving rule (§5.5), no shifts.
"""

from __future__ import annotations

import numpy as np

from .path import Plan


def compute_metrics(plan: Plan) -> dict[str, object]:
    """JSON-serialisable metrics of a plan (module docstring)."""
    tr = plan.trajectory
    t_end = float(tr.time_units[-1])
    xy = tr.position_base_in_world[:, :2]
    cog_path = float(np.sum(np.hypot(*np.diff(xy, axis=0).T))) if len(tr) > 1 else 0.0
    distance = float(sum(plan.workspace.stride_m / 2 for s in plan.steps
                         if s.label == "creep body"))
    errors = np.hypot(*(plan.position_reached_in_world - plan.waypoints_in_world).T)
    lifted = ~np.all(tr.contact, axis=1)
    units = {kind: 0.0 for kind in ("creep", "spin", "transition", "shift")}
    for s in plan.steps:
        key = s.label.split(" ")[0] if s.label else s.kind
        units[key if key in units else "creep"] = units.get(key, 0.0) + s.duration
    thesis_time = 4 * plan.n_creep_half_cycles + sum(4 + 6 * sp.thesis_cycles
                                                     for sp in plan.spins)
    names = tr.joint_names
    return {
        "workspace": plan.workspace.preset,
        "height_m": plan.height,
        "stride_m": plan.workspace.stride_m,
        "swing_height_m": plan.workspace.swing_height_m,
        "psi_max_deg": float(np.rad2deg(plan.workspace.psi_max_rad)),
        "tolerance_m": plan.tolerance,
        "stability_threshold_m": plan.stability_threshold,
        "n_waypoints": int(plan.waypoints_in_world.shape[0]),
        "n_samples": len(tr),
        "normalized_time": t_end,
        "distance_m": distance,
        "cog_path_length_m": cog_path,
        "average_speed": distance / t_end if t_end > 0 else 0.0,
        "normalized_error_m": float(errors.mean()),
        "min_stability_margin_m": float(tr.margin[lifted].min()) if lifted.any() else None,
        "min_stability_margin_all_m": float(tr.margin.min()),
        "peak_abs_qd": {n: float(v) for n, v in zip(names, np.abs(tr.qd).max(axis=0))},
        "peak_abs_qdd": {n: float(v) for n, v in zip(names, np.abs(tr.qdd).max(axis=0))},
        "n_creep_cycles": plan.n_creep_half_cycles / 2,
        "n_creep_half_cycles": plan.n_creep_half_cycles,
        "n_spins": len(plan.spins),
        "n_spin_cycles": int(sum(sp.cycles for sp in plan.spins)),
        "n_shifts": plan.n_shifts,
        "time_units_by_phase": units,
        "thesis_spin_cycles": int(sum(sp.thesis_cycles for sp in plan.spins)),
        "thesis_time_units": float(thesis_time),
        "spins": [{"waypoint_index": sp.waypoint_index, "psi_deg": float(np.rad2deg(sp.psi_rad)),
                   "cycles": sp.cycles, "thesis_cycles": sp.thesis_cycles,
                   "leg_orders": [list(o) for o in sp.orders]} for sp in plan.spins],
    }
