"""report.html's tables: every metric has a label and a unit, numbers read as numbers,
empty rows are left out, and a physics replay's verdict and sim.html appear on the page."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from viz.report.page import add_physics_section, write_report
from viz.report.tables import QUANTITIES, format_number, metric_tables, quantity


@pytest.fixture(scope="module")
def run_metrics() -> dict[str, Any]:
    """metrics.json of a short plan through the outputs pipeline (torques, limits)."""
    from planner.outputs.pipeline import RunRequest, plan_run
    from silo4kin import load_robot
    from silo4kin.motors import Gearing

    robot = load_robot()
    run = plan_run(
        robot,
        np.array([[0.0, 0.6]]),
        0.4,
        RunRequest(unit_time="auto", gearing=Gearing.uniform(12)),
        samples_per_unit=20,
    )
    return dict(run.metrics)


def _keys(value: Any) -> set[str]:
    """Every key of a metrics document, record keys included (not per-joint names)."""
    keys: set[str] = set()
    if isinstance(value, dict):
        for k, v in value.items():
            keys.add(k)
            if not (isinstance(v, dict) and k.startswith(("peak_", "time_units_by"))):
                keys |= _keys(v)
    elif isinstance(value, list):
        for item in value:
            keys |= _keys(item)
    return keys


def test_every_metric_key_has_a_label(run_metrics: dict[str, Any]) -> None:
    """Every key compute_metrics and the pipeline write (records too) is in QUANTITIES."""
    missing = sorted(_keys(run_metrics) - set(QUANTITIES))
    assert missing == []


def test_every_metric_compute_metrics_can_emit_is_listed() -> None:
    """The keys in compute_metrics' source (also those of a spin or a CoM warning, which a
    short straight plan does not have) are in QUANTITIES."""
    import re

    import planner.path.metrics as metrics_module

    source = Path(metrics_module.__file__).read_text(encoding="utf-8")
    emitted = set(re.findall(r'^\s*(?:\{)?"([a-z_A-Z0-9]+)":', source, flags=re.M))
    emitted |= set(re.findall(r'\{"([a-z_]+)":', source))
    assert emitted, "no key found: the pattern no longer matches compute_metrics"
    assert sorted(emitted - set(QUANTITIES)) == []


@pytest.mark.parametrize(
    ("value", "decimals", "text"),
    [
        (3.8e-36, 4, "0"),
        (-0.00001, 3, "0"),
        (-0.0004, 3, "0"),
        (-0.0006, 3, "-0.001"),
        (0.5851, 4, "0.5851"),
        (3.8e-36, None, "0"),
        (12.0, None, "12"),
        (0.123456, None, "0.1235"),
        (None, 3, "–"),
        (True, None, "yes"),
    ],
)
def test_numbers_for_people(value: Any, decimals: int | None, text: str) -> None:
    """Below the last shown digit a value is 0 (no 3.8e-36, no -0.000)."""
    assert format_number(value, decimals) == text


def test_page_has_labels_not_keys(run_metrics: dict[str, Any], tmp_path: Path) -> None:
    """No raw key, no exponent, no -0.000 and no empty row on the page."""
    metrics = dict(
        run_metrics,
        normalized_error_m=3.8e-36,
        min_margin_com_m=-1e-12,
        warnings=[],
        spins=[],
        fallback_reason=None,
    )
    page = write_report(tmp_path, metrics=metrics, animation=None).read_text()
    body = page.split("<body>")[1]
    for key in ("min_margin_com", "n_crawl_swings", "normalized_error_m"):
        assert key not in body
    assert quantity("n_crawl_swings").label in body
    assert "e-36" not in body and "-0.000" not in body
    assert "<td></td>" not in body and "<h2>Warnings</h2>" not in body
    assert "why a faster gait" not in body  # fallback_reason None: no row
    assert "normalised error E_n (eq 6.1) [m]</td><td>0</td>" in body


def test_warnings_are_listed(tmp_path: Path) -> None:
    """A warning line shows in its own list."""
    page = write_report(
        tmp_path, metrics={"warnings": ["", "warning: CoM out"]}, animation=None
    ).read_text()
    assert "<h2>Warnings</h2>" in page and "<li>warning: CoM out</li>" in page
    assert "<li></li>" not in page


def test_report_shows_physics_verdict_and_links_sim_html(tmp_path: Path) -> None:
    """With sim.json (and sim.html) in the folder the page shows the verdict and the link;
    a replay after the page was written puts the section in (add_physics_section)."""
    page = write_report(tmp_path, metrics={"height_m": 0.4}, animation=None)
    assert "Physics" not in page.read_text()
    (tmp_path / "sim.json").write_text(
        json.dumps(
            {"walks": False, "reasons": ["fell at t = 3 s"], "drift_max_m": 0.02, "falls": 1}
        )
    )
    (tmp_path / "sim.html").write_text("<html></html>")
    assert add_physics_section(tmp_path) == page
    text = page.read_text()
    assert "does not walk: fell at t = 3 s" in text and 'href="sim.html"' in text
    (tmp_path / "sim.json").write_text(json.dumps({"walks": True}))
    add_physics_section(tmp_path)
    text = page.read_text()
    assert "<strong>walks</strong>" in text and text.count("<h2>Physics</h2>") == 1


def test_metric_tables_skip_empty_structures() -> None:
    """An empty mapping or list of records has no table."""
    titles = [
        t
        for t, _ in metric_tables(
            {"spins": [], "joint_limits": {"violation": None}, "height_m": 0.4}
        )
    ]
    assert titles == ["Metrics"]
