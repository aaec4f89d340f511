"""What the physics replay measures, and the verdict: does the robot walk the plan?

All figures come from the 1 ms steps of a :class:`silo4sim.replay.SimRecord`, compared with the
plan at the same instants (:class:`silo4sim.replay.Reference`). Frames: world W; the base is the
body CoG (the planner's ``position_base_in_world``).

Slip: per planned stance, how far the xy of (sim sphere centre - planned sphere centre)
moves from where it was after touch-down (:func:`stance_slip`). Both are the same point of
the foot, the site the foot_position sensor reads, once simulated and once placed on the
planned pose (Reference.position_ball_centre_in_world), so the difference moves only when
the foot moves otherwise than planned. The planned contact point of a ball (centre - r n)
is not that point: where the contact normal n changes during a stance (a height map's
triangles) it moves by r dn with no slip at all; on a plane n is constant and the two
measures agree (tests/test_sim_slip.py).
"""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

import numpy as np

from silo4kin.geometry import LEG_NAMES

from .model import SimModel
from .replay import SimRecord
from .thresholds import Thresholds

LEGS = LEG_NAMES


def body_angles(quat_wxyz: np.ndarray) -> dict[str, np.ndarray]:
    """Roll, pitch, yaw (Z-Y-X) and tilt (angle of the body z axis from W's z) [rad].

    Args:
        quat_wxyz: body orientation in W, shape (S, 4), w x y z.
    """
    w, x, y, z = (quat_wxyz[:, i] for i in range(4))
    return {
        "roll": np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)),
        "pitch": np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0)),
        "yaw": np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)),
        "tilt": np.arccos(np.clip(1 - 2 * (x * x + y * y), -1.0, 1.0)),
    }


def fallen(
    sensors: np.ndarray, sim_model: SimModel, planned_height_m: float, th: Thresholds
) -> bool:
    """Whether any step of ``sensors`` (S, nsensordata) shows a fall (tilt or height)."""
    quat = sensors[:, sim_model.sensor["body_quat"]]
    z = sensors[:, sim_model.sensor["body_position"]][:, 2]
    tilt = body_angles(quat)["tilt"]
    return bool(
        np.any(tilt > np.radians(th.tilt_deg))
        or np.any(z < th.fall_height_ratio * planned_height_m)
    )


