"""viz/cli/progress.py: a bar at a terminal, silence otherwise."""

from __future__ import annotations

import io
import sys

import pytest

from viz.cli.progress import progress_bar, track


def test_progress_is_silent_without_a_terminal(monkeypatch: pytest.MonkeyPatch,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    """stdout not a terminal: no bar, nothing on stdout or stderr; items pass through."""
    assert list(track(range(5), "x")) == [0, 1, 2, 3, 4]
    with progress_bar(3, "y") as bar:
        bar.update()
    assert capsys.readouterr() == ("", "")


def test_progress_bar_at_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    """stdout a terminal: a tqdm bar on stderr (shown at once when the delay is 0)."""
    class Tty(io.StringIO):
        def isatty(self) -> bool:
            return True

    err = io.StringIO()
    monkeypatch.setattr(sys, "stdout", Tty())
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr("viz.cli.progress.MIN_VISIBLE_S", 0.0)
    assert list(track([1, 2, 3], "cases")) == [1, 2, 3]
    assert "cases" in err.getvalue() and "/3 [" in err.getvalue()  # tqdm throttles redraws
