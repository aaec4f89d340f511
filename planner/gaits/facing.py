"""Turn choices of the default policy's path follower (planner/path/plan_path.py): the crab range of a
height and the look-ahead turn that keeps the most following path legs within it."""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from planner.gaits.creep_spin import crab_limit_rad, spin_cycles
from planner.workspace.layout import Workspace, workspace_for
from silo4kin.robot import Robot

#: Turns tried between the two ends of the crab range, and the slack kept on the following
#: path legs (their actual start is the reached CoG, up to λ/4 off the waypoint) [rad].
LOOKAHEAD_SAMPLES = 61
LOOKAHEAD_SLACK_RAD = math.radians(5.0)


@lru_cache(maxsize=64)
def crab_limit(robot: Robot, height: float) -> float:
    """gaits.crab_limit_rad of the default workspace, cached per robot and height [rad]."""
    return crab_limit_rad(robot, workspace_for(robot, height, "default"))


def wrap(angle: float) -> float:
    """angle [rad] wrapped to (-π, π]."""
    return math.pi - (math.pi - angle) % (2.0 * math.pi)


def lookahead_turn(ws: Workspace, wp: np.ndarray, k: int, yaw: float, angle: float,
                   crab_max: float) -> float:
    """The turn ψ [rad] before walking to waypoint k, which lies ``angle`` [rad] off the
    heading ``yaw``: any ψ leaving it within ±``crab_max`` [rad] of the new heading will do, so
    among those needing the fewest spinning cycles take the ones under which the most of the
    following path legs (waypoint to waypoint, in order) stay within the crab range less
    LOOKAHEAD_SLACK_RAD, and of those the middle one (when no leg stays in range: the one
    nearest ψ = angle, facing the waypoint)."""
    grid = np.linspace(angle - crab_max, angle + crab_max, LOOKAHEAD_SAMPLES)
    cycles = np.array([spin_cycles(ws, float(psi)) for psi in grid])
    grid = grid[cycles == cycles.min()]
    legs = np.diff(wp[k:], axis=0)
    headings = [math.atan2(v[1], v[0]) for v in legs if math.hypot(v[0], v[1]) > 1e-9]
    runs = []
    for psi in grid:
        run = 0
        for h in headings:
            if abs(wrap(h - yaw - psi)) > crab_max - LOOKAHEAD_SLACK_RAD:
                break
            run += 1
        runs.append(run)
    if max(runs) == 0:
        return float(grid[np.argmin(np.abs(grid - angle))])
    best = grid[np.array(runs) == max(runs)]
    return float(best[len(best) // 2])
