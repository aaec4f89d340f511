"""The solids of a terrain file: boxes (a ramp is a tilted box) and vertical cylinders.

Each answers, vectorised over points (N, 2) in the world frame W [m], where a vertical line
through the point leaves the solid at the top (:meth:`Box.top_at`, :meth:`Cylinder.top_at`):
the height z [m] (-inf where the line misses the solid) and the outward unit normal of the
face it leaves through, (N, 3) (NaN where it misses). That is the first point a ray cast
straight down from above hits, the ground a foot would stand on. Each also gives the
signed Euclidean distance of points (N, 3) to its surface (:meth:`Box.signed_distance`,
:meth:`Cylinder.signed_distance`; negative inside), which sees side faces: what a sphere
beside a riser is measured against (TerrainMap.sphere_clearance).

A box's orientation ``rpy_deg`` is roll, pitch, yaw [deg] about the world's fixed x, y, z
axes in that order (URDF's rpy): ``R = R_z(yaw) R_y(pitch) R_x(roll)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: Vertices of the polygon that stands for a cylinder's round top face in :meth:`surface`.
CYLINDER_TOP_VERTICES = 32


@dataclass(frozen=True)
class Surface:
    """A flat top face a foot may use: its polygon (M, 3) in W [m], counter-clockwise seen
    from above its normal, the outward unit normal (3,), and what it is ("box 2")."""

    vertices_in_world: np.ndarray
    normal_in_world: np.ndarray
    name: str


def _signed_distance_of_excess(q: np.ndarray) -> np.ndarray:
    """Signed distance (N,) [m] to a box-like solid from each point's excess (N, D) over the
    half-extents along the solid's axes: |max(q, 0)| outside, max_i q_i inside."""
    return np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)


def rotation_rpy_deg(rpy_deg: np.ndarray) -> np.ndarray:
    """R = R_z(yaw) R_y(pitch) R_x(roll) of roll, pitch, yaw (3,) [deg], shape (3, 3)."""
    roll, pitch, yaw = np.radians(np.asarray(rpy_deg, dtype=float))
    cr, sr, cp, sp, cy, sy = (
        np.cos(roll),
        np.sin(roll),
        np.cos(pitch),
        np.sin(pitch),
        np.cos(yaw),
        np.sin(yaw),
    )
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    return rz @ ry @ rx


