"""A closed chain's first sample is reached from the drawn pose along the loops, so it is in
the drawn assembly mode wherever the motion starts (found in a user trial).

Newton went from the drawn passive angles straight to the first sample's crank angle: the
in-line slider-crank (crank r = 0.153 m, rod l = 0.306 m, drawn at 60 degrees with the slider
on the +x side) started at 240 degrees closed with the slider at x = -352 mm, behind the crank
pivot (its other mode; torque 7% off), and the four-bar started at 120 degrees came out on the
crossed branch. The reference is the slider-crank's closed form in the drawn mode,
x = r cos(theta) + sqrt(l^2 - (r sin(theta))^2), against the slider coordinate plus the drawn
slider position; a target the loops close at in no mode is still refused as outside.
"""

from __future__ import annotations

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import WorkspaceError
from planar_sym.motion import closure

R, L = 0.153, 0.306  # m: planar_sym/robots/slider_crank.toml


def x_slider(theta):
    return R * np.cos(theta) + np.sqrt(L**2 - (R * np.sin(theta)) ** 2)


@pytest.fixture(scope="module")
def crank():
    return ps.load("slider_crank")


@pytest.mark.parametrize("deg", [60.0, 100.0, 180.0, 240.0, 300.0, -120.0])
def test_the_first_sample_keeps_the_drawn_mode(crank, deg):
    theta = np.radians(deg)
    q = closure.solve_passive(crank, [[theta]])[0]
    drawn = x_slider(crank.q_drawn[0])
    assert abs(q[2] + drawn - x_slider(theta)) < 1e-12, (q, x_slider(theta))
    assert np.max(np.abs(crank.constraint(q))) < 1e-12


def test_a_joint_move_from_far_off_the_drawn_pose(crank):
    """The user's move: 240 to 250 degrees in 5 samples; the slider on the +x side all along
    (the other mode put it at x = -352 mm)."""
    t = np.linspace(0.0, 1.0, 5)
    qa = np.radians(240.0) + np.radians(10.0) * t[:, None]
    jt = closure.from_actuated(crank, t, qa, np.full((5, 1), np.radians(10.0)), np.zeros((5, 1)))
    drawn = x_slider(crank.q_drawn[0])
    np.testing.assert_allclose(jt.q[:, 2] + drawn, x_slider(qa[:, 0]), rtol=0, atol=1e-12)


def test_a_target_closed_in_no_mode_is_outside(crank):
    five = ps.load("five_bar_type2")
    with pytest.raises(WorkspaceError, match=r"the loops cannot be closed at sample 0 .*outside "
                                             r"the workspace"):
        closure.solve_passive(five, [[np.pi, 0.0]])


def test_a_forward_study_from_the_actuated_joints_keeps_the_drawn_mode(crank, tmp_path):
    """A forward study giving the crank angle only solved the passive joints by Newton from the
    drawn pose: released at 240 degrees, it started in the other mode."""
    path = tmp_path / "release.toml"
    path.write_text('robot = "slider_crank"\nkind = "forward"\n[units]\nangle = "deg"\n'
                    "[simulation]\nq0 = [240.0]\nduration = 0.01\nsamples = 2\n")
    result = ps.run_study(path)
    q3 = result.get("q", 2).values[0]
    assert abs(q3 + x_slider(crank.q_drawn[0]) - x_slider(np.radians(240.0))) < 1e-12
