"""Golden-plan fingerprints: the plans a refactor must not move.

A fingerprint is the SHA-256 of a plan's samples: time, body pose (the planning frame's
position and yaw in the world), joint positions q and foot contacts, each rounded to 1e-9
(-0.0 folded to 0.0) and hashed as little-endian float64 / uint8 bytes in that order. A plan
that is refused fingerprints as its error class and message.

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
#: Rounding of every hashed float [same unit as the quantity].
ROUNDING_DECIMALS = 9
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


def _rounded(values: np.ndarray) -> bytes:
    a = np.round(np.asarray(values, dtype=np.float64), ROUNDING_DECIMALS) + 0.0
    return np.ascontiguousarray(a, dtype="<f8").tobytes()


def fingerprint_trajectory(trajectory: Any) -> str:
    """SHA-256 (hex) of t, body position, body yaw, q (rounded to 1e-9) and contact."""
    digest = hashlib.sha256()
    for values in (
        trajectory.t,
        trajectory.position_base_in_world,
        trajectory.yaw_base_in_world,
        trajectory.q,
    ):
        digest.update(_rounded(values))
    digest.update(np.ascontiguousarray(trajectory.contact, dtype=np.uint8).tobytes())
    return digest.hexdigest()


def fingerprint_error(exc: BaseException) -> str:
    """The fingerprint of a refused plan: its error class and message."""
    text = f"{type(exc).__name__}: {exc}"
    return "error:" + hashlib.sha256(text.encode()).hexdigest()


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


def plan_fingerprint(spec: dict[str, Any], robot: Any) -> str:
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
        print(f"{spec['name']:32s} {spec['fingerprint'][:16]}", flush=True)
        cases.append(spec)
    doc = {"about": "tests/golden_plans.py: plans a refactor must not move", "cases": cases}
    GOLDEN_FILE.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    if sys.argv[1:] != ["--update"]:
        sys.exit("usage: tests/golden_plans.py --update")
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    update()
