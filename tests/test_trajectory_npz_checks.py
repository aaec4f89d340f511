"""A hand-edited trajectory.npz is refused with one line before it can do harm: NaN or inf
in the samples, or a member that would decompress to more than any plan within the work
budget (checked from the zip directory, before anything is decompressed)."""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest

from planner.outputs.trajectory_npz import (
    MAX_NPZ_MEMBER_BYTES,
    read_root_pose_npz,
    read_trajectory_npz,
)
from silo4kin.errors import Silo4Error

N = 5  # samples of the small trajectory


def _arrays() -> dict[str, np.ndarray]:
    """A valid trajectory.npz's arrays with N samples."""
    return {
        "t": np.linspace(0.0, 1.0, N),
        "unit_time_s": np.asarray(1.0),
        "position_base_in_world": np.zeros((N, 3)),
        "yaw_base_in_world": np.zeros(N),
        "joint_names": np.array([f"j{i}" for i in range(12)]),
        "q": np.zeros((N, 12)),
        "qd": np.zeros((N, 12)),
        "qdd": np.zeros((N, 12)),
        "position_foot_in_world": np.zeros((N, 4, 3)),
        "contact": np.ones((N, 4), bool),
        "margin": np.full(N, 0.05),
        "phase": np.array(["stand"] * N),
        "position_root_in_world": np.zeros((N, 3)),
        "orientation_root_in_world_xyzw": np.tile([0.0, 0.0, 0.0, 1.0], (N, 1)),
    }


def _write(path: Path, **changes: np.ndarray) -> Path:
    np.savez_compressed(path, **{**_arrays(), **changes})
    return path


def test_a_valid_file_is_read(tmp_path: Path) -> None:
    """The control: the same arrays, unedited, read back."""
    path = _write(tmp_path / "trajectory.npz")
    assert read_trajectory_npz(path).q.shape == (N, 12)
    assert read_root_pose_npz(path) is not None


@pytest.mark.parametrize(
    "name,value",
    [("q", np.nan), ("qd", np.inf), ("t", -np.inf), ("position_root_in_world", np.nan)],
)
def test_nan_or_inf_in_the_samples_is_refused(tmp_path: Path, name: str, value: float) -> None:
    """NaN in q (would reach sim.json), inf in qd (the bag and the goal): refused, named."""
    array = _arrays()[name].copy()
    array.reshape(-1)[-1] = value
    path = _write(tmp_path / "trajectory.npz", **{name: array})
    reader = read_root_pose_npz if name.startswith("position_root") else read_trajectory_npz
    with pytest.raises(Silo4Error, match=f"{name}.*finite numbers only"):
        reader(path)


def test_an_oversized_member_is_refused_before_decompressing(tmp_path: Path) -> None:
    """A member of ours larger than MAX_NPZ_MEMBER_BYTES (zeros deflate ~1000:1) is refused
    from its directory entry; an unknown extra member, however large, is never read."""
    path = _write(tmp_path / "trajectory.npz")
    with zipfile.ZipFile(path, "a", compression=zipfile.ZIP_DEFLATED) as archive:
        with archive.open("huge.npy", "w", force_zip64=True) as member:
            block = bytes(1 << 20)
            for _ in range(MAX_NPZ_MEMBER_BYTES // len(block) + 2):
                member.write(block)
    assert read_trajectory_npz(path).q.shape == (N, 12)  # the extra member is ignored
    with zipfile.ZipFile(path, "a", compression=zipfile.ZIP_DEFLATED) as archive:
        with archive.open("tau_part_gravity.npy", "w", force_zip64=True) as member:
            for _ in range(MAX_NPZ_MEMBER_BYTES // len(block) + 2):
                member.write(block)
    with pytest.raises(Silo4Error, match="tau_part_gravity holds .* bytes uncompressed"):
        read_trajectory_npz(path)
    assert path.stat().st_size < MAX_NPZ_MEMBER_BYTES // 100
