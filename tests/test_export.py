"""Output folder: CSV columns and round trip, npz, JSON, atomic replace, refusing other runs."""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pytest

from planner.outputs.export import (
    CSV_SIGNIFICANT_DIGITS,
    OPTION_DEFAULTS,
    read_trajectory_csv,
    trajectory_columns,
    write_run,
    write_trajectory_csv,
)
from planner.outputs.files import OutputFolderError
from planner.trajectory.samples import LEGS, Trajectory
from silo4kin.errors import Silo4Error

JOINTS = tuple(f"{leg}_{j}" for leg in LEGS for j in ("hip_yaw", "hip_pitch", "knee"))

#: write_run's robot: SILO4, whose URDF root link is its body CoG (the root pose is B_c's).
SILO4 = {"robot_name": "silo4", "position_body_com_in_root": np.zeros(3)}

#: CSV numbers carry CSV_SIGNIFICANT_DIGITS digits: relative error below 10^(1-digits).
CSV_RELATIVE_TOLERANCE = 10.0 ** (1 - CSV_SIGNIFICANT_DIGITS)


@dataclass(frozen=True)
class FakeWorkspace:
    preset: str = "default"
    stride_m: float = 0.3
    swing_height_m: float = 0.1


@dataclass(frozen=True)
class FakeStep:
    kind: str
    leg: str | None
    t_start: float
    t_end: float

    def to_dict(self) -> dict:
        return {"kind": self.kind, "leg": self.leg, "t_start": self.t_start, "t_end": self.t_end}


@dataclass(frozen=True)
class FakePlan:
    """The fields of planner.path.plan_path.Plan that export uses."""

    trajectory: Trajectory
    waypoints_in_world: np.ndarray
    height: float = 0.4
    workspace: FakeWorkspace = FakeWorkspace()
    steps: tuple = (FakeStep("transfer", "RH", 0.0, 1.0), FakeStep("body", None, 1.0, 3.0))
    start_heading: float = np.pi / 2
    tolerance: float | None = None
    stability_threshold: float | None = 0.02


