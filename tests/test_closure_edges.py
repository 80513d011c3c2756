"""motion/closure.py at its edges, by value: positions, rates and refusals against references
computed here, independently of the module.

- Positions: the loop residual Phi(q) = 0 to 1e-12 m at every sample, the slider-crank's and
  the four-bar's closed forms (both assembly modes), the actuated coordinates returned exactly
  as given (bit for bit, also where ``a + (b - a) != b``).
- Rates and accelerations: the slider-crank's closed-form derivatives, and central finite
  differences of the positions for the five-bar.
- Step control (a spy on the Newton corrections): ``MAX_STEP`` at its exact edge, the step
  halved at most ``MAX_HALVINGS`` times (Newton made to fail), the conditioning guard
  ``|step| * cond_1(Phi_p) <= 1``, and ``COND_LIMIT`` on the start pose, at the sample and on
  the way, each refusal word for word with its 1-norm condition number recomputed here.
- Newton made to land in the other assembly mode: the mode refusal, word for word.
- The input refusals: shapes, non-finite values (named by time), an inexactly actuated chain.
"""

from __future__ import annotations

import itertools
import re
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import InputError, WorkspaceError
from planar_sym.model.loops import COND_LIMIT
from planar_sym.motion import closure, continuation

ROOT = Path(__file__).resolve().parents[1]
TOL = 1e-12


@pytest.fixture(scope="module")
def slider():
    return ps.load("slider_crank")


@pytest.fixture(scope="module")
def four():
    return ps.load(str(ROOT / "examples" / "four_bar.toml"))


@pytest.fixture(scope="module")
def par():
    return ps.load(str(ROOT / "tests" / "robots" / "parallelogram.toml"))


@pytest.fixture(scope="module")
def five():
    return ps.load("five_bar_type1")


# ---------------------------------------------------------------- independent references

def slider_closed_form(robot, theta):
    """Slider-crank q = [crank, rod relative to crank, slider - s0] from the crank angle."""
    p = robot.parameters
    r, length, s0 = p["px_crank_A"], p["px_rod_B"], p["s0_slide"]
    theta = np.asarray(theta, dtype=float)
    x = r * np.cos(theta) + np.sqrt(length**2 - (r * np.sin(theta)) ** 2)
    phi = np.arctan2(-r * np.sin(theta), x - r * np.cos(theta))
    return np.column_stack([theta, phi - theta, x - s0])


def four_bar_closed_form(robot, theta, upper=True):
    """Four-bar q = [crank, coupler relative to crank, rocker] in the mode with B above (or
    below) the line A-O4, from the circles |B - A| = b and |B - O4| = c."""
    p = robot.parameters
    a, b, c, d = p["px_crank_A"], p["px_coupler_B"], p["px_rocker_B"], p["px_ground_O4"]
    theta = np.asarray(theta, dtype=float)
    ax, ay = a * np.cos(theta), a * np.sin(theta)
    ex, ey = d - ax, -ay  # A -> O4
    e = np.hypot(ex, ey)
    along = (b**2 - c**2 + e**2) / (2 * e)
    h = np.sqrt(b**2 - along**2) * (1.0 if upper else -1.0)
    bx = ax + along * ex / e - h * ey / e
    by = ay + along * ey / e + h * ex / e
    coupler = np.arctan2(by - ay, bx - ax)
    rocker = np.arctan2(by, bx - d)
    return np.column_stack([theta, coupler - theta, rocker])


def wrapped(a):
    return np.angle(np.exp(1j * np.asarray(a)))


def cond1(robot, q):
    """1-norm condition number of Phi_p at q, by numpy."""
    pas = list(robot.passive)
    return float(np.linalg.cond(robot.constraint_jacobian(np.asarray(q, float))[:, pas], 1))


def spy(monkeypatch, fake=None):
    """Record every Newton start (the predicted guesses); ``fake(self, q, real)`` may replace
    the correction's result."""
    real = continuation.Loops.newton
    guesses = []

    def newton(self, q):
        guesses.append(q.copy())
        return real(self, q) if fake is None else fake(self, q, real)

    monkeypatch.setattr(continuation.Loops, "newton", newton)
    return guesses


# ---------------------------------------------------------------- positions

