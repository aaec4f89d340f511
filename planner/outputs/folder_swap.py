"""Replace a folder whole: fill a temporary sibling, then rename it over the old one.

An existing folder is moved aside first and deleted only after the rename; on any error or
signal the temporary folder is removed and the old folder is left exactly as it was. The
swap runs under the folder lock (planner/outputs/lock.py) and only over a folder that holds
nothing silo4 did not write (planner/outputs/ownership.py); folders get the modes the umask
gives (0777 masked), not mkdtemp's 0700. A stop that arrives during the swap undoes it; the
temporaries of a killed run and the parents a failed run created are removed
(planner/outputs/leftovers.py).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

from planner.outputs.atomic import OutputFolderError, check_output_path, current_umask
from planner.outputs.leftovers import (
    make_parents,
    remove_created,
    remove_stale_siblings,
    remove_tree,
    sibling_prefix,
)
from planner.outputs.lock import folder_lock
from planner.outputs.ownership import check_replaceable, write_manifest
from planner.outputs.signals import (
    STOP_SIGNALS,
    RunInterrupted,
    signals_deferred,
    stop_requested,
    stop_signals_held,
)


def replace_folder_atomically(
    out_dir: str | Path,
    fill: Callable[[Path], None],
    *,
    check: Callable[[Path], None] | None = None,
) -> Path:
    """Create ``out_dir`` by filling a temporary sibling folder and renaming it.

    ``check(out_dir)`` runs first, under the folder lock (so its verdict still holds at the
    rename); then the folder is refused if it holds files silo4 did not write. ``fill(tmp)``
    writes the files; if it raises (or a signal interrupts), the temporary folder is removed
    and any existing ``out_dir`` is left exactly as it was. Returns the final folder.
    """
    out_dir = check_output_path(out_dir, what="output folder")
    try:
        made = make_parents(out_dir)
    except OSError as exc:
        raise OutputFolderError(
            f"cannot write output folder {out_dir}: {exc.strerror or exc}", out_dir
        ) from exc
    try:
        with folder_lock(out_dir):
            remove_stale_siblings(out_dir)  # of a run killed by SIGKILL or SIGHUP
            if check is not None:
                check(out_dir)
            check_replaceable(out_dir)
            _fill_and_swap(out_dir, fill)
    except BaseException:  # a run that does not finish removes the parents it created
        remove_created(made)
        raise
    return out_dir


def _stop_pending() -> bool:
    """Whether one of STOP_SIGNALS arrived while signals_deferred held it back."""
    import signal

    try:
        return bool(signal.sigpending() & set(STOP_SIGNALS))
    except (AttributeError, OSError):
        return False


def _fill_and_swap(out_dir: Path, fill: Callable[[Path], None]) -> None:
    import shutil
    import tempfile

    parent = out_dir.parent
    tmp: Path | None = None
    try:
        with stop_signals_held():  # a signal lands after tmp is known, so it is removed
            tmp = Path(tempfile.mkdtemp(prefix=sibling_prefix(out_dir, "tmp"), dir=parent))
        fill(tmp)
        write_manifest(tmp)
        os.chmod(tmp, 0o777 & ~current_umask())  # mkdtemp made it 0700
        with signals_deferred():
            if stop_requested():  # a signal came during fill() and its exception was lost
                raise RunInterrupted()
            old = None
            if out_dir.exists():
                old = Path(tempfile.mkdtemp(prefix=sibling_prefix(out_dir, "old"), dir=parent))
                try:
                    os.replace(out_dir, old / out_dir.name)
                except OSError:  # e.g. a read-only run folder cannot be moved
                    os.rmdir(old)
                    raise
            try:
                os.replace(tmp, out_dir)
            except OSError:
                if old is not None:  # put the previous run back
                    os.replace(old / out_dir.name, out_dir)
                    remove_tree(old)
                raise
            if _stop_pending():  # a stop came during the swap: undo it, the stop wins
                os.replace(out_dir, tmp)
                if old is not None:
                    os.replace(old / out_dir.name, out_dir)
                    remove_tree(old)
                raise RunInterrupted()
            if old is not None:
                remove_tree(old)
    except OSError as exc:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        raise OutputFolderError(
            f"cannot write output folder {out_dir}: {exc.strerror or exc}", out_dir
        ) from exc
    except BaseException:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        raise
