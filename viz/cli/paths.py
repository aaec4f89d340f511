"""Waypoints from the command line: ``--waypoints "X,Y X,Y ..."`` and ``--path FILE.csv``.

Both give a (K, 2) float array of finite waypoints in the world frame [m] or raise
:class:`~silo4kin.errors.Silo4Error` with one line naming the bad token or line. The counts
are bounded by the planner's work budget (planner/request.py MAX_WAYPOINTS) so a huge input
is refused before it is parsed into memory.
"""

from __future__ import annotations

import codecs
import csv
import math
import re
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

from planner.budget import MAX_WAYPOINTS
from silo4kin.errors import Silo4Error

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_POINT = re.compile(rf"^\s*({_NUMBER})\s*,\s*({_NUMBER})\s*$", re.ASCII)
_NUMBER_ONLY = re.compile(rf"^{_NUMBER}$", re.ASCII)
#: Largest --path file read [bytes]: MAX_WAYPOINTS lines with room for comments.
MAX_PATH_FILE_BYTES = 1_000_000


def _finite_point(x: float, y: float, where: str) -> tuple[float, float]:
    if not (math.isfinite(x) and math.isfinite(y)):
        raise Silo4Error(f"{where}: ({x}, {y}) is not a finite point [m]")
    return x, y


def parse_waypoints(text: str) -> np.ndarray:
    """``"0,1 1,1 0,2"`` -> (K, 2) array [m]; points separated by spaces or ';'."""
    tokens = [tok for tok in re.split(r"[\s;]+", re.sub(r"\s*,\s*", ",", text.strip())) if tok]
    if not tokens:
        raise Silo4Error(f'--waypoints {text[:40]!r}: no points; give x,y pairs, e.g. "0,1 1,1"')
    if len(tokens) > MAX_WAYPOINTS:
        raise Silo4Error(
            f"--waypoints: {len(tokens)} points exceed the budget of "
            f"{MAX_WAYPOINTS} per plan; split the path into several runs"
        )
    points = []
    for tok in tokens:
        match = _POINT.match(tok)
        if match is None:
            raise Silo4Error(
                f"--waypoints: {tok[:40]!r} is not a point x,y (two numbers in "
                "metres separated by a comma, points separated by spaces), "
                'e.g. "0,1 1,1"'
            )
        points.append(
            _finite_point(float(match.group(1)), float(match.group(2)), f"--waypoints {tok[:40]!r}")
        )
    import numpy as np

    return np.array(points)


def _read_text(path: Path) -> str:
    """The file's text: UTF-8 with or without a BOM; refuses folders, devices, binary files
    and files over MAX_PATH_FILE_BYTES. Undecodable bytes (a Latin-1 comment) become U+FFFD,
    so they only matter on a data line, which is then refused naming the line."""
    try:
        if not path.is_file():
            what = (
                "a folder"
                if path.is_dir()
                else ("not a regular file" if path.exists() else "no such file")
            )
            raise Silo4Error(f"--path {path}: {what}; expected a CSV file of waypoints x,y")
        size = path.stat().st_size
        if size > MAX_PATH_FILE_BYTES:
            raise Silo4Error(
                f"--path {path}: {size:,} bytes is too large for a waypoint file "
                f"(at most {MAX_PATH_FILE_BYTES:,}; {MAX_WAYPOINTS} waypoints)"
            )
        data = path.read_bytes()
    except OSError as exc:
        raise Silo4Error(f"--path {path}: cannot read the file ({exc.strerror or exc})") from exc
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):  # "Unicode text" export
        try:
            return data.decode("utf-16")
        except UnicodeDecodeError:
            raise Silo4Error(
                f"--path {path}: starts with a UTF-16 byte order mark but is not "
                "UTF-16 text; save it as UTF-8 CSV (lines x,y)"
            ) from None
    if b"\0" in data:
        raise Silo4Error(f"--path {path}: a binary file, not CSV text (lines x,y)")
    return data.decode("utf-8-sig", errors="replace")


def _cells(line: str) -> list[str]:
    """The cells of one CSV line, RFC 4180 quotes removed (``"0","1"`` -> ``["0", "1"]``)."""
    try:
        row = next(csv.reader([line.lstrip("\ufeff")], skipinitialspace=True), [])
    except csv.Error:  # e.g. a stray quote inside a field: the line as plain text
        row = line.split(",")
    return [c.strip() for c in row]


def _not_a_point(path: Path, n: int, line: str, what: str) -> Silo4Error:
    """The refusal of line ``n``, with a hint when ``;`` separates the columns."""
    hint = (
        "; the columns are separated by ';': save the file with commas (x,y)" if ";" in line else ""
    )
    return Silo4Error(f"--path {path}: line {n} {line.strip()[:60]!r} is {what}{hint}")


def read_path_file(path: str | Path) -> np.ndarray:
    """Waypoints (K, 2) [m] from a CSV file with columns x, y (header line optional).

    Blank lines and lines starting with '#' are skipped; cells may be quoted (RFC 4180:
    ``"x","y"``), lines may end in CRLF, and the file may start with a UTF-8 or UTF-16 byte
    order mark. With a header, columns named ``x`` and ``y`` are used (any order, other
    columns ignored); without, the first two columns. A file whose columns are separated by
    ``;`` is refused with that hint.
    """
    path = Path(path)
    lines = _read_text(path).splitlines()
    rows = [
        (n, line)
        for n, line in enumerate(lines, 1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not rows:
        raise Silo4Error(f"--path {path}: no waypoints (expected lines x,y)")
    columns = (0, 1)
    first = _cells(rows[0][1])
    if not all(_NUMBER_ONLY.match(c) for c in first[:2]) or len(first) < 2:
        names = [c.lower() for c in first]
        if "x" not in names or "y" not in names:
            raise _not_a_point(
                path,
                rows[0][0],
                rows[0][1],
                "neither a point x,y nor a header naming columns x and y",
            )
        columns = (names.index("x"), names.index("y"))
        rows = rows[1:]
    if len(rows) > MAX_WAYPOINTS:
        raise Silo4Error(
            f"--path {path}: {len(rows)} waypoints exceed the budget of "
            f"{MAX_WAYPOINTS} per plan; split the path into several files"
        )
    points = []
    for n, line in rows:
        cells = _cells(line)
        try:
            x, y = cells[columns[0]], cells[columns[1]]
            if not (_NUMBER_ONLY.match(x) and _NUMBER_ONLY.match(y)):
                raise ValueError
        except (ValueError, IndexError):
            raise _not_a_point(path, n, line, "not a point x,y (two numbers in metres)") from None
        points.append(_finite_point(float(x), float(y), f"--path {path}: line {n}"))
    if not points:
        raise Silo4Error(f"--path {path}: no waypoints after the header")
    import numpy as np

    return np.array(points)
