"""A robot's gearing from a small motor table (``--motors-file``, docs/torques.md).

A JSON (or, with PyYAML installed, YAML) mapping::

    {"gear_ratio": 6.33, "gear_efficiency": 0.9,            every joint (optional)
     "joints": {"calf": {"gear_ratio": 10.0},               a joint type: every leg's
                "FL_hip_joint": {"gear_efficiency": 0.8}}}  one joint, by URDF name

A key of ``joints`` names one joint exactly, or a joint type: the part of the joint names
after the leg prefix (``calf`` and ``calf_joint`` match ``FL_calf_joint``; ``HFE`` matches
``HL_HFE``). For each joint and each of the two numbers, the joint's own entry wins, then
its type's, then the top-level value. A joint left without a gear ratio or an efficiency is
an error: a table sizes every joint from the robot's data or says it cannot.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .errors import Silo4Error
from .motors import Gearing

#: The two numbers a table gives per joint: (key, what it is).
NUMBERS = (("gear_ratio", "gear ratio mu"), ("gear_efficiency", "gear efficiency eta"))


def read_motor_table(path: str | Path, joint_names: Sequence[str]) -> Gearing:
    """The gearing of joints ``joint_names`` (J,) from the motor table at ``path``.

    Raises:
        Silo4Error: unreadable file, bad structure, a key matching no joint, a joint without
            a value, a value out of range (Gearing's checks).
    """
    path = Path(path)
    table = _load(path)
    names = list(joint_names)
    top = {key: table[key] for key, _ in NUMBERS if key in table}
    unknown = set(table) - {"joints", *(key for key, _ in NUMBERS)}
    if unknown:
        raise Silo4Error(
            f"{path}: unknown keys {sorted(unknown)}; expected gear_ratio, gear_efficiency, joints"
        )
    joints = table.get("joints", {})
    if not isinstance(joints, Mapping):
        raise Silo4Error(f"{path}: 'joints' must map joint names or types to numbers")
    entries = {str(k): _entry(path, str(k), v) for k, v in joints.items()}
    for key in entries:
        if not any(key == n or _is_type(n, key) for n in names):
            raise Silo4Error(f"{path}: {key!r} matches no joint of {names}")
    values: dict[str, list[float]] = {key: [] for key, _ in NUMBERS}
    for name in names:
        chain = [
            entries.get(name, {}),
            *(e for k, e in entries.items() if k != name and _is_type(name, k)),
            top,
        ]
        for key, what in NUMBERS:
            value = next((e[key] for e in chain if key in e), None)
            if value is None:
                raise Silo4Error(
                    f"{path}: no {what} ({key}) for joint {name!r}: give it, "
                    "its type's or a top-level value"
                )
            values[key].append(_number(path, key, value))
    return Gearing(
        np.asarray(values["gear_ratio"]),
        np.asarray(values["gear_efficiency"]),
        f"motors file {path.name}",
    )


def gearing_from_options(
    joint_names: Sequence[str],
    gear_ratio: float,
    gear_efficiency: float,
    motors_file: str | Path | None = None,
) -> Gearing:
    """The gearing a command asks for: the motor table when ``motors_file`` is given (the
    options' mu and eta then unused), else ``gear_ratio`` and ``gear_efficiency`` for every
    joint (source: assumed when they are SILO4's defaults, else given)."""
    if motors_file is not None:
        return read_motor_table(motors_file, joint_names)
    return Gearing.uniform(len(joint_names), gear_ratio, gear_efficiency)


def _load(path: Path) -> dict[str, Any]:
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise Silo4Error(f"cannot read motor table {path}: {exc.strerror or exc}") from exc
    try:
        if path.suffix.lower() in (".yaml", ".yml"):
            import yaml

            data = yaml.safe_load(text)
        else:
            data = json.loads(text)
    except ImportError as exc:
        raise Silo4Error(
            f"{path}: a YAML motor table needs PyYAML (pip install pyyaml); or write it as JSON"
        ) from exc
    except Exception as exc:  # json.JSONDecodeError; yaml.YAMLError derives from Exception
        raise Silo4Error(f"{path}: not a motor table: {exc}") from exc
    if not isinstance(data, dict):
        raise Silo4Error(
            f"{path}: a motor table is a mapping (module docstring of silo4kin.motor_table)"
        )
    return data


def _entry(path: Path, key: str, value: Any) -> dict[str, Any]:
    if not isinstance(value, Mapping) or not set(value) <= {k for k, _ in NUMBERS}:
        raise Silo4Error(
            f"{path}: joints.{key} must map gear_ratio and/or gear_efficiency to numbers"
        )
    return dict(value)


def _number(path: Path, key: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise Silo4Error(f"{path}: {key} {value!r} is not a number")
    return float(value)


def _is_type(joint_name: str, key: str) -> bool:
    """``key`` names the type of ``joint_name``: its name after the leg prefix."""
    tail = joint_name.split("_", 1)[1] if "_" in joint_name else ""
    return bool(tail) and tail in (key, f"{key}_joint")
