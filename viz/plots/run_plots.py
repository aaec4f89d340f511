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
at the user interface only). Long plans are drawn through a min/max envelope of at most
MAX_PLOT_POINTS vertices per line, so peaks survive and SVGs stay small. Output bytes are
deterministic (fixed SVG hash salt, no date metadata).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from planner.outputs.files import record_written, write_atomic
from planner.trajectory.samples import LEGS, Trajectory
from silo4kin.errors import Silo4Error
from viz.plots.figure import new_figure

#: Most vertices drawn per line (min/max envelope beyond this).
MAX_PLOT_POINTS = 4000
FORMATS = ("png", "svg")
#: Written unless asked otherwise (SVG on request: ``--svg``; each costs a second render).
DEFAULT_FORMATS = ("png",)
DPI = 110
#: zlib level of the PNGs: 1 encodes ~2x faster than the default 6 for ~1 % more bytes
#: (plots are flat colours and lines).
PNG_COMPRESS_LEVEL = 1
JOINT_LABELS = ("hip yaw", "hip pitch", "knee")
JOINT_COLORS = ("#1f77b4", "#d62728", "#2ca02c")
LEG_COLORS = dict(zip(LEGS, ("#1f77b4", "#d62728", "#2ca02c", "#9467bd"), strict=True))
SHADE_TRANSFER = "#9ecae1"
SHADE_ROTATE = "#fdd0a2"


