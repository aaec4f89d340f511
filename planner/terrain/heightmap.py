"""A height map: a grid of heights [m] over the floor, read from a .npy or a 16-bit PNG.

``heights`` (R, C): row r along y, column c along x; the sample (r, c) stands at
``origin + resolution * (c, r)`` in W [m] (the centre of cell (0, 0) is ``origin``). Between
samples the ground is two flat triangles per grid square, split along the diagonal from
(c, r) to (c + 1, r + 1): MuJoCo's hfield triangulation, so the planner, the HTML mesh and
the physics stand on one surface. On the edges of a grid square (and at the samples) this is
the bilinear interpolation; inside a square it is the linear one of its triangle. Outside the
grid the map adds nothing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Largest value of a 16-bit PNG sample (maps to z_range[1]).
PNG_16_BIT_MAX = 65535


@dataclass(frozen=True, eq=False)
class HeightMap:
    """Heights (R, C) [m] added to ``base_z`` [m] (the floor) on the grid (module docstring):
    ``resolution`` [m] per cell, ``origin_in_world`` (2,) [m] the centre of cell (0, 0)."""

    heights: np.ndarray
    resolution: float
    origin_in_world: np.ndarray
    base_z: float = 0.0

    @property
    def extent_in_world(self) -> tuple[np.ndarray, np.ndarray]:
        """(lowest xy, highest xy) of the grid's samples [m], (2,) each."""
        rows, cols = self.heights.shape
        lo = np.asarray(self.origin_in_world, dtype=float)
        return lo, lo + self.resolution * np.array([cols - 1, rows - 1], dtype=float)

    def _cells(self, xy_in_world: np.ndarray):
        xy = np.asarray(xy_in_world, dtype=float).reshape(-1, 2)
        lo, hi = self.extent_in_world
        inside = np.all((xy >= lo) & (xy <= hi), axis=1)
        grid = (xy - lo) / self.resolution
        rows, cols = self.heights.shape
        c = np.clip(np.floor(grid[:, 0]).astype(int), 0, max(cols - 2, 0))
        r = np.clip(np.floor(grid[:, 1]).astype(int), 0, max(rows - 2, 0))
        u = grid[:, 0] - c  # along x in the square, [0, 1]
        v = grid[:, 1] - r  # along y
        return inside, r, c, u, v

    def cell_at(self, xy_in_world: np.ndarray) -> tuple[int, int]:
        """(row, column) of the grid square under one point (2,) [m] (its lower corner
        sample), for messages."""
        _, r, c, _, _ = self._cells(np.reshape(xy_in_world, (1, 2)))
        return int(r[0]), int(c[0])

    def top_at(self, xy_in_world: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(z (N,) [m], unit normal (N, 3)) on the triangulated grid; -inf / NaN outside."""
        inside, r, c, u, v = self._cells(xy_in_world)
        h = self.heights
        h00 = h[r, c]
        h10 = h[r, c + 1]  # one column on (+x)
        h01 = h[r + 1, c]  # one row on (+y)
        h11 = h[r + 1, c + 1]
        upper = v > u  # the triangle (c, r), (c+1, r+1), (c, r+1)
        slope_x = np.where(upper, h11 - h01, h10 - h00)  # dz per cell along x
        slope_y = np.where(upper, h01 - h00, h11 - h10)
        z = self.base_z + h00 + u * slope_x + v * slope_y
        normal = np.column_stack(
            [-slope_x / self.resolution, -slope_y / self.resolution, np.ones(len(z))]
        )
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        z = np.where(inside, z, -np.inf)
        normal[~inside] = np.nan
        return z, normal

    def samples_near(
        self, xy_in_world: np.ndarray, radius_m: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """(points (M, K, 2) [m], near (M, K) bool): the grid samples in a square window
        around each point (M, 2) [m] in W, and which of them lie on the grid within
        ``radius_m`` [m] of it."""
        xy = np.asarray(xy_in_world, dtype=float).reshape(-1, 2)
        lo, _ = self.extent_in_world
        k = int(np.ceil(radius_m / self.resolution)) + 1
        window = np.arange(-k, k + 1)
        offsets = np.stack(np.meshgrid(window, window), axis=-1).reshape(-1, 2)  # (col, row)
        index = np.round((xy - lo) / self.resolution).astype(int)[:, None, :] + offsets[None]
        rows, cols = self.heights.shape
        on_grid = (
            (index[..., 0] >= 0)
            & (index[..., 0] < cols)
            & (index[..., 1] >= 0)
            & (index[..., 1] < rows)
        )
        points = lo + self.resolution * index
        near = on_grid & (np.linalg.norm(points - xy[:, None, :], axis=2) <= radius_m)
        return points, near

    def to_document(self) -> dict:
        """The map as terrain-file content with its heights inline (a run folder stands on
        its own)."""
        return {
            "heights": np.asarray(self.heights, dtype=float).tolist(),
            "resolution": float(self.resolution),
            "origin": [float(v) for v in self.origin_in_world],
        }


def png_heights(path, z_range: tuple[float, float], max_samples: int) -> np.ndarray:
    """A 16-bit greyscale PNG's samples mapped linearly onto ``z_range`` [m]: 0 -> z_range[0],
    PNG_16_BIT_MAX -> z_range[1]; PNG rows run top to bottom, so image row 0 is the map's
    last row (highest y). Shape (R, C). Raises ValueError for another kind of image or one
    of more than ``max_samples`` pixels (judged from its header, before decoding)."""
    from PIL import Image  # matplotlib's own dependency

    try:
        opened = Image.open(path)
    except Image.DecompressionBombError as exc:
        raise ValueError(str(exc)) from None
    with opened as image:
        width, height = image.size
        if width * height > max_samples:
            raise ValueError(f"{width} x {height} pixels, more than {max_samples} samples")
        if image.mode not in ("I;16", "I;16B", "I;16L", "I"):
            raise ValueError(f"not a 16-bit greyscale PNG (mode {image.mode})")
        samples = np.asarray(image, dtype=float)
    if samples.ndim != 2:
        raise ValueError(f"not a greyscale image (shape {samples.shape})")
    lo, hi = z_range
    return (lo + (hi - lo) * samples / PNG_16_BIT_MAX)[::-1]
