"""trajectory.npz: every Trajectory array, exact (float64), plus joint_names and the URDF
root link's pose (docs/outputs.md).

Keys: the Trajectory's field names; ``joint_names`` (12,) str, ``unit_time_s`` scalar,
``tau_part_<name>``; ``position_root_in_world`` (N, 3) [m] and
``orientation_root_in_world_xyzw`` (N, 4) (planner/outputs/root_pose.py; a file written
before they were recorded lacks them: :func:`read_root_pose_npz` returns None).
"""

from __future__ import annotations

import time
import zipfile
import zlib
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from planner.budget import MAX_TOTAL_SAMPLES
from planner.outputs.root_pose import RootPose
from planner.trajectory.samples import Trajectory
from silo4kin.errors import Silo4Error

#: zlib level of trajectory.npz: 1 writes ~1.5x faster than numpy's default 6 for ~3 % more
#: bytes (3.93 vs 3.83 MB on the thesis straight path); np.load reads either.
NPZ_COMPRESS_LEVEL = 1
#: An array is stored uncompressed in trajectory.npz when deflating its first NPZ_PROBE_BYTES
#: saves less than NPZ_MIN_SAVING of them (torques and margins of some plans: noise-like
#: doubles). On the 8 cases of bench_run.py: 22 % less CPU for 4 % more bytes (41.9 vs 40.3 MB).
NPZ_PROBE_BYTES = 65536
NPZ_MIN_SAVING = 0.2


def write_trajectory_npz(
    path: Path, trajectory: Trajectory, root_pose: RootPose | None = None
) -> None:
    """Write ``trajectory.npz`` (deflated where it pays, NPZ_MIN_SAVING): every array of the
    Trajectory under its field name, and ``root_pose`` when given (module docstring).

    Strings are stored as unicode arrays, so ``np.load`` needs no pickle.
    """
    arrays: dict[str, np.ndarray] = {
        "t": trajectory.t,
        "unit_time_s": np.asarray(trajectory.unit_time_s, dtype=float),
        "position_base_in_world": trajectory.position_base_in_world,
        "yaw_base_in_world": trajectory.yaw_base_in_world,
        "joint_names": np.array(trajectory.joint_names, dtype=str),
        "q": trajectory.q,
        "qd": trajectory.qd,
        "qdd": trajectory.qdd,
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
    if root_pose is not None:
        arrays.update(root_pose._asdict())
    with zipfile.ZipFile(
        path, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=NPZ_COMPRESS_LEVEL
    ) as archive:
        for name, value in arrays.items():  # np.savez_compressed's layout, our zlib level
            value = np.asarray(value, order="C")  # (keeps a 0-d array 0-d)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=time.localtime()[:6])
            info.compress_type = zipfile.ZIP_DEFLATED if _deflates(value) else zipfile.ZIP_STORED
            info._compresslevel = NPZ_COMPRESS_LEVEL  # type: ignore[attr-defined]  # as ZipFile.open
            with archive.open(info, "w", force_zip64=True) as member:
                np.lib.format.write_array(member, value, allow_pickle=False)


def _deflates(array: np.ndarray) -> bool:
    """Whether deflating the first NPZ_PROBE_BYTES of ``array`` (C-contiguous) saves at least
    NPZ_MIN_SAVING of them."""
    probe = array.reshape(-1).view(np.uint8)[:NPZ_PROBE_BYTES].tobytes()
    return len(zlib.compress(probe, NPZ_COMPRESS_LEVEL)) <= (1.0 - NPZ_MIN_SAVING) * len(probe)


_NPZ_ARRAYS = (
    "t",
    "position_base_in_world",
    "yaw_base_in_world",
    "joint_names",
    "q",
    "qd",
    "qdd",
    "position_foot_in_world",
    "contact",
    "margin",
    "phase",
)


def read_trajectory_npz(path: str | Path) -> Trajectory:
    """The :class:`Trajectory` stored by :func:`write_trajectory_npz` (round trip, exact).

    Raises:
        Silo4Error: the file is missing, not an npz, or lacks a field (named).
    """
    path = Path(path)
    if not path.is_file():
        raise Silo4Error(f"{path}: no such file (expected a trajectory.npz written by silo4)")
    try:
        _check_member_sizes(path)
        with np.load(path, allow_pickle=False) as npz:
            missing = [k for k in _NPZ_ARRAYS + ("unit_time_s",) if k not in npz.files]
            if missing:
                raise Silo4Error(f"{path}: not a silo4 trajectory.npz (missing {missing})")
            arrays = {k: npz[k] for k in npz.files if _is_ours(k)}
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile, zlib.error) as exc:
        # truncated, empty or corrupt files raise any of these from numpy / zipfile
        raise Silo4Error(
            f"{path}: cannot read a trajectory, the file is truncated or "
            f"corrupt ({type(exc).__name__}: {exc})"
        ) from exc
    _check_npz_shapes(path, arrays)
    _check_finite(path, arrays)
    parts = {
        k.removeprefix("tau_part_"): v
        for k, v in arrays.items()
        if k.startswith("tau_part_") and k not in RootPose._fields
    }
    return Trajectory(
        t=arrays["t"],
        unit_time_s=float(arrays["unit_time_s"]),
        position_base_in_world=arrays["position_base_in_world"],
        yaw_base_in_world=arrays["yaw_base_in_world"],
        joint_names=tuple(str(n) for n in arrays["joint_names"]),
        q=arrays["q"],
        qd=arrays["qd"],
        qdd=arrays["qdd"],
        position_foot_in_world=arrays["position_foot_in_world"],
        contact=arrays["contact"].astype(bool),
        margin=arrays["margin"],
        phase=arrays["phase"],
        margin_com=arrays.get("margin_com"),
        margin_body=arrays.get("margin_body"),
        tau=arrays.get("tau"),
        tau_parts=parts,
    )


