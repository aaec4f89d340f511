"""A real headless Chromium opens animation.html from disk with the network off.

Checks (issue 5): the canvas is not blank; screenshots at two ``?t=`` values differ where the
robot moved (whole-path view, a still camera); two runs at the same ``?t=`` give the same
pixels; the page asks for nothing from the network (Chromium's own net log, with a control
page proving the check can fail).

Checks (issue 14): the follow camera keeps the robot large at t = 0 and after 40 m (its
pixel extent, measured as the bounding box of the pixels that change when ``?hide=robot``
removes it), while the whole-path view of the same instant shows it small (so the measure
can fail); the legend, the player bar and the hidden dat.GUI are in the live DOM
(``--dump-dom`` after the scripts ran); report.html renders its header, tables and plots.

Chromium: ``/usr/bin/chromium`` (Debian package ``chromium``; ``scripts/install_chromium.sh``),
or the path in ``SILO4_CHROMIUM``. In CI (``CI=true``) a missing browser FAILS the test;
elsewhere it skips. Flags from docs stack-notes.md; the network is cut by an unreachable
proxy and a host resolver that resolves nothing, and the page's own CSP forbids fetches.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from test_animation import synthetic_trajectory  # tests/ is on sys.path (pytest rootdir)

from planner.trajectory.samples import Trajectory
from silo4kin import Robot
from viz.animation.page import write_animation_html
from viz.animation.player import LEGEND

#: Virtual time Chromium grants the page before the screenshot [ms].
VIRTUAL_TIME_BUDGET_MS = 3000
#: Wall-clock limit per Chromium run [s] (a run takes ~1.5 s on this 2-core machine).
RUN_TIMEOUT_S = 90
WINDOW = (1024, 768)
#: Rows at the bottom holding the time/phase overlay, which differs between ?t= values
#: by construction; the scene comparison ignores them [px].
OVERLAY_ROWS = 90
#: A rendered scene has sky gradient, ground, grid and robot: grey-level std far above 0;
#: a blank canvas (one colour) has 0.
MIN_PIXEL_STD = 10.0
#: Fraction of scene pixels that must change between t = 1.5 s and t = 6.0 s: the robot
#: (~100 x 100 px) walks about 1.5 m and its legs move; 0.2% of 1024 x 678 is ~1400 px.
MIN_CHANGED_FRACTION = 0.002
#: The changed pixels lie in a box around the robot's two poses, well under this share of
#: the frame (a moving camera or a re-laid-out scene would change everything).
MAX_CHANGED_BOX_FRACTION = 0.25
#: Same ?t= twice: software rendering (SwiftShader) is deterministic; allow a few pixels of
#: anti-aliasing noise per million.
MAX_REPEAT_CHANGED_FRACTION = 1e-5
#: Same ?t= twice, the player bar: Chromium's native slider thumb may be anti-aliased a
#: fraction of a pixel apart (seen once: 11 px, channel difference 9); a label showing
#: another time or a thumb at another place differs by ~100-250 in hundreds of pixels.
MAX_BAR_ANTIALIAS_DIFF = 32
MAX_BAR_ANTIALIAS_PX = 40
#: The robot counts as "large in the frame" when its pixel box spans at least this share of
#: the window height (SILO4, ~0.9 m between feet, at the follow offset: ~35 %).
MIN_ROBOT_EXTENT_FRACTION = 0.2
#: ... and as small in the whole-path view of a 47 m walk (~2 %): the control.
MAX_OVERVIEW_ROBOT_EXTENT_FRACTION = 0.08
#: A pixel belongs to the robot when hiding the robot changes its grey level by more than
#: this (shading noise of SwiftShader is 0).
ROBOT_PIXEL_THRESHOLD = 8
NETWORK_OFF_FLAGS = ("--proxy-server=127.0.0.1:9", "--host-resolver-rules=MAP * ~NOTFOUND")


def _chromium() -> str:
    candidates = [os.environ.get("SILO4_CHROMIUM"), "/usr/bin/chromium", shutil.which("chromium")]
    for c in candidates:
        if c and Path(c).is_file() and os.access(c, os.X_OK):
            return c
    message = (
        "headless Chromium not found (looked at $SILO4_CHROMIUM, /usr/bin/chromium, "
        "PATH); install it with scripts/install_chromium.sh (apt-get install -y chromium)"
    )
    if os.environ.get("CI", "").lower() in ("true", "1", "yes"):
        pytest.fail(f"CI is set: the browser test must run. {message}")
    pytest.skip(message)


def _chromium_flags(profile: Path) -> list[str]:
    return [
        _chromium(),
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--disable-extensions",
        "--hide-scrollbars",
        "--mute-audio",
        f"--user-data-dir={profile}",
        f"--window-size={WINDOW[0]},{WINDOW[1]}",
        f"--virtual-time-budget={VIRTUAL_TIME_BUDGET_MS}",
        *NETWORK_OFF_FLAGS,
    ]


def _dump_dom(url: str, profile: Path) -> str:
    """The page's DOM after its scripts ran (Chromium --dump-dom)."""
    proc = subprocess.run(
        [*_chromium_flags(profile), "--dump-dom", url],
        capture_output=True,
        text=True,
        timeout=RUN_TIMEOUT_S,
        check=False,
    )
    shutil.rmtree(profile, ignore_errors=True)
    assert "<html" in proc.stdout, proc.stderr[-2000:]
    return proc.stdout


