"""The controls of animation.html: a camera that follows the robot, a legend, a player bar.

What a person sees over the 3-D view (all plain HTML/JS in the page, no network):

- top left: the title and a legend with one swatch per colour of the scene (LEGEND:
  desired path, waypoints, walked CoG path, CoG ground projection, footholds, support
  polygon, stance feet, swing feet), and a note when the keyframes were thinned;
- bottom: play/pause, a time slider, the time in s and t_l with the phase, a speed menu
  (0.25x-8x) and a view toggle: "Follow robot" (default: the orbit camera's centre rides on
  the CoG's ground projection, so the robot stays large on any path length) or "Whole path"
  (the overview).

URL options: ``?t=SECONDS`` pauses and seeks (shareable links, pixel-stable screenshots);
``?view=path`` starts in the whole-path view; ``?speed=2`` plays at 2x; ``?hide=robot``
hides the robot (tests measure its pixels by difference). Space toggles play/pause.

meshcat turns its Z-up scene into three.js's Y-up world (scene Rx(-90 deg)); the camera sits
under /Cameras/default/rotated (Rx(+90 deg)), so with /Cameras/default at the origin the
camera position and the orbit target are three.js world points: a meshcat world point
(x, y, z) is (x, z, -y). Following moves target and camera by the robot's step each frame,
so the user can still orbit and zoom around the robot.
"""

from __future__ import annotations

import html
import json

from viz.animation.scene import (
    COLOR_COG,
    COLOR_FOOTHOLD,
    COLOR_PATH,
    COLOR_STANCE,
    COLOR_SUPPORT,
    COLOR_SWING,
)

#: (label, colour 0xRRGGBB, swatch shape) of every colour drawn in the scene.
LEGEND: tuple[tuple[str, int, str], ...] = (
    ("desired path", COLOR_PATH, "line"),
    ("waypoints", COLOR_PATH, "dot"),
    ("walked path (CoG)", COLOR_COG, "line"),
    ("CoG ground projection", COLOR_COG, "dot"),
    ("footholds", COLOR_FOOTHOLD, "dot"),
    ("support polygon", COLOR_SUPPORT, "line"),
    ("stance foot", COLOR_STANCE, "dot"),
    ("swing foot", COLOR_SWING, "dot"),
)
#: Speeds offered in the menu [x real time].
SPEEDS = (0.25, 0.5, 1.0, 2.0, 4.0, 8.0)


def legend_html() -> str:
    """The legend's list items (one per LEGEND entry)."""
    items = []
    for label, color, shape in LEGEND:
        cls = "sw-line" if shape == "line" else "sw-dot"
        items.append(
            f'<li><span class="{cls}" style="background:#{color:06x}"></span>'
            f"{html.escape(label)}</li>"
        )
    return "".join(items)


def overlay_html(title: str, note: str | None) -> str:
    """The HTML over the viewer: title + legend box, and the player bar."""
    speeds = "".join(
        f'<option value="{s:g}"{" selected" if s == 1.0 else ""}>{s:g}x</option>' for s in SPEEDS
    )
    note_html = f'<div id="silo4-note">{html.escape(note)}</div>' if note else ""
    return (
        f'<div id="silo4-legend"><b>{html.escape(title)}</b><ul>{legend_html()}</ul>'
        f"{note_html}</div>"
        '<div id="silo4-bar">'
        '<button id="silo4-play" title="play / pause (space)">Pause</button>'
        '<input id="silo4-slider" type="range" min="0" value="0" step="0.01" '
        'aria-label="time">'
        '<span id="silo4-time"></span>'
        f'<label>speed <select id="silo4-speed">{speeds}</select></label>'
        '<button id="silo4-view" title="camera: follow the robot / whole path">'
        "Whole path</button></div>"
    )


STYLE = """<style>
#silo4-legend { position: fixed; left: 10px; top: 10px; padding: 6px 10px;
  font: 13px/1.35 sans-serif; color: #222; background: rgba(255, 255, 255, 0.85);
  border-radius: 4px; max-width: 300px; }
#silo4-legend ul { list-style: none; margin: 4px 0 0; padding: 0; }
#silo4-legend li { white-space: nowrap; }
.sw-line { display: inline-block; width: 18px; height: 3px; margin: 0 6px 3px 0;
  vertical-align: middle; }
.sw-dot { display: inline-block; width: 10px; height: 10px; border-radius: 50%;
  margin: 0 10px 2px 4px; vertical-align: middle; }
#silo4-note { margin-top: 4px; color: #8a4b00; font-size: 12px; white-space: normal; }
#silo4-bar { position: fixed; left: 10px; right: 10px; bottom: 10px; display: flex;
  align-items: center; gap: 10px; padding: 6px 10px; font: 13px sans-serif; color: #222;
  background: rgba(255, 255, 255, 0.85); border-radius: 4px; }
#silo4-bar button { font: inherit; padding: 3px 10px; min-width: 80px; }
#silo4-slider { flex: 1; }
#silo4-time { font-variant-numeric: tabular-nums; min-width: 300px; }
</style>"""

