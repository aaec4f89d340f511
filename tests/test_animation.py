"""animation.html: self-contained, small, deterministic, faithful to the trajectory.

``synthetic_trajectory`` (also used by test_plots.py and test_browser.py) builds a plan-shaped
Trajectory without the planner: the base runs along a circle or a line at a fixed height,
joints follow a periodic pattern, one leg per time unit is in transfer, and the feet come
from the closed-form forward kinematics (eq 3.5), so they are consistent with q.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import umsgpack
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.trajectory.samples import LEGS, Trajectory
from silo4kin import Robot, Silo4Error
from silo4kin.kinematics import forward_kinematics
from viz.animation.markers import COLOR_GRID, FOLLOW_OFFSET_IN_SPANS, camera_views
from viz.animation.page import ROOT, build_scene, write_animation_html
from viz.animation.plan_points import touchdown_footholds
from viz.animation.playback import DEFAULT_FPS, playback_frame_indices
from viz.animation.player import LEGEND
from viz.animation.recorder import RecorderWindow
from viz.animation.scene import COLOR_GROUND

#: Issue 5: the largest thesis case (~420 time units, 100 samples per unit) stays below this.
MAX_HTML_BYTES = 4_000_000
#: Foot position rebuilt from the scene vs the trajectory [m]: the scene stores float32
#: (~1e-7 relative: ~0.2 µm at 2 m) and chains 4 transforms; 1e-5 m is far above that
#: and far below a wrong axis or joint (centimetres).
SCENE_FK_TOLERANCE = 1e-5
#: Only inert strings may spell a URL inside the page: an XML namespace, and the default
#: address of meshcat's ``Viewer.connect()``, which the page never calls.
ALLOWED_URLS = {"http://www.w3.org/1999/xhtml", "ws://${location.host}"}


def synthetic_trajectory(
    robot: Robot,
    n_units: float = 12.0,
    samples_per_unit: int = 100,
    unit_time_s: float = 1.0,
    path: str = "circle",
    radius: float = 1.0,
) -> Trajectory:
    """A plan-shaped trajectory of ``n_units`` time units (see the module docstring)."""
    n = int(round(n_units * samples_per_unit)) + 1
    tu = np.linspace(0.0, n_units, n)
    order = [3, 1, 2, 0]  # creeping order 4-2-3-1 (RH, RF, LH, LF)
    unit = np.floor(tu).astype(int) % 4
    frac = tu - np.floor(tu)
    contact = np.ones((n, 4), dtype=bool)
    swing = np.zeros((n, 4))
    for k, leg in enumerate(order):
        in_transfer = (unit == k) & (tu < n_units)
        contact[in_transfer, leg] = False
        swing[in_transfer, leg] = np.sin(np.pi * frac[in_transfer])
    phase = np.array([f"transfer {LEGS[order[u]]}" for u in unit])
    q = np.zeros((n, 12))
    for i, leg in enumerate(robot.legs):
        theta = np.column_stack(
            [0.25 * np.sin(2 * np.pi * tu / 4 + i), 0.2 + 0.35 * swing[:, i], np.full(n, -1.9)]
        )
        q[:, 3 * i : 3 * i + 3] = leg.dh_to_joint(theta)
    s = tu / n_units
    height = 0.34  # [m] about where the feet of this pattern touch the ground
    if path == "circle":
        yaw = 2 * np.pi * s
        base = np.column_stack(
            [radius * np.sin(yaw), radius * (1 - np.cos(yaw)), np.full(n, height)]
        )
    else:
        yaw = np.zeros(n)
        base = np.column_stack([2.0 * s, np.zeros(n), np.full(n, height)])
    feet = np.zeros((n, 4, 3))
    c, sn = np.cos(yaw), np.sin(yaw)
    for i, leg in enumerate(robot.legs):
        p = forward_kinematics(leg, q[:, 3 * i : 3 * i + 3])  # position_foot_in_base
        feet[:, i] = base + np.column_stack(
            [c * p[:, 0] - sn * p[:, 1], sn * p[:, 0] + c * p[:, 1], p[:, 2]]
        )
    dt = unit_time_s / samples_per_unit
    qd = np.gradient(q, dt, axis=0)
    qdd = np.gradient(qd, dt, axis=0)
    return Trajectory(
        t=tu * unit_time_s,
        unit_time_s=unit_time_s,
        position_base_in_world=base,
        yaw_base_in_world=yaw,
        joint_names=tuple(robot.joint_names),
        q=q,
        qd=qd,
        qdd=qdd,
        position_foot_in_world=feet,
        contact=contact,
        margin=0.05 + 0.03 * np.cos(2 * np.pi * tu),
        phase=phase,
    )


@pytest.fixture(scope="module")
def small(silo4: Robot) -> Trajectory:
    return synthetic_trajectory(silo4, n_units=8.0)


def test_page_is_self_contained(silo4: Robot, small: Trajectory, tmp_path: Path) -> None:
    """The page names no URL except inert XML namespaces, and loads nothing by src/href."""
    page = write_animation_html(
        tmp_path / "a.html", silo4, small, waypoints_in_world=[[1, 1], [0, 2]]
    ).read_text()
    assert set(re.findall(r"(?:https?|wss?|ftp)://[^\s\"'`<>)\\]*", page)) <= ALLOWED_URLS
    assert not re.search(r"""(?:src|href)\s*=\s*["']?(?!data:|#)[a-z]+:""", page, re.I)
    assert "fetch(" not in page.split("var viewer = new MeshCat.Viewer")[1]
    assert "default-src 'none'" in page  # CSP: the browser itself refuses any fetch


