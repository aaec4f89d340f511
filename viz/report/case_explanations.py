"""The sentences of docs/results.md that explain why a case differs from the thesis's row,
each built from computed facts (strides, cycle counts, the time budget per phase)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from planner.gaits.crawl import FOUR_FOOT_UNITS
from planner.studies.cases import (
    THESIS_STRIDES_M,
    THESIS_UNITS_PER_CREEP_CYCLE,
    CaseResult,
    ThesisRow,
)
from viz.report.case_tables import format_count, format_value

#: A relative difference in time, distance or speed above this is "notable" (the thesis
#: prints 2-3 significant digits, so 5 % is well above its rounding).
NOTABLE_RELATIVE = 0.05
#: An E_n difference above this is notable [m] (the thesis prints E_n to 0.01 m).
NOTABLE_ERROR_M = 0.02


def _transition_text(metrics: Mapping[str, Any]) -> str:
    """ ", of which N transitions" or ", no transitions" (the default preset spins straight
    from the creeping stance)."""
    units = float((metrics.get("time_units_by_phase") or {}).get("transition", 0.0))
    return f", of which {format_count(units)} transitions" if units else ", no transitions"


#: Time units of one half cycle of the omnidirectional gait (two transfers + body phase).
OMNI_UNITS_PER_HALF_CYCLE = 3


def time_budget(metrics: Mapping[str, Any]) -> tuple[float, float, float]:
    """(creep cycles, units turning = spin + transitions, units of stability shifts)."""
    n_creep = float(metrics.get("n_creep_cycles", 0))
    phases = metrics.get("time_units_by_phase") or {}
    if phases:
        turning = float(phases.get("spin", 0.0)) + float(phases.get("transition", 0.0))
        shifts = float(phases.get("shift", 0.0))
    else:
        turning = float(metrics["normalized_time"]) - THESIS_UNITS_PER_CREEP_CYCLE * n_creep
        shifts = 0.0
    return n_creep, turning, shifts


def _spin_note(metrics: Mapping[str, Any]) -> str:
    """Why our spin-cycle count differs: the per-cycle turn cap (thesis: pi/2, halving)."""
    psi_max = metrics.get("psi_max_deg")
    ours, thesis = metrics.get("n_spin_cycles"), metrics.get("thesis_spin_cycles")
    if psi_max is None or ours is None or thesis is None or ours == thesis:
        return ""
    return (
        f" (a spin cycle of ours turns at most {float(psi_max):.0f} deg, set by the joint "
        f"limits and the legs' reach with footholds rotated about the CoG; the thesis's "
        f"halving rule up to 90 deg would use {thesis} cycles)"
    )


def thesis_budget(height_m: float, row: ThesisRow) -> tuple[int, float]:
    """(creep cycles implied by distance / stride, units left for turning) of a thesis row."""
    n_creep = round(row.distance_m / THESIS_STRIDES_M[height_m])
    return n_creep, row.time_units - THESIS_UNITS_PER_CREEP_CYCLE * n_creep


def explain(result: CaseResult) -> list[str]:
    """One sentence per notable difference between our case and the thesis's row."""
    case, m = result.case, result.metrics
    row = case.thesis
    if row is None:
        return []
    sentences = []
    stride, stride_t = float(m["stride_m"]), THESIS_STRIDES_M[case.height_m]
    n_creep, turning, shifts = time_budget(m)
    n_creep_t, turning_t = thesis_budget(case.height_m, row)
    n_spins, n_spin_cycles = m.get("n_spins", "?"), m.get("n_spin_cycles", "?")
    tag = f"h = {case.height_m:g} m, `{case.workspace}`"
    if abs(stride - stride_t) > 0.01 * stride_t:
        sentences.append(
            f"{tag}: our stride is {stride:.4f} m against the thesis's {stride_t:.4f} m "
            f"({100 * (stride / stride_t - 1):+.0f} %), which changes every count below."
        )
    if m.get("gait") == "crawl":
        return sentences + _explain_crawl(m, row, tag, stride_t, n_creep_t, turning_t)
    if m.get("gait") == "creep":
        return sentences + _explain_omni(m, row, tag, stride_t, shifts, n_creep_t, turning_t)
    if abs(m["normalized_time"] - row.time_units) > NOTABLE_RELATIVE * row.time_units:
        shift_text = f" and {format_count(shifts)} units of stability shifts" if shifts else ""
        sentences.append(
            f"{tag}: time {m['normalized_time']:.0f} vs {row.time_units:.0f} units: we walk "
            f"{format_count(n_creep)} creep cycles "
            f"({format_count(THESIS_UNITS_PER_CREEP_CYCLE * n_creep)} units) and "
            f"turn {n_spins} times in {n_spin_cycles} spin cycles "
            f"({format_count(turning)} units{_transition_text(m)}){shift_text}{_spin_note(m)}; "
            f"the thesis's "
            f"{row.distance_m} m is {row.distance_m / stride_t:.2f} of its strides, i.e. "
            f"{n_creep_t} cycles ({THESIS_UNITS_PER_CREEP_CYCLE * n_creep_t} units), leaving "
            f"{turning_t:.0f} units for turning."
        )
    if abs(m["distance_m"] - row.distance_m) > NOTABLE_RELATIVE * row.distance_m:
        walked = n_creep * stride
        extra = float(m["distance_m"]) - walked
        extra_text = f" plus {extra:.2f} m of stability shifts and returns" if extra > 0.005 else ""
        sentences.append(
            f"{tag}: distance {m['distance_m']:.2f} vs {row.distance_m} m: our "
            f"{format_count(n_creep)} cycles of {stride:.4f} m give {walked:.2f} m{extra_text}; "
            f"the "
            f"thesis's {n_creep_t} cycles of {stride_t} m give {n_creep_t * stride_t:.2f} m."
        )
    if abs(m["normalized_error_m"] - row.normalized_error_m) > NOTABLE_ERROR_M:
        half_cycles = getattr(
            getattr(result.plan, "workspace", None), "half_cycles", case.workspace == "default"
        )
        step = stride / 2 if half_cycles else stride
        sentences.append(
            f"{tag}: E_n {m['normalized_error_m']:.3f} vs {row.normalized_error_m} m: the "
            f"CoG advances in whole steps of {step:.3f} m, so each waypoint is missed by up "
            f"to {step / 2:.3f} m along the way, plus what earlier misses leave across it; "
            f"the two planners round the cycle counts and turn angles differently."
        )
    return sentences


