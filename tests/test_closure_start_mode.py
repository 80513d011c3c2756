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

import warnings
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import WorkspaceError
from planar_sym.motion import closure, continuation

ROOT = Path(__file__).resolve().parents[1]
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


@pytest.mark.parametrize("deg", [120.0, 180.0, 240.0])
def test_simulate_projected_from_the_drawn_pose_keeps_its_mode(crank, deg):
    """``simulate(project=True)`` from ``q_drawn`` with the crank turned: its passive values
    are the drawn ones, no guess; Newton from them put the slider at x = -0.81 m at 120
    degrees (the other mode) and the passive angle four turns away (12.57 rad)."""
    q0 = crank.q_drawn.copy()
    q0[0] += np.radians(deg)
    q = ps.simulate(crank, q0, np.zeros(3), (0.0, 0.001), project=True).q[0]
    assert abs(q[2] + x_slider(crank.q_drawn[0]) - x_slider(q0[0])) < 1e-12, q
    rod = q[0] + q[1]  # the rod's own angle swings about the drawn one, in the same turn
    assert abs(rod) <= np.arcsin(R / L) + 1e-12, q  # within +-30 degrees, not turns away


def test_a_far_guess_in_another_mode_is_said(crank):
    """A start whose passive values Newton must move far (here zeros) and which closes the
    other mode keeps the user's closure, with a warning naming both; the same guess at a
    crank angle where both agree says nothing."""
    q0 = np.array([crank.q_drawn[0] + np.radians(120.0), 0.0, 0.0])
    with pytest.warns(RuntimeWarning, match=r"another pose than the drawn assembly mode's "
                                            r"\[-3.1416, -0.1993\]"):
        q = ps.simulate(crank, q0, np.zeros(3), (0.0, 0.001), project=True).q[0]
    # the other mode: x = r cos(theta) - sqrt(l^2 - (r sin(theta))^2)
    other = R * np.cos(q0[0]) - np.sqrt(L**2 - (R * np.sin(q0[0])) ** 2)
    assert abs(q[2] + x_slider(crank.q_drawn[0]) - other) < 1e-12, q
    assert abs(q[1]) < np.pi, q  # the turn nearest the guess, where Newton may wander off
    near = crank.q_drawn.copy()
    near[1:] += 0.01  # a guess near the drawn pose's closure: no word
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ps.simulate(crank, near, np.zeros(3), (0.0, 0.001), project=True)


def test_a_guess_newton_cannot_close_from_falls_back_to_the_drawn_mode():
    """The four-bar at 300 degrees from its drawn passive angles shifted: Newton from them does
    not close the loops, the drawn mode continued does (it was refused as outside)."""
    bar = ps.load(str(ROOT / "examples" / "four_bar.toml"))
    q0 = bar.q_drawn.copy()
    q0[0] += np.radians(300.0)
    q_drawn_mode = closure.solve_passive(bar, [[q0[0]]])[0]
    q0[1:] += 1e-3  # not the drawn values: a guess
    q = ps.simulate(bar, q0, np.zeros(3), (0.0, 0.001), project=True).q[0]
    np.testing.assert_allclose(q, q_drawn_mode, rtol=0, atol=1e-12)


@pytest.mark.parametrize("deg", [60.0, 120.0, 240.0])
def test_newton_from_a_guess_stays_in_the_guess_turn(crank, deg):
    """Newton from passive zeros wandered five turns off (q2 = 33.96 rad at 60 degrees); the
    closure is given in the turn nearest the guess, still on the loops."""
    guess = np.array([np.radians(deg), 0.0, 0.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        q = closure.solve_passive(crank, [[guess[0]]], q_guess=guess)[0]
    assert abs(q[1]) <= np.pi and np.max(np.abs(crank.constraint(q))) < 1e-12, q


def test_an_exactly_singular_target_is_a_workspace_error():
    """The type-2 five-bar with both cranks at 0: Phi_p is exactly singular there; numpy's
    LinAlgError('Singular matrix') reached the user."""
    five = ps.load("five_bar_type2")
    with pytest.raises(WorkspaceError, match=r"singular pose between the drawn pose and "
                                             r"sample 0"):
        closure.solve_passive(five, [[0.0, 0.0]])


def test_a_small_residual_outside_says_what_closed_means():
    """Just past the type-2 five-bar's edge Newton stalls at |Phi| ~ 6e-9 m, which read as
    closed in a user trial; the message gives the tolerance of closed loops."""
    five = ps.load("five_bar_type2")
    with pytest.raises(WorkspaceError, match=r"\(\|Phi\| = [0-9.e-]+ m, not below the 1e-13 m of "
                                             r"closed loops: at or just past the edge of the "
                                             r"workspace\): outside the workspace") as err:
        closure.solve_passive(five, [[0.0002661016949152542, 0.0]])
    assert float(str(err.value).split("|Phi| = ")[1].split(" m")[0]) < continuation.NEAR_EDGE_M


def test_a_guess_of_the_wrong_length_is_named(crank):
    """A one-value guess for the three coordinates raised numpy's IndexError."""
    with pytest.raises(ps.InputError, match=r"q_guess must have shape .*\(3,\), got \(1,\)"):
        closure.solve_passive(crank, [[1.0]], q_guess=[0.0])
