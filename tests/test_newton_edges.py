"""Edges of ``motion/newton.py`` held to real numbers and exact messages:

- the C entry point's loader (``_newton``) rebuilt from scratch, with its ctypes signature;
- the predictor: the times set the extrapolation (a motion quadratic in time needs far fewer
  corrections with its true times than with equal ones), whatever dtype the times have;
- targets given as float32, checked against the 2-DOF arm's law-of-cosines closed form;
- every failure code of the C loop, with toy one-coordinate robots whose task is a ctypes
  callback (a gap in x(q): no convergence; a flat x(q): an exactly singular Jacobian; a task
  function that fails; more coordinates than the solver takes), and its message word for word;
- ``branch_check``'s step size measured per step (not over the whole motion), the joint it
  names, and untrusted samples that may hold anything (inf) skipped silently.
"""

from __future__ import annotations

import ctypes
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import WorkspaceError
from planar_sym.motion import newton
from planar_sym.motion.failures import Failures

A = 0.1  # m: serial_2dof's two links (planar_sym/robots/serial_2dof.toml)
Q0 = np.array([0.5, 1.0])  # rad: elbow bent, well conditioned


def fk2(q):
    """Tip (m) of the 2-link arm, q (N, 2) rad."""
    s = q[:, 0] + q[:, 1]
    return A * np.column_stack([np.cos(q[:, 0]) + np.cos(s), np.sin(q[:, 0]) + np.sin(s)])


def ik2(x):
    """Closed form (rad), elbow q2 > 0: q2 = arccos((r^2 - a1^2 - a2^2) / (2 a1 a2))."""
    r2 = x[:, 0] ** 2 + x[:, 1] ** 2
    q2 = np.arccos((r2 - 2 * A**2) / (2 * A**2))
    q1 = np.arctan2(x[:, 1], x[:, 0]) - np.arctan2(A * np.sin(q2), A + A * np.cos(q2))
    return np.column_stack([q1, q2])


@pytest.fixture(scope="module")
def arm():
    return ps.load("serial_2dof")


# -- the loader ------------------------------------------------------------------------------------

def test_loader_builds_the_entry_point(monkeypatch, arm):
    """With nothing cached, ``_newton`` loads planar_sym_ik_newton, declares its signature (the
    C prototype in _newton.c), caches it, and the function solves."""
    monkeypatch.setattr(newton, "_NEWTON", None)
    fn = newton._newton()
    assert fn is not None and newton._NEWTON is fn
    assert fn.__name__ == "planar_sym_ik_newton"
    assert fn.restype is ctypes.c_int
    i, p = ctypes.c_int, ctypes.c_void_p
    assert tuple(fn.argtypes) == (i, i, i, p, p, p, p, p, ctypes.c_longlong, p, p, p, p, p, p, p)
    assert newton._newton() is fn
    t = np.linspace(0.0, 1.0, 5)
    x = fk2(Q0 + np.outer(t, [0.2, -0.3]))
    run = newton.solve(arm, t, x, Q0)
    assert run.failed is None and run.code == 0
    assert np.max(np.abs(run.q - ik2(x))) < 1e-12


# -- the predictor and the inputs' dtypes ----------------------------------------------------------

#: an uneven grid (s), multiples of 1/64 so that float32 holds them exactly
UNEVEN = np.array([0, 5, 9, 13, 16, 19, 21, 23, 25, 27, 32, 36, 41, 45, 49, 54, 58]) / 64


def _quadratic_motion(t):
    """Targets of the joint motion q = Q0 + a s + b s^2 (rad), s = t / t_end, and q itself."""
    s = np.asarray(t, dtype=float)[:, None] / float(t[-1])
    q = Q0 + s * np.array([0.3, -0.2]) + s**2 * np.array([-0.4, 0.25])
    return fk2(q), q


@pytest.mark.parametrize("t", [UNEVEN.astype(np.float32), np.arange(17)],
                         ids=["float32", "integers"])
