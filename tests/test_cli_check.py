"""``silo4 check``: exit 0 when the closed form agrees with Pinocchio, 1 when not,
2 with one clear line (no traceback) on bad input."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from silo4kin import kinematics
from viz.cli.main import main


def test_check_passes_on_silo4(capsys):
    assert main(["check", "--samples", "200"]) == 0
    out = capsys.readouterr().out
    assert "all 32 checks inside tolerance" in out
    for quantity in ("fk", "jacobian", "jdot_qd", "ik", "mass", "coriolis", "gravity", "rnea"):
        assert quantity in out
    assert "42.44 kg" in out


def test_check_passes_on_a_xacro_variant(capsys):
    assert (
        main(["check", "--samples", "100", "--xacro-arg", "L2=0.3", "--xacro-arg", "L3=0.35"]) == 0
    )


def test_check_exits_1_when_the_closed_form_is_wrong(monkeypatch, capsys):
    """A 1 mm error in the closed-form FK is reported as FAIL, exit code 1."""
    original = kinematics.forward_kinematics

    def shifted(leg, q):
        return original(leg, q) + np.array([1e-3, 0.0, 0.0])

    monkeypatch.setattr(kinematics, "forward_kinematics", shifted)
    assert main(["check", "--samples", "50"]) == 1
    out = capsys.readouterr().out
    assert "FAIL" in out and "FAILED" in out


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["check", "--xacro-arg", "L9=0.3"], "unknown xacro argument 'L9'"),
        (["check", "--xacro-arg", "L2=long"], "not a number"),
        (["check", "--xacro-arg", "L2"], "not NAME=VALUE"),
        (["check", "--robot", "/nonexistent/robot.urdf"], "not found"),
        (["check", "--samples", "0"], "--samples 0"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(argv, fragment, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert fragment in err
    assert "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


def test_malformed_robot_file_exit_2(tmp_path: Path, capsys):
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'>")
    assert main(["check", "--robot", str(bad)]) == 2
    assert "malformed" in capsys.readouterr().err


def test_console_script_runs_as_a_module():
    """`python -m viz check` is the same program as the `silo4` console script."""
    res = subprocess.run(
        [sys.executable, "-m", "viz", "check", "--samples", "20"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert res.returncode == 0, res.stderr
    assert "inside tolerance" in res.stdout
