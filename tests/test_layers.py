"""Layers point one way: silo4kin <- planner <- viz; sim and sweep beside viz (sim never
imports viz; sweep may import silo4kin, planner and sim, never viz; neither is imported by
silo4kin or planner) (docs/architecture.md).

Checked on the source text (static imports), so a lazy import inside a function counts too.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
FORBIDDEN = {"silo4kin": {"planner", "viz", "sim", "sweep", "mujoco"},
             "planner": {"viz", "sim", "sweep", "mujoco"},
             "sim": {"viz", "sweep"}, "sweep": {"viz", "mujoco"}, "viz": {"mujoco"}}
#: The planner modules the physics replay may read: the trajectory and run-folder files,
#: never the planner's internals (design.md, round 2).
SIM_MAY_IMPORT_FROM_PLANNER = {"planner.trajectory", "planner.export", "planner.files"}


def _imported_packages(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module.split(".")[0])
    return names


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_lower_layers_do_not_import_higher_ones(package):
    files = sorted((ROOT / package).glob("*.py"))
    assert files
    for path in files:
        bad = _imported_packages(path) & FORBIDDEN[package]
        assert not bad, f"{path.relative_to(ROOT)} imports {sorted(bad)}"


def test_sim_reads_only_trajectories_and_run_folders_from_the_planner():
    for path in sorted((ROOT / "sim").glob("*.py")):
        tree = ast.parse(path.read_text(), filename=str(path))
        modules = {node.module for node in ast.walk(tree)
                   if isinstance(node, ast.ImportFrom) and node.module and node.level == 0}
        modules |= {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import)
                    for alias in node.names}
        planner = {m for m in modules if m.split(".")[0] == "planner"}
        assert planner <= SIM_MAY_IMPORT_FROM_PLANNER, f"{path.name} imports {planner}"


def test_mujoco_is_imported_only_when_asked_for():
    """No module of sim imports mujoco at module level (only inside functions)."""
    for path in sorted((ROOT / "sim").glob("*.py")):
        tree = ast.parse(path.read_text(), filename=str(path))
        top = {alias.name.split(".")[0] for node in tree.body if isinstance(node, ast.Import)
               for alias in node.names}
        top |= {node.module.split(".")[0] for node in tree.body
                if isinstance(node, ast.ImportFrom) and node.module}
        assert "mujoco" not in top, f"{path.name} imports mujoco at module level"
