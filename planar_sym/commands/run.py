"""``planar-sym run``: studies (built-in names or study files) into CSV, plots and animations."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError


def register(sub) -> None:
    p = sub.add_parser("run", help="run studies: built-in names (see `list`) or study files; "
                                   "writes STUDY.csv, STUDY.png (and more, as the study says)")
    p.add_argument("studies", nargs="*", metavar="STUDY",
                   help="built-in study name, or a study file (.toml)")
    p.add_argument("--all", action="store_true", help="run every built-in study")
    p.add_argument("--out", type=Path, default=Path("results"),
                   help="output folder (default results)")
    p.add_argument("--samples", type=int, default=None,
                   help="evenly spaced samples, overriding the study's (2 to 1000000)")
    p.add_argument("--split", action="store_true",
                   help="also plot each torque split into M qdd, C qd and g, and friction and rotors where the robot has actuator models (STUDY_split.png)")
    p.add_argument("--npz", action="store_true",
                   help="also write STUDY.npz: the CSV's columns as float64 arrays (bit for bit), "
                        "with the study's and robot's names")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..study.builtin import names
    from ..study.run import load_study

    if args.all and args.studies:
        raise InputError("name studies or give --all, not both")
    refs = names() if args.all else args.studies
    if not refs:
        raise InputError("name at least one study, or --all (see `planar-sym list`)")
    check_samples(args.samples)
    check_out(args.out)
    studies = [load_study(r) for r in refs]  # every file checked before anything runs
    for st in studies:
        with simulation_clock(st.name, args.quiet):
            done = write_study(st, args.out, args.samples, args.split, npz=args.npz,
                               quiet=args.quiet)
        report(done, st.name, args.quiet)
    return 0


def simulation_clock(name: str, quiet: bool):
    """A clock line for the study's simulations on a terminal (``progress.Clock``: shown once
    a run lasts over a second); a do-nothing context elsewhere, so pipes and logs get nothing
    and the integrator runs without a watching thread."""
    from contextlib import nullcontext

    from ..progress import Clock, watching

    clock = Clock(f"{name}: simulating", quiet=quiet)
    return watching(clock) if clock.enabled else nullcontext()


def check_samples(samples: int | None) -> None:
    from ..study.spec import MAX_SAMPLES

    if samples is not None and not 2 <= samples <= MAX_SAMPLES:
        raise InputError(f"--samples must be an integer from 2 to {MAX_SAMPLES} (got {samples})")


def check_out(out: Path) -> None:
    """``--out`` must be a folder, or a path to make one at (a file on the way was a bare
    "Not a directory" from the system: a trial)."""
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out} is a file, not a folder")
    for above in Path(out).parents:
        if above.exists() and not above.is_dir():
            raise InputError(f"--out {out}: {above} is a file, so no folder can be made "
                             "under it")


def write_study(st, out: Path, samples: int | None = None, split: bool = False,
                npz: bool = False, quiet: bool = False):
    """Run one study and write what its [outputs] asks for (and ``STUDY.npz`` with ``npz``);
    returns (result, paths)."""
    from ..study.run import run as run_study

    return write_result(st, run_study(st, samples), out, split, npz, quiet)


def write_result(st, result, out: Path, split: bool = False, npz: bool = False,
                 quiet: bool = False):
    """Write what the study's [outputs] asks for of its ``result``, already run (``report``
    runs every study before writing any); returns (result, paths)."""
    from ..outputs.results import write

    o = st.outputs
    paths = write(result, out, split=split or o.split, csv=o.csv, plot=o.plot, npz=npz)
    if o.animation:
        import warnings

        # the animation runs the study again at its frames: what that run would warn, the run
        # above has said once already (one mistake, one message)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            paths.append(animate_study(st, out / f"{st.name}.{o.animation}", o.frames,
                                       quiet=quiet))
    return result, paths


def animate_study(st, path: Path, frames: int = 60, fps: float = 20.0, dpi: int = 80,
                  figsize: tuple[float, float] = (5.6, 4.6), quiet: bool = False) -> Path:
    """The study's mechanism moving, written to ``path`` (.gif or .mp4); a progress line
    counts the frames on a terminal unless ``quiet``."""
    from ..outputs.animation import check_frames, write_animation, writer_for
    from ..study.run import motion_and_reference

    writer_for(Path(path), fps)  # a bad request fails before any work
    check_frames(frames, dpi)
    robot, t, q, reference = motion_and_reference(st, frames)
    from ..progress import Meter

    meter = Meter(len(t), f"{st.name}: drawing {Path(path).name}", quiet=quiet)
    try:
        return write_animation(robot, t, q, path, f"{st.name}: {st.title}", fps=fps, dpi=dpi,
                               figsize=figsize, reference=reference, progress=meter)
    finally:
        meter.close()


def report(done, name: str, quiet: bool) -> None:
    import sys

    result, paths = done
    for s in result.sizing:  # a limit exceeded is never silent, not even with --quiet
        for sentence in s.exceeded:
            print(f"{name}: warning: actuator limit exceeded: {sentence}", file=sys.stderr)
    for event in result.events:  # nor is an event of a controlled run
        print(f"{name}: event: {event}", file=sys.stderr)
    if quiet:
        return
    peaks = ", ".join(f"{k} {v:.4g} {unit}"
                      for k, (v, unit) in result.peak_torques_with_units().items())
    extra = f" (peak |tau|: {peaks})" if peaks else ""
    solver = f" [{result.solver}]" if result.solver else ""
    print(f"{name}: wrote {', '.join(str(p) for p in paths)}{extra}{solver}")
    if result.timing:  # an [optimise] study: the time reached
        print(f"  {result.timing}")
    from ..outputs.html_index import tracking_errors

    errors = tracking_errors(result)  # a control study: the largest error and the last one
    if errors:
        print("  tracking error: max " + ", ".join(
            f"{k} {big:.3g} {unit}" for k, big, _, unit in errors) + "; at the end "
            + ", ".join(f"{k} {end:.3g} {unit}" for k, _, end, unit in errors))
    for s in result.sizing:
        if s.gear_ratio != 1.0 or s.exceeded:
            print(f"  {s.joint}: motor peak {s.peak_motor_torque_n_m:.4g} N*m, RMS "
                  f"{s.rms_motor_torque_n_m:.4g} N*m, peak {s.peak_motor_speed_rpm:.4g} rpm "
                  f"(gear {s.gear_ratio:g}); peak power {s.peak_power_w:.4g} W")
