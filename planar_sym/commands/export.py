"""``planar-sym export``: a robot as an MJCF (MuJoCo) or URDF file, with its parameters."""

from __future__ import annotations

from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("export", help="write a robot as MJCF (MuJoCo; every robot) or URDF "
                                      "(trees only)")
    p.add_argument("robot", help="built-in robot name (see `list`) or a description file (.toml)")
    p.add_argument("--format", default=None, metavar="FORMAT",
                   help="mjcf or urdf (default: from --out's suffix, .xml or .urdf; else mjcf)")
    p.add_argument("--out", type=Path, default=None,
                   help="file to write (its folder must exist); default ROBOT.xml or ROBOT.urdf")
    p.add_argument("--ideal", action="store_true",
                   help="the ideal machine (no rotors, friction, gears or limits); default: "
                        "the drive train where the format has a place for it (MJCF: armature, "
                        "damping, frictionloss, gear and ranges; URDF: damping, friction, effort "
                        "and velocity limits)")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..model.locate import load
    from ..outputs.export import check_out, format_of, write

    if args.out is not None:  # a bad option fails before the robot loads
        check_out(args.out, Path(args.robot).stem)
    fmt = format_of(args.format, args.out)
    robot = load(args.robot)
    path = write(robot, args.out, fmt, ideal=args.ideal)
    if not args.quiet:
        kind = "closed chain" if robot.is_closed_chain else "tree"
        print(f"{robot.name}: wrote {path} ({fmt.upper()}, {kind}, {robot.n} joints, "
              f"{len(robot.body_names)} bodies)")
    return 0
