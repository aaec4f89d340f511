"""Hostile terrain files through ``silo4 plan --terrain``: each one exits 2 with one line
naming the file and the field, before any planning, and writes nothing."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from planner.terrain.terrain_file import MAX_HEIGHTMAP_SAMPLES, MAX_TERRAIN_FILE_BYTES
from viz.cli.main import main

MAP = "heightmap: {file: map.%s, resolution: 0.05, origin: [-0.5, 0.5]%s}\n"


def _npy(array) -> Callable[[Path], str]:
    def write(folder: Path) -> str:
        np.save(folder / "map.npy", array, allow_pickle=True)
        return MAP % ("npy", "")

    return write


def _text(text: str) -> Callable[[Path], str]:
    return lambda folder: text


def _garbage_npy(folder: Path) -> str:
    (folder / "map.npy").write_text("hello")
    return MAP % ("npy", "")


def _enormous_npy(folder: Path) -> str:
    """A .npy whose header claims more samples than the limit (its data is never read: a
    sparse file of that size)."""
    side = int(np.sqrt(MAX_HEIGHTMAP_SAMPLES)) + 1
    header = np.lib.format.header_data_from_array_1_0(np.zeros((1, 1)))
    header["shape"] = (side, side)
    with open(folder / "map.npy", "wb") as f:
        np.lib.format.write_array_header_1_0(f, header)
        f.seek(8 * side * side - 1, 1)
        f.write(b"\0")
    return MAP % ("npy", "")


def _png_without_range(folder: Path) -> str:
    from PIL import Image

    Image.fromarray(np.zeros((4, 4), dtype=np.uint16)).save(folder / "map.png")
    return MAP % ("png", "")


def _bomb(folder: Path) -> str:
    lines = ["a: &a [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]"]
    for k in "bcdefghi":
        prev = chr(ord(k) - 1)
        lines.append(f"{k}: &{k} [*{prev}, *{prev}, *{prev}, *{prev}, *{prev}, *{prev}]")
    lines.append("heightmap: {heights: *i, resolution: 0.05, origin: [0, 0]}")
    return "\n".join(lines) + "\n"


def _fifty_megabytes(folder: Path) -> str:
    return "floor: 0.0\n" + "#" * 50_000_000 + "\n"


CASES = {
    "nan center": (
        _text("boxes: [{center: [.nan, 0, 0], size: [1, 1, 1]}]\n"),
        "boxes[0].center[0]",
    ),
    "inf size": (_text("boxes: [{center: [0, 1, 0], size: [.inf, 1, 1]}]\n"), "boxes[0].size[0]"),
    "negative size": (
        _text("boxes: [{center: [0, 1, 0], size: [1, -1, 1]}]\n"),
        "boxes[0].size[1]",
    ),
    "nan radius": (
        _text("cylinders: [{center: [0, 1, 0], radius: .nan, height: 1}]\n"),
        "cylinders[0].radius",
    ),
    "inf floor": (_text("floor: .inf\n"), "floor"),
    "missing map": (_text(MAP % ("npy", "")), "heightmap.file"),
    "1-D map": (_npy(np.zeros(10)), "heightmap"),
    "3-D map": (_npy(np.zeros((3, 3, 3))), "heightmap"),
    "text map": (_npy(np.array([["a", "b"], ["c", "d"]])), "heightmap.file"),
    "complex map": (_npy(np.zeros((3, 3), dtype=complex)), "heightmap.file"),
    "bool map": (_npy(np.zeros((3, 3), dtype=bool)), "heightmap.file"),
    "object map": (_npy(np.array([[None, 1], [2, 3]], dtype=object)), "heightmap.file"),
    "not a .npy": (_garbage_npy, "heightmap.file"),
    "nan in map": (_npy(np.array([[0.0, np.nan], [0.0, 0.0]])), "heightmap"),
    "enormous map": (_enormous_npy, "heightmap.file"),
    "png without z_range": (_png_without_range, "heightmap.z_range"),
    "two vertices": (_text("forbidden: [[[0, 0], [1, 0]]]\n"), "forbidden[0]"),
    "self-intersecting": (
        _text("forbidden: [[[0, 0], [1, 1], [1, 0], [0, 1]]]\n"),
        "forbidden[0]",
    ),
    "pentagram": (
        _text(
            "forbidden: [["
            + ", ".join(
                f"[{np.cos(a):.6f}, {np.sin(a):.6f}]" for a in 2 * np.pi * np.arange(0, 10, 2) / 5
            )
            + "]]\n"
        ),
        "forbidden[0]",
    ),
    "start over the void": (
        _text("floor: null\nboxes: [{center: [0, 2, 0.05], size: [1, 1, 0.1]}]\n"),
        "floor",
    ),
    "yaml bomb": (_bomb, "aliases"),
    "50 MB file": (_fifty_megabytes, f"more than the {MAX_TERRAIN_FILE_BYTES}"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_hostile_terrain_exits_2_in_one_line_naming_the_field(case, tmp_path, capsys):
    write, field = CASES[case]
    terrain = tmp_path / "terrain.yaml"
    terrain.write_text(write(tmp_path))
    out = tmp_path / "run"
    code = main(
        [
            "plan",
            "--waypoints",
            "0,1",
            "--height",
            "0.4",
            "--no-plots",
            "--no-html",
            "--terrain",
            str(terrain),
            "--out",
            str(out),
        ]
    )
    err = capsys.readouterr().err
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert str(terrain) in err and field in err, err
    assert len(err) < 600, err  # one readable line, not a dump of the input
    assert not out.exists()


def test_a_convex_polygon_either_way_round_is_accepted(tmp_path):
    """The winding check refuses stars, not a square listed clockwise or counter-clockwise."""
    from planner.terrain import load_terrain

    for square in ("[[0, 0], [1, 0], [1, 1], [0, 1]]", "[[0, 1], [1, 1], [1, 0], [0, 0]]"):
        path = tmp_path / "square.yaml"
        path.write_text(f"forbidden: [{square}]\n")
        assert len(load_terrain(path).forbidden_xy_in_world) == 1
