"""Newton's inverse kinematics through the fused ``ik_terms`` call (``_newton.c``): ``F = [Phi; x]``
and ``dF/dq = [Phi_q; J]`` from one generated function that computes every sine once, where
the robot was derived with it, instead of ``task``, ``constraint`` and ``constraint_jacobian``
one by one.

* The fused function equals the three it replaces (the compiled batch functions, at random
  states) to 1e-14 on a serial arm, a five-bar and the 3-RRR.
* Newton through it gives the same solutions as through the three calls (a library whose
  manifest lacks ``ik_terms``, as one derived before it) to 1e-13 rad, with the same numbers of
  corrections and evaluations, on the seed's S3, S5 and S7 motions; and both equal the seed's
  closed forms to 1e-12 rad.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import study_motion

from planar_sym.motion import newton
from planar_sym.motion.ik import inverse_kinematics

CASES = {"serial_2dof_cartesian_move": [0.5, 1.0], "five_bar_type1_move_x": None,
         "parallel_3rrr_move_y": None}


@pytest.mark.parametrize("name", CASES)
def test_the_fused_terms_are_the_three_calls(name):
    robot, _, _ = study_motion(name)
    fns = robot.library.functions
    rng = np.random.default_rng(2)
    q = rng.uniform(-np.pi, np.pi, (7, robot.n))
    n, m = robot.n, robot.n_constraints
    zero = np.zeros_like(q)
    got = fns["ik_terms"](7, {"q": q, "p": robot.p})
    x = fns["task"](7, {"q": q, "qd": zero, "p": robot.p})
    want_f, want_a = x["x"].reshape(7, -1), x["J"].reshape(7, -1, n)
    if m:
        want_f = np.concatenate([fns["constraint"](7, {"q": q, "p": robot.p})["phi"]
                                 .reshape(7, m), want_f], axis=1)
        want_a = np.concatenate([fns["constraint_jacobian"](7, {"q": q, "p": robot.p})["phi_q"]
                                 .reshape(7, m, n), want_a], axis=1)
    scale = 1 + np.max(np.abs(want_a))
    assert np.max(np.abs(got["F"].reshape(want_f.shape) - want_f)) <= 1e-14 * scale
    assert np.max(np.abs(got["dF_dq"].reshape(want_a.shape) - want_a)) <= 1e-14 * scale


@pytest.mark.parametrize("name", CASES)
def test_newton_through_one_call_or_three_agrees(name, monkeypatch):
    robot, traj, _ = study_motion(name)
    start = CASES[name]
    fused = newton.solve(robot, traj.t_s, traj.x, start)
    lib = robot.library
    without = {**lib.manifest, "functions": {k: v for k, v in lib.manifest["functions"].items()
                                             if k != "ik_terms"}}
    monkeypatch.setattr(lib, "manifest", without)
    three = newton.solve(robot, traj.t_s, traj.x, start)
    monkeypatch.undo()
    assert fused.failed is None and three.failed is None
    assert np.max(np.abs(fused.q - three.q)) <= 1e-13
    assert (fused.iterations, fused.evaluations) == (three.iterations, three.evaluations)
    seed = inverse_kinematics(robot, traj, solver="seed")
    assert np.max(np.abs(fused.q - seed.q)) <= 1e-12


def test_newton_asks_for_the_fused_call_where_the_robot_has_it(monkeypatch):
    """The fused call is the one used (the two paths give the same numbers, so only the
    addresses asked for show it): ik_terms where the manifest lists it, else the three."""
    robot, traj, _ = study_motion("five_bar_type1_move_x")
    lib = robot.library
    asked = []
    address = lib.address
    monkeypatch.setattr(lib, "address", lambda quantity: asked.append(quantity) or
                        address(quantity))
    newton.solve(robot, traj.t_s, traj.x)
    assert asked == ["task", "constraint", "constraint_jacobian", "ik_terms"]
    asked.clear()
    monkeypatch.setattr(lib, "manifest", {**lib.manifest, "functions": {
        k: v for k, v in lib.manifest["functions"].items() if k != "ik_terms"}})
    newton.solve(robot, traj.t_s, traj.x)
    assert asked == ["task", "constraint", "constraint_jacobian"]
