"""sweep.csv: the table of a sweep, one row per configuration, appended as rows arrive and
rewritten in grid order at the end; its Parquet copy; the settings record sweep.json.

Resuming: a rerun reads DIR/sweep.csv, skips every configuration already in it (whatever
its status) and appends the rest. A row cut short by an interrupted run (no final newline)
is dropped and planned again. A rerun with other settings or other xacro arguments is
refused (the table would mix two sweeps) unless --force starts it anew.

Text form: floats by ``repr`` (round-trips exactly, so tables from different processes
compare as text), missing values empty.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any

from planner.outputs.files import check_target, record_written, write_atomic, write_text_atomically

from .grid import SweepConfig, SweepInputError, format_value
from .task import JOINT_TYPES, SweepSettings

CSV_NAME, PARQUET_NAME, SETTINGS_NAME = "sweep.csv", "sweep.parquet", "sweep.json"

#: Result columns after the configuration columns (see silo4sweep.task for their meaning).
RESULT_COLUMNS: tuple[str, ...] = (
    "status",
    "reason",
    "normalized_time",
    "normalized_error_m",
    "distance_m",
    "average_speed",
    "stride_m",
    "min_margin_m",
    "n_samples",
    "load",
    *(
        f"{q}_{kind}_{unit}"
        for kind in JOINT_TYPES
        for q, unit in (("tau_peak", "Nm"), ("tau_rms", "Nm"), ("qd_peak", "rad_s"))
    ),
    "tau_peak_Nm",
    "motor_tau_peak_Nm",
    "motor_speed_peak_rpm",
)
SIM_COLUMNS: tuple[str, ...] = ("sim_verdict", "sim_reason")
TEXT_COLUMNS = frozenset({"path", "preset", "status", "reason", "load", *SIM_COLUMNS})
INT_COLUMNS = frozenset({"n_samples"})


def columns(xacro_names: Sequence[str], simulate: bool) -> list[str]:
    """Column order of sweep.csv."""
    return [
        "path",
        "height_m",
        *xacro_names,
        "preset",
        *RESULT_COLUMNS,
        *(SIM_COLUMNS if simulate else ()),
    ]


def to_text(value: Any) -> str:
    """One cell: '' for None/NaN, repr for floats, str otherwise."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def typed(row: Mapping[str, str]) -> dict[str, Any]:
    """A text row with numbers as float/int and empty cells as None."""
    out: dict[str, Any] = {}
    for key, text in row.items():
        if key in TEXT_COLUMNS:
            out[key] = text
        elif text == "":
            out[key] = None
        else:
            out[key] = int(text) if key in INT_COLUMNS else float(text)
    return out


def row_key(row: Mapping[str, str], xacro_names: Sequence[str]) -> tuple[str, ...]:
    """The configuration key of a text row (equal to SweepConfig.key of its configuration)."""
    return (
        row["path"],
        format_value(float(row["height_m"])),
        row["preset"],
        *(f"{n}={format_value(float(row[n]))}" for n in xacro_names),
    )


def _csv_line(values: Iterable[str]) -> str:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow(list(values))
    return buf.getvalue()


