"""A GIF's frames are drawn by blitting (``outputs.animation.blitted_frames``: the still figure
once, then only the moving artists per frame); each must be the picture matplotlib's full
render of the same figure gives (``savefig``, what ``Animation.save`` grabs per frame), on a
robot with a faint reference behind it (a tracking study) and on a closed chain."""

from __future__ import annotations

import io

import numpy as np
import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.outputs.animation import blitted_frames, scene_figure, write_animation

DPI = 60


def _full_renders(robot, t, q, ref) -> list[np.ndarray]:
    fig, update = scene_figure(robot, t, q, "a title", reference=ref)
    out = []
    for k in range(len(t)):
        update(k)
        buf = io.BytesIO()
        fig.savefig(buf, format="rgba", dpi=DPI)
        w, h = (np.array(fig.get_size_inches()) * DPI).astype(int)
        out.append(np.frombuffer(buf.getvalue(), np.uint8).reshape(h, w, 4)[..., :3])
    return out


@pytest.mark.parametrize("robot_name, reference", [("serial_2dof", True), ("five_bar_type1", False)])
def test_blitted_frames_are_the_full_renders(robot_name, reference):
    robot = ps.load(robot_name)
    t = np.linspace(0.0, 1.0, 6)
    q0 = np.asarray(robot.q_drawn)
    q = q0 + np.outer(np.sin(t), np.full(robot.n, 0.02))
    if robot.is_closed_chain:  # a motion on the loops: the actuated joints turned, the rest solved
        from planar_sym.motion.closure import from_actuated

        qa = q0[list(robot.actuated)] + np.outer(t, [0.1, -0.1])
        rate = np.tile([0.1, -0.1], (len(t), 1))
        q = from_actuated(robot, t, qa, rate, np.zeros_like(rate)).q
    ref = (robot, q + 0.05) if reference else None
    fig, update = scene_figure(robot, t, q, "a title", reference=ref)
    fast = [np.asarray(f) for f in blitted_frames(fig, update, len(t), DPI)]
    full = _full_renders(robot, t, q, ref)
    assert len(fast) == len(full) == len(t)
    for k, (a, b) in enumerate(zip(fast, full)):
        assert a.shape == b.shape, k
        # pixel for pixel: the still artists above the moving ones (labels, the legend) are
        # redrawn over them per frame, in the full render's order
        assert np.array_equal(a, b), (k, np.abs(a.astype(int) - b.astype(int)).max())
    assert not np.array_equal(fast[0], fast[-1])  # the frames do move


def test_the_gif_holds_every_frame_at_its_size(tmp_path):
    from PIL import Image

    robot = ps.load("serial_2dof")
    t = np.linspace(0.0, 1.0, 7)
    q = np.asarray(robot.q_drawn) + np.outer(t, [0.3, -0.2])
    path = write_animation(robot, t, q, tmp_path / "a.gif", "a title", fps=10, dpi=DPI)
    with Image.open(path) as im:
        assert im.n_frames == 7 and im.size == (int(5.6 * DPI), int(4.6 * DPI))
        assert im.info["duration"] == 100 and im.info["loop"] == 0
    assert ROOT.is_dir()


def test_frames_that_would_not_fit_in_memory_are_refused_before_drawing():
    """A GIF's frames are held until it is written: 2000 frames at 600 dpi would be 55.64 GB
    (3360 x 2760 pixels x 3 bytes each); refused with the size, before any work. 70 frames
    there (1.95 GB) fit."""
    from planar_sym.errors import InputError
    from planar_sym.outputs.animation import check_frames

    with pytest.raises(InputError, match=r"--frames 2000 at --dpi 600 would hold 55\.64 GB of "
                                         r"images in memory \(limit 2 GB\)"):
        check_frames(2000, 600)
    check_frames(70, 600)
    with pytest.raises(InputError, match=r"would hold 2\.003 GB"):
        check_frames(72, 600)
