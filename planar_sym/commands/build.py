"""``planar-sym build``: compile robots' generated C into the cache ahead of first use."""

from __future__ import annotations


def register(sub) -> None:
    p = sub.add_parser("build", help="compile the generated C of robots into the cache")
    p.add_argument("robots", nargs="*", help="robot names (default: every built-in robot)")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..description import builtin_robots
    from ..library import Library

    for robot in args.robots or builtin_robots():
        lib = Library(robot)
        if not args.quiet:
            print(f"{robot}: {lib.path}")
    return 0
