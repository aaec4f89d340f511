"""The ground of a terrain map (planner/terrain/terrain_map.py, shapes.py, heightmap.py)
against hand computations: a box's top, a rotated ramp's normal, a cylinder's top, height
map values, surfaces, clearances, footholds and what today's gaits may walk."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.terrain import (
    FlatGround,
    ForbiddenPolygons,
    TerrainNotWalkableError,
    terrain_from_document,
)

#: Exact up to rounding of a few flops on numbers of order 1 [m].
TOL_M = 1e-12


def test_a_box_top_is_its_centre_plus_half_its_height_over_its_footprint():
    """An axis-aligned box: height center_z + size_z / 2 over x0 +- sx/2, y0 +- sy/2, normal
    +z; the floor beside it."""
    t = terrain_from_document({"boxes": [{"center": [1.0, 0.0, 0.04], "size": [0.4, 1.0, 0.08]}]})
    xy = np.array([[1.0, 0.0], [0.81, 0.49], [1.19, -0.49], [0.79, 0.0], [1.0, 0.51]])
    np.testing.assert_allclose(t.height_at(xy), [0.08, 0.08, 0.08, 0.0, 0.0], rtol=0, atol=TOL_M)
    np.testing.assert_allclose(t.normal_at(xy), np.tile([0, 0, 1.0], (5, 1)), rtol=0, atol=TOL_M)


def test_a_rotated_ramp_has_the_tilted_normal_and_the_plane_height():
    """A plank rolled 6 deg about x then turned 30 deg about z (rpy = (6, 0, 30) deg): the
    top's normal is R_z(30) R_x(6) e_z = (sin6 sin30, -sin6 cos30, cos6), and the height at
    xy on it is the plane through the top face's centre c + (t/2) n: z = z_c' - (n_x (x -
    x_c') + n_y (y - y_c')) / n_z."""
    a, yaw, thick = math.radians(6.0), math.radians(30.0), 0.02
    t = terrain_from_document(
        {"boxes": [{"center": [0.0, 2.0, 0.1], "size": [1.2, 2.0, thick], "rpy": [6, 0, 30]}]}
    )
    n = np.array([math.sin(a) * math.sin(yaw), -math.sin(a) * math.cos(yaw), math.cos(a)])
    top_centre = np.array([0.0, 2.0, 0.1]) + 0.5 * thick * n
    xy = np.array([[0.0, 2.0], [0.2, 2.3], [-0.3, 1.6]])
    z = (
        top_centre[2]
        - (n[0] * (xy[:, 0] - top_centre[0]) + n[1] * (xy[:, 1] - top_centre[1])) / n[2]
    )
    np.testing.assert_allclose(t.height_at(xy), z, rtol=0, atol=TOL_M)
    np.testing.assert_allclose(t.normal_at(xy), np.tile(n, (3, 1)), rtol=0, atol=TOL_M)


def test_a_cylinder_top_is_flat_over_its_disc():
    """A post: height center_z + height/2 within the radius, the floor outside."""
    t = terrain_from_document(
        {"cylinders": [{"center": [2.0, 0.3, 0.1], "radius": 0.08, "height": 0.2}]}
    )
    xy = np.array([[2.0, 0.3], [2.0 + 0.079, 0.3], [2.0, 0.3 - 0.0799], [2.06, 0.36], [2.0, 0.39]])
    np.testing.assert_allclose(t.height_at(xy), [0.2, 0.2, 0.2, 0.0, 0.0], rtol=0, atol=TOL_M)


def test_heightmap_values_at_samples_on_edges_and_inside_a_square():
    """At a sample: its height plus the floor; on a grid square's edge: the linear (there
    equal to the bilinear) interpolation of the edge's two samples; inside: the plane of the
    square's triangle split along the (c, r)-(c+1, r+1) diagonal."""
    heights = [[0.0, 0.1, 0.0], [0.2, 0.4, 0.1]]  # rows along y, columns along x
    t = terrain_from_document(
        {"floor": 0.5, "heightmap": {"heights": heights, "resolution": 0.1, "origin": [1.0, 2.0]}}
    )
    h = np.array(heights)

    def bilinear(x, y):
        u, v = (x - 1.0) / 0.1, (y - 2.0) / 0.1
        c, r = min(int(u), 1), min(int(v), 0)
        u, v = u - c, v - r
        return 0.5 + (
            h[r, c] * (1 - u) * (1 - v)
            + h[r, c + 1] * u * (1 - v)
            + h[r + 1, c] * (1 - u) * v
            + h[r + 1, c + 1] * u * v
        )

    samples = [(1.0, 2.0), (1.1, 2.0), (1.2, 2.1), (1.1, 2.1)]
    edges = [(1.05, 2.0), (1.0, 2.03), (1.13, 2.1), (1.2, 2.07), (1.1, 2.02)]
    for x, y in samples + edges:
        assert t.height_at(np.array([[x, y]]))[0] == pytest.approx(bilinear(x, y), abs=TOL_M)
    # inside the first square: (u, v) = (0.7, 0.2) lies below the diagonal, in the triangle
    # (0,0), (1,0), (1,1): z = h00 + u (h10 - h00) + v (h11 - h10)
    z_low = 0.5 + 0.0 + 0.7 * 0.1 + 0.2 * (0.4 - 0.1)
    # (u, v) = (0.2, 0.7) above it, in (0,0), (1,1), (0,1): z = h00 + u (h11 - h01) + v (h01 - h00)
    z_up = 0.5 + 0.0 + 0.2 * (0.4 - 0.2) + 0.7 * 0.2
    got = t.height_at(np.array([[1.07, 2.02], [1.02, 2.07]]))
    np.testing.assert_allclose(got, [z_low, z_up], rtol=0, atol=TOL_M)
    # the lower triangle's normal: (-dz/dx, -dz/dy, 1) normalised, dz/dx = 1, dz/dy = 3
    normal = np.array([-1.0, -3.0, 1.0]) / math.sqrt(11.0)
    np.testing.assert_allclose(t.normal_at(np.array([[1.07, 2.02]]))[0], normal, atol=TOL_M)
    # outside the grid: the floor
    assert t.height_at(np.array([[0.99, 2.0], [1.0, 2.11]])).tolist() == [0.5, 0.5]


