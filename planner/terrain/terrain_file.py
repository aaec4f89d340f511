"""Terrain files (YAML or JSON; docs/terrain.md): :func:`load_terrain` reads one into a
:class:`~planner.terrain.terrain_map.TerrainMap`.

    floor: 0.0                  # [m]; null: no ground
    boxes: [{center: [1, 0, 0.04], size: [0.4, 1, 0.08], rpy: [0, 0, 0]}]   # [m], [deg]
    cylinders: [{center: [2, 0.3, 0.1], radius: 0.08, height: 0.2}]       # [m]
    forbidden: [[[1.5, -1], [1.75, -1], [1.75, 1], [1.5, 1]]]              # convex, [m]
    heightmap: {file: map.npy, resolution: 0.02, origin: [-1, -1]}         # or a 16-bit
                                                  # PNG with z_range: [lo, hi] [m]

Every key is optional (an empty file is flat ground at 0). A heightmap may give its
``heights`` inline instead of a ``file`` (what plan.json records). A malformed file is
refused with one line naming the field (:class:`TerrainFileError`); a UTF-8 byte-order mark
and CRLF line ends are read as usual.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from planner.errors import PlannerInputError
from planner.terrain.heightmap import HeightMap, png_heights
from planner.terrain.shapes import Box, Cylinder
from planner.terrain.terrain_map import FORBIDDEN_CLEARANCE_M, TerrainMap

#: The keys of a terrain file.
TERRAIN_KEYS = ("floor", "boxes", "cylinders", "forbidden", "heightmap")
#: Largest height map the planner reads [samples] (a 2000 x 2000 grid); a larger .npy or
#: PNG is refused from its header, before its samples are read.
MAX_HEIGHTMAP_SAMPLES = 4_000_000
#: Largest terrain file read [bytes] (10 MB; a height map goes in its own file).
MAX_TERRAIN_FILE_BYTES = 10_000_000


class TerrainFileError(PlannerInputError):
    """A terrain file that cannot be read; the message names the file and the field."""


class _Fields:
    """Checks values of one file, naming the file and the field in every refusal."""

    def __init__(self, name: str) -> None:
        self.name = name

    def fail(self, where: str, what: str) -> TerrainFileError:
        source = f"terrain file {self.name}" if self.name else "terrain"
        return TerrainFileError(f"{source}: {where}: {what}")

    def number(self, where: str, value: Any, *, positive: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            hint = ""
            if isinstance(value, str) and _is_float(value):
                hint = f" (YAML reads {value} as text: write it with a point, e.g. 1.0e-2)"
            raise self.fail(where, f"a number expected, got {value!r}{hint}")
        if not math.isfinite(value) or (positive and not value > 0):
            raise self.fail(
                where, f"a {'positive' if positive else 'finite'} number expected, got {value!r}"
            )
        return float(value)

    def vector(self, where: str, value: Any, n: int, *, positive: bool = False) -> np.ndarray:
        if not isinstance(value, (list, tuple)) or len(value) != n:
            raise self.fail(where, f"a list of {n} numbers expected, got {value!r}")
        return np.array(
            [self.number(f"{where}[{i}]", v, positive=positive) for i, v in enumerate(value)]
        )

    def mapping(self, where: str, value: Any, keys: tuple[str, ...], required: tuple[str, ...]):
        if not isinstance(value, dict):
            needs = f" with {', '.join(required)}" if required else ""
            raise self.fail(where, f"a mapping{needs} expected, got {value!r}")
        unknown = sorted(set(value) - set(keys))
        if unknown:
            raise self.fail(where, f"unknown field {unknown[0]!r}; known: {', '.join(keys)}")
        missing = [k for k in required if k not in value]
        if missing:
            raise self.fail(where, f"{missing[0]!r} missing")
        return value

    def items(self, where: str, value: Any) -> list:
        if value is None:
            return []
        if not isinstance(value, list):
            raise self.fail(where, f"a list expected, got {value!r}")
        return value


def _polygon(fields: _Fields, where: str, value: Any) -> np.ndarray:
    if not isinstance(value, list) or len(value) < 3:
        raise fields.fail(where, f"a list of at least 3 [x, y] vertices expected, got {value!r}")
    pts = np.array([fields.vector(f"{where}[{i}]", v, 2) for i, v in enumerate(value)])
    edges = np.roll(pts, -1, axis=0) - pts
    cross = edges[:, 0] * np.roll(edges[:, 1], -1) - edges[:, 1] * np.roll(edges[:, 0], -1)
    if np.any(np.hypot(*edges.T) == 0) or not (np.all(cross > 0) or np.all(cross < 0)):
        raise fields.fail(where, "the polygon is not convex (split it into convex ones)")
    dots = np.sum(edges * np.roll(edges, -1, axis=0), axis=1)
    turns = abs(float(np.sum(np.arctan2(cross, dots)))) / (2.0 * np.pi)
    if round(turns) != 1:  # a star turns twice or more: its edges cross
        raise fields.fail(where, f"the polygon intersects itself (it winds {turns:.0f} times)")
    return pts


def _heightmap(fields: _Fields, value: Any, folder: Path, floor: float | None) -> HeightMap:
    keys = ("file", "heights", "resolution", "origin", "z_range")
    hm = fields.mapping("heightmap", value, keys, ("resolution", "origin"))
    resolution = fields.number("heightmap.resolution", hm["resolution"], positive=True)
    origin = fields.vector("heightmap.origin", hm["origin"], 2)
    if ("file" in hm) == ("heights" in hm):
        raise fields.fail("heightmap", "give one of 'file' and 'heights'")
    if "heights" in hm:
        try:
            heights = np.array(hm["heights"], dtype=float)
        except (TypeError, ValueError):
            raise fields.fail(
                "heightmap.heights", "a list of equal rows of numbers expected"
            ) from None
    else:
        heights = _read_heights(fields, folder / str(hm["file"]), hm.get("z_range"))
    _check_grid(fields, "heightmap", heights.shape)
    if not np.all(np.isfinite(heights)):
        raise fields.fail("heightmap", "heights must be finite numbers [m]")
    if floor is not None and heights.min() < 0:
        raise fields.fail(
            "heightmap",
            f"heights below 0 (lowest {heights.min():g} m) would lie under the "
            "floor; they are added to it: lower the floor and raise the map instead",
        )
    return HeightMap(heights, resolution, origin, 0.0 if floor is None else floor)


def _read_heights(fields: _Fields, path: Path, z_range: Any) -> np.ndarray:
    if path.suffix.lower() == ".png":
        if z_range is None:
            raise fields.fail("heightmap.z_range", "a PNG height map needs z_range: [lo, hi] [m]")
        lo, hi = fields.vector("heightmap.z_range", z_range, 2)
        try:
            return png_heights(path, (lo, hi), MAX_HEIGHTMAP_SAMPLES)
        except (OSError, ValueError) as exc:
            raise fields.fail("heightmap.file", f"{path}: {exc}") from None
    if z_range is not None:
        raise fields.fail("heightmap.z_range", "only a PNG height map takes z_range")
    try:
        with open(path, "rb") as f:
            magic = f.read(6)
    except OSError as exc:
        raise fields.fail("heightmap.file", f"{path}: cannot be read: {_one_line(exc)}") from None
    if magic != b"\x93NUMPY":
        raise fields.fail("heightmap.file", f"{path}: not a .npy file (no NUMPY header)")
    try:
        stored = np.load(path, mmap_mode="r", allow_pickle=False)  # the header: no samples
    except (OSError, ValueError, EOFError) as exc:
        raise fields.fail("heightmap.file", f"{path}: not a .npy array: {_one_line(exc)}") from None
    if not isinstance(stored, np.ndarray):
        raise fields.fail("heightmap.file", f"{path}: one array expected, got an archive")
    _check_grid(fields, "heightmap.file", stored.shape)
    if not (np.issubdtype(stored.dtype, np.floating) or np.issubdtype(stored.dtype, np.integer)):
        raise fields.fail(
            "heightmap.file", f"{path}: real numbers [m] expected, got dtype {stored.dtype}"
        )
    return np.array(stored, dtype=float)


def _check_grid(fields: _Fields, where: str, shape: tuple[int, ...]) -> None:
    """Refuse a grid that is not 2-D of at least 2 x 2 and at most MAX_HEIGHTMAP_SAMPLES."""
    if len(shape) != 2 or min(shape) < 2 or math.prod(shape) > MAX_HEIGHTMAP_SAMPLES:
        raise fields.fail(
            where,
            f"a 2-D grid of at least 2 x 2 and at most {MAX_HEIGHTMAP_SAMPLES} "
            f"samples expected, got shape {tuple(shape)}",
        )


def terrain_from_document(
    document: Any,
    *,
    name: str = "",
    folder: Path | str = ".",
    forbidden_clearance_m: float = FORBIDDEN_CLEARANCE_M,
) -> TerrainMap:
    """The TerrainMap of a terrain file's content (a mapping; None: flat ground at 0);
    ``name``: the file, for messages; ``folder``: where a heightmap ``file`` is read from.

    Raises:
        TerrainFileError: a malformed field (named).
    """
    fields = _Fields(name)
    doc = {} if document is None else document
    fields.mapping("the file", doc, TERRAIN_KEYS, ())
    floor = doc.get("floor", 0.0)
    floor = None if floor is None else fields.number("floor", floor)
    boxes = []
    for i, item in enumerate(fields.items("boxes", doc.get("boxes"))):
        where = f"boxes[{i}]"
        box = fields.mapping(where, item, ("center", "size", "rpy"), ("center", "size"))
        boxes.append(
            Box(
                fields.vector(f"{where}.center", box["center"], 3),
                fields.vector(f"{where}.size", box["size"], 3, positive=True),
                fields.vector(f"{where}.rpy", box.get("rpy", [0, 0, 0]), 3),
            )
        )
    cylinders = []
    for i, item in enumerate(fields.items("cylinders", doc.get("cylinders"))):
        where = f"cylinders[{i}]"
        cyl = fields.mapping(
            where, item, ("center", "radius", "height"), ("center", "radius", "height")
        )
        cylinders.append(
            Cylinder(
                fields.vector(f"{where}.center", cyl["center"], 3),
                fields.number(f"{where}.radius", cyl["radius"], positive=True),
                fields.number(f"{where}.height", cyl["height"], positive=True),
            )
        )
    forbidden = tuple(
        _polygon(fields, f"forbidden[{i}]", p)
        for i, p in enumerate(fields.items("forbidden", doc.get("forbidden")))
    )
    heightmap = doc.get("heightmap")
    return TerrainMap(
        floor_z=floor,
        boxes=tuple(boxes),
        cylinders=tuple(cylinders),
        forbidden_xy_in_world=forbidden,
        heightmap=None if heightmap is None else _heightmap(fields, heightmap, Path(folder), floor),
        forbidden_clearance_m=forbidden_clearance_m,
        name=name,
    )


def load_terrain(
    path: str | Path, *, forbidden_clearance_m: float = FORBIDDEN_CLEARANCE_M
) -> TerrainMap:
    """Read a terrain file (module docstring): JSON when it ends in .json, else YAML.

    Raises:
        TerrainFileError: the file cannot be read, is not YAML/JSON, or has a malformed
            field (named).
    """
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_TERRAIN_FILE_BYTES:
            raise TerrainFileError(
                f"terrain file {path}: {size} bytes, more than the {MAX_TERRAIN_FILE_BYTES} "
                "a terrain file may hold (put a large height map in its own .npy or PNG)"
            )
        text = path.read_bytes().decode("utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise TerrainFileError(f"terrain file {path}: cannot be read: {exc}") from None
    if path.suffix.lower() == ".json":
        try:
            document = json.loads(text)
        except ValueError as exc:
            raise TerrainFileError(f"terrain file {path}: not JSON: {_one_line(exc)}") from None
    else:
        import yaml

        try:
            document = yaml.load(text, Loader=_loader_without_aliases())
        except yaml.YAMLError as exc:
            raise TerrainFileError(f"terrain file {path}: not YAML: {_one_line(exc)}") from None
    return terrain_from_document(
        document, name=str(path), folder=path.parent, forbidden_clearance_m=forbidden_clearance_m
    )


def _loader_without_aliases() -> type:
    """yaml.SafeLoader refusing aliases (``*name``): a terrain file has no use for them, and
    nested ones expand to a tree of any size from a few lines (a "YAML bomb")."""
    import yaml

    class NoAliases(yaml.SafeLoader):
        def compose_node(self, parent, index):
            if self.check_event(yaml.AliasEvent):
                mark = self.peek_event().start_mark
                raise yaml.composer.ComposerError(
                    None, None, "aliases (*name) are not accepted in a terrain file", mark
                )
            return super().compose_node(parent, index)

    return NoAliases


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def terrain_document(terrain: TerrainMap | None) -> dict[str, Any] | None:
    """What plan.json records for ``--terrain FILE`` (``inputs.terrain``): the content of the
    file as read once by :func:`load_terrain` (:meth:`TerrainMap.to_document`, the height
    map inline); None without a terrain."""
    return None if terrain is None else terrain.to_document()
