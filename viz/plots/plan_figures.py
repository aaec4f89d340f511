"""The plan view (desired and walked CoG paths, footholds; thesis Figs 6.5, 6.9, 6.13) and the
stability margin S_m over time (§5.1)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from planner.trajectory.samples import Trajectory
from viz.plots.figure import new_figure
from viz.plots.time_series import (
    MAX_PLOT_POINTS,
    PhaseSpans,
    envelope_indices,
    plot_envelope,
    shade_phases,
)


def path_figure(
    trajectory: Trajectory, waypoints: np.ndarray | None, footholds: np.ndarray | None
) -> Figure:
    """Plan view: desired path, walked (allowed) CoG path, CoG at phase starts, footholds."""
    base = trajectory.position_base_in_world
    fig = new_figure(7, 7)
    fig.subplots_adjust(left=0.12, right=0.97, top=0.94, bottom=0.08)
    ax = fig.subplots()
    if waypoints is not None and len(waypoints):
        desired = np.vstack([base[0, :2], waypoints[:, :2]])
        ax.plot(desired[:, 0], desired[:, 1], "--", color="#2ca02c", label="desired path")
        ax.plot(
            waypoints[:, 0], waypoints[:, 1], "o", color="#2ca02c", markersize=7, label="waypoints"
        )
    idx = envelope_indices(len(base), MAX_PLOT_POINTS)
    ax.plot(base[idx, 0], base[idx, 1], "-", color="#ff7f0e", label="allowed path (CoG)")
    labels = np.asarray(trajectory.phase).astype(str)
    starts = np.concatenate([[0], np.flatnonzero(labels[1:] != labels[:-1]) + 1, [len(base) - 1]])
    ax.plot(
        base[starts, 0],
        base[starts, 1],
        ".",
        color="#ff7f0e",
        markersize=5,
        label="CoG at phase changes",
    )
    if footholds is not None and len(footholds):
        ax.plot(
            footholds[:, 0], footholds[:, 1], "x", color="#1f3a93", markersize=5, label="footholds"
        )
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m] (world)")
    ax.set_ylabel("y [m] (world)")
    ax.grid(True, linewidth=0.3)
    ax.legend(loc="best", fontsize=8)
    ax.set_title("Allowed vs desired path")
    return fig


def margin_figure(trajectory: Trajectory, spans: PhaseSpans) -> Figure:
    """Stability margin S_m vs time; transfer phases shaded; the minimum marked."""
    t, margin = trajectory.time_units, np.asarray(trajectory.margin, dtype=float)
    fig = new_figure(9, 3.5)
    fig.subplots_adjust(left=0.09, right=0.98, top=0.9, bottom=0.15)
    ax = fig.subplots()
    shade_phases(ax, spans, None)
    plot_envelope(ax, t, margin, color="#333333", label="S_m")
    ax.axhline(0.0, color="#d62728", linewidth=0.8)
    k = int(np.nanargmin(margin))
    ax.plot(
        t[k],
        margin[k],
        "v",
        color="#d62728",
        label=f"min {margin[k] * 1000:.1f} mm at t = {t[k]:.2f} t_l",
    )
    ax.set_xlabel("time t / t_l  (shaded: transfer phases)")
    ax.set_ylabel("stability margin S_m [m]")
    ax.set_xlim(t[0], t[-1])
    ax.grid(True, linewidth=0.3)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title("Static stability margin")
    return fig