def test_no_floor_is_a_void_between_the_solids():
    """floor: null: -inf height and NaN normal where no solid is, no foothold allowed
    there, +inf clearance above it."""
    t = terrain_from_document(
        {"floor": None, "boxes": [{"center": [0, 0, -0.25], "size": [1, 1, 0.5]}]}
    )
    xy = np.array([[0.0, 0.0], [2.0, 0.0]])
    assert t.height_at(xy).tolist() == [0.0, -np.inf]
    assert np.isnan(t.normal_at(xy)[1]).all()
    assert t.allows_footholds(xy).tolist() == [True, False]
    assert t.lowest_clearance(np.array([[0, 0, 0.1], [2, 0, 0.1]])).tolist() == [0.1, np.inf]


def test_lowest_clearance_is_the_height_above_the_highest_top():
    """A point's clearance is its z minus the top under it: negative inside a box."""
    t = terrain_from_document({"boxes": [{"center": [0, 0, 0.1], "size": [1, 1, 0.2]}]})
    pts = np.array([[0.0, 0.0, 0.25], [0.0, 0.0, 0.15], [3.0, 0.0, 0.05]])
    np.testing.assert_allclose(t.lowest_clearance(pts), [0.05, -0.05, 0.05], atol=TOL_M)


def test_surfaces_are_the_top_faces_with_their_normals():
    """The floor, each box's top (its 4 corners at the top's height, counter-clockwise
    about the normal) and each cylinder's top polygon, every vertex on the ground."""
    t = terrain_from_document(
        {
            "boxes": [{"center": [0, 2, 0.1], "size": [1.2, 2, 0.02], "rpy": [6, 0, 0]}],
            "cylinders": [{"center": [2, 0.3, 0.1], "radius": 0.08, "height": 0.2}],
        }
    )
    floor, box, cylinder = t.surfaces()
    assert (floor.name, box.name, cylinder.name) == ("floor", "box 0", "cylinder 0")
    assert len(box.vertices_in_world) == 4
    a = math.radians(6.0)
    np.testing.assert_allclose(box.normal_in_world, [0, -math.sin(a), math.cos(a)], atol=TOL_M)
    turn = np.cross(
        box.vertices_in_world[1] - box.vertices_in_world[0],
        box.vertices_in_world[2] - box.vertices_in_world[1],
    )
    assert np.dot(turn, box.normal_in_world) > 0
    # the top face's corners lie on the box's top (shrunk 1 um inward to stay on it)
    inner = box.vertices_in_world + 1e-6 * (
        box.vertices_in_world.mean(axis=0) - box.vertices_in_world
    )
    np.testing.assert_allclose(t.height_at(inner[:, :2]), inner[:, 2], atol=1e-9)
    assert np.all(cylinder.vertices_in_world[:, 2] == 0.2)