class SweepTable:
    """The rows of DIR/sweep.csv, in memory and on disk.

    Attributes:
        folder: DIR.
        columns: column names.
        rows: text rows (dicts column -> cell) by configuration key.
    """

    def __init__(
        self,
        folder: Path,
        xacro_names: Sequence[str],
        settings: SweepSettings,
        *,
        force: bool = False,
    ) -> None:
        self.folder = Path(folder)
        self.xacro_names = list(xacro_names)
        self.columns = columns(self.xacro_names, settings.simulate)
        self.rows: dict[tuple[str, ...], dict[str, str]] = {}
        record: dict[str, Any] = {"settings": asdict(settings), "xacro_args": self.xacro_names}
        csv_path, settings_path = self.folder / CSV_NAME, self.folder / SETTINGS_NAME
        self._record = record
        if not force and csv_path.exists():
            self._check_record(settings_path, record)
            self._read(csv_path)

    def start(self) -> None:
        """Write sweep.json and sweep.csv's header and rows (without a cut-short tail), so
        that rows can be appended. Nothing is written before this (a sweep that cannot
        start leaves the folder as it was)."""
        self.folder.mkdir(parents=True, exist_ok=True)
        parquet = check_target(self.folder / PARQUET_NAME)  # only ever delete our own
        parquet.unlink(missing_ok=True)  # stale until finish()
        record_written(
            [
                write_text_atomically(
                    self.folder / SETTINGS_NAME, json.dumps(self._record, indent=2) + "\n"
                )
            ]
        )
        self._write_all()

    def _check_record(self, path: Path, record: dict[str, Any]) -> None:
        try:
            old = json.loads(path.read_text())
        except (OSError, ValueError):
            old = None
        if old != json.loads(json.dumps(record)):
            raise SweepInputError(
                f"{self.folder} holds a sweep with other settings or xacro arguments "
                f"({path.name}: {json.dumps(old)}); use another --out, or --force to start anew"
            )

    def _read(self, path: Path) -> None:
        text = path.read_text(encoding="utf-8")
        if text and not text.endswith("\n"):  # a row cut short by an interrupted run
            text = text[: text.rfind("\n") + 1]
        reader = csv.DictReader(io.StringIO(text))
        if reader.fieldnames is not None and list(reader.fieldnames) != self.columns:
            raise SweepInputError(
                f"{path} has columns {reader.fieldnames}, expected "
                f"{self.columns}; use another --out, or --force"
            )
        for row in reader:
            self.rows[row_key(row, self.xacro_names)] = dict(row)

    def _write_all(self, order: Sequence[SweepConfig] = ()) -> None:
        keys = self._ordered_keys(order)
        text = _csv_line(self.columns) + "".join(
            _csv_line(self.rows[k][c] for c in self.columns) for k in keys
        )
        record_written([write_text_atomically(self.folder / CSV_NAME, text)])  # rows append

    def _ordered_keys(self, order: Sequence[SweepConfig]) -> list[tuple[str, ...]]:
        keys = [c.key for c in order if c.key in self.rows]
        seen = set(keys)
        return keys + [k for k in self.rows if k not in seen]

    def missing(self, configs: Sequence[SweepConfig]) -> list[SweepConfig]:
        """The configurations without a row yet."""
        return [c for c in configs if c.key not in self.rows]

    def add(self, config: SweepConfig, row: Mapping[str, Any]) -> None:
        """Record a row and append it to sweep.csv at once (an interrupted sweep keeps it)."""
        cells = {c: to_text(row.get(c)) for c in self.columns}
        # the configuration columns in their one spelling, whatever the task returned
        cells["height_m"] = format_value(config.height_m)
        cells.update({n: format_value(v) for n, v in config.xacro_args})
        self.rows[config.key] = cells
        with open(self.folder / CSV_NAME, "a", encoding="utf-8") as f:
            f.write(_csv_line(cells[c] for c in self.columns))

    def finish(self, order: Sequence[SweepConfig]) -> list[Path]:
        """Rewrite sweep.csv in grid order (rows of earlier, other grids after) and write
        sweep.parquet; returns the files written."""
        self._write_all(order)
        written = [self.folder / CSV_NAME]
        try:
            import pyarrow as pa
            import pyarrow.parquet as pq
        except ImportError:  # the optional sweep extra brings it; the CSV has everything
            return written
        typed_rows = self.typed_rows(order)
        data = {c: [r[c] for r in typed_rows] for c in self.columns}
        written.append(
            write_atomic(
                self.folder / PARQUET_NAME, lambda tmp: pq.write_table(pa.table(data), tmp)
            )
        )
        record_written(written[-1:])
        return written

    def typed_rows(self, order: Sequence[SweepConfig] = ()) -> list[dict[str, Any]]:
        """Every row with numbers as numbers, in grid order."""
        keys = self._ordered_keys(order)
        return [typed(self.rows[k]) for k in keys]


def read_table(path: str | Path) -> list[dict[str, Any]]:
    """The typed rows of a sweep.csv (for analysis and the results page)."""
    with open(path, encoding="utf-8", newline="") as f:
        return [typed(row) for row in csv.DictReader(f)]


__all__ = ["SweepTable", "columns", "read_table", "typed"]