def envelope_indices(n: int, max_points: int = MAX_PLOT_POINTS, y: np.ndarray | None = None
                     ) -> np.ndarray:
    """Indices of a min/max envelope of ``y`` (N,) with at most ``max_points`` vertices.

    Each of max_points // 2 bins keeps its smallest and largest sample (so peaks are drawn);
    the first and last samples are always kept. Without ``y``, a uniform stride.
    """
    if n <= max_points:
        return np.arange(n)
    bins = max(1, max_points // 2 - 1)
    width = int(np.ceil(n / bins))
    if y is None:
        return np.unique(np.concatenate([np.arange(0, n, width), [n - 1]]))
    padded = np.concatenate([y, np.full(bins * width - n, y[-1])]).reshape(bins, width)
    base = np.arange(bins) * width
    idx = np.concatenate([base + padded.argmin(axis=1), base + padded.argmax(axis=1),
                          [0, n - 1]])
    return np.unique(np.clip(idx, 0, n - 1))


class PhaseSpans:
    """Runs of phase labels, computed once per trajectory and shared by every figure.

    The labels are reduced to their unique values once (``np.unique`` with the inverse), so
    asking for the transfer spans of each of 4 legs on 6 figures costs 4 small lookups, not
    24 passes over N labels.

    Args:
        t: x positions of the samples (e.g. time units), shape (N,).
        phase: phase label per sample, shape (N,).
    """

    def __init__(self, t: np.ndarray, phase: np.ndarray) -> None:
        self.t = np.asarray(t, dtype=float)
        self.labels, self.inverse = np.unique(np.asarray(phase).astype(str), return_inverse=True)
        self.words = [label.split() for label in self.labels]
        self._cache: dict[tuple[str, str | None], list[tuple[float, float]]] = {}

    def spans(self, match: str, leg: str | None = None) -> list[tuple[float, float]]:
        """(start, width) of the runs whose label contains the word ``match`` (and ``leg``)."""
        key = (match, leg)
        if key not in self._cache:
            ids = [i for i, w in enumerate(self.words) if match in w and (leg is None or leg in w)]
            mask = np.isin(self.inverse, ids).astype(np.int8)
            edges = np.flatnonzero(np.diff(np.concatenate([[0], mask, [0]])))
            starts, ends = edges[::2], np.minimum(edges[1::2], len(self.t) - 1)
            self._cache[key] = [(float(self.t[s]), float(self.t[e] - self.t[s]))
                                for s, e in zip(starts, ends, strict=True)]
        return self._cache[key]


def phase_spans(t: np.ndarray, phase: np.ndarray, match: str, leg: str | None = None
                ) -> list[tuple[float, float]]:
    """(start, width) of the runs of samples whose phase label matches.

    A label matches when it contains the word ``match`` (e.g. "transfer", "rotate") and, if
    ``leg`` is given, also the word ``leg`` ("creep transfer LF" matches transfer/LF).
    """
    return PhaseSpans(t, phase).spans(match, leg)


def _shade(ax: Axes, spans: PhaseSpans, leg: str | None) -> None:
    """Shade transfer phases (of ``leg``, or all) blue and body rotations orange."""
    trans = ax.get_xaxis_transform()
    ax.broken_barh(spans.spans("transfer", leg), (0, 1), transform=trans,
                   facecolor=SHADE_TRANSFER, alpha=0.5, zorder=0, label="transfer")
    rotate = spans.spans("rotate")
    if rotate:
        ax.broken_barh(rotate, (0, 1), transform=trans, facecolor=SHADE_ROTATE, alpha=0.5,
                       zorder=0, label="rotate")


def _plot(ax: Axes, t: np.ndarray, y: np.ndarray, **kwargs: Any) -> None:
    idx = envelope_indices(len(t), MAX_PLOT_POINTS, y)
    ax.plot(t[idx], y[idx], linewidth=1.0, **kwargs)


class PerLegFigure:
    """4 stacked axes (LF, RF, LH, RH) with 3 joint lines each, built once and re-used.

    Joint positions, velocities, accelerations and each torque figure share the axes, the
    phase shading, the legend and the layout; :meth:`show` only swaps the 12 lines' data,
    the limits and the labels (figures reused).

    Args:
        t: x values (time units t / t_l), shape (N,).
        spans: the trajectory's phase runs.
        xlim: x range shown; None: the whole trajectory.
    """

    def __init__(self, t: np.ndarray, spans: PhaseSpans,
                 xlim: tuple[float, float] | None = None) -> None:
        self.t = t
        self.fig = new_figure(9, 9)
        self.fig.subplots_adjust(left=0.1, right=0.98, top=0.91, bottom=0.07, hspace=0.1)
        self.axes = self.fig.subplots(4, 1, sharex=True)
        self.lines = []
        for ax, leg in zip(self.axes, LEGS, strict=True):
            _shade(ax, spans, leg)
            for j in range(3):
                (line,) = ax.plot([], [], linewidth=1.0, color=JOINT_COLORS[j],
                                  label=JOINT_LABELS[j])
                self.lines.append(line)
            ax.grid(True, linewidth=0.3)
        handles, labels = self.axes[0].get_legend_handles_labels()
        self.fig.legend(handles, labels, loc="upper right", ncol=5, fontsize=8)
        self.axes[-1].set_xlabel("time t / t_l  (shaded: this leg's transfer phases)")
        lo, hi = xlim if xlim is not None else (float(t[0]), float(t[-1]))
        self.axes[-1].set_xlim(lo, hi)
        first, last = np.searchsorted(t, [lo, hi])
        self.shown = slice(max(int(first) - 1, 0), min(int(last) + 1, len(t)))

    def show(self, values: np.ndarray, title: str, ylabel: str) -> Figure:
        """Draw ``values`` (N, 12) in our joint order; returns the figure to save."""
        t = self.t[self.shown]
        for k, line in enumerate(self.lines):
            y = values[self.shown, k]
            idx = envelope_indices(len(t), MAX_PLOT_POINTS, y)
            line.set_data(t[idx], y[idx])
        for i, (ax, leg) in enumerate(zip(self.axes, LEGS, strict=True)):
            block = values[self.shown, 3 * i:3 * i + 3]
            lo, hi = float(np.min(block)), float(np.max(block))
            pad = 0.05 * (hi - lo) if hi > lo else max(abs(hi), 1.0) * 0.05
            ax.set_ylim(lo - pad, hi + pad)
            ax.set_ylabel(f"{leg}\n{ylabel}")
        self.fig.suptitle(title, x=0.3)
        return self.fig


def _path_figure(trajectory: Trajectory, waypoints: np.ndarray | None,
                 footholds: np.ndarray | None) -> Figure:
    """Plan view: desired path, walked (allowed) CoG path, CoG at phase starts, footholds."""
    base = trajectory.position_base_in_world
    fig = new_figure(7, 7)
    fig.subplots_adjust(left=0.12, right=0.97, top=0.94, bottom=0.08)
    ax = fig.subplots()
    if waypoints is not None and len(waypoints):
        desired = np.vstack([base[0, :2], waypoints[:, :2]])
        ax.plot(desired[:, 0], desired[:, 1], "--", color="#2ca02c", label="desired path")
        ax.plot(waypoints[:, 0], waypoints[:, 1], "o", color="#2ca02c", markersize=7,
                label="waypoints")
    idx = envelope_indices(len(base), MAX_PLOT_POINTS)
    ax.plot(base[idx, 0], base[idx, 1], "-", color="#ff7f0e", label="allowed path (CoG)")
    labels = np.asarray(trajectory.phase).astype(str)
    starts = np.concatenate([[0], np.flatnonzero(labels[1:] != labels[:-1]) + 1, [len(base) - 1]])
    ax.plot(base[starts, 0], base[starts, 1], ".", color="#ff7f0e", markersize=5,
            label="CoG at phase changes")
    if footholds is not None and len(footholds):
        ax.plot(footholds[:, 0], footholds[:, 1], "x", color="#1f3a93", markersize=5,
                label="footholds")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m] (world)")
    ax.set_ylabel("y [m] (world)")
    ax.grid(True, linewidth=0.3)
    ax.legend(loc="best", fontsize=8)
    ax.set_title("Allowed vs desired path")
    return fig