def test_slider_crank_positions_are_its_closed_form_over_a_turn(slider):
    t = np.linspace(0.0, 2.0, 9)
    theta = np.linspace(0.0, 2 * np.pi, 9)[:, None]  # 0.785 rad per sample: 16 steps each
    q = closure.solve_passive(slider, theta, None, t)
    assert q.shape == (9, 3)
    assert np.max(np.abs(slider.constraint(q))) < TOL
    ref = slider_closed_form(slider, theta[:, 0])
    assert np.max(np.abs(q[:, 2] - ref[:, 2])) < TOL  # slider, m
    assert np.max(np.abs(wrapped(q[:, 1] - ref[:, 1]))) < 1e-11
    assert np.array_equal(q[:, 0], theta[:, 0])


def test_four_bar_keeps_either_assembly_mode_over_a_turn(four):
    theta = np.linspace(1.0, 1.0 + 2 * np.pi, 13)
    up = closure.solve_passive(four, theta[:, None])
    ref = four_bar_closed_form(four, theta)
    assert np.max(np.abs(four.constraint(up))) < TOL
    assert np.max(np.abs(wrapped(up - ref))) < 1e-10
    down_guess = four_bar_closed_form(four, theta[:1], upper=False)[0] + 0.01
    down = closure.solve_passive(four, theta[:, None], down_guess)
    ref = four_bar_closed_form(four, theta, upper=False)
    assert np.max(np.abs(four.constraint(down))) < TOL
    assert np.max(np.abs(wrapped(down - ref))) < 1e-10
    assert np.max(np.abs(wrapped(down[:, 2] - up[:, 2]))) > 0.5  # two different modes


def test_actuated_coordinates_are_returned_bit_for_bit(slider):
    # a + (b - a) != b in floating point for these: each last step aims at the sample itself
    crank = [0.002, 0.027, 1.6, 0.3]
    assert all(a + (b - a) != b for a, b in [(0.002, 0.027), (1.6, 0.3)])
    q = closure.solve_passive(slider, np.array(crank)[:, None],
                              slider_closed_form(slider, crank[:1])[0])
    assert q[:, 0].tolist() == crank
    assert np.max(np.abs(slider.constraint(q))) < TOL
    assert np.max(np.abs(q[:, 2] - slider_closed_form(slider, crank)[:, 2])) < TOL


def test_an_integer_start_pose_is_taken_as_floats(slider):
    q = closure.solve_passive(slider, [[1.0]], [1, -1, 0])
    ref = slider_closed_form(slider, [1.0])
    assert q.dtype == np.float64
    assert np.max(np.abs(q - ref)) < TOL


def test_a_single_sample_at_a_singular_pose_is_solved(par):
    q = closure.solve_passive(par, [[0.0]], [0, 0, 0], np.array([0.25]))
    assert q.tolist() == [[0.0, 0.0, 0.0]]
    q = closure.solve_passive(par, [[1e-6]], [1e-6, -1e-6, 1e-6])
    assert np.max(np.abs(q - [1e-6, -1e-6, 1e-6])) < TOL


# ---------------------------------------------------------------- rates

def test_slider_crank_rates_are_the_closed_form_derivatives(slider):
    p = slider.parameters
    r, length = p["px_crank_A"], p["px_rod_B"]
    t = np.linspace(0.0, 1.0, 11)
    th, thd, thdd = 0.3 + 2.0 * t + 1.5 * t**2, 2.0 + 3.0 * t, np.full_like(t, 3.0)
    jt = closure.from_actuated(slider, t, th[:, None], thd[:, None], thdd[:, None])
    assert np.array_equal(jt.t_s, t)
    assert np.max(np.abs(jt.q - slider_closed_form(slider, th))) < 1e-11
    root = np.sqrt(length**2 - (r * np.sin(th)) ** 2)
    dx = -r * np.sin(th) - r**2 * np.sin(th) * np.cos(th) / root  # dx/dtheta
    assert np.max(np.abs(jt.qd[:, 2] - dx * thd)) < TOL
    assert np.array_equal(jt.qd[:, 0], thd) and np.array_equal(jt.qdd[:, 0], thdd)
    h = 1e-5  # the slider's acceleration: central differences of its closed-form rate

    def xdot(tt):
        a = 0.3 + 2.0 * tt + 1.5 * tt**2
        w = 2.0 + 3.0 * tt
        rt = np.sqrt(length**2 - (r * np.sin(a)) ** 2)
        return (-r * np.sin(a) - r**2 * np.sin(a) * np.cos(a) / rt) * w

    xdd = (xdot(t + h) - xdot(t - h)) / (2 * h)
    assert np.max(np.abs(jt.qdd[:, 2] - xdd)) < 1e-6
    # the rod's angle (absolute = crank + relative): its rate by central differences
    fd = (slider_closed_form(slider, th + h * thd)[:, 1]
          - slider_closed_form(slider, th - h * thd)[:, 1]) / (2 * h)
    assert np.max(np.abs(jt.qd[:, 1] - fd)) < 1e-7


