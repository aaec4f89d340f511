"""A ball foot standing on a terrain's surface: where its foot frame is over the point it
touches, and the body height over the points the feet touch.

A ball of radius r centred on the foot frame (silo4kin.foot_contact.FootBall: the foot's
contact offset r - o_z, the equivalent ball of an offset one) that rests on a plane of unit
normal n touches it at centre - r n: its centre is the contact point + r n, straight above
it only on level ground (n = ẑ), and the contact point is r n_z below the centre. Every
function here keeps level ground bit for bit: there, it adds r to z and nothing else.
"""

from __future__ import annotations

import numpy as np

from planner.trajectory.heightmap_rest import rest_on_heightmap


def foot_frames_on_surface(
    terrain, position_contact_in_world: np.ndarray, offset_m: float
) -> np.ndarray:
    """The foot frames (N, 3) [m] in W of balls of radius ``offset_m`` [m] touching
    ``terrain`` (its normal_at) at the contact points (N, 3) [m] on its surface: contact
    point + r n, n the normal under the contact point (module docstring). On a height map
    a contact point within r tan(δ/2) of a concave crease (the neighbouring triangle rising
    by δ) would put that centre inside the neighbouring triangle: the centre is lifted
    along the contact normal until it is r from every triangle, so the ball touches the
    rising one (planner/trajectory/heightmap_rest.py; its contact point moves by at most
    2 r tan(δ/2), the distance between the points where a ball seated in the crease touches
    it)."""
    contact = np.asarray(position_contact_in_world, dtype=float).reshape(-1, 3)
    feet = contact.copy()
    if offset_m == 0.0:
        return feet
    normal = terrain.normal_at(contact[:, :2])
    feet[:, 2] += offset_m * normal[:, 2]
    tilted = np.any(normal[:, :2] != 0.0, axis=1)  # level rows keep their x, y bit for bit
    feet[tilted, :2] += offset_m * normal[tilted, :2]
    if getattr(terrain, "heightmap", None) is not None:
        with np.errstate(invalid="ignore"):
            feet = rest_on_heightmap(terrain, feet, offset_m)[0]
    return feet


def body_height(
    terrain, position_feet_in_world: np.ndarray, offset_m: float, height_m: float
) -> float:
    """The base z [m] ``height_m`` [m] above the mean z of the points where balls of radius
    ``offset_m`` [m] centred on the stance feet's frames (4, 3) [m] touch the surface under
    them: foot z - r n_z (module docstring). n is asked under the foot frame, r |n_xy| from
    its contact point (<= r sin 20 deg, within the foothold's edge margin r + 2 cm:
    planner/gaits/surface_footholds.py), so on the same plane. Level ground: mean z - r +
    height_m, in that order (the plans before slopes, bit for bit)."""
    feet = np.asarray(position_feet_in_world, dtype=float).reshape(-1, 3)
    normal_z = terrain.normal_at(feet[:, :2])[:, 2] if offset_m != 0.0 else None
    if normal_z is None or np.all(normal_z == 1.0):
        return float(np.mean(feet[:, 2])) - offset_m + height_m
    return float(np.mean(feet[:, 2] - offset_m * normal_z)) + height_m