def make_trajectory(n: int = 31, seed: int = 0, with_tau: bool = False) -> Trajectory:
    rng = np.random.default_rng(seed)
    tau = rng.normal(size=(n, 12)) if with_tau else None
    return Trajectory(
        t=np.linspace(0.0, 3.0, n),
        unit_time_s=1.0,
        position_base_in_world=rng.normal(size=(n, 3)),
        yaw_base_in_world=rng.normal(size=n),
        joint_names=JOINTS,
        q=rng.normal(size=(n, 12)),
        qd=rng.normal(size=(n, 12)) * 1e3,
        qdd=rng.normal(size=(n, 12)) * 1e-7,
        position_foot_in_world=rng.normal(size=(n, 4, 3)),
        contact=rng.random((n, 4)) > 0.3,
        margin=rng.normal(size=n),
        phase=np.array(["transfer RH" if k < n // 3 else "body" for k in range(n)]),
        tau=tau,
        tau_parts={"motion": tau} if with_tau else {},
    )


def make_plan(**kw) -> FakePlan:
    traj = kw.pop("trajectory", None) or make_trajectory()
    return FakePlan(trajectory=traj, waypoints_in_world=np.array([[0.0, 1.0], [1.0, 1.0]]), **kw)


METRICS = {
    "normalized_time": 3.0,
    "distance_m": np.float64(0.5),
    "peak_abs_qd": np.ones(12),
    "nan_value": float("nan"),
}


def test_csv_columns_exactly_as_specified(tmp_path: Path) -> None:
    """The header is t, base pose, q/qd/qdd blocks by URDF name, contacts, margin, phase,
    then the feet in the world frame, then the URDF root link's pose (added at the end:
    positions of older columns kept)."""
    files = write_run(tmp_path / "run", make_plan(), METRICS, **SILO4)
    header = files["trajectory.csv"].read_text().splitlines()[0].split(",")
    expected = (
        ["t", "base_x", "base_y", "base_z", "base_yaw"]
        + [f"q_{j}" for j in JOINTS]
        + [f"qd_{j}" for j in JOINTS]
        + [f"qdd_{j}" for j in JOINTS]
        + ["contact_LF", "contact_RF", "contact_LH", "contact_RH", "margin", "phase"]
        + [f"foot_{leg}_{a}" for leg in LEGS for a in "xyz"]
        + ["root_x", "root_y", "root_z", "root_qx", "root_qy", "root_qz", "root_qw"]
    )
    assert header == expected
    assert set(files) == {"trajectory.csv", "trajectory.npz", "plan.json", "metrics.json"}


GO2_JOINTS = tuple(
    f"{leg}_{j}_joint" for leg in ("FL", "FR", "RL", "RR") for j in ("hip", "thigh", "calf")
)


def test_csv_leg_columns_speak_the_robot_s_own_leg_names(tmp_path: Path) -> None:
    """One vocabulary per file: with go2's joint names (FL_hip_joint, ...) the leg columns are
    contact_FL ... foot_RR_z in the planner's leg order; reading the file back gives them
    under the planner's names (contact_LF, foot_LH_x), as for a SILO4 file."""
    traj = replace(make_trajectory(), joint_names=GO2_JOINTS)
    cols = trajectory_columns(traj)
    assert [c for c in cols if c.startswith("contact_")] == [
        "contact_FL",
        "contact_FR",
        "contact_RL",
        "contact_RR",
    ]
    assert cols[-12:-9] == ["foot_FL_x", "foot_FL_y", "foot_FL_z"]
    assert not any(leg in c for c in cols for leg in ("_LF", "_LH", "_RH"))
    path = tmp_path / "trajectory.csv"
    write_trajectory_csv(path, traj)
    table = read_trajectory_csv(path)
    assert "contact_FL" not in table and "q_FL_hip_joint" in table
    for i, leg in enumerate(LEGS):
        np.testing.assert_array_equal(table[f"contact_{leg}"], traj.contact[:, i])
        np.testing.assert_allclose(
            table[f"foot_{leg}_y"],
            traj.position_foot_in_world[:, i, 1],
            rtol=CSV_RELATIVE_TOLERANCE,
            atol=1e-300,
            err_msg=leg,
        )


def test_tau_columns_only_with_torques() -> None:
    """tau_<joint> columns appear after qdd exactly when the trajectory carries torques."""
    cols = trajectory_columns(make_trajectory(with_tau=True))
    assert cols.index(f"tau_{JOINTS[0]}") == cols.index(f"qdd_{JOINTS[-1]}") + 1
    assert not any(c.startswith("tau_") for c in trajectory_columns(make_trajectory()))


def test_csv_and_npz_round_trip(tmp_path: Path) -> None:
    """Reading the CSV back gives the trajectory to 10 digits; the npz gives it exactly."""
    traj = make_trajectory(with_tau=True)
    files = write_run(tmp_path / "run", make_plan(trajectory=traj), METRICS, **SILO4)
    table = read_trajectory_csv(files["trajectory.csv"])
    pairs = {
        "t": traj.t,
        "base_x": traj.position_base_in_world[:, 0],
        "base_z": traj.position_base_in_world[:, 2],
        "base_yaw": traj.yaw_base_in_world,
        "margin": traj.margin,
    }
    for k, j in enumerate(JOINTS):
        pairs[f"q_{j}"], pairs[f"qd_{j}"] = traj.q[:, k], traj.qd[:, k]
        pairs[f"qdd_{j}"], pairs[f"tau_{j}"] = traj.qdd[:, k], traj.tau[:, k]
    for name, want in pairs.items():
        np.testing.assert_allclose(
            table[name], want, rtol=CSV_RELATIVE_TOLERANCE, atol=0, err_msg=name
        )
    for i, leg in enumerate(LEGS):
        np.testing.assert_array_equal(table[f"contact_{leg}"], traj.contact[:, i])
    np.testing.assert_array_equal(table["phase"], traj.phase)
    for i, leg in enumerate(LEGS):
        for a, axis in enumerate("xyz"):
            np.testing.assert_allclose(
                table[f"foot_{leg}_{axis}"],
                traj.position_foot_in_world[:, i, a],
                rtol=CSV_RELATIVE_TOLERANCE,
                atol=1e-300,
                err_msg=leg,
            )

    with np.load(files["trajectory.npz"]) as npz:
        for name in (
            "t",
            "q",
            "qd",
            "qdd",
            "tau",
            "margin",
            "position_foot_in_world",
            "contact",
            "phase",
            "yaw_base_in_world",
            "position_base_in_world",
        ):
            np.testing.assert_array_equal(npz[name], getattr(traj, name), err_msg=name)
        assert tuple(npz["joint_names"]) == JOINTS
        np.testing.assert_array_equal(npz["tau_part_motion"], traj.tau)


def test_json_files_are_strict_json(tmp_path: Path) -> None:
    """plan.json and metrics.json parse as strict JSON (no NaN) and carry the step list."""
    files = write_run(tmp_path / "run", make_plan(), METRICS, **SILO4)

    def strict(text: str) -> dict:
        return json.loads(text, parse_constant=lambda c: pytest.fail(f"non-JSON {c}"))

    plan = strict(files["plan.json"].read_text())
    metrics = strict(files["metrics.json"].read_text())
    assert plan["steps"][0] == {"kind": "transfer", "leg": "RH", "t_start": 0.0, "t_end": 1.0}
    assert plan["inputs"]["waypoints_in_world"] == [[0.0, 1.0], [1.0, 1.0]]
    assert plan["inputs"]["start_heading_deg"] == pytest.approx(90.0, abs=1e-12)
    assert plan["stride_m"] == 0.3 and plan["workspace"]["preset"] == "default"
    assert metrics["nan_value"] is None and len(metrics["peak_abs_qd"]) == 12


def _boom(folder: Path) -> None:
    (folder / "half.html").write_text("partial")
    raise RuntimeError("writer failed")


def test_failing_writer_leaves_no_folder(tmp_path: Path) -> None:
    """An error in any writer leaves neither the output folder nor a temporary folder."""
    with pytest.raises(RuntimeError):
        write_run(tmp_path / "run", make_plan(), METRICS, **SILO4, extra_writers=[_boom])
    assert list(tmp_path.iterdir()) == []


def test_failing_writer_keeps_old_run_intact(tmp_path: Path) -> None:
    """Re-running into an existing run folder and failing leaves the old files byte-identical."""
    out = tmp_path / "run"
    write_run(out, make_plan(), METRICS, **SILO4)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    with pytest.raises(RuntimeError):
        write_run(out, make_plan(), METRICS, **SILO4, extra_writers=[_boom])
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert [p.name for p in tmp_path.iterdir()] == ["run"]


def test_extra_writer_output_lands_in_folder(tmp_path: Path) -> None:
    """Files an extra writer creates in the temporary folder end up in the run folder."""
    files = write_run(
        tmp_path / "run",
        make_plan(),
        METRICS,
        **SILO4,
        write_csv=False,
        extra_writers=[lambda d: (d / "animation.html").write_text("<html/>")],
    )
    assert files["animation.html"].read_text() == "<html/>"
    assert "trajectory.csv" not in files


def test_same_run_is_replaced_different_run_needs_force(tmp_path: Path) -> None:
    """The same inputs overwrite silently; other inputs are refused unless force=True."""
    out = tmp_path / "run"
    write_run(out, make_plan(), METRICS, **SILO4)
    write_run(out, make_plan(), {"distance_m": 2.0}, **SILO4)
    assert json.loads((out / "metrics.json").read_text()) == {"distance_m": 2.0}
    other = make_plan(height=0.2)
    with pytest.raises(OutputFolderError, match="different run"):
        write_run(out, other, METRICS, **SILO4)
    assert json.loads((out / "plan.json").read_text())["height_m"] == 0.4
    write_run(out, other, METRICS, **SILO4, force=True)
    assert json.loads((out / "plan.json").read_text())["height_m"] == 0.2


def test_recorded_options_tell_runs_apart(tmp_path: Path) -> None:
    """The same plan with another requested gait is another run; the options are recorded in
    plan.json "inputs", each missing one at its default."""
    out = tmp_path / "run"
    write_run(out, make_plan(), METRICS, **SILO4, options={"gait": "creep"})
    inputs = json.loads((out / "plan.json").read_text())["inputs"]
    assert inputs["gait"] == "creep" and inputs["face_path"] is False
    assert inputs["height_auto"] is False
    write_run(out, make_plan(), METRICS, **SILO4, options={"gait": "creep"})
    for options in ({"gait": "crawl"}, None, {"gait": "creep", "swing_height_request_m": 0.1}):
        with pytest.raises(OutputFolderError, match="different run"):
            write_run(out, make_plan(), METRICS, **SILO4, options=options)
    write_run(out, make_plan(), METRICS, **SILO4, options={"gait": "crawl"}, force=True)
    assert json.loads((out / "plan.json").read_text())["inputs"]["gait"] == "crawl"


def test_old_plan_json_without_options_reads_as_defaults(tmp_path: Path) -> None:
    """A plan.json written before the options were recorded (no such keys in "inputs") is the
    same run as the defaults, and a different run from any other request."""
    out = tmp_path / "run"
    write_run(out, make_plan(), METRICS, **SILO4)
    document = json.loads((out / "plan.json").read_text())
    for key in (*OPTION_DEFAULTS, "height_auto"):
        del document["inputs"][key]
    (out / "plan.json").write_text(json.dumps(document))
    with pytest.raises(OutputFolderError, match="different run"):
        write_run(out, make_plan(), METRICS, **SILO4, options={"face_path": True})
    write_run(out, make_plan(), METRICS, **SILO4, options=dict(OPTION_DEFAULTS))
    assert json.loads((out / "plan.json").read_text())["inputs"]["gait"] == "auto"


def test_height_auto_is_part_of_the_run(tmp_path: Path) -> None:
    """A plan whose height was searched (``height="auto"``) is not the run at that height."""
    out = tmp_path / "run"
    write_run(out, make_plan(), METRICS, **SILO4)

    @dataclass(frozen=True)
    class SearchedPlan(FakePlan):
        height_search: dict | None = None

    searched = SearchedPlan(
        trajectory=make_trajectory(),
        waypoints_in_world=np.array([[0.0, 1.0], [1.0, 1.0]]),
        height_search={"n_evaluated": 3},
    )
    with pytest.raises(OutputFolderError, match="different run"):
        write_run(out, searched, METRICS, **SILO4)
    write_run(out, searched, METRICS, **SILO4, force=True)
    assert json.loads((out / "plan.json").read_text())["inputs"]["height_auto"] is True


def test_unknown_option_is_refused(tmp_path: Path) -> None:
    """An option key write_run does not know is an error naming the known ones."""
    with pytest.raises(Silo4Error, match="unknown run options.*gait"):
        write_run(tmp_path / "run", make_plan(), METRICS, **SILO4, options={"gaitt": "creep"})
    assert not (tmp_path / "run").exists()


def test_foreign_folder_is_never_replaced(tmp_path: Path) -> None:
    """A non-empty folder without our plan.json is refused, even with force."""
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("precious")
    for force in (False, True):
        with pytest.raises(OutputFolderError, match="not a silo4 run folder"):
            write_run(out, make_plan(), METRICS, **SILO4, force=force)
    assert (out / "thesis.tex").read_text() == "precious"


def test_unwritable_folder_names_the_path(tmp_path: Path) -> None:
    """A folder that cannot be created gives a Silo4Error naming the path."""
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(Silo4Error, match=str(blocker)):
        write_run(blocker / "run", make_plan(), METRICS, **SILO4)
    with pytest.raises(OutputFolderError, match="not a folder"):
        write_run(blocker, replace(make_plan()), METRICS, **SILO4)


def test_npz_stores_what_does_not_deflate_and_reads_back_exactly(tmp_path: Path) -> None:
    """trajectory.npz deflates an array only when deflating its start saves >= 20 %: noise-like
    doubles are stored, smooth and repetitive arrays deflated; np.load and
    read_trajectory_npz give every array back exactly, 0-d unit_time_s included."""
    import zipfile

    from planner.outputs.export import read_trajectory_npz, write_trajectory_npz

    traj = make_trajectory(with_tau=True)
    n = len(traj.t)
    noisy = np.random.default_rng(3).normal(size=(n, 12))
    traj = replace(traj, tau=noisy, q=np.zeros((n, 12)))
    path = tmp_path / "trajectory.npz"
    write_trajectory_npz(path, traj)
    with zipfile.ZipFile(path) as archive:
        kinds = {i.filename: i.compress_type for i in archive.infolist()}
    assert kinds["tau.npy"] == zipfile.ZIP_STORED
    assert kinds["q.npy"] == kinds["phase.npy"] == zipfile.ZIP_DEFLATED
    back = read_trajectory_npz(path)
    for name in ("t", "q", "tau", "margin", "phase", "contact", "position_foot_in_world"):
        np.testing.assert_array_equal(getattr(back, name), getattr(traj, name), err_msg=name)
    with np.load(path) as npz:
        assert npz["unit_time_s"].shape == () and npz["tau"].dtype == np.float64