def test_five_bar_rates_against_finite_differences(five):
    q0 = five.q_drawn
    t = np.linspace(0.0, 0.5, 6)
    h = 1e-5

    def motion(tt):
        return np.column_stack([q0[0] + 0.2 * np.sin(tt), q0[2] - 0.15 * tt**2])

    qd_a = np.column_stack([0.2 * np.cos(t), -0.3 * t])
    qdd_a = np.column_stack([-0.2 * np.sin(t), np.full_like(t, -0.3)])
    jt = closure.from_actuated(five, t, motion(t), qd_a, qdd_a)
    assert np.max(np.abs(five.constraint(jt.q))) < TOL
    qp = closure.solve_passive(five, motion(t + h))
    qm = closure.solve_passive(five, motion(t - h))
    assert np.max(np.abs(jt.qd - (qp - qm) / (2 * h))) < 1e-7
    assert np.max(np.abs(jt.qdd - (qp - 2 * jt.q + qm) / h**2)) < 1e-3
    q, qd = closure.complete_state(five, motion(t[2:3])[0], qd_a[2])
    assert np.max(np.abs(q - jt.q[2])) < TOL and np.max(np.abs(qd - jt.qd[2])) < TOL


# ---------------------------------------------------------------- step control

@pytest.mark.parametrize("to, steps", [(3.05, 1), (float(np.nextafter(3.05, 4.0)), 2),
                                       (3.12, 3), (3.02, 1), (3.0, 1)])
def test_steps_of_at_most_max_step(slider, monkeypatch, to, steps):
    """From crank 3 rad (the rod turns half as fast as the crank there, so only MAX_STEP on
    the crank binds): 3.05 - 3 is 0.04999999999999982, one step; one ulp more, two."""
    assert continuation.MAX_STEP == 0.05
    a = 3.0
    guesses = spy(monkeypatch)
    q = closure.solve_passive(slider, [[a], [to]], slider_closed_form(slider, [a])[0])
    assert len(guesses) == 1 + steps  # the first sample, then one Newton per step
    targets = [g[0] for g in guesses[1:]]
    assert targets[-1] == to
    assert np.allclose(targets, a + (to - a) * np.arange(1, steps + 1) / steps, rtol=0,
                       atol=1e-15)
    moves = np.diff(np.array(guesses), axis=0)
    assert np.max(np.abs(moves)) <= continuation.MAX_STEP
    assert np.max(np.abs(q - slider_closed_form(slider, [a, to]))) < TOL


def test_a_failing_step_is_halved_max_halvings_times_then_refused(slider, monkeypatch):
    a, b = 0.002, 0.027  # one step (the rod turns 1.5 times the crank: 0.0375 rad)
    calls = []

    def fail(self, q, real):
        calls.append(1)
        return real(self, q) if len(calls) == 1 else (q, 1.0)

    guesses = spy(monkeypatch, fail)
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(slider, [[a], [b]], slider_closed_form(slider, [a])[0],
                              np.array([0.0, 0.5]))
    assert str(exc.value) == ("slider_crank: the loops cannot be closed at t = 0.5 s (sample 1) "
                              "for actuated coordinates [0.027] (rad; O = 1.54699 deg) (|Phi| = "
                              "1 m): outside the workspace")
    assert continuation.MAX_HALVINGS == 20
    targets = [g[0] for g in guesses[1:]]
    assert len(targets) == 21  # the whole step, then 20 halvings
    assert targets[0] == b  # the sample itself, exactly
    assert targets[1:] == [a + 2.0**-k * (b - a) for k in range(1, 21)]


def test_the_conditioning_guard_halves_at_most_max_halvings_times(par, monkeypatch):
    """With MAX_HALVINGS = 3, a step that |step| * cond would halve 6 times is halved 3 times,
    then taken as it is: 8 steps, each exact on the parallelogram's straight branch."""
    monkeypatch.setattr(continuation, "MAX_HALVINGS", 3)
    d = 1e-5
    assert 1e-4 * cond1(par, [d, -d, d]) > 32  # the guard would want 2**5 or more
    guesses = spy(monkeypatch)
    q = closure.solve_passive(par, [[d], [d + 1e-4]], [d, -d, d])
    assert len(guesses) == 1 + 8
    assert np.max(np.abs(q[1] - [d + 1e-4, -d - 1e-4, d + 1e-4])) < TOL


