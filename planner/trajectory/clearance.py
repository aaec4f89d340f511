"""How far an insect leg's tibia stays above the ground: the lowest point of the tibia capsule
the physics replay gives it (silo4sim/model.py), from the sampled joints in closed form.

The physics model (docs/physics.md) makes each tibia a capsule of radius r (the URDF's round
tibia shape, LegGeometry.tibia_radius_m from silo4kin.shapes) on the segment from
the knee axis to TIBIA_FOOT_GAP_M short of the foot tip; a foot tip on the ground with the
capsule below it puts the tibia on the floor. The 30-degree shank rule (planner/gaits/sway.py
MIN_SHANK_SLOPE_RAD) measures the shank from the outward horizontal and so passes a shank
folded under the body past the vertical: on SILO4 at h = 0.3 m, walking to (-1, -1) with
heading 0, the crawl's LF shank stood 162 deg below the outward horizontal (18 deg above the
inward one), the capsule 3.5 mm into the ground, and physics put LF and RH tibias on the
floor (docs/gaits.md). This module measures the capsule itself.

In the leg plane (eq 3.5, DH angles θ = axis_sign q + zero_offset) the knee is at
z_hip + L2 sin θ2 and the foot at z_knee + L3 sin(θ2 + θ3) in the base frame; the capsule's
far end is (L3 - gap)/L3 of the way from knee to foot. The planner keeps the body level (roll
= pitch = 0), so a point's height above the ground is the base height plus its z in B, and
the lowest point of a straight capsule is at one of its ends, minus its radius.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from planner.presets import MIN_GROUND_CLEARANCE_M
from planner.terrain.base import level_height
from planner.terrain.capsule_distance import capsule_clearance
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.clearance_text import mm_down
from planner.trajectory.samples import LEGS
from planner.trajectory.tibia_capsules import TIBIA_FOOT_GAP_M, tibia_capsule_violation
from silo4kin.leg_family import INSECT, family_of

#: Least height of the capsule's lowest point above the ground [m]. Measured (planner at
#: 10-20 samples per unit, `silo4 simulate`, SILO4, the floor 1 mm below the planner's ground
#: for the foot sphere): plans whose lowest capsule point was 0.0 (a crawl on the circle at
#: h 0.2, shank 23.6°), -1.3, -1.6, -3.1 and -3.5 mm put a tibia on the floor; plans at 1.0,
#: 1.8, 3.8, 3.9, 4.2 and 4.4 mm walked (docs/gaits.md, Tibia clearance). 2 mm above the
#: last touch.
MIN_TIBIA_CLEARANCE_M = 0.002


def tibia_clearance(legs, q: np.ndarray, height_base_m: np.ndarray) -> np.ndarray:
    """Height of the lowest point of each insect leg's tibia capsule above the ground [m],
    shape (N, 4) (NaN for a leg of another family), for joints q (N, 12) [rad] in legs order
    and base heights ``height_base_m`` (N,) [m] (body level, module docstring)."""
    q = np.asarray(q, dtype=float).reshape(len(q), -1, 3)
    n, n_legs = q.shape[:2]
    rows = np.tile(np.arange(n_legs), n)
    height = np.repeat(np.asarray(height_base_m, dtype=float), n_legs)
    return tibia_clearance_of_rows(legs, rows, q.reshape(-1, 3), height).reshape(n, n_legs)


def tibia_clearance_of_rows(
    legs, leg_index: np.ndarray, q: np.ndarray, height_base_m: np.ndarray | float
) -> np.ndarray:
    """:func:`tibia_clearance` of row i: leg ``legs[leg_index[i]]`` at joints q[i] (M, 3)
    [rad], base height ``height_base_m`` (M,) or scalar [m]; shape (M,), NaN for a leg of
    another family or a NaN joint value."""
    idx = np.asarray(leg_index, dtype=np.intp)
    q = np.asarray(q, dtype=float).reshape(-1, 3)
    const = _tibia_constants(legs)[:, idx]  # (10, M): each row's leg's, NaN for other families
    axis_sign, zero_offset = const[0:3].T, const[3:6].T
    theta = axis_sign * q + zero_offset  # LegGeometry.joint_to_dh
    hip_z, l2, l3_to_gap, radius = const[6], const[7], const[8], const[9]
    knee_z = hip_z + l2 * np.sin(theta[:, 1])
    end_z = knee_z + l3_to_gap * np.sin(theta[:, 1] + theta[:, 2])
    return (np.minimum(knee_z, end_z) - radius) + height_base_m


def _tibia_constants(legs) -> np.ndarray:
    """(10, L), one column per leg of :func:`tibia_clearance_of_rows`: axis_sign (3 rows),
    zero_offset (3), hip z [m], L2 [m], L3 minus TIBIA_FOOT_GAP_M [m] and the tibia radius
    [m] of an insect leg; NaN for a leg of another family."""
    out = np.full((10, len(legs)), np.nan)
    for k, leg in enumerate(legs):
        if family_of(leg) is INSECT:
            out[0:3, k] = leg.axis_sign
            out[3:6, k] = leg.zero_offset
            out[6, k] = leg.position_hip_in_base[2]
            out[7, k] = leg.L2
            out[8, k] = leg.L3 - TIBIA_FOOT_GAP_M
            out[9, k] = leg.tibia_radius_m
    return out


#: Samples per pass of :func:`clearance_of_poses` over a link's points on level ground: a
#: (rows, P) block that stays in the cache (47 k samples, 13 links of up to 48 points: 87 ->
#: 59 ms, the same values).
CLEARANCE_CHUNK_ROWS = 2048

#: Points along each tibia capsule's axis where the clearance above a terrain that is neither
#: level nor a TerrainMap is measured (a TerrainMap measures the whole axis).
CAPSULE_POINTS = 9


def trajectory_tibia_clearance(legs, trajectory, terrain=None) -> np.ndarray:
    """Height of each insect leg's tibia capsule above the terrain [m], (N, 4) (NaN for a
    leg of another family), for every sample of ``trajectory``. ``terrain`` (the Terrain
    protocol of planner/terrain/base.py; None: flat ground at z = 0): level ground of height
    z0 (planner.terrain.base.level_height) gives :func:`tibia_clearance` - z0; any other
    terrain is sampled under CAPSULE_POINTS points of each capsule's axis."""
    base = trajectory.position_base_in_world
    ground = 0.0 if terrain is None else level_height(terrain)
    if ground is not None:
        return tibia_clearance(legs, trajectory.q, base[:, 2]) - ground
    return _clearance_over_terrain(legs, trajectory, terrain)


