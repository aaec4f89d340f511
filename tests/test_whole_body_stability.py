"""Whole-body stability of the written plans (issue 9): the CoM recomputed by Pinocchio from
trajectory.csv, the feet by Pinocchio's forward kinematics, the margin by the reference
support_margin (planner/stability/margin.py), independently of the planner's own numbers."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from planner.outputs.export import read_trajectory_csv, write_trajectory_csv
from planner.path.metrics import compute_metrics
from planner.path.plan_path import plan_path
from planner.stability.margin import support_margin
from planner.studies.cases import path_waypoints
from silo4kin.joint_torques import free_flyer_q_index

#: Default stability threshold [m] (issue 9: >= 0.02 m whenever a leg is up).
THRESHOLD_M = 0.02
#: CSV numbers carry 10 significant digits: positions of ~5 m are exact to ~1e-9 m.
CSV_ROUNDING_M = 1e-8
#: Samples per unit of these plans: the step check does not depend on it; 50 keeps the
#: per-sample Pinocchio loop below a second per case.
SAMPLES_PER_UNIT = 50


def pinocchio_margins(robot, csv: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(S_m of the whole-robot CoM, leg-up mask) of every CSV row: base pose and joints into
    the free-flyer model (the URDF root sits at the CoG for SILO4), pin.centerOfMass, feet by
    pin.framesForwardKinematics, contacts from the CSV."""
    model = robot.model_free_flyer
    data = model.createData()
    idx = free_flyer_q_index(robot)
    q_cols = np.stack([csv[f"q_{name}"] for name in robot.joint_names], axis=1)
    contact = np.stack([csv[f"contact_{leg.name}"] for leg in robot.legs], axis=1)
    feet_ids = [model.getFrameId(leg.foot_frame) for leg in robot.legs]
    n = len(csv["t"])
    com = np.empty((n, 2))
    feet = np.empty((n, 4, 2))
    for i in range(n):
        q = np.zeros(model.nq)
        q[:3] = csv["base_x"][i], csv["base_y"][i], csv["base_z"][i]
        yaw = csv["base_yaw"][i]
        q[3:7] = 0.0, 0.0, np.sin(yaw / 2), np.cos(yaw / 2)  # (x, y, z, w)
        q[idx] = q_cols[i]
        com[i] = pin.centerOfMass(model, data, q)[:2]
        pin.framesForwardKinematics(model, data, q)
        feet[i] = [data.oMf[f].translation[:2] for f in feet_ids]
    return support_margin(feet, contact, com), ~contact.all(axis=1)


@pytest.mark.parametrize("path", ["straight", "circle"])
@pytest.mark.parametrize("height", [0.2, 0.4, 0.6])
def test_default_plans_keep_the_whole_body_com_inside(silo4, tmp_path, path, height):
    """Default preset, thesis paths: with a leg up, the whole-robot CoM is >= 0.02 m inside
    the support triangle at every written sample, and the CSV's margin_com is that margin."""
    wp, tol = path_waypoints(path)
    plan = plan_path(silo4, wp, height, tolerance=tol, samples_per_unit=SAMPLES_PER_UNIT)
    write_trajectory_csv(tmp_path / "trajectory.csv", plan.trajectory)
    csv = read_trajectory_csv(tmp_path / "trajectory.csv")
    margin, up = pinocchio_margins(silo4, csv)
    print(f"{path} h = {height}: min whole-body margin with a leg up {margin[up].min():.4f} m")
    assert margin[up].min() >= THRESHOLD_M - CSV_ROUNDING_M
    np.testing.assert_allclose(csv["margin_com"], margin, atol=CSV_ROUNDING_M)
    np.testing.assert_array_equal(csv["margin"], csv["margin_com"])
    assert compute_metrics(plan)["warnings"] == []


def test_thesis_preset_warns_where_the_com_leaves_the_polygon(silo4, tmp_path):
    """The thesis preset keeps the body CoG inside (its margin column is margin_body) and
    reports where the whole-robot CoM leaves the support polygon: the same sample and margin
    as Pinocchio's CoM from the CSV."""
    wp, _ = path_waypoints("straight")
    plan = plan_path(silo4, wp, 0.6, workspace="thesis", samples_per_unit=SAMPLES_PER_UNIT)
    write_trajectory_csv(tmp_path / "trajectory.csv", plan.trajectory)
    csv = read_trajectory_csv(tmp_path / "trajectory.csv")
    margin, up = pinocchio_margins(silo4, csv)
    np.testing.assert_array_equal(csv["margin"], csv["margin_body"])
    assert csv["margin_body"][up].min() >= -1e-9
    m = compute_metrics(plan)
    worst = m["com_outside_support"]
    assert worst is not None and len(m["warnings"]) == 1
    # the worst sample: the plan's and Pinocchio's margins agree there, and no sample is
    # worse by more than the CSV's rounding (two spins can tie to the last bits)
    i = worst["sample"]
    assert up[i] and abs(worst["margin_com_m"] - margin[i]) < CSV_ROUNDING_M
    assert np.where(up, margin, np.inf).min() > margin[i] - CSV_ROUNDING_M
    # issue 9: millimetres outside at 0.6 m (the thesis's body CoG on an edge while a leg of
    # ~3 kg swings); at 0.2 m that depends on the machine (docs/results.md)
    assert -0.01 < worst["margin_com_m"] < -0.002
    assert f"sample {i}" in m["warnings"][0]
