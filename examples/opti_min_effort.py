"""Optimal control with casadi.Opti on planar-sym's saved functions (no SymPy, no compiler).

1. The 2-DOF arm swings from hanging to a pose in 0.8 s with the least torque effort
   (integral of |tau|^2): direct multiple shooting, RK4 on qdd = M(q)^-1 (tau - h(q, qd)), with
   ``M`` and ``h`` loaded from the robot's ``mass_matrix.casadi`` and ``bias.casadi``. The
   optimal torques are then replayed through planar-sym's own simulation, which must land
   where the optimiser said.
2. The Type I 5-bar: the pose that puts P at a target nearest the drawn one, with the loop
   closure Phi(q) = 0 (``constraint.casadi``) as an equality constraint, checked against
   planar-sym's inverse kinematics.

Run: python examples/opti_min_effort.py [--intervals N]
"""

from __future__ import annotations

import argparse

import casadi as ca
import numpy as np

import planar_sym as ps


def min_effort_swing(intervals: int, duration_s: float = 0.8):
    arm = ps.load("serial_2dof")
    M, h = arm.casadi_function("mass_matrix"), arm.casadi_function("bias")
    p = ca.DM(arm.p)
    q_start, q_goal = np.radians([-90.0, 0.0]), np.radians([30.0, 60.0])

    def f(x, tau):  # state x = [q, qd] -> its rate
        q, qd = x[:2], x[2:]
        return ca.vertcat(qd, ca.solve(M(q, p), tau - h(q, qd, p)))

    dt = duration_s / intervals
    opti = ca.Opti()
    x = opti.variable(4, intervals + 1)
    tau = opti.variable(2, intervals)  # N*m, held over each interval
    for k in range(intervals):
        k1 = f(x[:, k], tau[:, k])
        k2 = f(x[:, k] + dt / 2 * k1, tau[:, k])
        k3 = f(x[:, k] + dt / 2 * k2, tau[:, k])
        k4 = f(x[:, k] + dt * k3, tau[:, k])
        opti.subject_to(x[:, k + 1] == x[:, k] + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4))
    opti.subject_to(x[:, 0] == np.r_[q_start, 0.0, 0.0])
    opti.subject_to(x[:, -1] == np.r_[q_goal, 0.0, 0.0])
    opti.minimize(dt * ca.sumsqr(tau))
    opti.set_initial(x, np.linspace(np.r_[q_start, 0, 0], np.r_[q_goal, 0, 0], intervals + 1).T)
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes"})
    sol = opti.solve()
    taus = np.atleast_2d(sol.value(tau)).reshape(2, intervals)
    # replay: the same held torques through planar-sym's compiled simulation
    edges = np.linspace(0.0, duration_s, intervals + 1)

    def held(t):
        return taus[:, min(int(np.searchsorted(edges, t, side="right")) - 1, intervals - 1)]

    sim = ps.simulate(arm, q_start, [0.0, 0.0], (0.0, duration_s), torque=held,
                      t_eval=edges, rtol=1e-10, atol=1e-12)
    effort = float(dt * np.sum(taus ** 2))
    miss = float(np.max(np.abs(sim.q[-1] - q_goal)))
    return effort, float(np.max(np.abs(taus))), miss


def five_bar_pose(target_m=(0.07, 0.16)):
    robot = ps.load("five_bar_type1")
    phi, task = robot.casadi_function("constraint"), robot.casadi_function("task")
    p = ca.DM(robot.p)
    opti = ca.Opti()
    q = opti.variable(robot.n)
    opti.subject_to(phi(q, p) == 0)  # the loop closes (m)
    opti.subject_to(task(q, ca.DM.zeros(robot.n), p)[0] == ca.DM(target_m))  # P at the target
    opti.minimize(ca.sumsqr(q - robot.q_drawn))
    opti.set_initial(q, robot.q_drawn)
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes"})
    q_opt = np.atleast_1d(opti.solve().value(q))
    t = np.array([0.0])
    ik = ps.inverse_kinematics(robot, ps.Trajectory(t, np.array([target_m]), np.zeros((1, 2)),
                                                    np.zeros((1, 2))))
    return q_opt, ik.q[0]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--intervals", type=int, default=40, help="shooting intervals (default 40)")
    args = ap.parse_args()
    effort, peak, miss = min_effort_swing(args.intervals)
    print(f"serial_2dof: least effort {effort:.6g} N^2*m^2*s, peak |tau| {peak:.6g} N*m")
    print(f"serial_2dof: replayed in planar-sym, misses the goal by {miss:.3g} rad")
    q_opt, q_ik = five_bar_pose()
    print(f"five_bar_type1: Opti pose {np.round(q_opt, 9).tolist()} rad")
    print(f"five_bar_type1: differs from planar-sym's IK by {np.max(np.abs(q_opt - q_ik)):.3g} rad")


if __name__ == "__main__":
    main()
