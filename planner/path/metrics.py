"""Plan metrics (thesis Ch. 6): time, distance, speed, normalised error E_n (eq 6.1), margins,
peak joint rates, gait counts, and the thesis's time count for the same decisions.

    normalized_time      t / t_l at the end of the plan [units].
    distance_m           length of the nominal CoG path (creeping body phases, Phase.CREEP) [m],
                         as the thesis counts it (the omni gait's steps vary: their sum,
                         Plan.nominal_distance_m); cog_path_length_m adds the stability shifts
                         (length of the sampled CoG path in the ground plane).
    average_speed        distance_m / normalized_time [m per unit].
    normalized_error_m   eq 6.1: mean over waypoints of |allowed - desired|, with "allowed" the
                         sampled CoG (as walked, shifts included) when the planner was done
                         with the waypoint [m]; normalized_error_nominal_m uses the gait's
                         nominal CoG instead (docs/decisions.md: why E_n is taken as walked).
    min_stability_margin_m   smallest S_m of the planner's criterion while a leg is in the
                         air [m]; min_margin_com_m / min_margin_body_m the same for the
                         whole-robot CoM and the body CoG.
    com_outside_support  None, or the worst sample (index, t, margin) where the whole-robot
                         CoM is outside the support polygon with a leg up (the thesis
                         preset plans on the body CoG only); warnings says it in one line.
    warnings             those lines, and one when the default preset leaves a waypoint
                         further than the tolerance (tolerance_warning; never silently).
    gait, fallback_reason    the gait that walked (Plan.gait: "crawl", "creep", "facing",
                         "plain" or "thesis"), and why a gait preferred to it was not used.
    n_crawl_swings       swings of the continuous crawl (planner/gaits/crawl.py).
    duty_factor          β: the fraction of samples each foot is on the ground, averaged over
                         the feet (thesis §4.2: 7/8 for the creeping gait; 3/4 and up for a
                         crawl).
    height_search        None, or how ``height="auto"`` chose height_m (planner/path/height.py).
    thesis_time_units    the same decisions counted the thesis's way: 8 units per creeping
                         cycle (half cycles 4), 2 + 6 n + 2 per turn with n from the thesis's
                         halving rule (§5.5), no shifts.
"""

from __future__ import annotations

import numpy as np

from planner.gaits.steps import Phase, StepKind
from planner.path.plan_path import Plan
from planner.stability.margin import MARGIN_TOLERANCE

#: Rounding allowed over the tolerance before a waypoint counts as missed [m]: the walked CoG
#: is a sample of the trajectory, exact to ~1e-12 m where the plan lands on the waypoint.
TOLERANCE_SLACK_M = 1e-9


def com_warning(plan: Plan) -> tuple[dict[str, float] | None, list[str]]:
    """(worst sample, warning lines) when the whole-robot CoM leaves the support polygon
    with a leg in the air (margin_com < 0); (None, []) otherwise."""
    tr = plan.trajectory
    if tr.margin_com is None or not np.any(np.isfinite(tr.margin_com)):
        return None, []
    lifted = ~np.all(tr.contact, axis=1)
    m = np.where(lifted, tr.margin_com, np.inf)
    i = int(np.argmin(m))
    if not m[i] < -MARGIN_TOLERANCE:  # a CoM on an edge to rounding is not outside
        return None, []
    worst = {
        "sample": i,
        "t_s": float(tr.t[i]),
        "time_units": float(tr.time_units[i]),
        "margin_com_m": float(m[i]),
        "n_samples": int(np.sum(m < -MARGIN_TOLERANCE)),
    }
    line = (
        f"warning: the whole-robot CoM leaves the support polygon by "
        f"{-m[i] * 1000:.2f} mm at sample {i} (t = {tr.t[i]:.2f} s, {tr.phase[i]}); "
        f"{worst['n_samples']} samples with a leg up are outside (the "
        f"{plan.preset.name!r} preset keeps only the body CoG inside)"
    )
    return worst, [line]