def _runs(flags: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start and end (exclusive) indices of the True runs of a 1-D bool array."""
    padded = np.concatenate([[False], flags, [False]]).astype(np.int8)
    change = np.diff(padded)
    return np.flatnonzero(change == 1), np.flatnonzero(change == -1)


def _judged(flags: np.ndarray, margin: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Runs of ``flags`` shrunk by ``margin`` steps at both ends (runs left empty dropped).

    Returns (mask of judged steps (S,), run starts, run ends) of the shrunk runs.
    """
    starts, ends = _runs(flags)
    starts, ends = starts + margin, ends - margin
    keep = ends > starts
    starts, ends = starts[keep], ends[keep]
    mask = np.zeros(flags.shape[0], dtype=bool)
    delta = np.zeros(flags.shape[0] + 1, dtype=int)
    np.add.at(delta, starts, 1)
    np.add.at(delta, ends, -1)
    mask = np.cumsum(delta[:-1]) > 0
    return mask, starts, ends


def stance_slip(
    offset_xy: np.ndarray, stance: np.ndarray, margin: int
) -> tuple[np.ndarray, np.ndarray]:
    """Slip of one foot in each planned stance: the largest distance of its offset from the
    plan from where it was ``margin`` steps after touch-down, until ``margin`` before
    lift-off.

    Args:
        offset_xy: (S, 2) [m], the foot's xy less its planned xy (module docstring, "Slip");
            stance: planned stance flags (S,).

    Returns:
        (slip per stance [m], shape (K,); stance start steps, shape (K,)).
    """
    mask, starts, ends = _judged(stance, margin)
    if starts.size == 0:
        return np.zeros(0), starts
    anchor_of_step = np.zeros(stance.shape[0], dtype=int)
    anchor_of_step[starts] = starts
    anchor_of_step = np.maximum.accumulate(anchor_of_step)
    distance = np.linalg.norm(offset_xy - offset_xy[anchor_of_step], axis=1)
    distance = np.where(mask, distance, 0.0)
    return np.maximum.reduceat(distance, starts) if starts.size else np.zeros(0), starts


def _per(names: tuple[str, ...] | list[str], values: np.ndarray, digits: int = 6) -> dict:
    return {n: round(float(v), digits) for n, v in zip(names, values)}


def measure(sim_model: SimModel, record: SimRecord, th: Thresholds | None = None) -> dict:
    """The replay's figures as a JSON-ready dict (lengths [m], angles [deg], times [s],
    torques [N m]); ``walks`` and the ``reasons`` it does not."""
    th = th or Thresholds()
    n = record.steps_run
    ref = record.reference
    dt = sim_model.settings.timestep_s
    margin = int(round(th.transition_s / dt))

    position = record.get("body_position", sim_model)
    angles = body_angles(record.get("body_quat", sim_model))
    planned = ref.position_base_in_world[:n]
    error = np.linalg.norm(position - planned, axis=1)
    yaw_error = np.angle(np.exp(1j * (angles["yaw"] - ref.yaw_base_in_world[:n])))
    fall_steps = np.flatnonzero(
        (angles["tilt"] > np.radians(th.tilt_deg))
        | (position[:, 2] < th.fall_height_ratio * planned[:, 2])
    )

    feet = record.get("foot_position", sim_model).reshape(n, 4, 3)
    force = record.get("foot_force", sim_model)
    contact_plan = ref.contact[:n]
    # the sim's sphere centres against the planned ones (module docstring, "Slip")
    planned_centres = ref.position_ball_centre_in_world[:n]
    slip_legs, missing, scuff, stances, missed_stances = [], [], [], 0, 0
    for leg in range(4):  # four legs: the per-step work inside is vectorised
        slip, _ = stance_slip(
            feet[:, leg, :2] - planned_centres[:, leg, :2], contact_plan[:, leg], margin
        )
        slip_legs.append(float(slip.max()) if slip.size else 0.0)
        stances += slip.size
        stance_mask, s0, s1 = _judged(contact_plan[:, leg], margin)
        swing_mask, _, _ = _judged(~contact_plan[:, leg], margin)
        lost = stance_mask & (force[:, leg] < th.contact_force_n)
        missing.append(lost.sum() * dt)
        if s0.size:
            missed_stances += int(np.count_nonzero(np.add.reduceat(lost.astype(int), s0)))
        raised = ref.position_foot_in_world[:n, leg, 2] > th.scuff_height_m
        scuff.append((swing_mask & raised & (force[:, leg] >= th.contact_force_n)).sum() * dt)

    body_force = record.get("body_force", sim_model)
    touching = body_force >= th.contact_force_n
    non_foot = {
        name: {
            "seconds": round(float(touching[:, i].sum() * dt), 4),
            "first_s": round(float(ref.t[np.argmax(touching[:, i])]), 4),
        }
        for i, name in enumerate(sim_model.contact_bodies)
        if touching[:, i].any()
    }

    names = sim_model.joint_names
    q_error = record.get("q", sim_model) - ref.q[:n]
    tau_sim = record.get("tau", sim_model)
    tau_plan = ref.tau[:n]
    at_limit = np.abs(tau_sim) >= sim_model.effort_limit * (1 - 1e-6)

    out: dict[str, Any] = {
        "simulated_s": round(float(n * dt), 4),
        "plan_duration_s": round(float(ref.t[-1]), 4),
        "fell": bool(fall_steps.size),
        "falls": int(bool(fall_steps.size)),
        "fell_at_s": round(float(ref.t[fall_steps[0]]), 4) if fall_steps.size else None,
        "max_roll_deg": round(float(np.degrees(np.abs(angles["roll"]).max())), 4),
        "max_pitch_deg": round(float(np.degrees(np.abs(angles["pitch"]).max())), 4),
        "max_tilt_deg": round(float(np.degrees(angles["tilt"].max())), 4),
        "drift_max_m": round(float(error.max()), 6),
        "drift_final_m": round(float(error[-1]), 6),
        "yaw_error_max_deg": round(float(np.degrees(np.abs(yaw_error).max())), 4),
        "yaw_error_final_deg": round(float(np.degrees(yaw_error[-1])), 4),
        "slip_max_m": round(max(slip_legs), 6),
        "slip_per_leg_m": _per(LEGS, np.array(slip_legs)),
        "stances": stances,
        "stances_missing_contact": missed_stances,
        "missing_contact_s": _per(LEGS, np.array(missing), 4),
        "scuff_s": _per(LEGS, np.array(scuff), 4),
        "non_foot_contacts": non_foot,
        "joint_tracking_max_deg": _per(names, np.degrees(np.abs(q_error).max(0)), 4),
        "joint_tracking_rms_deg": _per(names, np.degrees(np.sqrt((q_error**2).mean(0))), 4),
        "torque_peak_sim_nm": _per(names, np.abs(tau_sim).max(0), 3),
        "torque_peak_plan_nm": _per(names, np.abs(tau_plan).max(0), 3),
        "torque_rms_error_nm": _per(names, np.sqrt(((tau_sim - tau_plan) ** 2).mean(0)), 3),
        "effort_limit_s": _per(names, at_limit.sum(0) * dt, 4),
        "thresholds": asdict(th),
    }
    reasons = []
    if out["fell"]:
        reasons.append(
            f"fell at t = {out['fell_at_s']:.2f} s (tilt > {th.tilt_deg:g} deg or "
            f"CoG below {th.fall_height_ratio:g} of its planned height)"
        )
    if out["drift_max_m"] > th.drift_m:
        reasons.append(f"CoG drift {1e3 * out['drift_max_m']:.1f} mm > {1e3 * th.drift_m:g} mm")
    if out["slip_max_m"] > th.slip_m:
        reasons.append(f"foot slip {1e3 * out['slip_max_m']:.1f} mm > {1e3 * th.slip_m:g} mm")
    if out["yaw_error_max_deg"] > th.yaw_deg:
        reasons.append(f"yaw error {out['yaw_error_max_deg']:.1f} deg > {th.yaw_deg:g} deg")
    if non_foot:
        reasons.append(f"non-foot ground contact: {', '.join(sorted(non_foot))}")
    out["walks"] = not reasons
    out["reasons"] = reasons
    return out


def measure_standing(sim_model: SimModel, record: SimRecord, th: Thresholds | None = None) -> dict:
    """The calibration figures: CoG and foot motion while holding the first posture."""
    th = th or Thresholds()
    position = record.get("body_position", sim_model)
    feet = record.get("foot_position", sim_model).reshape(record.steps_run, 4, 3)
    drift = float(np.linalg.norm(position - position[0], axis=1).max())
    slip = float(np.linalg.norm(feet[:, :, :2] - feet[0, :, :2], axis=2).max())
    ok = drift < th.standing_drift_m and slip < th.standing_drift_m
    return {
        "seconds": round(float(record.steps_run * sim_model.settings.timestep_s), 3),
        "base_drift_m": round(drift, 7),
        "foot_slip_m": round(slip, 7),
        "ok": ok,
    }
