"""motion/closure.py by value: continuation along the loops and its refusals, each named.

- A parallelogram four-bar (tests/robots/parallelogram.toml) driven through its change point
  (crank angle 0, every link in one line): the parallelogram and antiparallelogram branches
  meet there, so a motion through it is refused at any sampling, never continued silently on
  either branch (before, 4 samples from 0.3 to -0.3 rad went through without a word).
- Stopped short of it, the parallelogram is kept: the rocker turns with the crank and the
  coupler keeps its angle (the closed form of this mode), to 1e-9 rad.
- A target outside the workspace at the first sample and at a later one, with and without
  times; the passive rates at a singular pose, by time.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import WorkspaceError
from planar_sym.motion import closure

ROBOTS = Path(__file__).parent / "robots"


@pytest.fixture(scope="module")
def parallelogram():
    return ps.load(ROBOTS / "parallelogram.toml")


@pytest.mark.parametrize("n", [2, 3, 4, 7, 101])
def test_a_change_point_is_met_and_refused_at_any_sampling(parallelogram, n):
    t = np.linspace(0.0, 1.0, n)
    crank = np.linspace(0.3, -0.3, n)[:, None]
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(parallelogram, crank, None, t)
    msg = str(exc.value)
    k = int(np.argmax(crank[:, 0] <= 0.0))  # the first sample at or past the change point
    between = (rf"between t = {t[k - 1]:.6g} s \(sample {k - 1}\) and t = {t[k]:.6g} s "
               rf"\(sample {k}\)")
    got = re.fullmatch(rf"parallelogram: singular pose {between}: the passive-joint constraint "
                       r"Jacobian Phi_p has 1-norm condition number [0-9.e+]+ > 1e\+06 \(actuated "
                       r"coordinates there: \[([0-9.e+-]+)\] \(rad; crank_joint = ([0-9.e+-]+) "
                       r"deg\)\): the actuated joints cannot drive the loops through this pose "
                       r"\(a dead point .*\); end the motion short of it, or drive another joint",
                       msg)
    assert got, msg  # where: at the change point (crank 0), in rad and in degrees
    assert abs(float(got[1])) < 1e-4 and float(got[2]) == pytest.approx(
        np.degrees(float(got[1])), rel=1e-3)  # (the rad figure is rounded to 1e-9)


@pytest.mark.parametrize("n", [2, 3, 5, 41])
def test_short_of_it_the_parallelogram_is_kept(parallelogram, n):
    t = np.linspace(0.0, 1.0, n)
    crank = np.linspace(1.0, 0.02, n)[:, None]  # from 57 deg down to 1.1 deg
    q = closure.solve_passive(parallelogram, crank, None, t)
    wrapped = np.angle(np.exp(1j * (q[:, 2] - crank[:, 0])))  # rocker absolute = crank
    # (to 1e-9 rad: the file's coordinates are rounded to 1e-9 mm, and near the change point
    # Newton's 1e-13 m residual is an angle error of 1e-13 m / (40 mm sin 0.02))
    assert np.max(np.abs(wrapped)) < 1e-9
    assert np.max(np.abs(np.angle(np.exp(1j * (q[:, 1] + crank[:, 0]))))) < 1e-9
    assert np.max(np.abs(q[1:] - q[:-1])) < 1.0  # continued: no 2 pi jumps between samples


def test_outside_the_workspace_is_named_by_sample_and_time():
    five = ps.load("five_bar_type2")
    unit = (r"\(rad, rad; A = [0-9.e+-]+ deg, E = [0-9.e+-]+ deg\) \(\|Phi\| = [0-9.e+-]+ m\): "
            r"outside the workspace")
    far = np.array([[np.pi, 0.0]])  # the proximal links cannot reach each other's elbows
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(five, far, None, np.array([0.25]))
    assert re.fullmatch(r"five_bar_type2: the loops cannot be closed at t = 0.25 s \(sample 0\) "
                        rf"for actuated coordinates \[3.141592654, 0.0\] {unit}",
                        str(exc.value)), str(exc.value)
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(five, far)
    assert str(exc.value).startswith("five_bar_type2: the loops cannot be closed at sample 0 ")
    t = np.linspace(0.0, 1.0, 5)  # past the stretched pose: the loops cannot close beyond it
    crank = np.column_stack([np.linspace(0.0, 2 * np.pi / 3, 5), np.full(5, np.pi / 2)])
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(five, crank, None, t)
    assert re.fullmatch(r"five_bar_type2: the loops cannot be closed at t = 0.75 s \(sample 3\) "
                        rf"for actuated coordinates \[1.570796327, 1.570796327\] {unit}"
                        r"|five_bar_type2: singular pose (between t = 0.5 s \(sample 2\) and |at )"
                        r"t = 0.75 s \(sample 3\): .*", str(exc.value)), str(exc.value)


def test_passive_rates_at_a_singular_pose_are_refused_by_time():
    """complete_rates on its own (states given by hand): the slider-driven slider-crank on its
    loop (closed form) at a crank 0.3 rad and 1e-7 rad from its dead centre, where Phi_p is
    singular; the second sample is named by its time."""
    robot = ps.load("slider_crank_slider_driven")
    p = robot.parameters
    r, length, s0 = p["px_crank_A"], p["px_rod_B"], p["s0_slide"]
    theta = np.array([0.3, 1e-7])
    x = r * np.cos(theta) + np.sqrt(length**2 - (r * np.sin(theta)) ** 2)
    phi = np.arctan2(-r * np.sin(theta), x - r * np.cos(theta))
    q = np.column_stack([theta, phi - theta, x - s0])
    zero = np.zeros((2, 1))
    with pytest.raises(WorkspaceError) as exc:
        closure.complete_rates(robot, q, zero, zero, t=np.array([0.0, 0.5]))
    assert re.fullmatch(r"slider_crank_slider_driven: singular pose at t = 0.5 s \(sample 1\): "
                        r"the passive-joint constraint Jacobian Phi_p has condition number "
                        r"[0-9.e+]+ > 1e\+06", str(exc.value)), str(exc.value)
    qd, _ = closure.complete_rates(robot, q[:1], [[0.1]], [[0.0]])
    assert np.all(np.isfinite(qd)) and qd[0, 2] == 0.1
