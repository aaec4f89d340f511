"""The wheel carries what runtime needs (issue 13): the SILO4 xacro inside silo4kin/data,
only runtime dependencies, a version. .ci/run installs that wheel into a fresh venv and plans
from an empty folder outside the checkout; this test checks the wheel's content."""

from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
IGNORE = shutil.ignore_patterns(
    ".venv",
    "build",
    "dist",
    "out",
    ".git",
    "*.egg-info",
    "__pycache__",
    ".pytest_cache",
    ".hypothesis",
    ".ruff_cache",
    ".mypy_cache",
)


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """A wheel built from a clean copy of the checkout (pip wheel, build isolation)."""
    tmp = tmp_path_factory.mktemp("wheel")
    shutil.copytree(ROOT, tmp / "src", ignore=IGNORE)
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--quiet",
            "--no-deps",
            "--wheel-dir",
            str(tmp / "dist"),
            str(tmp / "src"),
        ],
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, result.stderr
    (path,) = (tmp / "dist").glob("silo4kin-*.whl")
    return path


def test_wheel_carries_the_silo4_xacro(wheel: Path) -> None:
    """silo4kin/data/silo4.urdf.xacro is in the wheel, byte-identical to urdf/ (its source)."""
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
        assert "silo4kin/data/silo4.urdf.xacro" in names, sorted(names)
        shipped = z.read("silo4kin/data/silo4.urdf.xacro")
    assert shipped == (ROOT / "urdf" / "silo4.urdf.xacro").read_bytes()
    assert {"silo4kin/py.typed", "planner/py.typed", "viz/py.typed"} <= names


def test_wheel_requires_only_runtime_dependencies(wheel: Path) -> None:
    """example-robot-data and yourdfpy (test-only today) are an extra, not a requirement."""
    with zipfile.ZipFile(wheel) as z:
        meta = z.read(next(n for n in z.namelist() if n.endswith("METADATA"))).decode()
    required = [
        line.split(":", 1)[1].strip()
        for line in meta.splitlines()
        if line.startswith("Requires-Dist:") and "extra ==" not in line
    ]
    names = {r.split(">")[0].split("=")[0].split("<")[0].split(";")[0].strip() for r in required}
    # tqdm: progress bars (viz/cli/progress.py); rosbags: silo4 export --ros2 (viz/export/ros2.py);
    # trimesh, pycollada, fast-simplification: meshes over the page budget simplified
    # (viz/animation/mesh_budget.py); pyyaml: terrain files (planner/terrain/terrain_file.py)
    assert names == {
        "pin",
        "numpy",
        "meshcat",
        "xacro",
        "matplotlib",
        "tqdm",
        "rosbags",
        "trimesh",
        "pycollada",
        "fast-simplification",
        "pyyaml",
    }


#: The one module that may import the robots extra, inside a function that turns a missing
#: package into one error line naming what to install (robots by name).
OPTIONAL_IMPORT_GUARDED = {"robot_library.py"}


def test_runtime_code_imports_no_optional_dependency() -> None:
    """No module of silo4kin, planner or viz imports a dependency the wheel does not require,
    except robot_library.py, which imports example-robot-data inside a try/except ImportError
    that says what to install."""
    optional = ("example_robot_data", "yourdfpy")
    for package in ("silo4kin", "planner", "viz"):
        for path in (ROOT / package).glob("*.py"):
            text = path.read_text()
            for name in optional:
                imported = f"import {name}" in text or f"from {name}" in text
                if path.name in OPTIONAL_IMPORT_GUARDED:
                    assert not imported or "except ImportError" in text, path
                else:
                    assert not imported, path


def test_wheel_declares_the_console_script_and_extras(wheel: Path) -> None:
    """``silo4`` is viz.cli.main:main; the robots extra holds the optional dependencies."""
    with zipfile.ZipFile(wheel) as z:
        entry = z.read(next(n for n in z.namelist() if n.endswith("entry_points.txt")))
        meta = z.read(next(n for n in z.namelist() if n.endswith("METADATA"))).decode()
    assert "silo4 = viz.cli.main:main" in entry.decode()
    assert 'Requires-Dist: example-robot-data; extra == "robots"' in meta
    assert 'Requires-Dist: yourdfpy; extra == "robots"' in meta


def test_version_option(capsys) -> None:
    """``silo4 --version`` prints the installed distribution's version and exits 0."""
    from importlib.metadata import version

    from viz.cli.main import main

    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0
    assert capsys.readouterr().out.strip() == f"silo4 (silo4kin) {version('silo4kin')}"
