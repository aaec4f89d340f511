"""One writer per output folder: a lock file ``.<name>.lock`` beside it (``fcntl.flock``)
keeps a second run from writing into the same folder at the same time; it is removed when
the run ends."""

from __future__ import annotations

import contextlib
import errno
import os
from collections.abc import Iterator
from pathlib import Path

from planner.outputs.atomic import OutputFolderError, current_umask


@contextlib.contextmanager
def folder_lock(out_dir: Path) -> Iterator[None]:
    """Hold ``.<name>.lock`` beside ``out_dir`` for the block; a second holder is refused."""
    try:
        import fcntl
    except ImportError:  # not POSIX: no lock
        yield
        return
    lock_path = out_dir.parent / f".{out_dir.name}.lock"
    while True:
        try:
            fd = os.open(lock_path, os.O_RDWR | os.O_CREAT, 0o666 & ~current_umask())
        except OSError as exc:
            raise OutputFolderError(
                f"cannot write output folder {out_dir}: {exc.strerror or exc}", out_dir
            ) from exc
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            os.close(fd)
            if exc.errno in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
                raise OutputFolderError(
                    f"another silo4 run is writing {out_dir} right now (lock {lock_path.name}); "
                    "wait for it or choose another folder",
                    out_dir,
                ) from None
            raise
        try:  # the holder before us may have removed the file we opened: lock the new one
            same = os.path.samestat(os.fstat(fd), os.stat(lock_path))
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        yield
    finally:
        with contextlib.suppress(OSError):
            os.unlink(lock_path)
        os.close(fd)
