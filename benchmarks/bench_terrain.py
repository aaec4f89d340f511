"""Random terrain in physics: seeded stepping-stone fields and height maps x robots, planned
as ``silo4 plan --terrain`` plans them and replayed as ``silo4 simulate`` replays them (its
default settings and limits) on the same terrain; prints per robot the plan rate, the walk
rate, the median planning time per step and every failure's reason.

    .venv/bin/python benchmarks/bench_terrain.py [--cases 12] [--seed 20261202]
                                                 [--robots silo4 mantis phasmid go2]
                                                 [--scenarios]

Case k is robot ``robots[k % R]`` at its height in HEIGHTS_M, on field kind
``FIELDS[(k // R) % 3]``: stones over a void, stones on a floor, a height map. A field is
laid out for the robot from its default workspace at that height (planner/workspace/layout.py):
a start platform under the standing feet, rows of posts (random radius, top height and
spacing) under the two columns the feet walk along, an end platform; the path is straight
along +y (the default start heading faces +y) to where the hind feet stand on the end
platform. A height map is smooth noise (a sum of random plane waves) of a random amplitude
over the whole walk. Planning is ``plan_path`` with the options ``silo4 plan`` parses by
default, then the run pipeline (URDF limits, torques: planner/outputs/pipeline.py); "plan
time" is plan_path's wall time, "per step" divides it by the plan's leg transfers.
``--scenarios`` also plans and replays every scenario of examples/terrain_scenarios.yaml
(block, stairs, gap, ramp, stones, rough, ditch; SILO4 at h = 0.4 m, go2 at 0.28 m) for the
robots it lists among ``--robots`` (``--cases 0``: the scenarios alone). A figure, not a
test: tests/test_terrain_bench.py runs a 3-case subset.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
#: The benchmark's robots: label -> load_robot argument (None: SILO4 from urdf/).
ROBOTS: dict[str, str | None] = {
    "silo4": None,
    "mantis": str(ROOT / "tests" / "robots" / "mantis.urdf"),
    "phasmid": str(ROOT / "tests" / "robots" / "phasmid.urdf.xacro"),
    "go2": "go2",
}
#: Body height of each robot [m]: SILO4's terrain height; mantis mid-range (docs/robots.md);
#: phasmid in the upper half of its range 0.15-0.517 m (at 0.3 m and below its RF hip pitch
#: needs more than 0.85 of its URDF effort standing still, and silo4 plan refuses the run);
#: go2's height that walks a straight path in physics (docs/robots.md).
HEIGHTS_M = {"silo4": 0.4, "mantis": 0.35, "phasmid": 0.36, "go2": 0.28}
DEFAULT_SEED = 20261202
#: Field kinds, in case order.
FIELDS = ("stones over a void", "stones on a floor", "height map")
#: Distance between rows of posts along the path, as a fraction of the stride [m/m].
ROW_SPACING = (0.45, 0.72)
#: Post radius beyond the edge margin [m], post top heights +- this fraction of h.
RADIUS_EXTRA_M = (0.025, 0.06)
TOP_SPREAD = 0.06
#: Lateral jitter of a post about its foot column [m].
LATERAL_JITTER_M = 0.02
#: Length of the stone field along the path, in strides.
FIELD_STRIDES = 2.5
#: Floor below the stone tops, as a fraction of h (stones on a floor).
FLOOR_DEPTH = (0.2, 0.5)
#: Height-map amplitude as a fraction of h, its cell [m], its waves' lengths [m].
MAP_AMPLITUDE = (0.025, 0.1)
MAP_RESOLUTION_M = 0.02
MAP_WAVELENGTH_M = (0.3, 1.2)
MAP_WAVES = 6
#: The terrain scenarios: per robot its height and, per scenario, file and waypoints.
SCENARIOS_FILE = ROOT / "examples" / "terrain_scenarios.yaml"


@dataclass(frozen=True)
class Layout:
    """Where a robot's feet stand, from its workspace at height h: foot columns at world x
    +-``column_x_m``, front and hind feet at world y ``front_y_m``/``hind_y_m`` (start pose,
    base at the origin facing +y), stride ``stride_m`` [m]."""

    column_x_m: float
    front_y_m: float
    hind_y_m: float
    stride_m: float
    height_m: float


@dataclass(frozen=True)
class Field:
    """One random terrain: its kind (FIELDS), terrain-file document and goal y [m]."""

    kind: str
    document: dict
    goal_y_m: float


@dataclass(frozen=True)
class Case:
    """One benchmark case: index, robot label, height [m], field."""

    index: int
    robot: str
    height_m: float
    field: Field

    def describe(self) -> str:
        return f"#{self.index} {self.robot} h={self.height_m:.3f} m {self.field.kind}"


@dataclass
class Outcome:
    """What a case gave: planned, walks, timings [s], leg transfers, failure reasons."""

    case: Case
    planned: bool = False
    walks: bool = False
    plan_s: float = 0.0
    transfers: int = 0
    reasons: list[str] = field(default_factory=list)

    @property
    def seconds_per_step(self) -> float:
        return self.plan_s / self.transfers if self.transfers else math.nan


def layout_for(robot, height_m: float) -> Layout:  # noqa: ANN001
    """The robot's standing feet and stride at ``height_m`` (default preset)."""
    from planner.workspace.layout import workspace_for

    ws = workspace_for(robot, height_m)
    mid = np.asarray(ws.position_mid_in_base)  # (4, 3) in B: x forward = world +y
    return Layout(
        column_x_m=float(np.mean(np.abs(mid[:, 1]))),
        front_y_m=float(mid[:, 0].max()),
        hind_y_m=float(mid[:, 0].min()),
        stride_m=float(ws.stride_m),
        height_m=height_m,
    )


