"""Write a plan's output folder atomically: trajectory.csv, trajectory.npz, plan.json, metrics.json.

Folder layout (docs/design.md "Outputs and interfaces")::

    OUT/trajectory.csv   one row per sample, one column per named quantity (see below)
    OUT/trajectory.npz   every Trajectory array, exact (float64), plus joint_names
    OUT/plan.json        inputs of the run, stride, the gait that walked (Plan.gait) and why a
                         faster one was not used, the step list (Step.to_dict())
    OUT/metrics.json     planner.path.metrics.compute_metrics(plan)
    OUT/...              whatever ``extra_writers`` add (viz: animation.html, PNG plots)

CSV columns, in this order (decision: all q first, then all qd, then all qdd, each block in
``Trajectory.joint_names`` order, so a spreadsheet user reads one block per quantity)::

    t, base_x, base_y, base_z, base_yaw,
    q_<joint> x12, qd_<joint> x12, qdd_<joint> x12, [tau_<joint> x12 if torques exist],
    contact_LF, contact_RF, contact_LH, contact_RH, margin, phase,
    [margin_com, margin_body,]                            (when the trajectory has them)
    foot_LF_x, foot_LF_y, foot_LF_z, ... foot_RH_z      (feet in the world frame W)

Units: t [s], base_* [m] / [rad], q [rad], qd [rad/s], qdd [rad/s^2], tau [N m], contact 0/1,
margin [m] (signed stability margin S_m of the planner's criterion, positive inside), phase a
text label, margin_com / margin_body [m] (S_m of the whole-robot CoM / of the body CoG),
foot_* [m]. Columns are only ever added after ``phase`` (readers that index by position keep
working); docs/outputs.md is the reference with a line per column. Numbers are written with 10
significant digits (CSV is for people and spreadsheets; the npz is exact). Formatting a
number costs ~0.25 us in C whatever the method (``%`` per row, one ``%`` over the whole
file, ``np.savetxt``, ``ndarray.tofile``, ``np.char.mod``: measured, this is the fastest);
the Python overhead is one string operation per row.

Atomicity: everything is written into a hidden temporary sibling folder, which is renamed to
OUT only when every writer has succeeded. An existing OUT is moved aside first and deleted
only after the rename; on any error the temporary folder is removed and OUT is untouched.

An existing OUT is replaced without asking only when its plan.json records the same inputs
(the same command run again). A folder holding a different run needs ``force=True``; a
non-empty folder that is not a silo4 run folder is never replaced (we refuse to delete
files we did not write). The inputs are what the plan records (waypoints, height, preset,
...) and the caller's requests that the plan does not (``write_run(options=...)``: the gait
asked for, facing the path, the swing height, ``--unit-time auto``, the torque options; see
:data:`OPTION_DEFAULTS`). A plan.json written before a request was recorded lacks its key and
is read as that request's default, so old run folders stay "the same run".
"""

from __future__ import annotations

import csv
import json
import math
import time
import zipfile
import zlib
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from planner.outputs.files import MANIFEST_NAME, OutputFolderError, replace_folder_atomically
from planner.trajectory.samples import LEGS, Trajectory
from silo4kin.errors import Silo4Error
from silo4kin.motor_defaults import DEFAULT_GEAR_EFFICIENCY, DEFAULT_GEAR_RATIO

#: Format tag written into plan.json; identifies a folder as a silo4 run folder.
RUN_FORMAT = "silo4kin.run/1"

#: The files write_run itself writes: the run. A command that reads a run (animate,
#: simulate, export) takes them as its input, so none of its outputs may replace them.
RUN_DATA_FILES = ("trajectory.npz", "plan.json", "metrics.json", "trajectory.csv")


def run_inputs(run_dir: str | Path) -> list[Path]:
    """The run a command reads (:data:`RUN_DATA_FILES` of ``run_dir``), never a target of
    that command (``planner.outputs.files.check_target(inputs=...)``)."""
    return [Path(run_dir) / name for name in RUN_DATA_FILES]

