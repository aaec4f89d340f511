"""What a run leaves beside its output folder, and how the next one cleans it.

A folder swap's temporary siblings carry the writer's pid in their names
(``.NAME.tmp-<pid>-XXXX``, ``.NAME.old-<pid>-XXXX``, :func:`sibling_prefix`): a run killed
by SIGKILL or SIGHUP cannot remove them, so the next run into the same folder removes those
whose writer is dead (:func:`remove_stale_siblings`, under the folder lock). The lock file of
a dead run needs nothing: its flock died with the process, the next run takes it and removes
it at the end. Folders a run had to create above its output folder (``--out new/deeper/o``)
are removed again when the run does not finish (:func:`make_parents`, :func:`remove_created`).
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
from pathlib import Path

#: The kinds of temporary sibling a folder swap makes.
KINDS = ("tmp", "old")


def sibling_prefix(out_dir: Path, kind: str) -> str:
    """``.NAME.<kind>-<pid>-``: the name prefix of this process's temporary sibling."""
    return f".{out_dir.name}.{kind}-{os.getpid()}-"


def _alive(pid: int) -> bool:
    """Whether process ``pid`` exists (a process of another user counts as alive)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def remove_stale_siblings(out_dir: Path) -> list[Path]:
    """Remove the temporary siblings of ``out_dir`` whose writer process is dead; returns
    them. Call under the folder lock. Entries not named by :func:`sibling_prefix` are left."""
    pattern = re.compile(rf"^\.{re.escape(out_dir.name)}\.(?:{'|'.join(KINDS)})-(\d+)-")
    removed = []
    try:
        entries = list(out_dir.parent.iterdir())
    except OSError:
        return []
    for entry in entries:
        match = pattern.match(entry.name)
        if match is None or _alive(int(match.group(1))):
            continue
        if entry.is_dir() and not entry.is_symlink():
            _make_writable(entry)
            shutil.rmtree(entry, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                entry.unlink()
        removed.append(entry)
    return removed


def _make_writable(folder: Path) -> None:
    """Give the owner write permission on ``folder`` and its subfolders (a read-only run
    folder moved aside cannot be emptied otherwise)."""
    for root, dirs, _files in os.walk(folder):
        for name in (".", *dirs):
            with contextlib.suppress(OSError):
                path = os.path.join(root, name)
                os.chmod(path, os.stat(path).st_mode | 0o700)


def remove_tree(folder: Path) -> None:
    """``shutil.rmtree`` that also empties read-only subfolders; errors ignored."""
    _make_writable(folder)
    shutil.rmtree(folder, ignore_errors=True)


def make_parents(folder: Path) -> list[Path]:
    """Create the missing parents of ``folder``; returns those created, innermost first
    (for :func:`remove_created`)."""
    missing = []
    parent = folder.parent
    while not parent.exists() and parent != parent.parent:
        missing.append(parent)
        parent = parent.parent
    folder.parent.mkdir(parents=True, exist_ok=True)
    return missing


def remove_created(made: list[Path]) -> None:
    """Remove the folders :func:`make_parents` created, innermost first, while empty."""
    for folder in made:
        try:
            folder.rmdir()
        except OSError:
            break  # not empty (something else wrote there) or gone: leave the rest
