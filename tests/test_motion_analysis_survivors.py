"""Issue 30: the mutants of motion/closure.py and model/description/quantities.py that the
other tests let through, each killed here by a check against a value worked out independently.

closure.py (the continuation of a closed chain's passive joints, ``continuation.follow``):

- Every tolerance and limit at its exact edge, as its docstring states it: Newton stops only
  *below* ``NEWTON_TOL_M`` (a residual of exactly 1e-13 m is not closed, at the first sample, in
  a step and in Newton's own loop); ``COND_LIMIT`` is allowed (a pose whose condition number is
  exactly 1e6 is not singular, at the start of a step, at its end and after a failed step); the
  step guard refuses only *more* than ``MAX_STEP`` of predicted passive motion and a
  ``|step| * cond`` *above* 1; a correction exactly half the predicted step (floor 1e-6) from the
  prediction is near, one ulp further is a jump. The condition numbers are forced by a subclass
  of ``_Pose`` and the Newton results by a spy, as in tests/test_closure_edges.py; the edge
  values (|dp| == 0.05, |step| * cond == 1.0) are found or built exactly in floats here.
- The refusal after Newton closed the loops only away from the prediction, word for word.
- The slider-crank's poses against its closed form (both assembly modes).

quantities.py: the slip warnings at their edges: a value 20 times smaller than the robot's own
is not 'far' (only 30 times is), and the readings offered for a too-heavy mass or a too-small
inertia include one exactly at the bound (osmium's mass; 0.01 and 3 times the reach).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import WorkspaceError
from planar_sym.model.description import quantities as qt
from planar_sym.model.description.types import DENSITY_MAX, GYRATION_LIMIT, GYRATION_LOW
from planar_sym.model.loops import COND_LIMIT
from planar_sym.motion import closure, continuation

TOL = continuation.NEWTON_TOL_M


@pytest.fixture(scope="module")
def slider():
    return ps.load("slider_crank")


def closed_form(robot, theta, other=False):
    """Slider-crank q = [crank, rod relative to crank, slider - s0] from the crank angle, with
    the slider on the far side of the crank pivot (``other``: on the near side, the other
    assembly mode)."""
    p = robot.parameters
    r, length, s0 = p["px_crank_A"], p["px_rod_B"], p["s0_slide"]
    theta = np.asarray(theta, dtype=float)
    root = np.sqrt(length**2 - (r * np.sin(theta)) ** 2)
    x = r * np.cos(theta) + (-root if other else root)
    phi = np.arctan2(-r * np.sin(theta), x - r * np.cos(theta))
    return np.column_stack([theta, phi - theta, x - s0])


def spy(monkeypatch, fake=None, real_calls=1):
    """Record every Newton start; after the first ``real_calls`` calls ``fake(self, q, real)``
    gives the result."""
    real = continuation.Loops.newton
    guesses = []

    def newton(self, q):
        guesses.append(q.copy())
        if fake is None or len(guesses) <= real_calls:
            return real(self, q)
        return fake(self, q, real)

    monkeypatch.setattr(continuation.Loops, "newton", newton)
    return guesses


def force_cond(monkeypatch, cond):
    """Every pose the continuation builds reports the 1-norm condition number ``cond``."""
    class Forced(continuation.Pose):
        def __init__(self, loops, q, jac=None):
            super().__init__(loops, q, jac)
            self.cond = cond

    monkeypatch.setattr(closure, "Pose", Forced)  # the first pose
    monkeypatch.setattr(continuation, "Pose", Forced)  # every step's


OUTSIDE = ("slider_crank: the loops cannot be closed at t = 0.5 s (sample 1) for actuated "
           "coordinates [{qa}] (rad; O = {deg:.6g} deg) ({why}): outside the workspace")
CLOSED_FAR = ("Newton closes them (|Phi| = {res} m) only at a pose away from where the motion "
              "goes on: another solution, not this motion's")
T = np.array([0.0, 0.5])


# ---------------------------------------------------------------- Newton's tolerance, exactly

def test_newton_keeps_correcting_at_a_residual_of_exactly_the_tolerance(slider):
    """|Phi| == NEWTON_TOL_M is not below it: all NEWTON_MAX_ITER corrections are made (one ulp
    less stops at once, the pose untouched)."""
    act, pas = closure.partition(slider)
    loops = continuation.Loops(slider, act, pas)
    q0 = closed_form(slider, [0.5])[0]
    for value, calls in ((TOL, continuation.NEWTON_MAX_ITER), (np.nextafter(TOL, 0.0), 1)):
        seen = []

        def phi(q, value=value, seen=seen):
            seen.append(1)
            return (np.array([value, 0.0]),)

        loops.phi = phi
        q, residual = loops.newton(q0)
        assert len(seen) == calls and residual == value
        assert np.array_equal(q, q0) == (calls == 1)
        if calls > 1:  # each correction is J_p^-1 [value, 0] off the pose before
            assert np.all(q[act] == q0[act]) and np.max(np.abs(q[pas] - q0[pas])) > 0


def test_the_first_sample_is_refused_at_a_residual_of_exactly_the_tolerance(slider,
                                                                           monkeypatch):
    q0 = closed_form(slider, [0.5])[0]
    monkeypatch.setattr(continuation.Loops, "newton", lambda self, q: (q.copy(), TOL))
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(slider, [[0.5]], q0, T[1:])
    assert str(exc.value) == ("slider_crank: the loops cannot be closed at t = 0.5 s (sample 0) "
                              "for actuated coordinates [0.5] (rad; O = 28.6479 deg) (|Phi| = "
                              "1e-13 m, not below "
                              "the 1e-13 m of closed loops: at or just past the edge of the "
                              "workspace): outside the workspace")
    below = np.nextafter(TOL, 0.0)
    monkeypatch.setattr(continuation.Loops, "newton", lambda self, q: (q.copy(), below))
    assert np.array_equal(closure.solve_passive(slider, [[0.5]], q0)[0], q0)


@pytest.mark.parametrize("other", [False, True])
def test_a_step_closed_to_exactly_the_tolerance_is_not_taken(slider, monkeypatch, other):
    """Every correction of the step 0 -> 0.02 rad lands on the slider-crank's closed form (this
    assembly mode or the other) with |Phi| reported as exactly NEWTON_TOL_M: not closed, so the
    motion is refused as outside (not accepted, not 'closed away from the motion', not the
    assembly-mode refusal that a closed pose in the other mode gets)."""
    def land(self, q, real):
        return closed_form(slider, [q[0]], other)[0], TOL

    guesses = spy(monkeypatch, land)
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(slider, [[0.0], [0.02]], closed_form(slider, [0.0])[0], T)
    assert str(exc.value) == OUTSIDE.format(qa=0.02, deg=np.degrees(0.02), why="|Phi| = 1e-13 m, not below the 1e-13 m of closed loops: at or just past the "
                                                "edge of the workspace")
    assert len(guesses) == 1 + 1 + continuation.MAX_HALVINGS


# ---------------------------------------------------------------- 'near' and the far refusal

@pytest.mark.parametrize("cond", [None, COND_LIMIT])
def test_a_correction_exactly_half_the_prediction_away_is_near(slider, monkeypatch, cond):
    """At crank 0 (the rod's relative angle is -0.0) a repeated sample predicts no motion:
    dp = 0, so 'near' is max|trial_p - guess_p| <= 0.5 * 1e-6. A correction moving the rod by
    exactly that is taken (the pose is the one returned); one ulp more is a jump, refused after
    MAX_HALVINGS tries as closed away from the motion. With every pose's condition number
    exactly COND_LIMIT the same happens: the limit itself is not singular."""
    if cond is not None:
        force_cond(monkeypatch, cond)
    q0 = closed_form(slider, [0.0])[0]
    bound = 0.5 * 1e-6

    def off_by(d):
        def land(self, q, real):
            trial = q.copy()
            trial[1] = q[1] + d
            return trial, 0.0
        return land

    spy(monkeypatch, off_by(bound))
    q = closure.solve_passive(slider, [[0.0], [0.0]], q0, T)
    assert q[1, 1] == bound and q[1, 0] == 0.0 and q[1, 2] == q0[2]
    guesses = spy(monkeypatch, off_by(np.nextafter(bound, 1.0)))
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(slider, [[0.0], [0.0]], q0, T)
    assert str(exc.value) == OUTSIDE.format(qa=0.0, deg=0.0, why=CLOSED_FAR.format(res=0))
    assert len(guesses) == 1 + 1 + continuation.MAX_HALVINGS


def test_newton_closing_the_loops_a_turn_away_is_refused_as_another_solution(slider,
                                                                              monkeypatch):
    """Newton lands on the same mode's pose with the rod a full turn on: closed (|Phi| of the
    real residual, ~1e-17 m), same sign of det Phi_p, but 2 pi from the prediction."""
    res = []

    def turned(self, q, real):
        trial = closed_form(slider, [q[0]])[0] + [0.0, 2 * np.pi, 0.0]
        res.append(float(np.max(np.abs(slider.constraint(trial)))))
        return trial, res[-1]

    spy(monkeypatch, turned)
    with pytest.raises(WorkspaceError) as exc:
        closure.solve_passive(slider, [[0.0], [0.02]], closed_form(slider, [0.0])[0], T)
    assert res[-1] < TOL
    assert str(exc.value) == OUTSIDE.format(qa=0.02, deg=np.degrees(0.02), why=CLOSED_FAR.format(res=f"{res[-1]:.3g}"))


# ---------------------------------------------------------------- the step guard at its edges

def test_a_step_of_exactly_one_over_cond_is_taken_whole(slider, monkeypatch):
    """With cond forced to 2**19, a step of exactly 2**-19 rad (1 + 2**-19 - 1, exact) has
    |step| * cond == 1.0: taken in one Newton call, and the pose is the closed form; one ulp
    longer is taken in two halves."""
    force_cond(monkeypatch, 2.0**19)
    a = 1.0
    q0 = closed_form(slider, [a])[0]
    assert ((a + 2.0**-19) - a) * 2.0**19 == 1.0
    for to, calls in ((a + 2.0**-19, 2), (np.nextafter(a + 2.0**-19, 2.0), 3)):
        guesses = spy(monkeypatch)
        q = closure.solve_passive(slider, [[a], [to]], q0)
        assert len(guesses) == calls
        assert np.max(np.abs(q - closed_form(slider, [a, to]))) < 1e-12


def test_a_predicted_passive_step_of_exactly_max_step_is_taken_whole(slider, monkeypatch):
    """From crank 0 the rod's relative angle moves -1.5 times the crank; the crank step b whose
    prediction max|dp| (computed as continuation.follow computes it) is exactly MAX_STEP is taken in one
    step (|step| * cond = 0.11 there); a larger one is halved."""
    act, pas = closure.partition(slider)
    q0 = closure.solve_passive(slider, [[0.0]], closed_form(slider, [0.0])[0])[0]
    pose = continuation.Pose(continuation.Loops(slider, act, pas), q0)

    def dp_max(b):
        step = np.array([b]) - q0[act]
        return float(np.max(np.abs(-pose.inv @ (pose.jac[:, act] @ step))))

    b = continuation.MAX_STEP / dp_max(1.0)
    candidates = [b]
    for direction in (1.0, -1.0):
        x = b
        for _ in range(2000):
            x = float(np.nextafter(x, direction))
            candidates.append(x)
    exact = [x for x in candidates if dp_max(x) == continuation.MAX_STEP]
    assert exact, "no crank step gives exactly MAX_STEP of passive motion"
    b = exact[0]
    assert abs(b * 1.5 - continuation.MAX_STEP) < 1e-15 and b * pose.cond < 1.0
    guesses = spy(monkeypatch)
    q = closure.solve_passive(slider, [[0.0], [b]], q0)
    assert len(guesses) == 2
    assert np.max(np.abs(q - closed_form(slider, [0.0, b]))) < 1e-12
    over = max(candidates, key=dp_max)
    assert dp_max(over) > continuation.MAX_STEP
    guesses = spy(monkeypatch)
    closure.solve_passive(slider, [[0.0], [over]], q0)
    assert len(guesses) > 2


# ---------------------------------------------------------------- quantities at their edges

def test_a_value_twenty_times_smaller_than_the_robots_own_is_not_a_slip():
    """'Far' is 30 times the robot's own value or 1/30 of it: a gear ratio of 0.2 against the
    robot's 4 (1/20; read upside down it would be 5, near 4) is plausible and not doubted;
    0.1 (1/40) is, offering the upside-down reading 10."""
    gear = qt.QUANTITIES["gear_ratio"]
    assert qt.doubt(gear, 0.2, reference=4.0) is None
    assert qt.doubt(gear, 0.1, reference=4.0) == (
        "0.1 is 0.025 times the robot's own 4; a slip? Upside down (joint turns per motor turn) "
        "it would be 10")


def test_a_mass_reading_exactly_osmiums_mass_is_offered():
    """Osmium filling a ball of 1 cm: most = 22590 * 4/3 pi (0.01 m)^3 kg. A mass typed in kg
    whose reading in g is exactly that is offered the reading (the bound is allowed)."""
    extent = 0.01
    most = DENSITY_MAX * 4.0 / 3.0 * math.pi * extent**3
    typed = most * 1000.0
    for _ in range(100):
        if typed * 0.001 == most:
            break
        typed = float(np.nextafter(typed, 0.0 if typed * 0.001 > most else math.inf))
    assert typed * 0.001 == most
    text = qt.mass_doubt(typed, "kg", extent)
    assert text.endswith(f'a slip? In "g" it would be {most:.6g} kg'), text
    heavier = float(np.nextafter(typed, math.inf))
    assert heavier * 0.001 > most
    assert qt.mass_doubt(heavier, "kg", extent).endswith("a unit or decimal slip?")


@pytest.mark.parametrize("typed, at_bound, other", [
    (1.0, "kg*cm^2", ('in "kg*m^2" it would be 1 kg*m^2',)),  # radius 0.01 m: GYRATION_LOW
    (9.0, "kg*m^2", ('in "kg*cm^2" it would be 0.0009 kg*m^2',)),  # radius 3 m: GYRATION_LIMIT
])
def test_an_inertia_reading_with_a_radius_of_gyration_exactly_at_a_bound_is_offered(
        typed, at_bound, other):
    """Mass 1 kg, reach 1 m: a reading fits when its radius of gyration sqrt(I / m) is from
    0.01 m to 3 m, both included. Typed in g*mm^2, 1.0 read in kg*cm^2 is 1e-4 kg*m^2 (radius
    exactly 0.01 m) and 9.0 read in kg*m^2 has radius exactly 3 m."""
    assert GYRATION_LOW == 0.01 and GYRATION_LIMIT == 3.0
    factor = {"kg*cm^2": 1e-4, "kg*m^2": 1.0}[at_bound]
    assert math.sqrt(typed * factor / 1.0) in (GYRATION_LOW * 1.0, GYRATION_LIMIT * 1.0)
    text = qt.inertia_doubt(typed, "g*mm^2", 1.0, 1.0)
    readings = text.split("a slip? ", 1)[1].lower()
    assert f'in "{at_bound}" it would be {typed * factor:.6g} kg*m^2'.lower() in readings, text
    for o in other:
        assert o.lower() in readings, text


# ---------------------------------------------------------------- motion/_checks.py, failures.py

def test_the_profile_argument_checks_name_the_value_at_fault():
    """Each refusal of _checks names its argument: start, displacement, times (not numbers,
    not finite, no channel, not 1-D)."""
    from planar_sym.errors import InputError
    from planar_sym.motion import _checks

    cases = [
        (lambda: _checks.start_and_step("a", [1.0]), "trajectory start must be numbers (got 'a'"),
        (lambda: _checks.start_and_step([1.0], "b"),
         "trajectory displacement must be numbers (got 'b'"),
        (lambda: _checks.start_and_step([], []),
         "trajectory start and displacement need at least one channel"),
        (lambda: _checks.start_and_step([0.0], [np.inf]),
         "trajectory displacement must be finite (got [inf])"),
        (lambda: _checks.times("x", 0.0, 1.0), "trajectory times must be numbers (got 'x'"),
        (lambda: _checks.times([[0.5]], 0.0, 1.0),
         "trajectory times must be a 1-D array (got shape (1, 1))"),
    ]
    for call, start in cases:
        with pytest.raises(InputError) as exc:
            call()
        assert str(exc.value).startswith(start), str(exc.value)
        if start.endswith(")"):
            assert str(exc.value) == start


def test_of_two_failures_at_one_sample_the_first_recorded_is_reported():
    """Failures reports the earliest sample; at a tie the check recorded first (the checks run
    in order of priority), not the message that sorts first."""
    from planar_sym.motion.failures import Failures

    robot = ps.load("serial_2dof")
    fails = Failures(robot, np.array([0.0, 0.5]), np.array([[0.1, 0.0], [0.15, -0.02]]))
    fails.add(np.array([False, True]), lambda k: f"z: recorded first at {k}")
    fails.add(np.array([False, True]), lambda k: f"a: recorded second at {k}")
    fails.add(np.array([False, False]), lambda k: "never")
    with pytest.raises(WorkspaceError) as exc:
        fails.raise_earliest()
    assert str(exc.value) == ("serial_2dof: target (x = 150 mm, y = -20 mm) at t = 0.5 s "
                              "(sample 1) z: recorded first at 1")