def _edge_margin_m() -> float:
    from planner.gaits.surface_footholds import DEFAULT_FOOT_RADIUS_M, EDGE_EXTRA_M

    return DEFAULT_FOOT_RADIUS_M + EDGE_EXTRA_M


def _box(x0: float, x1: float, y0: float, y1: float, top: float, bottom: float) -> dict:
    return {
        "center": [0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (top + bottom)],
        "size": [x1 - x0, y1 - y0, top - bottom],
    }


def stone_field(rng: np.random.Generator, layout: Layout, on_floor: bool) -> Field:
    """Posts under the two foot columns between a start and an end platform (tops at z = 0),
    over a void or on a floor (module docstring)."""
    margin = _edge_margin_m()
    half_width = layout.column_x_m + 0.3
    start_y = layout.front_y_m + margin + 0.03
    bottom = -float(rng.uniform(*FLOOR_DEPTH)) * layout.height_m if on_floor else -0.5
    posts, y = [], start_y
    while y < start_y + FIELD_STRIDES * layout.stride_m:
        y += float(rng.uniform(*ROW_SPACING)) * layout.stride_m
        for side in (-1.0, 1.0):
            top = float(rng.uniform(-TOP_SPREAD, TOP_SPREAD)) * layout.height_m
            top = max(top, bottom + 0.01)
            x = side * layout.column_x_m + float(rng.uniform(-1, 1)) * LATERAL_JITTER_M
            posts.append(
                {
                    "center": [round(x, 4), round(y, 4), round(0.5 * (top + bottom), 4)],
                    "radius": round(margin + float(rng.uniform(*RADIUS_EXTRA_M)), 4),
                    "height": round(top - bottom, 4),
                }
            )
    end_y = y + 0.5 * layout.stride_m
    goal_y = end_y - layout.hind_y_m + margin + 0.05
    boxes = [
        _box(-half_width, half_width, layout.hind_y_m - 0.6, start_y, 0.0, bottom),
        _box(-half_width, half_width, end_y, goal_y + layout.front_y_m + 0.6, 0.0, bottom),
    ]
    document = {"floor": bottom if on_floor else None, "boxes": boxes, "cylinders": posts}
    return Field(FIELDS[1] if on_floor else FIELDS[0], document, round(goal_y, 4))


