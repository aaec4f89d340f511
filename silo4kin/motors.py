"""Motor torque, speed and power through the gearbox, and a per-joint sizing table (App. A.2.3).

    tau_m = tau_j / (mu eta)        (eq A.35)
    omega_m = mu omega_j            (eq A.36)

mu is the gear ratio (motor turns per joint turn), eta the gear efficiency in (0, 1].
Eq A.35 is applied to every sample whatever the sign of the power: when the joint drives the
motor back (braking), the true motor torque is tau_j eta / mu, smaller; A.35 is therefore the
conservative sizing value, as in the thesis.

Defaults: the thesis gives no gear data for SILO4 (it only names mu and eta). We assume
mu = 100 and eta = 0.7 for every joint (a DC motor with a multi-stage planetary or harmonic
gearhead, the usual choice on 30-50 kg walking robots of SILO4's era); both are per-joint
arrays and should be replaced by the real gearbox data (docs/torques.md). Every Gearing
says where each joint's mu and eta came from (``source``): a robot sized without its own
gear data is sized with SILO4's assumed gearing, and its table says so on every row
(ASSUMED_SOURCE). The URDF's effort and velocity limits, when given, go into the table
beside the peaks they bound.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .errors import Silo4Error
from .motor_defaults import (  # noqa: F401 (re-export)
    ASSUMED_SOURCE,
    DEFAULT_GEAR_EFFICIENCY,
    DEFAULT_GEAR_RATIO,
    GIVEN_SOURCE,
)


@dataclass(frozen=True)
class Gearing:
    """Gear ratio and efficiency per joint.

    Attributes:
        ratio: gear ratio mu > 0 per joint [dimensionless], shape (J,).
        efficiency: gear efficiency eta in (0, 1] per joint [dimensionless], shape (J,).
        source: where each joint's mu and eta come from, (J,) texts (one text: every
            joint); default GIVEN_SOURCE.
    """

    ratio: np.ndarray
    efficiency: np.ndarray
    source: tuple[str, ...] | str = GIVEN_SOURCE

    def __post_init__(self) -> None:
        ratio = np.atleast_1d(np.asarray(self.ratio, dtype=float))
        eff = np.broadcast_to(np.asarray(self.efficiency, dtype=float), ratio.shape).copy()
        source = (self.source,) * len(ratio) if isinstance(self.source, str) else tuple(self.source)
        if len(source) != len(ratio):
            raise Silo4Error(f"gearing has {len(source)} sources for {len(ratio)} joints")
        for k, mu in enumerate(ratio):
            if not np.isfinite(mu) or mu <= 0:
                raise Silo4Error(f"gear ratio {mu} (joint {k}) is not allowed: it must be > 0")
        for k, eta in enumerate(eff):
            if not np.isfinite(eta) or not 0.0 < eta <= 1.0:
                raise Silo4Error(
                    f"gear efficiency {eta} (joint {k}) is not allowed: it must be in (0, 1]"
                )
        object.__setattr__(self, "ratio", ratio)
        object.__setattr__(self, "efficiency", eff)
        object.__setattr__(self, "source", source)

    @classmethod
    def uniform(
        cls,
        n_joints: int = 12,
        ratio: float = DEFAULT_GEAR_RATIO,
        efficiency: float = DEFAULT_GEAR_EFFICIENCY,
        source: str | None = None,
    ) -> Gearing:
        """The same mu and eta for every joint (defaults: the documented assumption).

        ``source``: where they come from; None: ASSUMED_SOURCE when they are SILO4's
        defaults (DEFAULT_GEAR_RATIO, DEFAULT_GEAR_EFFICIENCY), else GIVEN_SOURCE.
        """
        if source is None:
            assumed = ratio == DEFAULT_GEAR_RATIO and efficiency == DEFAULT_GEAR_EFFICIENCY
            source = ASSUMED_SOURCE if assumed else GIVEN_SOURCE
        return cls(np.full(n_joints, float(ratio)), np.full(n_joints, float(efficiency)), source)

    @property
    def assumed(self) -> bool:
        """Some joint is sized with SILO4's assumed gearing (no gear data of the robot's)."""
        return ASSUMED_SOURCE in self.source


def motor_torque(tau_joint: np.ndarray, gearing: Gearing) -> np.ndarray:
    """tau_m = tau_j / (mu eta), eq A.35 [N m], same shape as tau_joint (..., J)."""
    return np.asarray(tau_joint, dtype=float) / (gearing.ratio * gearing.efficiency)


def motor_speed(qd_joint: np.ndarray, gearing: Gearing) -> np.ndarray:
    """omega_m = mu omega_j, eq A.36 [rad/s], same shape as qd_joint (..., J)."""
    return np.asarray(qd_joint, dtype=float) * gearing.ratio


def _rms(x: np.ndarray, t: np.ndarray | None) -> np.ndarray:
    """Root mean square over axis 0; time-weighted (trapezoid) when t is given."""
    if t is None or x.shape[0] < 2:
        return np.sqrt(np.mean(x**2, axis=0))
    x2, dt = x**2, np.diff(t)[:, None]
    return np.sqrt(np.sum(0.5 * (x2[1:] + x2[:-1]) * dt, axis=0) / (t[-1] - t[0]))


def sizing_table(
    joint_names: Sequence[str],
    tau_joint: np.ndarray,
    qd_joint: np.ndarray,
    gearing: Gearing | None = None,
    t: np.ndarray | None = None,
    urdf_limits: tuple[np.ndarray, np.ndarray] | None = None,
) -> list[dict[str, float | str]]:
    """Per-joint sizing numbers, JSON-able: one dict per joint.

    Args:
        joint_names: J names, column order of the arrays.
        tau_joint: joint torques [N m], shape (N, J).
        qd_joint: joint velocities [rad/s], shape (N, J).
        gearing: gear ratio and efficiency (default :meth:`Gearing.uniform`).
        t: sample times [s], shape (N,), for time-weighted RMS (default: plain mean).
        urdf_limits: the URDF's (velocity [rad/s], effort [N m]) limits, shape (J,) each
            (planner.trajectory.limits.urdf_limits); None: no limit columns.

    Returns:
        rows with keys joint, gear_ratio, gear_efficiency, gearing_source (where mu and eta
        come from), joint_torque_peak_Nm,
        joint_torque_rms_Nm, joint_speed_peak_rad_s, motor_torque_peak_Nm,
        motor_torque_rms_Nm, motor_speed_peak_rad_s, motor_speed_peak_rpm,
        joint_power_peak_W (max |tau_j omega_j|), motor_power_peak_W (max |tau_m omega_m|,
        = joint power / eta); with ``urdf_limits`` also urdf_effort_limit_Nm,
        urdf_velocity_limit_rad_s, effort_use (joint torque peak / effort limit) and
        speed_use (joint speed peak / velocity limit), 0 where a limit is not positive.
    """
    tau = np.asarray(tau_joint, dtype=float)
    qd = np.asarray(qd_joint, dtype=float)
    names = list(joint_names)
    if tau.ndim != 2 or tau.shape[1] != len(names) or qd.shape != tau.shape or not tau.size:
        raise Silo4Error(
            f"tau {tau.shape} and qd {qd.shape} must both be (N > 0, "
            f"{len(names)}) for joints {names}"
        )
    gearing = gearing or Gearing.uniform(len(names))
    if gearing.ratio.shape != (len(names),):
        raise Silo4Error(f"gearing has {gearing.ratio.shape[0]} joints, expected {len(names)}")
    tt = None if t is None else np.asarray(t, dtype=float)
    tau_m = motor_torque(tau, gearing)
    w_m = motor_speed(qd, gearing)
    cols = {
        "joint_torque_peak_Nm": np.max(np.abs(tau), axis=0),
        "joint_torque_rms_Nm": _rms(tau, tt),
        "joint_speed_peak_rad_s": np.max(np.abs(qd), axis=0),
        "motor_torque_peak_Nm": np.max(np.abs(tau_m), axis=0),
        "motor_torque_rms_Nm": _rms(tau_m, tt),
        "motor_speed_peak_rad_s": np.max(np.abs(w_m), axis=0),
        "motor_speed_peak_rpm": np.max(np.abs(w_m), axis=0) * 30.0 / np.pi,
        "joint_power_peak_W": np.max(np.abs(tau * qd), axis=0),
        "motor_power_peak_W": np.max(np.abs(tau_m * w_m), axis=0),
    }
    if urdf_limits is not None:
        velocity, effort = (
            np.broadcast_to(np.asarray(x, dtype=float), (len(names),)) for x in urdf_limits
        )
        cols["urdf_effort_limit_Nm"], cols["urdf_velocity_limit_rad_s"] = effort, velocity
        cols["effort_use"] = _use(cols["joint_torque_peak_Nm"], effort)
        cols["speed_use"] = _use(cols["joint_speed_peak_rad_s"], velocity)
    rows: list[dict[str, float | str]] = []
    for k, name in enumerate(names):
        row: dict[str, float | str] = {
            "joint": name,
            "gear_ratio": float(gearing.ratio[k]),
            "gear_efficiency": float(gearing.efficiency[k]),
            "gearing_source": gearing.source[k],
        }
        row.update({key: float(v[k]) for key, v in cols.items()})
        rows.append(row)
    return rows


def _use(peak: np.ndarray, limit: np.ndarray) -> np.ndarray:
    """peak / limit where the limit is positive, else 0 (a URDF without the limit)."""
    return np.divide(peak, limit, out=np.zeros_like(peak), where=limit > 0)


_COLUMNS = (
    ("joint", "joint", "{}"),
    ("mu", "gear_ratio", "{:g}"),
    ("eta", "gear_efficiency", "{:g}"),
    ("tau_j pk", "joint_torque_peak_Nm", "{:.2f}"),
    ("tau_j rms", "joint_torque_rms_Nm", "{:.2f}"),
    ("w_j pk", "joint_speed_peak_rad_s", "{:.3f}"),
    ("tau_m pk", "motor_torque_peak_Nm", "{:.4f}"),
    ("tau_m rms", "motor_torque_rms_Nm", "{:.4f}"),
    ("rpm_m pk", "motor_speed_peak_rpm", "{:.0f}"),
    ("P pk", "joint_power_peak_W", "{:.2f}"),
    ("tau/lim", "effort_use", "{:.2f}"),
    ("w/lim", "speed_use", "{:.2f}"),
    ("gearing", "gearing_source", "{}"),
)


def format_sizing_table(rows: Sequence[dict[str, float | str]]) -> str:
    """Plain-text table of :func:`sizing_table` rows for the CLI.

    Units: torques N m, joint speed rad/s, motor speed rpm, power W (joint side); tau/lim and
    w/lim are the peaks over the URDF's limits (when the rows have them); the last line
    says when the gearing is SILO4's assumed one.
    """
    columns = [c for c in _COLUMNS if all(c[1] in row for row in rows)]
    header = [h for h, _, _ in columns]
    body = [[fmt.format(row[key]) for _, key, fmt in columns] for row in rows]
    widths = [max(len(x) for x in col) for col in zip(header, *body)]
    text = {0, len(columns) - 1} if columns[-1][1] == "gearing_source" else {0}
    lines = [
        "  ".join(
            h.ljust(w) if i in text else h.rjust(w) for i, (h, w) in enumerate(zip(header, widths))
        ).rstrip()
    ]
    lines += [
        "  ".join(
            c.ljust(w) if i in text else c.rjust(w) for i, (c, w) in enumerate(zip(r, widths))
        ).rstrip()
        for r in body
    ]
    lines.append(
        "torques N m, w_j rad/s, motor speed rpm, P = max |tau_j w_j| W; "
        "tau_m = tau_j/(mu eta) (A.35), w_m = mu w_j (A.36)"
    )
    if any(row.get("gearing_source") == ASSUMED_SOURCE for row in rows):
        lines.append(
            f"gearing {ASSUMED_SOURCE}: the robot's own gear data was not given (docs/torques.md)"
        )
    return "\n".join(lines)
