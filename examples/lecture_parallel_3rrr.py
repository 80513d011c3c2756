"""Lecture 5: the 3-RRR parallel robot (seed section [2](5), S7): three legs closed through the
platform, torques at A1, A2, A3 and the reaction forces at the two cut joints, for platform moves
in x and in y at phi = 0.

    python examples/lecture_parallel_3rrr.py [--samples N] [--plot DIR]
"""

from __future__ import annotations

from _lectures import options, print_equations, report, report_forces

import planar_sym as ps


def main() -> None:
    args = options(__doc__)
    robot = ps.load("parallel_3rrr")
    act = ", ".join(robot.coordinates[i] for i in robot.actuated)
    print(f"{robot.title}\n{robot.n} coordinates, actuated {act}, cut at {robot.loops} "
          f"({robot.n_constraints} loop equations)\n")
    # leg 1 carries the platform in the spanning tree, so I_P sits in its entries (M33); legs 2
    # and 3 are plain two-link arms (M44, M45), joined to the platform only through Phi = 0
    print_equations("parallel_3rrr", ("M33", "M44", "M45", "g4", "Phi1", "Phi2"))
    for name in ("parallel_3rrr_move_x", "parallel_3rrr_move_y"):
        result = ps.run_study(name, args.samples)
        report(result, args.plot)
        report_forces(result)


if __name__ == "__main__":
    main()