#: Largest member of a trajectory.npz read, uncompressed [bytes]: the (N, 4, 3) float64 foot
#: positions at the work budget's N (planner/budget.py), plus room for the .npy header. A
#: hand-edited file with a bigger member (an all-zeros array deflates 1000:1) is refused
#: before anything is decompressed.
MAX_NPZ_MEMBER_BYTES = (MAX_TOTAL_SAMPLES + 1) * 12 * 8 + 65536
#: Arrays that must hold finite numbers only (a NaN in q would reach the simulator, an inf in
#: qd the ROS 2 bag and the goal).
_FINITE_ARRAYS = (
    "t",
    "position_base_in_world",
    "yaw_base_in_world",
    "q",
    "qd",
    "qdd",
    "position_foot_in_world",
    *RootPose._fields,
)


def _is_ours(key: str) -> bool:
    """Whether ``key`` is an array write_trajectory_npz writes (others are never read)."""
    return (
        key in _NPZ_ARRAYS
        or key in RootPose._fields
        or key.startswith("tau_part_")
        or key in ("unit_time_s", "margin_com", "margin_body", "tau")
    )


def _check_member_sizes(path: Path) -> None:
    """Refuse an archive member of ours larger than MAX_NPZ_MEMBER_BYTES once decompressed
    (zipfile's ``file_size``, read from the central directory: nothing is decompressed)."""
    with zipfile.ZipFile(path) as archive:
        for info in archive.infolist():
            key = info.filename.removesuffix(".npy")
            if _is_ours(key) and info.file_size > MAX_NPZ_MEMBER_BYTES:
                raise Silo4Error(
                    f"{path}: {key} holds {info.file_size:,} bytes uncompressed, more than a "
                    f"trajectory within the work budget can ({MAX_NPZ_MEMBER_BYTES:,}); "
                    "not a trajectory.npz written by silo4"
                )


def _check_finite(path: Path, arrays: Mapping[str, np.ndarray]) -> None:
    """Refuse NaN or infinities in the arrays of _FINITE_ARRAYS (a hand-edited file)."""
    for name in _FINITE_ARRAYS:
        a = arrays.get(name)
        if a is not None and a.dtype.kind == "f" and not np.isfinite(a).all():
            bad = np.argwhere(~np.isfinite(a))[0]
            raise Silo4Error(
                f"{path}: {name}{bad.tolist()} is {a[tuple(bad)]}: a trajectory "
                "holds finite numbers only (was the file edited?)"
            )


def _check_npz_shapes(path: Path, arrays: Mapping[str, np.ndarray]) -> None:
    """Refuse arrays whose shapes or types do not make one trajectory (a hand-edited file)."""
    n = arrays["t"].shape[0] if arrays["t"].ndim == 1 else -1
    expected = {
        "t": (n,),
        "position_base_in_world": (n, 3),
        "yaw_base_in_world": (n,),
        "joint_names": (12,),
        "q": (n, 12),
        "qd": (n, 12),
        "qdd": (n, 12),
        "position_foot_in_world": (n, 4, 3),
        "contact": (n, 4),
        "margin": (n,),
        "phase": (n,),
        "unit_time_s": (),
    }
    for name, shape in expected.items():
        a = arrays[name]
        numeric = name in ("joint_names", "phase") or a.dtype.kind in "biuf"
        if n < 1 or a.shape != shape or not numeric:
            raise Silo4Error(
                f"{path}: not a valid silo4 trajectory.npz ({name} has shape "
                f"{a.shape} and type {a.dtype}, expected shape {shape})"
            )
    unit_time = float(arrays["unit_time_s"])
    if not (np.isfinite(unit_time) and unit_time > 0):
        raise Silo4Error(f"{path}: not a valid silo4 trajectory.npz (unit_time_s {unit_time})")


def read_root_pose_npz(path: str | Path) -> RootPose | None:
    """The URDF root link's pose stored in a ``trajectory.npz``, or None for a file written
    before it was recorded.

    Raises:
        Silo4Error: the file cannot be read, or the arrays have the wrong shapes.
    """
    path = Path(path)
    try:
        _check_member_sizes(path)
        with np.load(path, allow_pickle=False) as npz:
            if not all(name in npz.files for name in RootPose._fields):
                return None
            pose = RootPose(*(np.asarray(npz[name], dtype=float) for name in RootPose._fields))
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile, zlib.error) as exc:
        raise Silo4Error(
            f"{path}: cannot read the root pose ({type(exc).__name__}: {exc})"
        ) from exc
    n = len(pose.position_root_in_world)
    if pose.position_root_in_world.shape != (n, 3) or pose.orientation_root_in_world_xyzw.shape != (
        n,
        4,
    ):
        raise Silo4Error(
            f"{path}: not a valid silo4 trajectory.npz (root pose shapes "
            f"{pose.position_root_in_world.shape}, "
            f"{pose.orientation_root_in_world_xyzw.shape})"
        )
    _check_finite(path, pose._asdict())
    return pose
