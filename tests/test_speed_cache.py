"""The user's cache of ``silo4 robots`` rows (viz/cli/robot_cache.py): a row read back is the
row computed; another URDF, version or row format misses; --no-cache and --clear-cache."""

from __future__ import annotations

from argparse import Namespace
from pathlib import Path

import numpy as np
import pytest

import viz.cli.robot_cache as robot_cache
import viz.cli.robots as robots
from viz.cli.robot_cache import RobotRowCache, cache_folder, description_key


@pytest.fixture(autouse=True)
def fresh_cache(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> Path:
    """An empty cache folder per test."""
    monkeypatch.setenv("SILO4_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


def test_cache_folder_follows_the_environment(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """SILO4_CACHE_DIR wins; else $XDG_CACHE_HOME/silo4; else ~/.cache/silo4."""
    monkeypatch.setenv("SILO4_CACHE_DIR", str(tmp_path / "explicit"))
    assert cache_folder() == tmp_path / "explicit"
    monkeypatch.delenv("SILO4_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_folder() == tmp_path / "xdg" / "silo4"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert cache_folder() == tmp_path / "home" / ".cache" / "silo4"


def test_the_key_changes_with_the_urdf_the_version_and_the_format(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The key hashes the expanded URDF, the silo4kin version, ROW_FORMAT and the code."""
    base = description_key("silo4")
    assert description_key("silo4") == base
    assert description_key("go2") != base
    monkeypatch.setattr(
        "silo4kin.robot_files.read_robot_description", lambda *a, **k: "<robot name='x'/>"
    )
    assert description_key("silo4") != base
    monkeypatch.undo()
    monkeypatch.setattr(robot_cache, "silo4_version", lambda: "99.0")
    assert description_key("silo4") != base
    monkeypatch.undo()
    monkeypatch.setattr(robot_cache, "ROW_FORMAT", robot_cache.ROW_FORMAT + 1)
    assert description_key("silo4") != base
    monkeypatch.undo()
    monkeypatch.setattr(robot_cache, "code_fingerprint", lambda: "an edited checkout")
    assert description_key("silo4") != base


def _counting(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Replace robots.robot_row by a fake one that records the names it computes."""
    computed: list[str] = []

    def fake_row(name: str, **_: object) -> dict[str, object]:
        computed.append(name)
        return {
            "robot": name,
            "family": "mammal",
            "mass_kg": 15.0 + len(computed),
            "range_m": (0.2, 0.3),
            "stride_m": 0.1,
        }

    monkeypatch.setattr(robots, "robot_row", fake_row)
    return computed


def test_a_second_call_reads_the_rows_back(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The second ``silo4 robots`` computes nothing and prints the same table."""
    computed = _counting(monkeypatch)
    assert robots.run(Namespace(only="silo4,go2")) == 0
    first = capsys.readouterr().out
    assert computed == ["silo4", "go2"]
    assert robots.run(Namespace(only="silo4,go2")) == 0
    assert capsys.readouterr().out == first
    assert computed == ["silo4", "go2"]
    assert len(list(RobotRowCache().rows_folder.glob("*.json"))) == 2


def test_no_cache_and_clear_cache_compute_again(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """--no-cache computes every row and writes nothing; --clear-cache empties the cache."""
    computed = _counting(monkeypatch)
    assert robots.run(Namespace(only="silo4", no_cache=True)) == 0
    assert computed == ["silo4"] and not RobotRowCache().rows_folder.exists()
    assert robots.run(Namespace(only="silo4")) == 0
    assert robots.run(Namespace(only="silo4")) == 0
    assert computed == ["silo4", "silo4"]
    assert robots.run(Namespace(only="silo4", clear_cache=True)) == 0
    assert computed == ["silo4", "silo4", "silo4"]
    capsys.readouterr()


def test_a_new_row_replaces_only_the_cache_s_own_files() -> None:
    """A robot's row under a new key deletes its row under the old key, and no file of the
    user's named like the robot."""
    cache = RobotRowCache()
    row = {"robot": "go2", "family": "mammal", "mass_kg": 15.0, "range_m": None}
    cache.put("go2", "a" * 64, row)
    cache.rows_folder.joinpath("go2-notes.json").write_text("a user's file")
    cache.put("go2", "b" * 64, row)
    names = sorted(p.name for p in cache.rows_folder.iterdir())
    assert names == ["go2-" + "b" * 32 + ".json", "go2-notes.json"]
    assert cache.clear() == 1
    assert cache.rows_folder.joinpath("go2-notes.json").read_text() == "a user's file"


def test_a_stale_or_broken_row_is_computed_again(monkeypatch: pytest.MonkeyPatch) -> None:
    """A file of another key or of broken JSON is a miss, not a row."""
    cache = RobotRowCache()
    key = description_key("silo4")
    row = {
        "robot": "silo4",
        "family": "insect",
        "mass_kg": 1.0,
        "range_m": [0.1, 0.2],
        "stride_m": None,
    }
    cache.put("silo4", key, row)
    assert cache.get("silo4", key) == dict(row, range_m=(0.1, 0.2))
    assert cache.get("silo4", "0" * 64) is None
    cache.path_for("silo4", key).write_text("{not json", encoding="utf-8")
    assert cache.get("silo4", key) is None


def test_a_real_row_survives_the_round_trip(capsys: pytest.CaptureFixture[str]) -> None:
    """SILO4's computed row and its cached copy print the same line."""
    assert robots.run(Namespace(only="silo4")) == 0
    first = capsys.readouterr().out
    key = description_key("silo4")
    assert RobotRowCache().get("silo4", key) is not None
    assert robots.run(Namespace(only="silo4")) == 0
    assert capsys.readouterr().out == first


@pytest.mark.parametrize(
    ("preset", "waypoints"),
    [("thesis", [(0.0, 1.0), (1.0, 1.0), (0.0, 2.0)]), ("default", [(0.0, 0.6), (0.4, 0.9)])],
)
def test_height_search_stopping_slow_candidates_picks_what_planning_all_picks(
    monkeypatch: pytest.MonkeyPatch, silo4, preset: str, waypoints: list
) -> None:
    """--height auto, whose candidates stop once slower than the bound, returns the height,
    time and E_n of the same grid search with every candidate planned in full, and every
    candidate it finished has the time the full search found."""
    import planner.path.height as height

    fast = height.best_height(silo4, waypoints, workspace=preset)
    planned = height.plan_at_height

    def in_full(*args, slower_than=None, **kwargs):  # noqa: ANN002, ANN003, ANN202
        return planned(*args, **kwargs)

    monkeypatch.setattr(height, "plan_at_height", in_full)
    full = height.best_height(silo4, waypoints, workspace=preset)
    assert full.stopped_m == ()
    assert (fast.height_m, fast.time_units, fast.normalized_error_m) == (
        full.height_m,
        full.time_units,
        full.normalized_error_m,
    )
    times_full = dict(map(tuple, full.evaluated))
    for h, t in fast.evaluated:
        if h not in fast.stopped_m:
            assert t == times_full[h]
        else:
            assert times_full[h] >= fast.time_units
    assert fast.stopped_m, "nothing was stopped: the test would not see a wrong bound"


def test_the_command_line_flags(fresh_cache: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``silo4 robots --no-cache`` leaves no cache behind; ``--clear-cache`` refills it."""
    from viz.cli.main import main

    assert main(["robots", "--only", "silo4", "--no-cache"]) == 0
    assert not fresh_cache.exists()
    assert main(["robots", "--only", "silo4", "--clear-cache"]) == 0
    assert len(list((fresh_cache / "robots").glob("silo4-*.json"))) == 1
    assert capsys.readouterr().out.count("silo4") == 2


def _table_search(monkeypatch: pytest.MonkeyPatch, units: dict[float, float], limited: bool):
    """best_height over [0.2, 0.3] m where the plan at h takes ``units[h]`` (inf: refused,
    missing: 500 units); ``limited`` False plans every candidate in full."""
    from types import SimpleNamespace

    import numpy as np

    import planner.path.height as height
    from planner.errors import PlanningError
    from planner.gaits.base import NotFaster

    limits: list[tuple[float, float | None]] = []

    def fake_plan(model, waypoints, h, *, slower_than=None, **kwargs):  # noqa: ANN001, ANN003, ANN202
        limits.append((h, slower_than))
        t = units.get(round(h, 6), 500.0)
        if not np.isfinite(t):
            raise PlanningError("refused")
        if limited and slower_than is not None and t >= slower_than:
            raise NotFaster(t)
        return SimpleNamespace(
            trajectory=SimpleNamespace(time_units=np.array([0.0, t])),
            position_walked_in_world=np.zeros((1, 2)),
            waypoints_in_world=np.full((1, 2), h),
            preset=SimpleNamespace(load=None, ground_clearance_m=0.0, torque_headroom=0.85),
        )

    monkeypatch.setattr(height, "plan_at_height", fake_plan)
    monkeypatch.setattr(
        height,
        "as_planning_model",
        lambda robot: SimpleNamespace(robot=robot, planning_robot=robot),
    )
    monkeypatch.setattr(height, "feasible_height_range", lambda robot, preset: (0.2, 0.3))
    monkeypatch.setattr(height, "check_search_budget", lambda *args: None)
    monkeypatch.setattr(height, "check_static_effort", lambda *args: None)
    monkeypatch.setattr(height, "check_ground_clearance", lambda *args, **kwargs: None)
    return height.best_height(None, [(0.0, 1.0)]), limits


def _assert_evaluates_as_the_full_search(fast, full) -> None:  # noqa: ANN001
    """The bounded search evaluated the same heights as the full one, each with the full
    search's time, or stopped where the full time is slower than the choice."""
    assert {h for h, _ in full.evaluated} == {h for h, _ in fast.evaluated}
    times_full = dict(map(tuple, full.evaluated))
    for h, t in fast.evaluated:
        assert t == times_full[h] or (h in fast.stopped_m and times_full[h] > fast.time_units)


def test_height_search_plans_again_what_it_stopped_below_the_final_bound(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """With one coarse time known, a coarse candidate is stopped at PROVISIONAL_FACTOR times
    that time; if the search ends with fewer than REFINE_COUNT faster times, it is planned
    again (here in full), so the refined heights, the choice and every finished time are
    those of the full search."""
    from planner.path.height import PROVISIONAL_FACTOR

    # middle-out order: 0.24, 0.26, 0.22, 0.28, 0.2, 0.3; only 0.24 and 0.22 walk
    units = {0.24: 100.0, 0.22: 130.0, 0.26: float("inf"), 0.28: float("inf")}
    units.update({0.2: float("inf"), 0.3: float("inf"), 0.215: 90.0, 0.245: 95.0})
    fast, limits = _table_search(monkeypatch, units, limited=True)
    full, _ = _table_search(monkeypatch, units, limited=False)
    assert (fast.height_m, fast.time_units) == (full.height_m, full.time_units) == (0.215, 90.0)
    provisional = float(np.nextafter(100.0 * PROVISIONAL_FACTOR, np.inf))
    assert (0.22, provisional) in limits  # stopped at the best so far x the factor
    assert (0.22, None) in limits  # then planned in full: no second time was found
    _assert_evaluates_as_the_full_search(fast, full)


def test_height_search_plans_again_first_what_stopped_soonest(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """With one coarse time known (0.24 m, 100 units), 0.26 m (200) and 0.22 m (130) are
    stopped at PROVISIONAL_FACTOR (1.25) times it; the search then needs a second time, and
    plans again first the height whose gait stopped at the lesser time (0.22 m, in full):
    its 130 units stop 0.26 m instead of 0.26 m being planned in full (go2 on the thesis
    straight path planned a height of 870 units in full so, 10 s of a 46 s search)."""
    # middle-out order: 0.24, 0.26, 0.22, 0.28, 0.2, 0.3
    units = {0.24: 100.0, 0.26: 200.0, 0.22: 130.0}
    units.update({0.28: float("inf"), 0.2: float("inf"), 0.3: float("inf")})
    fast, limits = _table_search(monkeypatch, units, limited=True)
    full, _ = _table_search(monkeypatch, units, limited=False)
    assert (fast.height_m, fast.time_units) == (full.height_m, full.time_units) == (0.24, 100.0)
    assert (0.22, None) in limits  # planned again in full: the second time
    assert (0.26, None) not in limits  # not planned in full
    _assert_evaluates_as_the_full_search(fast, full)


def test_height_search_does_not_plan_again_what_stopped_beyond_the_new_bound(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A height stopped below the final second-best coarse time is not planned again when
    its gaits stopped at or beyond the new limit (NotFaster's value, the least over the
    gaits: Fastest): it would stop at the same steps. 0.26 m stopped at 200 units against
    the first bound 125; the second time is 130: 0.26 m is planned once."""
    from planner.path.height import PROVISIONAL_FACTOR

    units = {0.24: 100.0, 0.26: 200.0, 0.22: 130.0}
    units.update({0.28: float("inf"), 0.2: float("inf"), 0.3: float("inf")})
    fast, limits = _table_search(monkeypatch, units, limited=True)
    full, _ = _table_search(monkeypatch, units, limited=False)
    assert (fast.height_m, fast.time_units) == (full.height_m, full.time_units)
    provisional = float(np.nextafter(100.0 * PROVISIONAL_FACTOR, np.inf))
    assert [limit for h, limit in limits if h == 0.26] == [provisional]
    assert 0.26 in fast.stopped_m
    assert {h for h, _ in full.evaluated} == {h for h, _ in fast.evaluated}


def test_height_search_lets_a_coarse_height_about_as_fast_as_the_first_finish(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """With one coarse time known (0.24 m, 100 units), 0.26 m (110 units, within
    PROVISIONAL_FACTOR of it) is planned once, to its end, instead of being stopped at 100
    and planned again once the second time is known."""
    from planner.path.height import PROVISIONAL_FACTOR

    assert 110.0 < 100.0 * PROVISIONAL_FACTOR
    units = {0.24: 100.0, 0.26: 110.0, 0.22: 150.0}
    units.update({0.28: float("inf"), 0.2: float("inf"), 0.3: float("inf")})
    fast, limits = _table_search(monkeypatch, units, limited=True)
    full, _ = _table_search(monkeypatch, units, limited=False)
    assert (fast.height_m, fast.time_units) == (full.height_m, full.time_units) == (0.24, 100.0)
    assert [limit for h, limit in limits if h == 0.26] == [
        float(np.nextafter(100.0 * PROVISIONAL_FACTOR, np.inf))
    ]
    assert 0.26 not in fast.stopped_m and dict(map(tuple, fast.evaluated))[0.26] == 110.0
