"""Lecture 4: the 5-bar Type II closed chain (seed S6): loop-closure equations,
torques at A and E and the reaction force at the cut joint, for moves of P in x and in y; the
same equations as Type I with other link lengths and the other assembly mode.

    python examples/lecture_five_bar_type2.py [--samples N] [--plot DIR]
"""

from __future__ import annotations

from _lectures import options, print_equations, report, report_forces

import planar_sym as ps


def main() -> None:
    args = options(__doc__)
    robot = ps.load("five_bar_type2")
    act = ", ".join(robot.coordinates[i] for i in robot.actuated)
    print(f"{robot.title}\ncoordinates {robot.coordinates}, actuated {act}, "
          f"cut at {robot.loops}\n")
    # the passive joints appear in M and g like any other; Phi = 0 ties them to A and E
    print_equations("five_bar_type2", ("M11", "M12", "g1", "Phi1", "Phi2"))
    for name in ("five_bar_type2_move_x", "five_bar_type2_move_y"):
        result = ps.run_study(name, args.samples)
        report(result, args.plot)
        report_forces(result)


if __name__ == "__main__":
    main()
