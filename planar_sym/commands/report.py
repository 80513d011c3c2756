"""``planar-sym report STUDY... --out DIR``: the user's own studies run (as ``run`` runs them),
their robots drawn, and ``DIR/index.html`` (``outputs.html_index``, the page ``demo`` writes)
showing them: plots, actuator sizing, tracking errors, drawings, equations, and the atlas maps
and sweep tables already in DIR."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path

from ..errors import InputError, PlanarSymError

ABOUT = ("Run studies, given as study files (.toml) or built-in study names (see `planar-sym "
         "list`), write their files as `planar-sym run` does, draw their robots, and write "
         "DIR/index.html: one page that opens with no network and shows each study's plots "
         "(each a link to the full-size file), its actuator sizing and, for a control study, "
         "its tracking errors, and each robot's drawing and equations (robots of your own "
         "included, read from their description files). Atlas maps (`planar-sym atlas --out "
         "DIR`) and sweep tables (`planar-sym sweep --out DIR`) already in DIR are shown too.")


def register(sub) -> None:
    p = sub.add_parser("report", description=ABOUT,
                       help="run study files (.toml) or built-in study names and write "
                            "DIR/index.html: plots, sizing, robots' drawings and equations")
    p.add_argument("studies", nargs="+", metavar="STUDY",
                   help="a study file (.toml) or a built-in study name (see `list`)")
    p.add_argument("--out", type=Path, default=Path("results"), metavar="DIR",
                   help="output folder: the studies' files and index.html (default results)")
    p.add_argument("--samples", type=int, default=None,
                   help="evenly spaced samples, overriding the studies' (2 to 1000000)")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..outputs.animation import writer_for
    from ..outputs.html_index import write_index
    from ..study.run import load_study
    from .draw import save_drawing
    from .run import check_out, check_samples, report, write_result

    check_samples(args.samples)
    check_out(args.out)
    studies = [load_study(r) for r in args.studies]  # every file checked before anything runs
    names = [st.name for st in studies]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InputError(f"studies named alike ({', '.join(twice)}): their files would "
                         "overwrite each other; give each once, or rename a study file")
    for st in studies:
        if st.outputs.animation:  # a missing writer (mp4 without ffmpeg) fails before any run
            writer_for(Path(f"{st.name}.{st.outputs.animation}"), 20.0)
    results = [_run(st, args.samples) for st in studies]  # all run before any file is written
    robots = {}  # robot name -> what to read it from: its description file, or built-in name
    for st, result in zip(studies, results):
        robots.setdefault(result.robot, st.robot)
    clash = set(robots) & set(names)
    if clash:  # the drawing ROBOT.png would replace the study's plot STUDY.png
        raise InputError(f"{', '.join(sorted(clash))}: a study and its robot have the same "
                         "name, so the drawing would replace the study's plot; rename the "
                         "study file")
    out = Path(args.out)
    for st, result in zip(studies, results):
        report(write_result(st, result, out, quiet=args.quiet), st.name, args.quiet)
    for name, source in robots.items():
        try:
            save_drawing(source, out / f"{name}.png")
        except PlanarSymError as exc:  # e.g. a generated folder without its description
            print(f"{name}: warning: not drawn: {exc}", file=sys.stderr)
    made_by = "planar-sym report " + shlex.join(map(str, args.studies))
    page = write_index(results, robots, out, made_by=made_by, link=True)
    if not args.quiet:
        print(f"wrote {page}: {len(results)} stud{'y' if len(results) == 1 else 'ies'}, "
              f"{len(robots)} robot{'' if len(robots) == 1 else 's'}")
    return 0


def _run(st, samples):
    """``st`` run; a failure names the study file (a run's error names the time or field)."""
    from ..study.run import run as run_study

    try:
        return run_study(st, samples)
    except PlanarSymError as exc:
        where = str(st.path or st.name)
        if where in str(exc):
            raise
        raise PlanarSymError(f"{where}: {exc}") from exc