def test_every_step_keeps_step_times_cond_at_most_one(par, monkeypatch):
    """Towards the change point the steps shrink so that |step| * cond_1(Phi_p) <= 1 from
    every pose (the start at 1e-5 rad has cond 3.5e5: one step of 6e-6 rad would be 2.1)."""
    guesses = spy(monkeypatch)
    q = closure.solve_passive(par, [[1e-5], [4e-6]], [1e-5, -1e-5, 1e-5])
    crank = [g[0] for g in guesses]
    assert len(crank) > 2 and crank[0] == 1e-5 and crank[-1] == 4e-6
    for c0, c1 in itertools.pairwise(crank):
        assert 0 < (c0 - c1) * cond1(par, [c0, -c0, c0]) <= 1.0, (c0, c1)
    assert np.max(np.abs(q[1] - [4e-6, -4e-6, 4e-6])) < TOL


# ---------------------------------------------------------------- singular poses

SINGULAR = ("{name}: singular pose {where}: the passive-joint constraint Jacobian Phi_p has "
            "1-norm condition number {cond} > 1e+06")  # then where and what to do


def test_a_singular_start_is_refused_between_the_first_two_samples(par):
    t = np.array([0.0, 0.5, 1.0])
    between = "between t = 0 s (sample 0) and t = 0.5 s (sample 1)"
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(par, [[0.0], [0.1], [0.2]], [0, 0, 0], t)
    assert str(exc.value).startswith(SINGULAR.format(name="parallelogram", where=between, cond="inf"))
    crank = par.coordinates[par.actuated[0]]  # where the start is, in its units and degrees
    assert (f"> 1e+06 (actuated coordinates there: [0.0] (rad; {crank} = 0 deg)): the actuated "
            "joints cannot drive") in str(exc.value)
    d = 1e-6
    cond = cond1(par, [d, -d, d])
    assert COND_LIMIT < cond < 1e7
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(par, [[d], [0.1], [0.2]], [d, -d, d], t)
    assert str(exc.value).startswith(SINGULAR.format(name="parallelogram", where=between,
                                             cond=f"{cond:.3g}"))
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(par, [[d], [0.1]], [d, -d, d])
    assert str(exc.value).startswith(SINGULAR.format(name="parallelogram",
                                             where="between sample 0 and sample 1",
                                             cond=f"{cond:.3g}"))


def test_a_five_bar_start_at_its_workspace_edge_is_refused(five):
    """The last crank angle at which Newton closes the loops (bisection), where the distal
    links are nearly stretched: its 1-norm condition number, recomputed, is in the message."""
    # a start pose given (passive values not the drawn ones): Newton, no continuation
    left, guess = five.q_drawn[0], five.q_drawn.copy()
    guess[list(five.passive)] += 1e-9
    lo, hi = 0.7003, 0.7
    q = closure.solve_passive(five, [[left, lo]], guess)[0]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        try:
            q = closure.solve_passive(five, [[left, mid]], guess)[0]
            lo = mid
        except WorkspaceError:
            hi = mid
    assert np.max(np.abs(five.constraint(q))) < TOL
    cond = cond1(five, q)
    assert cond > COND_LIMIT
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(five, [[left, lo], [left, 0.71]], guess, np.array([1.0, 2.0]))
    where = "between t = 1 s (sample 0) and t = 2 s (sample 1)"
    assert str(exc.value).startswith(SINGULAR.format(name="five_bar_type1", where=where,
                                             cond=f"{cond:.3g}"))
    # the start's actuated coordinates, to 9 decimals, with their units and degrees
    there = np.round(q[list(five.actuated)], 9).tolist()
    assert (f" (actuated coordinates there: {there} (rad, rad; A = {np.degrees(there[0]):.6g} "
            f"deg, E = {np.degrees(there[1]):.6g} deg)): the actuated joints") in str(exc.value)


def test_a_singular_sample_reached_in_one_step_is_refused_at_it(par):
    # from 4e-6 rad (cond 8.75e5) to 3e-6 rad (cond 1.17e6) in one step: |step| * cond < 1
    start, end = 4e-6, 3e-6
    assert cond1(par, [start, -start, start]) * (start - end) < 1.0
    cond = cond1(par, [end, -end, end])
    assert cond > COND_LIMIT
    t = np.array([0.0, 0.5, 1.0])
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(par, [[5e-6], [start], [end]], [5e-6, -5e-6, 5e-6], t)
    assert str(exc.value).startswith(SINGULAR.format(name="parallelogram",
                                             where="at t = 1 s (sample 2)", cond=f"{cond:.3g}"))


