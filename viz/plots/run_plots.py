"""Thesis-style figures of a plan (matplotlib, Agg backend), PNG and SVG.

    paths = write_plots("out/run", trajectory, waypoints_in_world=waypoints)

Figures (file stem: what, thesis figures it mirrors):

    joint_positions      q per leg vs time [deg], transfers shaded      Figs 4.10, 6.2
    joint_velocities     qd per leg [deg/s]                             Figs 4.11, 6.3
    joint_accelerations  qdd per leg [deg/s^2]                          Figs 4.12, 6.4
    path                 desired vs allowed (walked) path, CoG, footholds Figs 6.5, 6.9, 6.13
    stability_margin     S_m vs time [m], min marked                     §5.1
    torques              tau per leg [N m] when present                 Figs A.2, A.3
    torques_<part>       each named part of tau (e.g. motion, support)

Time axes are in thesis time units t / t_l. Angles are shown in degrees (docs/design.md: degrees
at the user interface only). Long plans are drawn through a min/max envelope
(viz/plots/time_series.py); the per-leg figures are viz/plots/per_leg.py, the path and margin
viz/plots/plan_figures.py. Output bytes are deterministic (fixed SVG hash salt, no date
metadata).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib.figure import Figure

from planner.outputs.files import record_written, write_atomic
from planner.outputs.leg_labels import LegLabels
from planner.trajectory.samples import Trajectory
from silo4kin.errors import Silo4Error
from viz.plots.per_leg import PerLegFigure
from viz.plots.plan_figures import margin_figure, path_figure
from viz.plots.time_series import PhaseSpans

FORMATS = ("png", "svg")
#: Written unless asked otherwise (SVG on request: ``--svg``; each costs a second render).
DEFAULT_FORMATS = ("png",)
DPI = 110
#: zlib level of the PNGs: 1 encodes ~2x faster than the default 6 for ~1 % more bytes
#: (plots are flat colours and lines).
PNG_COMPRESS_LEVEL = 1


def write_plots(
    out_dir: str | Path,
    trajectory: Trajectory,
    *,
    waypoints_in_world: np.ndarray | Sequence | None = None,
    footholds_in_world: np.ndarray | Sequence | None = None,
    formats: Sequence[str] = DEFAULT_FORMATS,
    window_s: tuple[float, float] | None = None,
    on_figure: Any = None,
    only: Sequence[str] | None = None,
) -> list[Path]:
    """Write the plan's figures into ``out_dir`` (created if missing), each file atomically.

    Args:
        trajectory: the plan (N >= 2 samples).
        waypoints_in_world: desired path waypoints [m], (M, 2) or (M, 3), or None.
        footholds_in_world: footholds [m], (F, 2) or (F, 3); None: start + touch-downs.
        formats: any of "png", "svg" (default PNG only).
        window_s: (t0, t1) [s] of ``trajectory.t``: also write joint histories over that
            window (``<stem>_window``); must overlap the plan.
        on_figure: called with each figure's stem after it is written (progress bars).
        only: write just these stems (of :func:`figure_stems`); None: all of them.

    Returns:
        the written files, in figure order then format order.

    Raises:
        Silo4Error: unknown format, too few samples, bad points or window, unwritable folder.
    """
    from viz.animation.plan_points import points_in_world, touchdown_footholds
    from viz.plots.cycle import cycle_figure

    bad = [f for f in formats if f not in FORMATS]
    if bad or not formats:
        raise Silo4Error(f"plot formats {list(formats)!r}: choose from {list(FORMATS)}")
    if len(trajectory) < 2:
        raise Silo4Error(f"plots need at least 2 samples, the trajectory has {len(trajectory)}")
    waypoints = points_in_world(waypoints_in_world, "waypoints_in_world")
    footholds = points_in_world(footholds_in_world, "footholds_in_world")
    if footholds is None:
        footholds = touchdown_footholds(trajectory)
    if window_s is not None:
        t0, t1 = window_s
        if t0 >= float(trajectory.t[-1]) or t1 <= float(trajectory.t[0]):
            raise Silo4Error(
                f"--window {t0:g}:{t1:g} s lies outside the plan "
                f"(0 to {float(trajectory.t[-1]):.2f} s)"
            )
    out_dir = Path(out_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise Silo4Error(f"cannot create plot folder {out_dir}: {exc.strerror or exc}") from exc

    t = trajectory.time_units
    spans = PhaseSpans(t, trajectory.phase)
    deg = np.degrees
    per_leg: list[tuple[str, np.ndarray, str, str]] = [
        ("joint_positions", deg(trajectory.q), "Joint positions", "q [deg]"),
        ("joint_velocities", deg(trajectory.qd), "Joint velocities", "qd [deg/s]"),
        ("joint_accelerations", deg(trajectory.qdd), "Joint accelerations", "qdd [deg/s²]"),
    ]
    torques: list[tuple[str, np.ndarray, str, str]] = []
    if trajectory.tau is not None:
        torques.append(
            ("torques", np.asarray(trajectory.tau, dtype=float), "Joint torques", "tau [N m]")
        )
        for part, values in sorted(trajectory.tau_parts.items()):
            stem = "torques_" + re.sub(r"[^A-Za-z0-9_-]+", "_", part)
            torques.append(
                (stem, np.asarray(values, dtype=float), f"Joint torques: {part}", "tau [N m]")
            )

    written: list[Path] = []

    def wanted(*stems: str) -> bool:
        return only is None or any(stem in only for stem in stems)

    def save(stem: str, fig: Figure | None) -> None:
        if fig is None:
            return
        for fmt in formats:
            written.append(
                write_atomic(out_dir / f"{stem}.{fmt}", functools.partial(_save, fig, fmt=fmt))
            )
        if on_figure is not None:
            on_figure(stem)

    with mpl.rc_context({"svg.hashsalt": "silo4kin", "svg.fonttype": "path"}):
        per_leg_stems = [row[0] for row in per_leg + torques]
        labels = LegLabels.from_joint_names(trajectory.joint_names)
        legs = PerLegFigure(t, spans, labels) if wanted(*per_leg_stems) else None
        for stem, values, title, ylabel in per_leg:
            save(stem, legs.show(values, title, ylabel) if legs and wanted(stem) else None)
        save("path", path_figure(trajectory, waypoints, footholds) if wanted("path") else None)
        save(
            "stability_margin",
            margin_figure(trajectory, spans) if wanted("stability_margin") else None,
        )
        save("cycle_cartesian", cycle_figure(trajectory) if wanted("cycle_cartesian") else None)
        for stem, values, title, ylabel in torques:
            save(stem, legs.show(values, title, ylabel) if legs and wanted(stem) else None)
        window_stems = [f"{row[0]}_window" for row in per_leg + torques[:1]]
        if window_s is not None and wanted(*window_stems):
            unit = float(trajectory.unit_time_s)
            window = PerLegFigure(t, spans, labels, xlim=(window_s[0] / unit, window_s[1] / unit))
            label = f" from {window_s[0]:g} s to {window_s[1]:g} s"
            for stem, values, title, ylabel in per_leg + torques[:1]:
                if wanted(f"{stem}_window"):
                    save(f"{stem}_window", window.show(values, title + label, ylabel))
    record_written(written)  # so the same call may replace them (check_target)
    return written


def _save(fig: Figure, tmp: Path, fmt: str) -> None:
    """Render ``fig`` to ``tmp`` as ``fmt``, with no date or software metadata (same bytes)."""
    if fmt == "png":
        fig.savefig(
            tmp,
            format="png",
            dpi=DPI,
            metadata={"Software": None},
            pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL},
        )
    else:
        fig.savefig(tmp, format=fmt, dpi=DPI, metadata={"Date": None})