def tolerance_warning(plan: Plan, errors_m: np.ndarray) -> list[str]:
    """One warning line when a preset that promises to arrive (Preset.arrives: the
    default's gaits land on each waypoint, planner/gaits/) leaves a waypoint
    further than the tolerance: ``errors_m`` (K,) [m] from the CoG as walked. The thesis
    preset walks whole cycles (§5.5) and is not held to it."""
    if not plan.preset.arrives or not len(errors_m):
        return []
    missed = errors_m > plan.tolerance + TOLERANCE_SLACK_M
    if not missed.any():
        return []
    k = int(np.argmax(errors_m))
    return [
        f"warning: waypoint {k} is reached only within {errors_m[k]:.3f} m, over the "
        f"tolerance {plan.tolerance:g} m ({int(missed.sum())} of {len(errors_m)} "
        f"waypoints missed; gait {plan.gait})"
    ]


def compute_metrics(plan: Plan) -> dict[str, object]:
    """JSON-serialisable metrics of a plan (module docstring)."""
    tr = plan.trajectory
    t_end = float(tr.time_units[-1])
    xy = tr.position_base_in_world[:, :2]
    cog_path = float(np.sum(np.hypot(*np.diff(xy, axis=0).T))) if len(tr) > 1 else 0.0
    nominal = getattr(plan, "nominal_distance_m", None)
    distance = float(
        sum(
            plan.workspace.stride_m / 2
            for s in plan.steps
            if s.phase == Phase.CREEP and s.kind == StepKind.BODY
        )
        if nominal is None
        else nominal
    )
    walked = (
        plan.position_walked_in_world
        if len(plan.position_walked_in_world)
        else plan.position_reached_in_world
    )
    errors = np.hypot(*(walked - plan.waypoints_in_world).T)
    errors_nominal = np.hypot(*(plan.position_reached_in_world - plan.waypoints_in_world).T)
    lifted = ~np.all(tr.contact, axis=1)
    units = {str(p): 0.0 for p in (Phase.CREEP, Phase.SPIN, Phase.TRANSITION, Phase.SHIFT)}
    for s in plan.steps:
        if s.phase in units:
            units[str(s.phase)] += s.duration
    worst, warnings = com_warning(plan)
    warnings = warnings + tolerance_warning(plan, errors)

    def lifted_min(values: np.ndarray | None) -> float | None:
        if values is None or not lifted.any():
            return None
        return float(values[lifted].min())

    thesis_time = 4 * plan.n_creep_half_cycles + sum(4 + 6 * sp.thesis_cycles for sp in plan.spins)
    names = tr.joint_names
    return {
        "workspace": plan.workspace.preset,
        "height_m": plan.height,
        "height_search": plan.height_search,
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
        "normalized_error_nominal_m": float(errors_nominal.mean()),
        "stability_point": str(plan.preset.stability_point),
        "min_stability_margin_m": float(tr.margin[lifted].min()) if lifted.any() else None,
        "min_margin_com_m": lifted_min(tr.margin_com),
        "min_margin_body_m": lifted_min(tr.margin_body),
        "com_outside_support": worst,
        "warnings": warnings,
        "gait": plan.gait,
        "fallback_reason": plan.fallback_reason,
        "min_stability_margin_all_m": float(tr.margin.min()),
        "peak_abs_qd": {n: float(v) for n, v in zip(names, np.abs(tr.qd).max(axis=0))},
        "peak_abs_qdd": {n: float(v) for n, v in zip(names, np.abs(tr.qdd).max(axis=0))},
        "n_creep_cycles": plan.n_creep_half_cycles / 2,
        "n_creep_half_cycles": plan.n_creep_half_cycles,
        "n_crawl_swings": int(getattr(plan, "n_crawl_swings", 0)),
        "duty_factor": float(tr.contact.mean()) if len(tr) > 1 else 1.0,
        "n_spins": len(plan.spins),
        "n_spin_cycles": int(sum(sp.cycles for sp in plan.spins)),
        "n_shifts": plan.n_shifts,
        "n_folded_shifts": plan.n_folded_shifts,
        "time_units_by_phase": units,
        "thesis_spin_cycles": int(sum(sp.thesis_cycles for sp in plan.spins)),
        "thesis_time_units": float(thesis_time),
        "spins": [
            {
                "waypoint_index": sp.waypoint_index,
                "psi_deg": float(np.rad2deg(sp.psi_rad)),
                "cycles": sp.cycles,
                "thesis_cycles": sp.thesis_cycles,
                "leg_orders": [list(o) for o in sp.orders],
            }
            for sp in plan.spins
        ],
    }
