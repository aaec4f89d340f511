"""Replay a planned trajectory in MuJoCo: servo references from the plan, one rollout in C.

    sim_model = build_sim_model(robot)
    record = replay(sim_model, trajectory)       # every 1 ms step, see SimRecord
    record = stand_still(sim_model, trajectory)  # the calibration: hold the first posture

The servo command of every step is computed up front (vectorised: the plan interpolated at
the step times), so the run is ``mujoco.rollout`` in chunks with no Python per step;
between chunks the replay stops early once the robot has fallen (silo4sim.metrics.FALL_*).
Only the put-down that starts both (:func:`put_down`, SimSettings.put_down_s: gravity and
the feed-forward ramped in while the posture is held, 300 steps) is stepped from Python,
as a rollout cannot change gravity.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import SimulationError, import_mujoco
from .model import SimModel

#: Steps per rollout chunk (a fall is checked between chunks).
CHUNK_STEPS = 5000


@dataclass(frozen=True, eq=False)
class Reference:
    """The plan at the step times (plan time: 0 at its first sample).

    Attributes:
        t: plan time of each step [s], shape (S,); negative while settling.
        q, qd, tau: joint reference [rad], [rad/s], feed-forward [N m], shape (S, 12), our
            joint order (SimModel.joint_names).
        position_base_in_world: planned CoG [m], shape (S, 3).
        yaw_base_in_world: planned heading [rad], shape (S,).
        contact: planned stance flags, shape (S, 4).
        position_foot_in_world: planned feet [m], shape (S, 4, 3): the plan's contact
            points (a ball foot: its centre less r n, n the ground's normal at the contact).
        position_ball_centre_in_world: planned foot-sphere centres [m], shape (S, 4, 3):
            the sites the sim's foot_position sensors read, placed by the sim model's own
            forward kinematics on the planned pose (:func:`planned_foot_sites`); a ball
            foot's centre, which the planner fixes, a point foot's foot point.
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    position_base_in_world: np.ndarray
    yaw_base_in_world: np.ndarray
    contact: np.ndarray
    position_foot_in_world: np.ndarray
    position_ball_centre_in_world: np.ndarray


@dataclass(frozen=True, eq=False)
class SimRecord:
    """What MuJoCo did, every step (the step's end state).

    Attributes:
        reference: the plan at the same times.
        sensors: sensordata per step, shape (S, nsensordata); SimModel.sensor names slices.
        steps_run: steps simulated (< S when the run stopped after a fall).
    """

    reference: Reference
    sensors: np.ndarray
    steps_run: int

    def get(self, name: str, sim_model: SimModel) -> np.ndarray:
        """Sensor group ``name`` over the steps run, shape (steps_run, dim)."""
        return self.sensors[: self.steps_run, sim_model.sensor[name]]


def _column_order(sim_model: SimModel, trajectory_joint_names: tuple[str, ...]) -> np.ndarray:
    """Index of each of our joints in the trajectory's columns."""
    cols = {name: i for i, name in enumerate(trajectory_joint_names)}
    missing = [n for n in sim_model.joint_names if n not in cols]
    if missing:
        raise SimulationError(
            f"the trajectory does not belong to this robot: it has no column for joints {missing}"
        )
    return np.array([cols[n] for n in sim_model.joint_names])


def reference_at_steps(
    sim_model: SimModel,
    trajectory,
    settle_s: float,  # noqa: ANN001
    hold_only: bool = False,
) -> Reference:
    """The plan sampled at every step end, after ``settle_s`` holding its first sample.

    Linear interpolation between plan samples (plans are sampled at 10 ms or finer, the
    step is 1 ms). With ``hold_only`` the reference is the first sample for settle_s.
    """
    dt = sim_model.settings.timestep_s
    t_plan = np.asarray(trajectory.t, dtype=float) - float(trajectory.t[0])
    if t_plan.shape[0] < 2 or np.any(np.diff(t_plan) <= 0):
        raise SimulationError("the trajectory needs >= 2 samples at increasing times")
    end = 0.0 if hold_only else float(t_plan[-1])
    n_settle = int(round(settle_s / dt))
    n_steps = n_settle + int(np.floor(end / dt + 1e-9))
    t = (np.arange(n_steps) + 1) * dt - n_settle * dt
    tc = np.clip(t, 0.0, t_plan[-1])
    right = np.clip(np.searchsorted(t_plan, tc, side="right"), 1, len(t_plan) - 1)
    left = right - 1
    w = ((tc - t_plan[left]) / (t_plan[right] - t_plan[left]))[:, None]

    def lerp(a: np.ndarray) -> np.ndarray:
        a = np.asarray(a, dtype=float)
        wa = w.reshape(w.shape + (1,) * (a.ndim - 2))
        return a[left] * (1 - wa) + a[right] * wa

    cols = _column_order(sim_model, tuple(trajectory.joint_names))
    tau = trajectory.tau if trajectory.tau is not None else np.zeros_like(trajectory.q)
    nearest = np.where(w[:, 0] < 0.5, left, right)
    rows = np.unique(np.concatenate([left, right]))  # the samples the steps interpolate
    centres = np.full((t_plan.shape[0], 4, 3), np.nan)
    centres[rows] = planned_foot_sites(sim_model, trajectory, rows)
    yaw = np.unwrap(np.asarray(trajectory.yaw_base_in_world, dtype=float))
    qd = lerp(np.asarray(trajectory.qd)[:, cols])
    qd[t < 0] = 0.0
    return Reference(
        t=t,
        q=lerp(np.asarray(trajectory.q)[:, cols]),
        qd=qd,
        tau=lerp(np.asarray(tau)[:, cols]),
        position_base_in_world=lerp(trajectory.position_base_in_world),
        yaw_base_in_world=lerp(yaw[:, None])[:, 0],
        contact=np.asarray(trajectory.contact, dtype=bool)[nearest],
        position_foot_in_world=lerp(trajectory.position_foot_in_world),
        position_ball_centre_in_world=lerp(centres),
    )


def planned_qpos(sim_model: SimModel, trajectory, rows: np.ndarray) -> np.ndarray:  # noqa: ANN001
    """Free-joint pose and joints of the plan's samples ``rows`` (K,), shape (K, nq): the
    root link placed from the planned CoG and yaw (body level), the planned joints."""
    cols = _column_order(sim_model, tuple(trajectory.joint_names))
    rows = np.asarray(rows, dtype=int)
    yaw = np.asarray(trajectory.yaw_base_in_world, dtype=float)[rows]
    c, s = np.cos(yaw), np.sin(yaw)
    rotation = np.zeros((rows.shape[0], 3, 3))
    rotation[:, 0, 0], rotation[:, 0, 1], rotation[:, 1, 0], rotation[:, 1, 1] = c, -s, s, c
    rotation[:, 2, 2] = 1.0
    position_root = (
        np.asarray(trajectory.position_base_in_world, dtype=float)[rows]
        - rotation @ sim_model.position_body_com_in_root
    )
    qpos = np.zeros((rows.shape[0], sim_model.model.nq))  # type: ignore[attr-defined]
    qpos[:, :3] = position_root
    qpos[:, 3] = np.cos(yaw / 2)
    qpos[:, 6] = np.sin(yaw / 2)
    qpos[:, sim_model.qpos_adr] = np.asarray(trajectory.q, dtype=float)[rows][:, cols]
    return qpos


def initial_qpos(sim_model: SimModel, trajectory) -> np.ndarray:  # noqa: ANN001
    """Free-joint pose and joints of the plan's first sample, shape (nq,)."""
    return planned_qpos(sim_model, trajectory, np.zeros(1, dtype=int))[0]


def foot_site_ids(sim_model: SimModel) -> np.ndarray:
    """MuJoCo ids of the sites the foot_position sensors read, in leg order, shape (4,)."""
    model = sim_model.model
    group = sim_model.sensor["foot_position"]
    ids = [
        i
        for i in range(model.nsensor)  # type: ignore[attr-defined]
        if group.start <= model.sensor_adr[i] < group.stop  # type: ignore[attr-defined]
    ]
    return np.asarray(model.sensor_objid[ids])  # type: ignore[attr-defined]


def planned_foot_sites(sim_model: SimModel, trajectory, rows: np.ndarray) -> np.ndarray:  # noqa: ANN001
    """The foot sites (foot-sphere centres) in W [m] of the plan's samples ``rows`` (K,),
    shape (K, 4, 3): MuJoCo's forward kinematics of :func:`planned_qpos`, so exactly what
    the foot_position sensors would read were the robot on the planned pose.

    The planner's foot-frame targets are the ball centres (planner/trajectory/
    rolling_feet.py), so these are the planned centres; its contact points are derived
    from them (centre - r n). One mj_kinematics per sample: MuJoCo has no batched
    kinematics (a few microseconds each)."""
    mj = import_mujoco()
    model = sim_model.model
    data = mj.MjData(model)
    sites = foot_site_ids(sim_model)
    out = np.empty((len(rows), 4, 3))
    for k, qpos in enumerate(planned_qpos(sim_model, trajectory, rows)):
        data.qpos[:] = qpos
        mj.mj_kinematics(model, data)
        out[k] = data.site_xpos[sites]
    return out


def servo_command(sim_model: SimModel, ref: Reference) -> np.ndarray:
    """u = q_ref + (kd q̇_ref + tau_ff) / kp (module doc of silo4sim.model), shape (S, 12)."""
    return ref.q + (sim_model.kd * ref.qd + ref.tau) / sim_model.kp


def smoothstep(n: int) -> np.ndarray:
    """The put-down's load fraction at the end of each of its ``n`` steps, shape (n,):
    3 a^2 - 2 a^3 of a = (k + 1) / n (0 to 1 with zero rate at both ends; 1 at the last)."""
    a = (np.arange(n) + 1.0) / n
    return a * a * (3.0 - 2.0 * a)


def put_down(sim_model: SimModel, data, ref: Reference, n: int) -> np.ndarray:  # noqa: ANN001
    """Step ``data`` through the first ``n`` steps of ``ref`` with gravity and the servos'
    feed-forward both scaled by :func:`smoothstep` (the model's gravity is restored after);
    the sensors of each step, shape (n, nsensordata).

    The robot starts on its planned pose with its feet just touching the floor; dropped
    there at full load, the legs push with the four-foot torques before the contacts carry
    anything and the feet slide until they do (go2 at h 0.37-0.39 m: 1.2-1.4 mm in the first
    0.2 s, then 0.01 mm in 2.5 s; docs/physics.md, "Calibration"). Ramped, the contact forces
    grow with the load they carry, as when a robot is lowered onto its feet. The reference
    must hold one posture over these steps (the settle, the calibration)."""
    mj = import_mujoco()
    model = sim_model.model
    load = smoothstep(n)
    u = ref.q[:n] + (sim_model.kd * ref.qd[:n] + load[:, None] * ref.tau[:n]) / sim_model.kp
    gravity = np.array(model.opt.gravity)  # type: ignore[attr-defined]
    sensors = np.empty((n, model.nsensordata))  # type: ignore[attr-defined]
    try:
        for k in range(n):  # gravity is a model constant: no rollout can ramp it
            model.opt.gravity[:] = load[k] * gravity  # type: ignore[attr-defined]
            data.ctrl[:] = u[k]
            mj.mj_step(model, data)
            sensors[k] = data.sensordata
    finally:
        model.opt.gravity[:] = gravity  # type: ignore[attr-defined]
    return sensors


def put_down_steps(sim_model: SimModel, ref: Reference) -> int:
    """Steps of the put-down (SimSettings.put_down_s) at the start of ``ref``, which must
    hold its first posture over them."""
    n = int(round(sim_model.settings.put_down_s / sim_model.settings.timestep_s))
    if n < 0:
        raise SimulationError(f"put_down_s must be >= 0, got {sim_model.settings.put_down_s}")
    held = int(np.count_nonzero(ref.t <= 0.0))
    if n > held:
        raise SimulationError(
            f"the put-down ({sim_model.settings.put_down_s:g} s) must fit in the time the "
            f"first posture is held ({held * sim_model.settings.timestep_s:g} s: settle_s)"
        )
    return n


def run_rollout(sim_model: SimModel, ref: Reference, qpos0: np.ndarray, stop=None) -> SimRecord:  # noqa: ANN001
    """Simulate the reference from qpos0 (at rest), put down over its first steps
    (:func:`put_down`); ``stop(sensors_of_chunk)`` -> bool ends the run after that chunk
    (e.g. a fall)."""
    mj = import_mujoco()
    from mujoco import rollout

    model = sim_model.model
    data = mj.MjData(model)
    data.qpos[:] = qpos0
    mj.mj_forward(model, data)
    u = servo_command(sim_model, ref)
    n = u.shape[0]
    sensors = np.zeros((n, model.nsensordata))  # type: ignore[attr-defined]
    done = put_down_steps(sim_model, ref)
    sensors[:done] = put_down(sim_model, data, ref, done)
    spec = mj.mjtState.mjSTATE_FULLPHYSICS
    state = np.empty(mj.mj_stateSize(model, spec))
    mj.mj_getState(model, data, state, spec)
    while done < n:
        k = min(CHUNK_STEPS, n - done)
        states, sens = rollout.rollout(model, data, state[None, :], u[None, done : done + k])
        sensors[done : done + k] = sens[0]
        state = states[0, -1]
        done += k
        if not np.all(np.isfinite(sens[0])):
            raise SimulationError(f"the simulation diverged (NaN) at t = {ref.t[done - 1]:.3f} s")
        if stop is not None and stop(sens[0]):
            break
    return SimRecord(reference=ref, sensors=sensors, steps_run=done)


def replay(sim_model: SimModel, trajectory, stop=None) -> SimRecord:  # noqa: ANN001
    """Replay ``trajectory`` (a planner Trajectory) after settling; see the module doc."""
    ref = reference_at_steps(sim_model, trajectory, sim_model.settings.settle_s)
    return run_rollout(sim_model, ref, initial_qpos(sim_model, trajectory), stop)


def stand_still(
    sim_model: SimModel,
    trajectory,
    seconds: float = 3.0,  # noqa: ANN001
) -> SimRecord:
    """The calibration: hold the plan's first posture (with its torques) for ``seconds``,
    put down over the first SimSettings.put_down_s of them."""
    ref = reference_at_steps(sim_model, trajectory, seconds, hold_only=True)
    return run_rollout(sim_model, ref, initial_qpos(sim_model, trajectory))
