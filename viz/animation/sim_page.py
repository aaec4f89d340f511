"""sim.html: the simulated robot walking, with the planned robot as a translucent ghost.

    write_sim_animation_html("out/straight/sim.html", robot, trajectory, result.arrays())

Reuses the plan animation (viz.animation.page.build_scene: ground, path, footholds, the planned
robot and its tracks) and adds a second robot tree (viz.animation.scene.add_robot_tree)
driven by the simulated base pose (position and full orientation: roll and pitch too) and
joint angles. The planned robot is made translucent; the simulated robot's red foot markers
show where MuJoCo measured ground contact (not where the plan expects it).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import umsgpack

from planner.outputs.files import write_text_atomically
from planner.trajectory.samples import Trajectory
from silo4kin.robot import Robot
from viz.animation.page import ROOT, build_scene
from viz.animation.playback import playback_frame_indices
from viz.animation.player import STYLE, overlay_html, player_script
from viz.animation.recorder import INTERPOLATE_DISCRETE, RecorderWindow, find_node, track, walk
from viz.animation.scene import add_robot_tree

#: Opacity of the planned robot (the ghost).
GHOST_OPACITY = 0.3
#: A foot marker of the simulated robot shows above this normal force [N].
CONTACT_FORCE_N = 1.0


def _make_translucent(rec: RecorderWindow, path: str, opacity: float) -> None:
    """Set every material under ``path`` to ``opacity`` (in the recorded scene tree)."""
    node = find_node(rec.tree, [p for p in path.split("/") if p])
    for child in walk(node):
        if child.object is None:
            continue
        command = umsgpack.unpackb(child.object)
        for mat in command.get("object", {}).get("materials", []):
            mat["opacity"] = opacity
            mat["transparent"] = True
        child.object = umsgpack.packb(command)


def _sim_clips(
    tree,
    robot: Robot,
    arrays: dict[str, np.ndarray],  # noqa: ANN001
) -> list[dict]:
    """Animation clips of the simulated robot (plan time >= 0, decimated for playback)."""
    keep = arrays["t"] >= 0
    t = arrays["t"][keep]
    idx = playback_frame_indices(t)
    times = t[idx]
    position = arrays["position_base_in_world"][keep][idx]
    quat_wxyz = arrays["quat_base_in_world"][keep][idx]
    clips = {
        tree.ground_path: [
            track(".position", "vector", times, position),
            track(".quaternion", "quaternion", times, quat_wxyz[:, [1, 2, 3, 0]]),
        ],
        tree.base_path: [track(".position[z]", "number", times, np.zeros(len(idx)))],
    }
    col = {str(name): i for i, name in enumerate(arrays["joint_names"])}
    q = arrays["q"][keep][idx]
    for joint_name, path in tree.joint_rotation_paths.items():
        clips[path] = [track(".rotation[z]", "number", times, q[:, col[joint_name]])]
    touching = arrays["foot_force"][keep] >= CONTACT_FORCE_N
    for leg, path in enumerate(tree.stance_marker_paths):
        change = np.flatnonzero(touching[1:, leg] != touching[:-1, leg]) + 1
        keys = np.concatenate([[0], change, [len(t) - 1]])
        clips[path] = [
            track(".visible", "bool", t[keys], touching[keys, leg], INTERPOLATE_DISCRETE)
        ]
    return [
        {
            "path": path,
            "clip": {"fps": 1, "name": "default", "duration": float(t[-1]), "tracks": tracks},
        }
        for path, tracks in clips.items()
    ]


def write_sim_animation_html(
    path: str | Path,
    robot: Robot,
    trajectory: Trajectory,
    arrays: dict[str, np.ndarray],
    *,
    title: str = "physics replay",
) -> Path:
    """Write sim.html (self-contained, offline, like animation.html).

    Args:
        path: output file (written atomically).
        robot: the simulated robot.
        trajectory: the plan (the ghost).
        arrays: silo4sim.run.SimResult.arrays() (the sim.npz content).
        title: page title.
    """
    rec, meta = build_scene(robot, trajectory)
    _make_translucent(rec, f"{ROOT}/robot", GHOST_OPACITY)
    tree = add_robot_tree(rec, robot, f"{ROOT}/simulated")
    animation = umsgpack.unpackb(rec.animations[-1])
    animation["animations"].extend(_sim_clips(tree, robot, arrays))
    rec.animations[-1] = umsgpack.packb(animation)
    page = rec.get_scene(
        title=title,
        head=STYLE,
        body=overlay_html(
            title,
            "The translucent robot is the plan (the ghost); the solid one is the MuJoCo replay.",
        ),
        script=player_script(meta),
    )
    return write_text_atomically(Path(path), page, make_parents=False)