#: The requests recorded in plan.json "inputs" that the plan itself does not carry
#: (``write_run(options=...)``), each with its default: the value ``silo4 plan`` uses when the
#: option is not given, and the value a plan.json that lacks the key is read as (older runs).
OPTION_DEFAULTS: dict[str, Any] = {
    "gait": "auto",              # plan_path(gait=): "auto", "crawl" or "creep"
    "face_path": False,          # plan_path(face_path=): turn to face each segment
    "swing_height_request_m": None,  # plan_path(swing_height_m=) [m]; None: eq 5.12
    "unit_time_auto": False,     # --unit-time auto: the shortest unit time within the limits
    "torques": True,             # tau columns and motor sizing written
    "load": None,                # --load: "body" or "total"; None: the preset's load
    "gear_ratio": DEFAULT_GEAR_RATIO,            # eq A.35-A.36 [dimensionless]
    "gear_efficiency": DEFAULT_GEAR_EFFICIENCY,  # eq A.36 [dimensionless]
}

#: Significant digits of CSV numbers: 1e-10 relative, far below any planning tolerance.
CSV_SIGNIFICANT_DIGITS = 10

#: zlib level of trajectory.npz: 1 writes ~1.5x faster than numpy's default 6 for ~3 % more
#: bytes (3.93 vs 3.83 MB on the thesis straight path); np.load reads either.
NPZ_COMPRESS_LEVEL = 1
#: An array is stored uncompressed in trajectory.npz when deflating its first NPZ_PROBE_BYTES
#: saves less than NPZ_MIN_SAVING of them (torques and margins of some plans: noise-like
#: doubles). On the 8 cases of bench_run.py: 22 % less CPU for 4 % more bytes (41.9 vs 40.3 MB).
NPZ_PROBE_BYTES = 65536
NPZ_MIN_SAVING = 0.2

#: A writer the caller adds to the folder (e.g. viz's animation.html); gets the temp folder.
ExtraWriter = Callable[[Path], object]


# --------------------------------------------------------------------------- columns


def trajectory_columns(trajectory: Trajectory) -> list[str]:
    """CSV header of a trajectory, in file order (module docstring)."""
    names = list(trajectory.joint_names)
    cols = ["t", "base_x", "base_y", "base_z", "base_yaw"]
    for prefix in ("q", "qd", "qdd"):
        cols += [f"{prefix}_{j}" for j in names]
    if trajectory.tau is not None:
        cols += [f"tau_{j}" for j in names]
    cols += [f"contact_{leg}" for leg in LEGS]
    cols += ["margin", "phase"] + _extra_margins(trajectory)[0]
    cols += [f"foot_{leg}_{axis}" for leg in LEGS for axis in "xyz"]
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
        trajectory.q, trajectory.qd, trajectory.qdd,
    ]
    if trajectory.tau is not None:
        parts.append(trajectory.tau)
    parts += [trajectory.contact.astype(float), trajectory.margin[:, None]]
    parts += _extra_margins(trajectory)[1]
    return np.hstack([np.asarray(p, dtype=float) for p in parts])


def write_trajectory_csv(path: Path, trajectory: Trajectory) -> None:
    """Write ``trajectory.csv`` (columns in the module docstring).

    Formats follow the column names (``contact_*`` as integers, ``phase`` as text, the rest
    with CSV_SIGNIFICANT_DIGITS), so a column added to :func:`trajectory_columns` and to the
    numeric blocks in the same order is written right.
    """
    columns = trajectory_columns(trajectory)
    feet = np.asarray(trajectory.position_foot_in_world, dtype=float).reshape(len(trajectory), -1)
    values = np.hstack([_numeric_block(trajectory), feet])  # every column but phase
    numeric = [c for c in columns if c != "phase"]
    if values.shape[1] != len(numeric):
        raise Silo4Error(f"trajectory.csv: {values.shape[1]} numeric values for "
                         f"{len(numeric)} numeric columns")
    num = f"%.{CSV_SIGNIFICANT_DIGITS}g"
    formats = ["%d" if c.startswith("contact_") else num for c in numeric]
    k = columns.index("phase")  # numeric columns before it
    fmt_before, fmt_after = ",".join(formats[:k]), ",".join(formats[k:])
    phases = [_csv_text(str(p)) for p in trajectory.phase]
    with open(path, "w", newline="") as f:
        f.write(",".join(columns) + "\n")
        f.writelines([fmt_before % tuple(row[:k]) + "," + ph + ","
                      + fmt_after % tuple(row[k:]) + "\n"
                      for row, ph in zip(values, phases)])


