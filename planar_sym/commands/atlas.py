"""``planar-sym atlas ROBOT``: maps of a robot over its task plane, e.g.

.. code:: text

    planar-sym atlas five_bar_type1 --out atlas --points 120
    planar-sym atlas serial_2dof --x -210 210 --y -210 210 --step 2 --q-start 0 60
    planar-sym atlas five_bar_type1 --study five_bar_type1_move_x --accel 2
    planar-sym atlas five_bar_type1 five_bar_type2 --out atlas    # side by side: compare.png

Reachable region of the start pose's working mode (and which cells keep its assembly mode),
both kinds of singularity, dexterity, gravity torque and the torque envelope, as PNG, NPZ and
CSV. Lengths are in mm, angles in deg.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError


def register(sub) -> None:
    p = sub.add_parser("atlas", help="maps of a robot over its task plane: reachable region, "
                                     "singularities, dexterity, gravity torque and torque "
                                     "envelope (PNG, NPZ, CSV)")
    p.add_argument("robots", nargs="+", metavar="ROBOT",
                   help="built-in robot name, a description file (.toml) or a generated folder;"
                        " several: each into OUT/ROBOT/, and OUT/compare.png side by side")
    p.add_argument("--out", type=Path, default=Path("results"), help="output folder")
    p.add_argument("--x", nargs=2, type=float, metavar=("MIN", "MAX"), default=None,
                   help="x range (mm); default the reach bound around the ground pivots")
    p.add_argument("--y", nargs=2, type=float, metavar=("MIN", "MAX"), default=None,
                   help="y range (mm)")
    size = p.add_mutually_exclusive_group()
    size.add_argument("--step", type=float, default=None, metavar="MM", help="grid step (mm)")
    size.add_argument("--points", type=int, default=None, metavar="N",
                      help="points per axis (default 101 along the longer side)")
    p.add_argument("--phi", nargs="+", type=float, default=None, metavar="DEG",
                   help="platform orientations (deg) of a robot whose task has one")
    p.add_argument("--accel", type=float, default=1.0, metavar="M_S2",
                   help="size of the task acceleration of the torque envelope (m/s^2, "
                        "default 1)")
    p.add_argument("--study", default=None, metavar="NAME_OR_FILE",
                   help="an inverse-dynamics study of this robot: its path is drawn, its "
                        "start pose chooses the working mode, and envelope_along.csv/.png "
                        "are written")
    p.add_argument("--q-start", nargs="+", type=float, default=None, metavar="Q",
                   help="start pose, every coordinate (deg; mm for a slider); default the "
                        "drawn configuration (or the study's first pose)")
    p.add_argument("--length-scale", type=float, default=None, metavar="MM",
                   help="characteristic length L_c of the measures (mm); default the reach")
    p.add_argument("--dpi", type=int, default=100, help="pixels per inch of the pictures")
    p.set_defaults(fn=run)


def _mm(values, option: str):
    """A range typed in mm, checked and in m."""
    import math

    if values is None:
        return None
    lo, hi = values
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise InputError(f"{option} {lo:g} {hi:g}: give MIN MAX in mm, finite, MIN below MAX")
    return lo / 1e3, hi / 1e3


def _q_start(robot, values):
    import numpy as np

    if values is None:
        return None
    if len(values) != robot.n:
        raise InputError(f"--q-start: {robot.name} needs {robot.n} values, one per coordinate "
                         f"({', '.join(robot.coordinates)}), got {len(values)}")
    return np.array([v / 1e3 if u == "m" else np.radians(v)
                     for v, u in zip(values, robot.coordinate_units)])


def run(args) -> int:
    import numpy as np

    from ..analysis.atlas import envelope_along
    from ..model.locate import load
    from ..outputs.atlas_plots import write_atlas

    if args.out.exists() and not args.out.is_dir():
        raise InputError(f"--out {args.out} is a file, not a folder")
    from ..outputs.resolution import check_dpi

    check_dpi(args.dpi)
    for option, value in (("--step", args.step), ("--length-scale", args.length_scale)):
        if value is not None and not (np.isfinite(value) and value > 0):
            raise InputError(f"{option} must be a positive length in mm (got {value:g})")
    if len(args.robots) > 1:
        return _several(args)
    robot = load(args.robots[0])
    along = None
    q_start = _q_start(robot, args.q_start)
    if args.study is not None:
        along = envelope_along(args.study, args.accel)
        if along.robot != robot.name:
            raise InputError(f"--study {args.study} moves {along.robot}, not {robot.name}")
        from ..study.run import load_study, robot_of

        robot = robot_of(load_study(args.study))  # with the study's parameters
        q_start = along.q[0] if q_start is None else q_start
    result = _atlas(args, robot, q_start)
    paths = write_atlas(result, args.out, along, dpi=args.dpi)
    if not args.quiet:
        for path in paths:
            print(f"{robot.name}: wrote {path}")
        print(summary_text(result))
    return 0


def _atlas(args, robot, q_start):
    import numpy as np

    from ..analysis.atlas import atlas
    from ..progress import Meter

    current: list = [None, None]  # the stage and its Meter

    def progress(stage: str, done: int, total: int) -> None:
        """One line per stage on a terminal: the poses, then the measures."""
        if current[0] != stage:
            if current[1] is not None:
                current[1].close()
            what = {"poses": "solving poses (grid cells)", "measures": "measuring poses"}[stage]
            current[:] = [stage, Meter(total, f"{robot.name}: {what}", quiet=args.quiet)]
        current[1](done, total)

    try:
        return atlas(robot, _mm(args.x, "--x"), _mm(args.y, "--y"),
                     None if args.step is None else args.step / 1e3, args.points,
                     None if args.phi is None else np.radians(args.phi), q_start, args.accel,
                     None if args.length_scale is None else args.length_scale / 1e3,
                     progress=progress)
    finally:
        if current[1] is not None:
            current[1].close()


def _several(args) -> int:
    """Each robot's atlas into OUT/ROBOT/, and the comparison OUT/compare.png; every atlas is
    computed before anything is written."""
    from ..files import atomic_files
    from ..model.locate import load
    from ..outputs.atlas_compare import compare_figure
    from ..outputs.atlas_plots import write_atlas

    if args.study is not None or args.q_start is not None:
        raise InputError("--study and --q-start are for one robot: run the robots one by one")
    results = [_atlas(args, load(name), None) for name in args.robots]
    names = [r.robot for r in results]
    if len(set(names)) < len(names):
        raise InputError(f"a robot is named twice: {', '.join(names)}")
    fig = compare_figure(results)
    for result in results:
        paths = write_atlas(result, args.out / result.robot, dpi=args.dpi)
        if not args.quiet:
            print(f"{result.robot}: wrote {len(paths)} files into {args.out / result.robot}")
            print(summary_text(result))
    target = args.out / "compare.png"
    with atomic_files([target]) as (tmp,):
        fig.savefig(tmp, dpi=args.dpi, format="png")
    if not args.quiet:
        print(f"wrote {target}")
    return 0


def area_text(area_m2: float) -> str:
    """An area in the unit that keeps it between 1 and 10^4 (m^2, cm^2 or mm^2; 1.322 m^2,
    not 1.322e+04 cm^2), four significant digits."""
    for unit, scale in (("m^2", 1.0), ("cm^2", 1e4)):
        if area_m2 * scale >= 1.0:
            return f"{area_m2 * scale:.4g} {unit}"
    return f"{area_m2 * 1e6:.4g} mm^2"


def summary_text(result) -> str:
    """A few lines: area, dexterity, Type II inside, peak torques, time."""
    s = result.summary()
    lines = [(f"  reachable area {area_text(s['area_m2'])} (start assembly mode "
              f"{area_text(s['area_same_assembly_m2'])}), "
              f"{s['reachable_cells']} of {s['cells']} grid points"),
             f"  dexterity: worst {s['worst_dexterity']:.3g}, median {s['median_dexterity']:.3g}",
             (f"  Type II singularity inside the workspace: "
              f"{'yes' if s['type2_inside'] else 'no'} ({100 * s['type2_near_fraction']:.2g} % "
              "of the reachable points near one)")]
    names = [result.coordinates[i] for i in result.actuated]
    for key, what in (("peak_gravity_regular", "gravity torque"),
                      ("peak_envelope_regular", f"envelope at {result.accel_m_s2:g} m/s^2")):
        lines.append(f"  peak {what} (away from singular poses): " + ", ".join(
            f"{n} {v:.4g} {u}" for n, v, u in zip(names, s[key], s["actuator_units"])))
    if result.start_note:
        lines.append(f"  note: {result.start_note}")
    lines.append(f"  {s['time_s']:.2f} s")
    return "\n".join(lines)
