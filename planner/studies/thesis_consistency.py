"""Where the thesis disagrees with itself, computed (shown on docs/results.md).

Every fact here is computed from the robot and the planner, never typed in:

- :func:`spin_limit`: which limit caps one spinning-gait cycle (§4.2.2 says ψ <= π/2 per
  cycle; with footholds rotated about the CoG, thesis-notes.md, a joint limit or the leg's
  reach stops it first);
- :func:`stride_jump`: where the thesis's stride rule λ(h) jumps (thesis-notes.md: the
  Chapter 4 example at h = 0.39 m and the Chapter 6 strides follow two different rules);
- :func:`own_count`: the time §5.5's own counts give for the decisions of a case (8 units
  per creeping cycle, 6 per spinning cycle with the halving rule, 2 + 2 transitions).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.workspace.layout import Workspace, stride_at
from silo4kin.frames import rotation_z
from silo4kin.joint_limits import joint_limit_bounds
from silo4kin.kinematics import inverse_kinematics_masked

#: How far past ψ_max the binding limit is looked for [rad]: 0.1 deg, far above the
#: bisection's 1e-12 rad and far below any second limit's distance.
PAST_LIMIT_RAD = math.radians(0.1)


@dataclass(frozen=True)
class SpinLimit:
    """What caps a spinning cycle at one height.

    Attributes:
        psi_max_deg: largest turn per cycle [deg].
        limit: "leg reach" (the rotated foothold is beyond the leg's length), or the URDF
            name of the joint whose limit is crossed just past psi_max_deg.
        leg: name of the first leg that fails.
    """

    psi_max_deg: float
    limit: str
    leg: str


def spin_limit(robot, ws: Workspace) -> SpinLimit:
    """The limit that stops a spinning cycle of ``ws`` at ψ_max (module docstring); ``robot``
    in the planning frame (PlanningModel.planning_robot). At ψ_max = 90 deg (the thesis's cap
    itself) the limit is "pi/2 (thesis §4.2.2)"."""
    if ws.psi_max_rad >= math.pi / 2 - 1e-9:
        return SpinLimit(90.0, "pi/2 (thesis §4.2.2)", "")
    psi = ws.psi_max_rad + PAST_LIMIT_RAD
    for i, leg in enumerate(robot.legs):
        for sign in (1.0, -1.0):
            target = (rotation_z(sign * psi) @ ws.position_mid_in_base[i])[None]
            res = inverse_kinematics_masked(leg, target)
            if not bool(res.reachable[0]):
                return SpinLimit(math.degrees(ws.psi_max_rad), "leg reach", leg.name)
            q = res.q[0]
            lo, hi = joint_limit_bounds(leg.q_lower, leg.q_upper)
            out = (q < lo) | (q > hi)
            if out.any():
                joint = leg.joint_names[int(np.argmax(out))]
                return SpinLimit(math.degrees(ws.psi_max_rad), joint, leg.name)
    return SpinLimit(math.degrees(ws.psi_max_rad), "unknown", "")


def stride_jump(
    robot,
    lo_m: float = 0.3,
    hi_m: float = 0.5,
    *,
    preset: str = "thesis",
    min_jump_m: float = 0.01,
    tol_m: float = 1e-5,
) -> tuple[float, float, float] | None:
    """(height [m], stride below, stride above [m]) of the largest jump of the preset's
    stride λ(h) in [lo_m, hi_m], located by bisection to ``tol_m``; None when λ moves by
    less than ``min_jump_m`` between 1 mm grid points."""

    def stride(h: float) -> float:
        return stride_at(robot, h, preset)  # workspace_for(...).stride_m, without ψ_max

    grid = np.arange(lo_m, hi_m + 1e-9, 0.001)
    strides = np.array([stride(float(h)) for h in grid])
    steps = np.abs(np.diff(strides))
    k = int(np.argmax(steps))
    if steps[k] < min_jump_m:
        return None
    a, b = float(grid[k]), float(grid[k + 1])
    sa = stride(a)
    while b - a > tol_m:
        m = 0.5 * (a + b)
        if abs(stride(m) - sa) < 0.5 * steps[k]:
            a = m
        else:
            b = m
    return 0.5 * (a + b), stride(a), stride(b)


def own_count(metrics) -> float:
    """§5.5's time count of a plan's decisions [units] (planner.path.metrics thesis_time_units)."""
    return float(metrics["thesis_time_units"])


def render_contradictions(results, robot) -> list[str]:
    """Markdown lines of the results page's "Where the thesis contradicts itself" section,
    from the ``thesis``-preset case results (planner.studies.cases.CaseResult) and the robot in the
    planning frame (module docstring)."""
    from planner.presets import preset_for
    from planner.studies.cases import (
        CIRCLE_RADIUS_M,
        THESIS_STRIDES_M,
        THESIS_UNITS_PER_CREEP_CYCLE,
        THESIS_UNITS_PER_SPIN_CYCLE,
        THESIS_UNITS_PER_SPIN_TRANSITIONS,
    )

    ours = {
        (r.case.path, r.case.height_m): r
        for r in results
        if preset_for(r.case.workspace).follows_thesis
    }
    out = [
        "## Where the thesis contradicts itself",
        "",
        "Computed from the `thesis` preset, which follows §5.5 as written (every waypoint "
        "off the body's axis is faced by spinning, then round(d / λ) creeping cycles are "
        "walked). The scans behind the circle's sampling and Table 6.3 are in "
        "[thesis-contradictions.md](thesis-contradictions.md).",
        "",
    ]
    straight = sorted(h for p, h in ours if p == "straight")
    if straight:
        out += [
            "**Table 6.1 against §5.5's own count.** The same decisions counted the "
            "thesis's way (8 units per creeping cycle, 6 per spinning cycle with its "
            "halving rule, 2 + 2 transitions per turn):",
            "",
            "| h (m) | printed time | §5.5 count | creep cycles, §5.5 | printed distance "
            "/ λ | spin cycles, halving rule | spin cycles the printed time leaves |",
            "|---|---|---|---|---|---|---|",
        ]
        notes = []
        for h in straight:
            r = ours[("straight", h)]
            m, row = r.metrics, r.case.thesis
            count = own_count(m)
            cycles_printed = round(row.distance_m / THESIS_STRIDES_M[h])
            left = (
                row.time_units
                - THESIS_UNITS_PER_CREEP_CYCLE * cycles_printed
                - THESIS_UNITS_PER_SPIN_TRANSITIONS * m["n_spins"]
            ) / THESIS_UNITS_PER_SPIN_CYCLE
            out.append(
                f"| {h:g} | {row.time_units:.0f} | {count:.0f} | "
                f"{m['n_creep_cycles']:g} | {row.distance_m / THESIS_STRIDES_M[h]:.2f} | "
                f"{m['thesis_spin_cycles']} | {left:g} |"
            )
            if abs(count - row.time_units) > 0.5:
                creep = (
                    f"{m['n_creep_cycles']:g} creeping cycles where the printed "
                    f"distance is {cycles_printed} strides; "
                    if abs(m["n_creep_cycles"] - cycles_printed) > 0
                    else ""
                )
                notes.append(
                    f"h = {h:g} m: {count:.0f} units, not the printed "
                    f"{row.time_units:.0f} ({creep}{m['thesis_spin_cycles']} spinning "
                    f"cycles for the {m['n_spins']} turns where the printed time "
                    f"leaves {left:g})"
                )
        if notes:
            out += ["", "The text's own rules give " + "; ".join(notes) + ".", ""]
        else:
            out.append("")
    circle = sorted(h for p, h in ours if p == "circle")
    if circle:
        parts = []
        for h in circle:
            m, row = ours[("circle", h)].metrics, ours[("circle", h)].case.thesis
            rel = 100 * (m["normalized_time"] / row.time_units - 1)
            parts.append(
                f"h = {h:g} m: {m['normalized_time']:.0f} vs {row.time_units:.0f} "
                f"units ({rel:+.1f} %), E_n {m['normalized_error_m']:.3f} vs "
                f"{row.normalized_error_m:.2f} m"
            )
        fits = "; ".join(parts)
        out += [
            f"**Table 6.2 is reproduced** once every waypoint off the axis is faced "
            f"(a waypoint whose creep count rounds to zero is faced too, not counted "
            f"as reached): {fits}. The thesis gives no sampling of the circle; 31 or 32 "
            f"waypoints fit all three heights within 3 %, other counts from 16 to 72 do "
            f"not (planner/studies/cases.py).",
            "",
        ]
    heights = sorted({h for _, h in ours})
    if heights:
        out += [
            "**What caps a spinning cycle.** §4.2.2 allows up to 90 deg per cycle and "
            "rotates each foothold about its own hip, which would slide the stance feet "
            "(thesis-notes.md). Rotating the footholds about the CoG, a cycle stops at:",
            "",
            "| h (m) | ψ_max per cycle (deg) | limit | first leg |",
            "|---|---|---|---|",
        ]
        for h in heights:
            r = next(v for (p, hh), v in ours.items() if hh == h)
            lim = spin_limit(robot, r.plan.workspace)
            out.append(f"| {h:g} | {lim.psi_max_deg:.1f} | {lim.limit} | {lim.leg} |")
        out.append("")
    jump = stride_jump(robot)
    if jump is not None:
        h_jump, below, above = jump
        out += [
            f"**The stride jumps at h = {h_jump:.4f} m** from {below:.4f} m to "
            f"{above:.4f} m: below it the thesis's rule keeps the knee bent (§4.2.1's "
            f"example at h = 0.39 m, λ = 0.2176 m), above it the leg is stretched "
            f"straight (the Chapter 6 strides): two rules in one λ(h).",
            "",
        ]
    reduced = sorted(h for p, h in ours if p == "circle-reduced")
    if reduced:
        length = 2 * math.pi * CIRCLE_RADIUS_M
        cells = ", ".join(
            f"{ours[('circle-reduced', h)].case.thesis.distance_m} m "
            f"(ours {ours[('circle-reduced', h)].metrics['distance_m']:.2f} m)"
            for h in reduced
        )
        out += [
            f"**Table 6.3 cannot be reproduced from the text.** Its distances, at h = "
            f"{', '.join(f'{h:g}' for h in reduced)} m: {cells}, against a circle "
            f"{length:.2f} m long. Distance counts creeping cycles x λ, and with the "
            f"0.15 m rule of §6.3 (creep only when the waypoint is more than 0.15 m "
            f"ahead, spin only when it is more than 0.15 m to the side) the count is "
            f"never below 6.27 m for any sampling from 12 to 72 waypoints "
            f"(scripts/circle_sampling_scan.py): the printed distances at h = 0.2 and "
            f"0.4 m are 0.6 and 0.3 m shorter than every one of these walks, and the "
            f"printed times cannot be checked without the walk they belong to.",
            "",
        ]
    return out