# Runs after the scene is built. Animator methods: meshcat viewer/src/index.js (Animator).
_SCRIPT = """
(function () {
  var meta = __META__;
  var animator = viewer.animator;
  var params = new URLSearchParams(window.location.search);
  viewer.gui.domElement.style.display = "none";  // our bar replaces dat.GUI's controls
  var cameraNode = viewer.scene_tree.find(["Cameras", "default"]).object;
  var robotNode = viewer.scene_tree.find(meta.ground_path).object;
  var camera = viewer.camera;
  camera.far = meta.camera.far;
  camera.updateProjectionMatrix();
  (params.get("hide") || "").split(",").forEach(function (name) {
    if (name === "robot") viewer.scene_tree.find(meta.robot_path).object.visible = false;
  });
  var playButton = document.getElementById("silo4-play");
  var slider = document.getElementById("silo4-slider");
  var speed = document.getElementById("silo4-speed");
  var viewButton = document.getElementById("silo4-view");
  var label = document.getElementById("silo4-time");
  slider.max = meta.duration_s;
  var follow = params.get("view") !== "path";

  // OrbitControls works in three.js world coordinates (Y up): a meshcat world point
  // (x, y, z) is (x, z, -y) there. The camera node stays at the origin so the camera's
  // position is a world position; following moves target and camera by the same step,
  // which keeps any orbit or zoom the user made.
  cameraNode.position.set(0, 0, 0);
  function three(p) { return [p[0], p[2], -p[1]]; }
  function lookFrom(target, offset) {
    var t = three(target), o = three(offset);
    viewer.controls.target.set(t[0], t[1], t[2]);
    camera.position.set(t[0] + o[0], t[1] + o[1], t[2] + o[2]);
    viewer.controls.update();
    viewer.set_dirty();
  }
  function robotGround() {
    robotNode.updateMatrixWorld(true);
    var e = robotNode.matrixWorld.elements;  // three.js world: (x, z_up, -y)
    return [e[12], -e[14], 0];
  }
  function applyView() {
    if (follow) {
      lookFrom(robotGround(), meta.camera.follow_offset);
    } else {
      var c = meta.camera.overview_centre;
      lookFrom([c[0], c[1], 0], meta.camera.overview_offset);
    }
    viewButton.textContent = follow ? "Whole path" : "Follow robot";
  }
  function now() {  // a still plan's clip lasts 0 s: three.js then reports NaN
    var t = animator.actions.length ? animator.actions[0].time : 0;
    return isFinite(t) ? t : 0;
  }
  function seek(t) {
    t = Math.max(0, Math.min(meta.duration_s, t));
    animator.seek(t);
    animator.display_progress(t);
  }
  function phaseAt(t) {
    var lo = 0, hi = meta.phase_start_s.length - 1;
    while (lo < hi) {
      var mid = (lo + hi + 1) >> 1;
      if (meta.phase_start_s[mid] <= t) lo = mid; else hi = mid - 1;
    }
    return meta.phase[lo];
  }
  playButton.onclick = function () {
    if (animator.playing) animator.pause(); else animator.play();
  };
  viewButton.onclick = function () { follow = !follow; applyView(); };
  speed.onchange = function () { animator.mixer.timeScale = parseFloat(speed.value); };
  var dragging = false;
  slider.addEventListener("input", function () {
    dragging = true;
    seek(parseFloat(slider.value));
  });
  slider.addEventListener("change", function () { dragging = false; });
  document.addEventListener("keydown", function (e) {
    if (e.code === "Space" && e.target.tagName !== "SELECT") {
      e.preventDefault();
      playButton.onclick();
    }
  });
  var wanted = parseFloat(params.get("speed"));
  if (isFinite(wanted) && wanted > 0) {
    animator.mixer.timeScale = wanted;
    speed.value = String(wanted);
  }
  var at = parseFloat(params.get("t"));
  if (isFinite(at)) { animator.pause(); seek(at); }
  applyView();
  function tick() {
    if (follow) {
      var g = three(robotGround()), target = viewer.controls.target;
      var dx = g[0] - target.x, dy = g[1] - target.y, dz = g[2] - target.z;
      if (dx !== 0 || dy !== 0 || dz !== 0) {
        target.set(g[0], g[1], g[2]);
        camera.position.set(camera.position.x + dx, camera.position.y + dy,
                            camera.position.z + dz);
        viewer.controls.update();
        viewer.set_dirty();
      }
    }
    var t = now();
    if (!dragging) slider.value = t;
    playButton.textContent = animator.playing ? "Pause" : "Play";
    label.textContent = "t = " + t.toFixed(2) + " s (" + (t / meta.time_unit_s).toFixed(2) +
      " t_l) \\u00b7 " + phaseAt(t) + (animator.playing ? "" : " \\u00b7 paused");
    window.requestAnimationFrame(tick);
  }
  tick();
})();
"""


def player_script(meta: dict) -> str:
    """The page's script with ``meta`` (JSON, safe inside <script>) filled in."""
    return _SCRIPT.replace("__META__", json.dumps(meta, sort_keys=True).replace("</", "<\\/"))
