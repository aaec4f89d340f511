"""Plan one configuration and summarise it as one row: the only code a sweep task runs.

    row = plan_row(SweepConfig("straight", 0.4, "default", (("L2", 0.25),)), SweepSettings())

This is the one place that knows the planner's API (planner.studies.cases.path_waypoints and
the plan pipeline planner.outputs.pipeline.plan_run: plan, URDF limits, torques, metrics,
the same as ``silo4 plan`` and ``silo4 cases``): when that API changes, only this module
follows. The planner does not know it runs in a sweep.

A configuration the planner or the robot loader refuses (any Silo4Error) is a row with
status "refused" and the reason; any other exception is a row with status "error" (a bug to
report, with the exception type): one bad configuration never stops a sweep.

Row columns (silo4sweep.table.COLUMNS gives the order): the configuration (path, height_m, one
column per xacro argument, preset), status, reason, and for a planned configuration:
normalized_time [time units t_l], normalized_error_m (eq 6.1) [m], distance_m [m],
average_speed [m/unit], stride_m [m], min_margin_m (smallest whole-body stability margin
while a leg is in the air where the planner reports it, else its S_m) [m], n_samples, load
(the mass the feet carry for the torques: body or total); per joint type
(hip_yaw, hip_pitch, knee; the largest of the four legs): tau_peak_<type>_Nm,
tau_rms_<type>_Nm (time-weighted RMS), qd_peak_<type>_rad_s; over all joints:
tau_peak_Nm, motor_tau_peak_Nm (eq A.35), motor_speed_peak_rpm (eq A.36); with --simulate,
sim_verdict ("walks" / "fails") and sim_reason. Speeds are per second at 1 s per time unit.
A planned row whose plan breaks a URDF velocity or effort limit at 1 s per time unit keeps
status "ok" and names the limit in "reason" (the limits are reported, not refused).
"""

from __future__ import annotations

import importlib.util
import threading
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from silo4kin.errors import Silo4Error
from silo4kin.motors import DEFAULT_GEAR_EFFICIENCY, DEFAULT_GEAR_RATIO, Gearing

from .grid import SweepConfig, format_value

#: Joint types in each leg's joint order (silo4kin.robot.JOINT_SUFFIXES: yaw, pitch, knee).
JOINT_TYPES: tuple[str, str, str] = ("hip_yaw", "hip_pitch", "knee")
#: Row statuses.
OK, REFUSED, ERROR = "ok", "refused", "error"

# xacro keeps module-global state (stack-notes.md): one robot load at a time per process,
# in case a Dask worker runs several threads.
_LOAD_LOCK = threading.Lock()


@dataclass(frozen=True)
class SweepSettings:
    """What every configuration of one sweep shares (recorded in DIR/sweep.json).

    Attributes:
        samples_per_unit: samples per time unit t_l of the planned trajectories.
        load: mass the feet carry for the torques, "body" (thesis) or "total"; None: the
            plan's preset's (Plan.preset.load).
        gear_ratio: mu of every joint, eq A.35-A.36 [dimensionless].
        gear_efficiency: eta of every joint, in (0, 1].
        robot: robot .urdf / .urdf.xacro file (None: SILO4); must be readable on the workers.
        simulate: replay each plan in the physics simulator (package ``sim``).
    """

    samples_per_unit: int = 100
    load: str | None = None
    gear_ratio: float = DEFAULT_GEAR_RATIO
    gear_efficiency: float = DEFAULT_GEAR_EFFICIENCY
    robot: str | None = None
    simulate: bool = False


def simulator_available() -> bool:
    """Whether the physics replay package ``sim`` is importable here."""
    return importlib.util.find_spec("silo4sim") is not None


@lru_cache(maxsize=16)
def _robot(robot: str | None, xacro_args: tuple[tuple[str, float], ...]) -> Any:
    from silo4kin.robot import load_robot

    mapping = {name: format_value(value) for name, value in xacro_args}
    with _LOAD_LOCK:
        return load_robot(robot, mapping or None)


def config_columns(config: SweepConfig) -> dict[str, Any]:
    """The configuration part of a row."""
    row: dict[str, Any] = {"path": config.path, "height_m": config.height_m}
    row.update({name: value for name, value in config.xacro_args})
    row["preset"] = config.preset
    return row