def _csv_text(text: str) -> str:
    """Quote a text cell the way the csv module reads it back."""
    if any(c in text for c in ',"\n\r'):
        return '"' + text.replace('"', '""') + '"'
    return text


def read_trajectory_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Read a ``trajectory.csv`` back: column name -> array, shape (N,) each.

    Numbers come back as float64, ``contact_*`` as bool, ``phase`` as str.
    """
    path = Path(path)
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as exc:
        raise Silo4Error(f"cannot read {path}: {exc.strerror or exc}") from exc
    if not rows:
        raise Silo4Error(f"{path}: empty file, expected a trajectory.csv header")
    header, body = rows[0], rows[1:]
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


def write_trajectory_npz(path: Path, trajectory: Trajectory) -> None:
    """Write ``trajectory.npz`` (deflated where it pays, NPZ_MIN_SAVING): every array of the
    Trajectory under its field name.

    Extra keys: ``joint_names`` (12,) str, ``unit_time_s`` scalar, ``tau_part_<name>``.
    Strings are stored as unicode arrays, so ``np.load`` needs no pickle.
    """
    arrays: dict[str, np.ndarray] = {
        "t": trajectory.t,
        "unit_time_s": np.asarray(trajectory.unit_time_s, dtype=float),
        "position_base_in_world": trajectory.position_base_in_world,
        "yaw_base_in_world": trajectory.yaw_base_in_world,
        "joint_names": np.array(trajectory.joint_names, dtype=str),
        "q": trajectory.q, "qd": trajectory.qd, "qdd": trajectory.qdd,
        "position_foot_in_world": trajectory.position_foot_in_world,
        "contact": np.asarray(trajectory.contact, dtype=bool),
        "margin": trajectory.margin,
        "phase": np.asarray(trajectory.phase, dtype=str),
    }
    for name in ("margin_com", "margin_body"):
        if getattr(trajectory, name) is not None:
            arrays[name] = getattr(trajectory, name)
    if trajectory.tau is not None:
        arrays["tau"] = trajectory.tau
    for name, value in trajectory.tau_parts.items():
        arrays[f"tau_part_{name}"] = value
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED,
                         compresslevel=NPZ_COMPRESS_LEVEL) as archive:
        for name, value in arrays.items():  # np.savez_compressed's layout, our zlib level
            value = np.asarray(value, order="C")      # (keeps a 0-d array 0-d)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=time.localtime()[:6])
            info.compress_type = (zipfile.ZIP_DEFLATED if _deflates(value)
                                  else zipfile.ZIP_STORED)
            info._compresslevel = NPZ_COMPRESS_LEVEL   # what ZipFile.open(name) sets
            with archive.open(info, "w", force_zip64=True) as member:
                np.lib.format.write_array(member, value, allow_pickle=False)


def _deflates(array: np.ndarray) -> bool:
    """Whether deflating the first NPZ_PROBE_BYTES of ``array`` (C-contiguous) saves at least
    NPZ_MIN_SAVING of them."""
    probe = array.reshape(-1).view(np.uint8)[:NPZ_PROBE_BYTES].tobytes()
    return len(zlib.compress(probe, NPZ_COMPRESS_LEVEL)) <= (1.0 - NPZ_MIN_SAVING) * len(probe)


_NPZ_ARRAYS = ("t", "position_base_in_world", "yaw_base_in_world", "joint_names", "q", "qd",
               "qdd", "position_foot_in_world", "contact", "margin", "phase")


def read_trajectory_npz(path: str | Path) -> Trajectory:
    """The :class:`Trajectory` stored by :func:`write_trajectory_npz` (round trip, exact).

    Raises:
        Silo4Error: the file is missing, not an npz, or lacks a field (named).
    """
    path = Path(path)
    if not path.is_file():
        raise Silo4Error(f"{path}: no such file (expected a trajectory.npz written by silo4)")
    try:
        with np.load(path, allow_pickle=False) as npz:
            missing = [k for k in _NPZ_ARRAYS + ("unit_time_s",) if k not in npz.files]
            if missing:
                raise Silo4Error(f"{path}: not a silo4 trajectory.npz (missing {missing})")
            arrays = {k: npz[k] for k in npz.files}
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile, zlib.error) as exc:
        # truncated, empty or corrupt files raise any of these from numpy / zipfile
        raise Silo4Error(f"{path}: cannot read a trajectory, the file is truncated or "
                         f"corrupt ({type(exc).__name__}: {exc})") from exc
    _check_npz_shapes(path, arrays)
    parts = {k.removeprefix("tau_part_"): v for k, v in arrays.items()
             if k.startswith("tau_part_")}
    return Trajectory(
        t=arrays["t"], unit_time_s=float(arrays["unit_time_s"]),
        position_base_in_world=arrays["position_base_in_world"],
        yaw_base_in_world=arrays["yaw_base_in_world"],
        joint_names=tuple(str(n) for n in arrays["joint_names"]),
        q=arrays["q"], qd=arrays["qd"], qdd=arrays["qdd"],
        position_foot_in_world=arrays["position_foot_in_world"],
        contact=arrays["contact"].astype(bool), margin=arrays["margin"],
        phase=arrays["phase"], margin_com=arrays.get("margin_com"),
        margin_body=arrays.get("margin_body"), tau=arrays.get("tau"), tau_parts=parts)


def _check_npz_shapes(path: Path, arrays: Mapping[str, np.ndarray]) -> None:
    """Refuse arrays whose shapes or types do not make one trajectory (a hand-edited file)."""
    n = arrays["t"].shape[0] if arrays["t"].ndim == 1 else -1
    expected = {"t": (n,), "position_base_in_world": (n, 3), "yaw_base_in_world": (n,),
                "joint_names": (12,), "q": (n, 12), "qd": (n, 12), "qdd": (n, 12),
                "position_foot_in_world": (n, 4, 3), "contact": (n, 4), "margin": (n,),
                "phase": (n,), "unit_time_s": ()}
    for name, shape in expected.items():
        a = arrays[name]
        numeric = name in ("joint_names", "phase") or a.dtype.kind in "biuf"
        if n < 1 or a.shape != shape or not numeric:
            raise Silo4Error(f"{path}: not a valid silo4 trajectory.npz ({name} has shape "
                             f"{a.shape} and type {a.dtype}, expected shape {shape})")
    unit_time = float(arrays["unit_time_s"])
    if not (np.isfinite(unit_time) and unit_time > 0):
        raise Silo4Error(f"{path}: not a valid silo4 trajectory.npz (unit_time_s {unit_time})")


# --------------------------------------------------------------------------- JSON


def to_jsonable(value: Any) -> Any:
    """numpy scalars/arrays, tuples, Paths -> plain JSON types; NaN/inf -> None."""
    kind = type(value)          # the plain types first (plan.json: ~10,000 values a run)
    if kind is float:
        return value if math.isfinite(value) else None
    if kind is str or kind is int or kind is bool or value is None:
        return value
    if kind is dict:
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if kind is list or kind is tuple:
        return [to_jsonable(v) for v in value]
    if isinstance(value, Mapping):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, (np.integer, int)):
        return int(value)
    if isinstance(value, (np.floating, float)):
        v = float(value)
        return v if math.isfinite(v) else None
    if isinstance(value, (np.str_, Path)):
        return str(value)
    return value


def plan_inputs(plan: Any, robot_name: str,
                options: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """What identifies a run: the same inputs give the same plan (compared before replacing).

    Keys read off the plan: robot, waypoints_in_world [m], height_m, height_auto (``height=
    "auto"``: Plan.height_search is set), workspace, start_heading_deg, tolerance_m,
    stability_threshold_m, samples_per_unit, unit_time_s; then every key of
    :data:`OPTION_DEFAULTS`, from ``options`` where given, else its default.

    Raises:
        Silo4Error: an ``options`` key that is not in OPTION_DEFAULTS.
    """
    unknown = sorted(set(options or {}) - set(OPTION_DEFAULTS))
    if unknown:
        raise Silo4Error(f"unknown run options {unknown}; known: {sorted(OPTION_DEFAULTS)}")
    trajectory = plan.trajectory
    samples_per_unit = getattr(plan, "samples_per_unit", None)
    if samples_per_unit is None and len(trajectory) > 1:
        units = float(trajectory.time_units[-1] - trajectory.time_units[0])
        samples_per_unit = round((len(trajectory) - 1) / units) if units > 0 else None
    return to_jsonable({
        "robot": robot_name,
        "waypoints_in_world": np.asarray(plan.waypoints_in_world, dtype=float),
        "height_m": float(plan.height),
        "height_auto": getattr(plan, "height_search", None) is not None,
        "workspace": getattr(plan.workspace, "preset", str(plan.workspace)),
        "start_heading_deg": math.degrees(float(plan.start_heading)),
        "tolerance_m": plan.tolerance,
        "stability_threshold_m": plan.stability_threshold,
        "samples_per_unit": samples_per_unit,
        "unit_time_s": float(trajectory.unit_time_s),
        **OPTION_DEFAULTS,
        **(options or {}),
    })


def plan_document(plan: Any, robot_name: str,
                  options: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The content of plan.json: format tag, inputs (:func:`plan_inputs`), workspace numbers
    and the step list."""
    workspace = plan.workspace
    trajectory = plan.trajectory
    return to_jsonable({
        "format": RUN_FORMAT,
        "inputs": plan_inputs(plan, robot_name, options),
        "robot": robot_name,
        "height_m": float(plan.height),
        "start_heading_rad": float(plan.start_heading),
        "height_search": getattr(plan, "height_search", None),
        "gait": getattr(plan, "gait", None),
        "fallback_reason": getattr(plan, "fallback_reason", None),
        "workspace": {
            "preset": getattr(workspace, "preset", None),
            "stride_m": getattr(workspace, "stride_m", None),
            "swing_height_m": getattr(workspace, "swing_height_m", None),
        },
        "stride_m": getattr(workspace, "stride_m", None),
        "n_samples": len(trajectory),
        "duration_units": float(trajectory.time_units[-1]) if len(trajectory) else 0.0,
        "steps": [step.to_dict() for step in plan.steps],
    })


