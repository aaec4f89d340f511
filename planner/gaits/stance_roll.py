"""How far a ball foot's contact point travels over one stance, for the foothold rules that
must hold along it (planner/gaits/surface_footholds.py; docs/terrain.md, "Footholds on
surfaces").

A ball of rolling radius r on the foot link rolls without slipping while the body moves
over it (docs/physics.md, round feet): its centre, and the contact point under it, travel
r |ω_h| per unit of the foot link's rotation rate ω about horizontal axes. Over a stance the
foot sweeps its stroke relative to the hip: from λ/2 ahead of position 2 to λ/2 behind it
along the body x axis (λ the stride), or across it (the lateral stride) for the
omnidirectional gait's sideways steps, and the body's stability shifts add up to the
workspace's reserve SHIFT_RESERVE_M at each end. :func:`stance_roll_bound_m` integrates
r |ω_h| along each leg's stroke with the closed-form IK and its Jacobian (the same ω as the
sampler's rolling pass, planner/trajectory/rolling_feet.py) and returns the largest: go2 at
h 0.28 m 29.5 mm (its plans on examples/terrain rolled 22-25.2 mm in a stance), solo12 at
0.237 m 27.3 mm; a point foot (SILO4) 0.
"""

from __future__ import annotations

import numpy as np

from planner.terrain.terrain_map import TerrainMap
from planner.trajectory.rolling_feet import angular_velocity_foot_in_base
from planner.workspace.layout import SHIFT_RESERVE_M
from silo4kin.foot_contact import foot_ball
from silo4kin.legs import joint_motion

#: Points along a stroke where ω is evaluated (trapezoidal rule).
STROKE_SAMPLES = 41


def stance_roll_bound_m(legs, ws, rolling_radius_m: float) -> float:
    """The largest distance [m] a contact point rolls over one stance stroke of any leg
    (module docstring): ``legs`` the planning robot's legs in B, ``ws`` the workspace
    (position 2 of every leg, strides), ``rolling_radius_m`` the foot ball's (0: a point
    foot, which does not roll). Strokes whose IK leaves the legs' reach are integrated over
    the part in reach."""
    if rolling_radius_m <= 0.0:
        return 0.0
    s = np.linspace(-0.5, 0.5, STROKE_SAMPLES)
    mid = np.asarray(ws.position_mid_in_base, dtype=float)
    worst = 0.0
    for k, leg in enumerate(legs):
        for axis, stride in ((0, float(ws.stride_m)), (1, float(ws.stride_lateral_m))):
            if stride <= 0.0:
                continue
            stroke = stride + 2.0 * SHIFT_RESERVE_M
            p = np.tile(mid[k], (len(s), 1))
            p[:, axis] += s * stroke
            v = np.zeros_like(p)
            v[:, axis] = stroke  # dp/ds
            q, qd, *_ = joint_motion(leg, p, v, np.zeros_like(p))
            omega, _ = angular_velocity_foot_in_base(leg, q, qd, np.zeros_like(q))
            rate = np.hypot(omega[:, 0], omega[:, 1])
            ok = np.isfinite(rate)
            if ok.sum() < 2:
                continue
            r = np.where(ok, rate, 0.0)
            roll = float(np.sum(0.5 * (r[1:] + r[:-1]) * np.diff(s)))
            worst = max(worst, rolling_radius_m * roll)
    return worst


def stance_roll_m(planning_robot, ws, terrain) -> float:
    """:func:`stance_roll_bound_m` of the planning robot's foot ball on a terrain map's
    surfaces (planner/gaits/surface_footholds.py), 0 elsewhere (no surface search) and for
    feet that do not roll."""
    if not isinstance(terrain, TerrainMap):
        return 0.0
    ball = foot_ball(planning_robot)
    if not ball.rolls:
        return 0.0
    return stance_roll_bound_m(planning_robot.legs, ws, ball.rolling_radius_m)
