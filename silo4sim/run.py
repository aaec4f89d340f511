"""Simulate a plan end to end: calibration, replay, figures, and the files of a run folder.

    result = simulate(robot, trajectory)          # a planner Trajectory with tau
    result.metrics["walks"], result.metrics["drift_max_m"]
    write_sim_outputs(run_dir, result)            # sim.json, sim.npz, model.xml

The calibration comes first: the robot holding the plan's first posture for
``CALIBRATION_S`` must not move (Thresholds.standing_drift_m); if it does, the simulation,
not the plan, is wrong, and the result says so instead of judging the plan.
"""

from __future__ import annotations

import json
import time
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from planner.outputs.export import read_trajectory_npz
from planner.outputs.files import record_written, write_atomic, write_text_atomically
from silo4kin.geometry import LEG_NAMES
from silo4kin.robot import Robot

from .errors import SimulationError
from .metrics import Thresholds, body_angles, fallen, measure, measure_standing
from .model import SimModel, build_sim_model
from .replay import SimRecord, replay, stand_still
from .settings import SimSettings, knee_inertia

#: Length of the standing calibration [s].
CALIBRATION_S = 3.0
#: Sampling of sim.npz [s] (the simulation itself steps at SimSettings.timestep_s).
NPZ_PERIOD_S = 0.01


@dataclass(frozen=True, eq=False)
class SimResult:
    """A finished replay.

    Attributes:
        metrics: the sim.json document (figures of silo4sim.metrics.measure, the calibration,
            settings, wall time).
        record: every step (None when the calibration failed and the plan was not replayed).
        sim_model: the MuJoCo model used.
    """

    metrics: dict
    record: SimRecord | None
    sim_model: SimModel

    def arrays(self, period_s: float = NPZ_PERIOD_S) -> dict[str, np.ndarray]:
        """The sim.npz arrays, one row every ``period_s`` (plan time t [s], 0 at the plan's
        first sample, negative while settling). Simulated: position_base_in_world (CoG)
        [m] (S, 3), quat_base_in_world (w x y z) (S, 4), roll_pitch_yaw [rad] (S, 3),
        q [rad], qd [rad/s], tau [N m] (S, 12), position_foot_in_world [m] (S, 4, 3),
        foot_force [N] (S, 4); planned: planned_position_base_in_world, planned_yaw, planned_q,
        planned_tau, planned_contact, planned_position_foot_in_world (the contact points),
        planned_position_ball_centre_in_world (the sphere centres, what
        position_foot_in_world is simulated); joint_names (12,)."""
        rec, m = self.record, self.sim_model
        if rec is None:
            return {}
        n = rec.steps_run
        every = max(1, int(round(period_s / m.settings.timestep_s)))
        idx = np.arange(every - 1, n, every)
        if idx.size == 0 or idx[-1] != n - 1:
            idx = np.append(idx, n - 1)
        s = rec.sensors[idx]
        ref = rec.reference
        quat = s[:, m.sensor["body_quat"]]
        ang = body_angles(quat)
        return {
            "t": ref.t[idx],
            "position_base_in_world": s[:, m.sensor["body_position"]],
            "quat_base_in_world": quat,
            "roll_pitch_yaw": np.column_stack([ang["roll"], ang["pitch"], ang["yaw"]]),
            "q": s[:, m.sensor["q"]],
            "qd": s[:, m.sensor["qd"]],
            "tau": s[:, m.sensor["tau"]],
            "position_foot_in_world": s[:, m.sensor["foot_position"]].reshape(-1, 4, 3),
            "foot_force": s[:, m.sensor["foot_force"]],
            "planned_position_base_in_world": ref.position_base_in_world[idx],
            "planned_yaw": ref.yaw_base_in_world[idx],
            "planned_q": ref.q[idx],
            "planned_tau": ref.tau[idx],
            "planned_contact": ref.contact[idx],
            "planned_position_foot_in_world": ref.position_foot_in_world[idx],
            "planned_position_ball_centre_in_world": ref.position_ball_centre_in_world[idx],
            "joint_names": np.array(m.joint_names),
        }


