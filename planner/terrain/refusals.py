"""What a refusal on a terrain file says about the ground (planner/gaits/surface_footholds.py):
a surface too steep under a foothold, feet the body over them cannot all reach. Each names the
terrain (TerrainMap.label) and the parts the feet are over (TerrainMap.describe_at)."""

from __future__ import annotations

import numpy as np

from planner.terrain.terrain_map import TerrainMap

#: Feet whose heights differ by less than this stand level [m] (a refusal then names no
#: highest and lowest foot: they would be the same leg).
LEVEL_M = 1e-6


def slope_clause(
    terrain: TerrainMap, xy_in_world: np.ndarray, limits: list[tuple[float, str]]
) -> str:
    """ ", which slopes T deg, steeper than L deg (why)" for the first of ``limits`` (limit
    [deg], why) the surface under the point (2,) [m] breaks; "" when it breaks none or the
    point is over a void."""
    xy = np.asarray(xy_in_world, dtype=float).reshape(1, 2)
    z, normal, _ = terrain.ground_at(xy)
    if not np.isfinite(z[0]):
        return ""
    tilt_deg = float(np.degrees(np.arctan2(np.hypot(*normal[0, :2]), normal[0, 2])))
    broken = [(deg, why) for deg, why in limits if tilt_deg > deg]
    if not broken:
        return ""
    deg, why = broken[0]
    return f", which slopes {tilt_deg:.1f} deg, steeper than {deg:.1f} deg ({why})"


def stance_out_of_reach(
    terrain: TerrainMap,
    position_feet_in_world: np.ndarray,
    height_m: float,
    leg: int,
    leg_names: tuple[str, ...],
) -> str:
    """Why the body ``height_m`` [m] above the mean height of the stance feet (4, 3) [m] does
    not reach foot ``leg``: the part it stands on, the height the feet span and the parts under
    the highest and the lowest foot."""
    feet = np.asarray(position_feet_in_world, dtype=float)
    names = [terrain.describe_at(foot[:2]) for foot in feet]
    high, low = int(np.argmax(feet[:, 2])), int(np.argmin(feet[:, 2]))
    head = (
        f"{terrain.label()}: leg {leg_names[leg]}'s foot on {names[leg]} is out of reach with the "
        f"body {height_m:.3g} m above the stance feet's mean height: "
    )
    if feet[high, 2] - feet[low, 2] < LEVEL_M:  # no highest and lowest foot to name
        return head + f"the feet stand level at z = {feet[high, 2]:.3g} m"
    return head + (
        f"the feet span {feet[high, 2] - feet[low, 2]:.3g} m in height, leg {leg_names[high]} "
        f"on {names[high]} at z = {feet[high, 2]:.3g} m, leg {leg_names[low]} on {names[low]} "
        f"at z = {feet[low, 2]:.3g} m"
    )
