"""Writing outputs so that nothing is ever half-written and no user file is ever deleted.

A file is written under a temporary name in its folder, then renamed (``write_atomic``); a
run folder is filled as a temporary sibling folder, then renamed over the old one
(``replace_folder_atomically``). A reader never sees a partial file, a failure or a signal
(SIGINT, or SIGTERM turned into an exception by the CLI) leaves no stray file, and errors
become :class:`OutputFolderError` naming the path.

Run-folder safety (docs/errors.md):

- the folder is never the current folder or one above it, never an existing file, never an
  empty name, and its name leaves room for our temporary sibling under NAME_MAX;
- every run folder lists the files we wrote in ``.silo4-files``; an existing folder is
  replaced only when everything in it is on that list (a file the user added is named and
  the run refused, with or without ``--force``);
- a lock file ``.<name>.lock`` beside the folder (``fcntl.flock``) keeps a second run from
  writing into the same folder at the same time; it is removed when the run ends;
- files and folders get the modes the umask gives (0666 / 0777 masked), not mkstemp's 0600.

The one output-safety rule (:func:`check_target`, docs/errors.md "What silo4 may replace"),
for every file and folder any subcommand writes: a new path is fine; an existing one may be
replaced only when everything that would be removed or overwritten was written by silo4 (a
file listed in the ``.silo4-files`` beside it, a folder whose own ``.silo4-files`` lists
everything in it); an input of the same command is never a target; a link is never ours.
Files written outside a run folder are recorded in a ``.silo4-files`` of their folder
(:func:`record_written`), so the same command can replace them on a rerun. ``write_atomic``
applies the ownership half itself, so no writer can overwrite a file silo4 did not write.
"""

from __future__ import annotations

import contextlib
import errno
import os
import signal
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path

from silo4kin.errors import Silo4Error

#: The list of files a run folder holds, written last into it (hidden).
MANIFEST_NAME = ".silo4-files"
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


class RunInterrupted(BaseException):  # noqa: N818 (like KeyboardInterrupt, not an error)
    """A signal asked the run to stop (the CLI raises it from its SIGTERM handler)."""


_stop_requested = False


def request_stop() -> None:
    """Record that a signal asked the run to stop. Checked again just before a run folder is
    swapped into place, so the request holds even if library code swallowed the exception
    the signal handler raised."""
    global _stop_requested
    _stop_requested = True


def stop_requested() -> bool:
    """Whether :func:`request_stop` was called in this process."""
    return _stop_requested


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
            "its target, so name a new folder (e.g. out/run)", path)
    for part in path.parts:
        if len(os.fsencode(part)) > _name_max(path.parent) - _TEMP_NAME_EXTRA:
            raise OutputFolderError(
                f"{what}: the name {part[:40]!r}... is {len(os.fsencode(part))} bytes; at most "
                f"{_name_max(path.parent) - _TEMP_NAME_EXTRA} are allowed here", path)
    try:
        if path.exists() and not path.is_dir():
            raise OutputFolderError(f"{what} {text!r} is an existing file, not a folder", path)
    except OSError as exc:
        raise OutputFolderError(f"{what} {text!r}: {exc.strerror or exc}", path) from exc
    return path


def write_atomic(path: str | Path, write: Callable[[Path], object], *,
                 make_parents: bool = False) -> Path:
    """Call ``write(tmp_path)`` for a temporary sibling of ``path``, then rename it to ``path``.

    An existing ``path`` is replaced only when silo4 wrote it (:func:`check_target`).

    Args:
        make_parents: create missing parent folders (else a missing folder is an error).

    Raises:
        OutputFolderError: the folder is missing or not writable, ``path`` is a folder, or
            ``path`` exists and was not written by silo4.
    """
    return _write_atomic(path, write, make_parents=make_parents, check=True)


def _write_atomic(path: str | Path, write: Callable[[Path], object], *,
                  make_parents: bool, check: bool) -> Path:
    import tempfile  # here, not at the top: `silo4 --help` imports this module (issue 14)

    path = Path(path).absolute()
    try:
        if path.is_dir():
            raise OutputFolderError(f"cannot write {path}: it is a folder", path)
        if check:
            check_target(path)
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
        os.chmod(tmp, 0o666 & ~current_umask())
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


# --------------------------------------------------------------------------- run folders


def _listing(folder: Path) -> list[str]:
    """Every file and folder under ``folder``, as sorted relative POSIX paths (the manifest
    itself left out: it is not one of the files it lists)."""
    return sorted(rel for rel in (p.relative_to(folder).as_posix() for p in folder.rglob("*"))
                  if rel != MANIFEST_NAME)