def _write_json(path: Path, document: Mapping[str, Any], *, plain: bool = False) -> None:
    """``document`` as JSON (``plain``: already made of JSON types, :func:`to_jsonable`)."""
    with open(path, "w") as f:
        json.dump(document if plain else to_jsonable(document), f, indent=1, allow_nan=False)
        f.write("\n")


# --------------------------------------------------------------------------- folder


#: Keys read off the plan that a plan.json written before they were recorded lacks, with
#: the value such a run had (see OPTION_DEFAULTS for the caller's requests).
_PLAN_KEY_DEFAULTS: dict[str, Any] = {"height_auto": False}


def read_run_inputs(folder: Path) -> dict[str, Any] | None:
    """The inputs recorded in a folder's plan.json, a missing key read as its default
    (:data:`OPTION_DEFAULTS`: an older plan.json), or None if it is not a run folder."""
    try:
        document = json.loads((folder / "plan.json").read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(document, dict) or document.get("format") != RUN_FORMAT:
        return None
    inputs = document.get("inputs")
    if not isinstance(inputs, dict):
        return None
    return {**_PLAN_KEY_DEFAULTS, **to_jsonable(OPTION_DEFAULTS), **inputs}


def check_output_folder(out_dir: Path, inputs: Mapping[str, Any], *, force: bool) -> None:
    """Refuse to replace a folder holding something else (module docstring)."""
    if not out_dir.exists():
        return
    if not out_dir.is_dir():
        raise OutputFolderError(f"output {out_dir} exists and is not a folder", out_dir)
    if not any(out_dir.iterdir()):
        return
    recorded = read_run_inputs(out_dir)
    if recorded is None:
        raise OutputFolderError(
            f"output folder {out_dir} is not empty and is not a silo4 run folder "
            "(no plan.json of ours); choose a new or empty folder", out_dir)
    if recorded != to_jsonable(json.loads(json.dumps(to_jsonable(inputs)))) and not force:
        raise OutputFolderError(
            f"output folder {out_dir} holds a different run (its plan.json records other "
            "inputs); use --force to replace it, or choose another folder", out_dir)


def write_run(out_dir: str | Path, plan: Any, metrics: Mapping[str, Any], *, robot_name: str,
              force: bool = False, write_csv: bool = True,
              extra_writers: Sequence[ExtraWriter] = (),
              robot_source: Mapping[str, Any] | None = None,
              options: Mapping[str, Any] | None = None) -> dict[str, Path]:
    """Write a plan's output folder atomically; returns file name -> final path.

    Args:
        out_dir: the run folder (created, parents too).
        plan: a ``planner.path.plan_path.Plan``.
        metrics: ``planner.path.metrics.compute_metrics(plan)``.
        robot_name: recorded in plan.json (part of the run's identity).
        force: replace a folder that holds a different run.
        write_csv: False skips trajectory.csv (the npz has the same data, exactly).
        extra_writers: callables ``writer(tmp_folder)`` run after our files and before the
            rename (viz adds animation.html / PNGs here); any exception aborts the whole write.
            A writer with ``start(tmp_folder)`` is started before our files (work in the
            background) and one with ``stop()`` is stopped if the write fails.
        robot_source: where the robot came from (file, xacro_args, package_dirs), recorded
            in plan.json under "robot_source" so ``silo4 animate`` can load the same robot.
        options: the caller's requests the plan does not carry (keys of
            :data:`OPTION_DEFAULTS`; a missing key is its default), recorded in plan.json
            "inputs": part of the run's identity.

    Raises:
        OutputFolderError: folder not writable, or holds another run (without force), or
            holds files that are not a run.
    """
    out_dir = Path(out_dir)
    document = plan_document(plan, robot_name, options)
    if robot_source is not None:
        document["robot_source"] = to_jsonable(robot_source)

    def fill(tmp: Path) -> None:
        try:
            # started inside the try: a signal right after a start must still stop the
            # workers, or they keep drawing into the folder being removed (issue 14)
            for writer in extra_writers:  # e.g. plots drawn by worker processes meanwhile
                start = getattr(writer, "start", None)
                if start is not None:
                    start(tmp)
            if write_csv:
                write_trajectory_csv(tmp / "trajectory.csv", plan.trajectory)
            write_trajectory_npz(tmp / "trajectory.npz", plan.trajectory)
            _write_json(tmp / "plan.json", document, plain=True)   # plan_document's
            _write_json(tmp / "metrics.json", metrics)
            for writer in extra_writers:
                writer(tmp)
        except BaseException:
            for writer in extra_writers:  # nothing may keep writing into a removed folder
                stop = getattr(writer, "stop", None)
                if stop is not None:
                    stop()
            raise

    final = replace_folder_atomically(  # checked under the folder lock (planner/outputs/files.py)
        out_dir, fill, check=lambda d: check_output_folder(d, document["inputs"], force=force))
    return {p.name: p for p in sorted(final.iterdir()) if p.name != MANIFEST_NAME}
