"""Lecture 1: the 2-DOF serial arm (seed section [1]): equations, free swing, joint and
Cartesian moves, and what a heavier elbow motor costs.

    python examples/lecture_serial_2dof.py [--samples N] [--plot DIR]
"""

from __future__ import annotations

import numpy as np
from _lectures import options, print_equations, report

import planar_sym as ps


def main() -> None:
    args = options(__doc__)
    arm = ps.load("serial_2dof")
    print(f"{arm.title}\ncoordinates {arm.coordinates}, {len(arm.p)} parameters\n")
    # M11 carries the elbow motor as m_M2*a_1**2, and cos(q2) couples the two links; the
    # lumped parameters (alpha, beta, delta) are what an identification experiment can measure
    print_equations("serial_2dof", ("M11", "M12", "M22", "alpha", "beta", "delta", "g1", "g2"))

    # S1: released from q1 = -60 deg at rest, no torque: where is it after 1 s?
    swing = ps.run_study("serial_2dof_free_swing", args.samples)
    q_end = [swing.columns["q1_rad"][-1], swing.columns["q2_rad"][-1]]
    print(f"serial_2dof_free_swing: q(1 s) = ({np.degrees(q_end[0]):.6f}, "
          f"{np.degrees(q_end[1]):.6f}) deg")
    report(swing, args.plot)

    # S2 and S3: torques needed for a slow joint move and a straight-line tip move
    for name in ("serial_2dof_joint_move", "serial_2dof_cartesian_move"):
        report(ps.run_study(name, args.samples), args.plot)

    # the same S3 motion with a 0.6 kg motor: a new parameter value, no re-derivation
    t = np.linspace(0.0, 5.0, args.samples or 201)
    joints = ps.inverse_kinematics(arm, ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, t))
    for label, robot in (("0.292 kg motor", arm), ("0.6 kg motor", arm.with_parameters(
            m_motor2=0.6))):
        tau = robot.inverse_dynamics(joints.q, joints.qd, joints.qdd)
        print(f"S3 with a {label}: peak |tau1| = {np.max(np.abs(tau[:, 0])):.6f} N*m")


if __name__ == "__main__":
    main()