def test_a_singular_pose_closed_off_the_prediction_is_refused_at_the_sample(par, monkeypatch):
    """Newton made to land, at the last step, on the change point with the rocker a full turn
    on (closed, singular, far from the prediction): with no halving allowed (MAX_HALVINGS = 0)
    the motion is refused at the sample, naming that pose's condition number. (With halvings
    the continuation meets the singular pose itself first: the test after this one.)"""
    monkeypatch.setattr(continuation, "MAX_HALVINGS", 0)
    turned = np.array([0.0, 0.0, 2 * np.pi])

    def land(self, q, real):
        if q[0] == 0.0:
            return turned.copy(), float(np.max(np.abs(par.constraint(turned))))
        return real(self, q)

    guesses = spy(monkeypatch, land)
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(par, [[0.04], [0.0]], [0.04, -0.04, 0.04], np.array([0.0, 0.5]))
    jp = par.constraint_jacobian(turned)[:, list(par.passive)]
    try:
        cond = np.abs(jp).sum(axis=0).max() * np.abs(np.linalg.inv(jp)).sum(axis=0).max()
    except np.linalg.LinAlgError:
        cond = np.inf
    assert cond > COND_LIMIT
    assert str(exc.value).startswith(SINGULAR.format(name="parallelogram", where="at t = 0.5 s (sample 1)",
                                             cond=f"{cond:.3g}"))
    assert [g[0] for g in guesses] == pytest.approx([0.04, 0.0], abs=1e-15)


def test_near_a_singular_pose_the_steps_halve_as_it_nears_and_grow_back_after(par, monkeypatch):
    """Toward the parallelogram's change point (crank 0) each step stays under 1 / cond, so the
    steps halve as it nears (the distance halves each time) until the pose is refused; away
    from a hard part a halved step grows back (before, it stayed small: 16385 Newton starts
    for 0.01 rad after a start 4e-6 rad from the change point, about a million for 0.6 rad)."""
    monkeypatch.setattr(continuation, "MAX_HALVINGS", 2)
    guesses = spy(monkeypatch)
    with pytest.raises(WorkspaceError, match=r"singular pose between t = 0 s \(sample 0\) and "
                                             r"t = 0\.5 s \(sample 1\)"):
        closure.solve_passive(par, [[0.04], [0.0]], [0.04, -0.04, 0.04], np.array([0.0, 0.5]))
    cranks = [g[0] for g in guesses[1:]]
    assert cranks[:4] == pytest.approx([0.03, 0.02, 0.01, 0.005], abs=1e-15)
    assert all(b == pytest.approx(a / 2) for a, b in itertools.pairwise(cranks[3:]))
    guesses.clear()
    monkeypatch.setattr(continuation, "MAX_HALVINGS", 20)
    q = closure.solve_passive(par, [[4e-6], [0.6]], [4e-6, -4e-6, 4e-6])
    assert np.max(np.abs(par.constraint(q))) < 1e-12
    assert len(guesses) < 200, len(guesses)


# ---------------------------------------------------------------- another assembly mode

MODE = ("four_bar: between t = 0.25 s (sample 1) and t = 0.5 s (sample 2) the passive joints "
        "pass a singular pose (det Phi_p changes sign): the loops would go on in another "
        "assembly mode, so the motion leaves the workspace of the mode it started in")


def _other_mode(four, residual=None):
    """Newton replaced, past crank 1.04 rad, by the other assembly mode at the aimed crank
    angle (closed to ~1e-17 m, or reported with ``residual``)."""
    def land(self, q, real):
        if q[0] <= 1.04:
            return real(self, q)
        other = four_bar_closed_form(four, [q[0]], upper=False)[0]
        res = float(np.max(np.abs(four.constraint(other)))) if residual is None else residual
        return other, res
    return land


def test_a_correction_in_the_other_assembly_mode_is_refused(four, monkeypatch):
    guesses = spy(monkeypatch, _other_mode(four))
    t = np.array([0.0, 0.25, 0.5])
    guess = four.q_drawn.copy()
    guess[list(four.passive)] += 1e-9  # a start pose given (not the drawn one): Newton first
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(four, [[1.0], [1.04], [1.08]], guess, t)
    assert str(exc.value) == MODE
    assert len(guesses) == 1 + 1 + 21


def test_an_unclosed_correction_in_the_other_mode_is_outside(four, monkeypatch):
    spy(monkeypatch, _other_mode(four, residual=1.0))
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(four, [[1.0], [1.04], [1.08]], None, np.array([0.0, 0.25, 0.5]))
    assert str(exc.value) == ("four_bar: the loops cannot be closed at t = 0.5 s (sample 2) for "
                              "actuated coordinates [1.08] (rad; crank_joint = 61.8794 deg) "
                              "(|Phi| = 1 m): outside the workspace")


