"""World-frame markers of animation.html: ground, path, footholds, CoG trace, support polygon.

All positions are in the world frame W [m] (z up, ground z = 0). The support polygon (thesis
§5.1) is the convex hull of the stance feet; it only changes when a foot touches down or
lifts off, so its edges are discrete keyframe tracks keyed at those samples.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from viz.animation.recorder import (
    RecorderWindow,
    buffer_geometry,
    material,
    matrix_to_js,
    scene_object,
)
from viz.animation.scene import (
    COLOR_COG,
    COLOR_FOOTHOLD,
    COLOR_GROUND,
    COLOR_PATH,
    COLOR_SUPPORT,
    MAX_SUPPORT_EDGES,
    Z_LINES,
    Z_MARKERS,
)

#: Most vertices of the drawn CoG trace (the trace is decimated to this).
MAX_TRACE_POINTS = 4000
#: Margin of the ground patch and camera framing around the plan [m].
FRAME_MARGIN = 0.5
#: Ground grid cell [m].
GRID_CELL = 0.5
#: Grid line colour.
COLOR_GRID = 0xB0B0A8


class EdgeKeys(NamedTuple):
    """Discrete keys of one support-polygon edge (a unit box scaled along x).

    Attributes:
        times_s: key times [s], shape (K,).
        visible: edge in use, K booleans.
        position: edge midpoint in W [m], shape (K, 3).
        yaw: edge direction [rad], shape (K,).
        scale: (length [m], 1, 1), shape (K, 3).
    """

    times_s: np.ndarray
    visible: np.ndarray
    position: np.ndarray
    yaw: np.ndarray
    scale: np.ndarray


def convex_hull_2d(points_xy: np.ndarray) -> np.ndarray:
    """Counter-clockwise convex hull (Andrew's monotone chain) of ``points_xy: (M, 2)``.

    Returns:
        hull vertices, shape (H, 2), H <= M, no repeated vertex; M < 3 returns the
        unique points.
    """
    pts = np.unique(np.round(points_xy, 12), axis=0)
    if len(pts) < 3:
        return pts

    def turn(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
        return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))

    def half(sequence: np.ndarray) -> list[np.ndarray]:
        chain: list[np.ndarray] = []
        for p in sequence:
            while len(chain) >= 2 and turn(chain[-2], chain[-1], p) <= 0:
                chain.pop()
            chain.append(p)
        return chain

    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def support_polygon_keys(t_s: np.ndarray, contact: np.ndarray, feet: np.ndarray) -> list[EdgeKeys]:
    """Keys of the support polygon's edges at every contact change.

    Args:
        t_s: playback times [s], shape (N,).
        contact: stance flags, shape (N, 4).
        feet: position_foot_in_world [m], shape (N, 4, 3).

    Returns:
        MAX_SUPPORT_EDGES edge key sets; unused edges are invisible.
    """
    n = len(t_s)
    events = np.concatenate(
        [[0], np.flatnonzero(np.any(contact[1:] != contact[:-1], axis=1)) + 1, [n - 1]]
    )
    k = len(events)
    visible = np.zeros((MAX_SUPPORT_EDGES, k), dtype=bool)
    position = np.zeros((MAX_SUPPORT_EDGES, k, 3))
    yaw = np.zeros((MAX_SUPPORT_EDGES, k))
    scale = np.ones((MAX_SUPPORT_EDGES, k, 3))
    for e, i in enumerate(events):
        hull = convex_hull_2d(feet[i, contact[i], :2])
        count = len(hull) if len(hull) >= 3 else (1 if len(hull) == 2 else 0)
        for edge in range(min(count, MAX_SUPPORT_EDGES)):
            a, b = hull[edge], hull[(edge + 1) % len(hull)]
            visible[edge, e] = True
            position[edge, e] = [*(0.5 * (a + b)), Z_LINES]
            yaw[edge, e] = np.arctan2(b[1] - a[1], b[0] - a[0])
            scale[edge, e, 0] = max(float(np.hypot(*(b - a))), 1e-6)
    return [
        EdgeKeys(t_s[events], visible[m], position[m], yaw[m], scale[m])
        for m in range(MAX_SUPPORT_EDGES)
    ]


def _line(rec: RecorderWindow, path: str, points: np.ndarray, color: int) -> None:
    rec.record(
        {
            "type": "set_object",
            "path": path,
            "object": scene_object(
                path, "Line", buffer_geometry(points), material("", color, kind="LineBasicMaterial")
            ),
        }
    )


def _bounds(*arrays: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """(min xy, max xy) [m] of every given point array (..., >= 2)."""
    xy = np.concatenate([a.reshape(-1, a.shape[-1])[:, :2] for a in arrays if a is not None])
    return xy.min(axis=0), xy.max(axis=0)


def add_static_scene(
    rec: RecorderWindow,
    root: str,
    *,
    base: np.ndarray,
    feet: np.ndarray,
    waypoints: np.ndarray | None,
    footholds: np.ndarray,
) -> list[str]:
    """Record ground, desired path, waypoints, footholds, CoG trace, support-edge objects.

    Args:
        base: position_base_in_world, (N, 3). feet: position_foot_in_world, (N, 4, 3).
        waypoints: (M, 3) or None. footholds: (F, 3).

    Returns:
        scene paths of the support-polygon edge nodes (to animate).
    """
    lo, hi = _bounds(base, feet, waypoints, footholds)
    x_lo, y_lo = np.floor((lo - FRAME_MARGIN) / GRID_CELL) * GRID_CELL
    x_hi, y_hi = np.ceil((hi + FRAME_MARGIN) / GRID_CELL) * GRID_CELL
    ground = f"{root}/ground_patch"
    rec.record(
        {
            "type": "set_object",
            "path": ground,
            "object": scene_object(
                ground,
                "Mesh",
                {
                    "type": "BoxGeometry",
                    "width": float(x_hi - x_lo),
                    "height": float(y_hi - y_lo),
                    "depth": 0.01,
                },
                material("", COLOR_GROUND),
            ),
        }
    )
    rec.record(
        {
            "type": "set_transform",
            "path": ground,
            "matrix": matrix_to_js(
                np.array(
                    [
                        [1, 0, 0, (x_lo + x_hi) / 2],
                        [0, 1, 0, (y_lo + y_hi) / 2],
                        [0, 0, 1, -0.0051],
                        [0, 0, 0, 1],
                    ]
                )
            ),
        }
    )
    # meshcat's default 20 m grid and axes give way to a grid on the patch (0.5 m cells).
    rec.record({"type": "set_property", "path": "/Grid", "property": "visible", "value": False})
    rec.record({"type": "set_property", "path": "/Axes", "property": "visible", "value": False})
    xs = np.arange(x_lo, x_hi + GRID_CELL / 2, GRID_CELL)
    ys = np.arange(y_lo, y_hi + GRID_CELL / 2, GRID_CELL)
    segments = [[[x, y_lo, 0.0], [x, y_hi, 0.0]] for x in xs] + [
        [[x_lo, y, 0.0], [x_hi, y, 0.0]] for y in ys
    ]
    grid = f"{root}/grid"
    rec.record(
        {
            "type": "set_object",
            "path": grid,
            "object": scene_object(
                grid,
                "LineSegments",
                buffer_geometry(np.array(segments)),
                material("", COLOR_GRID, kind="LineBasicMaterial"),
            ),
        }
    )

    if waypoints is not None and len(waypoints):
        path_pts = np.vstack([[base[0, 0], base[0, 1], 0.0], waypoints])
        path_pts[:, 2] = Z_LINES
        _line(rec, f"{root}/desired_path", path_pts, COLOR_PATH)
        for i, w in enumerate(waypoints):
            p = f"{root}/waypoints/{i:03d}"
            rec.record(
                {
                    "type": "set_object",
                    "path": p,
                    "object": scene_object(
                        p,
                        "Mesh",
                        {
                            "type": "SphereGeometry",
                            "radius": 0.04,
                            "widthSegments": 16,
                            "heightSegments": 12,
                        },
                        material("", COLOR_PATH),
                    ),
                }
            )
            rec.record(
                {
                    "type": "set_transform",
                    "path": p,
                    "matrix": matrix_to_js(
                        np.array([[1, 0, 0, w[0]], [0, 1, 0, w[1]], [0, 0, 1, w[2]], [0, 0, 0, 1]])
                    ),
                }
            )

    if len(footholds):
        p = f"{root}/footholds"
        pts = footholds.copy()
        pts[:, 2] = np.maximum(pts[:, 2], Z_MARKERS)
        rec.record(
            {
                "type": "set_object",
                "path": p,
                "object": scene_object(
                    p,
                    "Points",
                    buffer_geometry(pts),
                    material("", COLOR_FOOTHOLD, kind="PointsMaterial", size=0.03),
                ),
            }
        )

    step = max(1, int(np.ceil(len(base) / MAX_TRACE_POINTS)))
    trace = base[::step].copy()
    if (len(base) - 1) % step:
        trace = np.vstack([trace, base[-1]])
    trace[:, 2] = Z_LINES
    _line(rec, f"{root}/cog_trace", trace, COLOR_COG)

    edges = []
    for m in range(MAX_SUPPORT_EDGES):
        p = f"{root}/support_polygon/edge{m}"
        rec.record(
            {
                "type": "set_object",
                "path": f"{p}/box",
                "object": scene_object(
                    f"{p}/box",
                    "Mesh",
                    {"type": "BoxGeometry", "width": 1.0, "height": 0.012, "depth": 0.004},
                    material("", COLOR_SUPPORT),
                ),
            }
        )
        edges.append(p)
    return edges


#: Follow camera: offset from the CoG's ground projection, in robot sizes (world frame:
#: behind-right and above, looking at the robot) [robot span / m].
FOLLOW_OFFSET_IN_SPANS = (-1.1, -1.7, 1.3)
#: The camera's far plane is at least this [m] (meshcat's default) and covers the overview.
MIN_FAR_M = 100.0


def camera_views(base: np.ndarray, feet: np.ndarray, waypoints: np.ndarray | None) -> dict:
    """The page's two camera views (animation_player.py), world-frame numbers [m].

    Returns:
        ``follow_offset`` (3,) from the CoG's ground projection, scaled by the robot's span
        (widest distance between two feet at the start, at least 0.5 m);
        ``overview_centre`` (2,) and ``overview_offset`` (3,) of the whole-path view
        (:func:`camera_commands`); ``far`` [m] of the perspective camera.
    """
    lo, hi = _bounds(base, feet, waypoints)
    centre = 0.5 * (lo + hi)
    extent = float(max(np.max(hi - lo) + 2 * FRAME_MARGIN, 1.5))
    overview = extent * np.array([-0.2, -0.45, 0.7])
    start = feet[0, :, :2]
    span = float(max(np.max(np.linalg.norm(start[:, None] - start[None], axis=-1)), 0.5))
    follow = span * np.array(FOLLOW_OFFSET_IN_SPANS)
    return {
        "follow_offset": [round(float(v), 6) for v in follow],
        "overview_centre": [round(float(v), 6) for v in centre],
        "overview_offset": [round(float(v), 6) for v in overview],
        "far": float(max(MIN_FAR_M, 4.0 * extent)),
    }


def camera_commands(base: np.ndarray, feet: np.ndarray, waypoints: np.ndarray | None) -> list[dict]:
    """Point meshcat's orbit camera at the plan's centre from the rear-right, above.

    meshcat's camera lives in a Y-up frame under /Cameras/default/rotated (Rx(+90 deg)):
    a world offset (x, y, z) is (x, z, -y) there (meshcat viewer Readme, "Camera Control").
    """
    lo, hi = _bounds(base, feet, waypoints)
    centre = 0.5 * (lo + hi)
    extent = float(max(np.max(hi - lo) + 2 * FRAME_MARGIN, 1.5))
    offset = extent * np.array([-0.2, -0.45, 0.7])  # [m] world frame
    return [
        {
            "type": "set_transform",
            "path": "/Cameras/default",
            "matrix": matrix_to_js(
                np.array([[1, 0, 0, centre[0]], [0, 1, 0, centre[1]], [0, 0, 1, 0.0], [0, 0, 0, 1]])
            ),
        },
        {
            "type": "set_property",
            "path": "/Cameras/default/rotated/<object>",
            "property": "position",
            "value": [float(offset[0]), float(offset[2]), float(-offset[1])],
        },
    ]
