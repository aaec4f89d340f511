"""A serverless Meshcat window: record scene commands, emit one self-contained HTML file.

``meshcat.Visualizer.static_html()`` asks meshcat's ZMQ server subprocess for the scene
(stack-notes.md). :class:`RecorderWindow` is a drop-in for ``meshcat.visualizer.ViewerWindow``
(``send(command)``, ``get_scene()``) that keeps the scene in a
``meshcat.servers.tree.SceneTree`` instead: no port, no subprocess, nothing that can outlive
the caller, and the same bytes for the same commands.

The page it writes inlines the viewer (``meshcat/viewer/dist/main.min.js``) and replays the
recorded commands synchronously from base64 msgpack blobs (no ``fetch``, not even of
``data:`` URLs), so a script placed after them (e.g. the ``?t=`` seek of animation.py) sees
the finished scene. The page makes no network request.

Helpers here build the command dictionaries meshcat's JavaScript understands, with
deterministic UUIDs (meshcat's Python classes use ``uuid.uuid1()``, time-dependent) and
float32 typed arrays (msgpack extension 0x17) for bulk numbers.
"""

from __future__ import annotations

import base64
import html
import importlib.util
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np
import umsgpack


def meshcat_dir() -> Path:
    """The installed meshcat package's folder, found without importing it: ``import
    meshcat`` runs its ``__init__``, which imports its live Visualizer (IPython, tornado,
    ZMQ; ~0.2 s of CPU), none of which a recorded page needs."""
    spec = importlib.util.find_spec("meshcat")
    if spec is None or not spec.submodule_search_locations:
        raise ModuleNotFoundError("meshcat is not installed (pip install meshcat)")
    return Path(next(iter(spec.submodule_search_locations)))


def _scene_tree_module() -> Any:
    """meshcat's ``servers/tree.py`` (SceneTree, find_node, walk: 30 lines, no imports of
    its own), loaded from its file under a private name, not through ``meshcat/__init__``."""
    name = "viz._meshcat_servers_tree"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, meshcat_dir() / "servers" / "tree.py")
        if spec is None or spec.loader is None:
            raise ModuleNotFoundError("meshcat/servers/tree.py not found")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


SceneTree = _scene_tree_module().SceneTree
find_node = _scene_tree_module().find_node
walk = _scene_tree_module().walk

#: msgpack extension codes of meshcat's viewer (msgpack-lite preset codec).
EXT_UINT8 = 0x12
EXT_UINT32 = 0x16
EXT_FLOAT32 = 0x17

#: three.js interpolation enum: keys held until the next key (contact flags, polygons).
INTERPOLATE_DISCRETE = 2300


def float32_ext(array: np.ndarray) -> umsgpack.Ext:
    """A numpy array as a Float32Array for meshcat's msgpack decoder (C order, flattened)."""
    return umsgpack.Ext(EXT_FLOAT32, np.ascontiguousarray(array, dtype="<f4").tobytes())


def matrix_to_js(transform: np.ndarray) -> list[float]:
    """A 4x4 homogeneous transform as three.js's column-major list of 16 floats."""
    return [float(x) for x in np.asarray(transform, dtype=float).reshape(4, 4).flatten("F")]


def color_to_int(rgb: Any) -> int:
    """RGB in [0, 1] (3 or more values, extra ignored) -> 0xRRGGBB."""
    r, g, b = (int(round(255 * float(np.clip(c, 0.0, 1.0)))) for c in list(rgb)[:3])
    return (r << 16) | (g << 8) | b


def material(
    uuid: str, color: int, *, kind: str = "MeshPhongMaterial", opacity: float = 1.0, **extra: Any
) -> dict[str, Any]:
    """A three.js material dict (meshcat ``GenericMaterial.lower`` without a random UUID)."""
    data: dict[str, Any] = {
        "uuid": uuid,
        "type": kind,
        "color": int(color),
        "side": 2,
        "transparent": bool(opacity < 1.0),
        "opacity": float(opacity),
    }
    if kind in ("MeshPhongMaterial", "MeshLambertMaterial"):
        data["reflectivity"] = 0.5
    data.update(extra)
    return data


def scene_object(
    uuid: str,
    kind: str,
    geometry: dict[str, Any],
    mat: dict[str, Any],
    intrinsic: np.ndarray | None = None,
) -> dict[str, Any]:
    """A three.js Object JSON (``Mesh``, ``Line``, ``Points``...) holding one geometry.

    Args:
        intrinsic: 4x4 transform applied to the geometry inside the object (e.g. turn a
            three.js cylinder, axis y, into a URDF cylinder, axis z); identity if None.
    """
    geometry = dict(geometry, uuid=f"{uuid}/geometry")
    mat = dict(mat, uuid=f"{uuid}/material")
    return {
        "metadata": {"version": 4.5, "type": "Object"},
        "geometries": [geometry],
        "materials": [mat],
        "object": {
            "uuid": uuid,
            "type": kind,
            "geometry": geometry["uuid"],
            "material": mat["uuid"],
            "matrix": matrix_to_js(np.eye(4) if intrinsic is None else intrinsic),
        },
    }


def buffer_geometry(position: np.ndarray) -> dict[str, Any]:
    """A BufferGeometry of vertices ``position: (M, 3)`` [m] (lines and point clouds)."""
    position = np.asarray(position, dtype=float).reshape(-1, 3)
    return {
        "type": "BufferGeometry",
        "data": {
            "attributes": {
                "position": {
                    "itemSize": 3,
                    "type": "Float32Array",
                    "array": float32_ext(position),
                    "normalized": False,
                }
            }
        },
    }