def _manifest_names(folder: Path) -> set[str] | None:
    """The entries a folder's ``.silo4-files`` lists, or None without a readable one."""
    import json

    try:
        listed = json.loads((folder / MANIFEST_NAME).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(listed, list) or not all(isinstance(n, str) for n in listed):
        return None
    return set(listed)


def record_written(paths: list[Path]) -> None:
    """Record files silo4 wrote in the ``.silo4-files`` of their folder, creating it where
    there is none (a goal YAML beside a user's files, a workspace PNG, a results page), so
    the same command may replace them on a rerun (:func:`check_target`). A manifest that
    cannot be read is left alone (the file then stays unreplaceable, the safe side)."""
    import json

    for path in paths:
        path = Path(path).absolute()
        if path.name == MANIFEST_NAME:
            continue
        manifest = path.parent / MANIFEST_NAME
        if os.path.lexists(manifest):
            listed = _manifest_names(path.parent)
            if listed is None or path.name in listed:
                continue
        else:
            listed = set()
        names = sorted({*listed, path.name})

        def write(tmp: Path, names: list[str] = names) -> None:
            tmp.write_text(json.dumps(names) + "\n", encoding="utf-8")

        _write_atomic(manifest, write, make_parents=False, check=False)


def record_in_run_folder(paths: list[Path]) -> None:
    """Former name of :func:`record_written` (which also records outside run folders)."""
    record_written(paths)


def foreign_files(folder: Path) -> list[str]:
    """Entries of an existing folder that its manifest does not list (a user's files), as
    sorted relative POSIX paths; a foreign folder is named, not walked (all it holds is
    foreign too). A folder without a manifest has no entry of ours: its top-level entries
    are returned, without walking it (``--ros2 /usr`` must not read the whole disk).
    """
    listed = _manifest_names(folder)
    if listed is None:
        with os.scandir(folder) as entries:
            return sorted(entry.name for entry in entries)
    foreign: list[str] = []
    stack = [""]
    while stack:
        rel = stack.pop()
        with os.scandir(folder / rel if rel else folder) as entries:
            for entry in entries:
                name = f"{rel}/{entry.name}" if rel else entry.name
                if name == MANIFEST_NAME:
                    continue
                if name not in listed:
                    foreign.append(name)
                elif entry.is_dir(follow_symlinks=False):
                    stack.append(name)
    return sorted(foreign)


def check_replaceable(out_dir: Path) -> None:
    """Refuse to replace a folder holding entries silo4 did not write, naming the first
    (:func:`check_target` for a folder)."""
    check_target(out_dir, folder=True, what="output folder")


def check_target(path: str | Path, *, inputs: Iterable[str | Path] = (), what: str = "output",
                 folder: bool = False) -> Path:
    """The one output-safety rule: may ``path`` be written? Returns it, or raises
    OutputFolderError (one line naming the file) without touching anything.

    - a path that does not exist yet may always be written;
    - an input of the same command (``inputs``: the files it reads; a run's data files) is
      never a target, nor is a folder holding one (replacing it would delete the input);
    - an existing file may be overwritten only when the ``.silo4-files`` beside it lists it
      (silo4 wrote it); the manifest itself and a link never;
    - an existing folder (``folder=True``: the target is replaced whole) only when its own
      ``.silo4-files`` lists everything in it; an empty folder holds nothing to lose.

    ``--force`` never relaxes this: it only lets a command replace silo4's own output made
    with other inputs (another run), which each command checks itself.

    Args:
        path: the file (or, with ``folder``, the folder) to be written.
        inputs: paths the command reads.
        what: how the message names the target (``--out``, ``--goal-yaml``, ...).
        folder: the target is a folder replaced as a whole.
    """
    path = Path(path)
    shown = str(path)
    if path.name == MANIFEST_NAME:
        raise OutputFolderError(
            f"{what} {shown}: {MANIFEST_NAME} is silo4's list of the files it wrote; choose "
            "another name", path)
    real = os.path.realpath(path)
    for item in inputs:
        real_input = os.path.realpath(item)
        if real_input == real or real_input.startswith(real.rstrip(os.sep) + os.sep):
            raise OutputFolderError(
                f"{what} {shown} would replace {item}, an input of this command; choose "
                "another path", path)
    try:
        if not os.path.lexists(path):
            return path
        if path.is_symlink():
            raise OutputFolderError(
                f"{what} {shown} is a link, which silo4 did not write; name another path "
                "(silo4 never replaces your files)", path)
        if folder:
            if not path.is_dir():
                raise OutputFolderError(f"{what} {shown} exists and is not a folder", path)
            foreign = foreign_files(path)
        else:
            if path.is_dir():
                raise OutputFolderError(f"{what} {shown} is a folder; expected a file name",
                                        path)
            listed = _manifest_names(path.absolute().parent) or set()
            foreign = [] if path.name in listed else [shown]
    except OSError as exc:
        raise OutputFolderError(f"{what} {shown}: {exc.strerror or exc}", path) from exc
    if foreign and folder:
        more = f" and {len(foreign) - 1} more" if len(foreign) > 1 else ""
        noun = "output folder" if what == "output folder" else f"{what} folder"
        raise OutputFolderError(
            f"{noun} {shown} holds {foreign[0]!r}{more}, which silo4 did not write; "
            "move it away or choose another folder (silo4 never deletes your files)", path)
    if foreign:
        raise OutputFolderError(
            f"{what} {shown} exists and was not written by silo4; move it away or choose "
            "another name (silo4 never overwrites your files)", path)
    return path


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
                f"cannot write output folder {out_dir}: {exc.strerror or exc}", out_dir) from exc
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            os.close(fd)
            if exc.errno in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
                raise OutputFolderError(
                    f"another silo4 run is writing {out_dir} right now (lock {lock_path.name}); "
                    "wait for it or choose another folder", out_dir) from None
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


