"""Cartesian trajectories over one gait cycle, as the thesis draws them (Figs 5.2-5.7).

    series = cycle_series(trajectory)      # numbers behind the figure
    fig = cycle_figure(trajectory)         # written as cycle_cartesian.png by write_plots

Left column, thesis Figs 5.2-5.4: the first leg's foot during its first transfer phase
(eq 5.2-5.10: sine swing), position / velocity / acceleration in the base frame B frozen at
lift-off, relative to the lift-off point. Right column, Figs 5.5-5.7: the CoG during the first
body phase of the creeping gait (eq 5.2, 5.5, 5.8 in x, y and 5.13-5.15 in z), in the base
frame at the phase start, relative to the start. Time runs from the phase start, in t_l.

Velocities and accelerations are central finite differences (``np.gradient``) of the sampled
positions over t [s]: the plan's samples are what a robot receives, so the figure shows them,
not the formulas (tests compare them with J(q) q' from the closed form).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from matplotlib.figure import Figure

from planner.outputs.leg_labels import LegLabels
from planner.trajectory.samples import LEGS, Trajectory

AXIS_COLORS = ("#1f77b4", "#d62728", "#2ca02c")


class CartesianSeries(NamedTuple):
    """One phase's Cartesian motion.

    Attributes:
        label: what moves, e.g. "LF foot, transfer".
        samples: trajectory sample indices of the phase, shape (K,).
        time_units: time since the phase start [t_l], shape (K,).
        position: [m], shape (K, 3), in B at the phase start, relative to the start.
        velocity: [m/s], shape (K, 3). acceleration: [m/s^2], shape (K, 3).
    """

    label: str
    samples: np.ndarray
    time_units: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


def _first_run(phase: np.ndarray, words: tuple[str, ...]) -> np.ndarray | None:
    """Sample indices of the first run of labels holding all ``words``; None if none."""
    labels = np.asarray(phase).astype(str)
    uniq, inverse = np.unique(labels, return_inverse=True)
    ids = [i for i, label in enumerate(uniq) if all(w in label.split() for w in words)]
    mask = np.isin(inverse, ids)
    if not mask.any():
        return None
    start = int(np.argmax(mask))
    stop = start + int(np.argmin(mask[start:])) if not mask[start:].all() else len(mask)
    # the run's last sample is the next phase's first: include it (the motion ends there)
    return np.arange(start, min(stop + 1, len(mask)))


def _series(
    trajectory: Trajectory, label: str, samples: np.ndarray, position_in_world: np.ndarray
) -> CartesianSeries:
    """Express ``position_in_world`` (K, 3) in B at samples[0]; differentiate over t."""
    yaw = float(trajectory.yaw_base_in_world[samples[0]])
    c, s = np.cos(yaw), np.sin(yaw)
    rel = position_in_world - position_in_world[0]
    position = np.column_stack(
        [c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1], rel[:, 2]]
    )
    t = trajectory.t[samples]
    velocity = np.gradient(position, t, axis=0, edge_order=2)
    acceleration = np.gradient(velocity, t, axis=0, edge_order=2)
    units = trajectory.time_units[samples] - trajectory.time_units[samples[0]]
    return CartesianSeries(label, samples, units, position, velocity, acceleration)


def cycle_series(
    trajectory: Trajectory, leg: str = LEGS[0]
) -> tuple[CartesianSeries | None, CartesianSeries | None]:
    """(foot of ``leg`` in its first transfer, CoG in the first creep body phase).

    Either is None when the plan has no such phase (e.g. a pure spin).
    """
    foot = body = None
    k = LEGS.index(leg)
    run = _first_run(trajectory.phase, ("transfer", leg))
    if run is not None and len(run) >= 3:
        own = LegLabels.from_joint_names(trajectory.joint_names).leg(leg)
        foot = _series(
            trajectory,
            f"{own} foot, first transfer (Figs 5.2-5.4)",
            run,
            trajectory.position_foot_in_world[run, k],
        )
    run = _first_run(trajectory.phase, ("creep", "body"))
    if run is not None and len(run) >= 3:
        body = _series(
            trajectory,
            "CoG, first body phase (Figs 5.5-5.7)",
            run,
            trajectory.position_base_in_world[run],
        )
    return foot, body


def cycle_figure(trajectory: Trajectory) -> Figure:
    """3 rows (position, velocity, acceleration) x 2 columns (foot, body), x/y/z lines."""
    from viz.plots.figure import new_figure

    fig = new_figure(10, 8)
    fig.subplots_adjust(left=0.09, right=0.98, top=0.9, bottom=0.07, hspace=0.12, wspace=0.22)
    axes = fig.subplots(3, 2, sharex="col")
    rows = (("position", "[m]"), ("velocity", "[m/s]"), ("acceleration", "[m/s²]"))
    for col, series in enumerate(cycle_series(trajectory)):
        for row, (name, unit) in enumerate(rows):
            ax = axes[row, col]
            ax.grid(True, linewidth=0.3)
            ax.set_ylabel(f"{name} {unit}")
            if series is None:
                ax.text(
                    0.5,
                    0.5,
                    "no such phase in this plan",
                    ha="center",
                    va="center",
                    transform=ax.transAxes,
                )
                continue
            values = getattr(series, name)
            for i, axis in enumerate("xyz"):
                ax.plot(
                    series.time_units,
                    values[:, i],
                    color=AXIS_COLORS[i],
                    linewidth=1.2,
                    label=f"{axis} (base frame)",
                )
        axes[0, col].set_title(
            series.label if series is not None else ("foot transfer" if col == 0 else "body phase"),
            fontsize=10,
        )
        axes[-1, col].set_xlabel("time since the phase start [t_l]")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    if not handles:
        handles, labels = axes[0, 1].get_legend_handles_labels()
    if handles:
        fig.legend(handles, labels, loc="upper right", ncol=3, fontsize=8)
    fig.suptitle("Cartesian trajectories over a cycle", x=0.25)
    return fig
