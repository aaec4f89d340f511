"""The height range `silo4 robots` prints is one the planner accepts, its printed ends too."""

from __future__ import annotations

import pytest

from planner.workspace.layout import feasible_height_range, workspace_for
from viz.cli.robots import inward_range_text


@pytest.mark.parametrize(
    "low,high,text",
    [(0.2, 0.6056, "0.200-0.605"), (0.1744, 0.3978, "0.175-0.397"), (0.2, 0.6, "0.200-0.600")],
)
def test_printed_range_is_rounded_inwards(low, high, text):
    assert inward_range_text(low, high) == text


def test_printed_ends_of_silo4_are_planned(silo4):
    """SILO4's range [0.2, 0.6056] m prints as 0.200-0.605: both printed ends get a
    workspace (0.606, the nearest rounding of the top, would not)."""
    low, high = feasible_height_range(silo4)
    shown = [float(v) for v in inward_range_text(low, high).split("-")]
    assert low <= shown[0] <= shown[1] <= high
    for h in shown:
        assert workspace_for(silo4, h).stride_m > 0
