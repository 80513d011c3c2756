"""``planar-sym sweep``: one study (or atlas) per design, the figures in one table and plot."""

from __future__ import annotations

import re
import sys
import time
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..progress import Meter


def register(sub) -> None:
    p = sub.add_parser(
        "sweep", help="run a study once per design (parameters over a grid or a random sample)"
                      "; writes STUDY_sweep.csv and STUDY_sweep.png",
        description="Vary robot parameters (SI: m, kg, kg*m^2; see `planar-sym list` and the "
                    "robot's parameters in the README) and collect each design's figures: peak "
                    "and RMS torque per actuator (and, with actuator models, motor torque, "
                    "speed and power), cut-joint forces, conditioning; or, with --atlas, the "
                    "workspace area and dexterity.")
    p.add_argument("study", help="built-in study name or study file (.toml)")
    p.add_argument("--vary", action="append", default=[], metavar="NAME=SPEC",
                   help="NAME=LOW:HIGH:COUNT (grid), NAME=V1,V2,... (values), NAME=LOW:HIGH "
                        "(with --random); NAME1,NAME2=... ties parameters to the same values; "
                        "repeat for more parameters (a grid takes every combination). Values "
                        "are SI (kg, m, kg*m^2: --parameters lists each one's), or in the unit "
                        "given after them: 'm_link2=50:90:5 g' (needed where the description "
                        "is in other units, mm or g, as --set reads those)")
    p.add_argument("--parameters", action="store_true",
                   help="list the study's robot's parameters (name, value, SI unit) and stop")
    p.add_argument("--random", type=int, default=None, metavar="N",
                   help="draw N designs uniformly between the LOW:HIGH bounds instead of a grid")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--workers", type=int, default=None,
                   help="local threads (default: every core)")
    p.add_argument("--processes", type=int, default=None, metavar="N",
                   help="run batches in N local processes instead of threads")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="a dask.distributed scheduler (tcp://host:8786) to run the batches on")
    p.add_argument("--on", default="both", metavar="SET",
                   help="for a control study, which parameter set the designs change: both "
                        "(default: the controller's model and the plant), model or plant")
    p.add_argument("--atlas", action="store_true",
                   help="sweep the robot's atlas (workspace area, dexterity) instead of the study")
    p.add_argument("--atlas-points", type=int, default=60, metavar="N",
                   help="atlas grid points per axis with --atlas (default 60)")
    p.add_argument("--out", type=Path, default=Path("results"), help="output folder")
    p.add_argument("--x", default=None, metavar="COLUMN", help="plot against this column")
    p.add_argument("--figure", action="append", default=None, metavar="COLUMN",
                   help="plot this figure (repeatable; default the peak torques)")
    p.set_defaults(fn=run)


def parse_vary(items: list[str], random: bool, robot=None) -> dict:
    """``--vary`` options as ``sweep``'s ``vary``: names (tied by commas) to values, SI; a
    unit after the values (``m_link2=50:90:5 g``) is converted by ``robot``'s parameters'
    units, as ``--set`` and a study's [parameters] read a value typed with its unit."""
    vary, bare = {}, []
    for item in items:
        name, sep, spec = item.partition("=")
        if not sep or not name.strip() or not spec.strip():
            raise InputError(f"--vary {item!r}: write NAME=LOW:HIGH:COUNT, NAME=V1,V2,... or "
                             "NAME=LOW:HIGH (with --random)")
        spec, _, unit = spec.strip().partition(" ")
        try:
            numbers = [float(v) for v in spec.replace(":", ",").split(",")]
        except ValueError:
            raise InputError(f"--vary {item!r}: {spec!r} is not numbers") from None
        if not unit.strip():
            bare.append((item, name))
        else:
            scale = _unit_scale(item, name.split(","), unit.strip(), robot)
            grid = ":" in spec and not random and len(numbers) == 3  # its count is a count
            numbers = [v * scale for v in numbers[:2]] + numbers[2:] if grid else [
                v * scale for v in numbers]
        if ":" in spec:
            want = 2 if random else 3
            if len(numbers) != want:
                raise InputError(f"--vary {item!r}: {'LOW:HIGH' if random else 'LOW:HIGH:COUNT'}"
                                 f" expected {'with --random' if random else 'on a grid'}")
            value = tuple(numbers)
        else:
            value = numbers
        key = name.strip()
        if key in vary:  # a dict would keep the last silently (a user's grid vanished)
            raise InputError(f"--vary {item!r}: {key!r} is varied twice (give its values in one "
                             "--vary, e.g. NAME=V1,V2,V3)")
        vary[key] = value
    _refuse_ambiguous(bare, robot)
    return vary


def _refuse_ambiguous(bare: list[tuple[str, str]], robot) -> None:
    """A bare number is SI here, but in the description's own units in a study's [parameters]
    and in ``--set``: where those differ (a description in mm or g) the same typed number
    would be 1000 times another value by route, so its unit must be written."""
    from ..model.parameter_set import QUANTITY
    from ..model.units import UNITS
    from ..study.parameters import description_units

    units = description_units(robot) if robot is not None and bare else None
    if not units:
        return
    known = {p.name: p.unit for p in robot.parameter_list}
    problems = []
    for item, names in bare:
        for name in names.split(","):
            quantity = QUANTITY.get(known.get(name.strip(), ""))
            own = units.get(quantity) if quantity else None
            if UNITS.get(quantity, {}).get(own, 1.0) != 1.0:
                problems.append(f"--vary {item!r}: {robot.name}'s description gives "
                                f"{quantity} in {own}, where --vary reads a bare number in SI "
                                f"({known[name.strip()]}) and --set and a study's [parameters] "
                                f"read it in {own}: write the unit after the values, e.g. "
                                f"'{item} {own}' or '{item} {known[name.strip()]}'")
                break
    if problems:
        raise InputError(problems[0] if len(problems) == 1 else
                         "ambiguous --vary values:\n  " + "\n  ".join(problems))


