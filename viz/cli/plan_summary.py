"""What ``silo4 plan`` prints about a plan: the choices it made for the user (gait, unit
time) and the two summary lines (path, time, distance, speed; E_n, margin, cycles, gait)."""

from __future__ import annotations

import argparse
from typing import Any


def automatic_choices(args: argparse.Namespace, plan: Any, metrics: dict) -> list[str]:
    """What silo4 chose for the user: the gait of ``--gait auto`` and why, the unit time of
    ``--unit-time auto``. The height of ``--height auto`` has its own line."""
    lines = []
    if getattr(args, "gait", "auto") == "auto":
        reason = metrics.get("fallback_reason")
        if reason:
            why = f"the faster gaits found no step: {reason}"
        elif plan.gait in ("crawl", "creep"):
            why = "the least time of the gaits tried: the crawl on insect legs and the creep"
        else:
            why = f"the {plan.workspace.preset} preset's gait"
        lines.append(f"--gait auto: {plan.gait} ({why})")
    if getattr(args, "unit_time", None) == "auto":
        limits = metrics.get("joint_limits") or {}
        lines.append(
            f"--unit-time auto: t_l = {plan.trajectory.unit_time_s:.4f} s (the "
            "shortest unit time within the URDF velocity and effort limits"
            + (
                f", ratios {limits['velocity_ratio']:.2f} / {limits['effort_ratio']:.2f}"
                if "velocity_ratio" in limits and "effort_ratio" in limits
                else ""
            )
            + ")"
        )
    return lines


def _number(value: Any, fmt: str, unit: str = "", missing: str = "n/a") -> str:
    """``value`` in ``fmt`` (a rounded zero as 0, never -0.000) and ``unit``."""
    if value is None:
        return missing
    text = format(value, fmt)
    if text.startswith("-") and float(text) == 0.0:
        text = text[1:]
    return text + unit


def format_summary(plan: Any, metrics: dict, n_waypoints: int) -> str:
    """Two lines: path, time, distance, speed; E_n, margin, cycles (n/a when nothing moved)."""
    m = metrics
    return (
        f"{n_waypoints} waypoints at h = {plan.height:.3g} m, workspace "
        f"{plan.workspace.preset} (stride {_number(m.get('stride_m'), '.4f', ' m')}): "
        f"{_number(m.get('normalized_time'), '.0f')} time units, "
        f"{_number(m.get('distance_m'), '.2f', ' m')}, "
        f"{_number(m.get('average_speed'), '.3f', ' m/unit')}\n"
        f"E_n {_number(m.get('normalized_error_m'), '.3f', ' m')}, min stability margin "
        f"{_number(m.get('min_stability_margin_m'), '.3f', ' m', 'n/a (no leg lifted)')}, "
        f"{m.get('n_creep_cycles', '?')} creep cycles, "
        f"{m.get('n_spin_cycles', '?')} spin cycles"
        + (f", {m['n_crawl_swings']} crawl swings" if m.get("n_crawl_swings") else "")
        + f"; gait {m.get('gait', '?')}"
        + (f" ({m['fallback_reason']})" if m.get("fallback_reason") else "")
        + f", duty factor {_number(m.get('duty_factor'), '.2f')}"
    )
