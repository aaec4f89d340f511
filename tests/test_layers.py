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
SIM_MAY_IMPORT_FROM_PLANNER = {"planner.trajectory.samples", "planner.export", "planner.files"}


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


def _relative_imports(path: Path) -> set[str]:
    """Modules of the same package a file imports (``from .x import``, ``from . import x``,
    ``from viz.x import``), lazy imports included."""
    tree = ast.parse(path.read_text(), filename=str(path))
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level == 1 and node.module:
                names.add(node.module.split(".")[0])
            elif node.level == 1:
                names |= {alias.name for alias in node.names}
            elif node.module and node.module.startswith("viz."):
                names.add(node.module.split(".")[1])
    return names


def test_cli_modules_form_a_tree():
    """The CLI's import graph has no cycle (issue 9 item 7): viz/cli.py imports the
    subcommand modules, they import viz/cli_common.py, and nothing imports viz/cli.py."""
    viz = ROOT / "viz"
    graph = {p.stem: _relative_imports(p) & {q.stem for q in viz.glob("*.py")}
             for p in viz.glob("*.py")}
    assert not [m for m, deps in graph.items() if "cli" in deps and m != "__main__"]

    def visit(module: str, stack: tuple[str, ...]) -> None:
        assert module not in stack, " -> ".join(stack + (module,))
        for dep in graph.get(module, ()):
            visit(dep, stack + (module,))

    for module in graph:
        visit(module, ())
