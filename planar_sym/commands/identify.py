"""``planar-sym identify ROBOT --data RUN.csv [--data MORE.csv] [--validate OTHER.csv] --out DIR``:
the robot's base parameters from measured (or simulated) positions and torques, their
standard deviations, a physically consistent set of standard parameters, and a check of the
identified model on data it was not fitted to.

Writes DIR/base_parameters.csv, DIR/standard_parameters.csv, DIR/identified_robot.toml (the
robot's description with the identified values: run any study on it),
DIR/identified_parameters.toml (the same values as a study's ``[parameters]`` table), DIR/report.txt
and DIR/validation.png.
"""

from __future__ import annotations

from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("identify", help="identify a robot's inertial and friction parameters "
                                        "from measured torques")
    p.add_argument("robot", help="built-in robot name or a description file (.toml)")
    p.add_argument("--data", type=Path, action="append", required=True, metavar="CSV",
                   help="an experiment: t_s, positions, torques (and rates and accelerations "
                        "if known); repeat for more")
    p.add_argument("--validate", type=Path, default=None, metavar="CSV",
                   help="an experiment kept out of the fit, to check the identified model on "
                        "(default: the first --data, which shows the fit only)")
    p.add_argument("--cutoff", type=float, default=None, metavar="HZ",
                   help="low-pass corner for filtering and differentiating (default 10 times "
                        "the highest frequency the positions carry, at most a tenth of the "
                        "sampling rate)")
    p.add_argument("--filter", action="store_true",
                   help="filter and differentiate even where the file gives rates and "
                        "accelerations")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..identify.csv_data import read_experiment
    from ..identify.estimate import identify
    from ..identify.physical import identified_robot, physical_parameters
    from ..identify.report import write_results
    from ..model.locate import load

    robot = load(args.robot)
    data = [read_experiment(robot, p, args.cutoff, args.filter) for p in args.data]
    check = (read_experiment(robot, args.validate, args.cutoff, args.filter)
             if args.validate else None)
    est = identify(robot, data)
    fit = physical_parameters(robot, est)
    identified = identified_robot(robot, fit, est)
    text = write_results(robot, est, fit, identified, check or data[0],
                         validated=check is not None, out=args.out)
    if not args.quiet:
        print(text)
    return 0
