"""The per-leg figure of joint histories (positions, velocities, accelerations, torques): four
stacked axes, in the planner's leg order LF, RF, LH, RH, with three joint lines each, named
with the robot's own leg and joint names (planner.outputs.leg_labels: go2's axes read FL,
FR, RL, RR and its lines hip, thigh, calf; SILO4's LF, ... and hip yaw, hip pitch, knee)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from planner.outputs.leg_labels import LegLabels
from planner.trajectory.samples import LEGS
from viz.plots.figure import new_figure
from viz.plots.time_series import MAX_PLOT_POINTS, PhaseSpans, envelope_indices, shade_phases

JOINT_COLORS = ("#1f77b4", "#d62728", "#2ca02c")


class PerLegFigure:
    """4 stacked axes (LF, RF, LH, RH) with 3 joint lines each, built once and re-used.

    Joint positions, velocities, accelerations and each torque figure share the axes, the
    phase shading, the legend and the layout; :meth:`show` only swaps the 12 lines' data,
    the limits and the labels (figures reused).

    Args:
        t: x values (time units t / t_l), shape (N,).
        spans: the trajectory's phase runs.
        labels: the robot's leg and joint names (LegLabels.from_joint_names).
        xlim: x range shown; None: the whole trajectory.
    """

    def __init__(
        self,
        t: np.ndarray,
        spans: PhaseSpans,
        labels: LegLabels,
        xlim: tuple[float, float] | None = None,
    ) -> None:
        self.t = t
        self.labels = labels
        self.fig = new_figure(9, 9)
        self.fig.subplots_adjust(left=0.1, right=0.98, top=0.91, bottom=0.07, hspace=0.1)
        self.axes = self.fig.subplots(4, 1, sharex=True)
        self.lines = []
        for ax, leg in zip(self.axes, LEGS, strict=True):
            shade_phases(ax, spans, leg)
            for j in range(3):
                (line,) = ax.plot(
                    [], [], linewidth=1.0, color=JOINT_COLORS[j], label=labels.joints[j]
                )
                self.lines.append(line)
            ax.grid(True, linewidth=0.3)
        handles, names = self.axes[0].get_legend_handles_labels()
        self.fig.legend(handles, names, loc="upper right", ncol=5, fontsize=8)
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
            block = values[self.shown, 3 * i : 3 * i + 3]
            lo, hi = float(np.min(block)), float(np.max(block))
            pad = 0.05 * (hi - lo) if hi > lo else max(abs(hi), 1.0) * 0.05
            ax.set_ylim(lo - pad, hi + pad)
            ax.set_ylabel(f"{self.labels.leg(leg)}\n{ylabel}")
        self.fig.suptitle(title, x=0.3)
        return self.fig