def plan_row(config: SweepConfig, settings: SweepSettings) -> dict[str, Any]:
    """Plan ``config`` with its torques (and physics replay) and summarise it as one row."""
    row = config_columns(config)
    try:
        row.update(status=OK, reason="")
        row.update(_planned_columns(config, settings))
    except Silo4Error as exc:
        row.update(status=REFUSED, reason=str(exc).splitlines()[0] if str(exc) else "")
    except Exception as exc:  # a bug, not a bad configuration: recorded, sweep goes on
        row.update(status=ERROR, reason=f"{type(exc).__name__}: {exc}".splitlines()[0])
    return row


def _planned_columns(config: SweepConfig, settings: SweepSettings) -> dict[str, Any]:
    from planner.outputs.pipeline import OnLimitViolation, RunRequest, plan_run
    from planner.studies.cases import START_HEADING_RAD, path_waypoints

    robot = _robot(settings.robot, config.xacro_args)
    waypoints, tolerance = path_waypoints(config.path)
    gearing = Gearing.uniform(12, settings.gear_ratio, settings.gear_efficiency)
    request = RunRequest(
        unit_time=1.0,
        load="body" if settings.load == "body" else "total" if settings.load == "total" else None,
        gearing=gearing,
        on_limit_violation=OnLimitViolation.REPORT,
    )
    run = plan_run(
        robot,
        waypoints,
        config.height_m,
        request,
        start_heading=START_HEADING_RAD,
        workspace=config.preset,
        tolerance=tolerance,
        samples_per_unit=settings.samples_per_unit,
    )
    metrics, traj = run.metrics, run.plan.trajectory
    cols: dict[str, Any] = {
        "normalized_time": metrics["normalized_time"],
        "normalized_error_m": metrics["normalized_error_m"],
        "distance_m": metrics["distance_m"],
        "average_speed": metrics["average_speed"],
        "stride_m": metrics["stride_m"],
        # the whole-body (CoM) margin where the planner reports it, else its own criterion's
        "min_margin_m": metrics.get("min_margin_com_m", metrics["min_stability_margin_m"]),
        "n_samples": metrics["n_samples"],
        "load": metrics["torque_load"],
        # a URDF limit the plan breaks at 1 s per time unit, else ""
        "reason": metrics["joint_limits"].get("violation") or "",
    }
    cols.update(torque_columns(metrics["motor_sizing"]))
    if settings.simulate:
        cols.update(physics_verdict(robot, traj))
    return cols


def torque_columns(sizing: list[dict[str, Any]]) -> dict[str, float]:
    """Per-joint-type and overall peaks of a silo4kin.motors.sizing_table (12 joints, leg by
    leg, yaw/pitch/knee in each leg): the largest over the four legs."""

    def column(key: str) -> np.ndarray:
        return np.array([float(r[key]) for r in sizing]).reshape(-1, len(JOINT_TYPES))

    tau_peak = column("joint_torque_peak_Nm")
    tau_rms = column("joint_torque_rms_Nm")
    qd_peak = column("joint_speed_peak_rad_s")
    cols: dict[str, float] = {}
    for k, kind in enumerate(JOINT_TYPES):
        cols[f"tau_peak_{kind}_Nm"] = float(tau_peak[:, k].max())
        cols[f"tau_rms_{kind}_Nm"] = float(tau_rms[:, k].max())
        cols[f"qd_peak_{kind}_rad_s"] = float(qd_peak[:, k].max())
    cols["tau_peak_Nm"] = float(tau_peak.max())
    cols["motor_tau_peak_Nm"] = float(column("motor_torque_peak_Nm").max())
    cols["motor_speed_peak_rpm"] = float(column("motor_speed_peak_rpm").max())
    return cols


def physics_verdict(robot: Any, trajectory: Any) -> dict[str, str]:
    """sim_verdict "walks" / "fails" and the first reason, from the physics replay (sim)."""
    from silo4sim.run import simulate  # the sim layer; only called when importable

    metrics = simulate(robot, trajectory).metrics
    walks = bool(metrics.get("walks"))
    reasons = metrics.get("reasons") or []
    return {
        "sim_verdict": "walks" if walks else "fails",
        "sim_reason": "" if walks else "; ".join(str(r) for r in reasons),
    }
