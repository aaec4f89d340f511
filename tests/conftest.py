"""Shared fixtures: the SILO4 robot and Pinocchio reference values, computed once; go2, solo12,
anymal, hyq and the insect test robots (tests/robots: mantis, phasmid) loaded once per
pytest process (one per xdist worker).

A robot keeps what is computed from it in its memo (silo4kin/memo.py): its feasible height
range (go2 16 s, solo12 15 s, anymal 75 s, mantis 7 s, phasmid 10 s on the shared machine;
hyq refused after 50-65 s), workspaces, reachable sets, planning model. The session robots
below share those across test modules. They are read only: a test that changes a robot (its
legs, limits, foot radius, memo) or asserts that a computation on it happens (counts calls,
times it) loads its own with ``load_robot``; ``dataclasses.replace`` makes a new robot and
is fine. Monkeypatching a function whose result a memo keeps (planner/workspace:
feasible_height_range, _height_ok, foothold_layout, default_layout, _workspace,
default_psi_max, default_spin_suffices; silo4kin.foot_contact: _foot_ball_of) would leave
that result in a session robot's memo: such a test loads its own robot too.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from silo4kin import Robot, load_robot
from silo4kin.check import PinocchioSamples, pinocchio_samples, random_states

#: The insect test robots' files.
TEST_ROBOTS = Path(__file__).resolve().parent / "robots"

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


@pytest.fixture(scope="session")
def go2() -> Robot:
    """go2 from example-robot-data, one per pytest process (read only: module docstring)."""
    pytest.importorskip("example_robot_data")
    return load_robot("go2")


@pytest.fixture(scope="session")
def solo12() -> Robot:
    """solo12 from example-robot-data, one per pytest process (read only: module docstring)."""
    pytest.importorskip("example_robot_data")
    return load_robot("solo12")


@pytest.fixture(scope="session")
def anymal() -> Robot:
    """anymal from example-robot-data, one per pytest process (read only: module docstring)."""
    pytest.importorskip("example_robot_data")
    return load_robot("anymal")


@pytest.fixture(scope="session")
def hyq() -> Robot:
    """hyq from example-robot-data, one per pytest process (read only: module docstring). It
    has no feasible range (the refusal is not memoised), but the heights its search judged
    are (planner/workspace/heights.py _height_ok): a second refusal takes no time."""
    pytest.importorskip("example_robot_data")
    return load_robot("hyq")


@pytest.fixture(scope="session")
def mantis() -> Robot:
    """tests/robots/mantis.urdf, one per pytest process (read only: module docstring)."""
    return load_robot(TEST_ROBOTS / "mantis.urdf")


@pytest.fixture(scope="session")
def phasmid() -> Robot:
    """tests/robots/phasmid.urdf.xacro, one per pytest process (read only: module docstring)."""
    return load_robot(TEST_ROBOTS / "phasmid.urdf.xacro")
