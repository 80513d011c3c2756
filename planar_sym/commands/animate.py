"""``planar-sym animate``: a scenario's mechanism moving, as a GIF (or MP4 with ffmpeg)."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

from ..errors import InputError

#: formats ``animate`` writes, and the matplotlib writer of each
WRITERS = {".gif": "pillow", ".mp4": "ffmpeg"}


def register(sub) -> None:
    p = sub.add_parser("animate", help="animate a scenario's motion into a GIF (or MP4)")
    p.add_argument("scenario", help="scenario name (see `list`)")
    p.add_argument("--out", type=Path, default=None,
                   help="animation file, .gif (or .mp4 where ffmpeg is installed); "
                        "default SCENARIO.gif")
    p.add_argument("--frames", type=int, default=60, help="frames, evenly spaced in time (default 60)")
    p.add_argument("--fps", type=float, default=20.0, help="frames per second of playback (default 20)")
    p.add_argument("--dpi", type=int, default=80, help="pixels per inch; frames are 5.6 x 4.6 in (default 80)")
    p.set_defaults(fn=run)


def run(args) -> int:
    out = args.out or Path(f"{args.scenario}.gif")
    write_animation(args.scenario, out, frames=args.frames, fps=args.fps, dpi=args.dpi)
    if not args.quiet:
        print(f"{args.scenario}: wrote {out} ({args.frames} frames at {args.fps:g} fps)")
    return 0


def writer_for(path: Path, fps: float):
    """The matplotlib writer for ``path``'s suffix; refuses what cannot be written here."""
    from matplotlib import animation

    suffix = path.suffix.lower()
    if suffix not in WRITERS:
        raise InputError(f"--out must end in .gif or .mp4 (got {path.name!r})")
    if not animation.writers.is_available(WRITERS[suffix]):
        raise InputError(f"{path.name}: writing {suffix} needs ffmpeg, which is not installed "
                         "(not on PATH); write a .gif instead, or install ffmpeg")
    if not (fps > 0 and math.isfinite(fps)):
        raise InputError(f"--fps must be a positive number (got {fps})")
    return animation.writers[WRITERS[suffix]](fps=fps)


def write_animation(name: str, path: Path, frames: int = 60, fps: float = 20.0,
                    dpi: int = 80, figsize: tuple[float, float] = (5.6, 4.6)) -> Path:
    """Animate scenario ``name`` into ``path``: one file, written whole or not at all.

    Parameters
    ----------
    name : str
        Scenario; forward dynamics shows the simulated q, inverse dynamics the full joint
        trajectory (passive joints of closed chains included).
    path : Path
        ``.gif`` (Pillow) or ``.mp4`` (ffmpeg).
    frames : int
        Frames, evenly spaced over the scenario's duration, >= 2.
    fps : float
        Playback frames per second.
    dpi : int
        Pixels per inch; the frame is ``figsize * dpi`` pixels.
    figsize : (float, float)
        Frame size in inches.
    """
    from matplotlib.animation import FuncAnimation

    from ..files import atomic_files
    from ..model.description import load as load_description
    from ..outputs.drawing import MM, Scene, geometry
    from ..outputs.plots import new_figure, tight
    from ..study.scenarios import get, motion

    path = Path(path)
    sc = get(name)
    writer = writer_for(path, fps)  # before any work: a bad request costs nothing
    if dpi <= 0:
        raise InputError(f"--dpi must be positive (got {dpi})")
    robot, t, q = motion(name, frames)
    desc = load_description(sc.robot)
    geo = geometry(desc, robot.body_names, robot.frames(q))
    fig = new_figure(figsize)
    ax = fig.add_subplot()
    scene = Scene(ax, desc, geo, labels=False)
    tip = geo.points[desc.task_point] * MM
    ax.plot(tip[:, 0], tip[:, 1], ":", color="crimson", lw=0.8, alpha=0.6)  # the whole path
    trace, = ax.plot([], [], "-", color="crimson", lw=1.6, zorder=8)
    stamp = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", family="monospace")
    # enough decimals that every frame's stamp differs (GIF writers merge identical frames)
    decimals = max(2, math.ceil(-math.log10(t[1] - t[0])))
    ax.set_title("\n".join([name, *textwrap.wrap(sc.summary, 75)]), fontsize=7)
    tight(fig)

    def update(k: int) -> list:
        trace.set_data(tip[:k + 1, 0], tip[:k + 1, 1])
        stamp.set_text(f"t = {t[k]:.{decimals}f} s")
        return [*scene.show(k), trace, stamp]

    anim = FuncAnimation(fig, update, frames=len(t), interval=1000.0 / fps, blit=False)
    with atomic_files([path]) as (tmp,):
        anim.save(tmp, writer=writer, dpi=dpi)
    return path
