"""The omnidirectional gaits' foothold region: each leg's foot stays inside the ellipse in B
centred on its position 2 (workspace.position_mid_in_base) with semi-axes λ_x/2 and λ_y/2
(the workspace strides along the body axes, whose ends the workspace checked for reach with
the shift reserve); along a body axis it is exactly the axis creeping gait's segment
rear-front (planner/gaits/omni.py, planner/gaits/crawl.py)."""

from __future__ import annotations

import math

import numpy as np

from planner.gaits.builder import StepBuilder
from planner.workspace.layout import Workspace
from silo4kin.frames import rotation_z

#: The ellipse is shrunk by this factor so a foothold on its edge is not a rounding error
#: away from the checked stride ends.
ELLIPSE_SCALE = 1.0 - 1e-9


def ellipse_semi_axes(ws: Workspace) -> np.ndarray:
    """(a_x, a_y) [m]: half the strides along the body axes."""
    return ELLIPSE_SCALE * 0.5 * np.array([ws.stride_m, ws.stride_lateral_m])


def ellipse_radius(ws: Workspace, u: np.ndarray) -> float:
    """Largest t [m] with t u inside the ellipse of semi-axes :func:`ellipse_semi_axes` (u unit,
    base frame)."""
    a = ellipse_semi_axes(ws)
    if np.any(a <= 0.0):
        return 0.0  # no stride along a body axis: no ellipse
    return float(1.0 / math.sqrt((u[0] / a[0]) ** 2 + (u[1] / a[1]) ** 2))


def stance_step_limit(ws: Workspace, offsets: np.ndarray, u: np.ndarray) -> float:
    """Largest t >= 0 [m] such that every offset r (N, 2) [m] from position 2 stays in the
    ellipse after r - t u (the stance feet as the body moves by t u); 0 if one is outside
    already. Closed form of the quadratic ((r_x - t u_x)/a_x)² + ((r_y - t u_y)/a_y)² = 1."""
    a = ellipse_semi_axes(ws)
    if np.any(a <= 0.0):
        return 0.0
    r = np.asarray(offsets, float) / a
    v = np.asarray(u, float) / a
    A = float(v @ v)
    B = -2.0 * (r @ v)
    C = np.einsum("ij,ij->i", r, r) - 1.0
    disc = B * B - 4.0 * A * C
    if np.any(C > 1e-12) or np.any(disc < 0):
        return 0.0
    roots = (-B + np.sqrt(np.maximum(disc, 0.0))) / (2.0 * A)
    return float(max(0.0, roots.min()))


def offsets_in_base(b: StepBuilder, ws: Workspace) -> np.ndarray:
    """Feet (4, 2) [m] relative to position 2, in B about the nominal CoG."""
    rel = (rotation_z(-b.nominal_yaw) @ (b.feet - b.nominal_base).T).T
    return rel[:, :2] - ws.position_mid_in_base[:, :2]