def _screenshot(url: str, out: Path) -> tuple[np.ndarray, float, list[str]]:
    """Render ``url``; return (RGB pixels (H, W, 3), wall time [s], page-initiated URLs)."""
    from PIL import Image

    netlog = out.with_suffix(".netlog.json")
    profile = out.with_suffix(".profile")
    cmd = [
        _chromium(),
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--disable-extensions",
        "--hide-scrollbars",
        "--mute-audio",
        f"--user-data-dir={profile}",
        f"--screenshot={out}",
        f"--window-size={WINDOW[0]},{WINDOW[1]}",
        f"--virtual-time-budget={VIRTUAL_TIME_BUDGET_MS}",
        f"--log-net-log={netlog}",
        *NETWORK_OFF_FLAGS,
        url,
    ]
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=RUN_TIMEOUT_S, check=False)
    elapsed = time.perf_counter() - start
    assert out.is_file(), (
        f"chromium wrote no screenshot (exit {proc.returncode}):\n{proc.stderr[-2000:]}"
    )
    with Image.open(out) as img:
        pixels = np.asarray(img.convert("RGB"), dtype=np.int16)
    shutil.rmtree(profile, ignore_errors=True)
    return pixels, elapsed, _page_requests(netlog)


def _page_requests(netlog: Path) -> list[str]:
    """URLs of network requests the page started (Chromium's own have no origin)."""
    text = netlog.read_text()
    try:
        log = json.loads(text)
    except json.JSONDecodeError:  # a net log cut short lacks its closing brackets
        log = json.loads(text.rstrip().rstrip(",") + "]}")
    start_job = log["constants"]["logEventTypes"]["URL_REQUEST_START_JOB"]
    return [
        e["params"]["url"]
        for e in log["events"]
        if e["type"] == start_job
        and "url" in e.get("params", {})
        and e["params"].get("initiator") != "not an origin"
    ]


