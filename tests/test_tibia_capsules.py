"""The tibia capsule the physics replay collides, measured by the planner against a terrain
map (planner/terrain/capsule_distance.py, planner/trajectory/tibia_capsules.py), checked
three other ways: dense points along the axis (brute force), the exact distance of a line
to a box edge, and MuJoCo's own geom distance (mj_geomDistance) between the capsule it
builds and the block, on random go2 poses beside a block."""

from __future__ import annotations

import re

import numpy as np
import pytest

from planner.terrain.capsule_distance import (
    GOLDEN_TOLERANCE,
    capsule_clearance,
    capsule_clearance_by_part,
    segment_minimum,
)
from planner.terrain.heightmap import HeightMap
from planner.terrain.shapes import Box, Cylinder
from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.clearance import CAPSULE_POINTS, TIBIA_FOOT_GAP_M, sphere_clearance
from silo4sim.settings import SimSettings

BLOCK = Box(np.array([0.0, 0.5, 0.035]), np.array([1.0, 0.4, 0.07]))
#: Dense points along an axis for the brute force.
BRUTE_POINTS = 20_001


def _brute_minimum(distance, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Least value of ``distance`` over BRUTE_POINTS points of each segment, and the bound
    on its error (half the spacing: the signed distance is 1-Lipschitz)."""
    t = np.linspace(0.0, 1.0, BRUTE_POINTS)
    values = [distance(a + t[:, None] * (b - a)).min() for a, b in zip(start, end)]
    return np.array(values), np.linalg.norm(end - start, axis=1) / (2 * (BRUTE_POINTS - 1))


@pytest.mark.parametrize(
    "solid",
    [
        BLOCK,
        Box(np.array([0.1, 0.4, 0.05]), np.array([0.3, 0.2, 0.1]), np.array([10.0, -5.0, 30.0])),
        Cylinder(np.array([0.0, 0.5, 0.05]), 0.1, 0.1),
    ],
)
def test_segment_minimum_matches_dense_points(solid):
    """Golden-section search on the convex signed distance finds the least value along random
    segments (some crossing the solid, some beside it) to the brute force's error bound; and
    capsule_clearance (which searches a solid only where its Lipschitz bound allows it to
    be the nearest) equals the least of capsule_clearance_by_part."""
    rng = np.random.default_rng(3)
    start = rng.uniform([-0.4, 0.0, -0.05], [0.4, 1.0, 0.3], size=(300, 3))
    end = start + rng.uniform(-0.3, 0.3, size=(300, 3))
    got = segment_minimum(solid.signed_distance, start, end)
    brute, bound = _brute_minimum(solid.signed_distance, start, end)
    terrain = TerrainMap(floor_z=0.0, boxes=(BLOCK, solid) if solid is not BLOCK else (BLOCK,))
    np.testing.assert_array_equal(
        capsule_clearance(terrain, start, end, 0.01),
        capsule_clearance_by_part(terrain, start, end, 0.01).min(axis=0),
    )
    length = np.linalg.norm(end - start, axis=1)
    assert np.all(got <= brute + GOLDEN_TOLERANCE * length)  # the search's own bound
    assert np.all(brute - got <= bound + 1e-12)  # the dense points' bound


def test_capsule_crossing_a_block_edge_is_measured_to_the_edge():
    """A 0.2 m capsule sloping at 45 deg in the y-z plane passes over the block's top edge
    (the line y = 0.3, z = 0.07) with its axis d = 0.02 m from it: exact clearance d - r.
    Spheres at CAPSULE_POINTS points of the axis (clearance.py's insect measure) miss the
    nearest point of the axis, between two of them, and see more clearance than there is."""
    radius, d = 0.015, 0.02
    edge = np.array([0.0, 0.3, 0.07])
    unit = np.array([0.0, -1.0, -1.0]) / np.sqrt(2.0)  # down the slope, off the block (-y)
    normal = np.array([0.0, 1.0, -1.0]) / np.sqrt(2.0)  # from the axis towards the edge
    nearest = edge - d * normal  # the axis point nearest the edge
    offset = 0.011  # the nearest point lies between the 9 points of a 0.2 m axis
    start, end = nearest - (0.1 + offset) * unit, nearest + (0.1 - offset) * unit
    terrain = TerrainMap(floor_z=None, boxes=(BLOCK,))
    got = capsule_clearance(terrain, start[None], end[None], radius)[0]
    assert got == pytest.approx(d - radius, abs=1e-9)
    points = start + np.linspace(0.0, 1.0, CAPSULE_POINTS)[:, None] * (end - start)
    spheres = float(np.min(sphere_clearance(terrain, points, radius)))
    assert spheres > got + 1e-3


def test_floor_and_height_map_parts():
    """The floor is the lower end less the radius; a height map is the least of the sphere
    measure at points at most HEIGHTMAP_SPACING_M apart (here against 10x denser points)."""
    rng = np.random.default_rng(5)
    heights = rng.uniform(0.0, 0.03, size=(30, 30))
    terrain = TerrainMap(
        floor_z=-0.01, heightmap=HeightMap(heights, 0.02, np.array([-0.3, 0.0]), base_z=-0.01)
    )
    start = rng.uniform([-0.2, 0.1, 0.02], [0.2, 0.5, 0.1], size=(50, 3))
    end = start + rng.uniform(-0.1, 0.1, size=(50, 3))
    by_part = capsule_clearance_by_part(terrain, start, end, 0.01)
    assert terrain.part_names() == ["floor", "height map"]
    np.testing.assert_allclose(by_part[0], np.minimum(start[:, 2], end[:, 2]) + 0.01 - 0.01)
    alone = TerrainMap(floor_z=None, heightmap=terrain.heightmap)
    t = np.linspace(0.0, 1.0, 401)
    dense = np.array(
        [alone.sphere_clearance(a + t[:, None] * (b - a), 0.01).min() for a, b in zip(start, end)]
    )
    assert np.all(by_part[1] >= dense - 1e-12)
    # the sampled measure is within one spacing's rise of the dense one (slopes < 1.5)
    assert np.max(by_part[1] - dense) < 1.5 * 0.005


def test_gap_is_the_physics_models():
    assert SimSettings().tibia_clearance_m == TIBIA_FOOT_GAP_M


@pytest.mark.parametrize("robot_name", ["go2", None])
def test_capsule_clearance_equals_mujoco_geom_distance(robot_name):
    """On random poses of the robot beside a block (legs within their limits, body heights
    and headings random), the planner's clearance of each tibia capsule from the block equals
    MuJoCo's signed distance between the capsule geom it builds (silo4sim/model.py) and the
    block geom, posed by the same root pose."""
    mujoco = pytest.importorskip("mujoco")
    from planner.outputs.root_pose import root_pose_in_world
    from planner.trajectory.tibia_capsules import _BodyPose, posed_tibia_capsules
    from silo4kin import load_robot
    from silo4sim.model import build_sim_model

    robot = load_robot(robot_name)
    block = {"center": [0.0, 0.25, 0.05], "size": [1.0, 0.2, 0.1]}
    sim = build_sim_model(robot, SimSettings(), {"floor": 0.0, "boxes": [block]})
    model, data = sim.model, mujoco.MjData(sim.model)
    rng = np.random.default_rng(11)
    n = 40
    lower = np.concatenate([leg.q_lower for leg in robot.legs])
    upper = np.concatenate([leg.q_upper for leg in robot.legs])
    q = rng.uniform(lower, upper, size=(n, 12))
    base = np.column_stack(
        [rng.uniform(-0.1, 0.1, n), rng.uniform(0.0, 0.5, n), rng.uniform(0.15, 0.4, n)]
    )
    yaw = rng.uniform(-np.pi, np.pi, n)
    start, end, radius = posed_tibia_capsules(robot, q, base, yaw)
    box = Box(np.array(block["center"]), np.array(block["size"]))
    ours = capsule_clearance(
        TerrainMap(floor_z=None, boxes=(box,)),
        start.reshape(-1, 3),
        end.reshape(-1, 3),
        np.tile(radius, n),
    ).reshape(n, 4)
    # the sim's floor and boxes shift by its floor_z (0 for go2's ball feet, -r for SILO4)
    shift = float(model.geom("box0").pos[2]) - 0.05
    root = root_pose_in_world(_BodyPose(base, yaw), robot.position_body_com_in_base)
    box_id = model.geom("box0").id
    capsule_ids = [model.geom(f"{leg.name}_tibia_capsule").id for leg in robot.legs]
    theirs = np.empty((n, 4))
    for i in range(n):
        x, y, z, w = root.orientation_root_in_world_xyzw[i]
        data.qpos[:7] = [
            *root.position_root_in_world[i, :2],
            root.position_root_in_world[i, 2] + shift,
            w,
            x,
            y,
            z,
        ]
        data.qpos[sim.qpos_adr] = q[i]
        mujoco.mj_forward(model, data)
        for k, geom in enumerate(capsule_ids):
            theirs[i, k] = mujoco.mj_geomDistance(model, data, geom, box_id, 1.0, None)
    assert np.array_equal(ours < 0, theirs < 0)  # touch or not: the same answer
    # near the surface (the margins decided here) the same number; deeper in, MuJoCo's
    # penetration depth (the translation that separates) and the least signed distance of
    # the axis differ, and beyond 1 m mj_geomDistance answers its distmax
    near = (theirs > -0.005) & (theirs < 0.5)
    assert near.sum() > 20
    np.testing.assert_allclose(ours[near], theirs[near], atol=1e-6)


def test_insect_closed_form_capsule_equals_the_posed_physics_capsule(silo4):
    """SILO4's tibia clearance over a block (clearance.py: eq 3.5 closed form, the whole
    capsule measured) equals the clearance of the physics model's capsules posed by
    Pinocchio (tibia_capsules.py) on random level-body poses."""
    from dataclasses import dataclass

    @dataclass
    class Poses:  # the three Trajectory fields the clearance reads
        q: np.ndarray
        position_base_in_world: np.ndarray
        yaw_base_in_world: np.ndarray

        def __len__(self) -> int:
            return len(self.q)

    from planner.trajectory.clearance import trajectory_tibia_clearance
    from planner.trajectory.tibia_capsules import posed_tibia_capsules

    rng = np.random.default_rng(13)
    n = 200
    lower = np.concatenate([leg.q_lower for leg in silo4.legs])
    upper = np.concatenate([leg.q_upper for leg in silo4.legs])
    pose = Poses(
        q=rng.uniform(lower, upper, size=(n, 12)),
        position_base_in_world=np.column_stack(
            [rng.uniform(-0.2, 0.2, n), rng.uniform(0.0, 0.8, n), rng.uniform(0.1, 0.5, n)]
        ),
        yaw_base_in_world=rng.uniform(-np.pi, np.pi, n),
    )
    terrain = TerrainMap(floor_z=0.0, boxes=(BLOCK,))
    closed_form = trajectory_tibia_clearance(silo4.legs, pose, terrain)
    start, end, radius = posed_tibia_capsules(
        silo4, pose.q, pose.position_base_in_world, pose.yaw_base_in_world
    )
    posed = capsule_clearance(
        terrain, start.reshape(-1, 3), end.reshape(-1, 3), np.tile(radius, n)
    ).reshape(n, 4)
    np.testing.assert_allclose(closed_form, posed, atol=1e-9)


def test_a_link_touch_names_the_part_it_touches(silo4):
    """Over a terrain map with obstacles a non-foot shape's touch names the part nearest it:
    a platform under the whole of SILO4 (feet standing in it) raised 1 cm into its lowest
    non-foot shape is box 0, not "the ground" (which the line still says on flat ground)."""
    from planner.path.plan_path import plan_path
    from planner.trajectory.clearance import clearance_of_poses, ground_contact_violations

    trajectory = plan_path(silo4, np.array([[0.0, 0.3]]), 0.4, start_heading=np.pi / 2).trajectory
    x, y, _ = trajectory.position_base_in_world[0]
    side = np.array([3.0, 3.0])  # a platform under the whole robot
    probe = TerrainMap(floor_z=None, boxes=(Box(np.array([x, y, -0.5]), np.array([*side, 1.0])),))
    lowest = clearance_of_poses(
        silo4,
        trajectory.q,
        trajectory.position_base_in_world,
        trajectory.yaw_base_in_world,
        probe,
    ).min()  # how far the robot comes to a platform topped at z = 0
    top = lowest + 0.01  # the platform raised 1 cm into it
    post = Box(np.array([x, y, 0.5 * top]), np.array([*side, top]))
    terrain = TerrainMap(floor_z=0.0, boxes=(post,), name="posts.yaml")
    line = ground_contact_violations(silo4, trajectory, terrain, (0.0,))[0]
    assert line is not None
    assert re.search(
        r"^link \w+ comes -[\d.]+ mm above box 0 of terrain file posts.yaml at t = ", line
    )
    flat = ground_contact_violations(silo4, trajectory, None, (1.0,))[0]
    assert flat is not None and "above the ground at t = " in flat


def test_go2_on_a_007_m_block_is_refused_naming_the_calf_and_the_block(go2, monkeypatch):
    """Issue 22: go2 at h 0.28 m on bench_capability.py's 0.07 m block planned a walk whose
    RL_calf capsule lay on the block's far top edge in MuJoCo (LH stepping down to the floor
    0.104 m past it); the run is refused naming the leg, its calf and box 0. The foothold
    search now moves that foothold until the capsule clears (tests/test_shank_footholds.py),
    so the run's own check is shown here on the plan the search made without the shank."""
    import planner.gaits.walk
    from planner.errors import PlanningError
    from planner.outputs.pipeline import RunRequest, plan_run
    from planner.terrain import terrain_from_document

    # the walk's shank search left out (called per plan, outside every memo on the robot)
    monkeypatch.setattr(planner.gaits.walk, "shank_clearance_for", lambda *args: None)
    robot = go2
    block = {"center": [0.0, 0.71222, 0.035], "size": [0.917, 0.4602, 0.07]}
    terrain = terrain_from_document({"floor": 0.0, "boxes": [block]}, name="block7.json")
    with pytest.raises(
        PlanningError,
        match=r"terrain file block7.json: the tibia of LH \(RL_calf, the physics model's "
        r"capsule\) comes within 2 mm of box 0 at t = [\d.]+ units \(swing\), least -[\d.]+ mm",
    ):
        plan_run(
            robot,
            np.array([[0.0, 1.3522]]),
            0.28,
            RunRequest(),
            start_heading=np.pi / 2,
            terrain=terrain,
        )
