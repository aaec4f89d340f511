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

import re
from collections.abc import Callable, Sequence
from functools import partial
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from planner.files import write_atomic  # noqa: E402
from planner.trajectory import LEGS, Trajectory  # noqa: E402
from silo4kin.errors import Silo4Error  # noqa: E402

#: Most vertices drawn per line (min/max envelope beyond this).
MAX_PLOT_POINTS = 4000
FORMATS = ("png", "svg")
DPI = 110
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


def phase_spans(t: np.ndarray, phase: np.ndarray, match: str, leg: str | None = None
                ) -> list[tuple[float, float]]:
    """(start, width) of the runs of samples whose phase label matches.

    A label matches when it contains the word ``match`` (e.g. "transfer", "rotate") and, if
    ``leg`` is given, also the word ``leg`` ("creep transfer LF" matches transfer/LF).
    """
    labels = np.asarray(phase).astype(str)
    words = [label.split() for label in np.unique(labels)]
    hits = {" ".join(w) for w in words if match in w and (leg is None or leg in w)}
    mask = np.isin(labels, list(hits))
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(int), [0]])))
    starts, ends = edges[::2], np.minimum(edges[1::2], len(t) - 1)
    return [(float(t[s]), float(t[e] - t[s])) for s, e in zip(starts, ends, strict=True)]


def _shade(ax: plt.Axes, t: np.ndarray, phase: np.ndarray, leg: str | None) -> None:
    """Shade transfer phases (of ``leg``, or all) blue and body rotations orange."""
    trans = ax.get_xaxis_transform()
    ax.broken_barh(phase_spans(t, phase, "transfer", leg), (0, 1), transform=trans,
                   facecolor=SHADE_TRANSFER, alpha=0.5, zorder=0, label="transfer")
    rotate = phase_spans(t, phase, "rotate")
    if rotate:
        ax.broken_barh(rotate, (0, 1), transform=trans, facecolor=SHADE_ROTATE, alpha=0.5,
                       zorder=0, label="rotate")


def _plot(ax: plt.Axes, t: np.ndarray, y: np.ndarray, **kwargs: Any) -> None:
    idx = envelope_indices(len(t), MAX_PLOT_POINTS, y)
    ax.plot(t[idx], y[idx], linewidth=1.0, **kwargs)


def _per_leg_figure(trajectory: Trajectory, values: np.ndarray, title: str, ylabel: str
                    ) -> plt.Figure:
    """4 stacked axes (LF, RF, LH, RH), 3 joints each; values (N, 12) in our joint order."""
    t = trajectory.time_units
    fig, axes = plt.subplots(4, 1, sharex=True, figsize=(9, 9), constrained_layout=True)
    for i, (ax, leg) in enumerate(zip(axes, LEGS, strict=True)):
        _shade(ax, t, trajectory.phase, leg)
        for j in range(3):
            _plot(ax, t, values[:, 3 * i + j], color=JOINT_COLORS[j], label=JOINT_LABELS[j])
        ax.set_ylabel(f"{leg}\n{ylabel}")
        ax.grid(True, linewidth=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside upper right", ncol=4, fontsize=8)
    axes[-1].set_xlabel("time t / t_l  (shaded: this leg's transfer phases)")
    axes[-1].set_xlim(t[0], t[-1])
    fig.suptitle(title)
    return fig


def _path_figure(trajectory: Trajectory, waypoints: np.ndarray | None,
                 footholds: np.ndarray | None) -> plt.Figure:
    """Plan view: desired path, walked (allowed) CoG path, CoG at phase starts, footholds."""
    base = trajectory.position_base_in_world
    fig, ax = plt.subplots(figsize=(7, 7), constrained_layout=True)
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


def _margin_figure(trajectory: Trajectory) -> plt.Figure:
    """Stability margin S_m vs time; transfer phases shaded; the minimum marked."""
    t, margin = trajectory.time_units, np.asarray(trajectory.margin, dtype=float)
    fig, ax = plt.subplots(figsize=(9, 3.5), constrained_layout=True)
    _shade(ax, t, trajectory.phase, None)
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
                formats: Sequence[str] = FORMATS) -> list[Path]:
    """Write the plan's figures into ``out_dir`` (created if missing), each file atomically.

    Args:
        trajectory: the plan (N >= 2 samples).
        waypoints_in_world: desired path waypoints [m], (M, 2) or (M, 3), or None.
        footholds_in_world: footholds [m], (F, 2) or (F, 3); None: start + touch-downs.
        formats: any of "png", "svg".

    Returns:
        the written files, in figure order then format order.

    Raises:
        Silo4Error: unknown format, too few samples, bad points, unwritable folder.
    """
    from .animation import touchdown_footholds

    bad = [f for f in formats if f not in FORMATS]
    if bad or not formats:
        raise Silo4Error(f"plot formats {list(formats)!r}: choose from {list(FORMATS)}")
    if len(trajectory) < 2:
        raise Silo4Error(f"plots need at least 2 samples, the trajectory has {len(trajectory)}")
    waypoints = _as_points(waypoints_in_world, "waypoints_in_world")
    footholds = _as_points(footholds_in_world, "footholds_in_world")
    if footholds is None:
        footholds = touchdown_footholds(trajectory)
    out_dir = Path(out_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise Silo4Error(f"cannot create plot folder {out_dir}: {exc.strerror or exc}") from exc

    deg = np.degrees
    figures: dict[str, Callable[[], plt.Figure]] = {
        "joint_positions": lambda: _per_leg_figure(trajectory, deg(trajectory.q),
                                                   "Joint positions", "q [deg]"),
        "joint_velocities": lambda: _per_leg_figure(trajectory, deg(trajectory.qd),
                                                    "Joint velocities", "qd [deg/s]"),
        "joint_accelerations": lambda: _per_leg_figure(trajectory, deg(trajectory.qdd),
                                                       "Joint accelerations", "qdd [deg/s²]"),
        "path": lambda: _path_figure(trajectory, waypoints, footholds),
        "stability_margin": lambda: _margin_figure(trajectory),
    }
    if trajectory.tau is not None:
        tau = np.asarray(trajectory.tau, dtype=float)
        figures["torques"] = lambda: _per_leg_figure(trajectory, tau, "Joint torques",
                                                     "tau [N m]")
        for part, values in sorted(trajectory.tau_parts.items()):
            stem = "torques_" + re.sub(r"[^A-Za-z0-9_-]+", "_", part)
            figures[stem] = partial(_per_leg_figure, trajectory, np.asarray(values, dtype=float),
                                    f"Joint torques: {part}", "tau [N m]")
    written: list[Path] = []
    with plt.rc_context({"svg.hashsalt": "silo4kin", "svg.fonttype": "path"}):
        for stem, make in figures.items():
            fig = make()
            try:
                for fmt in formats:
                    metadata = {"Date": None} if fmt == "svg" else {"Software": None}

                    def save(tmp: Path, fig: plt.Figure = fig, fmt: str = fmt,
                             metadata: dict = metadata) -> None:
                        fig.savefig(tmp, format=fmt, dpi=DPI, metadata=metadata)

                    written.append(write_atomic(out_dir / f"{stem}.{fmt}", save))
            finally:
                plt.close(fig)
    return written