def _margin_figure(trajectory: Trajectory, spans: PhaseSpans) -> Figure:
    """Stability margin S_m vs time; transfer phases shaded; the minimum marked."""
    t, margin = trajectory.time_units, np.asarray(trajectory.margin, dtype=float)
    fig = new_figure(9, 3.5)
    fig.subplots_adjust(left=0.09, right=0.98, top=0.9, bottom=0.15)
    ax = fig.subplots()
    _shade(ax, spans, None)
    _plot(ax, t, margin, color="#333333", label="S_m")
    ax.axhline(0.0, color="#d62728", linewidth=0.8)
    k = int(np.nanargmin(margin))
    ax.plot(t[k], margin[k], "v", color="#d62728",
            label=f"min {margin[k] * 1000:.1f} mm at t = {t[k]:.2f} t_l")
    ax.set_xlabel("time t / t_l  (shaded: transfer phases)")
    ax.set_ylabel("stability margin S_m [m]")
    ax.set_xlim(t[0], t[-1])
    ax.grid(True, linewidth=0.3)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title("Static stability margin")
    return fig


def _as_points(points: np.ndarray | Sequence | None, name: str) -> np.ndarray | None:
    if points is None:
        return None
    arr = np.asarray(points, dtype=float)
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise Silo4Error(f"{name} must have shape (M, 2) or (M, 3), got {arr.shape}")
    return arr


def write_plots(out_dir: str | Path, trajectory: Trajectory, *,
                waypoints_in_world: np.ndarray | Sequence | None = None,
                footholds_in_world: np.ndarray | Sequence | None = None,
                formats: Sequence[str] = DEFAULT_FORMATS,
                window_s: tuple[float, float] | None = None,
                on_figure: Any = None, only: Sequence[str] | None = None) -> list[Path]:
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
    from viz.animation.page import touchdown_footholds
    from viz.plots.cycle import cycle_figure

    bad = [f for f in formats if f not in FORMATS]
    if bad or not formats:
        raise Silo4Error(f"plot formats {list(formats)!r}: choose from {list(FORMATS)}")
    if len(trajectory) < 2:
        raise Silo4Error(f"plots need at least 2 samples, the trajectory has {len(trajectory)}")
    waypoints = _as_points(waypoints_in_world, "waypoints_in_world")
    footholds = _as_points(footholds_in_world, "footholds_in_world")
    if footholds is None:
        footholds = touchdown_footholds(trajectory)
    if window_s is not None:
        t0, t1 = window_s
        if t0 >= float(trajectory.t[-1]) or t1 <= float(trajectory.t[0]):
            raise Silo4Error(f"--window {t0:g}:{t1:g} s lies outside the plan "
                             f"(0 to {float(trajectory.t[-1]):.2f} s)")
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
        torques.append(("torques", np.asarray(trajectory.tau, dtype=float), "Joint torques",
                        "tau [N m]"))
        for part, values in sorted(trajectory.tau_parts.items()):
            stem = "torques_" + re.sub(r"[^A-Za-z0-9_-]+", "_", part)
            torques.append((stem, np.asarray(values, dtype=float), f"Joint torques: {part}",
                            "tau [N m]"))

    written: list[Path] = []

    def wanted(*stems: str) -> bool:
        return only is None or any(stem in only for stem in stems)

    def save(stem: str, fig: Figure | None) -> None:
        if fig is None:
            return
        for fmt in formats:
            written.append(write_atomic(out_dir / f"{stem}.{fmt}",
                                        functools.partial(_save, fig, fmt=fmt)))
        if on_figure is not None:
            on_figure(stem)

    with mpl.rc_context({"svg.hashsalt": "silo4kin", "svg.fonttype": "path"}):
        per_leg_stems = [row[0] for row in per_leg + torques]
        legs = PerLegFigure(t, spans) if wanted(*per_leg_stems) else None
        for stem, values, title, ylabel in per_leg:
            save(stem, legs.show(values, title, ylabel) if legs and wanted(stem) else None)
        save("path", _path_figure(trajectory, waypoints, footholds) if wanted("path") else None)
        save("stability_margin",
             _margin_figure(trajectory, spans) if wanted("stability_margin") else None)
        save("cycle_cartesian", cycle_figure(trajectory) if wanted("cycle_cartesian") else None)
        for stem, values, title, ylabel in torques:
            save(stem, legs.show(values, title, ylabel) if legs and wanted(stem) else None)
        window_stems = [f"{row[0]}_window" for row in per_leg + torques[:1]]
        if window_s is not None and wanted(*window_stems):
            unit = float(trajectory.unit_time_s)
            window = PerLegFigure(t, spans, xlim=(window_s[0] / unit, window_s[1] / unit))
            label = f" from {window_s[0]:g} s to {window_s[1]:g} s"
            for stem, values, title, ylabel in per_leg + torques[:1]:
                if wanted(f"{stem}_window"):
                    save(f"{stem}_window", window.show(values, title + label, ylabel))
    record_written(written)   # so the same call may replace them (check_target)
    return written


def _save(fig: Figure, tmp: Path, fmt: str) -> None:
    """Render ``fig`` to ``tmp`` as ``fmt``, with no date or software metadata (same bytes)."""
    if fmt == "png":
        fig.savefig(tmp, format="png", dpi=DPI, metadata={"Software": None},
                    pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL})
    else:
        fig.savefig(tmp, format=fmt, dpi=DPI, metadata={"Date": None})
