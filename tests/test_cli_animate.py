"""``silo4 animate`` replays a saved run; a trajectory of another robot is refused (exit 2)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from planner.outputs.export import read_trajectory_npz
from viz.cli.main import main

ROBOTS = Path(__file__).resolve().parent / "robots"


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("animate") / "run"
    assert (
        main(
            [
                "plan",
                "--waypoints",
                "0,0.6",
                "--height",
                "0.4",
                "--out",
                str(out),
                "--samples-per-unit",
                "10",
                "--no-plots",
                "--no-html",
            ]
        )
        == 0
    )
    return out


def test_npz_round_trip_is_exact(run_dir: Path):
    """read_trajectory_npz gives back every array of the run, torques included."""
    traj = read_trajectory_npz(run_dir / "trajectory.npz")
    with np.load(run_dir / "trajectory.npz") as npz:
        for name in ("t", "q", "qd", "qdd", "position_foot_in_world", "margin", "tau"):
            assert np.array_equal(getattr(traj, name), npz[name])
    assert traj.joint_names[0] == "LF_hip_yaw" and traj.tau is not None
    assert set(traj.tau_parts) == {"motion", "support"}


def test_animate_writes_the_html(run_dir: Path, capsys):
    out = run_dir.parent / "slow.html"
    assert main(["animate", str(run_dir), "--out", str(out), "--unit-time", "2"]) == 0
    html = out.read_text()
    assert "<html" in html.lower() and len(html) > 100_000
    assert "slow.html" in capsys.readouterr().out


def test_animate_refuses_a_trajectory_of_another_robot(run_dir: Path, tmp_path: Path, capsys):
    """SILO4's run replayed on mantis: its joint names are not mantis's -> exit 2, one line,
    and no file is written."""
    out = tmp_path / "wrong.html"
    code = main(
        ["animate", str(run_dir), "--robot", str(ROBOTS / "mantis.urdf"), "--out", str(out)]
    )
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_animate_a_folder_without_a_run(tmp_path: Path, capsys):
    assert main(["animate", str(tmp_path)]) == 2
    assert "trajectory" in capsys.readouterr().err


def test_a_run_folder_animated_later_can_be_planned_again(tmp_path: Path, capsys):
    """animation.html written by ``silo4 animate`` into a run folder is recorded in its
    manifest: the same ``silo4 plan`` replaces the folder again (before, it refused it as
    holding a file silo4 did not write); a user's own file still stops it."""
    out = tmp_path / "run"
    plan = [
        "plan",
        "--waypoints",
        "0,0.6",
        "--height",
        "0.4",
        "--out",
        str(out),
        "--samples-per-unit",
        "10",
        "--no-plots",
        "--no-html",
    ]
    assert main(plan) == 0
    assert main(["animate", str(out)]) == 0 and (out / "animation.html").is_file()
    assert main(plan) == 0
    (out / "notes.txt").write_text("mine")
    capsys.readouterr()
    assert main(plan) == 2
    assert "notes.txt" in capsys.readouterr().err


def test_animate_keeps_the_runs_own_animation(tmp_path: Path, capsys):
    """``silo4 animate RUN --unit-time S`` writes RUN/animation_<S>s.html and leaves
    RUN/animation.html (the one that matches the CSV and report) as it was; ``--replace``
    rewrites it; ``--replace`` with ``--out`` is refused."""
    out = tmp_path / "run"
    assert (
        main(
            [
                "plan",
                "--waypoints",
                "0,0.6",
                "--height",
                "0.4",
                "--out",
                str(out),
                "--samples-per-unit",
                "10",
                "--no-plots",
            ]
        )
        == 0
    )
    own = (out / "animation.html").read_bytes()
    assert main(["animate", str(out), "--unit-time", "0.5"]) == 0
    assert (out / "animation_0.5s.html").is_file()
    assert (out / "animation.html").read_bytes() == own
    assert "animation_0.5s.html" in capsys.readouterr().out
    assert main(["animate", str(out)]) == 0  # as planned, but animation.html exists
    assert (out / "animation.html").read_bytes() == own
    assert main(["animate", str(out), "--unit-time", "0.5", "--replace"]) == 0
    assert (out / "animation.html").read_bytes() != own
    capsys.readouterr()
    assert main(["animate", str(out), "--replace", "--out", str(tmp_path / "x.html")]) == 2
    assert capsys.readouterr().err.count("\n") == 1
