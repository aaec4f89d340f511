"""Figures of a physics replay (matplotlib, Agg): CoG drift and yaw error, foot slip.

    write_sim_plots(run_dir, result.arrays(), result.metrics)
    -> run_dir/sim_drift.png, run_dir/sim_slip.png

Inputs are the sim.npz arrays (silo4sim.run.SimResult.arrays): plan time t [s], simulated and
planned CoG / yaw / feet in the world frame W.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from planner.outputs.files import write_atomic  # noqa: E402
from planner.outputs.leg_labels import LegLabels  # noqa: E402


def _save(fig: plt.Figure, path: Path) -> Path:
    out = write_atomic(
        path, lambda tmp: fig.savefig(tmp, format="png", dpi=110), make_parents=False
    )
    plt.close(fig)
    return out


def write_sim_plots(folder: str | Path, arrays: dict[str, np.ndarray], metrics: dict) -> list[Path]:
    """sim_drift.png (CoG error [mm] and yaw error [deg] vs time, with the thresholds) and
    sim_slip.png (per leg: distance of the foot-sphere centre from its planned place while
    the plan has the foot down [mm], the offset whose change in a stance is the slip,
    silo4sim.metrics; legs by the robot's own names, planner.outputs.leg_labels)."""
    folder = Path(folder)
    t = arrays["t"]
    th = metrics["thresholds"]
    error_mm = 1e3 * np.linalg.norm(
        arrays["position_base_in_world"] - arrays["planned_position_base_in_world"], axis=1
    )
    yaw_error = np.degrees(
        np.angle(np.exp(1j * (arrays["roll_pitch_yaw"][:, 2] - arrays["planned_yaw"])))
    )
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 5.5), sharex=True)
    ax1.plot(t, error_mm, lw=1)
    ax1.axhline(1e3 * th["drift_m"], color="r", ls="--", lw=0.8, label="limit")
    ax1.set_ylabel("CoG error vs plan [mm]")
    ax1.legend(loc="upper left")
    ax2.plot(t, yaw_error, lw=1)
    for sign in (1, -1):
        ax2.axhline(sign * th["yaw_deg"], color="r", ls="--", lw=0.8)
    ax2.set_ylabel("yaw error [deg]")
    ax2.set_xlabel("plan time t [s] (negative: settling)")
    fig.suptitle("Physics replay: base drift")
    fig.tight_layout()
    written = [_save(fig, folder / "sim_drift.png")]

    feet = arrays["position_foot_in_world"][:, :, :2]
    planned = arrays["planned_position_ball_centre_in_world"][:, :, :2]
    stance = arrays["planned_contact"].astype(bool)
    offset_mm = np.where(stance, 1e3 * np.linalg.norm(feet - planned, axis=2), np.nan)
    legs = LegLabels.from_joint_names([str(n) for n in arrays.get("joint_names", ())]).legs
    fig, axes = plt.subplots(4, 1, figsize=(9, 7), sharex=True)
    for leg, ax in enumerate(axes):
        ax.plot(t, offset_mm[:, leg], lw=0.8)
        ax.set_ylabel(f"{legs[leg]} [mm]")
    axes[0].set_title(
        "stance foot sphere centre vs its planned place "
        f"(per-stance slip max {1e3 * metrics['slip_max_m']:.2f} mm)"
    )
    axes[-1].set_xlabel("plan time t [s]")
    fig.tight_layout()
    written.append(_save(fig, folder / "sim_slip.png"))
    return written
