"""What a sweep says: the Pareto front of time vs peak joint torque (pareto.png) and the
best height per path and design (best.json).

Both read typed rows (silo4sweep.table.typed); only rows with status "ok" count. Paths are never
mixed: a front and a best height are per path (and preset), since paths differ in length.

    best height   the height with the smallest normalized_time; ties go to the smaller
                  normalized_error_m, then the lower height.
    Pareto front  the rows no other row of the same path beats in both normalized_time and
                  tau_peak_Nm (lower is better in both; equal in both is not beaten).
"""

from __future__ import annotations

import json
from collections import defaultdict
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from planner.outputs.files import write_atomic, write_text_atomically

from .task import OK

TIME, TORQUE = "normalized_time", "tau_peak_Nm"


def pareto_mask(points: np.ndarray) -> np.ndarray:
    """Which of the points (N, 2) are not dominated (lower is better in both coordinates).

    Point j dominates i when it is <= in both and < in one.
    """
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    le = np.all(p[None, :, :] <= p[:, None, :], axis=2)  # [i, j]: j <= i in both
    lt = np.any(p[None, :, :] < p[:, None, :], axis=2)
    return ~np.any(le & lt, axis=1)


def _groups(
    rows: Sequence[Mapping[str, Any]], by: Sequence[str]
) -> dict[tuple[Any, ...], list[Mapping[str, Any]]]:
    groups: dict[tuple[Any, ...], list[Mapping[str, Any]]] = defaultdict(list)
    for row in rows:
        groups[tuple(row[k] for k in by)].append(row)
    return groups


def best_heights(
    rows: Sequence[Mapping[str, Any]], xacro_names: Sequence[str]
) -> list[dict[str, Any]]:
    """One entry per (path, preset, design): the best height and how the others fared."""
    out = []
    for key, group in _groups(rows, ["path", "preset", *xacro_names]).items():
        ok = [r for r in group if r["status"] == OK]
        entry: dict[str, Any] = {
            "path": key[0],
            "preset": key[1],
            "design": dict(zip(xacro_names, key[2:])),
            "heights_m": sorted(r["height_m"] for r in group),
            "heights_refused_m": sorted(r["height_m"] for r in group if r["status"] != OK),
        }
        if ok:
            best = min(ok, key=lambda r: (r[TIME], r["normalized_error_m"], r["height_m"]))
            entry["best"] = {
                k: best[k]
                for k in (
                    "height_m",
                    TIME,
                    "normalized_error_m",
                    "stride_m",
                    "min_margin_m",
                    TORQUE,
                    "motor_tau_peak_Nm",
                    "motor_speed_peak_rpm",
                )
            }
        else:
            entry["best"] = None
        out.append(entry)
    return out


def pareto_rows(rows: Sequence[Mapping[str, Any]]) -> dict[str, list[Mapping[str, Any]]]:
    """Per path, the rows on the time vs peak torque front, fastest first."""
    fronts = {}
    for (path,), group in _groups([r for r in rows if r["status"] == OK], ["path"]).items():
        mask = pareto_mask(np.array([[r[TIME], r[TORQUE]] for r in group]))
        fronts[path] = sorted(
            (r for r, m in zip(group, mask) if m), key=lambda r: (r[TIME], r[TORQUE])
        )
    return fronts


def write_best_json(
    path: Path, rows: Sequence[Mapping[str, Any]], xacro_names: Sequence[str]
) -> Path:
    """best.json: best height per path and design, and each path's Pareto front."""
    keys = ("path", "preset", "height_m", *xacro_names, TIME, "normalized_error_m", TORQUE)
    doc = {
        "criterion": "best height = smallest normalized_time (ties: smaller "
        "normalized_error_m, then lower height); Pareto = time vs tau_peak_Nm",
        "configurations": len(rows),
        "planned": sum(r["status"] == OK for r in rows),
        "best_height": best_heights(rows, xacro_names),
        "pareto": {
            p: [{k: r[k] for k in keys} for r in front] for p, front in pareto_rows(rows).items()
        },
    }
    return write_text_atomically(path, json.dumps(doc, indent=2) + "\n")


def design_label(row: Mapping[str, Any], xacro_names: Sequence[str]) -> str:
    """``L2=0.25 L3=0.3 h=0.4`` (the design and height of a row)."""
    parts = [f"{n}={row[n]:g}" for n in xacro_names] + [f"h={row['height_m']:g}"]
    return " ".join(parts)


def write_pareto_png(
    path: Path, rows: Sequence[Mapping[str, Any]], xacro_names: Sequence[str]
) -> Path:
    """pareto.png: per path, normalized time vs peak joint torque of every planned row,
    coloured by height, the front joined and labelled with its designs."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = [r for r in rows if r["status"] == OK]
    fronts = pareto_rows(rows)
    paths = list(dict.fromkeys(r["path"] for r in ok)) or ["(no planned configuration)"]
    markers = dict(zip(dict.fromkeys(r["preset"] for r in ok), "o^sDv"))
    fig, axes = plt.subplots(1, len(paths), figsize=(6.0 * len(paths), 4.8), squeeze=False)
    heights = [r["height_m"] for r in ok] or [0.0, 1.0]
    norm = matplotlib.colors.Normalize(min(heights), max(heights))
    for ax, name in zip(axes[0], paths):
        group = [r for r in ok if r["path"] == name]
        title = f"{name}: {len(group)} planned"
        if group:
            for preset, marker in markers.items():
                pts = [r for r in group if r["preset"] == preset]
                sc = ax.scatter(
                    [r[TORQUE] for r in pts],
                    [r[TIME] for r in pts],
                    c=[r["height_m"] for r in pts],
                    cmap="viridis",
                    norm=norm,
                    s=22,
                    marker=marker,
                    label=f"{preset} preset",
                )
            front = fronts[name]
            ax.plot(
                [r[TORQUE] for r in front],
                [r[TIME] for r in front],
                "r-",
                lw=1,
                label="Pareto front",
            )
            for r, align in ((front[0], "right"), (front[-1], "left")):  # the two ends
                ax.annotate(
                    f"{design_label(r, xacro_names)} {r['preset']}",
                    (r[TORQUE], r[TIME]),
                    fontsize=7,
                    ha=align,
                    xytext=(0, 8),
                    textcoords="offset points",
                )
            # zoom on the front: slow outliers (a few times the front's slowest) are counted
            top = 1.5 * max(r[TIME] for r in front)
            hidden = sum(r[TIME] > top for r in group)
            if hidden:
                ax.set_ylim(top=top)
                title += f" ({hidden} slower than {top:.0f} units off the top)"
            fig.colorbar(sc, ax=ax, label="CoG height h [m]")
            ax.legend(loc="upper right", fontsize=8)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("peak joint torque, largest joint [N m]")
        ax.set_ylabel("normalized time [t_l units]")
        ax.margins(x=0.12, y=0.06)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    try:
        return write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    finally:
        plt.close(fig)
