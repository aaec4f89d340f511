"""Terrain files (planner/terrain/terrain_file.py): every example parses, a document reads
back to the same terrain, and a malformed file is refused with one line naming the field."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from planner.errors import PlannerInputError
from planner.terrain import TerrainFileError, TerrainMap, load_terrain, terrain_from_document

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "terrain"
EXAMPLE_FILES = sorted(EXAMPLES.glob("*.yaml")) + sorted(EXAMPLES.glob("go2/*.yaml"))

#: What each example holds: (boxes, cylinders, forbidden polygons, height map, floor).
EXPECTED = {
    "block.yaml": (1, 0, 0, False, 0.0),
    "ditch.yaml": (0, 0, 1, False, 0.0),
    "gap.yaml": (2, 0, 0, False, None),
    "ramp.yaml": (2, 0, 0, False, 0.0),
    "rough.yaml": (0, 0, 0, True, 0.0),
    "stairs.yaml": (5, 0, 0, False, 0.0),
    "stones.yaml": (2, 14, 0, False, None),
    "go2/stones.yaml": (2, 10, 0, False, None),
}


def test_the_examples_are_the_listed_scenarios():
    """examples/terrain holds the issue's scenarios, no more, no fewer."""
    assert sorted(str(p.relative_to(EXAMPLES)) for p in EXAMPLE_FILES) == sorted(EXPECTED)


@pytest.mark.parametrize("path", EXAMPLE_FILES, ids=lambda p: p.name)
def test_every_example_parses_to_what_it_says(path):
    """Each example file loads into a TerrainMap holding the parts its comments describe."""
    terrain = load_terrain(path)
    assert isinstance(terrain, TerrainMap)
    boxes, cylinders, forbidden, heightmap, floor = EXPECTED[str(path.relative_to(EXAMPLES))]
    assert len(terrain.boxes) == boxes
    assert len(terrain.cylinders) == cylinders
    assert len(terrain.forbidden_xy_in_world) == forbidden
    assert (terrain.heightmap is not None) == heightmap
    assert terrain.floor_z == floor


@pytest.mark.parametrize("path", EXAMPLE_FILES, ids=lambda p: p.name)
def test_the_document_reads_back_to_the_same_ground(path, tmp_path):
    """to_document() is itself a terrain file (JSON, the height map inline): read back, it
    gives the same document and the same heights and normals on random points."""
    terrain = load_terrain(path)
    document = terrain.to_document()
    copy = tmp_path / "copy.json"
    copy.write_text(json.dumps(document))
    again = load_terrain(copy)
    assert again.to_document() == document
    xy = np.random.default_rng(3).uniform([-1.5, -1.5], [1.5, 4.5], size=(500, 2))
    np.testing.assert_array_equal(again.height_at(xy), terrain.height_at(xy))
    np.testing.assert_array_equal(again.normal_at(xy), terrain.normal_at(xy))


def test_an_empty_file_is_flat_ground(tmp_path):
    """Every key is optional: an empty file is the floor at z = 0."""
    path = tmp_path / "empty.yaml"
    path.write_text("")
    terrain = load_terrain(path)
    assert terrain.floor_z == 0.0 and not terrain.obstacles()


def test_a_byte_order_mark_and_crlf_are_read(tmp_path):
    """A file saved by a Windows editor (UTF-8 BOM, CRLF) reads as the same terrain."""
    text = "floor: 0.1\r\nboxes:\r\n  - center: [1, 0, 0.05]\r\n    size: [0.4, 1, 0.1]\r\n"
    for suffix, body in (
        (".yaml", text),
        (
            ".json",
            json.dumps(
                {"floor": 0.1, "boxes": [{"center": [1, 0, 0.05], "size": [0.4, 1, 0.1]}]}, indent=1
            ).replace("\n", "\r\n"),
        ),
    ):
        path = tmp_path / f"bom{suffix}"
        path.write_bytes(b"\xef\xbb\xbf" + body.encode())
        terrain = load_terrain(path)
        assert terrain.floor_z == 0.1 and len(terrain.boxes) == 1, suffix


