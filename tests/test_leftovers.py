"""A run leaves nothing it created when it does not finish, and cleans what a killed run
left: temporary siblings of a dead writer, parents made for a nested --out, the aside copy
of a read-only run folder, and a swap a stop signal came during."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from planner.outputs import folder_swap
from planner.outputs.atomic import OutputFolderError
from planner.outputs.folder_swap import replace_folder_atomically
from planner.outputs.leftovers import remove_stale_siblings, sibling_prefix
from planner.outputs.signals import RunInterrupted


def _dead_pid() -> int:
    """The pid of a process that has ended."""
    child = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                           capture_output=True, text=True, check=True)
    return int(child.stdout)


def _fill(tmp: Path) -> None:
    (tmp / "plan.json").write_text("{}\n")


def test_temporaries_of_a_dead_writer_are_removed_on_the_next_run(tmp_path: Path) -> None:
    """``.o.tmp-<dead pid>-*`` and ``.o.old-<dead pid>-*`` go; a live writer's stay, and so
    does an entry not named by sibling_prefix."""
    dead = _dead_pid()
    stale = [tmp_path / f".o.tmp-{dead}-abc", tmp_path / f".o.old-{dead}-def"]
    for folder in stale:
        (folder / "o").mkdir(parents=True)
        (folder / "o" / "q.csv").write_text("1\n")
    live = tmp_path / f"{sibling_prefix(tmp_path / 'o', 'tmp')}xyz"
    live.mkdir()
    other = tmp_path / ".o.tmp-notapid"
    other.mkdir()
    (tmp_path / ".o.lock").write_text("")  # left by SIGKILL: its flock died with the writer
    replace_folder_atomically(tmp_path / "o", _fill)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [live.name, other.name, "o"])
    assert remove_stale_siblings(tmp_path / "o") == []


def test_a_failed_nested_run_removes_the_parents_it_created(tmp_path: Path) -> None:
    """``--out new/deeper/o`` interrupted or out of space: no ``new/`` is left."""
    def fail(tmp: Path) -> None:
        (tmp / "part").write_text("x")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        replace_folder_atomically(tmp_path / "new" / "deeper" / "o", fail)
    assert list(tmp_path.iterdir()) == []

    def full(tmp: Path) -> None:
        raise OSError(28, "No space left on device")

    (tmp_path / "small").mkdir()
    with pytest.raises(OutputFolderError, match="No space left"):
        replace_folder_atomically(tmp_path / "small" / "a" / "b" / "run", full)
    assert [p.name for p in tmp_path.rglob("*")] == ["small"]  # the user's folder stays


def test_replacing_a_read_only_run_folder_leaves_no_aside_copy(tmp_path: Path) -> None:
    """A run folder made read-only is replaced (or refused) without a ``.o.old-*`` left."""
    out = replace_folder_atomically(tmp_path / "o", _fill)
    os.chmod(out, 0o555)
    try:
        replace_folder_atomically(out, _fill)
    except OutputFolderError:
        pass  # not root: the folder cannot be moved; refused, and nothing left
    finally:
        os.chmod(out, 0o755)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o"]


def test_a_stop_during_the_swap_undoes_it(tmp_path: Path, monkeypatch) -> None:
    """A SIGINT held back during the rename: the new folder is taken back, the old one
    restored, RunInterrupted raised."""
    out = replace_folder_atomically(tmp_path / "o", _fill)
    before = (out / "plan.json").read_text()
    monkeypatch.setattr(folder_swap, "_stop_pending", lambda: True)

    def other(tmp: Path) -> None:
        (tmp / "plan.json").write_text('{"other": 1}\n')

    with pytest.raises(RunInterrupted):
        replace_folder_atomically(out, other)
    assert (out / "plan.json").read_text() == before
    with pytest.raises(RunInterrupted):
        replace_folder_atomically(tmp_path / "new", other)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o"]