def test_past_the_five_bar_edge_the_refusal_is_outside(five):
    left = five.q_drawn[0]
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(five, [[left, 1.0], [left, 0.5]], None, np.array([0.0, 2.0]))
    assert re.fullmatch(r"five_bar_type1: the loops cannot be closed at t = 2 s \(sample 1\) "
                        r"for actuated coordinates \[2\.073585212, 0\.5\] \(rad, rad; A = "
                        r"118\.808 deg, E = 28\.6479 deg\) "
                        r"\(\|Phi\| = [0-9.e+-]+ m(, not below the 1e-13 m of closed loops: at "
                        r"or just past the edge of the workspace)?\): outside the workspace",
                        str(exc.value)), str(exc.value)


# ---------------------------------------------------------------- inputs

def test_an_inexactly_actuated_chain_is_refused():
    over = SimpleNamespace(name="over", actuated=(0, 1), passive=(2,), n=3, n_constraints=2)
    with pytest.raises(InputError) as exc:
        closure.partition(over)
    assert str(exc.value) == ("over: 2 actuated joints and 2 loop equations for 3 coordinates: "
                              "the chain is not exactly actuated, so torques are not unique")


@pytest.mark.parametrize("actuated, passive, m", [((), (0, 1, 2), 3), ((0, 1, 2), (), 0)])
def test_the_partition_is_integer_indices_even_when_empty(actuated, passive, m):
    act, pas = closure.partition(SimpleNamespace(name="x", actuated=actuated, passive=passive,
                                                 n=3, n_constraints=m))
    assert act.dtype.kind == "i" and pas.dtype.kind == "i"
    assert act.tolist() == list(actuated) and pas.tolist() == list(passive)
    assert np.arange(3.0)[pas].tolist() == [float(i) for i in passive]


def test_from_actuated_input_refusals(slider):
    z = np.zeros((2, 1))
    with pytest.raises(InputError) as exc:
        closure.from_actuated(slider, [0.0, 0.5, 1.0], z, z, z)
    assert str(exc.value) == "t has 3 times for 2 samples of q_act"
    with pytest.raises(InputError) as exc:
        closure.from_actuated(slider, np.zeros((2, 2)), z, z, z)
    assert str(exc.value) == "t must have shape (N, 1) or (1,), got (2, 2)"
    with pytest.raises(InputError) as exc:
        closure.from_actuated(slider, 0.0, z[:1], z[:1], z[:1])
    assert str(exc.value) == "t must have shape (N, 1) or (1,), got ()"
    with pytest.raises(InputError) as exc:
        closure.from_actuated(slider, [0.0, np.nan], z, z, z)
    assert str(exc.value) == "t[1, 0] is nan at sample 1: inputs must be finite"
    jt = closure.from_actuated(slider, [[0.0], [0.5]], [[0.1], [0.2]], z, z)  # t as (N, 1)
    assert jt.t_s.tolist() == [0.0, 0.5]


def test_non_finite_inputs_are_named_by_time(slider):
    t = np.array([0.0, 0.5])
    ok = np.array([[0.1], [0.2]])
    bad = np.array([[0.1], [np.inf]])
    with pytest.raises(InputError) as exc:
        closure.from_actuated(slider, t, bad, ok, ok)
    assert str(exc.value) == "q_act[1, 0] is inf at sample 1 (t = 0.5 s): inputs must be finite"
    with pytest.raises(InputError) as exc:
        closure.solve_passive(slider, bad, None, t)
    assert str(exc.value) == "q_act[1, 0] is inf at sample 1 (t = 0.5 s): inputs must be finite"
    with pytest.raises(InputError) as exc:
        closure.from_actuated(slider, t, ok, bad, ok)
    assert str(exc.value) == "qd_act[1, 0] is inf at sample 1 (t = 0.5 s): inputs must be finite"
    q = slider_closed_form(slider, ok[:, 0])
    with pytest.raises(InputError) as exc:
        closure.complete_rates(slider, q, ok, bad, t)
    assert str(exc.value) == ("qdd_act[1, 0] is inf at sample 1 (t = 0.5 s): inputs must be "
                              "finite")


