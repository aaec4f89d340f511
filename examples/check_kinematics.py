"""Compare the closed-form leg kinematics and dynamics with Pinocchio on random poses."""

from silo4kin import load_robot
from silo4kin.check import cross_check, format_report

if __name__ == "__main__":
    robot = load_robot()  # urdf/silo4.urdf.xacro, default arguments
    rows = cross_check(robot, n=500, seed=1)
    print(format_report(rows))
    print("all inside tolerance" if all(r.ok for r in rows) else "SOME CHECKS FAILED")