@pytest.mark.parametrize(
    "text, field",
    [
        ("floor: high\n", "floor"),
        ("floor: 0\nstairs: []\n", "unknown field 'stairs'"),
        ("boxes: [{center: [1, 0], size: [1, 1, 1]}]\n", "boxes[0].center"),
        ("boxes: [{center: [1, 0, 0], size: [1, -1, 1]}]\n", "boxes[0].size[1]"),
        ("boxes: [{center: [1, 0, 0]}]\n", "boxes[0]: 'size' missing"),
        ("boxes: [{center: [1, 0, 0], size: [1, 1, 1], rpy: [0, 0]}]\n", "boxes[0].rpy"),
        ("boxes: {center: [1, 0, 0]}\n", "boxes: a list expected"),
        ("cylinders: [{center: [1, 0, 0], radius: 0, height: 1}]\n", "cylinders[0].radius"),
        ("cylinders: [{center: [1, 0, 0], radius: 1}]\n", "cylinders[0]: 'height' missing"),
        ("forbidden: [[[0, 0], [1, 0]]]\n", "forbidden[0]: a list of at least 3"),
        ("forbidden: [[[0, 0], [2, 0], [1, 0.2], [1, 2]]]\n", "forbidden[0]: the polygon is not"),
        ("forbidden: [[[0, 0], [1, 0], [x, 1]]]\n", "forbidden[0][2][0]"),
        ("heightmap: {file: m.npy, origin: [0, 0]}\n", "heightmap: 'resolution' missing"),
        ("heightmap: {file: m.npy, resolution: 2e-2, origin: [0, 0]}\n", "with a point"),
        ("heightmap: {resolution: 0.1, origin: [0, 0]}\n", "give one of 'file' and 'heights'"),
        (
            "heightmap: {heights: [[0, 1], [0]], resolution: 0.1, origin: [0, 0]}\n",
            "heightmap.heights",
        ),
        ("heightmap: {heights: [[0, 1]], resolution: 0.1, origin: [0, 0]}\n", "at least 2 x 2"),
        (
            "heightmap: {heights: [[0, -1], [0, 0]], resolution: 0.1, origin: [0, 0]}\n",
            "heights below 0",
        ),
        ("heightmap: {file: missing.npy, resolution: 0.1, origin: [0, 0]}\n", "heightmap.file"),
        ("heightmap: {file: m.png, resolution: 0.1, origin: [0, 0]}\n", "heightmap.z_range"),
        ("boxes: [1, 2\n", "not YAML"),
        ("- 1\n- 2\n", "the file: a mapping"),
    ],
)
def test_a_malformed_file_is_refused_in_one_line_naming_the_field(tmp_path, text, field):
    """Each malformed field is refused with a TerrainFileError (a PlannerInputError: the
    CLI's exit 2) whose one line names the file and the field."""
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(TerrainFileError) as info:
        load_terrain(path)
    message = str(info.value)
    assert isinstance(info.value, PlannerInputError)
    assert "\n" not in message and str(path) in message
    assert field in message, message


def test_a_missing_file_and_bad_json_are_refused(tmp_path):
    """A file that is not there, or not JSON, is one line naming it."""
    with pytest.raises(TerrainFileError, match="cannot be read"):
        load_terrain(tmp_path / "nowhere.yaml")
    bad = tmp_path / "bad.json"
    bad.write_text("{floor: 0}")
    with pytest.raises(TerrainFileError, match="not JSON"):
        load_terrain(bad)


def test_a_heightmap_file_is_read_beside_the_terrain_file(tmp_path):
    """heightmap.file is read relative to the terrain file's folder; .npy and a 16-bit PNG
    (mapped onto z_range, image row 0 the highest y) give the same grid."""
    from PIL import Image

    heights = np.array([[0.0, 0.01, 0.02], [0.03, 0.04, 0.05]])
    np.save(tmp_path / "m.npy", heights)
    samples = np.round(heights / 0.05 * 65535).astype(np.uint16)[::-1]
    Image.fromarray(samples).save(tmp_path / "m.png")
    (tmp_path / "npy.yaml").write_text("heightmap: {file: m.npy, resolution: 0.1, origin: [0, 0]}")
    (tmp_path / "png.yaml").write_text(
        "heightmap: {file: m.png, resolution: 0.1, origin: [0, 0], z_range: [0.0, 0.05]}"
    )
    from_npy = load_terrain(tmp_path / "npy.yaml").heightmap
    from_png = load_terrain(tmp_path / "png.yaml").heightmap
    assert from_npy is not None and from_png is not None
    np.testing.assert_array_equal(from_npy.heights, heights)
    # 16 bits over 0.05 m: a sample is within half a step (0.05 / 65535 / 2) of the value
    np.testing.assert_allclose(from_png.heights, heights, rtol=0, atol=0.05 / 65535 / 2 + 1e-15)


def test_the_document_of_no_terrain_is_flat_ground():
    """terrain_from_document(None) is the floor at 0 (a plan.json without a terrain)."""
    assert terrain_from_document(None).to_document()["floor"] == 0.0


def test_rough_npy_is_what_make_rough_writes():
    """examples/terrain/rough.npy is make_rough.py's seeded map (0 .. 0.03 m), bit for bit."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_rough", EXAMPLES / "make_rough.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    heights = module.rough_heights()
    np.testing.assert_array_equal(np.load(EXAMPLES / "rough.npy"), heights)
    assert heights.min() == 0.0 and heights.max() == pytest.approx(module.MAX_HEIGHT_M)
