"""Run-folder safety (planner/outputs/files.py, issue 13): never delete a user's file, refuse
dangerous --out values, one writer per folder, cleanup on SIGTERM, modes from the umask."""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from planner.outputs.files import (
    MANIFEST_NAME,
    OutputFolderError,
    check_output_path,
    folder_lock,
    replace_folder_atomically,
    write_atomic,
)

ROOT = Path(__file__).resolve().parent.parent


def _fill(folder: Path) -> None:
    (folder / "a.txt").write_text("a")
    (folder / "sub").mkdir()
    (folder / "sub" / "b.txt").write_text("b")


def test_manifest_lists_what_was_written(tmp_path: Path) -> None:
    """A run folder lists every entry it holds in .silo4-files; re-writing it is allowed."""
    out = replace_folder_atomically(tmp_path / "run", _fill)
    assert (out / MANIFEST_NAME).read_text().strip() == '["a.txt", "sub", "sub/b.txt"]'
    replace_folder_atomically(out, _fill)  # the same files again: fine
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]  # no lock, no temp left


@pytest.mark.parametrize("user_file", ["notes.txt", "sub/notes.txt", ".hidden"])
def test_a_user_file_in_a_run_folder_is_never_deleted(tmp_path: Path, user_file: str) -> None:
    """A file the user added to a run folder (anywhere, hidden too): refused, naming it."""
    out = replace_folder_atomically(tmp_path / "run", _fill)
    (out / user_file).write_text("mine")
    with pytest.raises(OutputFolderError, match=user_file.replace(".", r"\.")):
        replace_folder_atomically(out, _fill)
    assert (out / user_file).read_text() == "mine"


def test_folder_without_manifest_is_foreign(tmp_path: Path) -> None:
    """A non-empty folder silo4 did not write (no manifest) is refused; an empty one is not."""
    (tmp_path / "theirs").mkdir()
    (tmp_path / "theirs" / "data.csv").write_text("1,2")
    with pytest.raises(OutputFolderError, match="data.csv"):
        replace_folder_atomically(tmp_path / "theirs", _fill)
    (tmp_path / "empty").mkdir()
    replace_folder_atomically(tmp_path / "empty", _fill)


@pytest.mark.parametrize(
    "out,fragment",
    [
        ("", "empty folder name"),
        ("  ", "empty folder name"),
        (".", "current folder"),
        ("..", "current folder"),
        ("/", "current folder"),
        ("x/..", "current folder"),
        ("y" * 250, "bytes"),
    ],
)
def test_dangerous_out_values_are_refused(tmp_path: Path, monkeypatch, out, fragment) -> None:
    """Empty, the current folder or above, a name over the file-name limit."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(OutputFolderError, match=fragment):
        check_output_path(out)
    with pytest.raises(OutputFolderError):
        replace_folder_atomically(out, _fill)
    assert list(tmp_path.iterdir()) == []


def test_existing_file_and_symlink_to_cwd_are_refused(tmp_path: Path, monkeypatch) -> None:
    """An existing file, and a link that points at the current folder."""
    monkeypatch.chdir(tmp_path)
    Path("notes.txt").write_text("x")
    os.symlink(tmp_path, "here")
    with pytest.raises(OutputFolderError, match="existing file"):
        check_output_path("notes.txt")
    with pytest.raises(OutputFolderError, match="current folder"):
        check_output_path("here")


def test_second_writer_is_refused_while_the_first_holds_the_lock(tmp_path: Path) -> None:
    """Two runs into one folder at once: the second is refused; the lock file goes away."""
    out = tmp_path / "run"
    with folder_lock(out):
        with pytest.raises(OutputFolderError, match="another silo4 run"):
            replace_folder_atomically(out, _fill)
    assert list(tmp_path.iterdir()) == []
    replace_folder_atomically(out, _fill)


def test_cli_refuses_a_folder_another_run_is_writing(tmp_path: Path) -> None:
    """The CLI, while another process holds the lock: exit 2, nothing written."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    with folder_lock(tmp_path / "run"):
        result = subprocess.run(
            [
                sys.executable,
                "-m",
                "viz",
                "plan",
                "--waypoints",
                "0,0.3",
                "--height",
                "0.4",
                "--out",
                "run",
                "--samples-per-unit",
                "5",
                "--no-html",
                "--no-plots",
            ],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
        )
    assert result.returncode == 2, result.stderr
    assert "another silo4 run" in result.stderr and "Traceback" not in result.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("mask", [0o022, 0o027, 0o077])
def test_modes_follow_the_umask(tmp_path: Path, mask: int) -> None:
    """Folders 0777 and files 0666 less the umask (mkdtemp/mkstemp made them 0700/0600)."""
    old = os.umask(mask)
    try:
        out = replace_folder_atomically(tmp_path / "run", _fill)
        single = write_atomic(tmp_path / "single.txt", lambda p: p.write_text("x"))
    finally:
        os.umask(old)
    assert stat.S_IMODE(out.stat().st_mode) == 0o777 & ~mask
    assert stat.S_IMODE((out / "a.txt").stat().st_mode) == 0o666 & ~mask
    assert stat.S_IMODE(single.stat().st_mode) == 0o666 & ~mask


@pytest.mark.parametrize("sig,code", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_signal_during_the_write_leaves_nothing(tmp_path: Path, sig: int, code: int) -> None:
    """SIGTERM (as SIGINT) while the run folder is being filled: the temporary folder and the
    lock are removed, exit 128 + signal, one line on stderr."""
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
            "run",
            "--html",
            "--plots",
        ],
        cwd=tmp_path,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 600  # a safety net for a stuck child, not a timing bound
    while not any(p.name.startswith(".run.tmp-") for p in tmp_path.iterdir()):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.01)
    proc.send_signal(sig)
    out, err = proc.communicate()
    assert proc.returncode == code, err
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []
