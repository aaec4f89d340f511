"""Atomic file writes: a file is written under a temporary name in its folder, then renamed.

A reader never sees a partial file, and a failure or a signal leaves no stray file; errors
become :class:`OutputFolderError` naming the path. Files get the modes the umask gives
(0666 masked), not mkstemp's 0600. :func:`check_output_path` refuses output folder names
that a run may not replace (docs/errors.md). Whether an existing file may be replaced is
planner/outputs/ownership.py's rule.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

from silo4kin.errors import Silo4Error

#: Room kept under the file-name limit for ".<name>.tmp-XXXXXXXX" / ".<name>.lock".
_TEMP_NAME_EXTRA = 16


class OutputFolderError(Silo4Error):
    """The output folder cannot be written, or holds something we must not replace.

    Attributes:
        path: the offending folder.
    """

    def __init__(self, message: str, path: Path) -> None:
        super().__init__(message)
        self.path = path


def current_umask() -> int:
    """The process umask (read by setting and restoring it)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _name_max(folder: Path) -> int:
    try:
        return os.pathconf(folder if folder.is_dir() else "/", "PC_NAME_MAX")
    except (OSError, ValueError):
        return 255


def check_output_path(out: str | Path, *, what: str = "--out") -> Path:
    """The absolute output folder for ``out``, or OutputFolderError saying why it is refused:
    empty, the current folder or one above it, an existing file, or a name too long."""
    text = str(out)
    if not text.strip():
        raise OutputFolderError(f"{what} {text!r}: empty folder name", Path(text))
    path = Path(text).absolute()
    resolved = Path(os.path.realpath(path))
    cwd = Path(os.path.realpath(Path.cwd()))
    if resolved == cwd or resolved in cwd.parents:
        raise OutputFolderError(
            f"{what} {text!r} is the current folder or one above it; a run folder replaces "
            "its target, so name a new folder (e.g. out/run)",
            path,
        )
    for part in path.parts:
        if len(os.fsencode(part)) > _name_max(path.parent) - _TEMP_NAME_EXTRA:
            raise OutputFolderError(
                f"{what}: the name {part[:40]!r}... is {len(os.fsencode(part))} bytes; at most "
                f"{_name_max(path.parent) - _TEMP_NAME_EXTRA} are allowed here",
                path,
            )
    try:
        if path.exists() and not path.is_dir():
            raise OutputFolderError(f"{what} {text!r} is an existing file, not a folder", path)
    except OSError as exc:
        raise OutputFolderError(f"{what} {text!r}: {exc.strerror or exc}", path) from exc
    return path


def write_file_atomically(
    path: str | Path,
    write: Callable[[Path], object],
    *,
    make_parents: bool = False,
    check: Callable[[Path], object] | None = None,
) -> Path:
    """Call ``write(tmp_path)`` for a temporary sibling of ``path``, then rename it to ``path``.

    ``check(path)`` (absolute) runs before anything is created: the ownership rule of
    ``planner.outputs.ownership.write_atomic``; None replaces any file.

    Args:
        make_parents: create missing parent folders (else a missing folder is an error).

    Raises:
        OutputFolderError: the folder is missing or not writable, or ``path`` is a folder.
    """
    import tempfile  # here, not at the top: `silo4 --help` imports the files module

    path = Path(path).absolute()
    try:
        if path.is_dir():
            raise OutputFolderError(f"cannot write {path}: it is a folder", path)
        if check is not None:
            check(path)
        if make_parents:
            path.parent.mkdir(parents=True, exist_ok=True)
        elif not path.parent.is_dir():
            raise OutputFolderError(
                f"cannot write {path}: folder {path.parent} does not exist", path
            )
        fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise OutputFolderError(f"cannot write {path}: {exc.strerror or exc}", path) from exc
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        write(tmp)
        os.chmod(tmp, 0o666 & ~current_umask())
        os.replace(tmp, path)
    except OSError as exc:
        raise OutputFolderError(f"cannot write {path}: {exc.strerror or exc}", path) from exc
    finally:
        tmp.unlink(missing_ok=True)
    return path
