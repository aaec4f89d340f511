"""Motor torque and speed through the gearbox (eq A.35-A.36) and the sizing table."""

from __future__ import annotations

import json

import numpy as np
import pytest

from silo4kin.errors import Silo4Error
from silo4kin.motor_table import read_motor_table
from silo4kin.motors import (
    ASSUMED_SOURCE,
    DEFAULT_GEAR_EFFICIENCY,
    DEFAULT_GEAR_RATIO,
    Gearing,
    format_sizing_table,
    motor_speed,
    motor_torque,
    sizing_table,
)

#: Time-weighted RMS of a sampled sine vs A/sqrt(2): trapezoid error ~ (w dt)^2 / 12 relative
#: with w dt = 2 pi / 2000, ~ 1e-6; over whole periods it is smaller still. 1e-5 is safe.
RMS_TOLERANCE = 1e-5
NAMES = ["a", "b", "c"]


def test_eq_a35_a36():
    """tau_m = tau_j / (mu eta), omega_m = mu omega_j, per joint column."""
    g = Gearing(np.array([100.0, 50.0, 10.0]), np.array([0.7, 0.5, 1.0]))
    tau = np.array([[7.0, -5.0, 3.0]])
    assert np.allclose(motor_torque(tau, g), [[0.1, -0.2, 0.3]], rtol=1e-15, atol=0)
    assert np.allclose(
        motor_speed(np.array([[0.1, -0.2, 0.3]]), g), [[10.0, -10.0, 3.0]], rtol=1e-15, atol=0
    )


def test_sizing_table_of_sines():
    """Peak and RMS of tau = A sin(w t) over whole periods are A and A/sqrt(2); peak power of
    tau * qd with qd = B cos(w t) is A B / 2."""
    t = np.linspace(0.0, 2.0, 4001)
    w = 2 * np.pi
    amp = np.array([10.0, 20.0, 30.0])
    tau = amp * np.sin(w * t)[:, None]
    qd = 0.5 * np.cos(w * t)[:, None] * np.ones(3)
    rows = sizing_table(NAMES, tau, qd, Gearing.uniform(3, 50.0, 0.8), t=t)
    for row, a in zip(rows, amp):
        assert abs(row["joint_torque_peak_Nm"] - a) < 1e-9 * a
        assert abs(row["joint_torque_rms_Nm"] - a / np.sqrt(2)) < RMS_TOLERANCE * a
        assert abs(row["motor_torque_peak_Nm"] - a / 40.0) < 1e-9 * a
        assert abs(row["motor_speed_peak_rad_s"] - 25.0) < 1e-9
        assert abs(row["motor_speed_peak_rpm"] - 25.0 * 30 / np.pi) < 1e-9
        assert abs(row["joint_power_peak_W"] - a * 0.25) < 1e-5 * a
        assert abs(row["motor_power_peak_W"] - a * 0.25 / 0.8) < 1e-5 * a
    json.dumps(rows)  # JSON-able as it is


def test_defaults_are_documented_constants():
    rows = sizing_table(NAMES, np.ones((2, 3)), np.zeros((2, 3)))
    assert all(r["gear_ratio"] == DEFAULT_GEAR_RATIO for r in rows)
    assert all(r["gear_efficiency"] == DEFAULT_GEAR_EFFICIENCY for r in rows)


def test_format_lists_every_joint():
    rows = sizing_table(NAMES, np.ones((2, 3)), np.zeros((2, 3)))
    text = format_sizing_table(rows)
    lines = text.splitlines()
    assert lines[0].split()[0] == "joint" and len(lines) == 6  # + units, + assumed gearing
    assert [ln.split()[0] for ln in lines[1:4]] == NAMES


@pytest.mark.parametrize(
    "ratio, eff, match",
    [
        (0.0, 0.7, "gear ratio 0.0 .* must be > 0"),
        (-5.0, 0.7, "gear ratio -5.0 .* must be > 0"),
        (100.0, 0.0, r"gear efficiency 0.0 .* must be in \(0, 1\]"),
        (100.0, 1.2, r"gear efficiency 1.2 .* must be in \(0, 1\]"),
        (100.0, np.nan, "gear efficiency nan"),
    ],
)
def test_bad_gearing(ratio, eff, match):
    with pytest.raises(Silo4Error, match=match):
        Gearing.uniform(12, ratio, eff)


def test_bad_table_shapes():
    with pytest.raises(Silo4Error, match="must both be"):
        sizing_table(NAMES, np.ones((2, 3)), np.ones((2, 4)))
    with pytest.raises(Silo4Error, match="gearing has 12 joints, expected 3"):
        sizing_table(NAMES, np.ones((2, 3)), np.ones((2, 3)), Gearing.uniform(12))