def track(
    name: str, kind: str, times_s: np.ndarray, values: Any, interpolation: int | None = None
) -> dict[str, Any]:
    """One three.js KeyframeTrack in its JSON form with typed arrays.

    three.js ``KeyframeTrack.parse`` takes ``times``/``values`` directly when present (it
    only flattens ``keys`` when ``times`` is missing), which keeps 4 bytes per number.

    Args:
        name: property path on the clip's target, e.g. ``.position``, ``.rotation[z]``.
        kind: ``number``, ``vector``, ``quaternion`` or ``bool``.
        times_s: key times [s], shape (K,).
        values: (K,) or (K, d) numbers, or K booleans for ``bool``.
    """
    data: dict[str, Any] = {
        "name": name,
        "type": kind,
        "times": float32_ext(np.asarray(times_s, dtype=float)),
    }
    if kind == "bool":
        data["values"] = [bool(v) for v in values]
    else:
        data["values"] = float32_ext(np.asarray(values, dtype=float))
    if interpolation is not None:
        data["interpolation"] = int(interpolation)
    return data


class RecorderWindow:
    """Records meshcat commands into a SceneTree and serves the scene as static HTML.

    A drop-in for ``meshcat.visualizer.ViewerWindow``: ``meshcat.Visualizer(window=
    RecorderWindow())`` works, and :meth:`record` takes already-lowered command dicts.
    Like meshcat's server, a later ``set_object`` on a path replaces the earlier one.
    Animations are emitted after every object so that clips bind to the final objects.
    """

    def __init__(self) -> None:
        self.tree = SceneTree()
        self.animations: list[bytes] = []
        self.web_url = None

    def send(self, command: Any) -> None:
        """Record a meshcat command object (anything with ``lower() -> dict``)."""
        self.record(command.lower())

    def record(self, command: dict[str, Any]) -> None:
        """Record one lowered command dict (``type``, ``path``, payload)."""
        data = umsgpack.packb(command)
        kind = command["type"]
        if kind == "set_animation":
            self.animations.append(data)
            return
        path = [p for p in str(command["path"]).split("/") if p]
        node = find_node(self.tree, path)
        if kind == "set_object":
            node.object = data
            node.properties = []
        elif kind == "set_transform":
            node.transform = data
        elif kind == "set_property":
            node.properties.append(data)
        elif kind == "delete":
            if path:
                find_node(self.tree, path[:-1]).pop(path[-1], None)
            else:
                self.tree = SceneTree()
        else:
            raise ValueError(f"RecorderWindow cannot record command type {kind!r}")

    def commands(self) -> list[bytes]:
        """The msgpack command blobs in replay order: the tree depth first, then animations."""
        out: list[bytes] = []
        for node in walk(self.tree):
            if node.object is not None:
                out.append(node.object)
            out.extend(node.properties)
            if node.transform is not None:
                out.append(node.transform)
        return out + self.animations

    def get_scene(
        self, title: str = "MeshCat", head: str = "", body: str = "", script: str = ""
    ) -> str:
        """The whole page: inlined viewer, replayed commands, then ``script``.

        Args:
            title: page title (escaped here).
            head: extra HTML inside ``<head>`` (e.g. a ``<style>``).
            body: extra HTML after the viewer pane (e.g. an overlay ``<div>``).
            script: JavaScript run after the scene is built; ``viewer`` is defined.
        """
        viewer_js = viewer_javascript()
        blobs = ",\n".join(json.dumps(base64.b64encode(b).decode("ascii")) for b in self.commands())
        for part in (head, body, script):
            if "</script" in part.lower().replace("<\\/script", ""):
                raise ValueError("extra HTML/JS must not close a <script> element")
        return _PAGE.format(
            title=html.escape(title),
            head=head,
            body=body,
            viewer_js=viewer_js,
            blobs=blobs,
            script=script,
        )

    # ViewerWindow methods that need a live browser.
    def open(self) -> RecorderWindow:  # pragma: no cover - interface completeness
        raise NotImplementedError("RecorderWindow has no live viewer; write get_scene() out")

    def wait(self) -> str:  # pragma: no cover
        raise NotImplementedError("RecorderWindow has no live viewer")

    def get_image(self) -> None:  # pragma: no cover
        raise NotImplementedError("RecorderWindow has no live viewer")


def viewer_javascript() -> str:
    """The bundled meshcat viewer (three.js, msgpack, dat.GUI), ~850 kB."""
    text = (meshcat_dir() / "viewer" / "dist" / "main.min.js").read_text("utf-8")
    if "</script" in text.lower():  # would end the inline <script> early
        raise RuntimeError("meshcat main.min.js contains '</script'; cannot inline it")
    return text


_PAGE = """<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; \
script-src 'unsafe-inline' 'unsafe-eval'; style-src 'unsafe-inline'; img-src data: blob:; \
connect-src data: blob:; worker-src blob:">
<title>{title}</title>
<style>body {{ margin: 0; }} #meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
</style>
{head}
</head>
<body>
<div id="meshcat-pane"></div>
{body}
<script>
{viewer_js}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
(function () {{
  var blobs = [
{blobs}
  ];
  for (var i = 0; i < blobs.length; i++) {{
    var s = atob(blobs[i]), bytes = new Uint8Array(s.length);
    for (var j = 0; j < s.length; j++) bytes[j] = s.charCodeAt(j);
    viewer.handle_command_bytearray(bytes);
  }}
}})();
</script>
<script>
{script}
</script>
</body>
</html>
"""
