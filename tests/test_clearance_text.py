"""A clearance under its threshold is written rounded down to 0.1 mm
(planner/trajectory/clearance_text.py): 9.96 mm under a 10 mm rule read "10.0 mm"."""

import pytest

from planner.trajectory.clearance_text import mm_down


@pytest.mark.parametrize(
    ("value_m", "text"),
    [
        (0.00996, "9.9"),  # rounded to nearest this read 10.0, the threshold it failed
        (0.0012, "1.2"),  # on a tenth: stays there (0.0012 * 1e4 is 11.999999999999998)
        (0.01, "10.0"),
        (0.0, "0.0"),
        (-0.0005, "-0.5"),
        (-0.00049, "-0.5"),  # down, not towards zero
    ],
)
def test_a_clearance_is_rounded_down_to_a_tenth_of_a_millimetre(value_m, text):
    assert mm_down(value_m) == text


def test_a_value_under_a_threshold_never_reads_as_the_threshold():
    for k in range(1, 1000):
        value = 0.01 - k * 1e-7  # 9.9999 ... 9.9001 mm
        assert float(mm_down(value)) < 10.0