def _clearance_over_terrain(legs, trajectory, terrain) -> np.ndarray:
    """:func:`trajectory_tibia_clearance` on a terrain that is not level: the capsule's axis
    in W (eq 3.5 with the knee instead of the foot, the body level and turned by its yaw),
    measured as a whole capsule on a TerrainMap (planner/terrain/capsule_distance.py: the
    axis's nearest point to a block's edge may lie between any points put on it), on any
    other terrain the :func:`sphere_clearance` of a sphere of the capsule's radius at each
    of its CAPSULE_POINTS points."""
    n = len(trajectory)
    q = np.asarray(trajectory.q, dtype=float).reshape(n, -1, 3)
    base = np.asarray(trajectory.position_base_in_world, dtype=float)
    yaw = np.asarray(trajectory.yaw_base_in_world, dtype=float)
    out = np.full((n, q.shape[1]), np.nan)
    fractions = np.linspace(0.0, 1.0, CAPSULE_POINTS)
    for k, leg in enumerate(legs):
        if family_of(leg) is not INSECT:
            continue
        theta = leg.joint_to_dh(q[:, k])
        phi = leg.theta_b + theta[:, 0] + yaw  # the leg plane's yaw in W
        radial = np.stack([np.cos(phi), np.sin(phi)], axis=-1)  # (N, 2)
        c, s = np.cos(yaw), np.sin(yaw)
        hip = np.asarray(leg.position_hip_in_base, dtype=float)
        hip_xy = base[:, :2] + np.stack([c * hip[0] - s * hip[1], s * hip[0] + c * hip[1]], -1)
        knee_r = leg.L1 + leg.L2 * np.cos(theta[:, 1])
        knee_z = base[:, 2] + hip[2] + leg.L2 * np.sin(theta[:, 1])
        reach = leg.L3 - TIBIA_FOOT_GAP_M
        end_r = knee_r + reach * np.cos(theta[:, 1] + theta[:, 2])
        end_z = knee_z + reach * np.sin(theta[:, 1] + theta[:, 2])
        if isinstance(terrain, TerrainMap):  # the whole axis (capsule_distance.py)
            knee = np.column_stack([hip_xy + knee_r[:, None] * radial, knee_z])
            end = np.column_stack([hip_xy + end_r[:, None] * radial, end_z])
            out[:, k] = capsule_clearance(terrain, knee, end, leg.tibia_radius_m)
            continue
        r = knee_r[:, None] + fractions * (end_r - knee_r)[:, None]  # (N, P)
        z = knee_z[:, None] + fractions * (end_z - knee_z)[:, None]
        xy = hip_xy[:, None, :] + r[..., None] * radial[:, None, :]  # (N, P, 2)
        centers = np.dstack([xy, z])  # (N, P, 3)
        out[:, k] = np.min(sphere_clearance(terrain, centers, leg.tibia_radius_m), axis=1)
    return out


