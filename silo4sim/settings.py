"""The sim's settings and the servo gains they give a robot (docs/physics.md).

Servo gains per robot (:func:`servo_gains`): SimSettings.kp / kd were tuned on SILO4, whose
knee (the lightest joint) has a joint-space inertia I_ref = REFERENCE_KNEE_INERTIA. A leg
with a lighter knee gets both gains scaled by s = I_knee / I_ref (s <= 1), which keeps the
servo's natural frequency sqrt(kp / I) and damping ratio kd / (2 sqrt(kp I)) — and the
step's kd dt / I — those of SILO4. Measured (docs/physics.md, "Other robots"): unscaled,
Go2's knee (I = 0.005 kg m², kd dt / I = 4) chatters and the standing robot slides 40 mm in
3 s; scaled (kp 382, kd 3.8) it stands within 0.2 mm.
"""

from __future__ import annotations

from dataclasses import dataclass

from silo4kin.robot import Robot

#: SimSettings.friction_cone values.
FRICTION_CONES = ("elliptic", "pyramidal")


@dataclass(frozen=True)
class SimSettings:
    """Physics and servo settings (docs/physics.md says why each value).

    Attributes:
        timestep_s: integration step [s].
        friction: Coulomb friction coefficient of feet and floor [-].
        foot_radius_m: contact sphere radius at each foot frame [m] (small: a sphere rolls
            r * rotation during stance).
        tibia_clearance_m: the tibia's collision capsule stops this far short of the foot [m].
        kp: servo stiffness [N m / rad].
        kd: servo damping [N m s / rad].
        noslip_iterations: MuJoCo's no-slip solver passes (stops soft-contact creep).
        friction_cone: "elliptic" (Coulomb's cone; the no-slip solver then changes only the
            friction forces) or "pyramidal" (MuJoCo's default: its edges carry the normal
            force too, so the no-slip passes can unload a foot; with a tall, nearly straight
            leg at a 1 ms step the foot chatters and creeps: docs/physics.md, "Contacts").
        settle_s: time holding the first planned posture before the plan starts [s].
        put_down_s: the robot is put down on its feet over the first put_down_s of the
            settle and of the calibration: gravity and the servos' feed-forward torques
            ramped together from 0 to full (a smoothstep), the servos holding the first
            posture, so the contacts load as the legs do (silo4sim/replay.py ``put_down``;
            0: dropped at full load, the legs pushing before the feet carry anything) [s].
        contact_timeconst_s: MuJoCo contact solref time constant [s] (>= 2 steps; smaller
            is stiffer: a foot sinks less into the floor).
        contact_impedance: MuJoCo contact solimp (dmin, dmax, width [m]).
        ball_feet: a robot whose URDF has a foot ball (silo4kin/foot_contact.py) stands on
            it (the planner plans it rolling); off: point-like feet of foot_radius_m at the
            foot frames (silo4sim/model.py). Robots without a ball always get those.
        scale_gains: scale kp and kd to the robot's knee inertia (:func:`servo_gains`);
            off: kp and kd as given.
    """

    timestep_s: float = 0.001
    friction: float = 1.0
    foot_radius_m: float = 0.001
    tibia_clearance_m: float = 0.05
    kp: float = 2000.0
    kd: float = 20.0
    noslip_iterations: int = 10
    friction_cone: str = "elliptic"
    settle_s: float = 0.5
    put_down_s: float = 0.3
    contact_timeconst_s: float = 0.004
    contact_impedance: tuple[float, float, float] = (0.99, 0.999, 0.001)
    ball_feet: bool = True
    scale_gains: bool = True


#: Joint-space inertia of SILO4's knee (the shank about the knee axis) [kg m^2]: the
#: knee that SimSettings.kp / kd were tuned on (0.02603, rounded down so SILO4 scales by 1).
REFERENCE_KNEE_INERTIA = 0.026


def knee_inertia(robot: Robot) -> float:
    """Smallest knee joint-space inertia M[k, k] of the robot's legs [kg m^2] (the shank
    and foot about the knee axis: independent of the posture; pin.crba at the neutral q)."""
    import pinocchio as pin

    model = robot.model
    mass_matrix = pin.crba(model, model.createData(), pin.neutral(model))
    return float(
        min(
            mass_matrix[i, i]
            for i in (
                model.joints[model.getJointId(leg.joint_names[2])].idx_v for leg in robot.legs
            )
        )
    )


def servo_gains(robot: Robot, settings: SimSettings) -> tuple[float, float, float]:
    """(kp [N m/rad], kd [N m s/rad], scale s [-]) of every servo (module doc)."""
    scale = 1.0
    if settings.scale_gains:
        scale = min(1.0, knee_inertia(robot) / REFERENCE_KNEE_INERTIA)
    return settings.kp * scale, settings.kd * scale, scale
