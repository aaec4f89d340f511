"""Which files silo4 wrote, and the one output-safety rule (docs/errors.md "What silo4 may
replace").

Every run folder lists the files silo4 wrote in ``.silo4-files``; files written outside a
run folder are recorded in a ``.silo4-files`` of their folder (:func:`record_written`), so
the same command can replace them on a rerun. :func:`check_target`, for every file and
folder any subcommand writes: a new path is fine; an existing one may be replaced only when
everything that would be removed or overwritten was written by silo4 (a file listed in the
``.silo4-files`` beside it, a folder whose own ``.silo4-files`` lists everything in it); an
input of the same command is never a target; a link is never ours. :func:`write_atomic`
applies the rule itself, so no writer can overwrite a file silo4 did not write.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from pathlib import Path

from planner.outputs.atomic import OutputFolderError, write_file_atomically

#: The list of files a run folder holds, written last into it (hidden).
MANIFEST_NAME = ".silo4-files"


def write_atomic(
    path: str | Path, write: Callable[[Path], object], *, make_parents: bool = False
) -> Path:
    """Call ``write(tmp_path)`` for a temporary sibling of ``path``, then rename it to ``path``.

    An existing ``path`` is replaced only when silo4 wrote it (:func:`check_target`).

    Args:
        make_parents: create missing parent folders (else a missing folder is an error).

    Raises:
        OutputFolderError: the folder is missing or not writable, ``path`` is a folder, or
            ``path`` exists and was not written by silo4.
    """
    return write_file_atomically(path, write, make_parents=make_parents, check=check_target)


def write_text_atomically(path: str | Path, text: str, *, make_parents: bool = True) -> Path:
    """Write UTF-8 text to ``path`` atomically (:func:`write_atomic`)."""
    return write_atomic(
        path, lambda tmp: tmp.write_text(text, encoding="utf-8"), make_parents=make_parents
    )


def _listing(folder: Path) -> list[str]:
    """Every file and folder under ``folder``, as sorted relative POSIX paths (the manifest
    itself left out: it is not one of the files it lists)."""
    return sorted(
        rel
        for rel in (p.relative_to(folder).as_posix() for p in folder.rglob("*"))
        if rel != MANIFEST_NAME
    )


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

        write_file_atomically(manifest, write)


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


def check_target(
    path: str | Path,
    *,
    inputs: Iterable[str | Path] = (),
    what: str = "output",
    folder: bool = False,
) -> Path:
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
            "another name",
            path,
        )
    real = os.path.realpath(path)
    for item in inputs:
        real_input = os.path.realpath(item)
        if real_input == real or real_input.startswith(real.rstrip(os.sep) + os.sep):
            raise OutputFolderError(
                f"{what} {shown} would replace {item}, an input of this command; choose "
                "another path",
                path,
            )
    try:
        if not os.path.lexists(path):
            return path
        if path.is_symlink():
            raise OutputFolderError(
                f"{what} {shown} is a link, which silo4 did not write; name another path "
                "(silo4 never replaces your files)",
                path,
            )
        if folder:
            if not path.is_dir():
                raise OutputFolderError(f"{what} {shown} exists and is not a folder", path)
            foreign = foreign_files(path)
        else:
            if path.is_dir():
                raise OutputFolderError(f"{what} {shown} is a folder; expected a file name", path)
            listed = _manifest_names(path.absolute().parent) or set()
            foreign = [] if path.name in listed else [shown]
    except OSError as exc:
        raise OutputFolderError(f"{what} {shown}: {exc.strerror or exc}", path) from exc
    if foreign and folder:
        more = f" and {len(foreign) - 1} more" if len(foreign) > 1 else ""
        noun = "output folder" if what == "output folder" else f"{what} folder"
        raise OutputFolderError(
            f"{noun} {shown} holds {foreign[0]!r}{more}, which silo4 did not write; "
            "move it away or choose another folder (silo4 never deletes your files)",
            path,
        )
    if foreign:
        raise OutputFolderError(
            f"{what} {shown} exists and was not written by silo4; move it away or choose "
            "another name (silo4 never overwrites your files)",
            path,
        )
    return path


def write_manifest(folder: Path) -> None:
    """List everything ``folder`` holds in its ``.silo4-files`` (a folder silo4 filled)."""
    import json

    (folder / MANIFEST_NAME).write_text(json.dumps(_listing(folder)) + "\n", encoding="utf-8")