def _explain_omni(
    m: Mapping[str, Any],
    row: Any,
    tag: str,
    stride_t: float,
    shifts: float,
    n_creep_t: int,
    turning_t: float,
) -> list[str]:
    """The default's omnidirectional gait (planner/gaits/omni.py, docs/gaits.md): no turns, half
    cycles of two leg transfers and a body phase of 1 unit or more (planner/gaits/
    body_pace.py; 3 units or more), steps sized to land on each waypoint."""
    half = int(m.get("n_creep_half_cycles", 0))
    sentences = []
    if abs(m["normalized_time"] - row.time_units) > NOTABLE_RELATIVE * row.time_units:
        shift_text = f" and {format_count(shifts)} units of stability shifts" if shifts else ""
        sentences.append(
            f"{tag}: time {m['normalized_time']:.0f} vs {row.time_units:.0f} units: the body "
            f"keeps its heading and walks straight at each waypoint in any direction, "
            f"{half} half cycles of at least {OMNI_UNITS_PER_HALF_CYCLE} units (two leg "
            f"transfers and a body phase of 1 unit or more, paced so that its acceleration "
            f"keeps the zero-moment point within the lift threshold), no turns{shift_text}; "
            f"the thesis's {row.distance_m} m is "
            + _thesis_walk(row, stride_t, n_creep_t, turning_t)
        )
    if abs(m["distance_m"] - row.distance_m) > NOTABLE_RELATIVE * row.distance_m:
        sentences.append(
            f"{tag}: distance {m['distance_m']:.2f} vs {row.distance_m} m: ours is the CoG's "
            "nominal path, the sum of the steps (straight lines between waypoints); the "
            "thesis's counts creeping cycles x stride."
        )
    if abs(m["normalized_error_m"] - row.normalized_error_m) > NOTABLE_ERROR_M:
        sentences.append(
            f"{tag}: E_n {m['normalized_error_m']:.3f} vs {row.normalized_error_m} m: each "
            "segment is split into equal steps, so the CoG lands on every waypoint (with a "
            "tolerance, it walks straight past the waypoints the line passes within half of "
            "it, and E_n is taken where it came nearest); the thesis walks whole cycles."
        )
    return sentences


def _thesis_walk(row: Any, stride_t: float, n_creep_t: int, turning_t: float) -> str:
    """How the thesis spends its time on the case: whole creeping cycles, then turning."""
    return (
        f"{row.distance_m / stride_t:.2f} of its strides, i.e. {n_creep_t} cycles "
        f"({THESIS_UNITS_PER_CREEP_CYCLE * n_creep_t} units), plus {turning_t:.0f} units "
        "for turning."
    )


def _explain_crawl(
    m: Mapping[str, Any], row: Any, tag: str, stride_t: float, n_creep_t: int, turning_t: float
) -> list[str]:
    """The default's continuous crawl (planner/gaits/crawl.py, docs/gaits.md): no turns, one leg
    at a time with the body moving, a four-foot phase after each pair."""
    sentences = []
    if abs(m["normalized_time"] - row.time_units) > NOTABLE_RELATIVE * row.time_units:
        half = int(m.get("n_creep_half_cycles", 0))
        creep_text = (
            f", plus {half} half cycles of the creeping gait where the crawl found no step"
            if half
            else ""
        )
        sentences.append(
            f"{tag}: time {m['normalized_time']:.0f} vs {row.time_units:.0f} units: the body "
            f"keeps its heading and crawls straight at each waypoint, "
            f"{m.get('n_crawl_swings', '?')} swings with the body moving (duty factor "
            f"{format_value('{:.2f}', m.get('duty_factor'))}, a {FOUR_FOOT_UNITS:g}-unit four-foot "
            f"phase after each pair){creep_text}, no turns; the thesis's {row.distance_m} m is "
            + _thesis_walk(row, stride_t, n_creep_t, turning_t)
        )
    if abs(m["distance_m"] - row.distance_m) > NOTABLE_RELATIVE * row.distance_m:
        sentences.append(
            f"{tag}: distance {m['distance_m']:.2f} vs {row.distance_m} m: ours is the CoG's "
            "nominal path (straight lines between waypoints; the lateral sway is not "
            "counted); the thesis's counts creeping cycles x stride."
        )
    if abs(m["normalized_error_m"] - row.normalized_error_m) > NOTABLE_ERROR_M:
        sentences.append(
            f"{tag}: E_n {m['normalized_error_m']:.3f} vs {row.normalized_error_m} m: the "
            "last advance of each segment ends on the waypoint and a swayed CoG steps back "
            "onto it (with a tolerance, it walks straight past the waypoints the line passes "
            "within half of it, and E_n is taken where it came nearest); the thesis walks "
            "whole cycles."
        )
    return sentences
