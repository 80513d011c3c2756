"""``planar-sym run``: scenarios into CSV and PNG files."""

from __future__ import annotations

from pathlib import Path

from ..errors import PlanarSymError


def register(sub) -> None:
    p = sub.add_parser("run", help="run scenarios, write SCENARIO.csv and SCENARIO.png "
                                   "(and SCENARIO_split.png with --split)")
    p.add_argument("scenarios", nargs="*", help="scenario names (see `list`)")
    p.add_argument("--all", action="store_true", help="run every scenario")
    p.add_argument("--out", type=Path, default=Path("results"), help="output folder")
    p.add_argument("--samples", type=int, default=None,
                   help="evenly spaced samples (default 201 inverse, 1001 forward dynamics)")
    p.add_argument("--split", action="store_true",
                   help="also plot each torque split into M qdd, C qd and g (SCENARIO_split.png)")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..study.result import write
    from ..study.scenarios import SCENARIOS, get
    from ..study.scenarios import run as run_scenario

    names = list(SCENARIOS) if args.all else args.scenarios
    if not names:
        raise PlanarSymError("name at least one scenario, or --all (see `planar-sym list`)")
    for name in names:
        get(name)  # every name checked before anything runs
    for name in names:
        result = run_scenario(name, args.samples)
        paths = write(result, args.out, split=args.split)
        if not args.quiet:
            peaks = ", ".join(f"{k} {v:.4g}" for k, v in result.peak("tau").items())
            extra = f" (peak |tau| N*m: {peaks})" if peaks else f" ({result.note})"
            print(f"{name}: wrote {', '.join(str(p) for p in paths)}{extra}")
    return 0
