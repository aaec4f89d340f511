"""The terrain seen from above for report.html: the ground height under the walk (floor,
boxes, posts, height map: ``TerrainMap.height_at`` on a grid, so the picture is the ground
the planner stands on), void left white, forbidden regions hatched red, the CoG path and
every foothold on top.

    write_terrain_top_view(folder / "terrain_top_view.png", terrain, plan.trajectory)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from planner.outputs.files import record_written, write_atomic
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.samples import Trajectory
from viz.animation.terrain import clip_polygon
from viz.plots.figure import new_figure

#: Ground drawn this far around the path and the feet [m].
VIEW_MARGIN_M = 0.4
#: Most grid cells along the longer side of the view.
MAX_CELLS = 400
#: Least height range of the colour scale [m] (flat ground is one colour, not noise).
MIN_COLOUR_SPAN_M = 0.02
#: Figure width [in] and resolution [dpi].
FIGURE_WIDTH_IN = 6.0
DPI = 110


def ground_grid(
    terrain: TerrainMap, lo_xy: np.ndarray, hi_xy: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cell centres x (C,), y (R,) [m] and the ground height under each (R, C) [m] over the
    rectangle lo_xy..hi_xy, NaN where nothing lies under a cell (no floor)."""
    cell = float(max(hi_xy - lo_xy)) / MAX_CELLS
    x = np.arange(lo_xy[0] + cell / 2, hi_xy[0], cell)
    y = np.arange(lo_xy[1] + cell / 2, hi_xy[1], cell)
    gx, gy = np.meshgrid(x, y)
    z = terrain.height_at(np.column_stack([gx.ravel(), gy.ravel()])).reshape(gx.shape)
    return x, y, np.where(np.isfinite(z), z, np.nan)


def terrain_top_view(terrain: TerrainMap, trajectory: Trajectory):  # noqa: ANN201 (Figure)
    """The top view (module docstring) as a matplotlib Figure."""
    base_xy = np.asarray(trajectory.position_base_in_world, dtype=float)[:, :2]
    feet = np.asarray(trajectory.position_foot_in_world, dtype=float)  # (N, 4, 3)
    contact = np.asarray(trajectory.contact, dtype=bool)  # (N, 4)
    stance_xy = feet[contact][:, :2]
    points = np.concatenate([base_xy, feet.reshape(-1, 3)[:, :2]])
    lo, hi = points.min(axis=0) - VIEW_MARGIN_M, points.max(axis=0) + VIEW_MARGIN_M
    x, y, z = ground_grid(terrain, lo, hi)
    width = FIGURE_WIDTH_IN
    height = float(np.clip(width * (hi[1] - lo[1]) / (hi[0] - lo[0]), 2.5, 9.0))
    fig = new_figure(width, height)
    ax = fig.add_subplot(1, 1, 1)
    finite = z[np.isfinite(z)]
    z_lo, z_hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    span = max(z_hi - z_lo, MIN_COLOUR_SPAN_M)
    image = ax.imshow(
        np.ma.masked_invalid(z),
        origin="lower",
        extent=(lo[0], hi[0], lo[1], hi[1]),
        cmap="terrain",
        vmin=z_lo - 0.05 * span,
        vmax=z_lo + 1.05 * span,
        interpolation="nearest",
    )
    fig.colorbar(image, ax=ax, label="ground height z [m]", shrink=0.8)
    for polygon in terrain.forbidden_xy_in_world:
        shown = clip_polygon(polygon, lo, hi)
        if len(shown) >= 3:
            ax.fill(*shown.T, facecolor="none", edgecolor="#d62728", hatch="//", linewidth=1)
    ax.plot(base_xy[:, 0], base_xy[:, 1], color="black", linewidth=1.2, label="CoG path")
    ax.scatter(
        stance_xy[:, 0], stance_xy[:, 1], s=6, color="#d62728", label="stance feet", zorder=3
    )
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    void = " (white: no ground)" if terrain.floor_z is None else ""
    ax.set_title(f"terrain from above{void}")
    ax.legend(loc="upper right", fontsize=7)
    fig.tight_layout()
    return fig


def write_terrain_top_view(path: str | Path, terrain: TerrainMap, trajectory: Trajectory) -> Path:
    """Write the top view as a PNG at ``path`` (atomically, recorded as silo4's); returns it."""
    fig = terrain_top_view(terrain, trajectory)
    out = write_atomic(Path(path), lambda tmp: fig.savefig(tmp, dpi=DPI, format="png"))
    record_written([out])
    return out


def terrain_view_writer(terrain: TerrainMap, trajectory: Trajectory, made: list[Path]):  # noqa: ANN201
    """For ``silo4 plan --terrain``: a run-folder writer (``writer(folder)``) that writes
    ``folder/terrain_top_view.png`` from the run's terrain and appends it to ``made``, the
    figures report.html shows."""

    def write(folder: Path) -> None:
        made.append(write_terrain_top_view(folder / "terrain_top_view.png", terrain, trajectory))

    return write
