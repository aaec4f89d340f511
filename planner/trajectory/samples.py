"""The columnar result of a plan: one row per sample, one array per named quantity.

Frames and units (docs/notation.md): world frame W (z up, ground z = 0), base frame B at the
body CoG (REP-103). Time in seconds, t = (time units t_l) * unit_time_s; with the default
unit_time_s = 1 the numbers equal the thesis's normalised time.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from silo4kin.errors import Silo4Error
from silo4kin.geometry import LEG_NAMES

#: Leg order of every (N, 4, ...) array.
LEGS: tuple[str, ...] = LEG_NAMES


#: The arrays of a Trajectory with one row per sample, and the optional ones.
SAMPLE_ARRAYS: tuple[str, ...] = (
    "t",
    "position_base_in_world",
    "yaw_base_in_world",
    "q",
    "qd",
    "qdd",
    "position_foot_in_world",
    "contact",
    "margin",
    "phase",
)
OPTIONAL_SAMPLE_ARRAYS: tuple[str, ...] = ("margin_com", "margin_body", "tau")


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Dense samples of a plan.

    Attributes:
        t: sample times [s], shape (N,), strictly increasing.
        unit_time_s: duration of one thesis time unit t_l (one leg transfer) [s].
        position_base_in_world: CoG position (x, y, z = body height) [m], shape (N, 3).
        yaw_base_in_world: heading of the base x axis [rad], shape (N,).
        joint_names: URDF names of the 12 joints, column order of q, qd, qdd, tau.
        q: joint positions [rad], shape (N, 12).
        qd: joint velocities [rad/s], shape (N, 12).
        qdd: joint accelerations [rad/s^2], shape (N, 12).
        position_foot_in_world: foot tips [m], shape (N, 4, 3), legs LF, RF, LH, RH.
        contact: foot on the ground, shape (N, 4), bool.
        margin: static stability margin S_m of the stance feet [m], shape (N,)
            (distance from the planner's stability point, body CoG or whole-robot CoM
            (planner/presets.py), to the nearest support-polygon edge, positive inside).
        phase: phase label per sample, e.g. "transfer LF", "body", "rotate", shape (N,).
        margin_com: S_m of the whole-robot CoM (legs included) [m], shape (N,), or None.
        margin_body: S_m of the body CoG (the thesis's criterion) [m], shape (N,), or None.
        tau: joint torques [N m], shape (N, 12), or None before torques are computed.
        tau_parts: named parts of tau (e.g. "motion", "support"), each (N, 12).
    """

    t: np.ndarray
    unit_time_s: float
    position_base_in_world: np.ndarray
    yaw_base_in_world: np.ndarray
    joint_names: tuple[str, ...]
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    position_foot_in_world: np.ndarray
    contact: np.ndarray
    margin: np.ndarray
    phase: np.ndarray
    margin_com: np.ndarray | None = None
    margin_body: np.ndarray | None = None
    tau: np.ndarray | None = None
    tau_parts: dict[str, np.ndarray] = field(default_factory=dict)
    #: Results computed from these samples (silo4kin.memo), e.g. their torques.
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __getstate__(self) -> dict:
        """Pickled (to a plot worker) without the memo: a cache, keyed by functions that
        pickle cannot name."""
        return {**self.__dict__, "_memo": {}}

    def __post_init__(self) -> None:
        n = self.t.shape[0]
        shapes = {
            "position_base_in_world": (n, 3),
            "yaw_base_in_world": (n,),
            "q": (n, 12),
            "qd": (n, 12),
            "qdd": (n, 12),
            "position_foot_in_world": (n, 4, 3),
            "contact": (n, 4),
            "margin": (n,),
            "phase": (n,),
        }
        for name in ("margin_com", "margin_body"):
            if getattr(self, name) is not None:
                shapes[name] = (n,)
        for name, shape in shapes.items():
            got = getattr(self, name).shape
            if got != shape:
                raise Silo4Error(f"Trajectory.{name} has shape {got}, expected {shape}")
        if len(self.joint_names) != 12:
            raise Silo4Error(f"Trajectory needs 12 joint names, got {len(self.joint_names)}")

    def __len__(self) -> int:
        return int(self.t.shape[0])

    @property
    def time_units(self) -> np.ndarray:
        """Normalised time t / t_l, shape (N,)."""
        return self.t / self.unit_time_s

    def head(self, n: int) -> Trajectory:
        """The first ``n`` samples: every per-sample array (optional ones, torques and their
        parts included when present) cut to its first ``n`` rows."""
        rows = slice(0, int(n))
        cut = {
            name: value[rows]
            for name in (*SAMPLE_ARRAYS, *OPTIONAL_SAMPLE_ARRAYS)
            if (value := getattr(self, name)) is not None
        }
        parts = {name: value[rows] for name, value in self.tau_parts.items()}
        return replace(self, tau_parts=parts, **cut)

    def with_torques(
        self, tau: np.ndarray, parts: dict[str, np.ndarray] | None = None
    ) -> Trajectory:
        """A copy carrying joint torques tau (N, 12) [N m] and their named parts."""
        tau = np.asarray(tau, dtype=float)
        if tau.shape != self.q.shape:
            raise Silo4Error(f"tau has shape {tau.shape}, expected {self.q.shape}")
        return replace(self, tau=tau, tau_parts=dict(parts or {}))


def position_foot_in_base(trajectory: Trajectory) -> np.ndarray:
    """Feet relative to the CoG in the level base frame [m], shape (N, 4, 3).

    p_B = R_z(-yaw) (p_W - p_base_W): the body stays level, so only the yaw is undone.
    """
    rel = trajectory.position_foot_in_world - trajectory.position_base_in_world[:, None, :]
    c, s = np.cos(trajectory.yaw_base_in_world), np.sin(trajectory.yaw_base_in_world)
    out = rel.copy()
    out[..., 0] = c[:, None] * rel[..., 0] + s[:, None] * rel[..., 1]
    out[..., 1] = -s[:, None] * rel[..., 0] + c[:, None] * rel[..., 1]
    return out