def sphere_clearance(terrain, center_in_world: np.ndarray, radius_m) -> np.ndarray:
    """Signed clearance [m] of spheres (centres (..., 3) in W [m], radius broadcast to the
    centres' leading shape [m]) from ``terrain``, shape (...): the terrain's own
    ``sphere_clearance`` when it has one (TerrainMap: distance to its solids, side faces
    included), else the height above ``height_at`` under the centre less the radius."""
    centers = np.asarray(center_in_world, dtype=float)
    shape = centers.shape[:-1]
    flat = centers.reshape(-1, 3)
    radius = np.broadcast_to(np.asarray(radius_m, dtype=float), shape).reshape(-1)
    if hasattr(terrain, "sphere_clearance"):
        return np.asarray(terrain.sphere_clearance(flat, radius), dtype=float).reshape(shape)
    under = np.asarray(terrain.height_at(flat[:, :2]), dtype=float)
    return (flat[:, 2] - under - radius).reshape(shape)


def tibia_low(legs, trajectory, terrain=None) -> np.ndarray:
    """(N, 4) bool: the samples where a held leg's tibia capsule comes lower than
    MIN_TIBIA_CLEARANCE_M above the terrain (None: flat ground at z = 0), stance or swing.
    Held: insect legs whose capsule clears the margin at the first sample (a leg built
    otherwise, whose shank lies near the ground at rest, is not held to its capsule)."""
    clearance = trajectory_tibia_clearance(legs, trajectory, terrain)
    held = clearance[0] >= MIN_TIBIA_CLEARANCE_M  # NaN (other families): False
    return held & (clearance < MIN_TIBIA_CLEARANCE_M)


def tibia_violation(legs, trajectory, terrain=None) -> str | None:
    """One line for the first sample of :func:`tibia_low`, or None."""
    low = tibia_low(legs, trajectory, terrain)
    rows = np.flatnonzero(low.any(axis=1))
    if not rows.size:
        return None
    i = int(rows[0])
    k = int(np.argmax(low[i]))
    clearance = trajectory_tibia_clearance(legs, trajectory, terrain)[i, k]
    state = "stance" if trajectory.contact[i, k] else "swing"
    return (
        f"the tibia of {LEGS[k]} ({state}) comes {mm_down(clearance)} mm above the "
        f"ground at t = {trajectory.time_units[i]:.2f} units, under the "
        f"{1e3 * MIN_TIBIA_CLEARANCE_M:.0f} mm that keep it off"
    )


