"""A user's folders named like silo4's packages never run in their place: from a folder that
holds planner/, viz/ and sim/ the command still runs ours (the console script does not put
the current folder on the module path), and where such a folder does come first (PYTHONPATH,
``python -m viz`` from its parent) the command stops with one line naming it."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

SILO4 = Path(sys.executable).with_name("silo4")


def _user_folders(root: Path, names: tuple[str, ...]) -> Path:
    for name in names:
        (root / name).mkdir(parents=True)
        (root / name / "__init__.py").write_text(f'raise RuntimeError("the user\'s own {name}")\n')
    return root


@pytest.fixture
def env() -> dict[str, str]:
    return {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}


@pytest.mark.skipif(
    not SILO4.exists() and shutil.which("silo4") is None,
    reason="the silo4 console script is not installed",
)
def test_the_command_runs_ours_beside_folders_of_the_same_names(tmp_path, env):
    folder = _user_folders(tmp_path, ("planner", "viz", "sim", "sweep", "silo4sim"))
    script = str(SILO4) if SILO4.exists() else str(shutil.which("silo4"))
    proc = subprocess.run(
        [script, "--version"], cwd=folder, env=env, capture_output=True, text=True, check=False
    )
    assert proc.returncode == 0, proc.stderr
    assert "silo4kin" in proc.stdout
    proc = subprocess.run(
        [
            script,
            "plan",
            "--waypoints",
            "0,0.3",
            "--height",
            "0.4",
            "--samples-per-unit",
            "5",
            "--no-html",
            "--no-plots",
            "--out",
            "run",
        ],
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert (folder / "run" / "trajectory.csv").is_file()


def test_a_shadowing_folder_first_on_the_path_stops_the_command_in_one_line(tmp_path, env):
    folder = _user_folders(tmp_path / "mine", ("planner",))
    proc = subprocess.run(
        [sys.executable, "-m", "viz", "--version"],
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert "is not silo4's 'planner' package" in lines[0] and str(folder) in lines[0]
    assert "user's own" not in proc.stderr  # the user's code never ran
