"""metrics.json as HTML tables with labels and units (report.html): no raw keys on the page.

QUANTITIES is the one table metric key -> :class:`Quantity` (label, unit, how many
decimals): every key planner.path.metrics.compute_metrics and the outputs pipeline write has
an entry (tests/test_report_tables.py checks it), and so do the keys of its records
(``motor_sizing``, ``spins``, ``joint_limits``, ``height_search``). A key without an entry
still shows, labelled from its suffix (``_m`` -> m, ``_Nm`` -> N m; UNIT_SUFFIXES).

Numbers are written for people (:meth:`Quantity.format`): a value smaller than the last
shown decimal prints as ``0`` (never ``3.8e-36`` or ``-0.000``). A row with nothing in it
(None, an empty list or text) is left out. Structured values become their own tables: a
per-joint mapping (``peak_abs_qd``) a joint table, a list of records (``motor_sizing``,
``spins``) a table with one row per record, any other mapping a label/value table.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Quantity:
    """How the report shows one metric.

    Attributes:
        label: what a person reads, e.g. "normalised error E_n (eq 6.1)".
        unit: shown in brackets after the label ("" for a pure number or a text).
        decimals: digits after the point; None: 4 significant digits (integers as such).
    """

    label: str
    unit: str = ""
    decimals: int | None = None

    @property
    def heading(self) -> str:
        """``label [unit]`` (plain text)."""
        return f"{self.label} [{self.unit}]" if self.unit else self.label

    def format(self, value: Any) -> str:
        """``value`` for a person: rounded to ``decimals``, a rounded zero as "0"."""
        return format_number(value, self.decimals)


def format_number(value: Any, decimals: int | None = None) -> str:
    """A number with ``decimals`` digits after the point (None: 4 significant digits);
    values that round to zero (|value| below half the last digit, or 1e-9) print "0";
    booleans yes/no, None "–", lists comma-separated, mappings "name value; ...".
    """
    if isinstance(value, bool) or value is None:
        return "yes" if value is True else ("no" if value is False else "–")
    if isinstance(value, (int, float)) or hasattr(value, "dtype"):
        try:
            number = float(value)
        except (TypeError, ValueError):
            return str(value)
        if not math.isfinite(number):
            return str(number)
        resolution = 0.5 * 10.0**-decimals if decimals is not None else 1e-9
        if abs(number) < resolution:
            return "0"
        if decimals is not None:
            return f"{number:.{decimals}f}"
        if number.is_integer() and abs(number) < 1e9:
            return str(int(number))
        return f"{number:.4g}"
    if isinstance(value, Mapping):
        return "; ".join(f"{k} {format_number(v, decimals)}" for k, v in value.items())
    if isinstance(value, (list, tuple)):
        sep = "; " if any(isinstance(v, (list, tuple)) for v in value) else ", "
        if all(isinstance(v, str) for v in value):
            sep = " "
        return sep.join(format_number(v, decimals) for v in value)
    return str(value)


def _q(label: str, unit: str = "", decimals: int | None = None) -> Quantity:
    return Quantity(label, unit, decimals)


#: metric key -> how the report shows it (every key compute_metrics and the pipeline write,
#: and the keys of their records).
QUANTITIES: dict[str, Quantity] = {
    # the plan's settings
    "workspace": _q("workspace preset"),
    "height_m": _q("body height h (CoG above ground)", "m", 3),
    "height_search": _q("automatic height (--height auto, thesis §7.2)"),
    "stride_m": _q("stride λ", "m", 4),
    "swing_height_m": _q("swing height h_max (eq 5.12)", "m", 3),
    "psi_max_deg": _q("largest rotation per spin cycle ψ_max", "deg", 1),
    "tolerance_m": _q("path-following tolerance", "m", 3),
    "stability_threshold_m": _q("stability threshold", "m", 3),
    "stability_point": _q("point kept inside the support polygon"),
    "gait": _q("gait walked"),
    "fallback_reason": _q("why a faster gait was not used"),
    "n_waypoints": _q("waypoints"),
    "n_samples": _q("samples"),
    # time, distance, accuracy (§6)
    "normalized_time": _q("time t / t_l", "t_l", 1),
    "distance_m": _q("distance travelled", "m", 3),
    "cog_path_length_m": _q("CoG path length", "m", 3),
    "average_speed": _q("average speed", "m / t_l", 4),
    "normalized_error_m": _q("normalised error E_n (eq 6.1)", "m", 4),
    "normalized_error_nominal_m": _q("normalised error E_n of the nominal path", "m", 4),
    "time_units_by_phase": _q("time by phase", "t_l", 1),
    "thesis_time_units": _q("time by the thesis's rule", "t_l", 1),
    # stability
    "min_stability_margin_m": _q("minimum stability margin S_m (legs lifted)", "m", 4),
    "min_stability_margin_all_m": _q("minimum stability margin S_m (all samples)", "m", 4),
    "min_margin_com_m": _q("minimum margin of the whole-robot CoM (legs lifted)", "m", 4),
    "min_margin_body_m": _q("minimum margin of the body CoG (legs lifted)", "m", 4),
    "com_outside_support": _q("whole-robot CoM outside the support polygon"),
    "warnings": _q("warnings"),
    # cycles
    "n_creep_cycles": _q("creep cycles"),
    "n_creep_half_cycles": _q("creep half cycles"),
    "n_crawl_swings": _q("crawl swings (body moving while a leg swings)"),
    "duty_factor": _q("duty factor (feet on the ground)", "", 3),
    "n_spins": _q("spins"),
    "n_spin_cycles": _q("spin cycles"),
    "n_shifts": _q("sideways shifts"),
    "n_folded_shifts": _q("shifts folded into a creep"),
    "thesis_spin_cycles": _q("spin cycles by the thesis's rule"),
    # joints, torques, limits
    "peak_abs_qd": _q("peak |joint speed|", "rad/s", 3),
    "peak_abs_qdd": _q("peak |joint acceleration|", "rad/s²", 2),
    "joint_limits": _q("URDF joint limits"),
    "torque_load": _q("mass the feet carry"),
    "motor_sizing": _q("motor sizing (eq A.35-A.36)"),
    "spins": _q("spins"),
    # keys of the records above
    "sample": _q("sample"),
    "t_s": _q("time", "s", 2),
    "time_units": _q("time", "t_l", 1),
    "margin_com_m": _q("margin of the whole-robot CoM", "m", 4),
    "unit_time_s": _q("time unit t_l", "s", 4),
    "shortest_unit_time_s": _q("shortest time unit within the URDF limits", "s", 4),
    "velocity_ratio": _q("peak joint speed / URDF velocity limit", "", 3),
    "effort_ratio": _q("peak joint torque / URDF effort limit", "", 3),
    "violation": _q("limit violated"),
    "feasible_range_m": _q("feasible height range", "m", 3),
    "method": _q("search"),
    "n_evaluated": _q("heights evaluated"),
    "n_refused": _q("heights refused"),
    "psi_deg": _q("rotation ψ", "deg", 1),
    "waypoint_index": _q("waypoint"),
    "cycles": _q("cycles"),
    "thesis_cycles": _q("cycles by the thesis's rule"),
    "leg_orders": _q("leg order per cycle"),
    "joint": _q("joint"),
    "gear_ratio": _q("gear ratio μ"),
    "gear_efficiency": _q("gear efficiency η", "", 2),
    "joint_torque_peak_Nm": _q("joint torque peak", "N m", 2),
    "joint_torque_rms_Nm": _q("joint torque RMS", "N m", 2),
    "joint_speed_peak_rad_s": _q("joint speed peak", "rad/s", 3),
    "motor_torque_peak_Nm": _q("motor torque peak", "N m", 4),
    "motor_torque_rms_Nm": _q("motor torque RMS", "N m", 4),
    "motor_speed_peak_rad_s": _q("motor speed peak", "rad/s", 1),
    "motor_speed_peak_rpm": _q("motor speed peak", "rpm", 0),
    "joint_power_peak_W": _q("joint power peak", "W", 2),
    "motor_power_peak_W": _q("motor power peak", "W", 2),
    "gearing_source": _q("gearing from"),
    "urdf_effort_limit_Nm": _q("URDF effort limit", "N m", 1),
    "urdf_velocity_limit_rad_s": _q("URDF velocity limit", "rad/s", 2),
    "effort_use": _q("peak torque / effort limit", "", 2),
    "speed_use": _q("peak speed / velocity limit", "", 2),
}

#: Key suffix -> unit, longest first (a key like ``motor_speed_peak_rpm``).
UNIT_SUFFIXES: tuple[tuple[str, str], ...] = (
    ("_rad_s2", "rad/s²"),
    ("_rad_s", "rad/s"),
    ("_m_s2", "m/s²"),
    ("_m_s", "m/s"),
    ("_Nm", "N m"),
    ("_rpm", "rpm"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_kg", "kg"),
    ("_W", "W"),
    ("_N", "N"),
    ("_m", "m"),
    ("_s", "s"),
)


def quantity(key: str) -> Quantity:
    """How ``key`` is shown: QUANTITIES, else a label and unit from its suffix."""
    if key in QUANTITIES:
        return QUANTITIES[key]
    for suffix, unit in UNIT_SUFFIXES:
        if key.endswith(suffix):
            return Quantity(key[: -len(suffix)].replace("_", " "), unit)
    return Quantity(key.replace("_", " "))


def name_and_unit(key: str) -> tuple[str, str]:
    """(label, unit) of a metrics key."""
    q = quantity(key)
    return q.label, q.unit


def heading(key: str) -> str:
    """``label [unit]`` (escaped HTML)."""
    return html.escape(quantity(key).heading)


def format_value(value: Any, key: str | None = None) -> str:
    """``value`` as the report shows it (``key``'s decimals when given)."""
    return quantity(key).format(value) if key is not None else format_number(value)


def is_empty(value: Any) -> bool:
    """Nothing to show: None, or an empty text, list or mapping."""
    return value is None or (isinstance(value, (str, list, tuple, Mapping)) and not value)


def _table(header: Sequence[str], rows: Sequence[Sequence[str]], css: str = "") -> str:
    head = "".join(f"<th>{h}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in rows
    )
    cls = f' class="{css}"' if css else ""
    return f"<table{cls}><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _is_scalar(value: Any) -> bool:
    return not isinstance(value, (Mapping, list, tuple)) or (
        isinstance(value, (list, tuple)) and not any(isinstance(v, Mapping) for v in value)
    )


#: Keys shown outside the metric tables (report.html's warnings list).
LISTED_APART = ("warnings",)


def warning_lines(metrics: Mapping[str, Any]) -> list[str]:
    """The run's warning lines (metrics["warnings"]), empty ones left out."""
    lines = metrics.get("warnings")
    return [str(w) for w in lines if str(w).strip()] if isinstance(lines, list) else []


def metric_tables(metrics: Mapping[str, Any]) -> list[tuple[str, str]]:
    """(section title, table HTML) for metrics.json: scalars first, then one table per
    structured metric; per-joint mappings of the same joints share one table. Empty values
    have no row, and a structure with nothing in it no table."""
    shown = {k: v for k, v in metrics.items() if k not in LISTED_APART and not is_empty(v)}
    scalars = [(k, v) for k, v in shown.items() if _is_scalar(v)]
    out = [
        (
            "Metrics",
            _table(
                ["metric", "value"],
                [(quantity(k).heading, format_value(v, k)) for k, v in scalars],
                "metrics",
            ),
        )
    ]
    per_joint = {
        k: v
        for k, v in shown.items()
        if isinstance(v, Mapping)
        and all(_is_scalar(x) for x in v.values())
        and k.startswith("peak_")
    }
    if per_joint:
        joints = list(next(iter(per_joint.values())))
        rows = [[j] + [format_value(v.get(j), k) for k, v in per_joint.items()] for j in joints]
        out.append(
            ("Joint peaks", _table(["joint"] + [heading(k) for k in per_joint], rows, "joints"))
        )
    for key, value in shown.items():
        if _is_scalar(value) or key in per_joint:
            continue
        title = heading(key)
        if isinstance(value, Mapping):
            unit = quantity(key).unit
            pairs = [
                (quantity(k).heading, format_value(v, k if k in QUANTITIES else key))
                for k, v in value.items()
                if not is_empty(v)
            ]
            if pairs:
                out.append((title, _table(["name", f"value [{unit}]" if unit else "value"], pairs)))
        elif isinstance(value, (list, tuple)) and all(isinstance(r, Mapping) for r in value):
            keys = list(dict.fromkeys(k for r in value for k in r))
            rows = [[format_value(r.get(k), k) for k in keys] for r in value]
            out.append((title, _table([heading(k) for k in keys], rows, "records")))
    return out


#: The report header's rows: run_outputs.run_inputs key -> label.
INPUT_LABELS = {
    "robot": "robot",
    "waypoints_in_world": "waypoints (x, y) in the world [m]",
    "height_m": "body height [m]",
    "workspace": "workspace preset",
    "gait": "gait walked (and why another was dropped)",
    "unit_time_s": "time unit t_l [s]",
    "command": "command",
}


def inputs_table(inputs: Mapping[str, Any]) -> str:
    """The header's table of the run's inputs (robot, waypoints, height, preset, ...)."""
    rows = []
    for key, value in inputs.items():
        if is_empty(value):
            continue
        if key == "waypoints_in_world":
            text = "  ".join(f"({format_number(x)}, {format_number(y)})" for x, y in value)
        else:
            text = format_value(value, key)
        rows.append((INPUT_LABELS.get(key, quantity(key).heading), text))
    body = "".join(
        f"<tr><th>{html.escape(k)}</th><td>"
        + (f"<code>{html.escape(v)}</code>" if k == "command" else html.escape(v))
        + "</td></tr>"
        for k, v in rows
    )
    return f'<table class="inputs"><tbody>{body}</tbody></table>'
