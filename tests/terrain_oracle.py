"""The ground of a terrain file, computed here from the file alone (not with the planner's
planner/terrain code), for tests that check a run folder against it: the top faces of boxes
(possibly rolled or pitched) and posts, the floor, a height map's triangles, forbidden
polygons. Conventions of docs/terrain.md: rpy in degrees, R = R_z(yaw) R_y(pitch) R_x(roll);
a height map's sample (r, c) at origin + resolution (c, r), added to the floor, each square
split from (r, c) to (r + 1, c + 1).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import yaml


def rotation_rpy_deg(rpy) -> np.ndarray:
    r, p, y = np.radians(rpy)
    rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
    ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
    return rz @ ry @ rx


class Face:
    """A top face: its height z(x, y) [m] where it covers (x, y), and the distance from a point
    inside to its edges [m] (a box's top rectangle, possibly tilted; a post's disc)."""

    def __init__(self, box=None, cylinder=None):
        self.box, self.cylinder = box, cylinder
        if box is not None:
            self.rot = rotation_rpy_deg(box.get("rpy", [0, 0, 0]))
            self.centre = np.array(box["center"], float)
            self.half = 0.5 * np.array(box["size"], float)

    def _box_local(self, xy):
        """Point of the top plane over xy, in the box frame (N, 3)."""
        n = self.rot[:, 2]
        top = self.centre + self.rot[:, 2] * self.half[2]
        z = top[2] - (n[0] * (xy[:, 0] - top[0]) + n[1] * (xy[:, 1] - top[1])) / n[2]
        p = np.column_stack([xy, z])
        return (p - self.centre) @ self.rot, z

    def height(self, xy):
        """z [m] of the face over xy (N, 2), -inf where it does not cover it."""
        if self.box is not None:
            local, z = self._box_local(xy)
            inside = np.all(np.abs(local[:, :2]) <= self.half[:2] + 1e-9, axis=1)
            return np.where(inside, z, -np.inf)
        c = self.cylinder
        inside = np.hypot(xy[:, 0] - c["center"][0], xy[:, 1] - c["center"][1]) <= c["radius"]
        return np.where(inside, c["center"][2] + 0.5 * c["height"], -np.inf)

    def footprint_distance(self, xy):
        """Signed distance [m] of xy (N, 2) from the face's outline seen from above
        (positive inside); for a tilted box along its own axes, which is the same here."""
        if self.box is not None:
            local, _ = self._box_local(xy)
            return np.min(self.half[:2] - np.abs(local[:, :2]), axis=1)
        c = self.cylinder
        return c["radius"] - np.hypot(xy[:, 0] - c["center"][0], xy[:, 1] - c["center"][1])


#: A point this close outside a height map's grid stands on its border edge [m] (a ball
#: rolled onto the edge where the map stops above the floor).
BORDER_M = 1e-6


class HeightGrid:
    """A terrain file's height map: heights (R, C) [m] over the floor."""

    def __init__(self, document: dict, folder: Path) -> None:
        hm = document["heightmap"]
        if "heights" in hm:
            self.heights = np.asarray(hm["heights"], float)
        else:
            self.heights = np.asarray(np.load(folder / hm["file"]), float)
        self.resolution = float(hm["resolution"])
        self.origin = np.array(hm["origin"], float)
        self.floor = float(document.get("floor", 0.0) or 0.0)

    def height(self, xy) -> np.ndarray:
        """Ground z [m] under xy (N, 2) of the map's triangles, -inf off the grid."""
        xy = np.asarray(xy, float).reshape(-1, 2)
        rows, cols = self.heights.shape
        g = (xy - self.origin) / self.resolution
        e = BORDER_M / self.resolution  # the border edge belongs to the map
        on = (
            (g[:, 0] >= -e)
            & (g[:, 0] <= cols - 1 + e)
            & (g[:, 1] >= -e)
            & (g[:, 1] <= rows - 1 + e)
        )
        g = np.clip(g, 0.0, [cols - 1, rows - 1])
        c = np.clip(np.floor(g[:, 0]).astype(int), 0, cols - 2)
        r = np.clip(np.floor(g[:, 1]).astype(int), 0, rows - 2)
        u, v = g[:, 0] - c, g[:, 1] - r
        h = self.heights
        h00, h11 = h[r, c], h[r + 1, c + 1]
        upper = v > u  # the triangle (r, c), (r + 1, c + 1), (r + 1, c)
        z = np.where(
            upper,
            h00 + v * (h[r + 1, c] - h00) + u * (h11 - h[r + 1, c]),
            h00 + u * (h[r, c + 1] - h00) + v * (h11 - h[r, c + 1]),
        )
        return np.where(on, self.floor + z, -np.inf)


