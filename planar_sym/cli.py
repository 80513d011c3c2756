"""``planar-sym``: list and run the seed scenarios, print equations, build the libraries."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .errors import PlanarSymError


def _cmd_list(args) -> int:
    from .description import builtin_robots
    from .scenarios import DEFAULT_SAMPLES, SCENARIOS

    print("Scenarios (planar-sym run NAME --out DIR):")
    for sc in SCENARIOS.values():
        print(f"  {sc.name:<30} {sc.summary}  [default {DEFAULT_SAMPLES[sc.kind]} samples]")
    print("\nRobots (planar-sym equations NAME):")
    for r in builtin_robots():
        print(f"  {r}")
    return 0


def _cmd_run(args) -> int:
    from .results import write
    from .scenarios import SCENARIOS, get, run

    names = list(SCENARIOS) if args.all else args.scenarios
    if not names:
        raise PlanarSymError("name at least one scenario, or --all (see `planar-sym list`)")
    for name in names:
        get(name)  # every name checked before anything runs
    for name in names:
        result = run(name, args.samples)
        paths = write(result, args.out)
        if not args.quiet:
            peaks = ", ".join(f"{k} {v:.4g}" for k, v in result.peak("tau").items())
            extra = f" (peak |tau| N*m: {peaks})" if peaks else f" ({result.note})"
            print(f"{name}: wrote {', '.join(str(p) for p in paths)}{extra}")
    return 0


def _cmd_equations(args) -> int:
    from .library import find_generated

    folder = find_generated(args.robot)
    name = "equations.tex" if args.latex else "equations.txt"
    text = (folder / name).read_text()
    body = text.split("\n\n", 1)[1] if text.startswith(("#", "%")) else text
    sys.stdout.write(body)
    return 0


def _cmd_build(args) -> int:
    from .description import builtin_robots
    from .library import Library

    for robot in args.robots or builtin_robots():
        lib = Library(robot)
        if not args.quiet:
            print(f"{robot}: {lib.path}")
    return 0


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="planar-sym",
        description="Dynamics of planar robots: the seed chapter's scenarios, compiled.")
    ap.add_argument("--quiet", action="store_true", help="print only errors")
    sub = ap.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="list scenarios and robots").set_defaults(fn=_cmd_list)
    run = sub.add_parser("run", help="run scenarios, write SCENARIO.csv and SCENARIO.png")
    run.add_argument("scenarios", nargs="*", help="scenario names (see `list`)")
    run.add_argument("--all", action="store_true", help="run every scenario")
    run.add_argument("--out", type=Path, default=Path("results"), help="output folder")
    run.add_argument("--samples", type=int, default=None,
                     help="evenly spaced samples (default 201 inverse, 1001 forward dynamics)")
    run.set_defaults(fn=_cmd_run)
    eq = sub.add_parser("equations", help="print a robot's closed-form equations of motion")
    eq.add_argument("robot")
    eq.add_argument("--latex", action="store_true", help="LaTeX instead of text")
    eq.set_defaults(fn=_cmd_equations)
    b = sub.add_parser("build", help="compile the generated C of robots into the cache")
    b.add_argument("robots", nargs="*")
    b.set_defaults(fn=_cmd_build)
    return ap


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        return args.fn(args)
    except PlanarSymError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
