"""A mechanism moving: any robot along any joint motion, as a GIF (or MP4 with ffmpeg)."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..files import atomic_files
from ..model.robot import Robot
from .resolution import check_dpi

#: formats written, and the matplotlib writer of each
WRITERS = {".gif": "pillow", ".mp4": "ffmpeg"}
#: frames above this are refused: each frame costs about 30 ms (drawn and encoded) and its
#: image is held in memory until the file is written (2000 frames at 80 dpi: about 1 GB)
MAX_FRAMES = 2000


#: frames per second a picture format can hold: a GIF stores each frame's delay in 1/100 s
#: as a 16-bit number (10 ms to 655 s); 0.1 fps is a frame every 10 s
FPS_MIN, FPS_MAX = 0.1, 100.0


def writer_for(path: Path, fps: float):
    """The matplotlib writer for ``path``'s suffix; refuses what cannot be written here."""
    from matplotlib import animation

    suffix = path.suffix.lower()
    if suffix not in WRITERS:
        raise InputError(f"--out must end in .gif or .mp4 (got {path.name!r})")
    if not animation.writers.is_available(WRITERS[suffix]):
        raise InputError(f"{path.name}: writing {suffix} needs ffmpeg, which is not installed "
                         "(not on PATH); write a .gif instead, or install ffmpeg")
    if not FPS_MIN <= fps <= FPS_MAX:  # (NaN fails too)
        raise InputError(f"--fps must be a number from {FPS_MIN:g} to {FPS_MAX:g} (got {fps:g})")
    return animation.writers[WRITERS[suffix]](fps=fps)


#: a GIF's frames are held in memory until it is written: refused beyond this, before drawing
MEMORY_LIMIT_GB = 2.0
#: the animation's size in inches (frames are this times the dpi in pixels)
FIGSIZE = (5.6, 4.6)


def check_frames(frames: int, dpi: int, figsize: tuple[float, float] = FIGSIZE) -> None:
    """Refuse a frame count or dpi out of range, or frames that would not fit in memory."""
    if not isinstance(frames, int) or not 2 <= frames <= MAX_FRAMES:
        raise InputError(f"--frames must be an integer from 2 to {MAX_FRAMES} (got {frames})")
    check_dpi(dpi)
    need = frames * int(figsize[0] * dpi) * int(figsize[1] * dpi) * 3 / 1e9  # RGB bytes
    if need > MEMORY_LIMIT_GB:
        raise InputError(f"--frames {frames} at --dpi {dpi:g} would hold {need:.4g} GB of images "
                         f"in memory (limit {MEMORY_LIMIT_GB:g} GB): fewer frames or a lower "
                         "dpi")


def write_animation(robot: Robot, t: np.ndarray, q: np.ndarray, path: Path, title: str,
                    fps: float = 20.0, dpi: int = 80, figsize: tuple[float, float] = FIGSIZE,
                    reference: tuple[Robot, np.ndarray] | None = None, progress=None) -> Path:
    """Animate ``robot`` through the joint motion ``q`` into ``path``, whole or not at all.

    Parameters
    ----------
    robot : Robot
        Gives the body frames of each configuration (``Robot.frames``) and, with its
        description (``model.described``), the bodies' points and centres of gravity.
    t : ndarray, shape (frames,)
        Time of each frame (s).
    q : ndarray, shape (frames, n)
        Every coordinate (rad) at each frame, passive joints of closed chains included.
    path : Path
        ``.gif`` (Pillow) or ``.mp4`` (ffmpeg).
    title : str
        Shown above the mechanism.
    fps : float
        Playback frames per second.
    dpi : int
        Pixels per inch; the frame is ``figsize * dpi`` pixels.
    reference : (Robot, ndarray of shape (frames, n)), optional
        A second motion drawn faint behind the first, with its own robot: a controller's
        reference, drawn as its model (the controller's parameters) while ``robot`` is the
        plant that moved.
    progress : callable, optional
        Called with the number of frames drawn so far (``planar_sym.progress.Meter``).
    """
    from matplotlib.animation import FuncAnimation

    path = Path(path)
    writer = writer_for(path, fps)  # before any work: a bad request costs nothing
    check_frames(len(t), dpi, figsize)
    fig, update = scene_figure(robot, t, q, title, figsize, reference)
    with atomic_files([path]) as (tmp,):
        if path.suffix.lower() == ".gif":
            _write_gif(tmp, blitted_frames(fig, update, len(t), dpi, progress), fps)
        else:  # ffmpeg takes matplotlib's route: a full render per frame
            anim = FuncAnimation(fig, update, frames=len(t), interval=1000.0 / fps, blit=False)
            anim.save(tmp, writer=writer, dpi=dpi, progress_callback=None if progress is None
                      else lambda k, _n: progress(k + 1))
    return path