class TerrainOracle:
    """Ground height, top faces and forbidden polygons of one terrain file."""

    def __init__(self, path: Path) -> None:
        self.document = yaml.safe_load(Path(path).read_text()) or {}
        self.faces = [Face(box=b) for b in self.document.get("boxes") or []] + [
            Face(cylinder=c) for c in self.document.get("cylinders") or []
        ]
        self.floor = self.document.get("floor", 0.0)
        self.grid = (
            HeightGrid(self.document, Path(path).parent) if self.document.get("heightmap") else None
        )
        self.forbidden = [np.asarray(p, float) for p in self.document.get("forbidden") or []]

    def ground(self, xy) -> np.ndarray:
        """The highest surface z [m] under xy (N, 2): -inf over a void."""
        xy = np.asarray(xy, float).reshape(-1, 2)
        z = np.full(len(xy), -np.inf if self.floor is None else float(self.floor))
        if self.grid is not None:
            z = np.maximum(z, self.grid.height(xy))
        for face in self.faces:
            z = np.maximum(z, face.height(xy))
        return z

    def forbidden_distance(self, xy) -> np.ndarray:
        """Least distance [m] of xy (N, 2) outside every forbidden polygon (negative inside
        one: minus the distance to its nearest edge); +inf without polygons."""
        xy = np.asarray(xy, float).reshape(-1, 2)
        out = np.full(len(xy), np.inf)
        for poly in self.forbidden:
            a, b = poly, np.roll(poly, -1, axis=0)
            ab = b - a
            t = np.clip(
                np.einsum("nkj,kj->nk", xy[:, None] - a[None], ab) / np.sum(ab * ab, 1), 0, 1
            )
            edge = np.linalg.norm(xy[:, None] - (a[None] + t[..., None] * ab[None]), axis=2)
            cross = ab[None, :, 0] * (xy[:, None, 1] - a[None, :, 1]) - ab[None, :, 1] * (
                xy[:, None, 0] - a[None, :, 0]
            )
            inside = np.all(cross >= 0, axis=1) | np.all(cross <= 0, axis=1)
            out = np.minimum(out, np.where(inside, -edge.min(1), edge.min(1)))
        return out


def read_trajectory_csv(path: Path) -> dict[str, np.ndarray]:
    """trajectory.csv's columns by name (floats)."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        header = list(reader.fieldnames or [])
        rows = list(reader)
    out = {}
    for name in header:
        try:
            out[name] = np.array([float(r[name]) for r in rows])
        except ValueError:
            out[name] = np.array([r[name] for r in rows])
    return out


def feet_and_contact(columns: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """(feet (N, 4, 3) [m], contact (N, 4) bool, leg labels) from trajectory.csv's columns
    (``foot_<leg>_x`` ..., ``contact_<leg>``, the robot's own leg labels)."""
    legs = [name[len("contact_") :] for name in columns if name.startswith("contact_")]
    feet = np.stack(
        [np.stack([columns[f"foot_{leg}_{a}"] for a in "xyz"], axis=1) for leg in legs], axis=1
    )
    contact = np.stack([columns[f"contact_{leg}"] > 0.5 for leg in legs], axis=1)
    return feet, contact, legs
