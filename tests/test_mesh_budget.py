"""The robot's meshes in animation.html: whole when they fit MESH_BUDGET_BYTES, simplified when
they do not, a stick figure only when no simplification fits; the page and the terminal say
which (viz/animation/mesh_budget.py)."""

from __future__ import annotations

import numpy as np
import pytest
import umsgpack

from silo4kin import Robot
from viz.animation.mesh_budget import (
    MESH_BUDGET_BYTES,
    STL_HEADER_BYTES,
    STL_TRIANGLE_BYTES,
    MeshesSimplified,
    _decimate,
    _stl_bytes,
    fit_meshes,
    mesh_bytes,
)
from viz.animation.page import MAX_HTML_BYTES, build_scene, render_animation_page

pytest.importorskip("example_robot_data")


@pytest.fixture(scope="module")
def go2_trajectory(go2: Robot):
    from planner.path.plan_path import plan_path

    return plan_path(go2, np.array([[0.0, 0.2]]), 0.28, samples_per_unit=10).trajectory


def _mesh_geometries(rec) -> list[dict]:
    objects = [umsgpack.unpackb(b) for b in rec.commands()]
    return [
        g
        for c in objects
        if c["type"] == "set_object"
        for g in c["object"].get("geometries", ())
        if g.get("type") == "_meshfile_geometry"
    ]


def test_go2_page_has_simplified_meshes_under_the_budget(go2, go2_trajectory) -> None:
    """go2's meshes exceed the budget as files; simplified they fit it, no stick figure is
    drawn, the page stays under its budget and its legend says how much was kept."""
    assert mesh_bytes(go2) > MESH_BUDGET_BYTES
    meshes = fit_meshes(go2)
    assert not meshes.stick_figure and 0.0 < meshes.kept_fraction < 1.0
    assert sum(len(b) for b in meshes.stl.values()) <= MESH_BUDGET_BYTES
    rec, _ = build_scene(go2, go2_trajectory, meshes=meshes)
    embedded = _mesh_geometries(rec)
    assert len(embedded) == len(meshes.stl) and {g["format"] for g in embedded} == {"stl"}
    assert sum(len(g["data"].data) for g in embedded) <= MESH_BUDGET_BYTES
    with pytest.warns(MeshesSimplified, match="simplified to"):
        page = render_animation_page(go2, go2_trajectory)
    assert len(page.encode("utf-8")) <= MAX_HTML_BYTES
    assert f"Meshes simplified to {100 * meshes.kept_fraction:.0f} % of their triangles" in page
    assert "stick_" not in page


def test_too_small_a_budget_draws_a_stick_figure_and_says_so(go2, go2_trajectory) -> None:
    meshes = fit_meshes(go2, budget_bytes=2_000)
    assert meshes.stick_figure and meshes.note is not None
    assert meshes.note.startswith("Stick figure")
    rec, _ = build_scene(go2, go2_trajectory, meshes=meshes)
    assert not _mesh_geometries(rec)


def test_silo4_primitives_are_unchanged(silo4: Robot) -> None:
    """SILO4 has no meshes: nothing to fit, no note on its page."""
    meshes = fit_meshes(silo4)
    assert meshes.note is None and not meshes.stl and not meshes.stick_figure


def test_decimation_keeps_at_most_the_fraction_and_writes_binary_stl() -> None:
    """A sphere of 2 x 40 x 40 triangles, clustered to a quarter of them; the STL has the
    header, the count and 50 bytes per triangle."""
    u, v = np.meshgrid(np.linspace(0.0, np.pi, 41), np.linspace(0.0, 2 * np.pi, 41))
    points = np.column_stack(
        [
            np.sin(u).ravel() * np.cos(v).ravel(),
            np.sin(u).ravel() * np.sin(v).ravel(),
            np.cos(u).ravel(),
        ]
    )
    grid = np.arange(41 * 41).reshape(41, 41)
    a, b, c, d = grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]
    faces = np.concatenate(
        [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )
    points_out, faces_out = _decimate(points, faces, 0.25)
    assert 0 < len(faces_out) <= 0.25 * len(faces)
    assert faces_out.max() < len(points_out)
    stl = _stl_bytes(points_out, faces_out)
    assert len(stl) == STL_HEADER_BYTES + STL_TRIANGLE_BYTES * len(faces_out)
    assert int(np.frombuffer(stl[80:84], dtype="<u4")[0]) == len(faces_out)


def test_simplified_meshes_keep_every_part_of_their_file(go2) -> None:
    """go2's thigh.dae has two parts (the hip end and the long shank); the simplified STL spans
    the whole file's bounding box, within 5 mm (coal's triangles of it reach only the
    first part)."""
    import trimesh

    meshes = fit_meshes(go2)
    geom = next(g for g in go2.visual_model.geometryObjects if g.name == "FL_thigh_0")
    bounds = trimesh.load(geom.meshPath, force="mesh", process=False).bounds
    stl = np.frombuffer(
        meshes.stl[geom.name][STL_HEADER_BYTES:],
        dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")],
    )
    corners = stl["v"].reshape(-1, 3)
    np.testing.assert_allclose([corners.min(axis=0), corners.max(axis=0)], bounds, atol=5e-3)