def scene_figure(robot: Robot, t: np.ndarray, q: np.ndarray, title: str,
                 figsize: tuple[float, float] = FIGSIZE,
                 reference: tuple[Robot, np.ndarray] | None = None):
    """(figure, update): the mechanism at ``q`` (and ``reference``, a robot and its motion,
    faint behind it), and ``update(k)`` that moves it to frame ``k`` and returns the artists
    it moved. Each robot is drawn with its own parameters (``model.described``)."""
    from ..model.described import described
    from .drawing import Scene, geometry
    from .plots import new_figure, tight

    desc = described(robot)
    geo = geometry(desc, robot.body_names, robot.frames(q))
    fig = new_figure(figsize)
    ax = fig.add_subplot()
    ghost = None
    if reference is not None:
        model, q_reference = reference
        desc_ref = described(model)
        geo_ref = geometry(desc_ref, model.body_names, model.frames(q_reference))
        before = set(ax.get_children())
        ghost = Scene(ax, desc_ref, geo_ref, labels=False)
        for artist in set(ax.get_children()) - before:
            artist.set_alpha(0.25)
        ax.plot([], [], color="grey", alpha=0.4, lw=4, label="reference")
    scene = Scene(ax, desc, geo, labels=False)
    if ghost is not None:
        ax.legend(loc="upper right", fontsize=7)
    tip = geo.points[desc.task_point] * scene.scale if desc.task_point in geo.points else None
    if tip is not None:
        ax.plot(tip[:, 0], tip[:, 1], ":", color="crimson", lw=0.8, alpha=0.6)  # the whole path
    trace, = ax.plot([], [], "-", color="crimson", lw=1.6, zorder=8)
    stamp = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", family="monospace")
    # enough decimals that every frame's stamp differs (GIF writers merge identical frames)
    decimals = max(2, math.ceil(-math.log10(t[1] - t[0])))
    ax.set_title("\n".join(textwrap.wrap(title, 75)), fontsize=7)
    tight(fig)
    scene.declutter()  # the first frame's labels apart; later ones move with their joints

    def update(k: int) -> list:
        if tip is not None:
            trace.set_data(tip[:k + 1, 0], tip[:k + 1, 1])
        stamp.set_text(f"t = {t[k]:.{decimals}f} s")
        return [*(ghost.show(k) if ghost is not None else ()), *scene.show(k), trace, stamp]

    return fig, update


def blitted_frames(fig, update, count: int, dpi: int, progress=None) -> list:
    """Each frame as an RGB image: the still parts of ``fig`` drawn once, then per frame only
    the artists ``update(k)`` moves, over a copy of that background (matplotlib's blitting);
    ``progress(k)``, if given, after the k-th frame.

    ``Animation.save`` renders the whole figure per frame (axes, ticks, labels: 30 ms at 80
    dpi); this draws it once. The frames equal the full renders' pixel for pixel
    (tests/test_animation_frames.py); the time is in benchmarks/animation.py.
    """
    from matplotlib.axis import Axis
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from PIL import Image

    fig.set_dpi(dpi)
    canvas = FigureCanvasAgg(fig)
    moving = update(0)
    # the moving artists, and every still one that lies above the lowest of them (a label, a
    # legend), drawn per frame in the order the full render draws them (zorder, then order)
    ax, low = moving[0].axes, min(a.get_zorder() for a in moving)
    layers = [a for a in ax.get_children() if a in moving or (
        a.get_zorder() >= low and a.get_visible() and not isinstance(a, Axis))]
    layers.sort(key=lambda a: a.get_zorder())  # stable: ties keep the axes' order
    for artist in layers:
        artist.set_animated(True)  # left out of the background
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    size = canvas.get_width_height()
    frames = []
    for k in range(count):
        canvas.restore_region(background)
        update(k)
        for artist in layers:
            ax.draw_artist(artist)
        rgba = Image.frombuffer("RGBA", size, bytes(canvas.buffer_rgba()), "raw", "RGBA", 0, 1)
        frames.append(rgba.convert("RGB"))
        if progress is not None:
            progress(k + 1)
    return frames


def _write_gif(path: Path, frames: list, fps: float) -> None:
    """``frames`` as a looping GIF, as matplotlib's PillowWriter writes one."""
    frames[0].save(path, format="GIF", save_all=True, append_images=frames[1:],
                   duration=int(1000 / fps), loop=0)
