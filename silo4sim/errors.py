"""Errors of the physics replay; all derive from silo4kin.errors.Silo4Error (CLI exit 2)."""

from __future__ import annotations

from silo4kin.errors import Silo4Error


class SimulationError(Silo4Error):
    """The physics replay cannot run on this input (e.g. a run folder without a trajectory)."""


class MujocoMissingError(SimulationError):
    """The optional ``mujoco`` package is not installed."""


class MujocoModelError(SimulationError):
    """The robot's URDF cannot become a MuJoCo model; the message names the element."""


def import_mujoco():  # noqa: ANN201 (the mujoco module)
    """Import MuJoCo on demand; a missing package is one clear line (exit 2)."""
    try:
        import mujoco
    except ImportError:
        raise MujocoMissingError(
            "the physics replay needs the 'mujoco' package: pip install 'silo4kin[sim]'"
        ) from None
    return mujoco
