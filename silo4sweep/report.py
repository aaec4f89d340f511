"""The sweep's results page (docs/sweep_results.md): height vs speed and accuracy beside the
thesis's conclusion (§7.1-7.2), the best height per design, the Pareto front.

Every sentence that states a finding is computed from the rows: the rank correlations
(Spearman, average ranks for ties) between stride (set by the height) and time, error and
peak joint speed, and whether their signs agree with the thesis's statement.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .summary import TIME, TORQUE, best_heights, pareto_rows
from .task import OK

#: The thesis's words the page compares against (§7.1 and §7.2, quoted).
THESIS_71 = (
    "With a longer stride length, the planned trajectory was faster, but generally "
    "less accurate. A shorter stride length led to higher joint velocities and "
    "accelerations."
)
THESIS_72 = (
    "In order to improve the ability of the plan created by the trajectory planner "
    "to follow a path more closely, an algorithm could be developed to choose the "
    "optimum height of travel, which is linked to the stride length."
)


def rank_correlation(x: Sequence[float], y: Sequence[float]) -> float:
    """Spearman's rho of x and y (Pearson correlation of their average ranks); nan when
    fewer than 3 points or one side is constant."""

    def ranks(v: np.ndarray) -> np.ndarray:
        order = np.argsort(v, kind="stable")
        r = np.empty(len(v))
        r[order] = np.arange(len(v), dtype=float)
        for value in np.unique(v):  # average ranks of ties
            tied = v == value
            r[tied] = r[tied].mean()
        return r

    a, b = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if len(a) < 3 or np.ptp(a) == 0 or np.ptp(b) == 0:
        return float("nan")
    return float(np.corrcoef(ranks(a), ranks(b))[0, 1])


#: |rho| below this is called a weak trend.
WEAK_RHO = 0.5


def agreement(rho: float, sign: int) -> str:
    """Whether a rank correlation has the sign the thesis states (sign +1 or -1)."""
    if np.isnan(rho):
        return "no trend"
    if rho * sign <= 0:
        return "does not agree"
    return "agrees" if abs(rho) >= WEAK_RHO else "agrees weakly"


def _pooled_table(rows: Sequence[Mapping[str, Any]], xacro_names: Sequence[str]) -> list[str]:
    """Per path and preset, over every design: the trends and where the best height lies."""
    out = [
        "| path | preset | planned | ρ(stride, time) | ρ(stride, E_n) | ρ(stride, peak q̇) "
        "| best height = lowest feasible |",
        "|---|---|---|---|---|---|---|",
    ]
    best = best_heights(rows, xacro_names)
    for path, preset in dict.fromkeys((r["path"], r["preset"]) for r in rows):
        ok = [r for r in rows if r["status"] == OK and r["path"] == path and r["preset"] == preset]
        if len(ok) < 3:
            continue
        stride = [r["stride_m"] for r in ok]
        qd = [max(r[f"qd_peak_{k}_rad_s"] for k in ("hip_yaw", "hip_pitch", "knee")) for r in ok]
        rho = (
            rank_correlation(stride, [r[TIME] for r in ok]),
            rank_correlation(stride, [r["normalized_error_m"] for r in ok]),
            rank_correlation(stride, qd),
        )
        entries = [e for e in best if e["path"] == path and e["preset"] == preset and e["best"]]
        lowest = sum(
            e["best"]["height_m"] == min(set(e["heights_m"]) - set(e["heights_refused_m"]))
            for e in entries
        )
        out.append(
            f"| {path} | {preset} | {len(ok)} | {rho[0]:+.2f} ({agreement(rho[0], -1)}) "
            f"| {rho[1]:+.2f} ({agreement(rho[1], +1)}) | {rho[2]:+.2f} "
            f"({agreement(rho[2], -1)}) | {lowest} of {len(entries)} designs |"
        )
    return out


def _design_text(design: Mapping[str, Any]) -> str:
    return ", ".join(f"{k} = {v:g}" for k, v in design.items()) or "the robot as loaded"


def _reference_rows(
    rows: Sequence[Mapping[str, Any]], xacro_names: Sequence[str], reference: Mapping[str, float]
) -> tuple[dict[str, Any], list]:
    """Rows of the reference design (the xacro defaults) if the grid has it, else the first."""
    designs = list(dict.fromkeys(tuple(r[n] for n in xacro_names) for r in rows))
    wanted = tuple(reference.get(n) for n in xacro_names)
    design = wanted if wanted in designs else designs[0]
    return (
        dict(zip(xacro_names, design)),
        [r for r in rows if tuple(r[n] for n in xacro_names) == design],
    )


def _fmt(value: Any, fmt: str) -> str:
    if value is None:
        return "—"
    text = format(value, fmt)
    return text[1:] if text.startswith("-") and float(text) == 0 else text  # no "-0.000"


def _height_table(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    out = [
        "| h [m] | stride [m] | time [units] | E_n [m] | min margin [m] | peak τ hip "
        "pitch [N m] | peak τ knee [N m] | peak q̇ [rad/s] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in sorted(rows, key=lambda r: r["height_m"]):
        if r["status"] != OK:
            out.append(f"| {r['height_m']:g} | refused: {r['reason']} | | | | | | |")
            continue
        qd = max(r[f"qd_peak_{k}_rad_s"] for k in ("hip_yaw", "hip_pitch", "knee"))
        out.append(
            f"| {r['height_m']:g} | {r['stride_m']:.3f} | {r[TIME]:g} | "
            f"{r['normalized_error_m']:.3f} | {_fmt(r['min_margin_m'], '.3f')} | "
            f"{r['tau_peak_hip_pitch_Nm']:.1f} | {r['tau_peak_knee_Nm']:.1f} | {qd:.2f} |"
        )
    return out


def _findings(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    ok = [r for r in rows if r["status"] == OK]
    if len(ok) < 3:
        return ["- fewer than 3 planned heights: no trend to report."]
    stride = [r["stride_m"] for r in ok]
    qd = [max(r[f"qd_peak_{k}_rad_s"] for k in ("hip_yaw", "hip_pitch", "knee")) for r in ok]
    rho_t = rank_correlation(stride, [r[TIME] for r in ok])
    rho_e = rank_correlation(stride, [r["normalized_error_m"] for r in ok])
    rho_q = rank_correlation(stride, qd)
    fast = min(ok, key=lambda r: (r[TIME], r["normalized_error_m"], r["height_m"]))
    exact = min(ok, key=lambda r: (r["normalized_error_m"], r[TIME], r["height_m"]))
    slow = max(ok, key=lambda r: (r[TIME], -r["height_m"]))

    return [
        f"- Fastest at h = {fast['height_m']:g} m (stride {fast['stride_m']:.3f} m, "
        f"{fast[TIME]:g} units); slowest at h = {slow['height_m']:g} m ({slow[TIME]:g} units, "
        f"{slow[TIME] / fast[TIME]:.2f}x); most accurate at h = {exact['height_m']:g} m "
        f"(E_n {exact['normalized_error_m']:.3f} m).",
        f"- Longer stride, faster: rank correlation of stride with time {rho_t:+.2f} "
        f"({agreement(rho_t, -1)} with the thesis).",
        f"- Longer stride, less accurate: rank correlation of stride with E_n {rho_e:+.2f} "
        f"({agreement(rho_e, +1)} with the thesis).",
        f"- Shorter stride, faster joints: rank correlation of stride with peak joint speed "
        f"{rho_q:+.2f} ({agreement(rho_q, -1)} with the thesis).",
    ]


def render_sweep_page(
    rows: Sequence[Mapping[str, Any]],
    xacro_names: Sequence[str],
    *,
    command: str,
    reference: Mapping[str, float] | None = None,
    pareto_image: str | None = None,
) -> str:
    """Markdown of the sweep's results page (module docstring)."""
    paths = list(dict.fromkeys(r["path"] for r in rows))
    presets = list(dict.fromkeys(r["preset"] for r in rows))
    n_ok = sum(r["status"] == OK for r in rows)
    out = [
        "# Design sweep: body height vs speed and accuracy (thesis §7.2)",
        "",
        f"Generated by `{command}`; do not edit by hand (docs/sweeps.md).",
        "",
        f"{len(rows)} configurations ({n_ok} planned): paths {', '.join(paths)}; "
        f"presets {', '.join(presets)}; heights "
        f"{', '.join(f'{h:g}' for h in sorted({r['height_m'] for r in rows}))} m"
        + "".join(
            f"; {n} {', '.join(f'{v:g}' for v in sorted({r[n] for r in rows}))}"
            for n in xacro_names
        )
        + ". Time in thesis units t_l; the feet carry the "
        + " or ".join(sorted({str(r.get("load")) for r in rows if r["status"] == OK}))
        + " load for the torques (body: App. A; total: body and legs); E_n is eq 6.1.",
        "",
        "## The thesis's conclusion",
        "",
        f'> §7.1: "{THESIS_71}"',
        ">",
        f'> §7.2: "{THESIS_72}"',
        "",
    ]
    design, ref_rows = _reference_rows(rows, xacro_names, reference or {})
    for preset in presets:
        for path in paths:
            group = [r for r in ref_rows if r["path"] == path and r["preset"] == preset]
            if not group:
                continue
            out += [f"## {path}, {preset} preset, {_design_text(design)}", ""]
            out += _height_table(group) + ["", "What the sweep says:", ""] + _findings(group)
            out.append("")
    out += [
        "## Every design together",
        "",
        "Rank correlations over every planned configuration of a path and preset (all "
        "leg lengths and heights), with the sign the thesis states (§7.1: longer stride "
        "faster, less accurate, slower joints); and how often the fastest height is the "
        "lowest one the design can stand at.",
        "",
    ]
    out += _pooled_table(rows, xacro_names) + [""]
    out += [
        "Why E_n follows the stride only loosely: the planner walks a whole number of "
        "strides (`thesis` preset, §5.5) or half strides (`default`) towards each "
        "waypoint, so the error at a waypoint is what is left of its distance after "
        "rounding to that step, which jumps as the stride shrinks with height. That is "
        "the thesis's own remedy in §7.2: choose the stride (the "
        "height) so that it divides the distance to the waypoint.",
        "",
    ]
    out += [
        "## Best height per path and design",
        "",
        "Best = smallest normalized time (ties: smaller E_n, then lower height).",
        "",
        "| path | preset | "
        + " | ".join(xacro_names)
        + (" | " if xacro_names else "")
        + "best h [m] | time [units] | E_n [m] | peak τ [N m] | motor peak [N m] | "
        "refused heights [m] |",
        "|---|---|" + "---|" * (len(xacro_names) + 6),
    ]
    for e in best_heights(rows, xacro_names):
        b = e["best"]
        cells = [e["path"], e["preset"], *(f"{v:g}" for v in e["design"].values())]
        cells += (
            [
                f"{b['height_m']:g}",
                f"{b[TIME]:g}",
                f"{b['normalized_error_m']:.3f}",
                f"{b[TORQUE]:.1f}",
                f"{b['motor_tau_peak_Nm']:.3f}",
            ]
            if b
            else ["—"] * 5
        )
        cells.append(", ".join(f"{h:g}" for h in e["heights_refused_m"]) or "none")
        out.append("| " + " | ".join(cells) + " |")
    out += ["", "## Pareto front: time vs peak joint torque", ""]
    if pareto_image:
        out += [f"![time vs peak torque]({pareto_image})", ""]
    for path, front in pareto_rows(rows).items():
        items = [
            " ".join([*(f"{n}={r[n]:g}" for n in xacro_names), f"h={r['height_m']:g}", r["preset"]])
            + f" ({r[TIME]:g} units, {r[TORQUE]:.1f} N m)"
            for r in front
        ]
        out.append(f"- {path}: " + "; ".join(items))
    out.append("")
    return "\n".join(out)
