"""Physics as the referee (issue 10): the thesis cases walk in MuJoCo, an unstable plan falls,
and ``silo4 simulate`` / ``silo4 plan --simulate`` write sim.json and exit 0/1/2.

Each replay runs once per session (module fixtures); assertions read the sim.json figures.
Plans carry full-load torques (``--load total``: body and legs, issue 9), the feed-forward
that makes the replay hold.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from planner.gaits.builder import OverBudget
from planner.path.plan_path import plan_path
from planner.studies.cases import thesis_cases
from planner.trajectory.torques import add_torques
from silo4kin import load_robot
from silo4sim.run import simulate, write_sim_outputs
from viz.cli.main import main

pytest.importorskip("mujoco")
WALKING_CASES = (
    "straight_h0.2_default",
    "straight_h0.4_default",
    "straight_h0.6_default",
    "circle_h0.4_default",
)


def _case_trajectory(robot, name: str, load: str):  # noqa: ANN001, ANN202
    case = {c.name: c for c in thesis_cases()}[name]
    plan = plan_path(
        robot,
        case.waypoints_in_world,
        case.height_m,
        start_heading=case.start_heading_rad,
        workspace=case.workspace,
        tolerance=case.tolerance_m,
    )
    return add_torques(robot, plan.trajectory, load=load)


def _sim_json(result, folder: Path) -> dict:  # noqa: ANN001
    """Write the run's sim files and read sim.json back (what a user gets)."""
    folder.mkdir(parents=True)
    write_sim_outputs(folder, result)
    return json.loads((folder / "sim.json").read_text())


@pytest.fixture(scope="module")
def silo4_results(silo4, tmp_path_factory) -> dict[str, dict]:
    """sim.json documents of the four walking cases and the unstable thesis-preset plan."""
    root = tmp_path_factory.mktemp("sim_cases")
    out = {
        name: _sim_json(simulate(silo4, _case_trajectory(silo4, name, "total")), root / name)
        for name in WALKING_CASES
    }
    # The thesis preset has zero stability margin and its torques carry the body only:
    # at h = 0.6 it tips over (docs/physics.md).
    name = "straight_h0.6_thesis"
    out[name] = _sim_json(simulate(silo4, _case_trajectory(silo4, name, "body")), root / name)
    return out


@pytest.mark.parametrize("name", WALKING_CASES)
def test_silo4_thesis_cases_walk(silo4_results, name):
    """0 falls, CoG drift <= 20 mm, slip <= 5 mm, yaw <= 5 deg, no non-foot contact."""
    doc = silo4_results[name]
    assert doc["calibration"]["ok"] and doc["calibration"]["base_drift_m"] < 1e-3
    assert doc["falls"] == 0 and not doc["fell"]
    assert doc["drift_max_m"] <= 0.020
    assert doc["slip_max_m"] <= 0.005
    assert doc["yaw_error_max_deg"] <= 5.0
    assert doc["non_foot_contacts"] == {}
    assert doc["walks"] and doc["reasons"] == []
    assert doc["simulated_s"] >= doc["plan_duration_s"]
    # the servos track: joint error small, torques close to the plan's feed-forward
    assert max(doc["joint_tracking_max_deg"].values()) < 2.0
    # Load-bearing joints (hip pitch, knee) follow the plan's feed-forward within 20 % of the
    # largest peak. Hip yaw is judged against its effort limit only: the planned torques carry
    # vertical support reactions (eq A.30-A.33), while in physics a fast swing (the default's
    # spin swings reach 10 rad/s, 68 rad/s^2 in hip yaw) pushes the body and the stance feet's
    # friction loads the stance hips' yaw (measured: 12 N m on LH at t = 111.5 s of the
    # straight h = 0.4 case against 1.7 N m planned; docs/physics.md).
    sim_peaks, plan_peaks = doc["torque_peak_sim_nm"], doc["torque_peak_plan_nm"]
    loaded = [j for j in plan_peaks if not j.endswith("hip_yaw")]
    peak_sim = np.array([sim_peaks[j] for j in loaded])
    peak_plan = np.array([plan_peaks[j] for j in loaded])
    assert np.all(np.abs(peak_sim - peak_plan) < 0.2 * peak_plan.max())
    assert max(sim_peaks[j] for j in plan_peaks if j.endswith("hip_yaw")) < 60.0


