"""``silo4 cases`` checks every case folder before it writes any."""

from __future__ import annotations

from pathlib import Path

from viz.cli.main import main

FEW = ["--samples-per-unit", "5", "--no-html", "--no-plots", "--no-torques"]
CASES = [
    "cases",
    "--paths",
    "straight",
    "--heights",
    "0.4,0.5",
    "--workspaces",
    "default",
    "--no-ditch",
    *FEW,
]


def test_one_refused_case_folder_writes_no_case_folder(tmp_path: Path, capsys) -> None:
    """The second case's folder holds another run (no --force): exit 2 with one line naming
    it, and the first case's folder is not written either; with --force both are."""
    out = tmp_path / "cases"
    other = out / "straight_h0.5_default"
    assert main(["plan", "--waypoints", "0,0.3", "--height", "0.4", "--out", str(other), *FEW]) == 0
    before = sorted(p.name for p in other.iterdir())
    capsys.readouterr()
    assert main([*CASES, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "holds a different run" in err[0] and str(other) in err[0]
    assert sorted(p.name for p in out.iterdir()) == ["straight_h0.5_default"]
    assert sorted(p.name for p in other.iterdir()) == before
    assert main([*CASES, "--out", str(out), "--force"]) == 0
    assert {"straight_h0.4_default", "straight_h0.5_default", "results.md"} <= {
        p.name for p in out.iterdir()
    }
