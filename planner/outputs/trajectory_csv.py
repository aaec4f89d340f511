"""trajectory.csv: one row per sample, one column per named quantity (docs/outputs.md).

Columns, in this order (all q first, then all qd, then all qdd, each block in
``Trajectory.joint_names`` order, so a spreadsheet user reads one block per quantity)::

    t, base_x, base_y, base_z, base_yaw,
    q_<joint> x12, qd_<joint> x12, qdd_<joint> x12, [tau_<joint> x12 if torques exist],
    contact_<leg> x4, margin, phase,
    [margin_com, margin_body,]                            (when the trajectory has them)
    foot_<leg>_x, foot_<leg>_y, foot_<leg>_z x4         (feet in the world frame W)
    [root_x, root_y, root_z, root_qx, root_qy, root_qz, root_qw]   (URDF root link in W)

One vocabulary per file: ``<joint>`` is the URDF's joint name and ``<leg>`` the URDF's leg
prefix of those joints (planner.outputs.leg_labels: go2 FL, FR, RL, RR; SILO4 LF, RF, LH,
RH), in the planner's leg order LF, RF, LH, RH. :func:`read_trajectory_csv` gives the leg
columns back under the planner's names, so its callers read old and new files alike.

``base_*`` is the planner's body frame B_c (origin at the body CoG, axes of the URDF root
link, level), not the URDF root link; ``root_*`` is the root link's pose
(planner/outputs/root_pose.py), the floating base to give Pinocchio, MuJoCo or ROS.

Units: t [s], base_* [m] / [rad], q [rad], qd [rad/s], qdd [rad/s^2], tau [N m], contact 0/1,
margin [m] (signed stability margin S_m of the planner's criterion, positive inside), phase a
text label, margin_com / margin_body [m] (S_m of the whole-robot CoM / of the body CoG),
foot_* [m], root_x/y/z [m], root_q* a unit quaternion (x, y, z, w). Columns are only ever
added after ``phase`` (readers that index by position keep working). Numbers are written
with 10 significant digits (CSV is for people and spreadsheets; the npz is exact).
Formatting a number costs ~0.25 us in C whatever the method (``%`` per row, one ``%`` over
the whole file, ``np.savetxt``, ``ndarray.tofile``, ``np.char.mod``: measured, this is the
fastest); the Python overhead is one string operation per row.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from planner.outputs.leg_labels import LegLabels
from planner.outputs.root_pose import RootPose
from planner.trajectory.samples import LEGS, Trajectory
from silo4kin.errors import Silo4Error

#: Significant digits of CSV numbers: 1e-10 relative, far below any planning tolerance.
CSV_SIGNIFICANT_DIGITS = 10
#: The root link's pose columns, last in the file (when the writer is given the pose).
ROOT_COLUMNS = ("root_x", "root_y", "root_z", "root_qx", "root_qy", "root_qz", "root_qw")


def trajectory_columns(trajectory: Trajectory, *, root: bool = False) -> list[str]:
    """CSV header of a trajectory, in file order (module docstring); ``root``: with the
    root pose columns."""
    names = list(trajectory.joint_names)
    legs = LegLabels.from_joint_names(names).legs
    cols = ["t", "base_x", "base_y", "base_z", "base_yaw"]
    for prefix in ("q", "qd", "qdd"):
        cols += [f"{prefix}_{j}" for j in names]
    if trajectory.tau is not None:
        cols += [f"tau_{j}" for j in names]
    cols += [f"contact_{leg}" for leg in legs]
    cols += ["margin", "phase"] + _extra_margins(trajectory)[0]
    cols += [f"foot_{leg}_{axis}" for leg in legs for axis in "xyz"]
    if root:
        cols += ROOT_COLUMNS
    return cols


def _extra_margins(trajectory: Trajectory) -> tuple[list[str], list[np.ndarray]]:
    """(names, arrays) of the optional margin columns the trajectory has."""
    names, arrays = [], []
    for name in ("margin_com", "margin_body"):
        value = getattr(trajectory, name)
        if value is not None:
            names.append(name)
            arrays.append(value[:, None])
    return names, arrays


def _numeric_block(trajectory: Trajectory) -> np.ndarray:
    """All numeric CSV columns side by side, shape (N, n_columns - 1) (phase excluded)."""
    parts = [
        trajectory.t[:, None],
        trajectory.position_base_in_world,
        trajectory.yaw_base_in_world[:, None],
        trajectory.q,
        trajectory.qd,
        trajectory.qdd,
    ]
    if trajectory.tau is not None:
        parts.append(trajectory.tau)
    parts += [trajectory.contact.astype(float), trajectory.margin[:, None]]
    parts += _extra_margins(trajectory)[1]
    return np.hstack([np.asarray(p, dtype=float) for p in parts])


def write_trajectory_csv(
    path: Path, trajectory: Trajectory, root_pose: RootPose | None = None
) -> None:
    """Write ``trajectory.csv`` (columns in the module docstring); ``root_pose``: the URDF
    root link's pose (planner.outputs.root_pose.root_pose_in_world), written as the last
    columns (``planner.outputs.run_folder.write_run`` always gives it).

    Formats follow the column names (``contact_*`` as integers, ``phase`` as text, the rest
    with CSV_SIGNIFICANT_DIGITS), so a column added to :func:`trajectory_columns` and to the
    numeric blocks in the same order is written right.
    """
    columns = trajectory_columns(trajectory, root=root_pose is not None)
    feet = np.asarray(trajectory.position_foot_in_world, dtype=float).reshape(len(trajectory), -1)
    parts = [_numeric_block(trajectory), feet]
    if root_pose is not None:
        parts += [root_pose.position_root_in_world, root_pose.orientation_root_in_world_xyzw]
    values = np.hstack(parts)  # every column but phase
    numeric = [c for c in columns if c != "phase"]
    if values.shape[1] != len(numeric):
        raise Silo4Error(
            f"trajectory.csv: {values.shape[1]} numeric values for {len(numeric)} numeric columns"
        )
    num = f"%.{CSV_SIGNIFICANT_DIGITS}g"
    formats = ["%d" if c.startswith("contact_") else num for c in numeric]
    k = columns.index("phase")  # numeric columns before it
    fmt_before, fmt_after = ",".join(formats[:k]), ",".join(formats[k:])
    phases = [_csv_text(str(p)) for p in trajectory.phase]
    with open(path, "w", newline="") as f:
        f.write(",".join(columns) + "\n")
        f.writelines(
            [
                fmt_before % tuple(row[:k]) + "," + ph + "," + fmt_after % tuple(row[k:]) + "\n"
                for row, ph in zip(values, phases)
            ]
        )


def _csv_text(text: str) -> str:
    """Quote a text cell the way the csv module reads it back."""
    if any(c in text for c in ',"\n\r'):
        return '"' + text.replace('"', '""') + '"'
    return text


def read_trajectory_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Read a ``trajectory.csv`` back: column name -> array, shape (N,) each.

    Numbers come back as float64, ``contact_*`` as bool, ``phase`` as str. A file written
    before the root pose was recorded has no ``root_*`` columns. Leg columns come back under
    the planner's leg names (``contact_LF``, ``foot_LH_x``) whether the file uses them or
    the robot's own (``contact_FL``, ``foot_RL_x``: module docstring).
    """
    path = Path(path)
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as exc:
        raise Silo4Error(f"cannot read {path}: {exc.strerror or exc}") from exc
    if not rows:
        raise Silo4Error(f"{path}: empty file, expected a trajectory.csv header")
    header, body = _planner_leg_names(rows[0]), rows[1:]
    out: dict[str, np.ndarray] = {}
    for k, name in enumerate(header):
        values = [r[k] for r in body]
        if name == "phase":
            out[name] = np.array(values, dtype=str)
        elif name.startswith("contact_"):
            out[name] = np.array(values, dtype=float) != 0.0
        else:
            out[name] = np.array(values, dtype=float)
    return out


def _planner_leg_names(header: list[str]) -> list[str]:
    """``header`` with the leg columns renamed from the robot's leg names to LF, RF, LH, RH."""
    joints = [name[len("q_") :] for name in header if name.startswith("q_")]
    own = LegLabels.from_joint_names(joints).legs
    if tuple(own) == tuple(LEGS) or not all(f"contact_{leg}" in header for leg in own):
        return list(header)
    to_planner = {
        **{f"contact_{o}": f"contact_{p}" for o, p in zip(own, LEGS)},
        **{f"foot_{o}_{a}": f"foot_{p}_{a}" for o, p in zip(own, LEGS) for a in "xyz"},
    }
    return [to_planner.get(name, name) for name in header]