def test_thesis_preset_at_h06_falls(silo4_results):
    """The deliberately unstable plan (margin 0, body-only torques) is reported falling."""
    doc = silo4_results["straight_h0.6_thesis"]
    assert doc["fell"] and doc["falls"] == 1 and not doc["walks"]
    assert doc["max_tilt_deg"] > 20.0
    assert doc["simulated_s"] < doc["plan_duration_s"]  # stopped after the fall
    assert any("fell" in r for r in doc["reasons"])


def test_mantis_walks(mantis, tmp_path):
    """Another robot (other names, mirrored axes, off-centre CoG) walks its plan."""
    robot = mantis
    plan = plan_path(robot, np.array([[0.0, 1.0], [1.0, 1.0]]), 0.4, start_heading=np.pi / 2)
    doc = _sim_json(
        simulate(robot, add_torques(robot, plan.trajectory, load="total")), tmp_path / "mantis"
    )
    assert doc["calibration"]["ok"]
    assert doc["falls"] == 0 and doc["drift_max_m"] <= 0.020 and doc["slip_max_m"] <= 0.005
    assert doc["non_foot_contacts"] == {} and doc["walks"]


# --------------------------------------------------------------------------- CLI


@pytest.fixture(scope="module")
def short_run(tmp_path_factory) -> tuple[Path, int]:
    """``silo4 plan --simulate`` on a short walk (0.6 m ahead)."""
    out = tmp_path_factory.mktemp("sim") / "run"
    code = main(
        [
            "plan",
            "--waypoints",
            "0,0.6",
            "--height",
            "0.4",
            "--load",
            "total",
            "--out",
            str(out),
            "--simulate",
            "--no-plots",
            "--no-html",
        ]
    )
    return out, code


def test_plan_simulate_writes_sim_files(short_run):
    out, code = short_run
    assert code == 0
    doc = json.loads((out / "sim.json").read_text())
    assert doc["walks"] and doc["falls"] == 0 and doc["drift_max_m"] <= 0.020
    with np.load(out / "sim.npz") as npz:
        assert npz["q"].shape[1] == 12 and npz["position_foot_in_world"].shape[1:] == (4, 3)
        assert npz["t"][-1] == pytest.approx(doc["plan_duration_s"], abs=0.011)
    import mujoco

    model = mujoco.MjModel.from_xml_string((out / "model.xml").read_text())
    assert (model.nq, model.nu, model.opt.timestep) == (19, 12, 0.001)


def test_simulate_writes_html_plots_and_honours_thresholds(short_run, capsys):
    """``silo4 simulate RUN --max-drift 0.01``: the same replay now fails (exit 1) with the
    drift named in sim.json; sim.html and the plots are written."""
    out, _ = short_run
    assert main(["simulate", str(out), "--max-drift", "0.01"]) == 1
    doc = json.loads((out / "sim.json").read_text())
    assert not doc["walks"] and doc["thresholds"]["drift_m"] == pytest.approx(1e-5)
    assert any("drift" in r for r in doc["reasons"])
    assert "DOES NOT WALK" in capsys.readouterr().out
    html = (out / "sim.html").read_text()
    assert "<html" in html.lower() and len(html) > 100_000
    assert (out / "sim_drift.png").stat().st_size > 10_000
    assert (out / "sim_slip.png").stat().st_size > 10_000


