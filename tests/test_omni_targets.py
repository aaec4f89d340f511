"""Issue 11 part B targets over the 9 Chapter 6 cases, from the metrics.json `silo4 cases`
writes (default settings; 10 samples per unit to keep CI cost down: the step list, times
and waypoint arrivals do not depend on the sampling).

Held: E_n <= 0.01 m on Tables 6.1 and 6.2 and <= the thesis's on 6.3, whole-body margin >=
0.02 m with a leg up, no spinning cycle (the body keeps its heading), URDF velocity and
effort limits at unit time 1 s (`silo4 cases` refuses a case that breaks one). Time <= 0.7x
the thesis's holds on seven cases; the two at h = 0.6 m on the straight path and the reduced
circle are strict xfails (docs/gaits.md gives the measured ratios and why), so they turn red
the day they pass and the xfail must go.
"""

from __future__ import annotations

import json

import pytest

from planner.cases import THESIS_TABLES, thesis_cases
from planner.verify import SAMPLE_MARGIN_SLACK_M
from viz.cli import main

CASES = [(c.path, c.height_m) for c in thesis_cases(presets=("default",))]
#: Cases whose time is <= 0.7x the thesis's with the omnidirectional gait (measured).
FAST_ENOUGH = {("straight", 0.2), ("straight", 0.4), ("circle", 0.2), ("circle", 0.4),
               ("circle", 0.6), ("circle-reduced", 0.2), ("circle-reduced", 0.4)}


@pytest.fixture(scope="module")
def metrics(tmp_path_factory) -> dict[tuple[str, float], dict]:
    out = tmp_path_factory.mktemp("cases")
    rc = main(["cases", "--out", str(out), "--workspaces", "default", "--no-ditch",
               "--samples-per-unit", "10", "--no-html", "--no-plots", "--no-csv",
               "--no-torques"])
    assert rc == 0
    return {(p, h): json.loads((out / f"{p}_h{h:.1f}_default" / "metrics.json").read_text())
            for p, h in CASES}


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c[0]}-{c[1]}")
def test_arrives_with_margin_and_without_turning(metrics, case):
    m, thesis = metrics[case], THESIS_TABLES[case]
    assert m["gait"] == "omni" and m["fallback_reason"] is None
    assert m["n_spin_cycles"] == 0
    limit = thesis.normalized_error_m if case[0] == "circle-reduced" else 0.01
    assert m["normalized_error_m"] <= limit
    # the planner checks the CoM at 101 configurations per swing and verifies every sample
    # with SAMPLE_MARGIN_SLACK_M (0.2 mm) for the CoM between them (planner/verify.py)
    assert m["min_margin_com_m"] >= 0.02 - SAMPLE_MARGIN_SLACK_M


@pytest.mark.parametrize("case", [
    c if c in FAST_ENOUGH else pytest.param(c, marks=pytest.mark.xfail(
        strict=True, reason="h = 0.6 m: stride 0.12 m, 3 units per half cycle "
        "without a continuous crawl (docs/gaits.md)")) for c in CASES],
    ids=lambda c: f"{c[0]}-{c[1]}")
def test_time_at_most_0_7_of_the_thesis(metrics, case):
    assert metrics[case]["normalized_time"] <= 0.7 * THESIS_TABLES[case].time_units
