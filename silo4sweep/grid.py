"""The design grid of a sweep: paths x heights x xacro arguments x workspace presets.

    heights = parse_values("0.2:0.6:0.05", "--heights")     # 0.2, 0.25, ..., 0.6 [m]
    configs = design_grid(["straight"], heights, {"L2": [0.2, 0.25]}, ["default"])

A value list is ``a:b:step`` (b included when it falls on the grid, within a millionth of a
step) or comma-separated numbers, or both mixed ("0.2:0.4:0.1,0.55"). Every number is
rounded to 10 significant digits so that 0.2 + 3 * 0.05 is 0.35 and a configuration has one
spelling: :attr:`SweepConfig.key` identifies it in sweep.csv (resuming a sweep) whatever
process computed it.
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from silo4kin.errors import Silo4Error

#: Significant digits every grid value is rounded to (one spelling per configuration).
SIGNIFICANT_DIGITS = 10
#: Most values one range may expand to (a typo such as step 0.0001 is refused, not run).
MAX_RANGE_VALUES = 10_000
#: Most configurations one grid may have (each is a plan of about a second and a row in
#: memory); a larger grid is refused before it is built.
MAX_GRID_CONFIGS = 100_000
#: Paths a sweep can plan (planner.studies.cases: thesis Tables 6.1-6.3).
KNOWN_PATHS: tuple[str, ...] = ("straight", "circle", "circle-reduced")

_RANGE = re.compile(r"^([^:]+):([^:]+):([^:]+)$")


class SweepInputError(Silo4Error):
    """A sweep option is malformed: names the option, the value and what is allowed."""


def canonical(value: float) -> float:
    """``value`` rounded to SIGNIFICANT_DIGITS significant digits."""
    return float(f"{value:.{SIGNIFICANT_DIGITS}g}")


def format_value(value: float) -> str:
    """The one text form of a grid value (shortest repr of its canonical float)."""
    return repr(canonical(value))


def _number(text: str, option: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise SweepInputError(f"{option}: {text.strip()!r} is not a number") from None
    if not math.isfinite(value):
        raise SweepInputError(f"{option}: {text.strip()!r} is not finite")
    return value


def parse_values(text: str, option: str) -> list[float]:
    """Numbers from ``a:b:step`` ranges and comma-separated values, sorted, no duplicates."""
    values: list[float] = []
    items = [item.strip() for item in text.split(",") if item.strip()]
    if not items:
        raise SweepInputError(f"{option} {text!r}: empty; give values a,b,c or a range a:b:step")
    for item in items:
        match = _RANGE.match(item)
        if match is None:
            values.append(canonical(_number(item, option)))
            continue
        start, stop, step = (_number(g, option) for g in match.groups())
        if step <= 0 or stop < start:
            raise SweepInputError(
                f"{option}: range {item!r} needs a <= b and step > 0 (a:b:step, b included)"
            )
        count = math.floor((stop - start) / step + 1e-6) + 1
        if count > MAX_RANGE_VALUES:
            raise SweepInputError(
                f"{option}: range {item!r} has {count} values; at most {MAX_RANGE_VALUES}"
            )
        values.extend(canonical(start + k * step) for k in range(count))
    return sorted(set(values))


def parse_names(text: str, option: str, allowed: Sequence[str]) -> list[str]:
    """Comma-separated names, each one of ``allowed``, in the order given, no duplicates."""
    names = list(dict.fromkeys(s.strip() for s in text.split(",") if s.strip()))
    if not names:
        raise SweepInputError(f"{option} {text!r}: empty list; choose from {', '.join(allowed)}")
    for name in names:
        if name not in allowed:
            raise SweepInputError(f"{option}: {name!r} is not one of {', '.join(allowed)}")
    return names


def parse_xacro_sweeps(items: Iterable[str]) -> dict[str, list[float]]:
    """``["L2=0.2,0.25", "L3=0.2:0.3:0.05"]`` -> {"L2": [0.2, 0.25], "L3": [0.2, 0.25, 0.3]}.

    Names are checked against the robot's xacro file by the task (silo4kin.robot), values here.
    """
    sweeps: dict[str, list[float]] = {}
    for item in items:
        name, sep, values = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise SweepInputError(
                f"--xacro-arg {item!r} is not NAME=VALUES (e.g. L2=0.2,0.25 or L3=0.2:0.3:0.05)"
            )
        if name in sweeps:
            raise SweepInputError(f"--xacro-arg {name} given twice; list every value once")
        sweeps[name] = parse_values(values, f"--xacro-arg {name}")
    return sweeps


@dataclass(frozen=True)
class SweepConfig:
    """One configuration of the grid (one Dask task, one row of sweep.csv).

    Attributes:
        path: named path, one of KNOWN_PATHS.
        height_m: CoG height above the ground [m] (canonical).
        preset: workspace preset of the planner ("default", "thesis").
        xacro_args: ((name, value), ...) in the order of the --xacro-arg options; values
            canonical, in the xacro's units (SILO4: metres, kilograms, radians).
    """

    path: str
    height_m: float
    preset: str
    xacro_args: tuple[tuple[str, float], ...] = ()

    @property
    def key(self) -> tuple[str, ...]:
        """The identity of the configuration in sweep.csv: all fields as text."""
        return (
            self.path,
            format_value(self.height_m),
            self.preset,
            *(f"{n}={format_value(v)}" for n, v in self.xacro_args),
        )

    @property
    def design(self) -> tuple[tuple[str, float], ...]:
        """The robot design part: the xacro arguments."""
        return self.xacro_args

    @property
    def label(self) -> str:
        """Short human-readable name, e.g. ``straight h=0.4 default L2=0.25``."""
        args = " ".join(f"{n}={format_value(v)}" for n, v in self.xacro_args)
        return f"{self.path} h={format_value(self.height_m)} {self.preset}" + (
            f" {args}" if args else ""
        )


def grid_size(
    paths: Sequence[str],
    heights_m: Sequence[float],
    xacro_sweeps: Mapping[str, Sequence[float]],
    presets: Sequence[str],
) -> int:
    """How many configurations :func:`design_grid` would build (nothing is built)."""
    return math.prod(
        (len(paths), len(heights_m), len(presets), *(len(v) for v in xacro_sweeps.values()))
    )


def check_grid_size(
    paths: Sequence[str],
    heights_m: Sequence[float],
    xacro_sweeps: Mapping[str, Sequence[float]],
    presets: Sequence[str],
    limit: int = MAX_GRID_CONFIGS,
) -> int:
    """The grid's size, or SweepInputError (the count and the bound) when over ``limit``."""
    size = grid_size(paths, heights_m, xacro_sweeps, presets)
    if size > limit:
        factors = " x ".join(
            f"{len(v)} {n}"
            for n, v in (
                ("paths", paths),
                ("heights", heights_m),
                ("presets", presets),
                *xacro_sweeps.items(),
            )
        )
        raise SweepInputError(
            f"the grid has {size} configurations ({factors}); at most "
            f"{limit}: sweep fewer values, or split it into several sweeps"
        )
    return size


def design_grid(
    paths: Sequence[str],
    heights_m: Sequence[float],
    xacro_sweeps: Mapping[str, Sequence[float]],
    presets: Sequence[str],
) -> list[SweepConfig]:
    """Cartesian product, in a fixed order: design (xacro args, first varying slowest),
    preset, path, height. This is the row order of sweep.csv. Refused (SweepInputError)
    over MAX_GRID_CONFIGS configurations, before any is built."""
    check_grid_size(paths, heights_m, xacro_sweeps, presets)
    names = list(xacro_sweeps)
    configs = []
    for values in itertools.product(*(xacro_sweeps[n] for n in names)):
        design = tuple((n, canonical(v)) for n, v in zip(names, values))
        for preset, path, h in itertools.product(presets, paths, heights_m):
            configs.append(SweepConfig(path, canonical(h), preset, design))
    return configs
