"""The plan as one self-contained Meshcat HTML animation (``animation.html``).

    write_animation_html("out/animation.html", robot, trajectory,
                         waypoints_in_world=waypoints, footholds_in_world=footholds)

The page inlines the Meshcat viewer and the scene (meshcat_recorder.py): no server, no
network request; it opens offline from disk. It plays the plan at real-time speed in
seconds of ``trajectory.t`` (or of ``time_units * unit_time_s`` when ``unit_time_s`` is
given), loops, and ``animation.html?t=12.5`` pauses at t = 12.5 s (shareable links,
pixel-stable screenshots: stack-notes.md).

Size (the largest thesis case, ~420 time units, stays < 4 MB): the scene mirrors
the kinematic tree of ``robot.model``, so one float per joint per frame (``.rotation[z]`` of
a node whose z axis is aligned with the joint axis) plus the base pose animates every
geometry; frames are decimated to ``fps`` per second of playback, at most ``max_frames``
(viz/animation/playback.py).
Contact flags and the support polygon change only at touch-down / lift-off, so they are
discrete tracks keyed at those instants, at full time resolution.

Scene (world frame W, z up, ground z = 0): the robot, ground, desired path (start ->
waypoints), waypoints, footholds, the CoG trace and a marker under the CoG (its ground
projection), the support polygon of the stance feet, stance feet red and swing feet cyan.
The controls over it (camera following the robot, legend, play/pause, speed, time slider):
viz/animation/player.py.

Size budget: the page stays under MAX_HTML_BYTES for any plan length. Past the
budget the keyframes are thinned (fewer keys per second, measured from two builds) and the
page says so in its legend box; contact events are never thinned.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from planner.outputs.files import write_text_atomically
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.samples import Trajectory
from silo4kin.errors import Silo4Error
from silo4kin.robot import Robot
from viz.animation.markers import (
    add_static_scene,
    camera_commands,
    camera_views,
    support_polygon_keys,
)
from viz.animation.mesh_budget import RobotMeshes, fit_meshes, warn_once
from viz.animation.plan_points import points_in_world, touchdown_footholds
from viz.animation.playback import (
    DEFAULT_FPS,
    DEFAULT_MAX_FRAMES,
    playback_frame_indices,
    playback_times,
)
from viz.animation.player import STYLE, overlay_html, player_script
from viz.animation.recorder import INTERPOLATE_DISCRETE, RecorderWindow, track
from viz.animation.scene import add_robot_tree
from viz.animation.terrain import add_terrain_scene

#: Scene root path in Meshcat.
ROOT = "/meshcat/silo4"
#: Largest animation.html [bytes] (<= 4 MB for any plan length; 4 MB = 4e6 here).
MAX_HTML_BYTES = 4_000_000
#: Fewest keyframes per second of playback before the page refuses to thin further [1/s]
#: (a 1 s leg transfer still shows as lift, swing and touch-down between keys).
MIN_THINNED_FPS = 1.0


def build_scene(
    robot: Robot,
    trajectory: Trajectory,
    *,
    waypoints_in_world: np.ndarray | Sequence | None = None,
    footholds_in_world: np.ndarray | Sequence | None = None,
    unit_time_s: float | None = None,
    max_frames: int = DEFAULT_MAX_FRAMES,
    fps: float = DEFAULT_FPS,
    meshes: RobotMeshes | None = None,
    terrain: TerrainMap | None = None,
) -> tuple[RecorderWindow, dict]:
    """Record the scene and animation; return the recorder and the page's metadata.

    See :func:`write_animation_html` for the arguments; ``meshes``: how the robot's meshes
    fit the budget (default: viz.animation.mesh_budget.fit_meshes). The metadata holds
    ``duration_s``, ``frames`` (number of animation keys), ``time_unit_s`` and the phase runs.
    """
    t_s = playback_times(robot, trajectory, unit_time_s, max_frames, fps)
    waypoints = points_in_world(waypoints_in_world, "waypoints_in_world")
    footholds = points_in_world(footholds_in_world, "footholds_in_world")
    if footholds is None:
        footholds = touchdown_footholds(trajectory)

    rec = RecorderWindow()
    base = np.asarray(trajectory.position_base_in_world, dtype=float)
    feet = np.asarray(trajectory.position_foot_in_world, dtype=float)
    tree = add_robot_tree(rec, robot, f"{ROOT}/robot", meshes)
    edge_paths = add_static_scene(
        rec, ROOT, base=base, feet=feet, waypoints=waypoints, footholds=footholds
    )
    if terrain is not None:  # boxes, posts, height map, forbidden regions: viz/animation/terrain.py
        add_terrain_scene(rec, ROOT, terrain, base[:, :2])
    for cmd in camera_commands(base, feet, waypoints):
        rec.record(cmd)

    idx = playback_frame_indices(t_s, fps, max_frames)
    times = t_s[idx]
    duration = float(t_s[-1])
    yaw = np.unwrap(np.asarray(trajectory.yaw_base_in_world, dtype=float))[idx]
    ground_xy = np.column_stack([base[idx, :2], np.zeros(len(idx))])
    clips: dict[str, list[dict]] = {
        tree.ground_path: [
            track(".position", "vector", times, ground_xy),
            track(".rotation[z]", "number", times, yaw),
        ],
    }
    if np.ptp(base[:, 2]) > 0.0:
        clips[tree.base_path] = [track(".position[z]", "number", times, base[idx, 2])]
    else:  # a constant body height: one static transform instead of a key per frame
        rec.record(
            {
                "type": "set_transform",
                "path": tree.base_path,
                "matrix": [
                    1.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    1.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    1.0,
                    0.0,
                    0.0,
                    0.0,
                    float(base[0, 2]),
                    1.0,
                ],
            }
        )
    col = {name: i for i, name in enumerate(trajectory.joint_names)}
    for joint_name, path in tree.joint_rotation_paths.items():
        clips[path] = [track(".rotation[z]", "number", times, trajectory.q[idx, col[joint_name]])]

    contact = np.asarray(trajectory.contact, dtype=bool)
    for leg_index, (stance, swing) in enumerate(
        zip(tree.stance_marker_paths, tree.swing_marker_paths, strict=True)
    ):
        change = np.flatnonzero(contact[1:, leg_index] != contact[:-1, leg_index]) + 1
        keys = np.concatenate([[0], change, [len(t_s) - 1]])
        clips[stance] = [
            track(".visible", "bool", t_s[keys], contact[keys, leg_index], INTERPOLATE_DISCRETE)
        ]
        clips[swing] = [
            track(".visible", "bool", t_s[keys], ~contact[keys, leg_index], INTERPOLATE_DISCRETE)
        ]
    for edge_path, edge in zip(edge_paths, support_polygon_keys(t_s, contact, feet), strict=True):
        clips[edge_path] = [
            track(".visible", "bool", edge.times_s, edge.visible, INTERPOLATE_DISCRETE),
            track(".position", "vector", edge.times_s, edge.position, INTERPOLATE_DISCRETE),
            track(".rotation[z]", "number", edge.times_s, edge.yaw, INTERPOLATE_DISCRETE),
            track(".scale", "vector", edge.times_s, edge.scale, INTERPOLATE_DISCRETE),
        ]
    rec.record(
        {
            "type": "set_animation",
            "path": "",
            "animations": [
                {
                    "path": path,
                    "clip": {"fps": 1, "name": "default", "duration": duration, "tracks": tracks},
                }
                for path, tracks in clips.items()
            ],
            # LoopRepeat (2201), endless; meshcat's Animator reads these options.
            "options": {
                "play": True,
                "loopMode": 2201,
                "repetitions": float("inf"),
                "clampWhenFinished": False,
            },
        }
    )

    phase = np.asarray(trajectory.phase).astype(str)
    starts = np.concatenate([[0], np.flatnonzero(phase[1:] != phase[:-1]) + 1])
    span_units = float(trajectory.time_units[-1] - trajectory.time_units[0])
    # a still plan (one sample) has no time unit to show: the planned one
    time_unit_s = float(t_s[-1] / span_units) if span_units > 0 else float(trajectory.unit_time_s)
    meta = {
        "duration_s": duration,
        "frames": int(len(idx)),
        "time_unit_s": time_unit_s,
        "phase_start_s": [round(float(t_s[i]), 6) for i in starts],
        "phase": [str(phase[i]) for i in starts],
        "camera": camera_views(base, feet, waypoints),
        "ground_path": [p for p in tree.ground_path.split("/") if p],
        "robot_path": [p for p in tree.robot_path.split("/") if p],
    }
    return rec, meta


def write_animation_html(
    path: str | Path,
    robot: Robot,
    trajectory: Trajectory,
    *,
    waypoints_in_world: np.ndarray | Sequence | None = None,
    footholds_in_world: np.ndarray | Sequence | None = None,
    unit_time_s: float | None = None,
    max_frames: int = DEFAULT_MAX_FRAMES,
    fps: float = DEFAULT_FPS,
    title: str = "SILO4 plan",
    max_bytes: int = MAX_HTML_BYTES,
    terrain: TerrainMap | None = None,
) -> Path:
    """Write the plan as one self-contained, offline HTML animation.

    Args:
        path: output file (written to a temporary name in the same folder, then renamed).
        robot: the robot the trajectory was planned for (visuals from ``robot.visual_model``).
        trajectory: the plan, N >= 2 samples.
        waypoints_in_world: desired path waypoints [m], shape (M, 2) or (M, 3); the drawn
            path starts at the first CoG position. None: no path drawn.
        footholds_in_world: footholds to mark [m], shape (F, 2) or (F, 3); None: the foot
            positions at the start and at every touch-down.
        unit_time_s: seconds per thesis time unit for playback; None: ``trajectory.t``.
        max_frames: cap on animation keys (file size).
        fps: animation keys per second of playback.
        title: page title and overlay heading.
        max_bytes: size budget of the page [bytes]; past it the keyframes are thinned and
            the page says so.
        terrain: the ground drawn under the robot (planner/terrain/terrain_map.py), or None.

    Returns:
        the written path.

    Raises:
        Silo4Error: bad inputs, a trajectory of another robot, an unwritable path.
    """
    page = render_animation_page(
        robot,
        trajectory,
        waypoints_in_world=waypoints_in_world,
        footholds_in_world=footholds_in_world,
        unit_time_s=unit_time_s,
        max_frames=max_frames,
        fps=fps,
        title=title,
        max_bytes=max_bytes,
        terrain=terrain,
    )
    return write_text_atomically(Path(path), page, make_parents=False)


def render_animation_page(
    robot: Robot,
    trajectory: Trajectory,
    *,
    title: str = "SILO4 plan",
    max_frames: int = DEFAULT_MAX_FRAMES,
    fps: float = DEFAULT_FPS,
    max_bytes: int = MAX_HTML_BYTES,
    **scene: object,
) -> str:
    """The page's HTML text within ``max_bytes`` (see :func:`write_animation_html`).

    Keys cost a fixed number of bytes each, so two builds give the bytes per key and a third
    build the most keys that fit; a note on the page gives the resulting key rate. The
    meshes are fitted to their budget once (mesh_budget.fit_meshes); when they were
    simplified or replaced by a stick figure, the legend says so and so does the terminal
    (one MeshesSimplified warning).

    Raises:
        Silo4Error: even MIN_THINNED_FPS keys per second do not fit.
    """
    meshes = fit_meshes(robot)
    warn_once(meshes)

    def page(frames: int, note: str | None = None) -> tuple[str, dict]:
        rec, meta = build_scene(
            robot,
            trajectory,
            max_frames=frames,
            fps=fps,
            meshes=meshes,
            **scene,  # type: ignore[arg-type]
        )
        notes = " ".join(n for n in (meshes.note, note) if n) or None
        text = rec.get_scene(
            title=title, head=STYLE, body=overlay_html(title, notes), script=player_script(meta)
        )
        return text, meta

    text, meta = page(max_frames)
    size = len(text.encode("utf-8"))
    duration = float(meta["duration_s"])
    wanted = min(len(trajectory), math.ceil(duration * fps) + 1)
    if size <= max_bytes:
        if meta["frames"] < wanted:  # the max_frames cap thinned them: say so
            text, _ = page(
                max_frames,
                _thinned_note(meta["frames"], duration, fps, f"at most {max_frames} keys"),
            )
        return text
    frames = meta["frames"]
    half = max(2, frames // 2)
    text_half, _ = page(half)
    per_frame = (size - len(text_half.encode("utf-8"))) / max(frames - half, 1)
    fixed = size - per_frame * frames
    fit = int((max_bytes * 0.995 - fixed) / max(per_frame, 1.0))
    if fit < 2 or fit < MIN_THINNED_FPS * duration:
        raise Silo4Error(
            f"animation.html: {duration:.0f} s of plan cannot fit in {max_bytes / 1e6:.1f} MB "
            f"even at {MIN_THINNED_FPS:g} keyframes per second; plan a shorter path or "
            "leave out the animation (--no-html)"
        )
    text, _ = page(
        fit, _thinned_note(fit, duration, fps, f"this page under {max_bytes / 1e6:.0f} MB")
    )
    return text


def _thinned_note(frames: int, duration_s: float, fps: float, why: str) -> str:
    """The page's note when it shows fewer keys than ``fps`` per second."""
    return (
        f"Keyframes thinned to {frames / max(duration_s, 1e-9):.1f} per second "
        f"({frames} keys, {fps:g} wanted) to keep {why}; the trajectory files hold "
        "every sample."
    )