def test_largest_thesis_case_under_4_mb(silo4: Robot, tmp_path: Path) -> None:
    """420 time units at 100 samples per unit (42k samples) -> HTML < 4 MB."""
    big = synthetic_trajectory(silo4, n_units=420.0)
    assert len(big) == 42001
    out = write_animation_html(tmp_path / "big.html", silo4, big)
    assert out.stat().st_size < MAX_HTML_BYTES


def test_same_input_same_bytes(silo4: Robot, small: Trajectory, tmp_path: Path) -> None:
    """Two writes of the same plan give identical files (no UUIDs, clocks or dict order)."""
    a = write_animation_html(tmp_path / "a.html", silo4, small).read_bytes()
    b = write_animation_html(tmp_path / "b.html", silo4, small).read_bytes()
    assert a == b


@settings(max_examples=40, deadline=None, derandomize=True)
@given(
    n=st.integers(2, 5000),
    duration=st.floats(0.01, 500.0),
    fps=st.floats(1.0, 60.0),
    max_frames=st.integers(2, 3000),
)
def test_frame_indices(n: int, duration: float, fps: float, max_frames: int) -> None:
    """Kept frames start and end with the plan, increase, respect both caps, and are the
    samples nearest a uniform time grid (gaps at most one grid step plus one sample)."""
    t = np.linspace(0.0, duration, n)
    idx = playback_frame_indices(t, fps, max_frames)
    assert idx[0] == 0 and idx[-1] == n - 1
    assert np.all(np.diff(idx) > 0)
    assert len(idx) <= min(n, max_frames)
    assert len(idx) <= np.ceil(duration * fps) + 1 or len(idx) == 2
    k = max(2, int(min(n, max_frames, np.ceil(duration * fps) + 1)))
    step = duration / (k - 1)
    assert np.max(np.diff(t[idx])) <= step + 2 * duration / (n - 1) + 1e-9


def test_playback_is_real_time(silo4: Robot, small: Trajectory) -> None:
    """Keys run in seconds of trajectory.t, or of time units x unit_time_s when given."""
    _, meta = build_scene(silo4, small)
    assert meta["duration_s"] == pytest.approx(8.0)
    assert meta["frames"] == int(np.ceil(8.0 * DEFAULT_FPS)) + 1
    _, meta = build_scene(silo4, small, unit_time_s=2.5, max_frames=50)
    assert meta["duration_s"] == pytest.approx(20.0)
    assert meta["frames"] == 50


def _decode(rec: RecorderWindow) -> tuple[dict[str, np.ndarray], dict[str, list[dict]]]:
    """Static transforms (4x4) by path and animation tracks by path, from the recording."""
    statics: dict[str, np.ndarray] = {}
    clips: dict[str, list[dict]] = {}
    for blob in rec.commands():
        cmd = umsgpack.unpackb(blob)
        if cmd["type"] == "set_transform":
            statics[cmd["path"]] = np.array(cmd["matrix"]).reshape(4, 4).T
        elif cmd["type"] == "set_animation":
            for anim in cmd["animations"]:
                clips[anim["path"]] = anim["clip"]["tracks"]
    return statics, clips


def _values(tr: dict) -> np.ndarray:
    v = tr["values"]
    return np.array(v) if isinstance(v, list) else np.frombuffer(v.data, dtype="<f4")


def _rz(angle: float) -> np.ndarray:
    out = np.eye(4)
    out[:2, :2] = [[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]]
    return out


