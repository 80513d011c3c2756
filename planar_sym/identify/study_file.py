"""An excitation as a study: ``STUDY.toml`` (an inverse study, joint space, a table motion)
and its table ``STUDY_motion.csv`` (t_s and the actuated joints' coordinates, every joint of a
tree), written together or not at all."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..files import atomic_files
from ..model.robot import Robot
from .excite import Excitation


def write_excitation(robot: Robot, robot_ref: str, ex: Excitation, out: Path,
                     rate_hz: float) -> tuple[Path, Path]:
    """Write the study and its table; ``robot_ref`` is how the user named the robot (a
    description file is referred to from the study's folder)."""
    out = Path(out)
    table = out.with_name(out.stem + "_motion.csv")
    period = ex.fourier.period_s
    n = round(period * rate_hz) + 1
    t = np.linspace(0.0, period, n)
    q, _, _ = ex.fourier(t)
    coords = list(robot.actuated) if robot.is_closed_chain else list(range(robot.n))
    if not robot.is_closed_chain:  # a tree: every joint is actuated here (else refused)
        q = q[:, [list(robot.actuated).index(i) for i in coords]]
    head = ["t_s"] + [f"q{i + 1}_{robot.coordinate_units[i]}" for i in coords]
    rows = [",".join(head)] + [",".join(repr(float(v)) for v in (tt, *row))
                               for tt, row in zip(t, q)]
    ref = robot_ref
    if robot_ref.endswith(".toml"):
        ref = os.path.relpath(Path(robot_ref).resolve(), out.resolve().parent)
    text = "\n".join([
        (f'title = "Exciting motion of {robot.name} for identification: '
         f'{ex.fourier.a.shape[1]} harmonics, period {period:g} s, condition number '
         f'{ex.condition:.3g}"'),
        f"robot = {ref!r}".replace("'", '"'),
        'kind = "inverse"',
        "",
        "# a finite Fourier series per actuated joint (planar_sym.identify.fourier), sampled at",
        f"# {rate_hz:g} Hz: planar-sym run gives its torques, planar-sym identify reads them",
        "[motion]",
        'space = "joint"',
        'profile = "table"',
        f'file = "{table.name}"',
        f"samples = {n}",
        "",
        "[outputs]",
        "csv = true",
        ""])
    with atomic_files([table, out]) as (tmp_table, tmp_study):
        tmp_table.write_text("\n".join(rows) + "\n")
        tmp_study.write_text(text)
    return out, table