@dataclass(frozen=True, eq=False)
class Box:
    """A solid box: centre (3,) in W [m], full edge lengths ``size`` (3,) [m] along its own
    axes, orientation ``rpy_deg`` (3,) [deg] (module docstring)."""

    center_in_world: np.ndarray
    size: np.ndarray
    rpy_deg: np.ndarray = field(default_factory=lambda: np.zeros(3))

    @property
    def rotation_box_to_world(self) -> np.ndarray:
        """The box's axes in W, (3, 3) (columns: its x, y, z)."""
        return rotation_rpy_deg(self.rpy_deg)

    def top_at(self, xy_in_world: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(z (N,) [m], normal (N, 3)) where the vertical line through each point (N, 2)
        leaves the box (slab intersection in the box frame; -inf / NaN where it misses)."""
        xy = np.asarray(xy_in_world, dtype=float).reshape(-1, 2)
        rot = self.rotation_box_to_world
        half = 0.5 * np.asarray(self.size, dtype=float)
        # the line p(t) = (x, y, t) in the box frame: start + t * direction
        start = (np.column_stack([xy, np.zeros(len(xy))]) - self.center_in_world) @ rot
        direction = rot[2]  # R^T e_z
        with np.errstate(divide="ignore", invalid="ignore"):
            t_a = (-half - start) / direction
            t_b = (half - start) / direction
        parallel = np.abs(direction) < 1e-15
        inside = np.abs(start) <= half
        t_low = np.where(parallel, np.where(inside, -np.inf, np.inf), np.minimum(t_a, t_b))
        t_high = np.where(parallel, np.where(inside, np.inf, -np.inf), np.maximum(t_a, t_b))
        t_exit = t_high.min(axis=1)
        hit = t_low.max(axis=1) <= t_exit
        axis = np.argmin(t_high, axis=1)
        sign = np.sign(direction[axis])  # the line leaves through the +axis face when rising
        normal = rot[:, axis].T * sign[:, None]
        z = np.where(hit, t_exit, -np.inf)
        normal[~hit] = np.nan
        return z, normal

    def signed_distance(self, points_in_world: np.ndarray) -> np.ndarray:
        """Signed distance [m] of points (N, 3) in W to the box's surface, shape (N,):
        positive outside (to the nearest face, edge or corner), negative inside (to the
        nearest face). In the box frame q = |p| - half: |max(q, 0)| + min(max_i q_i, 0)."""
        pts = np.asarray(points_in_world, dtype=float).reshape(-1, 3)
        local = (pts - self.center_in_world) @ self.rotation_box_to_world
        return _signed_distance_of_excess(np.abs(local) - 0.5 * np.asarray(self.size, dtype=float))

    def surface(self, name: str) -> Surface:
        """The top face: the face whose outward normal points most upwards."""
        rot = self.rotation_box_to_world
        half = 0.5 * np.asarray(self.size, dtype=float)
        axis = int(np.argmax(np.abs(rot[2])))
        sign = 1.0 if rot[2, axis] > 0 else -1.0
        u, v = [k for k in range(3) if k != axis]
        corners = []
        for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            local = np.zeros(3)
            local[axis], local[u], local[v] = sign * half[axis], a * half[u], b * half[v]
            corners.append(self.center_in_world + rot @ local)
        normal = rot[:, axis] * sign
        pts = np.array(corners)
        if np.dot(np.cross(pts[1] - pts[0], pts[2] - pts[0]), normal) < 0:
            pts = pts[::-1]
        return Surface(pts, normal, name)


@dataclass(frozen=True, eq=False)
class Cylinder:
    """A vertical solid cylinder (a post, a stepping stone): centre (3,) in W [m] (the
    middle of its axis), ``radius`` and full ``height`` [m]."""

    center_in_world: np.ndarray
    radius: float
    height: float

    @property
    def top_z(self) -> float:
        """Height of the top face [m]."""
        return float(self.center_in_world[2] + 0.5 * self.height)

    def top_at(self, xy_in_world: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(z (N,) [m], normal (N, 3)): the top face over the disc, -inf / NaN elsewhere."""
        xy = np.asarray(xy_in_world, dtype=float).reshape(-1, 2)
        hit = np.hypot(*(xy - self.center_in_world[:2]).T) <= self.radius
        z = np.where(hit, self.top_z, -np.inf)
        normal = np.where(hit[:, None], np.array([0.0, 0.0, 1.0]), np.nan)
        return z, normal

    def signed_distance(self, points_in_world: np.ndarray) -> np.ndarray:
        """Signed distance [m] of points (N, 3) in W to the cylinder's surface, shape (N,):
        positive outside, negative inside (:meth:`Box.signed_distance` in the (radial, z)
        half-plane: q = (r - radius, |z - z_c| - height / 2))."""
        pts = np.asarray(points_in_world, dtype=float).reshape(-1, 3)
        rel = pts - self.center_in_world
        return _signed_distance_of_excess(
            np.column_stack(
                [
                    np.hypot(rel[:, 0], rel[:, 1]) - self.radius,
                    np.abs(rel[:, 2]) - 0.5 * self.height,
                ]
            )
        )

    def surface(self, name: str) -> Surface:
        """The top face as a regular CYLINDER_TOP_VERTICES-gon inscribed in the disc."""
        a = np.linspace(0.0, 2.0 * np.pi, CYLINDER_TOP_VERTICES, endpoint=False)
        cx, cy = self.center_in_world[:2]
        pts = np.column_stack(
            [
                cx + self.radius * np.cos(a),
                cy + self.radius * np.sin(a),
                np.full(len(a), self.top_z),
            ]
        )
        return Surface(pts, np.array([0.0, 0.0, 1.0]), name)
