"""``planar-sym move ROBOT``: one move without a study file, e.g.

.. code:: text

    planar-sym move five_bar_type1 --task --from 60.852,154.665 --by 30,30 --duration 1.5
    planar-sym move serial_2dof --joint --from 0,0 --to 90,45 --duration 2 --profile quintic \\
        --set m_motor2=0.5

Numbers are in mm and deg unless ``--length`` / ``--angle`` say otherwise (task phi and joint
angles in the angle unit). Negative values need the ``=`` form: ``--by=-200,0``. The move is
checked exactly as a study file is (``--save-study FILE`` writes that file).
"""

from __future__ import annotations

import os
import re
import warnings
from contextlib import contextmanager
from pathlib import Path

from ..errors import InputError, WorkspaceError


def register(sub) -> None:
    p = sub.add_parser("move", help="one move of a robot (no study file): torques along a "
                                    "task- or joint-space profile")
    p.add_argument("robot", help="built-in robot name, a description file (.toml) or a "
                                 "generated folder")
    space = p.add_mutually_exclusive_group(required=True)
    space.add_argument("--task", dest="space", action="store_const", const="task",
                       help="move the task point (x, y[, phi])")
    space.add_argument("--joint", dest="space", action="store_const", const="joint",
                       help="move the joints (the actuated joints of a closed chain)")
    p.add_argument("--from", dest="start", required=True, metavar="A,B[,...]",
                   help="start, comma-separated, in --length and --angle units (default mm, "
                        "deg): the task point's x, y (and phi) with --task, the joints' "
                        "coordinates with --joint")
    end = p.add_mutually_exclusive_group(required=True)
    end.add_argument("--by", metavar="A,B[,...]", help="displacement (use --by=-200,0 for "
                                                       "negative values)")
    end.add_argument("--to", metavar="A,B[,...]", help="end position (the units of --from)")
    p.add_argument("--duration", type=float, required=True, help="seconds")
    p.add_argument("--start-pose", default=None, metavar="Q1,Q2[,...]",
                   help="a task move's starting joint coordinates (in --angle, --length), "
                        "which pick the assembly or elbow mode (default: from the drawn pose)")
    p.add_argument("--profile", choices=("cubic", "quintic"), default="cubic",
                   help="cubic (the seed's coeff_3rd, default) or quintic")
    p.add_argument("--samples", type=int, default=201, help="samples (default 201)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="parameter override, e.g. m_motor2=0.5 (description units) or "
                        "m_motor2='500 g'; repeatable")
    p.add_argument("--length", default="mm", help="length unit of the numbers (default mm)")
    p.add_argument("--angle", default="deg", help="angle unit of the numbers (default deg)")
    p.add_argument("--ik", choices=("auto", "seed", "newton"), default=None,
                   help="inverse kinematics for --task (default auto: the seed's closed form "
                        "for its robots, else Newton)")
    p.add_argument("--name", default=None, help="result name (default ROBOT_move)")
    p.add_argument("--out", type=Path, default=Path("results"),
                   help="output folder (default results)")
    p.add_argument("--split", action="store_true", help="also write the torque split plot")
    p.add_argument("--animate", action="store_true", help="also write NAME.gif")
    p.add_argument("--save-study", type=Path, default=None, metavar="FILE",
                   help="also write the equivalent study file")
    p.set_defaults(fn=run)


def _vector(text: str, option: str) -> list[float]:
    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise InputError(f"{option} must be comma-separated numbers (got {text!r})") from None


def study_table(args) -> dict:
    """The study file's table that this command line stands for."""
    motion = {"space": args.space, "profile": args.profile,
              "start": _vector(args.start, "--from"), "duration": args.duration,
              "samples": args.samples}
    if args.by is not None:
        motion["by"] = _vector(args.by, "--by")
    else:
        motion["end"] = _vector(args.to, "--to")
    if args.ik is not None:
        motion["ik"] = args.ik
    if args.start_pose is not None:
        motion["start_pose"] = _vector(args.start_pose, "--start-pose")
    params = {}
    for item in args.set:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise InputError(f"--set must be NAME=VALUE (got {item!r})")
        if key.strip() in params:  # as with an option given twice: the last would win
            raise InputError(f"--set {key.strip()} is given more than once: give it once")
        value = value.strip()
        try:
            params[key.strip()] = float(value)
        except ValueError:
            number = value.rstrip("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ*^/2 ")
            params[key.strip()] = f"{number} {value[len(number):].strip()}"
    robot = args.robot
    if "/" in robot or robot.endswith(".toml"):
        robot = str(Path(robot).resolve())
    table = {"title": f"{args.robot}: {args.space}-space {args.profile} move",
             "robot": robot, "kind": "inverse",
             "units": {"length": args.length, "angle": args.angle}, "motion": motion,
             "outputs": {"split": args.split, "animation": "gif" if args.animate else False}}
    if params:
        table["parameters"] = params
    return table


def run(args) -> int:
    from ..study import spec
    from .run import check_out, report, simulation_clock, write_study

    check_out(args.out)
    name = args.name or f"{Path(args.robot).stem}_move"
    table = study_table(args)
    with _in_options():
        st = spec.parse(table, name)
    if args.save_study is not None:
        from ..files import atomic_files
        from ..toml_write import dumps

        saved = dict(table)
        if Path(saved["robot"]).is_absolute():  # a study's paths are relative to the study
            saved["robot"] = Path(os.path.relpath(
                saved["robot"], Path(args.save_study).resolve().parent)).as_posix()
        with atomic_files([args.save_study]) as (tmp,):
            tmp.write_text(dumps(saved))
    with simulation_clock(name, args.quiet), _in_options():
        done = write_study(st, args.out, quiet=args.quiet)
    report(done, name, args.quiet)
    return 0


#: the study fields this command line fills, and the options that fill them
_OPTION_OF = {"motion.duration": "--duration", "motion.start": "--from", "motion.by": "--by",
              "motion.end": "--to", "motion.samples": "--samples", "motion.profile": "--profile",
              "motion.ik": "--ik", "units.angle": "--angle", "units.length": "--length",
              "q_start, or a study's motion.start_pose": "--start-pose",
              "motion.start_pose": "--start-pose", 'space = "joint"': "--joint",
              "parameters.": "--set ", "parameters": "--set", "invalid study": "invalid move"}


@contextmanager
def _in_options():
    """Errors and warnings in the words of the command line: the study it builds is not the
    user's file, so ``motion.duration: must be > 0`` is said of ``--duration`` (and a doubtful
    ``--set`` value is not said of "parameters": a trial)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield
        except (InputError, WorkspaceError) as exc:
            text = _words(str(exc))
            if text == str(exc):
                raise
            raise (WorkspaceError if isinstance(exc, WorkspaceError) else InputError)(
                text) from None
        finally:
            said = [(w, _words(str(w.message))) for w in caught]
    for w, text in said:  # as given, now under the caller's filters
        warnings.warn_explicit(text, w.category, w.filename, w.lineno)


def _words(text: str) -> str:
    for fld, option in _OPTION_OF.items():
        text = re.sub(rf"(?<![\w.]){re.escape(fld)}(?![\w])" if not fld.endswith(".")
                      else rf"(?<![\w.]){re.escape(fld)}", option, text)
    return text
