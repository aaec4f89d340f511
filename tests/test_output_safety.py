"""The one output-safety rule (planner.outputs.files.check_target, docs/errors.md "What silo4 may
replace"): no silo4 command deletes or overwrites a file it did not write, ``--force`` or
not; an input of a command is never its target; what silo4 wrote it may replace on a rerun.

The refusals of the issue are rows of tests/test_cli_hostile.py (subprocess, one line, every
file byte-identical); here: the rule itself, reruns that must keep working, and a property
test over random command sequences on a tree of user files.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import shutil
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from planner.outputs.files import (
    MANIFEST_NAME,
    OutputFolderError,
    check_target,
    record_written,
    replace_folder_atomically,
    write_atomic,
)
from viz.cli.main import main

TINY = ["--height", "0.4", "--samples-per-unit", "5", "--no-html", "--no-plots", "--no-torques"]


def _run(*argv: str) -> tuple[int, str, str]:
    """``silo4 ARGV`` in this process: exit code, stdout, stderr."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def _hashes(root: Path, names) -> dict[str, str | None]:
    """sha256 of each file (None: missing)."""
    return {
        n: (hashlib.sha256((root / n).read_bytes()).hexdigest() if (root / n).is_file() else None)
        for n in names
    }


def _snapshot(root: Path) -> dict[str, str]:
    """Every entry under ``root``: relative path -> sha256 of a file, or 'dir'."""
    return {
        p.relative_to(root).as_posix(): "dir"
        if p.is_dir()
        else hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
    }


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory) -> Path:
    """A tiny run folder (0.3 m, 5 samples per unit, no HTML, plots or torques), made once."""
    run = tmp_path_factory.mktemp("tiny") / "run"
    code, _, err = _run("plan", "--waypoints", "0,0.3", *TINY, "--out", str(run))
    assert code == 0, err
    return run


# --------------------------------------------------------------------------- the rule


def test_a_new_path_may_always_be_written(tmp_path: Path) -> None:
    assert check_target(tmp_path / "new.txt") == tmp_path / "new.txt"
    assert check_target(tmp_path / "new", folder=True) == tmp_path / "new"
    (tmp_path / "empty").mkdir()
    check_target(tmp_path / "empty", folder=True)  # nothing in it to lose


def test_an_existing_file_only_when_recorded(tmp_path: Path) -> None:
    """A file is silo4's only when the .silo4-files beside it lists it; record_written
    creates that manifest (and adds to one) for files written outside a run folder."""
    mine = tmp_path / "goal.yaml"
    mine.write_text("mine")
    with pytest.raises(OutputFolderError, match="goal.yaml exists and was not written"):
        check_target(mine, what="--goal-yaml")
    with pytest.raises(OutputFolderError, match="not written by silo4"):
        write_atomic(mine, lambda tmp: tmp.write_text("ours"))  # the writer applies it too
    assert mine.read_text() == "mine"
    ours = write_atomic(tmp_path / "ws.png", lambda tmp: tmp.write_text("png"))
    record_written([ours])
    record_written([write_atomic(tmp_path / "b.txt", lambda tmp: tmp.write_text("b"))])
    assert json.loads((tmp_path / MANIFEST_NAME).read_text()) == ["b.txt", "ws.png"]
    write_atomic(ours, lambda tmp: tmp.write_text("png again"))
    with pytest.raises(OutputFolderError):
        check_target(mine)  # still the user's: recording others changed nothing for it


def test_a_folder_only_when_its_manifest_lists_everything(tmp_path: Path) -> None:
    def fill(tmp: Path) -> None:
        (tmp / "a.txt").write_text("a")

    run = replace_folder_atomically(tmp_path / "run", fill)
    check_target(run, folder=True)
    (run / "notes").mkdir()
    (run / "notes" / "n.txt").write_text("mine")
    with pytest.raises(OutputFolderError, match="holds 'notes', which silo4 did not write"):
        check_target(run, folder=True, what="--ros2")
    theirs = tmp_path / "theirs"
    (theirs / "deep").mkdir(parents=True)
    (theirs / "deep" / "x").write_text("x")
    with pytest.raises(OutputFolderError, match="'deep'"):  # named, not walked
        check_target(theirs, folder=True)


def test_an_input_is_never_a_target(tmp_path: Path) -> None:
    """Equal to an input, or a folder holding one: refused even when silo4 wrote it."""

    def fill(tmp: Path) -> None:
        (tmp / "trajectory.npz").write_text("data")

    run = replace_folder_atomically(tmp_path / "run", fill)
    inputs = [run / "trajectory.npz"]
    for target, folder in ((run, True), (run / "trajectory.npz", False), (tmp_path, True)):
        with pytest.raises(OutputFolderError, match="an input of this command"):
            check_target(target, inputs=inputs, folder=folder)
    check_target(run / "animation.html", inputs=inputs)


def test_links_and_the_manifest_are_never_ours(tmp_path: Path) -> None:
    (tmp_path / "real").mkdir()
    os.symlink(tmp_path / "real", tmp_path / "link")
    with pytest.raises(OutputFolderError, match="is a link"):
        check_target(tmp_path / "link", folder=True)
    with pytest.raises(OutputFolderError, match="silo4's list"):
        check_target(tmp_path / MANIFEST_NAME)


# --------------------------------------------------------------------------- reruns


