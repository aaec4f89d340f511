"""The case tables of docs/results.md: per path, thesis beside each preset for every height
and quantity; and the time counts per phase of every case."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from planner.studies.cases import THESIS_STRIDES_M, CaseResult

_QUANTITIES = (  # (label, thesis attribute, metrics key, format)
    ("time (t/t_l)", "time_units", "normalized_time", "{:.0f}"),
    ("distance (m)", "distance_m", "distance_m", "{:.2f}"),
    ("speed (m/unit)", "average_speed", "average_speed", "{:.3f}"),
    ("E_n (m)", "normalized_error_m", "normalized_error_m", "{:.2f}"),
)


#: Margins closer to 0 than this print as 0 (the thesis preset's S_m = 0 computes as
#: +-1e-16 m; "-0.000" would suggest an unstable sample) [m].
ZERO_MARGIN_M = 1e-9


def format_value(fmt: str, value: Any) -> str:
    """``value`` formatted with ``fmt``; "n/a" for None, 0 for a margin within ZERO_MARGIN_M."""
    if value is None:
        return "n/a"
    if isinstance(value, float) and abs(value) < ZERO_MARGIN_M:
        value = 0.0
    return fmt.format(value)


def format_count(value: float) -> str:
    """A count that may be a half: 13 or 11.5."""
    return f"{value:g}"


def _index(results: Sequence[CaseResult]) -> dict[tuple[str, float, str], CaseResult]:
    return {(r.case.path, r.case.height_m, r.case.workspace): r for r in results}


def case_table(
    path: str,
    results: Sequence[CaseResult],
    heights: Sequence[float],
    presets: Sequence[str],
    physics: Mapping[str, str],
) -> list[str]:
    idx = _index(results)
    head = "| h (m) | quantity | thesis | " + " | ".join(f"ours, `{p}`" for p in presets) + " |"
    lines = [head, "|" + "---|" * (3 + len(presets))]
    for h in heights:
        row = next(
            (r.case.thesis for r in results if r.case.path == path and r.case.height_m == h), None
        )
        quantities = (
            list(_QUANTITIES)
            + [
                ("stride (m)", None, "stride_m", "{:.4f}"),
                ("gait", None, "gait", "{}"),
                ("creep / spin cycles", None, None, None),
                ("min margin S_m (m)", None, "min_stability_margin_m", "{:.3f}"),
                ("min whole-body margin (m)", None, "min_margin_com_m", "{:.4f}"),
            ]
            + ([("physics (MuJoCo)", None, None, "physics")] if physics else [])
        )
        for k, (label, attr, key, fmt) in enumerate(quantities):
            if label == "stride (m)":
                thesis = f"{THESIS_STRIDES_M.get(h, float('nan')):.4f}"
            elif attr is not None and row is not None:
                thesis = format_value(fmt or "{}", getattr(row, attr))
            else:
                thesis = ""
            cells = []
            for preset in presets:
                r = idx.get((path, h, preset))
                if r is None:
                    cells.append("not run")
                elif fmt == "physics":
                    cells.append(physics.get(r.case.name, "not run"))
                elif key is None:
                    cells.append(
                        f"{r.metrics.get('n_creep_cycles', '?')} / "
                        f"{r.metrics.get('n_spin_cycles', '?')}"
                    )
                else:
                    cells.append(format_value(fmt or "{}", r.metrics.get(key)))
            first = f"{h:g}" if k == 0 else ""
            lines.append(f"| {first} | {label} | {thesis} | " + " | ".join(cells) + " |")
    return lines


def time_count_table(results: Sequence[CaseResult]) -> list[str]:
    lines = [
        "| case | preset | creep | spin | transitions | shifts | total | "
        "thesis count of the same decisions | turns / spin cycles (thesis rule) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        m = r.metrics
        phases = m.get("time_units_by_phase") or {}

        def units(key: str, phases: Mapping[str, Any] = phases) -> str:
            return format_count(float(phases.get(key, 0.0)))

        thesis_count = m.get("thesis_time_units")
        lines.append(
            f"| {r.case.path} h={r.case.height_m:g} | {r.case.workspace} | {units('creep')} | "
            f"{units('spin')} | {units('transition')} | {units('shift')} | "
            f"{m['normalized_time']:.0f} | "
            f"{'n/a' if thesis_count is None else format_count(float(thesis_count))} | "
            f"{m.get('n_spins', '?')} / {m.get('n_spin_cycles', '?')} "
            f"({m.get('thesis_spin_cycles', '?')}) |"
        )
    return lines
