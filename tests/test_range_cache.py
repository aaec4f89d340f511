"""The user's cache of feasible height ranges (viz/cli/range_cache.py): ``silo4 plan`` reads
back the ranges an earlier run computed and plans the same; another robot description or
other planner code misses; a malformed file is a miss; SILO4_NO_CACHE and --clear-cache."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import viz.cli.range_cache as range_cache
from planner.workspace import heights
from planner.workspace.heights import (
    feasible_height_range,
    known_feasible_ranges,
    remember_feasible_ranges,
)
from silo4kin.robot import load_robot
from viz.cli.main import EXIT_BAD_INPUT, EXIT_OK, main
from viz.cli.range_cache import RangeCache, robot_key


@pytest.fixture(autouse=True)
def fresh_cache(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> Path:
    """An empty cache folder per test, the cache on."""
    monkeypatch.setenv("SILO4_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv(range_cache.NO_CACHE_ENV, raising=False)
    return tmp_path / "cache"


def _plan(out: Path, height: str = "0.4", *extra: str) -> int:
    return main(
        [
            "plan",
            "--waypoints",
            "0,1 0,1.6",
            "--height",
            height,
            "--out",
            str(out),
            "--samples-per-unit",
            "10",
            "--no-html",
            "--no-plots",
            *extra,
        ]
    )


def _range_files(cache: Path) -> list[Path]:
    return sorted((cache / "ranges").glob("*.json"))


def test_remembered_ranges_are_the_ones_computed() -> None:
    """A fresh robot given another robot's known ranges answers with them without computing
    (the grid's heights are never asked), and computes the same range itself."""
    first = load_robot()
    computed = feasible_height_range(first)
    known = known_feasible_ranges(first)
    assert known == {("default", True, False): computed}

    second = load_robot()
    remember_feasible_ranges(second, known)
    asked: list[float] = []
    original = heights._height_ok

    def counting(robot, h, preset, clear_stance):  # noqa: ANN001
        asked.append(h)
        return original(robot, h, preset, clear_stance)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(heights, "_height_ok", counting)
        assert feasible_height_range(second) == computed
        assert feasible_height_range(second, "default", True, False) == computed
        assert asked == []
        assert feasible_height_range(load_robot()) == computed  # computed again: same
        assert asked


def test_a_second_plan_reads_the_range_back_and_plans_the_same(
    tmp_path: Path, fresh_cache: Path, monkeypatch: pytest.MonkeyPatch, capsys
) -> None:
    """A ``silo4 plan`` refused for a height above the range keeps the range it computed to
    say so under the robot's key; the next plan reads it (a range written there by hand is
    the one it refuses a height by) and plans what it plans without the cache."""
    assert _plan(tmp_path / "a", "0.7") == EXIT_BAD_INPUT
    files = _range_files(fresh_cache)
    assert len(files) == 1
    record = json.loads(files[0].read_text())
    assert record["key"] == robot_key(load_robot())
    lo, hi = feasible_height_range(load_robot())
    assert record["ranges"] == [["default", True, False, lo, hi]]
    assert f"[{lo:.4g}, {hi:.4g}] m" in capsys.readouterr().err

    assert _plan(tmp_path / "b") == EXIT_OK
    monkeypatch.setenv(range_cache.NO_CACHE_ENV, "1")
    assert _plan(tmp_path / "c") == EXIT_OK
    monkeypatch.delenv(range_cache.NO_CACHE_ENV)
    b = np.load(tmp_path / "b" / "trajectory.npz")
    c = np.load(tmp_path / "c" / "trajectory.npz")
    assert sorted(b.files) == sorted(c.files)
    for name in b.files:
        np.testing.assert_array_equal(b[name], c[name])

    # the file is what the next run believes: a narrower range refuses 0.4 m
    record["ranges"] = [["default", True, False, 0.3, 0.35]]
    files[0].write_text(json.dumps(record))
    capsys.readouterr()
    assert _plan(tmp_path / "d") == EXIT_BAD_INPUT
    assert "[0.3, 0.35] m" in capsys.readouterr().err


def test_another_description_or_other_code_misses(monkeypatch: pytest.MonkeyPatch) -> None:
    """The key hashes the robot as the planner sees it and the planner's source."""
    silo4 = load_robot()
    base = robot_key(silo4)
    assert robot_key(load_robot()) == base
    assert robot_key(load_robot(None, {"L2": "0.31"})) != base  # a longer femur
    assert robot_key(load_robot("solo12")) != base
    range_cache.code_fingerprint.cache_clear()
    try:
        monkeypatch.setattr(range_cache, "RANGE_FORMAT", range_cache.RANGE_FORMAT + 1)
        assert robot_key(silo4) != base
    finally:
        monkeypatch.undo()
        range_cache.code_fingerprint.cache_clear()
    assert robot_key(silo4) == base
    # one byte more in the planner's source: another fingerprint
    read_bytes = Path.read_bytes

    def edited(path: Path) -> bytes:
        return read_bytes(path) + (b"#" if path.name == "heights.py" else b"")

    range_cache.code_fingerprint.cache_clear()
    try:
        monkeypatch.setattr(Path, "read_bytes", edited)
        assert robot_key(silo4) != base
    finally:
        monkeypatch.undo()
        range_cache.code_fingerprint.cache_clear()


@pytest.mark.parametrize(
    "text",
    [
        "not json",
        '{"key": "another", "ranges": [["default", true, false, 0.2, 0.5]]}',
        '{"key": "KEY", "ranges": [["default", true, false, 0.5, 0.2]]}',
        '{"key": "KEY", "ranges": [["default", 1, false, 0.2, 0.5]]}',
        '{"key": "KEY", "ranges": [["default", true, false, "0.2", 0.5]]}',
        '{"key": "KEY", "ranges": [["default", true, false, NaN, 0.5]]}',
        '{"key": "KEY", "ranges": [["default", true, false, 0.2]]}',
    ],
)
def test_a_malformed_file_is_a_miss(fresh_cache: Path, text: str) -> None:
    """Whatever the file holds that is not a record of this key's ranges reads as none."""
    cache = RangeCache()
    key = "0" * 64
    cache.ranges_folder.mkdir(parents=True)
    cache.path_for(key).write_text(text.replace("KEY", key))
    assert cache.get(key) == {}
    cache.put(key, {("default", True, False): (0.2, 0.5)})  # replaced by a good record
    assert cache.get(key) == {("default", True, False): (0.2, 0.5)}


def test_no_cache_and_clear_cache(
    tmp_path: Path, fresh_cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """SILO4_NO_CACHE=1: nothing written; ``silo4 robots --clear-cache`` deletes the ranges
    and rows, and no file of the user's in their folders."""
    monkeypatch.setenv(range_cache.NO_CACHE_ENV, "1")
    assert _plan(tmp_path / "a", "0.7") == EXIT_BAD_INPUT
    assert not (fresh_cache / "ranges").exists()
    monkeypatch.delenv(range_cache.NO_CACHE_ENV)
    assert _plan(tmp_path / "b", "0.7") == EXIT_BAD_INPUT
    assert len(_range_files(fresh_cache)) == 1
    mine = [fresh_cache / "ranges" / "notes.txt", fresh_cache / "ranges" / "my-ranges.json"]
    mine.append(fresh_cache / "robots" / "notes.json")
    (fresh_cache / "robots").mkdir()
    for path in mine:
        path.write_text("a user's file")
    monkeypatch.setattr("viz.cli.robots.robot_names", lambda: ("silo4",))
    assert main(["robots", "--clear-cache", "--no-cache"]) == EXIT_OK
    assert _range_files(fresh_cache) == [mine[1]]
    for path in mine:
        assert path.read_text() == "a user's file"


def test_silo4_robots_and_silo4_plan_share_the_ranges(
    tmp_path: Path, fresh_cache: Path, monkeypatch: pytest.MonkeyPatch, capsys
) -> None:
    """The ranges ``silo4 robots`` computed for a row are the ones ``silo4 plan`` then refuses
    a height by, with no height of the grid asked again; ``--no-cache`` keeps none."""
    monkeypatch.setattr("viz.cli.robots.robot_names", lambda: ("silo4",))
    assert main(["robots", "--no-cache"]) == EXIT_OK
    assert not (fresh_cache / "ranges").exists()
    assert main(["robots"]) == EXIT_OK
    (file,) = _range_files(fresh_cache)
    lo, hi = feasible_height_range(load_robot())
    rows = json.loads(file.read_text())["ranges"]
    assert ["default", True, False, lo, hi] in rows
    assert len(rows) == 2  # and the any-direction range

    def refuse(*args: object) -> bool:
        raise AssertionError("a height of the grid was asked again")

    monkeypatch.setattr(heights, "_height_ok", refuse)
    capsys.readouterr()
    assert _plan(tmp_path / "a", "0.7") == EXIT_BAD_INPUT
    assert f"[{lo:.4g}, {hi:.4g}] m" in capsys.readouterr().err