def ground_clearance(robot, trajectory, terrain=None, every: int = 1) -> np.ndarray:
    """Height above the terrain of the lowest non-foot collision shape of ``robot`` [m],
    shape (N, L): :func:`clearance_of_poses` at every ``every``-th sample of ``trajectory``
    (the last one included). ``terrain`` None: flat ground at z = 0."""
    rows = _rows(len(trajectory), every)
    return clearance_of_poses(
        robot,
        np.asarray(trajectory.q, dtype=float)[rows],
        np.asarray(trajectory.position_base_in_world, dtype=float)[rows],
        np.asarray(trajectory.yaw_base_in_world, dtype=float)[rows],
        terrain,
    )


class _BodyPose(NamedTuple):
    """The two fields of a Trajectory that root_pose_in_world reads."""

    position_base_in_world: np.ndarray
    yaw_base_in_world: np.ndarray


def _rows(n: int, every: int) -> np.ndarray:
    rows = np.arange(0, n, max(1, int(every)))
    return rows if rows[-1] == n - 1 else np.append(rows, n - 1)


def clearance_of_poses(
    robot,
    q: np.ndarray,
    position_base_in_world: np.ndarray,
    yaw_base_in_world: np.ndarray,
    terrain=None,
) -> np.ndarray:
    """Height above the terrain of the lowest point of each link's non-foot collision shapes
    (silo4kin.collision_shapes, the robot's URDF) [m], shape (N, L) for the L links of
    ``collision_points(robot).links``, at joints q (N, 12) [rad] in legs order, the planning
    frame's position (N, 3) [m] and yaw (N,) [rad] in W, the body level. The URDF root's
    pose is planner.outputs.root_pose's; a point's height is the root's plus its z in the
    root frame; over a terrain that is not level each point with its inflation is a sphere
    measured by :func:`sphere_clearance` (side faces seen). ``terrain`` None: flat ground
    at z = 0."""
    from planner.outputs.root_pose import root_pose_in_world
    from silo4kin.collision_shapes import collision_points
    from silo4kin.frame_placements import frame_heights, frame_placements, joint_axes

    shapes = collision_points(robot).links
    yaw = np.asarray(yaw_base_in_world, dtype=float).reshape(-1)
    com_in_root = np.asarray(robot.position_body_com_in_base, dtype=float)
    base = np.asarray(position_base_in_world, dtype=float).reshape(-1, 3)
    root = root_pose_in_world(_BodyPose(base, yaw), com_in_root).position_root_in_world  # type: ignore[arg-type]
    model, memo = robot.model, robot._memo
    if "joint_axes" not in memo:
        memo["joint_axes"] = joint_axes(model)
    q_full = np.zeros((len(yaw), model.nq))
    q_full[:, robot.q_index] = np.asarray(q, dtype=float).reshape(len(yaw), -1)
    frame_ids = [link.frame_id for link in shapes]
    ground = 0.0 if terrain is None else level_height(terrain)
    out = np.empty((len(yaw), len(shapes)))
    if ground is not None:  # only the z row of each link's rotation is needed
        z_axis_row, z_link = frame_heights(model, memo["joint_axes"], q_full, frame_ids)
        lift = root[:, 2] - ground
        for k, link in enumerate(shapes):
            points_t, inflation = link.points_in_link.T, link.inflation_m
            for a in range(0, len(yaw), CLEARANCE_CHUNK_ROWS):  # (rows, P) stays in cache
                z = z_axis_row[k, a : a + CLEARANCE_CHUNK_ROWS] @ points_t  # z in the link
                z -= inflation
                out[a : a + CLEARANCE_CHUNK_ROWS, k] = np.min(z, axis=1)
            out[:, k] += z_link[k] + lift
        return out
    rotation, translation = frame_placements(model, memo["joint_axes"], q_full, frame_ids)
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    for k, link in enumerate(shapes):
        pts = rotation[:, k] @ link.points_in_link.T + translation[:, k, :, None]  # (N, 3, P)
        xy = root[:, None, :2] + np.stack(
            [c * pts[:, 0] - s * pts[:, 1], s * pts[:, 0] + c * pts[:, 1]], -1
        )
        z_in_world = pts[:, 2] + root[:, None, 2]
        out[:, k] = np.min(
            sphere_clearance(terrain, np.dstack([xy, z_in_world]), link.inflation_m), axis=1
        )
    return out


