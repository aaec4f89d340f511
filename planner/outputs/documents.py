"""plan.json and metrics.json: what identifies a run, and plain JSON of any result.

plan.json holds the format tag (:data:`RUN_FORMAT`, which marks a folder as a silo4 run
folder), the run's inputs (:func:`plan_inputs`: what the plan records, and the caller's
requests that it does not, :data:`OPTION_DEFAULTS`), the workspace numbers and the step
list. A plan.json written before a request was recorded lacks its key and is read as that
request's default (:func:`read_run_inputs`), so old run folders stay "the same run".
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from silo4kin.errors import Silo4Error
from silo4kin.motor_defaults import DEFAULT_GEAR_EFFICIENCY, DEFAULT_GEAR_RATIO

#: Format tag written into plan.json; identifies a folder as a silo4 run folder.
RUN_FORMAT = "silo4kin.run/1"

#: The requests recorded in plan.json "inputs" that the plan itself does not carry
#: (``write_run(options=...)``), each with its default: the value ``silo4 plan`` uses when the
#: option is not given, and the value a plan.json that lacks the key is read as (older runs).
OPTION_DEFAULTS: dict[str, Any] = {
    "gait": "auto",  # plan_path(gait=): "auto", "crawl" or "creep"
    "face_path": False,  # plan_path(face_path=): turn to face each segment
    "swing_height_request_m": None,  # plan_path(swing_height_m=) [m]; None: eq 5.12
    "unit_time_auto": False,  # --unit-time auto: the shortest unit time within the limits
    "torques": True,  # tau columns and motor sizing written
    "load": None,  # --load: "body" or "total"; None: the preset's load
    "gear_ratio": DEFAULT_GEAR_RATIO,  # eq A.35-A.36 [dimensionless]
    "gear_efficiency": DEFAULT_GEAR_EFFICIENCY,  # eq A.36 [dimensionless]
    "motors_file": None,  # --motors-file: the motor table's path, or None
    "terrain": None,  # --terrain: the terrain file's content (planner/terrain/), or None
}


def to_jsonable(value: Any) -> Any:
    """numpy scalars/arrays, tuples, Paths -> plain JSON types; NaN/inf -> None."""
    kind = type(value)  # the plain types first (plan.json: ~10,000 values a run)
    if kind is float:
        return value if math.isfinite(value) else None
    if kind is str or kind is int or kind is bool or value is None:
        return value
    if kind is dict:
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if kind is list or kind is tuple:
        return [to_jsonable(v) for v in value]
    if isinstance(value, Mapping):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, (np.integer, int)):
        return int(value)
    if isinstance(value, (np.floating, float)):
        v = float(value)
        return v if math.isfinite(v) else None
    if isinstance(value, (np.str_, Path)):
        return str(value)
    return value


def plan_inputs(
    plan: Any, robot_name: str, options: Mapping[str, Any] | None = None
) -> dict[str, Any]:
    """What identifies a run: the same inputs give the same plan (compared before replacing).

    Keys read off the plan: robot, waypoints_in_world [m], height_m, height_auto (``height=
    "auto"``: Plan.height_search is set), workspace, start_heading_deg, tolerance_m,
    stability_threshold_m, samples_per_unit, unit_time_s; then every key of
    :data:`OPTION_DEFAULTS`, from ``options`` where given, else its default.

    Raises:
        Silo4Error: an ``options`` key that is not in OPTION_DEFAULTS.
    """
    unknown = sorted(set(options or {}) - set(OPTION_DEFAULTS))
    if unknown:
        raise Silo4Error(f"unknown run options {unknown}; known: {sorted(OPTION_DEFAULTS)}")
    trajectory = plan.trajectory
    samples_per_unit = getattr(plan, "samples_per_unit", None)
    if samples_per_unit is None and len(trajectory) > 1:
        units = float(trajectory.time_units[-1] - trajectory.time_units[0])
        samples_per_unit = round((len(trajectory) - 1) / units) if units > 0 else None
    return to_jsonable(
        {
            "robot": robot_name,
            "waypoints_in_world": np.asarray(plan.waypoints_in_world, dtype=float),
            "height_m": float(plan.height),
            "height_auto": getattr(plan, "height_search", None) is not None,
            "workspace": getattr(plan.workspace, "preset", str(plan.workspace)),
            "start_heading_deg": math.degrees(float(plan.start_heading)),
            "tolerance_m": plan.tolerance,
            "stability_threshold_m": plan.stability_threshold,
            "samples_per_unit": samples_per_unit,
            "unit_time_s": float(trajectory.unit_time_s),
            **OPTION_DEFAULTS,
            **(options or {}),
        }
    )


def plan_document(
    plan: Any, robot_name: str, options: Mapping[str, Any] | None = None
) -> dict[str, Any]:
    """The content of plan.json: format tag, inputs (:func:`plan_inputs`), workspace numbers
    and the step list."""
    workspace = plan.workspace
    trajectory = plan.trajectory
    return to_jsonable(
        {
            "format": RUN_FORMAT,
            "inputs": plan_inputs(plan, robot_name, options),
            "robot": robot_name,
            "height_m": float(plan.height),
            "start_heading_rad": float(plan.start_heading),
            "height_search": getattr(plan, "height_search", None),
            "gait": getattr(plan, "gait", None),
            "fallback_reason": getattr(plan, "fallback_reason", None),
            "workspace": {
                "preset": getattr(workspace, "preset", None),
                "stride_m": getattr(workspace, "stride_m", None),
                "swing_height_m": getattr(workspace, "swing_height_m", None),
            },
            "stride_m": getattr(workspace, "stride_m", None),
            "n_samples": len(trajectory),
            "duration_units": float(trajectory.time_units[-1]) if len(trajectory) else 0.0,
            "steps": [step.to_dict() for step in plan.steps],
        }
    )


def write_json(path: Path, document: Mapping[str, Any], *, plain: bool = False) -> None:
    """``document`` as JSON (``plain``: already made of JSON types, :func:`to_jsonable`)."""
    with open(path, "w") as f:
        json.dump(document if plain else to_jsonable(document), f, indent=1, allow_nan=False)
        f.write("\n")


#: Keys read off the plan that a plan.json written before they were recorded lacks, with
#: the value such a run had (see OPTION_DEFAULTS for the caller's requests).
_PLAN_KEY_DEFAULTS: dict[str, Any] = {"height_auto": False}


def read_run_inputs(folder: Path) -> dict[str, Any] | None:
    """The inputs recorded in a folder's plan.json, a missing key read as its default
    (:data:`OPTION_DEFAULTS`: an older plan.json), or None if it is not a run folder."""
    try:
        document = json.loads((folder / "plan.json").read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(document, dict) or document.get("format") != RUN_FORMAT:
        return None
    inputs = document.get("inputs")
    if not isinstance(inputs, dict):
        return None
    return {**_PLAN_KEY_DEFAULTS, **to_jsonable(OPTION_DEFAULTS), **inputs}
