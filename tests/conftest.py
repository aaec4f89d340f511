"""Shared fixtures: the SILO4 robot and Pinocchio reference values, computed once."""

from __future__ import annotations

import os

import pytest

from silo4kin import Robot, load_robot
from silo4kin.check import PinocchioSamples, pinocchio_samples, random_states

#: Random configurations per leg for the closed-form vs Pinocchio cross-checks (issue 2: >= 1000).
N_CROSS_CHECK = 1000


@pytest.fixture(scope="session", autouse=True)
def _tmp_silo4_cache(tmp_path_factory: pytest.TempPathFactory) -> None:
    """The tests' silo4 cache (viz/cli/robot_cache.py) is a temporary folder, never the user's."""
    os.environ["SILO4_CACHE_DIR"] = str(tmp_path_factory.mktemp("silo4-cache"))


@pytest.fixture(scope="session")
def silo4() -> Robot:
    """The SILO4 robot from urdf/silo4.urdf.xacro with default arguments."""
    return load_robot()


@pytest.fixture(scope="session")
def pin_reference(silo4: Robot) -> PinocchioSamples:
    """Pinocchio FK, Jacobians, dJ*qd, M, C*qd, G, rnea on 1000 seeded random states."""
    q, v, a = random_states(silo4, N_CROSS_CHECK, seed=20081)
    return pinocchio_samples(silo4, q, v, a)