def height_map_field(rng: np.random.Generator, layout: Layout) -> Field:
    """A floor at z = 0 with smooth noise of a random amplitude (>= 0) over the walk."""
    goal_y = FIELD_STRIDES * layout.stride_m + layout.front_y_m
    x = np.arange(-layout.column_x_m - 0.5, layout.column_x_m + 0.5, MAP_RESOLUTION_M)
    y = np.arange(layout.hind_y_m - 0.5, goal_y + layout.front_y_m + 0.5, MAP_RESOLUTION_M)
    gx, gy = np.meshgrid(x, y)
    z = np.zeros_like(gx)
    for _ in range(MAP_WAVES):
        k = 2 * math.pi / float(rng.uniform(*MAP_WAVELENGTH_M))
        angle, phase = rng.uniform(0, 2 * math.pi, 2)
        z += np.cos(k * (math.cos(angle) * gx + math.sin(angle) * gy) + phase)
    amplitude = float(rng.uniform(*MAP_AMPLITUDE)) * layout.height_m
    z = amplitude * (z - z.min()) / max(float(np.ptp(z)), 1e-12)
    heightmap = {
        "heights": np.round(z, 5).tolist(),
        "resolution": MAP_RESOLUTION_M,
        "origin": [float(x[0]), float(y[0])],
    }
    return Field(FIELDS[2], {"floor": 0.0, "heightmap": heightmap}, round(goal_y, 4))