def test_reruns_replace_what_silo4_wrote(tiny_run: Path, tmp_path: Path) -> None:
    """The same export, goal, animation and workspace PNG twice: the second replaces the
    first (recorded in .silo4-files), and a user's file beside them is untouched."""
    run = tmp_path / "run"
    shutil.copytree(tiny_run, run)
    (tmp_path / "notes.txt").write_text("mine")
    bag, goal, html, png = (str(tmp_path / n) for n in ("b.bag", "g.yaml", "a.html", "w.png"))
    for _ in range(2):
        assert _run("export", str(run), "--ros2", bag, "--goal-yaml", goal, "--force")[0] == 0
        assert _run("animate", str(run), "--out", html)[0] == 0
        assert _run("workspace", "--height", "0.4", "--out", png)[0] == 0
    code, _, err = _run("export", str(run), "--ros2", bag)
    assert code == 2 and "--force" in err  # an existing bag still asks for it
    assert (tmp_path / "notes.txt").read_text() == "mine"
    assert sorted(json.loads((tmp_path / MANIFEST_NAME).read_text())) == [
        "a.html",
        "g.yaml",
        "send_goal.py",
        "w.png",
    ]
    assert (Path(bag) / MANIFEST_NAME).is_file()


def test_cases_rerun_replaces_its_results_page(tmp_path: Path) -> None:
    argv = [
        "cases",
        "--out",
        str(tmp_path / "c"),
        "--paths",
        "straight",
        "--heights",
        "0.4",
        "--workspaces",
        "default",
        "--no-ditch",
        "--samples-per-unit",
        "5",
        "--no-torques",
        "--results-md",
        str(tmp_path / "page.md"),
    ]
    assert _run(*argv)[0] == 0
    assert _run(*argv)[0] == 0
    (tmp_path / "page.md").unlink()
    (tmp_path / "page.md").write_text("mine")  # a user's file under silo4's old name
    (tmp_path / MANIFEST_NAME).unlink()  # ... and no record of silo4's
    code, _, err = _run(*argv)
    assert code == 2 and len(err.splitlines()) == 1 and "page.md" in err
    assert (tmp_path / "page.md").read_text() == "mine"


def test_the_docs_pages_are_recorded_as_generated() -> None:
    """docs/.silo4-files lists the generated pages, so the documented commands that
    regenerate them (cases/sweep --results-md docs/...) may replace them."""
    docs = Path(__file__).resolve().parent.parent / "docs"
    for page in ("results.md", "sweep_results.md", "sweep_results_pareto.png"):
        check_target(docs / page, what="--results-md")


# --------------------------------------------------------------------------- property

#: The user's files of the property test's tree (relative path -> content).
USER_FILES = {
    "notes.txt": "my notes\n",
    "mine/thesis.tex": "\\chapter{}\n",
    "run_noted/note.txt": "keep me\n",
    "goal.yaml": "my: goal\n",
    "ws.png": "not really a png\n",
    "page.html": "<p>mine</p>\n",
    "D/results.md": "# my results\n",
}
RUNS = ("run", "run_noted")
#: Targets: user files and folders, silo4's runs and files in them, new names.
TARGETS = (
    "run",
    "run_noted",
    "mine",
    "D",
    ".",
    "notes.txt",
    "mine/thesis.tex",
    "run/plan.json",
    "run/trajectory.npz",
    "run/metrics.json",
    "run_noted/note.txt",
    "goal.yaml",
    "ws.png",
    "page.html",
    "D/results.md",
    "new",
    "new.bag",
    "out.yaml",
    "out.png",
    "run/out.html",
    "mine/out.yaml",
)


@st.composite
def commands(draw) -> list[str]:
    """One cheap silo4 command writing to a drawn target, with or without --force."""
    kind = draw(st.sampled_from(["plan", "ros2", "goal", "animate", "workspace"]))
    target = draw(st.sampled_from(TARGETS))
    run = draw(st.sampled_from(RUNS))
    force = ["--force"] if draw(st.booleans()) else []
    if kind == "plan":
        far = draw(st.sampled_from(["0,0.3", "0,0.6"]))  # the same run, or another one
        return ["plan", "--waypoints", far, *TINY, "--out", f"@{target}", *force]
    if kind == "ros2":
        return ["export", f"@{run}", "--ros2", f"@{target}", *force]
    if kind == "goal":
        return ["export", f"@{run}", "--goal-yaml", f"@{target}"]
    if kind == "animate":
        return ["animate", f"@{run}", "--out", f"@{target}"]
    return ["workspace", "--height", "0.4", "--out", f"@{target}"]


@pytest.fixture(scope="module")
def user_tree(tiny_run: Path, tmp_path_factory) -> Path:
    """A folder as a user has it: two runs (one with a note in it) and files of theirs."""
    root = tmp_path_factory.mktemp("tree")
    for run in RUNS:
        shutil.copytree(tiny_run, root / run)
    for name, text in USER_FILES.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    return root


@settings(
    max_examples=40,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(sequence=st.lists(commands(), min_size=1, max_size=6))
def test_no_user_file_ever_changes(user_tree: Path, sequence: list[list[str]]) -> None:
    """Any sequence of commands, --force or not: every user file byte-identical, every
    refusal one line and exit 2 with nothing changed at all, no temporary folder or lock
    left behind."""
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp) / "tree"
        shutil.copytree(user_tree, root)
        before = _hashes(root, USER_FILES)
        for argv in sequence:
            argv = [str(root / a[1:]) if a.startswith("@") else a for a in argv]
            tree = _snapshot(root)
            code, out, err = _run(*argv)
            assert "Traceback" not in out + err
            assert code in (0, 2), (argv, code, err)
            if code == 2:
                assert len(err.splitlines()) == 1, (argv, err)
                assert _snapshot(root) == tree, (argv, err)  # a refusal changes nothing
            assert _hashes(root, USER_FILES) == before, (argv, out, err)
            left = [
                p.name for p in root.rglob(".*") if ".tmp-" in p.name or p.name.endswith(".lock")
            ]
            assert not left, (argv, left)