@contextlib.contextmanager
def stop_signals_held() -> Iterator[None]:
    """SIGINT/SIGTERM wait until the block ends, then reach the handlers they would have
    reached: for steps that must not be cut in two (a folder made but not yet known, a worker
    forked but not yet registered). Python runs a handler between bytecodes, and a signal
    that has already arrived is not held back by pthread_sigmask, so the handlers are swapped
    for one that only remembers (and sets the stop flag, :func:`request_stop`). Main thread
    only; elsewhere a no-op."""
    caught: list[int] = []

    def remember(signum: int, frame: object) -> None:
        request_stop()
        caught.append(signum)

    old: dict[int, object] = {}
    try:
        for signum in (signal.SIGINT, signal.SIGTERM):
            old[signum] = signal.signal(signum, remember)
    except ValueError:                           # not the main thread: nothing swapped
        yield
        return
    try:
        yield
    finally:
        for signum, handler in old.items():
            signal.signal(signum, signal.SIG_DFL if handler is None else handler)
        for signum in caught[:1]:
            signal.raise_signal(signum)


@contextlib.contextmanager
def _signals_deferred() -> Iterator[None]:
    """Hold SIGINT/SIGTERM back while a folder is swapped (delivered right after)."""
    blocked = {signal.SIGINT, signal.SIGTERM}
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, blocked)
    except (AttributeError, OSError, ValueError):
        yield
        return
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def replace_folder_atomically(out_dir: str | Path, fill: Callable[[Path], None], *,
                              check: Callable[[Path], None] | None = None) -> Path:
    """Create ``out_dir`` by filling a temporary sibling folder and renaming it.

    ``check(out_dir)`` runs first, under the folder lock (so its verdict still holds at the
    rename); then the folder is refused if it holds files silo4 did not write. ``fill(tmp)``
    writes the files; if it raises (or a signal interrupts), the temporary folder is removed
    and any existing ``out_dir`` is left exactly as it was. Returns the final folder.
    """
    out_dir = check_output_path(out_dir, what="output folder")
    parent = out_dir.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputFolderError(
            f"cannot write output folder {out_dir}: {exc.strerror or exc}", out_dir) from exc
    with folder_lock(out_dir):
        if check is not None:
            check(out_dir)
        check_replaceable(out_dir)
        _fill_and_swap(out_dir, fill)
    return out_dir


def write_manifest(folder: Path) -> None:
    """List everything ``folder`` holds in its ``.silo4-files`` (a folder silo4 filled)."""
    import json

    (folder / MANIFEST_NAME).write_text(json.dumps(_listing(folder)) + "\n", encoding="utf-8")


def _fill_and_swap(out_dir: Path, fill: Callable[[Path], None]) -> None:
    import shutil
    import tempfile

    parent = out_dir.parent
    tmp: Path | None = None
    try:
        with stop_signals_held():   # a signal lands after tmp is known, so it is removed
            tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.tmp-", dir=parent))
        fill(tmp)
        write_manifest(tmp)
        os.chmod(tmp, 0o777 & ~current_umask())  # mkdtemp made it 0700
        with _signals_deferred():
            if _stop_requested:  # a signal came during fill() and its exception was lost
                raise RunInterrupted()
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
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        raise OutputFolderError(
            f"cannot write output folder {out_dir}: {exc.strerror or exc}", out_dir) from exc
    except BaseException:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        raise