def ground_contact_violation(
    robot, trajectory, terrain=None, every: int = 1, min_clearance_m: float = MIN_GROUND_CLEARANCE_M
) -> str | None:
    """One line naming the first sample and link of :func:`ground_clearance` below
    ``min_clearance_m`` [m], or None."""
    return ground_contact_violations(robot, trajectory, terrain, (min_clearance_m,), every)[0]


def ground_contact_violations(
    robot, trajectory, terrain=None, min_clearances_m: tuple[float, ...] = (0.0,), every: int = 1
) -> list[str | None]:
    """:func:`ground_contact_violation` for each of ``min_clearances_m`` [m], from one
    :func:`ground_clearance` pass (planner.outputs.pipeline refuses a touch, the first line,
    clearance under 0, and reports a clearance under the preset's margin). Over a terrain
    map with obstacles the first line is also a tibia capsule of the physics model nearer
    than MIN_TIBIA_CLEARANCE_M to a part (planner/trajectory/tibia_capsules.py): MuJoCo
    collides that capsule, not the tibia's URDF shapes, and touches it at the margin the
    insect rule measured (go2 on a 0.07 m block touched its calf when the plan held it
    0.4 mm off)."""
    from silo4kin.collision_shapes import collision_points

    clearance = ground_clearance(robot, trajectory, terrain, every)
    capsule = tibia_capsule_violation(robot, trajectory, terrain, MIN_TIBIA_CLEARANCE_M)
    lines: list[str | None] = []
    for min_clearance_m in min_clearances_m:
        low = clearance < min_clearance_m
        if not low.any():
            lines.append(None)
            continue
        i, k = np.argwhere(low)[0]
        row = int(_rows(len(trajectory), every)[i])
        link = collision_points(robot).links[k].link
        lines.append(
            f"link {link} comes {mm_down(clearance[i, k])} mm above "
            f"{_nearest_part(robot, trajectory, row, int(k), terrain)} at "
            f"t = {trajectory.time_units[row]:.2f} units, under the "
            f"{1e3 * min_clearance_m:.0f} mm kept off it by everything but the feet"
        )
    if capsule is not None and lines and lines[0] is None:
        lines[0] = capsule
    return lines


def _nearest_part(robot, trajectory, row: int, link: int, terrain) -> str:  # noqa: ANN001
    """What link ``link`` of collision_points comes nearest at sample ``row``: "the ground",
    or over a terrain map with obstacles its part ("box 0 of terrain file NAME")."""
    if not isinstance(terrain, TerrainMap) or not terrain.obstacles():
        return "the ground"
    q, base, yaw = (
        np.asarray(getattr(trajectory, name), dtype=float)[row : row + 1]
        for name in ("q", "position_base_in_world", "yaw_base_in_world")
    )
    each = [clearance_of_poses(robot, q, base, yaw, part)[0, link] for part in terrain.part_maps()]
    return f"{terrain.part_names()[int(np.argmin(each))]} of {terrain.label()}"


def check_ground_clearance(
    robot, trajectory, terrain=None, every: int = 1, min_clearance_m: float = MIN_GROUND_CLEARANCE_M
) -> None:
    """Raise PlanningError with :func:`ground_contact_violation`'s line when a non-foot shape
    of ``robot`` comes under ``min_clearance_m`` [m] above the terrain."""
    from planner.errors import PlanningError

    violation = ground_contact_violation(robot, trajectory, terrain, every, min_clearance_m)
    if violation is not None:
        raise PlanningError(violation)
