"""Writing outputs so that nothing is ever half-written (docs/design.md, "Outputs").

A file is written under a temporary name in its folder, then renamed (``write_atomic``); a
run folder is filled as a temporary sibling folder, then renamed over the old one
(``replace_folder_atomically``). A reader never sees a partial file, a failure leaves no stray
file, and errors become :class:`OutputFolderError` naming the path.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path

from silo4kin.errors import Silo4Error


class OutputFolderError(Silo4Error):
    """The output folder cannot be written, or holds something we must not replace.

    Attributes:
        path: the offending folder.
    """

    def __init__(self, message: str, path: Path) -> None:
        super().__init__(message)
        self.path = path


def write_atomic(path: str | Path, write: Callable[[Path], object], *,
                 make_parents: bool = False) -> Path:
    """Call ``write(tmp_path)`` for a temporary sibling of ``path``, then rename it to ``path``.

    Args:
        make_parents: create missing parent folders (else a missing folder is an error).

    Raises:
        OutputFolderError: the folder is missing or not writable, or ``path`` is a folder.
    """
    path = Path(path).absolute()
    if path.is_dir():
        raise OutputFolderError(f"cannot write {path}: it is a folder", path)
    try:
        if make_parents:
            path.parent.mkdir(parents=True, exist_ok=True)
        elif not path.parent.is_dir():
            raise OutputFolderError(
                f"cannot write {path}: folder {path.parent} does not exist", path)
        fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise OutputFolderError(f"cannot write {path}: {exc.strerror or exc}", path) from exc
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        write(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except OSError as exc:
        raise OutputFolderError(f"cannot write {path}: {exc.strerror or exc}", path) from exc
    finally:
        tmp.unlink(missing_ok=True)
    return path


def write_text_atomically(path: str | Path, text: str, *, make_parents: bool = True) -> Path:
    """Write UTF-8 text to ``path`` atomically (:func:`write_atomic`)."""
    return write_atomic(path, lambda tmp: tmp.write_text(text, encoding="utf-8"),
                        make_parents=make_parents)


def replace_folder_atomically(out_dir: str | Path, fill: Callable[[Path], None]) -> Path:
    """Create ``out_dir`` by filling a temporary sibling folder and renaming it.

    ``fill(tmp)`` writes the files; if it raises, the temporary folder is removed and any
    existing ``out_dir`` is left exactly as it was. Returns the final folder.
    """
    out_dir = Path(out_dir).absolute()
    parent = out_dir.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.tmp-", dir=parent))
    except OSError as exc:
        raise OutputFolderError(
            f"cannot write output folder {out_dir}: {exc.strerror or exc}", out_dir) from exc
    try:
        fill(tmp)
        old = None
        if out_dir.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.old-", dir=parent))
            os.replace(out_dir, old / out_dir.name)
        try:
            os.replace(tmp, out_dir)
        except OSError:
            if old is not None:  # put the previous run back
                os.replace(old / out_dir.name, out_dir)
                shutil.rmtree(old, ignore_errors=True)
            raise
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except OSError as exc:
        shutil.rmtree(tmp, ignore_errors=True)
        raise OutputFolderError(
            f"cannot write output folder {out_dir}: {exc.strerror or exc}", out_dir) from exc
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out_dir
