"""The MuJoCo model of a robot: its URDF on a free-floating base, a floor, foot spheres,
joint servos and the sensors the replay reads (stack-notes.md, "MuJoCo").

    sim_model = build_sim_model(robot, SimSettings())
    sim_model.model      # mujoco.MjModel, 1 ms step, implicitfast integrator, elliptic cones
    sim_model.spec.to_xml()  # the MJCF, for MuJoCo's own viewer

Frames: the world frame W of the planner (z up), floor at z = 0. Feet
(silo4kin/foot_contact.py, docs/physics.md "Round feet"): a robot whose URDF has a foot ball
(a collision sphere, or a collision mesh measured as a ball centred on the foot frame) gets
that ball (for a ball above the foot frame, anymal's, its equivalent ball of radius r - o_z
centred on the foot frame), on the floor z = 0 where the planner puts its contact points;
the planner plans the ball as it rolls. A robot without one (SILO4) gets
a small sphere of foot_radius_m centred on the foot frame and the floor at -foot_radius_m,
so a foot frame at z = 0 just touches it.

Servo of each joint (an affine MuJoCo actuator, gain kp, bias [0, -kp, -kd]):
    tau = clamp(kp (u - q) - kd q̇, ±effort)   with   u = q_ref + (kd q̇_ref + tau_ff) / kp,
i.e. tau = kp (q_ref - q) + kd (q̇_ref - q̇) + tau_ff, clamped to the URDF effort limit;
tau_ff is the plan's joint torque (eq A.34). implicitfast integrates the stiff PD stably.

Servo gains per robot: silo4sim/settings.py.

``SimSettings(ball_feet=False)`` models a ball robot's feet as points at the foot frame
(floor at the foot frame's standing height, contact_offset_m - foot_radius_m): the model of
the planner before it planned rolling, kept to measure what the rolling changes.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from silo4kin.collision_shapes import tibia_capsules
from silo4kin.foot_contact import foot_ball
from silo4kin.robot import Robot

from .errors import MujocoModelError, import_mujoco
from .settings import FRICTION_CONES, SimSettings, servo_gains
from .terrain import FLAT_FLOOR, add_terrain
from .urdf_collisions import prepare_urdf


@dataclass(frozen=True, eq=False)
class SimModel:
    """A compiled MuJoCo model and where to find our quantities in it.

    Attributes:
        spec: the mujoco.MjSpec (``spec.to_xml()`` is the MJCF).
        model: the compiled mujoco.MjModel.
        settings: the settings it was built with.
        joint_names: the 12 joints in our array order (leg by leg); actuator i drives joint i.
        effort_limit: URDF effort limit per joint [N m], shape (12,); inf when none.
        qpos_adr: qpos index of each joint, shape (12,).
        root_body: name of the URDF root link (the free-floating body).
        position_body_com_in_root: the body CoG in the root link frame [m], shape (3,).
        sensor: name -> slice into sensordata (see :func:`_add_sensors`).
        contact_bodies: names of the bodies whose ground contacts are not feet.
        kp, kd: the servo gains used (:func:`servo_gains`) [N m/rad], [N m s/rad].
    """

    spec: object
    model: object
    settings: SimSettings
    joint_names: tuple[str, ...]
    effort_limit: np.ndarray
    qpos_adr: np.ndarray
    root_body: str
    position_body_com_in_root: np.ndarray
    sensor: dict[str, slice] = field(default_factory=dict)
    contact_bodies: tuple[str, ...] = ()
    kp: float = 0.0
    kd: float = 0.0

    def mjcf(self) -> str:
        """The model as MJCF text (opens in MuJoCo's viewer: python -m mujoco.viewer)."""
        return str(self.spec.to_xml())  # type: ignore[attr-defined]


def _knee_child_links(urdf_xml: str, knees: list[str]) -> dict[str, str]:
    import xml.etree.ElementTree as ET

    root = ET.fromstring(urdf_xml)
    out = {}
    for j in root.findall("joint"):
        child = j.find("child")
        if j.get("name") in knees and child is not None:
            out[j.get("name", "")] = child.get("link", "")
    return out


def build_sim_model(
    robot: Robot, settings: SimSettings | None = None, terrain: Mapping[str, Any] | None = None
) -> SimModel:
    """Build and compile the MuJoCo model of ``robot`` (see the module doc) on ``terrain``
    (plan.json's terrain document; None: the flat floor).

    Raises:
        MujocoMissingError: mujoco is not installed.
        MujocoModelError: MuJoCo refuses the URDF; the message quotes MuJoCo, which names
            the element.
    """
    settings = settings or SimSettings()
    mj = import_mujoco()
    knees = [leg.joint_names[2] for leg in robot.legs]
    urdf_text, _ = prepare_urdf(robot.urdf_xml, knees)
    try:
        spec = mj.MjSpec.from_string(urdf_text)
    except Exception as exc:  # mujoco raises ValueError with the parser's message
        raise MujocoModelError(f"MuJoCo cannot read the robot's URDF: {_one_line(exc)}") from None
    root = spec.worldbody.first_body()
    if root is None:
        raise MujocoModelError("MuJoCo found no link in the robot's URDF")
    root.add_freejoint(name="floating_base")

    # contact convention (silo4kin/foot_contact.py, module docstring): the URDF's ball
    # (its equivalent ball centred on the foot frame where it sits above it) on the floor
    # z = 0, or a point-like sphere of foot_radius_m on the foot frame, the floor where the
    # foot frame stands.
    ball = foot_ball(robot)
    offset = ball.contact_offset_m
    if ball.rolls and settings.ball_feet:
        r, floor_z = ball.rolling_radius_m, 0.0
    else:
        r, floor_z = settings.foot_radius_m, offset - settings.foot_radius_m
    for geom in spec.geoms:  # URDF collision shapes: collide with the floor only
        geom.contype, geom.conaffinity = 2, 1
        geom.friction = [settings.friction, 0.005, 0.0001]
    add_terrain(  # the floor, and the run's terrain (silo4sim/terrain.py)
        spec,
        terrain or FLAT_FLOOR,
        z_shift_m=floor_z,
        friction=[settings.friction, 0.005, 0.0001],
    )
    spec.worldbody.add_light(pos=[0, 0, 5], dir=[0, 0, -1])

    tibia_links = _knee_child_links(robot.urdf_xml, knees)
    capsules = tibia_capsules(robot, settings.tibia_clearance_m)
    foot_bodies: list[str] = []
    for leg, capsule in zip(robot.legs, capsules):
        knee = leg.joint_names[2]
        fid = robot.model.getFrameId(leg.foot_frame)
        frame = robot.model.frames[fid]
        if robot.model.names[frame.parentJoint] != knee:
            raise MujocoModelError(
                f"foot frame {leg.foot_frame!r} does not move with the knee joint {knee!r}"
            )
        position_foot_in_tibia = np.array(frame.placement.translation)
        tibia = spec.body(tibia_links[knee])
        if tibia is None:
            raise MujocoModelError(f"MuJoCo has no body for link {tibia_links[knee]!r}")
        tibia.add_geom(
            name=f"{leg.name}_tibia_capsule",
            type=mj.mjtGeom.mjGEOM_CAPSULE,
            fromto=[*capsule.start_in_link, *capsule.end_in_link],  # what the planner measures
            size=[capsule.radius_m, 0, 0],
            contype=2,
            conaffinity=1,
            mass=0,
            density=0,
            friction=[settings.friction, 0.005, 0.0001],
        )
        foot = spec.body(leg.foot_frame)
        if foot is None or foot.name == tibia.name:
            foot = tibia
            position_foot = position_foot_in_tibia
        else:
            position_foot = np.zeros(3)
        foot_bodies.append(foot.name)
        foot.add_geom(
            name=f"{leg.name}_foot_sphere",
            type=mj.mjtGeom.mjGEOM_SPHERE,
            pos=position_foot,
            size=[r, 0, 0],
            contype=2,
            conaffinity=1,
            mass=0,
            density=0,
            friction=[settings.friction, 0.005, 0.0001],
        )
        foot.add_site(name=f"{leg.name}_foot", pos=position_foot, size=[4 * r, 0, 0])

    com = np.asarray(robot.position_body_com_in_base, dtype=float)
    root.add_site(name="body_com", pos=com, size=[0.01, 0, 0])

    joint_names = tuple(robot.joint_names)
    kp, kd, _ = servo_gains(robot, settings)
    effort = np.full(12, np.inf)
    for i, name in enumerate(joint_names):
        jid = robot.model.getJointId(name)
        limit = float(robot.model.effortLimit[robot.model.joints[jid].idx_v])
        if np.isfinite(limit) and limit > 0:
            effort[i] = limit
        act = spec.add_actuator(name=f"servo_{name}", target=name, trntype=mj.mjtTrn.mjTRN_JOINT)
        act.set_to_position(kp=kp, kv=kd)
        if np.isfinite(effort[i]):
            act.forcelimited = mj.mjtLimited.mjLIMITED_TRUE
            act.forcerange = [-effort[i], effort[i]]

    for geom in spec.geoms:
        geom.solref = [settings.contact_timeconst_s, 1.0]
        geom.solimp = [*settings.contact_impedance, 0.5, 2.0]
    spec.option.timestep = settings.timestep_s
    spec.option.integrator = mj.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.noslip_iterations = settings.noslip_iterations
    spec.option.cone = _friction_cone(mj, settings.friction_cone)

    contact_bodies = [
        b.name for b in spec.bodies if b.name and b.name != "world" and b.name not in foot_bodies
    ]
    sensors = _add_sensors(mj, spec, robot, joint_names, contact_bodies)
    try:
        model = spec.compile()
    except Exception as exc:
        raise MujocoModelError(f"MuJoCo refuses the robot model: {_one_line(exc)}") from None
    qpos_adr = np.array([model.jnt_qposadr[model.joint(n).id] for n in joint_names])
    slices = {}
    for name, sensor_names in sensors.items():
        adr = [int(model.sensor_adr[model.sensor(s).id]) for s in sensor_names]
        dim = int(model.sensor_dim[model.sensor(sensor_names[0]).id])
        if adr != list(range(adr[0], adr[0] + dim * len(adr), dim)):
            raise MujocoModelError(f"sensors {name} are not contiguous")  # never: added in order
        slices[name] = slice(adr[0], adr[0] + dim * len(adr))
    return SimModel(
        spec=spec,
        model=model,
        settings=settings,
        joint_names=joint_names,
        effort_limit=effort,
        qpos_adr=qpos_adr,
        root_body=root.name,
        position_body_com_in_root=com,
        sensor=slices,
        contact_bodies=tuple(contact_bodies),
        kp=kp,
        kd=kd,
    )


def _add_sensors(
    mj,
    spec,
    robot: Robot,
    joint_names: tuple[str, ...],  # noqa: ANN001
    contact_bodies: list[str],
) -> dict[str, list[str]]:
    """Sensors read each step; returns group name -> sensor names in array order.

    body_position (3) and body_quat (4, w x y z): the body CoG site in W; q, qd (12 each);
    tau (12): actuator forces [N m]; foot_position (4 x 3): foot sphere centres in W;
    foot_force (4): normal contact force on each foot [N]; body_force (B): on each other
    body (a touch sensor whose site encloses the body).
    """
    S = mj.mjtSensor
    obj_site = mj.mjtObj.mjOBJ_SITE
    groups: dict[str, list[str]] = {}

    def add(group: str, name: str, kind: object, objname: str, objtype: object) -> None:
        spec.add_sensor(name=name, type=kind, objname=objname, objtype=objtype)
        groups.setdefault(group, []).append(name)

    add("body_position", "body_position", S.mjSENS_FRAMEPOS, "body_com", obj_site)
    add("body_quat", "body_quat", S.mjSENS_FRAMEQUAT, "body_com", obj_site)
    for name in joint_names:
        add("q", f"q_{name}", S.mjSENS_JOINTPOS, name, mj.mjtObj.mjOBJ_JOINT)
    for name in joint_names:
        add("qd", f"qd_{name}", S.mjSENS_JOINTVEL, name, mj.mjtObj.mjOBJ_JOINT)
    for name in joint_names:
        add("tau", f"tau_{name}", S.mjSENS_ACTUATORFRC, f"servo_{name}", mj.mjtObj.mjOBJ_ACTUATOR)
    for leg in robot.legs:
        add(
            "foot_position",
            f"{leg.name}_foot_position",
            S.mjSENS_FRAMEPOS,
            f"{leg.name}_foot",
            obj_site,
        )
    for leg in robot.legs:
        add("foot_force", f"{leg.name}_foot_force", S.mjSENS_TOUCH, f"{leg.name}_foot", obj_site)
    for body_name in contact_bodies:
        body = spec.body(body_name)
        body.add_site(name=f"touch_{body_name}", size=[5.0, 0, 0])
        add("body_force", f"touch_{body_name}", S.mjSENS_TOUCH, f"touch_{body_name}", obj_site)
    return groups


def _friction_cone(mj, name: str):  # noqa: ANN001, ANN202 (mujoco module, mjtCone)
    """MuJoCo's cone of SimSettings.friction_cone."""
    if name not in FRICTION_CONES:
        raise MujocoModelError(
            f"friction_cone must be one of {', '.join(FRICTION_CONES)}, got {name!r}"
        )
    return mj.mjtCone.mjCONE_ELLIPTIC if name == "elliptic" else mj.mjtCone.mjCONE_PYRAMIDAL


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())