def test_times_set_the_predictor(arm, t):
    """The predictor extrapolates the last solutions in time, so the times matter: with the
    true times a motion quadratic in time needs far fewer Newton corrections than with the
    times all equal (no extrapolation). Times of any dtype are the same floats: the run equals
    the one with the times as float64, corrections and all."""
    x, q = _quadratic_motion(t)
    run = newton.solve(arm, t, x, Q0)
    assert run.failed is None
    assert np.max(np.abs(run.q - q)) < 1e-12
    assert np.max(np.abs(run.q - ik2(x))) < 1e-12
    ref = newton.solve(arm, np.asarray(t, dtype=np.float64), x, Q0)
    assert np.array_equal(run.q, ref.q)
    assert (run.iterations, run.evaluations, run.halvings) == (
        ref.iterations, ref.evaluations, ref.halvings)
    flat = newton.solve(arm, np.zeros(len(t)), x, Q0)
    assert np.max(np.abs(flat.q - q)) < 1e-12
    assert 2 * run.iterations < flat.iterations


def test_float32_targets(arm):
    """Targets given as float32 are solved as the float64 numbers they hold."""
    t = np.linspace(0.0, 1.0, 6)
    x32 = fk2(Q0 + np.outer(t, [-0.25, 0.4])).astype(np.float32)
    x64 = x32.astype(float)
    run = newton.solve(arm, t, x32, Q0)
    assert run.failed is None
    assert np.max(np.abs(fk2(run.q) - x64)) < 1e-12
    assert np.max(np.abs(run.q - ik2(x64))) < 1e-12
    ref = newton.solve(arm, t, x64, Q0)
    assert np.array_equal(run.q, ref.q)


# -- every failure code, with toy robots ----------------------------------------------------------

_TASK = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_longlong, *[ctypes.POINTER(ctypes.c_double)] * 6)


def _toy(law, q_drawn=1.0, name="toy"):
    """A one-coordinate robot with task x = law(q)[0], dx/dq = law(q)[1]; law(q)[2] is the
    return code of the generated function (0: success)."""
    @_TASK
    def task(_n, q, _qd, _p, x, J, jd):
        x[0], J[0], rc = law(q[0])
        jd[0] = 0.0
        return rc

    def py_task(q, qd=None):
        q = np.atleast_2d(q)
        vals = [law(v) for v in q[:, 0]]
        return (np.array([[v[0]] for v in vals]), np.array([[[v[1]]] for v in vals]),
                np.zeros((len(q), 1)))

    address = ctypes.cast(task, ctypes.c_void_p).value
    return SimpleNamespace(name=name, n=1, n_constraints=0, task_names=("x",), actuated=(0,),
                           is_closed_chain=False, q_drawn=np.array([q_drawn]), p=np.zeros(1),
                           library=SimpleNamespace(address=lambda _name: address,
                                                   manifest={"functions": {}}),  # no ik_terms
                           task=py_task,
                           keep=task)


def _gap(q):  # x(q) = q below 2, q + 1 from 2 on: targets in [2, 3) are never reached
    return (q if q < 2.0 else q + 1.0), 1.0, 0


def _flat(q):  # x(q) = q below 2, then 2 with a zero Jacobian
    return (q, 1.0, 0) if q < 2.0 else (2.0, 0.0, 0)


@pytest.mark.parametrize("law, code", [(_gap, 1), (_flat, 2)])
def test_no_convergence_and_singular_are_returned(law, code):
    """From x = 1.5 (sample 0) to 2.5 (sample 1): the line is solved up to x = 2, not beyond;
    the step is bisected down to 2^-20 of it, so the last fraction solved is 0.5 - 2^-20. The
    run is returned (not raised) with the code of why the last attempt stopped: 1 (a correction
    of 1 > DQ_MAX across the gap) or 2 (the flat part's zero Jacobian)."""
    robot = _toy(law)
    run = newton.solve(robot, np.array([0.0, 1.0]), np.array([[1.5], [2.5]]))
    assert (run.failed, run.code) == (1, code)
    assert run.q[0, 0] == pytest.approx(1.5, abs=1e-14)
    assert np.isnan(run.q[1, 0])
    assert run.reached == 0.5 - 2.0**-20
    assert run.closest[0] == pytest.approx(1.5 + run.reached, abs=1e-14)
    assert run.residual == pytest.approx(2.5 - run.closest[0], abs=1e-14)
    assert run.halvings > 0


def _fails_above(q):
    return q, 1.0, int(q >= 1.15)


