"""Place the left-front foot, solve knee-down IK, and read joint rates for a foot velocity."""

import numpy as np

from silo4kin import kinematics, load_robot

if __name__ == "__main__":
    robot = load_robot()
    leg = robot.leg("LF")
    position_foot_in_base = np.array([0.30, 0.30, -0.40])  # [m]
    q = kinematics.inverse_kinematics(leg, position_foot_in_base)  # [rad]
    print("q [deg]:", np.round(np.degrees(q), 2))
    print("FK back [m]:", np.round(kinematics.forward_kinematics(leg, q), 6))
    velocity_foot_in_base = np.array([0.05, 0.0, 0.0])  # [m/s]
    print("qd [rad/s]:", np.round(kinematics.joint_velocity(leg, q, velocity_foot_in_base), 4))
    print("det J:", float(kinematics.jacobian_determinant(leg, q)))
