"""A random corpus in physics: seeded random paths x robots x heights, planned with the
defaults and replayed by the MuJoCo sim; prints the walk rate per robot and every failure.

    .venv/bin/python benchmarks/bench_corpus.py [--cases 60] [--seed 20261202] [--robots ...]
                                                [--strict] [--reach-only-heights]
                                                [--torque-headroom 0.85] [--along-body M]

Case k (k = 0 .. N-1) is robot ``ROBOTS[k % 6]`` (SILO4, tests/robots mantis and phasmid,
go2, solo12, anymal); its path is 2-5 waypoints from (0, 0), each 0.3-1.2 m from the one
before in a random direction, a random start heading, and its height the robot's
``feasible_height_range(robot, any_direction=True)`` (default preset: the heights where it
walks a path in every direction, with a stride across its body or a turning stance) swept
from end to end: the j-th case of a robot of n is at the fraction (j + 0.5) / n of the range.
``--along-body M`` adds M cases (case k of them robot ``ROBOTS[k % 6]``, skipping a robot
that walks any direction at every feasible height) at the heights where the robot walks
only along its body axis (the rest of its ``feasible_height_range``: mantis above 0.5041 m,
phasmid above 0.5173 m), swept alike: 2-5 waypoints each 0.3-1.2 m forwards or backwards
along the start heading, up to ALONG_BODY_JITTER_M to the side. Every case is planned as
``silo4 plan`` plans it (planner.outputs.pipeline.plan_run: the URDF limits within the
preset's torque headroom, 0.85 of the effort, the contact forces, the non-foot ground clearance),
its torques added (full load), and replayed by
``silo4sim.run.simulate`` with ``PHYSICS`` (friction 0.8, the URDF's foot balls) and the
sim's default thresholds. A case walks when it plans, meets its tolerance (E_n eq 6.1 at
most the plan's tolerance) and the sim says it walks (no fall, drift <= 20 mm, slip <= 5 mm,
feet only on the ground). ``--strict`` plans with ``plan_path(strict=True)`` (no degraded
fallback: E_n within the tolerance and q'' continuous, facing the path on quintic profiles,
or refused; off by default, as in plan_path);
``--reach-only-heights`` draws the heights from ``feasible_height_range(robot,
clear_stance=False)`` (the legs' reach alone, without the default's rule that the creeping
stance keeps everything but the feet clear of the ground); ``--torque-headroom F`` plans
the whole case (foothold search, shifts, the run's check) within F x URDF effort instead of
the preset's 0.85 (1.0: the effort the sim's servos clamp at; the corpus ran at 1.0 until
it was found to hide that the default refused 15 of 30 insect cases at 0.85, since fixed by
planner/workspace/stance_budget.py and planner/gaits/load_caps.py). A figure, not a test:
tests/test_corpus.py runs a 12-case subset.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
#: The corpus's robots: label -> load_robot argument (None: SILO4 from urdf/).
ROBOTS: dict[str, str | None] = {
    "silo4": None,
    "mantis": str(ROOT / "tests" / "robots" / "mantis.urdf"),
    "phasmid": str(ROOT / "tests" / "robots" / "phasmid.urdf.xacro"),
    "go2": "go2",
    "solo12": "solo12",
    "anymal": "anymal",
}
DEFAULT_SEED = 20261202
#: Waypoints per path (inclusive bounds) and their spacing [m].
WAYPOINTS = (2, 5)
SPACING_M = (0.3, 1.2)
#: The along-body paths' waypoints lie at most this far to the side of the start heading's
#: line [m]: half the default tolerance (0.01 m), so none needs a crab or a turn.
ALONG_BODY_JITTER_M = 0.005


@dataclass(frozen=True)
class Case:
    """One corpus case: robot label, waypoints (K, 2) [m], start heading [rad], height [m]."""

    index: int
    robot: str
    waypoints_in_world: np.ndarray
    start_heading: float
    height_m: float
    kind: str = "any direction"

    def describe(self) -> str:
        pts = " ".join(f"{x:.3f},{y:.3f}" for x, y in self.waypoints_in_world)
        kind = "" if self.kind == "any direction" else f" ({self.kind})"
        return (
            f"#{self.index}{kind} {self.robot} h={self.height_m:.4f} m "
            f"heading={math.degrees(self.start_heading):.0f} deg path {pts}"
        )


@dataclass
class Outcome:
    """What a case gave: ``walks`` and, when it does not, ``reasons`` (one line each)."""

    case: Case
    walks: bool = False
    reasons: list[str] = field(default_factory=list)
    gait: str | None = None
    error_m: float | None = None
    tolerance_m: float | None = None
    seconds: float = 0.0


def random_path(rng: np.random.Generator) -> np.ndarray:
    """2-5 waypoints (K, 2) [m]: from (0, 0), each SPACING_M from the one before, any
    direction (the start (0, 0) is not a waypoint)."""
    n = int(rng.integers(WAYPOINTS[0], WAYPOINTS[1] + 1))
    steps = rng.uniform(*SPACING_M, n)
    angles = rng.uniform(-math.pi, math.pi, n)
    return np.cumsum(np.column_stack([steps * np.cos(angles), steps * np.sin(angles)]), axis=0)


def along_body_path(rng: np.random.Generator, heading: float) -> np.ndarray:
    """2-5 waypoints (K, 2) [m] from (0, 0), each SPACING_M forwards or backwards along
    ``heading`` [rad] from the one before, at most ALONG_BODY_JITTER_M to the side of the
    heading's line through (0, 0)."""
    n = int(rng.integers(WAYPOINTS[0], WAYPOINTS[1] + 1))
    along = np.cumsum(rng.uniform(*SPACING_M, n) * rng.choice([-1.0, 1.0], n))
    side = rng.uniform(-ALONG_BODY_JITTER_M, ALONG_BODY_JITTER_M, n)
    c, s = math.cos(heading), math.sin(heading)
    return np.column_stack([along * c - side * s, along * s + side * c])