def test_simulate_a_folder_without_a_trajectory(tmp_path, capsys):
    assert main(["simulate", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "trajectory.npz" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "sim.json").exists()


def test_simulate_without_mujoco(short_run, monkeypatch, capsys):
    """A missing mujoco package: one line naming it, exit 2, nothing written."""
    out, _ = short_run
    before = (out / "sim.json").stat().st_mtime_ns
    monkeypatch.setitem(sys.modules, "mujoco", None)
    assert main(["simulate", str(out)]) == 2
    err = capsys.readouterr().err
    assert "mujoco" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert (out / "sim.json").stat().st_mtime_ns == before


def test_simulate_bad_threshold(short_run, capsys):
    out, _ = short_run
    assert main(["simulate", str(out), "--max-slip", "-1"]) == 2
    assert "--max-slip" in capsys.readouterr().err


def test_cases_simulate_adds_the_physics_section(tmp_path):
    """``silo4 cases --simulate`` on one case: its folder gets sim.json and the results
    page a physics row with the same verdict and drift. At the default 100 samples per unit,
    as docs/results.md is made (at 20 this plan's replay slips 5.3 mm: the feed-forward
    between 50 ms samples; noted in docs/physics.md)."""
    out = tmp_path / "cases"
    code = main(
        [
            "cases",
            "--out",
            str(out),
            "--paths",
            "straight",
            "--heights",
            "0.4",
            "--workspaces",
            "default",
            "--no-ditch",
            "--simulate",
        ]
    )
    assert code == 0
    doc = json.loads((out / "straight_h0.4_default" / "sim.json").read_text())
    page = (out / "results.md").read_text()
    assert "## Physics replay (MuJoCo)" in page and "--simulate" in page
    row = next(line for line in page.splitlines() if line.startswith("| straight | default"))
    assert ("**walks**" in row) == doc["walks"] and doc["walks"]
    assert f"{1e3 * doc['drift_max_m']:.1f} / " in row


@pytest.mark.parametrize("effort", [100.0, 60.0])
def test_xacro_variant_walks_with_its_joints(effort):
    """SILO4 with longer legs (L2 0.3, L3 0.35, hips 0.25 m out) facing the path needed 73 N m
    of hip pitch: with 100 N m joints it walks. With the default 60 N m joints no shift of
    its spin at (1, 1), in any leg order, keeps the stance legs within their budget (0.85 of
    the effort, 51 N m; RH_hip_pitch needs 68.4 N m standing still where the search gets
    nearest): the planner refuses it naming the joint (OverBudget, planner/gaits/load_caps.py
    and creep_spin.py). Before the spin kept the budget it planned this path, peaking at
    68.8 N m, and walked in the simulation with the servos past their budget."""
    robot = load_robot(xacro_args={"L2": 0.3, "L3": 0.35, "Lb": 0.25, "joint_effort": effort})
    waypoints = np.array([[0.0, 1.0], [1.0, 1.0]])
    if effort == 60.0:
        with pytest.raises(OverBudget, match=r"joint RH_hip_pitch needs .* N m standing still"):
            plan_path(robot, waypoints, 0.4, start_heading=np.pi / 2, face_path=True)
        return
    plan = plan_path(robot, waypoints, 0.4, start_heading=np.pi / 2, face_path=True)
    traj = add_torques(robot, plan.trajectory, load="total")
    doc = simulate(robot, traj).metrics
    assert np.abs(traj.tau).max() > 60.0
    assert doc["walks"], doc["reasons"]
    assert doc["drift_max_m"] <= 0.020
    assert sum(doc["effort_limit_s"].values()) == 0


def test_a_simulated_run_folder_can_be_planned_again(short_run, capsys):
    """sim.json, sim.npz and model.xml are recorded in the run folder's manifest: the same
    ``silo4 plan --simulate`` replaces the folder (it refused it before: "holds 'model.xml'
    ..., which silo4 did not write")."""
    out, code = short_run
    assert code == 0
    code = main(
        [
            "plan",
            "--waypoints",
            "0,0.6",
            "--height",
            "0.4",
            "--load",
            "total",
            "--out",
            str(out),
            "--simulate",
            "--no-plots",
            "--no-html",
        ]
    )
    assert code == 0, capsys.readouterr().err
    assert (out / "sim.json").is_file()