def test_complete_state_takes_one_sample_of_each(slider):
    q, qd = closure.complete_state(slider, [0.7], [2.0])
    assert np.max(np.abs(q - slider_closed_form(slider, [0.7])[0])) < TOL
    assert qd[0] == 2.0
    with pytest.raises(InputError) as exc:
        closure.complete_state(slider, [0.1, 0.2], [0.0])
    assert str(exc.value) == "q_act must have shape (N, 1) or (1,), got (1, 2)"
    with pytest.raises(InputError) as exc:
        closure.complete_state(slider, [0.1], [0.0, 0.0])
    assert str(exc.value) == "qd_act must have shape (N, 1) or (1,), got (1, 2)"


def test_a_crank_after_a_thousand_turns_runs_as_at_its_first():
    """A trial: the Jansen leg simulated from its drawn pose with the crank counted after 1000
    turns (17 minutes at 1 rev/s) failed "cannot project q onto the loop constraints (|Phi| =
    1.33e-13 m)": at 6283 rad an angle is stored to 9e-13 rad, and the projection's absolute
    1e-13 m could never be met. The same physical motion must come out whatever the count:
    the run after 1000 turns equals the run from the drawn pose, the crank 2 pi 1000 apart."""
    import planar_sym as ps

    leg = ps.load(ROOT / "examples" / "jansen_linkage.toml")
    t = np.linspace(0.0, 0.3, 31)
    base = ps.simulate(leg, leg.q_drawn, np.zeros(leg.n), (0.0, 0.3), t_eval=t)
    q0 = leg.q_drawn.copy()
    q0[0] += 2 * np.pi * 1000
    wound = ps.simulate(leg, q0, np.zeros(leg.n), (0.0, 0.3), t_eval=t)
    shift = np.zeros(leg.n)
    shift[0] = 2 * np.pi * 1000
    np.testing.assert_allclose(wound.q - shift, base.q, rtol=0, atol=1e-8)
    assert wound.constraint_drift_m < 1e-10


NEAR_CHANGE_POINT = """# a trial's four-bar: crank 4, coupler 10, rocker 4.0000004, ground 10 cm (a
# parallelogram to the 6th decimal of its points): within ~0.03 deg of its change point
name = "near_change_point"
title = "Four-bar passing near its change point (a trial's)"
assemble = true
gravity = [0.0, -9.81]
[units]
length = "cm"
mass = "kg"
inertia = "kg*cm^2"
angle = "deg"
acceleration = "m/s^2"
[ground]
points = { O2 = [0.0, 0.0], O4 = [10.0, 0.0] }
[[bodies]]
name = "crank"
mass = 0.3
izz = 0.4
cg = [1.0, 1.732]
cg_from = "O2"
points = { O2 = [0.0, 0.0], A = [2.0, 3.4641016] }
frame = ["O2", "A"]
[[bodies]]
name = "coupler"
mass = 0.6
izz = 5.0
cg = [5.0, 0.0115]
cg_from = "A"
points = { A = [2.0, 3.4641016], B = [12.000000, 3.464102] }
frame = ["A", "B"]
[[bodies]]
name = "rocker"
mass = 0.4
izz = 1.64
cg = [0.249, 0.434]
cg_from = "O4"
points = { O4 = [10.0, 0.0], B = [12.000000, 3.464102] }
frame = ["O4", "B"]
[[joints]]
name = "crank_j"
type = "revolute"
parent = "ground.O2"
child = "crank.O2"
actuated = true
[[joints]]
name = "coupler_j"
type = "revolute"
parent = "crank.A"
child = "coupler.A"
actuated = false
[[joints]]
name = "rocker_j"
type = "revolute"
parent = "ground.O4"
child = "rocker.O4"
actuated = false
[[joints]]
name = "B"
type = "revolute"
parent = "coupler.B"
child = "rocker.B"
actuated = false
closes_loop = true
"""


