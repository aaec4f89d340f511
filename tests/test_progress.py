"""viz/cli/progress.py: a bar at a terminal, silence otherwise."""

from __future__ import annotations

import io
import sys

import pytest

from viz.cli.progress import progress_bar, track, waiting


class Tty(io.StringIO):
    """A terminal stand-in."""

    def isatty(self) -> bool:
        return True


def test_progress_is_silent_without_a_terminal(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """stderr not a terminal: no bar, nothing on stdout or stderr; items pass through."""
    assert list(track(range(5), "x")) == [0, 1, 2, 3, 4]
    with progress_bar(3, "y") as bar:
        bar.update()
    with waiting("z"):
        pass
    assert capsys.readouterr() == ("", "")


def test_progress_bar_at_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    """stderr a terminal: a tqdm bar on stderr (shown at once when the delay is 0), even
    when stdout is piped."""
    err = Tty()
    monkeypatch.setattr(sys, "stdout", io.StringIO())
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr("viz.cli.progress.MIN_VISIBLE_S", 0.0)
    assert list(track([1, 2, 3], "cases")) == [1, 2, 3]
    assert "cases" in err.getvalue() and "/3 [" in err.getvalue()  # tqdm throttles redraws


def test_waiting_line_at_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    """stderr a terminal: the elapsed-time line appears, then is erased; stdout untouched."""
    import time

    err, out = Tty(), io.StringIO()
    monkeypatch.setattr(sys, "stdout", out)
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr("viz.cli.progress.MIN_VISIBLE_S", 0.0)
    monkeypatch.setattr("viz.cli.progress.REDRAW_S", 0.01)
    with waiting("--height auto"):
        time.sleep(0.05)
    assert "\r--height auto ... 0 s" in err.getvalue()
    assert err.getvalue().endswith("\r\033[K") and out.getvalue() == ""


def test_robots_shows_which_robot_is_being_computed(monkeypatch: pytest.MonkeyPatch) -> None:
    """``silo4 robots`` at a terminal: a bar on stderr naming the robot; stdout holds the
    table only (the same as when piped)."""
    from argparse import Namespace

    import viz.cli.robots as robots

    row = {
        "robot": "go2",
        "family": "mammal",
        "mass_kg": 15.0,
        "range_m": (0.2, 0.3),
        "stride_m": 0.1,
    }
    monkeypatch.setattr(robots, "robot_row", lambda name, **_: dict(row, robot=name))
    monkeypatch.setattr("viz.cli.progress.MIN_VISIBLE_S", 0.0)
    err, out = Tty(), io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr(sys, "stdout", out)
    assert robots.run(Namespace(only="silo4,go2", no_cache=True)) == 0  # rows computed
    assert "robots" in err.getvalue() and "go2: reachable sets" in err.getvalue()
    assert out.getvalue().splitlines() == [
        robots.HEADER,
        robots.format_row(dict(row, robot="silo4")),
        robots.format_row(row),
    ]