def _unit_scale(item: str, names: list[str], unit: str, robot) -> float:
    """SI per ``unit`` for the parameters ``names`` (tied ones share a quantity)."""
    from ..model.parameter_set import QUANTITY
    from ..model.units import factor

    known = {p.name: p.unit for p in robot.parameter_list} if robot is not None else {}
    kinds = {QUANTITY.get(known.get(n.strip(), ""), "") for n in names}
    if len(kinds) != 1 or "" in kinds:
        raise InputError(f"--vary {item!r}: a unit needs parameters of one quantity the units "
                         f"table knows (mass, length, inertia, angle, acceleration; "
                         f"{', '.join(n.strip() for n in names)} are not)")
    kind = kinds.pop()
    try:
        return factor(kind, unit)
    except KeyError as exc:
        raise InputError(f"--vary {item!r}: {exc.args[0]} for a {kind}") from None


def run(args) -> int:
    from ..analysis.sweep import ON, sweep
    from ..outputs.sweep_plots import write_sweep
    from ..study.run import load_study
    from .run import check_out

    check_out(args.out)
    if sum(x is not None for x in (args.processes, args.scheduler)) > 1:
        raise InputError("give --processes or --scheduler, not both")
    if args.atlas_points < 2:
        raise InputError(f"--atlas-points must be >= 2 (got {args.atlas_points})")
    if args.on not in ON:
        raise InputError(f"--on {args.on!r}: choose {', '.join(ON[:-1])} or {ON[-1]}")
    st = load_study(args.study)
    if args.parameters:
        return _list_parameters(st)
    if not args.vary:
        raise InputError("say what varies: --vary NAME=LOW:HIGH:COUNT (names: --parameters)")
    from ..study.run import robot_of

    vary = parse_vary(args.vary, args.random is not None, robot_of(st))
    executor = _executor(args)
    start = time.perf_counter()
    meter = Meter(0, f"{st.name}: designs", quiet=args.quiet)  # the sweep tells the count
    try:
        result = sweep(st, vary, sample="random" if args.random is not None else "grid",
                       count=args.random, seed=args.seed, executor=executor,
                       workers=args.workers, on=args.on, progress=meter,
                       atlas={"points": args.atlas_points} if args.atlas else None)
    except InputError as exc:  # in the command line's words: --vary NAME, not vary['NAME']
        text = re.sub(r"vary\['([^']+)'\]", r"--vary \1", str(exc))
        if text == str(exc):
            raise
        raise InputError(text) from None
    finally:
        meter.close()
        if executor is not None:
            # a Dask client is closed, never shut down: Client.shutdown would stop the user's
            # scheduler and workers too
            (getattr(executor, "close", None) or executor.shutdown)()
    took = time.perf_counter() - start
    csv, png = args.out / f"{st.name}_sweep.csv", args.out / f"{st.name}_sweep.png"
    # with every design failed there is nothing to plot: the table still says why
    paths = write_sweep(result, csv, png if result.figures else None, x=args.x,
                        figures=args.figure)
    lost = sum(why.startswith("worker error") for why in result.failed.values())
    if not args.quiet:
        print(f"{st.name}: {result.note}, {took:.3g} s")
        for name in result.figures:
            v = result.columns[name]
            v = v[np.isfinite(v)]
            if len(v):
                print(f"  {name}: {v.min():.6g} to {v.max():.6g}")
        for path in paths:
            print(f"  wrote {path}")
    # the sweep's warning named the first: the next four here, the rest in the CSV
    for k, why in list(result.over_limits.items())[1:5]:
        print(f"design {k}: over a limit: {why}", file=sys.stderr)
    if len(result.over_limits) > 5:
        print(f"... and {len(result.over_limits) - 5} more designs over a limit (see the CSV's "
              "limits column)", file=sys.stderr)
    for k, why in list(result.failed.items())[:5]:
        print(f"design {k}: {why}", file=sys.stderr)
    if len(result.failed) > 5:
        print(f"... and {len(result.failed) - 5} more failed designs (see the CSV's error column)",
              file=sys.stderr)
    return 1 if lost or not result.figures else 0


def _list_parameters(st) -> int:
    from ..study.run import robot_of

    robot = robot_of(st)
    print(f"{robot.name} (as {st.name} sets it): parameters in SI")
    for par, v in zip(robot.parameter_list, robot.p):
        print(f"  {par.name:<24} {v:<14.6g} {par.unit:<8} {par.meaning}")
    return 0


def _executor(args):
    if args.processes is not None:
        if args.processes < 1:
            raise InputError(f"--processes must be >= 1 (got {args.processes})")
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        # spawn, not fork: a forked child would inherit this process's threads and locks
        return ProcessPoolExecutor(args.processes, mp_context=multiprocessing.get_context("spawn"))
    if args.scheduler is not None:
        try:
            from dask.distributed import Client
        except ImportError:
            raise InputError("--scheduler needs dask.distributed: pip install "
                             "'planar-sym[cluster]'") from None
        try:
            return Client(args.scheduler, timeout=10)
        except OSError as exc:
            raise InputError(f"--scheduler {args.scheduler}: cannot reach it ({exc})") from None
    return None