def terrain_cases(n_cases: int, seed: int, robots: list[str], layouts: dict) -> list[Case]:
    """The first ``n_cases`` cases of the seeded benchmark (module docstring); ``layouts``:
    robot label -> Layout."""
    rng = np.random.default_rng(seed)
    cases = []
    for k in range(n_cases):
        label = robots[k % len(robots)]
        kind = FIELDS[(k // len(robots)) % len(FIELDS)]
        layout = layouts[label]
        made = (
            height_map_field(rng, layout)
            if kind == FIELDS[2]
            else stone_field(rng, layout, on_floor=kind == FIELDS[1])
        )
        cases.append(Case(k, label, layout.height_m, made))
    return cases


def plan_and_walk(robot, waypoints_in_world: np.ndarray, height_m: float, document: dict):  # noqa: ANN001, ANN201
    """Plan on the terrain ``document`` as ``silo4 plan --terrain`` does (its default
    options), finish the run (limits, torques) and replay it as ``silo4 simulate`` does.
    Returns (planned, walks, plan_s, transfers, reasons)."""
    from planner.gaits.steps import StepKind
    from planner.outputs.pipeline import finish_plan
    from planner.path.plan_path import plan_path
    from planner.terrain import terrain_from_document
    from silo4kin.errors import Silo4Error
    from silo4sim.run import simulate
    from silo4sim.thresholds import Thresholds
    from viz.cli.main import build_parser
    from viz.cli.physics_options import preset_with_contact_rule
    from viz.report.run_outputs import run_request

    args = build_parser().parse_args(
        ["plan", "--waypoints", "0,1", "--height", str(height_m), "--out", "unused"]
    )
    t0 = time.perf_counter()
    try:
        terrain = terrain_from_document(document, name="bench")
        plan = plan_path(
            robot,
            waypoints_in_world,
            height_m,
            unit_time_s=1.0,
            start_heading=math.radians(args.start_heading),
            workspace=preset_with_contact_rule(args),
            tolerance=args.tolerance,
            samples_per_unit=args.samples_per_unit,
            swing_height_m=args.swing_height,
            face_path=args.face_path,
            gait=args.gait,
            terrain=terrain,
        )
    except Silo4Error as exc:
        return False, False, time.perf_counter() - t0, 0, [f"plan refused: {exc}"]
    plan_s = time.perf_counter() - t0
    transfers = sum(step.kind is StepKind.TRANSFER for step in plan.steps)
    try:
        request = replace(run_request(args, robot.joint_names), terrain=terrain)
        run = finish_plan(robot, plan, request)
    except Silo4Error as exc:
        return False, False, plan_s, transfers, [f"run refused: {exc}"]
    doc = simulate(robot, run.plan.trajectory, Thresholds(), terrain=terrain.to_document()).metrics
    reasons = [f"physics: {r}" for r in doc["reasons"]]
    return True, bool(doc["walks"]), plan_s, transfers, reasons


def run_case(robot, case: Case) -> Outcome:  # noqa: ANN001
    """Plan and replay one case (plan_and_walk)."""
    waypoints = np.array([[0.0, case.field.goal_y_m]])
    planned, walks, plan_s, transfers, reasons = plan_and_walk(
        robot, waypoints, case.height_m, case.field.document
    )
    return Outcome(case, planned, walks, plan_s, transfers, reasons)


def run_benchmark(n_cases: int, seed: int, robots: list[str], echo=print) -> list[Outcome]:  # noqa: ANN001
    """Every case, echoing one line per case (and its reasons) as it finishes."""
    from silo4kin import load_robot

    loaded = {label: load_robot(ROBOTS[label]) for label in robots}
    layouts = {label: layout_for(loaded[label], HEIGHTS_M[label]) for label in robots}
    outcomes = []
    for case in terrain_cases(n_cases, seed, robots, layouts):
        t0 = time.perf_counter()
        try:
            outcome = run_case(loaded[case.robot], case)
        except Exception as exc:  # a crash is a finding of the benchmark, reported as such
            outcome = Outcome(case, reasons=[f"crashed ({type(exc).__name__}): {exc}"])
        outcomes.append(outcome)
        verdict = "walks" if outcome.walks else "plans, FALLS" if outcome.planned else "REFUSED"
        per_step_ms = 1e3 * outcome.seconds_per_step
        echo(
            f"{case.describe()}: {verdict} (plan {outcome.plan_s:.1f} s, {outcome.transfers} "
            f"steps, {per_step_ms:.0f} ms/step; {time.perf_counter() - t0:.0f} s)"
        )
        for reason in outcome.reasons:
            echo(f"    {reason}")
    return outcomes


def summary(outcomes: list[Outcome]) -> list[str]:
    """Per robot and overall: plan rate, walk rate, median planning time per step."""
    lines = []
    for label in [*dict.fromkeys(o.case.robot for o in outcomes), None]:
        mine = [o for o in outcomes if label is None or o.case.robot == label]
        planned = sum(o.planned for o in mine)
        walked = sum(o.walks for o in mine)
        per_step = [o.seconds_per_step for o in mine if o.planned]
        median = f"{1e3 * statistics.median(per_step):.0f} ms/step" if per_step else "-"
        lines.append(
            f"{label or 'all':8s} plans {planned}/{len(mine)}, walks {walked}/{len(mine)}, "
            f"median planning time {median}"
        )
    return lines


def run_scenarios(robots: list[str], echo=print) -> list[tuple[str, str, bool]]:  # noqa: ANN001
    """Plan and replay every scenario of examples/terrain_scenarios.yaml for ``robots`` (those
    the file lists); echo one line each and return (robot, scenario, walks)."""
    import yaml

    from planner.terrain import load_terrain
    from silo4kin import load_robot

    registry = yaml.safe_load(SCENARIOS_FILE.read_text())
    results = []
    for label, entry in registry.items():
        if label not in robots:
            continue
        robot = load_robot(ROBOTS[label])
        for name, scenario in entry["scenarios"].items():
            path = ROOT / "examples" / "terrain" / scenario["file"]
            document = load_terrain(path).to_document()
            waypoints = np.array(
                [[float(v) for v in point.split(",")] for point in scenario["waypoints"].split()]
            )
            planned, walks, plan_s, transfers, reasons = plan_and_walk(
                robot, waypoints, float(entry["height"]), document
            )
            per_step = 1e3 * plan_s / transfers if transfers else math.nan
            verdict = "walks" if walks else "plans, FALLS" if planned else "REFUSED"
            echo(
                f"scenario {label} {scenario['file']} h={entry['height']}: {verdict}, "
                f"plan {plan_s:.2f} s, {transfers} steps, {per_step:.0f} ms/step"
            )
            for reason in reasons:
                echo(f"    {reason}")
            results.append((label, name, walks))
    return results


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=12)
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED)
    parser.add_argument("--robots", nargs="+", choices=list(ROBOTS), default=list(ROBOTS))
    parser.add_argument(
        "--scenarios",
        action="store_true",
        help="also plan and replay examples/terrain_scenarios.yaml (for the --robots it lists)",
    )
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    echo = lambda s: print(s, flush=True)  # noqa: E731
    if args.scenarios:
        walked = run_scenarios(args.robots, echo)
        print(f"scenarios: {sum(w for *_, w in walked)}/{len(walked)} walk")
    outcomes = run_benchmark(args.cases, args.seed, args.robots, echo)
    print(f"\n{args.cases} cases, seed {args.seed}, {time.perf_counter() - t0:.0f} s")
    for line in summary(outcomes):
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