def test_a_singular_pose_between_samples_is_said(derived, tmp_path):
    """A trial: one crank turn of a four-bar passing within ~0.03 deg of its change point, at
    101 samples, gave a 0.34 N*m peak torque (137 N*m at 100001 samples) and no warning: no
    sample lands near the pose, though the continuation between two of them steps right past
    it. The largest condition number of Phi_p on the way is said, with the two samples; it
    agrees with the largest over 2001 samples between those two. There the samples themselves
    are near it (their warning is the inverse dynamics'): no second one here."""
    path = tmp_path / "near_change_point.toml"
    path.write_text(NEAR_CHANGE_POINT)
    _, robot = derived(path)
    turn = np.radians(60.0) + np.linspace(0.0, 2 * np.pi, 101)
    t = np.linspace(0.0, 1.0, 101)
    with pytest.warns(RuntimeWarning, match="the loops pass near a singular pose") as rec:
        closure.solve_passive(robot, turn[:, None], t=t)
    said = [str(w.message) for w in rec]
    assert len(said) == 1
    got = re.search(r"between t = ([\d.]+) s \(sample (\d+)\) and t = ([\d.]+) s \(sample "
                    r"(\d+)\).* condition number ([\d.e+]+) there, at most ([\d.e+]+) at the "
                    r"samples", said[0])
    assert got, said[0]
    k = int(got[4])
    assert int(got[2]) == k - 1 and float(got[1]) == pytest.approx(t[k - 1], abs=1e-9)
    assert float(got[3]) == pytest.approx(t[k], abs=1e-9)
    fine_turn = np.linspace(turn[k - 1], turn[k], 2001)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fine = closure.solve_passive(robot, fine_turn[:, None])
    jac = robot.constraint_jacobian(fine).reshape(len(fine), 2, 3)
    cond = np.linalg.cond(jac[:, :, list(robot.passive)], 1)
    assert cond.max() > 5e3 and 0 < np.argmax(cond) < len(cond) - 1  # inside the interval
    assert abs(float(got[5]) / cond.max() - 1) < 0.2 and float(got[6]) < 1e3


def test_the_between_samples_warning_at_its_edges():
    """``continuation.warn_between_samples`` at each edge of its rule (a mutation run left them
    unpinned): two samples have a between; every sample at exactly COND_WARN is still below the
    warning and a pass exactly at it is not above it; the message whole, with times and
    without."""
    from planar_sym.model.loops import COND_WARN

    warn = continuation.warn_between_samples
    said = ("r: between {a} and {b} the loops pass near a singular pose (Phi_p's 1-norm "
            "condition number 2e+03 there, at most {c} at the samples): torques and joint loads "
            "peak between the samples, so the peaks reported are too low; more samples resolve "
            "them")
    for cond, t, a, b in (([10.0, 10.0], None, "sample 0", "sample 1"),
                          ([10.0, COND_WARN], [0.0, 0.5], "t = 0 s (sample 0)",
                           "t = 0.5 s (sample 1)")):
        with pytest.warns(RuntimeWarning) as rec:
            warn("r", np.array(cond), np.array([10.0, 2 * COND_WARN]),
                 None if t is None else np.array(t))
        assert [str(w.message) for w in rec] == [said.format(a=a, b=b, c=f"{max(cond):.3g}")]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warn("r", np.array([10.0]), np.array([2 * COND_WARN]), None)  # one sample: no between
        warn("r", np.array([10.0, 10.0]), np.array([10.0, COND_WARN]), None)  # not above
        warn("r", np.array([10.0, 2 * COND_WARN]), np.array([10.0, 3 * COND_WARN]), None)


def test_a_slider_driven_chain_s_refusal_has_no_degrees():
    """A closed chain driven by a slider: its actuated coordinate in m has no degrees to give,
    and the refusal's units end where they do (a mutation left '; ' appended there)."""
    robot = ps.load("slider_crank_slider_driven")
    act, pas = closure.partition(robot)
    loops = continuation.Loops(robot, act, pas)
    assert loops.degrees(np.array([0.1])) == ""
    with pytest.raises(WorkspaceError) as err:
        loops.refuse_outside(np.array([5.0]), 1.0, np.array([0.0, 0.25]), 1)
    assert str(err.value) == (
        "slider_crank_slider_driven: the loops cannot be closed at t = 0.25 s (sample 1) for "
        "actuated coordinates [5.0] (m) (|Phi| = 1 m): outside the workspace")


def test_a_first_sample_in_the_other_mode_says_how_to_start_there(four, monkeypatch):
    """From the drawn pose to the first sample the loops would change assembly mode: the
    refusal names the drawn pose as where it came from and, the first sample only, how to
    start in the other mode (a mutation run left the hint unpinned). Newton is replaced below
    crank 1.0 rad by the other mode; the drawn crank is 1.047 rad."""
    assert four.q_drawn[0] > 1.0

    def land(self, q, real):
        if q[0] >= 1.0:
            return real(self, q)
        other = four_bar_closed_form(four, [q[0]], upper=False)[0]
        return other, float(np.max(np.abs(four.constraint(other))))

    spy(monkeypatch, land)
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(four, [[0.95], [0.9]], None, np.array([0.0, 0.25]))
    assert str(exc.value) == (
        "four_bar: between the drawn pose and t = 0 s (sample 0) the passive joints pass a "
        "singular pose (det Phi_p changes sign): the loops would go on in another assembly "
        "mode, so the motion leaves the workspace of the mode it started in; to start in "
        "another assembly mode, give a start pose in it (start_pose, q_guess)")