def along_body_cases(
    n_cases: int, seed: int, robots: list[str], outside: dict, first_index: int
) -> list[Case]:
    """``n_cases`` along-body cases (module docstring); ``outside``: robot label -> the
    intervals [(lo, hi), ...] [m] of its feasible heights outside its any-direction range
    (robots without any are skipped); indices from ``first_index``."""
    labels = [r for r in robots if outside.get(r)]
    if not labels or n_cases <= 0:
        return []
    rng = np.random.default_rng([seed, 1])
    cases = []
    for k, (label, fraction) in enumerate(_swept_robots(n_cases, labels)):
        heading = float(rng.uniform(-math.pi, math.pi))
        wp = along_body_path(rng, heading)
        cases.append(
            Case(
                first_index + k, label, wp, heading, _swept(outside[label], fraction), "along body"
            )
        )
    return cases


def _swept_robots(n_cases: int, robots: list[str]) -> list[tuple[str, float]]:
    """(robot label, fraction of its height range) of case k = 0 .. n_cases - 1: robot
    ``robots[k % len(robots)]``, the j-th of its n cases at (j + 0.5) / n (module
    docstring)."""
    labels = [robots[k % len(robots)] for k in range(n_cases)]
    seen = dict.fromkeys(robots, 0)
    out = []
    for label in labels:
        out.append((label, (seen[label] + 0.5) / labels.count(label)))
        seen[label] += 1
    return out


def _swept(intervals: list[tuple[float, float]], fraction: float) -> float:
    """The height [m] at ``fraction`` of the total length of ``intervals`` [(lo, hi), ...]."""
    left = fraction * sum(hi - lo for lo, hi in intervals)
    for lo, hi in intervals:
        if left <= hi - lo:
            return round(min(lo + left, hi), 4)
        left -= hi - lo
    return intervals[-1][1]


def outside_any_direction(reach: tuple[float, float], any_dir: tuple[float, float]) -> list:
    """The intervals [(lo, hi), ...] [m] of the feasible range ``reach`` outside the
    any-direction range ``any_dir`` (0.1 mm in from its ends)."""
    out = []
    if reach[0] < any_dir[0] - 1e-4:
        out.append((reach[0], round(any_dir[0] - 1e-4, 4)))
    if reach[1] > any_dir[1] + 1e-4:
        out.append((round(any_dir[1] + 1e-4, 4), reach[1]))
    return out


def corpus_cases(n_cases: int, seed: int, robots: list[str], ranges: dict) -> list[Case]:
    """The first ``n_cases`` cases of the seeded corpus over ``robots`` (module docstring);
    ``ranges``: robot label -> (lo, hi) feasible height range [m]."""
    rng = np.random.default_rng(seed)
    cases = []
    for k, (label, fraction) in enumerate(_swept_robots(n_cases, robots)):
        lo, hi = ranges[label]
        wp = random_path(rng)
        heading = float(rng.uniform(-math.pi, math.pi))
        height = round(lo + fraction * (hi - lo), 4)
        cases.append(Case(k, label, wp, heading, min(max(height, lo), hi)))
    return cases


def physics_settings():  # noqa: ANN201 (SimSettings: mujoco is imported lazily)
    """The replay's settings: the sim's defaults with friction 0.8 and the URDF's feet."""
    from silo4sim.settings import SimSettings

    return replace(SimSettings(), friction=0.8, ball_feet=True)