def simulate(
    robot: Robot,
    trajectory,
    thresholds: Thresholds | None = None,  # noqa: ANN001
    settings: SimSettings | None = None,
    calibrate: bool = True,
    terrain: Mapping[str, Any] | None = None,
) -> SimResult:
    """Calibrate, replay ``trajectory`` in MuJoCo and measure it (see the module doc).

    Args:
        robot: the robot the plan was made for (its URDF becomes the MuJoCo model).
        trajectory: a planner Trajectory; its tau (if any) is the servos' feed-forward.
        thresholds: verdict and contact criteria (defaults: silo4sim/threshold_defaults.py).
        settings: physics and servo settings.
        calibrate: run the standing calibration first.
        terrain: the run's terrain document (plan.json inputs.terrain; None: flat floor).
    """
    thresholds = thresholds or Thresholds()
    settings = settings or SimSettings()
    t0 = time.perf_counter()
    sim_model = build_sim_model(robot, settings, terrain)
    doc: dict = {
        "robot": robot.name,
        "feedforward": trajectory.tau is not None,
        "settings": asdict(settings),
        "servo": {
            "kp": sim_model.kp,
            "kd": sim_model.kd,
            "scale": sim_model.kp / settings.kp,
            "knee_inertia_kg_m2": round(knee_inertia(robot), 7),
        },
    }
    if calibrate:
        doc["calibration"] = measure_standing(
            sim_model, stand_still(sim_model, trajectory, CALIBRATION_S), thresholds
        )
        if not doc["calibration"]["ok"]:
            doc.update(
                walks=False,
                reasons=[
                    "calibration failed: standing still moved the CoG "
                    f"{1e3 * doc['calibration']['base_drift_m']:.2f} mm (feet "
                    f"{1e3 * doc['calibration']['foot_slip_m']:.2f} mm) > "
                    f"{1e3 * thresholds.standing_drift_m:g} mm: {_blame(trajectory)}"
                ],
                wall_time_s=round(time.perf_counter() - t0, 3),
            )
            return SimResult(metrics=doc, record=None, sim_model=sim_model)
    height = float(np.asarray(trajectory.position_base_in_world)[:, 2].min())
    record = replay(
        sim_model, trajectory, stop=lambda chunk: fallen(chunk, sim_model, height, thresholds)
    )
    figures = measure(sim_model, record, thresholds)
    doc.update(figures)
    doc["wall_time_s"] = round(time.perf_counter() - t0, 3)
    return SimResult(metrics=doc, record=record, sim_model=sim_model)


def _blame(trajectory) -> str:  # noqa: ANN001
    """Who a failed calibration blames: the simulation, unless the plan's first sample is
    not a four-foot stance (a foot planned in swing stands on the floor in the calibration,
    its torques the three-foot support's: no rest posture of the plan is tested)."""
    first = np.asarray(trajectory.contact, dtype=bool)[0]
    if first.all():
        return "the simulation, not the plan, is wrong"
    lifted = ", ".join(name for name, on in zip(LEG_NAMES, first) if not on)
    return (
        f"the plan does not start at rest on four feet ({lifted} in swing on its first "
        "sample, whose torques leave that foot unloaded while it stands on the floor): the "
        "plan, not the simulation, is wrong"
    )


def read_run_trajectory(run_dir: str | Path):  # noqa: ANN201 (Trajectory)
    """The trajectory of a run folder written by ``silo4 plan``."""
    run_dir = Path(run_dir)
    if not run_dir.is_dir():
        raise SimulationError(f"{run_dir}: no such run folder")
    path = run_dir / "trajectory.npz"
    if not path.is_file():
        raise SimulationError(
            f"{run_dir}: no trajectory.npz (write one with silo4 plan --out {run_dir})"
        )
    return read_trajectory_npz(path)


def write_sim_outputs(folder: str | Path, result: SimResult) -> list[Path]:
    """Write sim.json, sim.npz (when the plan was replayed) and model.xml into ``folder``."""
    folder = Path(folder)
    written = [
        write_text_atomically(folder / "model.xml", result.sim_model.mjcf(), make_parents=False)
    ]
    arrays = result.arrays()
    if arrays:
        written.append(write_atomic(folder / "sim.npz", lambda tmp: _save_npz(tmp, arrays)))
    written.append(
        write_text_atomically(
            folder / "sim.json",
            json.dumps(result.metrics, indent=2, sort_keys=True) + "\n",
            make_parents=False,
        )
    )
    record_written(written)  # a run folder stays replaceable by `silo4 plan`/`cases`
    return written


def _save_npz(tmp: Path, arrays: dict[str, np.ndarray]) -> None:
    """Floats as float32 (0.1 um at 10 m; a third of the float64 file), compressed."""
    small = {k: v.astype(np.float32) if v.dtype == np.float64 else v for k, v in arrays.items()}
    with open(tmp, "wb") as f:
        np.savez_compressed(f, **small)  # type: ignore[arg-type]
