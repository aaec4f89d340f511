"""Generate docs/results.md: thesis Tables 6.1-6.3 beside ours, with computed explanations.

Nothing on the page is typed by hand: every number comes from the case results
(planner.studies.cases) or the published values (planner.studies.cases.THESIS_TABLES), and
every sentence explaining a difference is built from computed facts (strides, cycle counts,
time budget). Wall times are left out so that regenerating the page gives the same file.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from planner.gaits.crawl import FOUR_FOOT_UNITS
from planner.studies.cases import (
    THESIS_STRIDES_M,
    THESIS_TABLE_OF_PATH,
    THESIS_UNITS_PER_CREEP_CYCLE,
    THESIS_UNITS_PER_SPIN_CYCLE,
    THESIS_UNITS_PER_SPIN_TRANSITIONS,
    CaseResult,
    ThesisRow,
)

#: A relative difference in time, distance or speed above this is "notable" (the thesis
#: prints 2-3 significant digits, so 5 % is well above its rounding).
NOTABLE_RELATIVE = 0.05
#: An E_n difference above this is notable [m] (the thesis prints E_n to 0.01 m).
NOTABLE_ERROR_M = 0.02

_PATH_TITLES = {"straight": "Straight path (0,1) (1,1) (0,2) (0,3)",
                "circle": "Circle, radius 1 m",
                "circle-reduced": "Circle with reduced accuracy (tolerance 0.15 m)"}
_QUANTITIES = (  # (label, thesis attribute, metrics key, format)
    ("time (t/t_l)", "time_units", "normalized_time", "{:.0f}"),
    ("distance (m)", "distance_m", "distance_m", "{:.2f}"),
    ("speed (m/unit)", "average_speed", "average_speed", "{:.3f}"),
    ("E_n (m)", "normalized_error_m", "normalized_error_m", "{:.2f}"),
)


#: Margins closer to 0 than this print as 0 (the thesis preset's S_m = 0 computes as
#: +-1e-16 m; "-0.000" would suggest an unstable sample) [m].
ZERO_MARGIN_M = 1e-9


def _fmt(fmt: str, value: Any) -> str:
    if value is None:
        return "n/a"
    if isinstance(value, float) and abs(value) < ZERO_MARGIN_M:
        value = 0.0
    return fmt.format(value)


def _index(results: Sequence[CaseResult]) -> dict[tuple[str, float, str], CaseResult]:
    return {(r.case.path, r.case.height_m, r.case.workspace): r for r in results}


def _num(value: float) -> str:
    """A count that may be a half: 13 or 11.5."""
    return f"{value:g}"


def _transition_text(metrics: Mapping[str, Any]) -> str:
    """", of which N transitions" or ", no transitions" (the default preset spins straight
    from the creeping stance)."""
    units = float((metrics.get("time_units_by_phase") or {}).get("transition", 0.0))
    return f", of which {_num(units)} transitions" if units else ", no transitions"


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
    return (f" (a spin cycle of ours turns at most {float(psi_max):.0f} deg, set by the joint "
            f"limits and the legs' reach with footholds rotated about the CoG; the thesis's "
            f"halving rule up to 90 deg would use {thesis} cycles)")


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
            f"({100 * (stride / stride_t - 1):+.0f} %), which changes every count below.")
    if m.get("gait") == "crawl":
        return sentences + _explain_crawl(m, row, tag, stride_t, n_creep_t, turning_t)
    if m.get("gait") == "creep":
        return sentences + _explain_omni(m, row, tag, stride_t, shifts, n_creep_t, turning_t)
    if abs(m["normalized_time"] - row.time_units) > NOTABLE_RELATIVE * row.time_units:
        shift_text = f" and {_num(shifts)} units of stability shifts" if shifts else ""
        sentences.append(
            f"{tag}: time {m['normalized_time']:.0f} vs {row.time_units:.0f} units: we walk "
            f"{_num(n_creep)} creep cycles ({_num(THESIS_UNITS_PER_CREEP_CYCLE * n_creep)} "
            f"units) and turn {n_spins} times in {n_spin_cycles} spin cycles "
            f"({_num(turning)} units{_transition_text(m)}){shift_text}{_spin_note(m)}; "
            f"the thesis's "
            f"{row.distance_m} m is {row.distance_m / stride_t:.2f} of its strides, i.e. "
            f"{n_creep_t} cycles ({THESIS_UNITS_PER_CREEP_CYCLE * n_creep_t} units), leaving "
            f"{turning_t:.0f} units for turning.")
    if abs(m["distance_m"] - row.distance_m) > NOTABLE_RELATIVE * row.distance_m:
        walked = n_creep * stride
        extra = float(m["distance_m"]) - walked
        extra_text = (f" plus {extra:.2f} m of stability shifts and returns"
                      if extra > 0.005 else "")
        sentences.append(
            f"{tag}: distance {m['distance_m']:.2f} vs {row.distance_m} m: our "
            f"{_num(n_creep)} cycles of {stride:.4f} m give {walked:.2f} m{extra_text}; the "
            f"thesis's {n_creep_t} cycles of {stride_t} m give {n_creep_t * stride_t:.2f} m.")
    if abs(m["normalized_error_m"] - row.normalized_error_m) > NOTABLE_ERROR_M:
        half_cycles = getattr(getattr(result.plan, "workspace", None), "half_cycles",
                              case.workspace == "default")
        step = stride / 2 if half_cycles else stride
        sentences.append(
            f"{tag}: E_n {m['normalized_error_m']:.3f} vs {row.normalized_error_m} m: the "
            f"CoG advances in whole steps of {step:.3f} m, so each waypoint is missed by up "
            f"to {step / 2:.3f} m along the way, plus what earlier misses leave across it; "
            f"the two planners round the cycle counts and turn angles differently.")
    return sentences


def _explain_omni(m: Mapping[str, Any], row: Any, tag: str, stride_t: float, shifts: float,
                  n_creep_t: int, turning_t: float) -> list[str]:
    """The default's omnidirectional gait (planner/gaits/omni.py, docs/gaits.md): no turns, half
    cycles of two leg transfers and a 1-unit body phase (3 units), steps sized to land on
    each waypoint."""
    half = int(m.get("n_creep_half_cycles", 0))
    sentences = []
    if abs(m["normalized_time"] - row.time_units) > NOTABLE_RELATIVE * row.time_units:
        shift_text = f" and {_num(shifts)} units of stability shifts" if shifts else ""
        sentences.append(
            f"{tag}: time {m['normalized_time']:.0f} vs {row.time_units:.0f} units: the body "
            f"keeps its heading and walks straight at each waypoint in any direction, "
            f"{half} half cycles of {OMNI_UNITS_PER_HALF_CYCLE} units (two leg transfers and "
            f"a 1-unit body phase), no turns{shift_text}; the thesis's {row.distance_m} m is "
            + _thesis_walk(row, stride_t, n_creep_t, turning_t))
    if abs(m["distance_m"] - row.distance_m) > NOTABLE_RELATIVE * row.distance_m:
        sentences.append(
            f"{tag}: distance {m['distance_m']:.2f} vs {row.distance_m} m: ours is the CoG's "
            "nominal path, the sum of the steps (straight lines between waypoints); the "
            "thesis's counts creeping cycles x stride.")
    if abs(m["normalized_error_m"] - row.normalized_error_m) > NOTABLE_ERROR_M:
        sentences.append(
            f"{tag}: E_n {m['normalized_error_m']:.3f} vs {row.normalized_error_m} m: each "
            "segment is split into equal steps, so the CoG lands on every waypoint (with a "
            "tolerance, it walks straight past the waypoints the line passes within half of "
            "it, and E_n is taken where it came nearest); the thesis walks whole cycles.")
    return sentences


def _thesis_walk(row: Any, stride_t: float, n_creep_t: int, turning_t: float) -> str:
    """How the thesis spends its time on the case: whole creeping cycles, then turning."""
    return (f"{row.distance_m / stride_t:.2f} of its strides, i.e. {n_creep_t} cycles "
            f"({THESIS_UNITS_PER_CREEP_CYCLE * n_creep_t} units), plus {turning_t:.0f} units "
            "for turning.")


def _explain_crawl(m: Mapping[str, Any], row: Any, tag: str, stride_t: float,
                   n_creep_t: int, turning_t: float) -> list[str]:
    """The default's continuous crawl (planner/gaits/crawl.py, docs/gaits.md): no turns, one leg
    at a time with the body moving, a four-foot phase after each pair."""
    sentences = []
    if abs(m["normalized_time"] - row.time_units) > NOTABLE_RELATIVE * row.time_units:
        half = int(m.get("n_creep_half_cycles", 0))
        creep_text = (f", plus {half} half cycles of the creeping gait where the crawl found "
                      "no step" if half else "")
        sentences.append(
            f"{tag}: time {m['normalized_time']:.0f} vs {row.time_units:.0f} units: the body "
            f"keeps its heading and crawls straight at each waypoint, "
            f"{m.get('n_crawl_swings', '?')} swings with the body moving (duty factor "
            f"{_fmt('{:.2f}', m.get('duty_factor'))}, a {FOUR_FOOT_UNITS:g}-unit four-foot "
            f"phase after each pair){creep_text}, no turns; the thesis's {row.distance_m} m is "
            + _thesis_walk(row, stride_t, n_creep_t, turning_t))
    if abs(m["distance_m"] - row.distance_m) > NOTABLE_RELATIVE * row.distance_m:
        sentences.append(
            f"{tag}: distance {m['distance_m']:.2f} vs {row.distance_m} m: ours is the CoG's "
            "nominal path (straight lines between waypoints; the lateral sway is not "
            "counted); the thesis's counts creeping cycles x stride.")
    if abs(m["normalized_error_m"] - row.normalized_error_m) > NOTABLE_ERROR_M:
        sentences.append(
            f"{tag}: E_n {m['normalized_error_m']:.3f} vs {row.normalized_error_m} m: the "
            "last advance of each segment ends on the waypoint and a swayed CoG steps back "
            "onto it (with a tolerance, it walks straight past the waypoints the line passes "
            "within half of it, and E_n is taken where it came nearest); the thesis walks "
            "whole cycles.")
    return sentences


def _case_table(path: str, results: Sequence[CaseResult], heights: Sequence[float],
                presets: Sequence[str], physics: Mapping[str, str]) -> list[str]:
    idx = _index(results)
    head = "| h (m) | quantity | thesis | " + " | ".join(f"ours, `{p}`" for p in presets) + " |"
    lines = [head, "|" + "---|" * (3 + len(presets))]
    for h in heights:
        row = next((r.case.thesis for r in results if r.case.path == path
                    and r.case.height_m == h), None)
        quantities = list(_QUANTITIES) + [
            ("stride (m)", None, "stride_m", "{:.4f}"),
            ("gait", None, "gait", "{}"),
            ("creep / spin cycles", None, None, None),
            ("min margin S_m (m)", None, "min_stability_margin_m", "{:.3f}"),
            ("min whole-body margin (m)", None, "min_margin_com_m", "{:.4f}"),
        ] + ([("physics (MuJoCo)", None, None, "physics")] if physics else [])
        for k, (label, attr, key, fmt) in enumerate(quantities):
            if label == "stride (m)":
                thesis = f"{THESIS_STRIDES_M.get(h, float('nan')):.4f}"
            elif attr is not None and row is not None:
                thesis = _fmt(fmt or "{}", getattr(row, attr))
            else:
                thesis = ""
            cells = []
            for preset in presets:
                r = idx.get((path, h, preset))
                if r is None:
                    cells.append("not run")
                elif fmt == "physics":
                    cells.append(physics.get(r.case.name, "not run"))
                elif key is None:
                    cells.append(f"{r.metrics.get('n_creep_cycles', '?')} / "
                                 f"{r.metrics.get('n_spin_cycles', '?')}")
                else:
                    cells.append(_fmt(fmt or "{}", r.metrics.get(key)))
            first = f"{h:g}" if k == 0 else ""
            lines.append(f"| {first} | {label} | {thesis} | " + " | ".join(cells) + " |")
    return lines


def _time_count_table(results: Sequence[CaseResult]) -> list[str]:
    lines = ["| case | preset | creep | spin | transitions | shifts | total | "
             "thesis count of the same decisions | turns / spin cycles (thesis rule) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        m = r.metrics
        phases = m.get("time_units_by_phase") or {}

        def units(key: str, phases: Mapping[str, Any] = phases) -> str:
            return _num(float(phases.get(key, 0.0)))

        thesis_count = m.get("thesis_time_units")
        lines.append(
            f"| {r.case.path} h={r.case.height_m:g} | {r.case.workspace} | {units('creep')} | "
            f"{units('spin')} | {units('transition')} | {units('shift')} | "
            f"{m['normalized_time']:.0f} | "
            f"{'n/a' if thesis_count is None else _num(float(thesis_count))} | "
            f"{m.get('n_spins', '?')} / {m.get('n_spin_cycles', '?')} "
            f"({m.get('thesis_spin_cycles', '?')}) |")
    return lines


def render_results_page(results: Sequence[CaseResult], ditches: Sequence[Any] = (), *,
                        command: str, refused: Sequence[tuple[Any, str]] = (),
                        physics: Mapping[str, str] | None = None, robot: Any = None) -> str:
    """The whole markdown page.

    Args:
        results: planned cases.
        ditches: planner.studies.ditch.DitchOutcome objects.
        command: the command line that regenerates the page.
        refused: (PathCase, planner's message) of cases the planner refused.
        physics: case name -> physics verdict ("walks", "falls", ...), a row in every
            case table (``silo4 cases --simulate``); none: no row.
        robot: the robot (Robot or PlanningModel); given, the page says where the thesis
            contradicts itself (planner/studies/thesis_consistency.py).
    """
    presets = list(dict.fromkeys(r.case.workspace for r in results))
    heights = sorted({r.case.height_m for r in results})
    paths = list(dict.fromkeys(r.case.path for r in results))
    out = [
        "# Results: thesis Chapter 6 beside this planner",
        "",
        f"Generated by `{command}`; do not edit by hand.",
        "",
        "Paths start at (0, 0) facing +y (heading 90 deg). The circle (radius 1 m) passes "
        "through the start, tangent to the start heading, centred at (-1, 0), sampled into "
        "32 waypoints 11.25 deg apart (planner/studies/cases.py; the count with which §5.5 "
        "reproduces Table 6.2). `thesis` is the preset that follows the thesis as written "
        "(Chapter 6 strides, §5.5's decisions, body CoG); `default` keeps a reach margin from the "
        "stretched-leg singularity. Time is in thesis units t_l (one leg transfer). "
        "\"min margin S_m\" is the planner's criterion with a leg up: the body CoG for "
        "`thesis` (threshold 0, as the thesis), the whole-robot CoM (legs included, as they "
        "move) for `default` (threshold 0.02 m); \"min whole-body margin\" is the whole-robot "
        "CoM's for both (negative: outside the support polygon; the `thesis` preset then "
        "warns, issue 9). E_n (eq 6.1) is measured on the CoG as walked. \"physics\" is "
        "the MuJoCo replay's verdict (`--simulate`; details in the last section): *walks* "
        "or not, *falls* when the body tips over.",
        "",
        "Height vs speed and accuracy over a grid of heights and leg lengths, beside the "
        "thesis's conclusion (§7.2): [sweep_results.md](sweep_results.md), generated by "
        "`silo4 sweep` (docs/sweeps.md).",
        "",
    ]
    for path in paths:
        out += [f"## Table {THESIS_TABLE_OF_PATH.get(path, '?')}: {_PATH_TITLES.get(path, path)}",
                ""]
        out += _case_table(path, results, heights, presets, physics or {})
        notes = [s for r in results if r.case.path == path for s in explain(r)]
        if notes:
            out += ["", "Why the numbers differ:", ""] + [f"- {s}" for s in notes]
        out.append("")
    if robot is not None and any(r.case.workspace == "thesis" for r in results):
        from planner.model import as_planning_model
        from planner.studies.thesis_consistency import render_contradictions

        out += render_contradictions(results, as_planning_model(robot).planning_robot)
    out += ["## Time counts", "",
            f"Thesis: one creeping cycle = {THESIS_UNITS_PER_CREEP_CYCLE} units; one spinning "
            f"cycle = {THESIS_UNITS_PER_SPIN_CYCLE} units plus the "
            f"{THESIS_UNITS_PER_SPIN_TRANSITIONS // 2} + "
            f"{THESIS_UNITS_PER_SPIN_TRANSITIONS // 2} unit transitions of legs 4 and 2 "
            "before and after each turn. Below, our time in units per phase; the thesis "
            "count applies those numbers to our decisions (creep cycles, turns, and spin "
            "cycles from the thesis's halving rule, §5.5), without our stability shifts.", ""]
    out += _time_count_table(results)
    out.append("")
    if refused:
        out += ["## Cases the planner refused", ""]
        out += [f"- {case.name}: {message}" for case, message in refused]
        out.append("")
    if ditches:
        out += ["## Ditch crossing (Fig 6.30)", "",
                "A ditch across the path (a strip of the ground, any depth); every foothold "
                "must stay outside it. Routes are tried straight across first, then at an "
                "angle to the ditch with the approach shifted sideways (planner/studies/ditch.py).",
                ""]
        out += [f"- {d.summary()}" for d in ditches]
        out.append("")
    return "\n".join(out)
