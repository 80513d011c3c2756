"""``planar-sym build``: compile robots' generated C into the cache ahead of first use."""

from __future__ import annotations


def register(sub) -> None:
    p = sub.add_parser("build", help="compile the generated C of robots into the cache")
    p.add_argument("robots", nargs="*",
                   help="robot names or generated folders DIR/<name> (default: every built-in "
                        "robot)")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..model.description import builtin_robots
    from ..model.library import Library
    from ..model.locate import locate
    from ..progress import Progress

    robots = args.robots or builtin_robots()
    progress = Progress(len(robots), quiet=args.quiet)
    for robot in robots:
        progress.step(f"compiling {robot}")  # a robot takes a second or more with cc -O3
        name, folder = locate(robot)
        lib = Library(name, folder)
        lib.build_all()  # a big robot's groups too, which otherwise compile when first called
        if not args.quiet:
            where = ("no C compiler: CasADi evaluator" if not lib.compiled
                     else lib.path if len(lib.groups) == 1
                     else f"{len(lib.groups)} libraries, one per function, in {lib.path.parent}")
            print(f"{robot}: {where}")
    progress.done()
    return 0
