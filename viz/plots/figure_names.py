"""The names of a run's figures and the plots' time window, for the CLI before any plotting
starts (this module imports neither numpy nor matplotlib)."""

from __future__ import annotations

import math
import re
from typing import Any

from silo4kin.errors import Silo4Error


def parse_window(text: str) -> tuple[float, float]:
    """``"T0:T1"`` [s] -> (t0, t1) with 0 <= t0 < t1 (the ``--window`` option)."""
    parts = text.split(":")
    try:
        t0, t1 = (float(p) for p in parts)
    except ValueError:
        raise Silo4Error(f"--window {text!r}: expected T0:T1 in seconds, e.g. 10:20") from None
    if not (math.isfinite(t0) and math.isfinite(t1) and 0 <= t0 < t1):
        raise Silo4Error(f"--window {text!r}: need 0 <= T0 < T1 [s]")
    return t0, t1


def figure_stems(trajectory: Any, window: bool = False) -> list[str]:
    """The stems ``write_plots`` writes for this trajectory, in order."""
    stems = [
        "joint_positions",
        "joint_velocities",
        "joint_accelerations",
        "path",
        "stability_margin",
        "cycle_cartesian",
    ]
    if trajectory.tau is not None:
        stems += ["torques"] + [
            "torques_" + re.sub(r"[^A-Za-z0-9_-]+", "_", p) for p in sorted(trajectory.tau_parts)
        ]
    if window:
        stems += [f"{s}_window" for s in stems[:3]] + (
            ["torques_window"] if trajectory.tau is not None else []
        )
    return stems