def test_function_failure_is_raised_with_its_sample():
    """A generated function that fails stops the run: raised, naming the sample (the start pose's
    own evaluation counts as sample 0)."""
    robot = _toy(_fails_above)
    with pytest.raises(WorkspaceError) as exc:
        newton.solve(robot, np.array([0.0, 1.0]), np.array([[1.1], [1.3]]))
    assert str(exc.value) == ("toy: generic inverse kinematics failed at sample 1: a generated "
                              "function failed")
    with pytest.raises(WorkspaceError) as exc:
        newton.solve(robot, np.array([0.0]), np.array([[1.1]]), q_start=[1.2])
    assert str(exc.value) == ("toy: generic inverse kinematics failed at sample 0: a generated "
                              "function failed")


def test_too_many_coordinates_is_raised():
    """33 coordinates (the solver takes 32): refused before any evaluation, at no sample (-1)."""
    n = 33

    def task(q, qd=None):
        q = np.atleast_2d(q)
        return q, np.tile(np.eye(n), (len(q), 1, 1)), np.zeros_like(q)

    robot = SimpleNamespace(name="big", n=n, n_constraints=0,
                            task_names=tuple(f"x{k}" for k in range(n)),
                            actuated=tuple(range(n)), is_closed_chain=False,
                            q_drawn=np.ones(n), p=np.zeros(1),
                            library=SimpleNamespace(address=lambda _name: None,
                                                    manifest={"functions": {}}), task=task)
    with pytest.raises(WorkspaceError) as exc:
        newton.solve(robot, np.array([0.0]), np.ones((1, n)))
    assert str(exc.value) == ("big: generic inverse kinematics failed at sample -1: too many "
                              "coordinates for the solver (32)")


# -- branch_check ----------------------------------------------------------------------------------

def _branch(arm, t, q, qd, ok):
    fails = Failures(arm, t, np.zeros((len(t), 2)))
    newton.branch_check(fails, np.asarray(t, dtype=float), np.asarray(q, dtype=float),
                        np.asarray(qd, dtype=float), np.asarray(ok, dtype=bool))
    return fails.found


def _msg(i, joint, step, qa, qb, dt, lo, hi):
    return (f"is on another branch than sample {i}, or the samples are too coarse to follow the "
            f"motion: from sample {i} joint {joint} moves by {step} rad, but its exact rates at "
            f"the two samples ({qa} and {qb} rad/s over {dt} s) account for {lo} to {hi} rad: "
            "use more samples")


def test_branch_step_size_is_per_step(arm):
    """Step 0 (joint1 moves 1 rad at rest rates) misses by 1 > 0.5 x its own size 1. Step 1 is
    untrusted (sample 2) yet huge (a step, a low and a high bound of 1000 rad): it must not
    enlarge step 0's size."""
    t = [0.0, 1.0, 2.0]
    q = [[0.0, 0.0], [1.0, 0.0], [1001.0, 0.0]]
    qd = [[0.0, 0.0], [0.0, 0.0], [-1000.0, 1000.0]]
    assert _branch(arm, t, q, qd, [True, True, False]) == [
        (1, _msg(0, "joint1", 1, 0, 0, 1, 0, 0))]


def test_branch_names_the_worst_joint_of_its_step(arm):
    """Step 0's worst joint is joint1 (0.01 rad out, not refused); step 1's is joint2 (0.5 rad
    out of a 0.5 rad step): the message names joint2 with step 1's numbers."""
    t = [0.0, 1.0, 2.0]
    q = [[0.0, 0.0], [0.11, 0.0], [0.21, 0.5]]
    qd = [[0.1, 0.0], [0.1, 0.0], [0.1, 0.0]]
    assert _branch(arm, t, q, qd, [True] * 3) == [(2, _msg(1, "joint2", 0.5, 0, 0, 1, 0, 0))]
    # and a step refused at sample 1 names its own joint, not the last step's
    q = [[0.0, 0.0], [0.0, 0.5], [0.1, 0.5]]
    qd = [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]
    assert _branch(arm, t, q, qd, [True] * 3)[0] == (1, _msg(0, "joint2", 0.5, 0, 0, 1, 0, 0))


def test_branch_untrusted_samples_may_hold_anything(arm):
    """An untrusted sample with infinite q and qd (inf - inf in the bounds) is skipped without
    a floating-point warning; the trusted step before it is fine."""
    t = [0.0, 1.0, 2.0]
    q = [[0.0, 0.0], [0.1, 0.0], [np.inf, 0.0]]
    qd = [[0.1, 0.0], [0.1, 0.0], [np.inf, 0.0]]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _branch(arm, t, q, qd, [True, True, False]) == []