def run_case(  # noqa: ANN001
    robot, case: Case, strict: bool = False, torque_headroom: float | None = None
) -> Outcome:
    """Plan ``case`` with the defaults (``strict``: plan_path's; ``torque_headroom``: a
    fraction of the URDF effort instead of the preset's, for the whole plan: the foothold
    search, the shifts and the run's check), check its tolerance, replay it in physics."""
    from planner.errors import PlanningError
    from planner.outputs.pipeline import RunRequest, plan_run
    from planner.path.metrics import compute_metrics
    from planner.presets import PRESETS
    from planner.trajectory.torques import add_torques
    from silo4kin.errors import Silo4Error
    from silo4sim.run import simulate

    preset = PRESETS["default"]
    if torque_headroom is not None:
        preset = preset._replace(torque_headroom=float(torque_headroom))
    out = Outcome(case)
    t0 = time.perf_counter()
    try:
        plan = plan_run(
            robot,
            case.waypoints_in_world,
            case.height_m,
            RunRequest(),
            start_heading=case.start_heading,
            strict=strict,
            workspace=preset,
        ).plan
    except (PlanningError, Silo4Error) as exc:
        out.reasons.append(f"plan refused ({type(exc).__name__}): {exc}")
        out.seconds = time.perf_counter() - t0
        return out
    out.gait = plan.gait
    error = float(compute_metrics(plan)["normalized_error_m"])
    out.error_m, out.tolerance_m = error, float(plan.tolerance)
    if error > plan.tolerance:
        out.reasons.append(
            f"misses its tolerance: E_n {1e3 * error:.1f} mm > {1e3 * plan.tolerance:.0f} mm "
            f"(gait {plan.gait})"
        )
    if plan.fallback_reason:
        out.reasons.append(f"(not a failure) gait {plan.gait} because {plan.fallback_reason}")
    try:
        traj = add_torques(robot, plan.trajectory, load="total")
    except Silo4Error as exc:
        out.reasons.append(f"torques refused: {exc}")
        out.seconds = time.perf_counter() - t0
        return out
    doc = simulate(robot, traj, settings=physics_settings()).metrics
    out.reasons.extend(f"physics: {r}" for r in doc["reasons"])
    out.walks = bool(doc["walks"]) and error <= plan.tolerance
    out.seconds = time.perf_counter() - t0
    return out


def run_corpus(  # noqa: ANN001
    n_cases: int,
    seed: int,
    robots: list[str],
    echo=print,
    strict: bool = False,
    clear_stance: bool = True,
    torque_headroom: float | None = None,
    along_body: int = 0,
) -> list[Outcome]:
    """Every case of the corpus and ``along_body`` along-body cases, echoing one line per
    case as it finishes (``strict``, ``clear_stance``, ``torque_headroom``: module
    docstring)."""
    from planner.workspace.heights import feasible_height_range
    from silo4kin import load_robot

    loaded = {label: load_robot(ROBOTS[label]) for label in robots}
    reach = {
        label: feasible_height_range(r, "default", clear_stance) for label, r in loaded.items()
    }
    ranges = {
        label: feasible_height_range(r, "default", clear_stance, any_direction=True)
        for label, r in loaded.items()
    }
    outside = {label: outside_any_direction(reach[label], ranges[label]) for label in robots}
    for label in robots:
        lo, hi = reach[label]
        echo(
            f"{label}: feasible range {lo:.4f}-{hi:.4f} m, any direction "
            f"{ranges[label][0]:.4f}-{ranges[label][1]:.4f} m"
        )
    cases = corpus_cases(n_cases, seed, robots, ranges)
    cases += along_body_cases(along_body, seed, robots, outside, n_cases)
    outcomes = []
    for case in cases:
        try:
            outcome = run_case(loaded[case.robot], case, strict, torque_headroom)
        except Exception as exc:  # a crash is a finding of the corpus, reported as such
            outcome = Outcome(case, reasons=[f"crashed ({type(exc).__name__}): {exc}"])
        outcomes.append(outcome)
        verdict = "walks" if outcome.walks else "FAILS"
        echo(f"{case.describe()}: {verdict} ({outcome.gait}, {outcome.seconds:.0f} s)")
        for reason in outcome.reasons:
            echo(f"    {reason}")
    return outcomes


def summary(outcomes: list[Outcome]) -> list[str]:
    """The walk rate per robot and overall, one line each, for each kind of case."""
    lines = []
    for kind in dict.fromkeys(o.case.kind for o in outcomes):
        of_kind = [o for o in outcomes if o.case.kind == kind]
        lines.append(f"{kind}:")
        labels = list(dict.fromkeys(o.case.robot for o in of_kind))
        for label in [*labels, None]:
            mine = [o for o in of_kind if label is None or o.case.robot == label]
            walked = sum(o.walks for o in mine)
            planned = sum(o.gait is not None for o in mine)
            lines.append(
                f"  {label or 'all':8s} walks {walked}/{len(mine)} "
                f"({100 * walked / len(mine):.0f} %), planned {planned}/{len(mine)}"
            )
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=60)
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED)
    parser.add_argument("--robots", nargs="+", choices=list(ROBOTS), default=list(ROBOTS))
    parser.add_argument("--strict", action="store_true")
    parser.add_argument("--reach-only-heights", action="store_true")
    parser.add_argument("--along-body", type=int, default=0, metavar="M")
    parser.add_argument(
        "--torque-headroom", type=float, default=None, help="default: the preset's, 0.85"
    )
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    outcomes = run_corpus(
        args.cases,
        args.seed,
        args.robots,
        echo=lambda s: print(s, flush=True),
        strict=args.strict,
        clear_stance=not args.reach_only_heights,
        torque_headroom=args.torque_headroom,
        along_body=args.along_body,
    )
    print(
        f"\n{args.cases} cases (+{args.along_body} along the body), seed {args.seed}, "
        f"{time.perf_counter() - t0:.0f} s"
    )
    for line in summary(outcomes):
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