@pytest.fixture(scope="module")
def page(silo4: Robot, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """animation.html of a 12-unit synthetic walk along a line (1 s per unit)."""
    _chromium()
    folder = tmp_path_factory.mktemp("browser")
    trajectory = synthetic_trajectory(silo4, n_units=12.0, path="line")
    return write_animation_html(
        folder / "animation.html", silo4, trajectory, waypoints_in_world=[[2.0, 0.0]]
    )


@pytest.fixture(scope="module")
def shots(page: Path) -> dict[str, tuple[np.ndarray, float, list[str]]]:
    """Three screenshots: t = 1.5 s twice and t = 6.0 s."""
    url = page.resolve().as_uri()
    return {
        name: _screenshot(f"{url}?view=path&t={t}", page.with_name(f"{name}.png"))
        for name, t in (("a", 1.5), ("a_again", 1.5), ("b", 6.0))
    }


def _scene(pixels: np.ndarray) -> np.ndarray:
    return pixels[:-OVERLAY_ROWS]


def test_canvas_is_not_blank(shots: dict) -> None:
    """The WebGL canvas shows a scene, not one flat colour."""
    pixels, _, _ = shots["a"]
    assert pixels.shape[:2] == (WINDOW[1], WINDOW[0])
    assert float(_scene(pixels).mean(axis=2).std()) > MIN_PIXEL_STD


def test_seek_shows_the_robot_moving(shots: dict) -> None:
    """?t=1.5 and ?t=6.0 differ in the scene, and the changes sit where the robot is
    (a compact region, not the whole frame: the camera does not move)."""
    a, b = _scene(shots["a"][0]), _scene(shots["b"][0])
    changed = np.any(a != b, axis=2)
    assert changed.mean() > MIN_CHANGED_FRACTION
    rows, cols = np.nonzero(changed)
    box = (np.ptp(rows) + 1) * (np.ptp(cols) + 1)
    assert box < MAX_CHANGED_BOX_FRACTION * changed.size  # sky, ground, grid stay put


def test_same_seek_same_pixels(shots: dict) -> None:
    """Two fresh browsers at the same ?t= render the same image: the scene pixel for pixel,
    the player bar up to the anti-aliasing of Chromium's own slider thumb."""
    a, again = shots["a"][0], shots["a_again"][0]
    diff = np.abs(a - again).max(axis=2)
    changed = diff > 0
    rows, cols = np.nonzero(changed)
    where = (
        f"rows {rows.min()}-{rows.max()} (the overlay starts at row {a.shape[0] - OVERLAY_ROWS}),"
        f" columns {cols.min()}-{cols.max()}, largest channel difference {int(diff.max())}"
        if rows.size
        else ""
    )
    # The scene (WebGL, SwiftShader) is deterministic.
    assert _scene(changed).mean() <= MAX_REPEAT_CHANGED_FRACTION, (
        f"{changed.sum()} px differ: {where}"
    )
    # The bar: the one difference ever seen (CI under load, 1 run in ~30) was 11 px of the
    # native range thumb, rows 738-746 x columns 156-168, channel difference <= 9: its
    # edges drawn a fraction of a pixel apart. A different time on the label or a thumb
    # at another place differs by far more than that, in far more pixels.
    assert _bar_matches(a, again), f"{changed.sum()} px differ: {where}"


def _bar_matches(a: np.ndarray, b: np.ndarray) -> bool:
    """The player bars of two screenshots agree up to the slider thumb's anti-aliasing."""
    bar = np.abs(a - b).max(axis=2)[-OVERLAY_ROWS:]
    return int(bar.max()) <= MAX_BAR_ANTIALIAS_DIFF and int((bar > 0).sum()) <= MAX_BAR_ANTIALIAS_PX


def test_bar_check_sees_another_time(shots: dict, page: Path) -> None:
    """Control: ?t= 0.01 s later (the slider's step) fails the bar comparison above."""
    url = page.resolve().as_uri()
    later, _, _ = _screenshot(f"{url}?view=path&t=1.51", page.with_name("a_later.png"))
    assert not _bar_matches(shots["a"][0], later)


def test_page_makes_no_network_request(shots: dict) -> None:
    """Chromium's net log records no request started by the page."""
    for _, _, requests in shots.values():
        assert requests == []


def test_network_check_can_fail(tmp_path: Path) -> None:
    """Control: a page that loads an image and fetches a URL is caught by the net-log check
    (so an empty list above means something)."""
    _chromium()
    control = tmp_path / "control.html"
    control.write_text(
        '<!DOCTYPE html><html><body><img src="http://192.0.2.1/x.png">'
        '<script>fetch("https://example.invalid/a").catch(() => 0);</script>'
        "</body></html>"
    )
    _, _, requests = _screenshot(control.resolve().as_uri(), tmp_path / "control.png")
    assert "http://192.0.2.1/x.png" in requests


def test_page_load_time_is_reported(shots: dict, record_property) -> None:  # noqa: ANN001
    """Record the Chromium wall time per screenshot (load + render, 3 s virtual budget)."""
    for name, (_, elapsed, _) in shots.items():
        record_property(f"screenshot_{name}_s", round(float(elapsed), 2))
        assert elapsed < RUN_TIMEOUT_S


def long_walk(robot: Robot) -> Trajectory:
    """A 50 s walk along world x that ends 47 m from the start (legs from the synthetic
    pattern, body and feet shifted along x: the camera only needs the robot to travel)."""
    walk = synthetic_trajectory(robot, n_units=50.0, samples_per_unit=20, path="line")
    shift = 45.0 * walk.t / walk.t[-1]  # [m]
    base = walk.position_base_in_world.copy()
    feet = walk.position_foot_in_world.copy()
    base[:, 0] += shift
    feet[:, :, 0] += shift[:, None]
    return replace(walk, position_base_in_world=base, position_foot_in_world=feet)


def _robot_extent(page: Path, query: str, tmp: Path) -> float:
    """Height-or-width of the robot's pixel box, as a share of the window height."""
    url = page.resolve().as_uri()
    shown, _, _ = _screenshot(f"{url}?{query}", tmp / "shown.png")
    hidden, _, _ = _screenshot(f"{url}?{query}&hide=robot", tmp / "hidden.png")
    changed = np.abs(shown - hidden).max(axis=2)[:-OVERLAY_ROWS] > ROBOT_PIXEL_THRESHOLD
    if not changed.any():
        return 0.0
    rows, cols = np.nonzero(changed)
    return max(np.ptp(rows) + 1, np.ptp(cols) + 1) / WINDOW[1]


@pytest.fixture(scope="module")
def long_page(silo4: Robot, tmp_path_factory: pytest.TempPathFactory) -> Path:
    _chromium()
    walk = long_walk(silo4)
    assert walk.position_base_in_world[-1, 0] - walk.position_base_in_world[0, 0] > 40.0
    return write_animation_html(
        tmp_path_factory.mktemp("long") / "animation.html",
        silo4,
        walk,
        waypoints_in_world=[[47.0, 0.0]],
    )


@pytest.mark.parametrize("t_s", [0.0, 45.0])  # at the start, and 42 m down the path
def test_follow_camera_keeps_the_robot_large(
    long_page: Path, tmp_path: Path, t_s: float, record_property
) -> None:  # noqa: ANN001
    """Default view: the robot spans >= MIN_ROBOT_EXTENT_FRACTION of the window height
    at t = 0 and after 40 m; the whole-path view of the same instant shows it small."""
    follow = _robot_extent(long_page, f"t={t_s}", tmp_path)
    overview = _robot_extent(long_page, f"t={t_s}&view=path", tmp_path)
    record_property(f"robot_extent_follow_{t_s:g}", round(float(follow), 3))
    record_property(f"robot_extent_overview_{t_s:g}", round(float(overview), 3))
    assert follow >= MIN_ROBOT_EXTENT_FRACTION
    assert 0.0 < overview <= MAX_OVERVIEW_ROBOT_EXTENT_FRACTION


def test_legend_and_player_bar_in_the_live_page(page: Path, tmp_path: Path) -> None:
    """After the scripts ran: one legend entry per LEGEND colour, play/pause, speed menu,
    a time slider whose range is the plan's duration, the view toggle, and dat.GUI hidden."""
    dom = _dump_dom(page.resolve().as_uri(), tmp_path / "profile")
    for label, colour, _ in LEGEND:
        assert f"background:#{colour:06x}" in dom.replace(" ", "") and label in dom
    assert 'id="silo4-play"' in dom and 'id="silo4-speed"' in dom
    assert 'id="silo4-view"' in dom and ">Whole path<" in dom  # following by default
    slider = (
        dom.split('id="silo4-slider"')[0].rsplit("<input", 1)[1]
        + dom.split('id="silo4-slider"')[1].split(">", 1)[0]
    )
    assert 'max="12"' in slider  # 12 time units of 1 s
    assert "t = " in dom.split('id="silo4-time"')[1][:80]
    assert 'class="dg main' in dom and "display: none" in dom.split('class="dg main')[1][:200]


def test_report_page_renders(silo4: Robot, page: Path, tmp_path: Path) -> None:
    """report.html beside the animation: the header lists the inputs and the command, the
    tables carry units, the plots load, and the screenshot shows a page, not a blank."""
    from viz.plots.run_plots import write_plots
    from viz.report.page import write_report

    folder = page.parent
    walk = synthetic_trajectory(silo4, n_units=12.0, path="line")
    plots = write_plots(folder, walk)
    metrics = {
        "distance_m": 2.0,
        "normalized_time": 12.0,
        "peak_abs_qd": dict.fromkeys(walk.joint_names, 1.5),
        "motor_sizing": [{"joint": j, "motor_torque_peak_Nm": 0.5} for j in walk.joint_names],
        "spins": [{"waypoint_index": 1, "psi_deg": 90.0, "cycles": 2}],
    }
    report = write_report(
        folder,
        metrics=metrics,
        plots=plots,
        inputs={
            "robot": "silo4",
            "waypoints_in_world": [(2.0, 0.0)],
            "height_m": 0.34,
            "workspace": "default",
            "command": "silo4 plan --waypoints 2,0 --height 0.34",
        },
    )
    pixels, _, requests = _screenshot(report.resolve().as_uri(), tmp_path / "report.png")
    assert requests == []
    top = pixels[:200].mean(axis=2)
    assert float(top.std()) > MIN_PIXEL_STD  # header text and table drawn
    dom = _dump_dom(report.resolve().as_uri(), tmp_path / "profile")
    assert "silo4 plan --waypoints 2,0 --height 0.34" in dom
    for heading in (
        "distance travelled [m]",
        "peak |joint speed| [rad/s]",
        "motor torque peak [N m]",
        "rotation ψ [deg]",
    ):
        assert heading in dom, heading
    assert "{" not in dom.split("<body>")[1].split("<script")[0]  # no raw dict
    assert dom.count("<img") == len(plots)