GO2 = [f"{leg}_{j}_joint" for leg in ("FL", "FR", "RL", "RR") for j in ("hip", "thigh", "calf")]


def test_gearing_says_where_it_comes_from():
    """SILO4's defaults are marked assumed on every row, in the table and its text; numbers
    the caller gives are marked given."""
    rows = sizing_table(NAMES, np.ones((2, 3)), np.zeros((2, 3)))
    assert {r["gearing_source"] for r in rows} == {ASSUMED_SOURCE}
    assert "assumed (SILO4's defaults)" in format_sizing_table(rows).splitlines()[-1]
    given = sizing_table(NAMES, np.ones((2, 3)), np.zeros((2, 3)), Gearing.uniform(3, 6.0, 0.9))
    assert {r["gearing_source"] for r in given} == {"given"}
    assert "assumed" not in format_sizing_table(given)


def test_urdf_limits_beside_the_peaks():
    """With the URDF's limits, each row has them and the peaks over them (0 without one)."""
    tau = np.array([[1.0, -4.0, 2.0], [0.5, 2.0, -1.0]])
    qd = np.array([[1.0, 0.0, 3.0], [-2.0, 1.0, 0.0]])
    rows = sizing_table(
        NAMES, tau, qd, urdf_limits=(np.array([4.0, 2.0, 0.0]), np.array([2.0, 8.0, 4.0]))
    )
    assert [r["effort_use"] for r in rows] == [0.5, 0.5, 0.5]
    assert [r["speed_use"] for r in rows] == [0.5, 0.5, 0.0]
    assert rows[1]["urdf_effort_limit_Nm"] == 8.0 and rows[0]["urdf_velocity_limit_rad_s"] == 4.0
    assert "tau/lim" in format_sizing_table(rows).splitlines()[0]


def test_motor_table_by_type_joint_and_default(tmp_path):
    """A joint's own entry beats its type's, which beats the top-level value."""
    path = tmp_path / "go2.json"
    path.write_text(
        json.dumps(
            {
                "gear_ratio": 6.33,
                "gear_efficiency": 0.9,
                "joints": {"calf": {"gear_ratio": 10.0}, "FL_calf_joint": {"gear_efficiency": 0.8}},
            }
        )
    )
    gearing = read_motor_table(path, GO2)
    assert gearing.ratio.tolist() == [6.33, 6.33, 10.0] * 4
    assert gearing.efficiency.tolist() == [0.9, 0.9, 0.8] + [0.9] * 9
    assert set(gearing.source) == {"motors file go2.json"} and not gearing.assumed


@pytest.mark.parametrize(
    "table, match",
    [
        ({"joints": {"calf": {"gear_ratio": 10.0}}}, "no gear ratio mu .* 'FL_hip_joint'"),
        (
            {"gear_ratio": 6.0, "gear_efficiency": 0.9, "joints": {"elbow": {"gear_ratio": 1.0}}},
            "'elbow' matches no joint",
        ),
        ({"gear_ratio": 6.0, "gear_efficiency": 1.5}, r"gear efficiency 1.5 .* \(0, 1\]"),
        ({"gear_ratio": "six", "gear_efficiency": 0.9}, "gear_ratio 'six' is not a number"),
        ({"ratio": 6.0}, "unknown keys"),
        ([1, 2], "is a mapping"),
    ],
)
def test_bad_motor_tables(tmp_path, table, match):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(table))
    with pytest.raises(Silo4Error, match=match):
        read_motor_table(path, GO2)


def test_unreadable_motor_table(tmp_path):
    with pytest.raises(Silo4Error, match="cannot read motor table"):
        read_motor_table(tmp_path / "missing.json", GO2)
    (tmp_path / "x.json").write_text("{not json")
    with pytest.raises(Silo4Error, match="not a motor table"):
        read_motor_table(tmp_path / "x.json", GO2)


def test_gearing_from_options(tmp_path):
    """A motors file wins over the uniform options; without one the options are used."""
    from silo4kin.motor_table import gearing_from_options

    path = tmp_path / "m.json"
    path.write_text(json.dumps({"gear_ratio": 9.0, "gear_efficiency": 0.95}))
    assert gearing_from_options(GO2, 100.0, 0.7, path).ratio.tolist() == [9.0] * 12
    uniform = gearing_from_options(GO2, 100.0, 0.7)
    assert uniform.assumed and uniform.ratio.tolist() == [100.0] * 12
