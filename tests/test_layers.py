"""Layers point one way: silo4kin <- planner <- viz (docs/architecture.md).

Checked on the source text (static imports), so a lazy import inside a function counts too.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
FORBIDDEN = {"silo4kin": {"planner", "viz"}, "planner": {"viz"}}


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
