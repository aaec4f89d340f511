"""The house's tooling holds on the whole tree: ruff's format and lint, mypy's types
(pyproject.toml configures all three; the test extra pins their versions)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: Everything that is Python in the repository.
PYTHON_TREES = (
    "silo4kin",
    "planner",
    "viz",
    "silo4sim",
    "silo4sweep",
    "tests",
    "benchmarks",
    "scripts",
    "examples",
    "setup.py",
)


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", *args], cwd=ROOT, capture_output=True, text=True, check=False
    )


def test_ruff_format_leaves_every_file_as_it_is():
    proc = _run("ruff", "format", "--check", *PYTHON_TREES)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_lint_is_clean():
    proc = _run("ruff", "check", *PYTHON_TREES)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_mypy_is_clean_on_the_packages():
    proc = _run("mypy")
    assert proc.returncode == 0, proc.stdout[-5000:] + proc.stderr
