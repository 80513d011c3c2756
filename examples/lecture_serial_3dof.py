"""Lecture 2: the 3-DOF serial arm (seed section [1], S4): a tool moved along a line at a fixed
orientation phi = pi/2, its joint motion and torques.

    python examples/lecture_serial_3dof.py [--samples N] [--plot DIR]
"""

from __future__ import annotations

import numpy as np
from _lectures import options, print_equations, report

import planar_sym as ps


def main() -> None:
    args = options(__doc__)
    arm = ps.load("serial_3dof")
    print(f"{arm.title}\ncoordinates {arm.coordinates}, task {arm.task_names}\n")
    print_equations("serial_3dof", ("M11", "M33", "g1", "g2", "g3"))

    result = ps.run_study("serial_3dof_cartesian_move", args.samples)
    report(result, args.plot)
    q = np.column_stack([result.columns[f"q{i}_rad"] for i in (1, 2, 3)])
    # the tool keeps phi = q1 + q2 + q3 = pi/2 all along: the wrist makes up for the arm
    print(f"serial_3dof_cartesian_move: max |q1 + q2 + q3 - pi/2| = "
          f"{np.max(np.abs(q.sum(axis=1) - np.pi / 2)):.3g} rad")
    print("serial_3dof_cartesian_move: joint ranges (deg) "
          + ", ".join(f"q{i + 1} {np.degrees(q[:, i].min()):.2f}..{np.degrees(q[:, i].max()):.2f}"
                      for i in range(3)))


if __name__ == "__main__":
    main()
