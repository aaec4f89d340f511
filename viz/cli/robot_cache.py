"""The user's cache of ``silo4 robots`` rows: what does not change between calls.

A robot's row (leg family, mass, feasible height range, stride: viz/cli/robots.py) depends
only on its robot description and on the code that computes it, so it is kept per robot in
the user's cache folder and read back while neither changes:

- folder: ``$SILO4_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/silo4``, else
  ``~/.cache/silo4`` (the XDG base-directory convention); rows live in its ``robots/``;
- key: SHA-256 of the expanded URDF text (the one ``load_robot`` builds the model from), the
  SRDF text that gives a mammal its reference posture, the silo4kin version, ROW_FORMAT
  and the source of the code that computes a row (:func:`code_fingerprint`):
  an edited URDF, an upgrade, an edited checkout or another row layout misses the cache
  and the row is computed again;
- one JSON file per robot and key, written atomically (planner/outputs/atomic.py), so two
  ``silo4 robots`` at once never read half a row; an unreadable file is a miss.

``silo4 robots --no-cache`` neither reads nor writes it; ``--clear-cache`` deletes the rows
first.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from functools import lru_cache
from pathlib import Path

#: Layout of a cached row; bump it when robot_row's keys or meaning change.
ROW_FORMAT = 2
#: Environment variable naming the cache folder (tests point it at a temporary folder).
CACHE_ENV = "SILO4_CACHE_DIR"


def cache_folder() -> Path:
    """The user's silo4 cache folder (module docstring); not created here."""
    explicit = os.environ.get(CACHE_ENV)
    if explicit:
        return Path(explicit).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg).expanduser() if xdg else Path.home() / ".cache"
    return base / "silo4"


def silo4_version() -> str:
    """The installed silo4kin version ("unknown" when run from an uninstalled tree)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("silo4kin")
    except PackageNotFoundError:
        return "unknown"


@lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """SHA-256 (hex) of the source files of silo4kin and planner and of numpy's and
    Pinocchio's versions: the code a cached row or range was computed with."""
    import numpy
    import pinocchio

    import planner
    import silo4kin

    digest = hashlib.sha256(f"{numpy.__version__}\0{pinocchio.__version__}\0".encode())
    for package in (silo4kin, planner):
        root = Path(str(package.__file__)).resolve().parent
        for path in sorted(root.rglob("*.py")):
            digest.update(path.relative_to(root.parent).as_posix().encode() + b"\0")
            digest.update(path.read_bytes())
    return digest.hexdigest()


def description_key(name: str) -> str:
    """The cache key of robot ``name`` ("silo4" or an example-robot-data name): SHA-256 of
    its expanded URDF, its SRDF (if any), the silo4kin version, ROW_FORMAT and the code's
    fingerprint (hex)."""
    from silo4kin.robot_files import read_robot_description
    from silo4kin.robot_library import canonical_robot_name, resolve_example_robot

    digest = hashlib.sha256(
        f"{name}\0{silo4_version()}\0{ROW_FORMAT}\0{code_fingerprint()}\0".encode()
    )
    if canonical_robot_name(name) == "silo4":
        digest.update(read_robot_description(None).encode())
    else:
        source = resolve_example_robot(name)
        digest.update(read_robot_description(source.urdf, None, source.package_dirs).encode())
        if source.srdf is not None:
            digest.update(b"\0srdf\0" + Path(source.srdf).read_bytes())
    return digest.hexdigest()


class KeyedJsonFiles:
    """JSON records in a subfolder of the user's cache folder, each carrying its key: read
    back only under that key (an unreadable file, or another key's, is a miss), written
    atomically (a cache that cannot be written is skipped), deleted only when named as the
    cache names its files (:attr:`own_name`: nothing else in the folder).

    Attributes:
        folder: the cache folder (cache_folder() by default).
    """

    #: The subfolder of the cache folder.
    subfolder = ""
    #: The names of the files this cache writes.
    own_name = re.compile(r"(?!)")

    def __init__(self, folder: Path | None = None) -> None:
        self.folder = cache_folder() if folder is None else Path(folder)

    @property
    def files_folder(self) -> Path:
        """Where the files are."""
        return self.folder / self.subfolder

    def read(self, path: Path, key: str) -> dict | None:
        """The record in ``path`` if it is a JSON object of ``key``, else None."""
        try:
            record = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        if not isinstance(record, dict) or record.get("key") != key:
            return None
        return record

    def write(self, path: Path, record: dict) -> bool:
        """Write ``record`` to ``path`` atomically; False where the folder cannot be written."""
        from planner.outputs.atomic import OutputFolderError, write_file_atomically

        text = json.dumps(record, indent=1)
        try:
            self.files_folder.mkdir(parents=True, exist_ok=True)
            write_file_atomically(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))
        except (OSError, OutputFolderError):
            return False
        return True

    def clear(self) -> int:
        """Delete every file of this cache (:attr:`own_name`); returns how many."""
        removed = 0
        for path in self.files_folder.glob("*.json"):
            if not self.own_name.fullmatch(path.name):
                continue
            try:
                path.unlink()
                removed += 1
            except OSError:
                pass
        return removed


class RobotRowCache(KeyedJsonFiles):
    """Rows of ``silo4 robots`` in ``folder / "robots"``, one JSON file per robot and key."""

    subfolder = "robots"
    own_name = re.compile(r"[A-Za-z0-9_.-]+-[0-9a-f]{32}\.json")

    @property
    def rows_folder(self) -> Path:
        """Where the rows are."""
        return self.files_folder

    def path_for(self, name: str, key: str) -> Path:
        """The file of robot ``name``'s row under ``key``."""
        return self.rows_folder / f"{name}-{key[:32]}.json"

    def get(self, name: str, key: str) -> dict[str, object] | None:
        """The cached row of ``name`` under ``key``, or None (missing or unreadable)."""
        record = self.read(self.path_for(name, key), key)
        row = None if record is None else record.get("row")
        if not isinstance(row, dict):
            return None
        for field in ("range_m", "any_direction_m"):
            if row.get(field) is not None:
                row[field] = tuple(row[field])
        return row

    def put(self, name: str, key: str, row: dict[str, object]) -> None:
        """Keep ``row`` for ``name`` under ``key``, replacing the robot's older rows; a cache
        that cannot be written is skipped (the row was computed and is printed anyway)."""
        target = self.path_for(name, key)
        if not self.write(target, {"key": key, "row": row}):
            return
        for old in self.rows_folder.glob(f"{name}-*.json"):
            if old != target and re.fullmatch(rf"{re.escape(name)}-[0-9a-f]{{32}}\.json", old.name):
                try:
                    old.unlink(missing_ok=True)
                except OSError:
                    return
