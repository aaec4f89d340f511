"""Layers point one way: silo4kin <- planner <- viz; sim and sweep beside viz (sim never
imports viz; sweep may import silo4kin, planner and sim, never viz; neither is imported by
silo4kin or planner); inside the planner, the method's subpackages point one way too
(docs/architecture.md). No import cycle anywhere.

Checked on the source text (static imports), so a lazy import inside a function counts too.
"""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("silo4kin", "planner", "viz", "silo4sim", "silo4sweep")
FORBIDDEN = {
    "silo4kin": {"planner", "viz", "silo4sim", "silo4sweep", "mujoco"},
    "planner": {"viz", "silo4sim", "silo4sweep", "mujoco"},
    "silo4sim": {"viz", "silo4sweep"},
    "silo4sweep": {"viz", "mujoco"},
    "viz": {"mujoco"},
}
#: The planner modules the physics replay may read: the trajectory and run-folder files,
#: never the planner's internals (design.md, round 2).
SIM_MAY_IMPORT_FROM_PLANNER = {
    "planner.trajectory.samples",
    "planner.outputs.export",
    "planner.outputs.files",
}
#: Inside the planner: a subpackage never imports the ones listed for it (the method reads
#: bottom-up: stability and terrain, the workspace, gaits, trajectories, path following, the
#: thesis studies on top).
PLANNER_FORBIDDEN = {
    "planner.stability": {
        "planner.workspace",
        "planner.gaits",
        "planner.path",
        "planner.studies",
        "planner.outputs",
    },
    "planner.terrain": {
        "planner.workspace",
        "planner.gaits",
        "planner.path",
        "planner.studies",
        "planner.outputs",
    },
    "planner.workspace": {"planner.gaits", "planner.path", "planner.studies"},
    "planner.gaits": {"planner.path", "planner.studies", "planner.outputs"},
    "planner.trajectory": {"planner.path", "planner.studies"},
    "planner.path": {"planner.studies"},
    "planner.outputs": {"planner.gaits", "planner.studies"},  # pipeline.py runs plan_path
}


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


@cache
def _modules() -> dict[str, Path]:
    return {_module_name(p): p for package in PACKAGES for p in (ROOT / package).rglob("*.py")}


def _imports(path: Path) -> set[str]:
    """Every module name ``path`` imports, relative imports resolved, lazy ones included."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    own = _module_name(path)
    package = own if path.name == "__init__.py" else own.rpartition(".")[0]
    type_only = {
        id(inner)
        for node in ast.walk(tree)
        if isinstance(node, ast.If)
        and ast.unparse(node.test) in ("TYPE_CHECKING", "typing.TYPE_CHECKING")
        for inner in ast.walk(node)
    }
    modules = _modules()
    names: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in type_only:  # annotations only: never imported at run time
            continue
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            submodules = {f"{module}.{alias.name}" for alias in node.names}
            found = submodules & set(modules)  # from pkg import mod
            names |= found if found else {module}
    return names


def _project_edges(path: Path) -> set[str]:
    """The project's modules ``path`` imports (names that are not modules are dropped)."""
    modules = _modules()
    return {name for name in _imports(path) if name in modules} - {_module_name(path)}


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_lower_layers_do_not_import_higher_ones(package):
    files = sorted((ROOT / package).rglob("*.py"))
    assert files
    for path in files:
        bad = {name.split(".")[0] for name in _imports(path)} & FORBIDDEN[package]
        assert not bad, f"{path.relative_to(ROOT)} imports {sorted(bad)}"


def test_planner_subpackages_point_one_way():
    for module, path in sorted(_modules().items()):
        for sub, forbidden in PLANNER_FORBIDDEN.items():
            if module == sub or module.startswith(sub + "."):
                bad = {
                    m
                    for m in _project_edges(path)
                    if any(m == f or m.startswith(f + ".") for f in forbidden)
                }
                assert not bad, f"{module} imports {sorted(bad)}"


def test_no_import_cycle_anywhere():
    """The import graph of every package (lazy imports included) has no cycle."""
    graph = {module: _project_edges(path) for module, path in _modules().items()}
    # a package's __init__ is reached by importing any of its modules: not an edge of ours
    state: dict[str, int] = {}

    def visit(module: str, stack: list[str]) -> None:
        state[module] = 1
        stack.append(module)
        for dep in sorted(graph[module]):
            if state.get(dep) == 1:
                cycle = stack[stack.index(dep) :] + [dep]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if dep not in state:
                visit(dep, stack)
        stack.pop()
        state[module] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module, [])


def test_the_cycle_check_sees_a_cycle(tmp_path, monkeypatch):
    """The cycle check fails on a two-module cycle (a check that cannot fail is a defect)."""
    (tmp_path / "planner").mkdir()
    (tmp_path / "planner" / "a.py").write_text("from planner.b import x\n")
    (tmp_path / "planner" / "b.py").write_text("def f():\n    from planner import a\n")
    for package in PACKAGES[1:]:
        (tmp_path / package).mkdir(exist_ok=True)
    (tmp_path / "silo4kin").mkdir(exist_ok=True)
    monkeypatch.setattr(__import__(__name__), "ROOT", tmp_path)
    _modules.cache_clear()
    try:
        with pytest.raises(pytest.fail.Exception, match="planner.a -> planner.b -> planner.a"):
            test_no_import_cycle_anywhere()
    finally:
        _modules.cache_clear()


def test_sim_reads_only_trajectories_and_run_folders_from_the_planner():
    for path in sorted((ROOT / "silo4sim").rglob("*.py")):
        planner = {m for m in _imports(path) if m.split(".")[0] == "planner" and m in _modules()}
        assert planner <= SIM_MAY_IMPORT_FROM_PLANNER, f"{path.name} imports {planner}"


def test_mujoco_is_imported_only_when_asked_for():
    """No module of sim imports mujoco at module level (only inside functions)."""
    for path in sorted((ROOT / "silo4sim").rglob("*.py")):
        tree = ast.parse(path.read_text(), filename=str(path))
        top = {
            alias.name.split(".")[0]
            for node in tree.body
            if isinstance(node, ast.Import)
            for alias in node.names
        }
        top |= {
            node.module.split(".")[0]
            for node in tree.body
            if isinstance(node, ast.ImportFrom) and node.module
        }
        assert "mujoco" not in top, f"{path.name} imports mujoco at module level"