def scene_foot_in_world(
    statics: dict[str, np.ndarray], clips: dict[str, list[dict]], leg: str, k: int
) -> np.ndarray:
    """A foot's position in the world at animation key k, by chaining the scene's static
    transforms and animated values from the root down to the leg's stance marker, (3,) [m]."""
    path = next(p for p in statics if p.endswith(f"/stance_{leg}"))
    parts = path.split("/")
    world = np.eye(4)
    for depth in range(1, len(parts) + 1):
        node = "/".join(parts[:depth])
        for tr in clips.get(node, []):
            v = _values(tr)
            if tr["name"] == ".position":
                world = world @ np.vstack(
                    [np.column_stack([np.eye(3), v.reshape(-1, 3)[k]]), [0, 0, 0, 1]]
                )
            elif tr["name"] == ".position[z]":
                world[:3, 3] += world[:3, :3] @ [0, 0, v[k]]
        for tr in clips.get(node, []):
            if tr["name"] == ".rotation[z]":
                world = world @ _rz(_values(tr)[k])
        world = world @ statics.get(node, np.eye(4))
    return world[:3, 3]


def test_scene_tree_reproduces_the_feet(silo4: Robot, small: Trajectory) -> None:
    """Chaining the scene's static joint placements with the animated joint angles and base
    pose at a key frame puts each foot where trajectory.position_foot_in_world says."""
    rec, meta = build_scene(silo4, small)
    statics, clips = _decode(rec)
    idx = playback_frame_indices(small.t - small.t[0], DEFAULT_FPS)
    for k in (0, len(idx) // 3, len(idx) - 1):
        for leg_index, leg in enumerate(LEGS):
            expected = small.position_foot_in_world[idx[k], leg_index]
            foot = scene_foot_in_world(statics, clips, leg, k)
            assert np.max(np.abs(foot - expected)) < SCENE_FK_TOLERANCE


def test_stance_markers_follow_contact(silo4: Robot, small: Trajectory) -> None:
    """Each stance highlight is visible exactly while its foot is in contact."""
    rec, _ = build_scene(silo4, small)
    _, clips = _decode(rec)
    t = small.t - small.t[0]
    for leg_index, leg in enumerate(LEGS):
        (tr,) = clips[next(p for p in clips if p.endswith(f"/stance_{leg}"))]
        times = np.frombuffer(tr["times"].data, dtype="<f4")
        visible = np.array(tr["values"])
        held = visible[np.searchsorted(times, t.astype(np.float32), side="right") - 1]
        assert np.array_equal(held, small.contact[:, leg_index])


def test_swing_markers_are_the_complement(silo4: Robot, small: Trajectory) -> None:
    """Each swing highlight is visible exactly while its foot is in the air."""
    rec, _ = build_scene(silo4, small)
    _, clips = _decode(rec)
    t = small.t - small.t[0]
    for leg_index, leg in enumerate(LEGS):
        (tr,) = clips[next(p for p in clips if p.endswith(f"/swing_{leg}"))]
        times = np.frombuffer(tr["times"].data, dtype="<f4")
        held = np.array(tr["values"])[
            np.searchsorted(times, t.astype(np.float32), side="right") - 1
        ]
        assert np.array_equal(held, ~small.contact[:, leg_index])


def test_legend_names_every_marker_colour(silo4: Robot, small: Trajectory) -> None:
    """Every colour of a non-robot object in the scene (paths, markers, polygon, feet
    highlights) has a legend entry; only the ground and its grid go without one."""
    rec, _ = build_scene(silo4, small, waypoints_in_world=[[1.0, 1.0]])
    colours = set()
    for blob in rec.commands():
        cmd = umsgpack.unpackb(blob)
        if (
            cmd["type"] == "set_object"
            and "/urdf_root/" not in cmd["path"]
            or (cmd["type"] == "set_object" and "/marker" in cmd["path"])
        ):
            colours |= {m["color"] for m in cmd["object"]["materials"]}
    legend = {colour for _, colour, _ in LEGEND}
    assert colours - legend == {COLOR_GROUND, COLOR_GRID}
    assert legend <= colours  # and the legend names nothing that is not drawn


def test_camera_views_follow_and_overview(small: Trajectory) -> None:
    """The follow offset scales with the robot's span (feet at the start) and the overview
    and the far plane scale with the path."""
    feet = small.position_foot_in_world
    views = camera_views(small.position_base_in_world, feet, None)
    start = feet[0, :, :2]
    span = np.max(np.linalg.norm(start[:, None] - start[None], axis=-1))
    np.testing.assert_allclose(
        views["follow_offset"], span * np.array(FOLLOW_OFFSET_IN_SPANS), atol=1e-6
    )
    far_away = small.position_base_in_world + [300.0, 0.0, 0.0]
    long_views = camera_views(np.vstack([small.position_base_in_world, far_away]), feet, None)
    assert long_views["far"] > 4 * 300 > views["far"] - 1
    assert (
        np.linalg.norm(long_views["overview_offset"])
        > 100 * np.linalg.norm(views["follow_offset"]) / 10
    )


def test_any_plan_length_fits_the_budget(silo4: Robot, tmp_path: Path) -> None:
    """A plan far longer than any thesis case (3000 time units, ~100 m) is thinned to fit
    MAX_HTML_BYTES, and the page says so; a budget that cannot hold even MIN_THINNED_FPS
    keys per second is refused with one clear error and no file."""
    huge = synthetic_trajectory(silo4, n_units=3000.0, samples_per_unit=10)
    out = write_animation_html(tmp_path / "huge.html", silo4, huge)
    page = out.read_text()
    assert out.stat().st_size <= MAX_HTML_BYTES
    assert "Keyframes thinned to" in page
    small_page = write_animation_html(
        tmp_path / "small.html", silo4, synthetic_trajectory(silo4, n_units=8.0)
    ).read_text()
    assert "Keyframes thinned" not in small_page
    tighter = write_animation_html(tmp_path / "tighter.html", silo4, huge, max_bytes=3_000_000)
    assert tighter.stat().st_size <= 3_000_000 < out.stat().st_size
    assert "under 3 MB" in tighter.read_text()
    with pytest.raises(Silo4Error, match="cannot fit"):
        write_animation_html(tmp_path / "tiny.html", silo4, huge, max_bytes=1_500_000)
    assert not (tmp_path / "tiny.html").exists()


def test_default_footholds_are_touchdowns(small: Trajectory) -> None:
    """Default footholds: the initial stance feet plus one per touch-down."""
    touchdowns = int(np.sum(small.contact[1:] & ~small.contact[:-1]))
    assert touchdowns > 0
    assert touchdown_footholds(small).shape == (small.contact[0].sum() + touchdowns, 3)


def test_unwritable_paths_raise(silo4: Robot, small: Trajectory, tmp_path: Path) -> None:
    """A missing folder, a file as folder, or a folder as target: Silo4Error, no leftovers."""
    (tmp_path / "file").write_text("x")
    for bad in (tmp_path / "missing" / "a.html", tmp_path / "file" / "a.html", tmp_path):
        with pytest.raises(Silo4Error, match="cannot write"):
            write_animation_html(bad, silo4, small)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


def test_bad_inputs_raise(silo4: Robot, small: Trajectory, tmp_path: Path) -> None:
    """Another robot's trajectory, NaN, bad options: Silo4Error; one sample (a plan with
    nothing to do): a still page."""
    from dataclasses import replace

    out = tmp_path / "a.html"
    other = replace(small, joint_names=tuple(n.replace("knee", "elbow") for n in small.joint_names))
    with pytest.raises(Silo4Error, match="does not belong to robot"):
        write_animation_html(out, silo4, other)
    q = small.q.copy()
    q[3, 2] = np.nan
    with pytest.raises(Silo4Error, match="NaN"):
        write_animation_html(out, silo4, replace(small, q=q))
    one = replace(
        small,
        **{
            name: getattr(small, name)[:1]
            for name in (
                "t",
                "position_base_in_world",
                "yaw_base_in_world",
                "q",
                "qd",
                "qdd",
                "position_foot_in_world",
                "contact",
                "margin",
                "phase",
            )
        },
    )
    # a plan of one sample (nothing to do) is a still page, not an error
    still = Path(write_animation_html(out.with_name("still.html"), silo4, one))
    assert still.is_file() and still.stat().st_size > 0
    for kwargs in (
        {"unit_time_s": -1.0},
        {"max_frames": 1},
        {"fps": 0.0},
        {"waypoints_in_world": [1.0, 2.0]},
    ):
        with pytest.raises(Silo4Error):
            write_animation_html(out, silo4, small, **kwargs)
    assert not out.exists()


def test_recorder_is_a_meshcat_window() -> None:
    """meshcat.Visualizer records into RecorderWindow without a server."""
    import meshcat
    import meshcat.geometry as g

    rec = RecorderWindow()
    vis = meshcat.Visualizer(window=rec)
    vis[f"{ROOT}/box"].set_object(g.Box([0.1, 0.2, 0.3]))
    vis[f"{ROOT}/box"].set_transform(np.eye(4))
    assert [umsgpack.unpackb(b)["type"] for b in rec.commands()] == ["set_object", "set_transform"]
    assert "MeshCat.Viewer" in vis.static_html()