def test_forbidden_polygons_refuse_footholds_as_forbidden_polygons_do():
    """A terrain map's footholds are refused exactly where ForbiddenPolygons with the same
    polygons and clearance refuses them (one implementation: the map asks it)."""
    strip = [[1.5, -1.0], [1.75, -1.0], [1.75, 1.0], [1.5, 1.0]]
    t = terrain_from_document({"forbidden": [strip]})
    same = ForbiddenPolygons((np.array(strip),), clearance_m=t.forbidden_clearance_m)
    pts = np.random.default_rng(0).uniform([1.3, -1.2, 0.0], [2.0, 1.2, 0.0], size=(400, 3))
    assert t.allows_footholds(pts).tolist() == [same.allows_foothold(p) for p in pts]
    assert not all(same.allows_foothold(p) for p in pts)  # the sample reaches into the strip


def test_level_terrain_is_the_flat_floor_or_refused_naming_the_obstacles():
    """Only forbidden polygons on a floor: FlatGround / ForbiddenPolygons at the floor's
    height; boxes, cylinders, a height map or no floor: one line naming them and what is
    not built yet."""
    flat = terrain_from_document({"floor": 0.2}).level_terrain()
    assert isinstance(flat, FlatGround) and flat.z == 0.2
    strip = terrain_from_document({"forbidden": [[[0, 0], [1, 0], [1, 1]]]}).level_terrain()
    assert isinstance(strip, ForbiddenPolygons)
    cases = [
        ({"boxes": [{"center": [0, 0, 0], "size": [1, 1, 1]}]}, "1 box"),
        ({"cylinders": [{"center": [0, 0, 0], "radius": 1, "height": 1}] * 2}, "2 cylinders"),
        (
            {"heightmap": {"heights": [[0, 0], [0, 0]], "resolution": 1, "origin": [0, 0]}},
            "a height map",
        ),
        ({"floor": None}, "no floor"),
    ]
    for document, named in cases:
        with pytest.raises(TerrainNotWalkableError) as info:
            terrain_from_document(document, name="t.yaml").level_terrain()
        message = str(info.value)
        assert named in message and "not built yet" in message and "\n" not in message


def test_vectorised_clearances_are_the_scalar_clearance_bit_for_bit():
    """ForbiddenPolygons.clearances (what a terrain map asks) gives exactly the numbers of
    ForbiddenPolygons.clearance (what the step builder asks), on random points and on
    points rounded onto a polygon's edges."""
    rng = np.random.default_rng(7)
    polygons = (
        np.array([[1.5, -1.0], [1.75, -1.0], [1.75, 1.0], [1.5, 1.0]]),
        np.array([[0.0, 0.0], [0.4, 0.1], [0.3, 0.5], [-0.1, 0.3]]),
    )
    terrain = ForbiddenPolygons(polygons, clearance_m=0.01)
    pts = np.vstack([rng.uniform(-0.5, 2.0, size=(300, 2)), [[1.5, 0.2], [1.75, -1.0]]])
    scalar = np.array([terrain.clearance(p) for p in pts])
    assert np.array_equal(terrain.clearances(pts), scalar)
    assert np.array_equal(ForbiddenPolygons(()).clearances(pts), np.full(len(pts), np.inf))


def test_a_stance_out_of_reach_on_level_feet_names_each_leg_once():
    """Feet at one height have no highest and lowest foot: the refusal says they stand level
    (it named the first leg twice: 'leg LF on box 0 at z = 0 m, leg LF on box 0 ...'); feet
    at two heights name the highest and the lowest."""
    from planner.terrain.refusals import stance_out_of_reach

    box = {"center": [0, 0, -0.25], "size": [3, 3, 0.5]}
    terrain = terrain_from_document({"floor": None, "boxes": [box]})
    legs = ("LF", "RF", "LH", "RH")
    feet = np.array([[0.3, 0.2, 0.0], [0.3, -0.2, 0.0], [-0.3, 0.2, 0.0], [-0.3, -0.2, 0.0]])
    level = stance_out_of_reach(terrain, feet, 0.28, 1, legs)
    assert "leg RF's foot on box 0 is out of reach" in level
    assert level.endswith("the feet stand level at z = 0 m") and "leg LF" not in level
    feet[2, 2] = -0.1  # LH lower, over the same box's side: named as the lowest
    uneven = stance_out_of_reach(terrain, feet, 0.28, 1, legs)
    assert "the feet span 0.1 m in height, leg LF" in uneven and "leg LH" in uneven
