"""A run leaves nothing it created when it does not finish, and cleans what a killed run
left: temporary siblings of a dead writer, parents made for a nested --out, the aside copy
of a read-only run folder, and a swap a stop signal came during."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from planner.outputs import folder_swap
from planner.outputs.atomic import OutputFolderError
from planner.outputs.folder_swap import replace_folder_atomically
from planner.outputs.leftovers import remove_stale_siblings, sibling_prefix
from planner.outputs.signals import RunInterrupted

ROOT = Path(__file__).resolve().parent.parent


def _dead_pid() -> int:
    """The pid of a process that has ended."""
    child = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        capture_output=True,
        text=True,
        check=True,
    )
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
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([live.name, other.name, "o"])
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


@pytest.mark.parametrize("sig,code", [(signal.SIGHUP, 129), (signal.SIGINT, 130)])
def test_a_stopped_nested_run_leaves_nothing(tmp_path: Path, sig: int, code: int) -> None:
    """SIGHUP (the terminal closed) or SIGINT while ``--out new/deeper/o`` is filled: exit
    128 + signal, one line, and neither the temporary folder nor ``new/`` is left."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "viz",
            "plan",
            "--waypoints",
            "0,1 1,1",
            "--height",
            "0.4",
            "--out",
            "new/deeper/o",
            "--html",
            "--no-plots",
        ],
        cwd=tmp_path,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 600  # a safety net for a stuck child, not a timing bound
    deeper = tmp_path / "new" / "deeper"
    while not (deeper.is_dir() and any(p.name.startswith(".o.tmp-") for p in deeper.iterdir())):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.01)
    proc.send_signal(sig)
    _out, err = proc.communicate()
    assert proc.returncode == code, err
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []
