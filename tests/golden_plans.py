"""Golden-plan fingerprints: the plans a refactor must not move.

A fingerprint holds a plan's discrete parts exactly and its floats to a tolerance, so that it
tells a change of the plan from the last-bit noise of another CPU (numpy's SIMD paths differ
by ~1e-16 relative between AVX2 and AVX-512 machines; planner/ties.py keeps the planner's
choices from following that noise):

- ``samples``: the number of samples, exact;
- ``contact_sha256``: SHA-256 of the foot-contact array (uint8 bytes), exact;
- ``projections``: for each of time, body position, body yaw (planning frame in the world)
  and joint positions q, PROJECTIONS weighted sums of its values, with weights drawn from
  WEIGHT_SEED (random sign, magnitude 0.5-1.0 in steps of 1/2000: integers, the same on
  every machine); compared within PROJECTION_ATOL. A value moved by δ moves every sum by at
  least δ/2, so a 1e-8 rad step shows (5e-9 > 1e-9); noise moves them by ~2e-12 (measured:
  the 38 plans on AVX2 and AVX-512, largest difference 1.9e-12).

A plan that is refused fingerprints as ``{"error": "<class>: <message>"}``, compared exactly.

The cases: the 18 Chapter 6 plans (straight, circle, reduced-accuracy circle at h = 0.2,
0.4, 0.6 m, presets thesis and default) and 20 seeded random paths on SILO4, mantis,
phasmid and go2 (2-4 waypoints 0.3-1.0 m apart, random start heading, a height drawn
inside the robot's feasible range). The random cases are drawn once by ``--update`` and
stored with their inputs in ``golden_plans.json``, so the test replays exactly those.

    .venv/bin/python tests/golden_plans.py --update   # rewrite golden_plans.json (say why in
                                                      # the commit: the plans changed on purpose)
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

GOLDEN_FILE = Path(__file__).with_name("golden_plans.json")
ROBOTS_DIR = Path(__file__).with_name("robots")
#: Weighted sums per array and their tolerance (module docstring).
PROJECTIONS = 4
PROJECTION_ATOL = 1e-9
WEIGHT_SEED = 20261206
#: Robots of the random cases: name -> (file or library name, default-preset height range [m]
#: as feasible_height_range gave it when the cases were drawn).
RANDOM_ROBOTS: dict[str, tuple[str | None, tuple[float, float]]] = {
    "silo4": (None, (0.2, 0.6056)),
    "mantis": ("mantis.urdf", (0.1723, 0.5041)),
    "phasmid": ("phasmid.urdf.xacro", (0.15, 0.5142)),
    "go2": ("go2", (0.0449, 0.3811)),
}
RANDOM_COUNTS = {"silo4": 8, "mantis": 4, "phasmid": 4, "go2": 4}
RANDOM_SEED = 20261201


def _weights(size: int, k: int) -> np.ndarray:
    """The k-th weight vector for an array of ``size`` values (module docstring)."""
    rng = np.random.default_rng([WEIGHT_SEED, size, k])
    sign = 2.0 * rng.integers(0, 2, size) - 1.0
    return sign * (0.5 + rng.integers(0, 1001, size) / 2000.0)


FLOAT_FIELDS = ("t", "position_base_in_world", "yaw_base_in_world", "q")


def fingerprint_trajectory(trajectory: Any) -> dict[str, Any]:
    """The fingerprint (module docstring) of a sampled trajectory."""
    projections = {}
    for field in FLOAT_FIELDS:
        values = np.asarray(getattr(trajectory, field), dtype=np.float64).ravel()
        projections[field] = [float(_weights(values.size, k) @ values) for k in range(PROJECTIONS)]
    contact = np.ascontiguousarray(trajectory.contact, dtype=np.uint8).tobytes()
    return {
        "samples": len(trajectory.t),
        "contact_sha256": hashlib.sha256(contact).hexdigest(),
        "projections": projections,
    }


def fingerprint_error(exc: BaseException) -> dict[str, Any]:
    """The fingerprint of a refused plan: its error class and message."""
    return {"error": f"{type(exc).__name__}: {exc}"}


def fingerprint_differences(got: dict[str, Any], stored: dict[str, Any]) -> list[str]:
    """What differs between two fingerprints (empty: the same plan): exact parts, then
    projections beyond PROJECTION_ATOL."""
    exact = [k for k in ("error", "samples", "contact_sha256") if got.get(k) != stored.get(k)]
    if exact or "error" in got:
        return [f"{k}: {stored.get(k)!r} -> {got.get(k)!r}" for k in exact]
    out = []
    for field in FLOAT_FIELDS:
        a, b = np.array(got["projections"][field]), np.array(stored["projections"][field])
        if not np.allclose(a, b, rtol=0.0, atol=PROJECTION_ATOL):
            out.append(f"{field}: sums differ by up to {np.max(np.abs(a - b)):.3g}")
    return out


def thesis_case_specs() -> list[dict[str, Any]]:
    """The 18 Chapter 6 cases as plain inputs (planner/studies/cases.py defines the paths)."""
    straight = [[0.0, 1.0], [1.0, 1.0], [0.0, 2.0], [0.0, 3.0]]
    angles = 2 * math.pi * np.arange(1, 33) / 32  # 32 points, counter-clockwise
    circle = np.column_stack([-1.0 + np.cos(angles), np.sin(angles)])  # centre (-1, 0)
    circle[-1] = 0.0
    specs = []
    for path, waypoints, tolerance in (
        ("straight", straight, None),
        ("circle", circle.tolist(), None),
        ("circle-reduced", circle.tolist(), 0.15),
    ):
        for preset in ("thesis", "default"):
            for h in (0.2, 0.4, 0.6):
                specs.append(
                    dict(
                        name=f"{path}_h{h:.1f}_{preset}",
                        robot="silo4",
                        waypoints=waypoints,
                        height=h,
                        preset=preset,
                        start_heading=math.pi / 2,
                        tolerance=tolerance,
                    )
                )
    return specs


def random_case_specs() -> list[dict[str, Any]]:
    """20 seeded random paths (module docstring), drawn from RANDOM_SEED."""
    rng = np.random.default_rng(RANDOM_SEED)
    specs = []
    for robot, count in RANDOM_COUNTS.items():
        low, high = RANDOM_ROBOTS[robot][1]
        for k in range(count):
            n = int(rng.integers(2, 5))
            heading = float(rng.uniform(-math.pi, math.pi))
            point = np.zeros(2)
            waypoints = []
            direction = heading
            for _ in range(n):
                direction += float(rng.uniform(-2.0, 2.0))
                point = point + float(rng.uniform(0.3, 1.0)) * np.array(
                    [math.cos(direction), math.sin(direction)]
                )
                waypoints.append([round(float(point[0]), 4), round(float(point[1]), 4)])
            h = round(float(rng.uniform(low + 0.02, high - 0.02)), 4)
            specs.append(
                dict(
                    name=f"random_{robot}_{k}",
                    robot=robot,
                    waypoints=waypoints,
                    height=h,
                    preset="default",
                    start_heading=round(heading, 6),
                    tolerance=None,
                )
            )
    return specs


def robot_loader() -> Callable[[str], Any]:
    """A function robot key -> loaded Robot, each loaded once."""
    from silo4kin import load_robot

    loaded: dict[str, Any] = {}

    def get(key: str) -> Any:
        if key not in loaded:
            source = RANDOM_ROBOTS[key][0]
            if source is not None and source.endswith((".urdf", ".xacro")):
                source = str(ROBOTS_DIR / source)
            loaded[key] = load_robot(source)
        return loaded[key]

    return get


def plan_fingerprint(spec: dict[str, Any], robot: Any) -> dict[str, Any]:
    """Plan one case with the planner's public entry point and fingerprint it."""
    from planner import plan_path
    from silo4kin.errors import Silo4Error

    try:
        plan = plan_path(
            robot,
            np.asarray(spec["waypoints"], dtype=float),
            spec["height"],
            start_heading=spec["start_heading"],
            workspace=spec["preset"],
            tolerance=spec["tolerance"],
        )
    except Silo4Error as exc:
        return fingerprint_error(exc)
    return fingerprint_trajectory(plan.trajectory)


def load_golden() -> list[dict[str, Any]]:
    """The stored cases, each with its inputs and ``fingerprint``."""
    return json.loads(GOLDEN_FILE.read_text(encoding="utf-8"))["cases"]


def update() -> None:
    """Plan every case and rewrite GOLDEN_FILE."""
    get = robot_loader()
    cases = []
    for spec in thesis_case_specs() + random_case_specs():
        spec = dict(spec, fingerprint=plan_fingerprint(spec, get(spec["robot"])))
        print(f"{spec['name']:32s} {spec['fingerprint'].get('samples', 'refused')}", flush=True)
        cases.append(spec)
    doc = {"about": "tests/golden_plans.py: plans a refactor must not move", "cases": cases}
    GOLDEN_FILE.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    if sys.argv[1:] != ["--update"]:
        sys.exit("usage: tests/golden_plans.py --update")
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    update()
