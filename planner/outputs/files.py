"""Writing outputs so that nothing is ever half-written and no user file is ever deleted.

The names of the modules that implement it, in one place (docs/errors.md):

- planner/outputs/atomic.py: atomic file writes, OutputFolderError, output folder names;
- planner/outputs/ownership.py: ``.silo4-files`` manifests and the one output-safety rule
  (:func:`check_target`), ``write_atomic`` that applies it;
- planner/outputs/lock.py: one writer per output folder;
- planner/outputs/folder_swap.py: a folder filled as a temporary sibling, then renamed;
- planner/outputs/signals.py: SIGINT / SIGTERM held back while a folder is swapped.
"""

from __future__ import annotations

from planner.outputs.atomic import (
    OutputFolderError,
    check_output_path,
    current_umask,
    write_file_atomically,
)
from planner.outputs.folder_swap import replace_folder_atomically
from planner.outputs.lock import folder_lock
from planner.outputs.ownership import (
    MANIFEST_NAME,
    check_replaceable,
    check_target,
    foreign_files,
    record_written,
    write_atomic,
    write_manifest,
    write_text_atomically,
)
from planner.outputs.signals import (
    RunInterrupted,
    request_stop,
    stop_requested,
    stop_signals_held,
)

__all__ = [
    "MANIFEST_NAME",
    "OutputFolderError",
    "RunInterrupted",
    "check_output_path",
    "check_replaceable",
    "check_target",
    "current_umask",
    "folder_lock",
    "foreign_files",
    "record_written",
    "replace_folder_atomically",
    "request_stop",
    "stop_requested",
    "stop_signals_held",
    "write_atomic",
    "write_file_atomically",
    "write_manifest",
    "write_text_atomically",
]
