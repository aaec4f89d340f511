"""metrics.json as HTML tables with names and units (report.html): no raw dicts on the page.

Known metrics get a readable name and unit (METRICS); any other key gets its unit from its
suffix (``_m`` -> m, ``_rad_s`` -> rad/s, ``_Nm`` -> N m, ...; UNIT_SUFFIXES), so metrics that
other parts of the planner add later still show up, with units. Structured values become
their own tables: a per-joint mapping (``peak_abs_qd``) a joint table, a list of records
(``motor_sizing``, ``spins``) a table with one row per record, any other mapping a
name/value table.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping, Sequence
from typing import Any

#: key -> (display name, unit). Units in brackets on the page; "" for a pure number.
METRICS: dict[str, tuple[str, str]] = {
    "workspace": ("workspace preset", ""),
    "height_m": ("body height h (CoG above ground)", "m"),
    "stride_m": ("stride λ", "m"),
    "swing_height_m": ("swing height h_max (eq 5.12)", "m"),
    "psi_max_deg": ("largest rotation per spin cycle ψ", "deg"),
    "tolerance_m": ("path-following tolerance", "m"),
    "stability_threshold_m": ("stability threshold", "m"),
    "n_waypoints": ("waypoints", ""),
    "n_samples": ("samples", ""),
    "normalized_time": ("time t / t_l", "t_l"),
    "distance_m": ("distance travelled", "m"),
    "cog_path_length_m": ("CoG path length", "m"),
    "average_speed": ("average speed", "m / t_l"),
    "normalized_error_m": ("normalised error E_n (eq 6.1)", "m"),
    "min_stability_margin_m": ("minimum stability margin S_m (legs lifted)", "m"),
    "min_stability_margin_all_m": ("minimum stability margin S_m (all samples)", "m"),
    "n_creep_cycles": ("creep cycles", ""),
    "n_creep_half_cycles": ("creep half cycles", ""),
    "n_spins": ("spins", ""),
    "n_spin_cycles": ("spin cycles", ""),
    "n_shifts": ("sideways shifts", ""),
    "thesis_spin_cycles": ("spin cycles by the thesis's rule", ""),
    "thesis_time_units": ("time by the thesis's rule", "t_l"),
    "torque_load": ("load the feet carry", ""),
    "time_units_by_phase": ("time by phase", "t_l"),
    "peak_abs_qd": ("peak |joint speed|", "rad/s"),
    "peak_abs_qdd": ("peak |joint acceleration|", "rad/s²"),
    "motor_sizing": ("motor sizing (eq A.35-A.36)", ""),
    "spins": ("spins", ""),
    "psi_deg": ("rotation ψ", "deg"),
    "waypoint_index": ("waypoint", ""),
    "cycles": ("cycles", ""),
    "thesis_cycles": ("cycles by the thesis's rule", ""),
    "leg_orders": ("leg order per cycle", ""),
    "joint": ("joint", ""),
    "gear_ratio": ("gear ratio μ", ""),
    "gear_efficiency": ("gear efficiency η", ""),
}

#: Key suffix -> unit, longest first (a key like ``motor_speed_peak_rpm``).
UNIT_SUFFIXES: tuple[tuple[str, str], ...] = (
    ("_rad_s2", "rad/s²"), ("_rad_s", "rad/s"), ("_m_s2", "m/s²"), ("_m_s", "m/s"),
    ("_Nm", "N m"), ("_rpm", "rpm"), ("_deg", "deg"), ("_rad", "rad"), ("_kg", "kg"),
    ("_W", "W"), ("_N", "N"), ("_m", "m"), ("_s", "s"),
)


def name_and_unit(key: str) -> tuple[str, str]:
    """(display name, unit) of a metrics key: METRICS, else from the suffix."""
    if key in METRICS:
        return METRICS[key]
    for suffix, unit in UNIT_SUFFIXES:
        if key.endswith(suffix):
            return key[: -len(suffix)].replace("_", " "), unit
    return key.replace("_", " "), ""


def heading(key: str) -> str:
    """``name [unit]`` (escaped HTML)."""
    name, unit = name_and_unit(key)
    return html.escape(f"{name} [{unit}]" if unit else name)


def format_value(value: Any) -> str:
    """Numbers with 4 significant digits, lists comma-separated, nested lists ';'-separated."""
    if isinstance(value, bool) or value is None:
        return "yes" if value is True else ("no" if value is False else "–")
    if isinstance(value, (int, float)) or hasattr(value, "dtype"):
        try:
            number = float(value)
        except (TypeError, ValueError):
            return str(value)
        if number.is_integer() and abs(number) < 1e9:
            return str(int(number))
        return f"{number:.4g}" if math.isfinite(number) else str(number)
    if isinstance(value, Mapping):
        return "; ".join(f"{k} {format_value(v)}" for k, v in value.items())
    if isinstance(value, (list, tuple)):
        sep = "; " if any(isinstance(v, (list, tuple)) for v in value) else ", "
        if all(isinstance(v, str) for v in value):
            sep = " "
        return sep.join(format_value(v) for v in value)
    return str(value)


def _table(header: Sequence[str], rows: Sequence[Sequence[str]], css: str = "") -> str:
    head = "".join(f"<th>{h}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>"
                   for row in rows)
    cls = f' class="{css}"' if css else ""
    return f"<table{cls}><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _is_scalar(value: Any) -> bool:
    return not isinstance(value, (Mapping, list, tuple)) or (
        isinstance(value, (list, tuple)) and not any(isinstance(v, Mapping) for v in value))


def metric_tables(metrics: Mapping[str, Any]) -> list[tuple[str, str]]:
    """(section title, table HTML) for metrics.json: scalars first, then one table per
    structured metric; per-joint mappings of the same joints share one table."""
    scalars = [(k, v) for k, v in metrics.items() if _is_scalar(v)]
    out = [("Metrics", _table(["metric", "value"],
                              [(_plain(k), format_value(v)) for k, v in scalars], "metrics"))]
    per_joint = {k: v for k, v in metrics.items()
                 if isinstance(v, Mapping) and v and all(_is_scalar(x) for x in v.values())
                 and k.startswith("peak_")}
    if per_joint:
        joints = list(next(iter(per_joint.values())))
        rows = [[j] + [format_value(v.get(j)) for v in per_joint.values()] for j in joints]
        out.append(("Joint peaks", _table(["joint"] + [heading(k) for k in per_joint], rows,
                                          "joints")))
    for key, value in metrics.items():
        if _is_scalar(value) or key in per_joint:
            continue
        title = heading(key)
        if isinstance(value, Mapping):
            pairs = [(_plain(k), format_value(v)) for k, v in value.items()]
            unit = name_and_unit(key)[1]
            out.append((title, _table(["name", f"value [{unit}]" if unit else "value"], pairs)))
        elif isinstance(value, (list, tuple)) and value and all(isinstance(r, Mapping)
                                                                 for r in value):
            keys = list(dict.fromkeys(k for r in value for k in r))
            rows = [[format_value(r.get(k)) for k in keys] for r in value]
            out.append((title, _table([heading(k) for k in keys], rows, "records")))
    return out


def _plain(key: str) -> str:
    """``name [unit]`` as plain text (escaped later by _table)."""
    name, unit = name_and_unit(key)
    return f"{name} [{unit}]" if unit else name


def inputs_table(inputs: Mapping[str, Any]) -> str:
    """The header's table of the run's inputs (robot, waypoints, height, preset, ...)."""
    labels = {"robot": "robot", "waypoints_in_world": "waypoints (x, y) in the world [m]",
              "height_m": "body height [m]", "workspace": "workspace preset",
              "gait": "gait walked (and why another was dropped)",
              "unit_time_s": "time unit t_l [s]", "command": "command"}
    rows = []
    for key, value in inputs.items():
        if key == "waypoints_in_world":
            text = "  ".join(f"({format_value(x)}, {format_value(y)})" for x, y in value)
        else:
            text = format_value(value)
        rows.append((labels.get(key, _plain(key)), text))
    body = "".join(f"<tr><th>{html.escape(k)}</th><td>"
                   + (f"<code>{html.escape(v)}</code>" if k == "command" else html.escape(v))
                   + "</td></tr>" for k, v in rows)
    return f'<table class="inputs"><tbody>{body}</tbody></table>'
