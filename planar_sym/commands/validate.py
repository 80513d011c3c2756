"""``planar-sym validate ROBOT``: the project's cross-checks on one robot, as a table.

ROBOT is a built-in name or a generated folder (``DIR/<name>`` from ``planar-sym derive``).
Exit code 0 when every check passes (or is skipped), 1 when any fails.
"""

from __future__ import annotations

from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("validate", help="cross-check a robot's compiled dynamics (table, exit 1 "
                                        "on a failure)")
    p.add_argument("robot", help="built-in robot name (see `list`), a description file "
                                 "(.toml) or a generated folder DIR/<name>")
    p.add_argument("--description", type=Path, default=None,
                   help="the robot's TOML, for the SymPy check (default: DIR/<name>/"
                        "description.toml, or the file named in the manifest)")
    p.add_argument("--samples", type=int, default=20, help="random states per check (default 20)")
    p.add_argument("--seconds", type=float, default=1.0, help="length of the free motion (s, default 1)")
    p.set_defaults(fn=run)


def table(rows) -> str:
    """Rows of ``planar_sym.validate`` as a fixed-width text table."""
    head = ("check", "worst", "tolerance", "result", "detail")
    body = [(r.check, "-" if r.worst is None else f"{r.worst:.2e}",
             "-" if r.tolerance is None else f"{r.tolerance:.0e}", r.status, r.detail)
            for r in rows]
    widths = [max(len(line[i]) for line in [head, *body]) for i in range(4)]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(line[:4], widths)) + "  " + line[4]
                     for line in [head, *body])


def run(args) -> int:
    from ..analysis.validate import run_all
    from ..errors import InputError
    from ..model.locate import load
    from ..progress import Progress

    if args.samples < 1 or not args.seconds > 0:
        raise InputError("--samples must be >= 1 and --seconds > 0")
    if args.description is not None and not args.description.is_file():
        raise InputError(f"--description {args.description}: no such file")
    robot = load(args.robot)
    progress = Progress(0, quiet=args.quiet)  # run_all sets the total
    rows = run_all(robot, args.description, samples=args.samples, seconds=args.seconds,
                   progress=progress)
    progress.done()
    failed = [r for r in rows if r.status == "FAIL"]
    if args.quiet:  # only the errors: the failing rows
        if failed:
            print(table(failed))
    else:
        print(f"{robot.name}: {robot.title}\n  from {robot.library.folder}\n")
        print(table(rows))
        verdict = (f"FAILED: {len(failed)} of {len(rows)} checks" if failed
                   else f"all {len(rows)} checks pass")
        print(f"\n{robot.name}: {verdict}")
    return 1 if failed else 0
