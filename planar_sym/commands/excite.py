"""``planar-sym excite ROBOT --duration T --harmonics K --out STUDY.toml``: an exciting motion
for identification, written as a study (an inverse study whose joint motion is a table), so
``planar-sym run STUDY.toml`` gives its torques and ``planar-sym identify`` reads them back.
"""

from __future__ import annotations

from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("excite", help="design an exciting motion for identification (a study)")
    p.add_argument("robot", help="built-in robot name or a description file (.toml)")
    p.add_argument("--duration", type=float, required=True,
                   help="period of the motion (s): it repeats exactly")
    p.add_argument("--harmonics", type=int, default=5, help="Fourier harmonics per joint (default 5)")
    p.add_argument("--out", type=Path, required=True,
                   help="the study file to write (STUDY.toml; its table STUDY_motion.csv beside "
                        "it)")
    p.add_argument("--range", type=float, nargs="+", default=None, metavar="R",
                   help="half range about the drawn pose, per actuated joint or one for all "
                        "(rad; m at a slider; default 1 rad, 0.1 m)")
    p.add_argument("--speed", type=float, nargs="+", default=None, metavar="V",
                   help="largest joint speed (rad/s; m/s; default 2 rad/s, 0.2 m/s)")
    p.add_argument("--acceleration", type=float, nargs="+", default=None, metavar="A",
                   help="largest joint acceleration (rad/s^2; m/s^2; default 10, 1)")
    p.add_argument("--rate", type=float, default=200.0,
                   help="samples per second of the table (Hz, default 200)")
    p.add_argument("--seed", type=int, default=0, help="random starts' seed (default 0)")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..errors import InputError
    from ..identify.excite import default_limits, excite
    from ..identify.study_file import write_excitation
    from ..model.locate import load

    if args.out.suffix != ".toml":
        raise InputError(f"--out {args.out}: a study file ends in .toml")
    if not args.duration > 0:  # before the rate: a negative period is the mistake to name
        raise InputError(f"--duration must be a positive number of seconds, got "
                         f"{args.duration:g}")
    if not (args.rate > 0 and args.rate * args.duration >= 10):
        raise InputError(f"--rate {args.rate:g} Hz gives fewer than 10 samples over "
                         f"{args.duration:g} s")
    robot = load(args.robot)
    limits = default_limits(robot, args.range, args.speed, args.acceleration)
    ex = excite(robot, args.duration, args.harmonics, limits=limits, seed=args.seed)
    study, table = write_excitation(robot, args.robot, ex, args.out, args.rate)
    if not args.quiet:
        names = [robot.coordinates[i] for i in robot.actuated]
        print(f"{robot.name}: exciting motion, {args.harmonics} harmonics, period "
              f"{args.duration:g} s: condition number {ex.condition:.3g} (from "
              f"{ex.start_condition:.3g} at the best start)")
        for k, j in enumerate(names):
            unit = robot.coordinate_units[robot.actuated[k]]
            print(f"  {j}: peak speed {ex.peak_speed[k]:.3g} {unit}/s, acceleration "
                  f"{ex.peak_acceleration[k]:.3g} {unit}/s^2, torque {ex.peak_torque[k]:.3g} "
                  f"{'N' if unit == 'm' else 'N*m'}")
        print(f"wrote {study} and {table}: run it with `planar-sym run {study}`")
    return 0
