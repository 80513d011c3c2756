"""Every integrator ``planar_sym.simulate`` accepts, on free swings of the serial arms, and the
Jacobian it hands to SciPy's implicit methods.

References, independent of the method under test:

* the C Dormand-Prince 5(4) (``dopri5``) at rtol 1e-12, atol 1e-14: each method at rtol 1e-10
  must agree with it to 1e-6 rad in q and 1e-6 rad/s in qd (measured worst 8e-8 rad/s, cvodes);
* conservation of energy (no friction, no torque): kinetic + potential stays at its initial
  value to 1e-7 of the peak kinetic energy;
* the Jacobian: central differences of the compiled right-hand side ``robot.forward_dynamics``
  (the matrix itself, compared entry by entry to 1e-6 of its largest entry: a wrong Jacobian
  only slows Radau, BDF and LSODA down, their results can still agree).

cvodes and idas (SUNDIALS) run in the simulation engine; ``simulate`` takes them like the
others, and a table of torques through ``simulate`` (evaluated in C by the engine) agrees with
the same torques given as a function of time to SciPy.
"""

from __future__ import annotations

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.dynamics import forward
from planar_sym.dynamics.integrate import SCIPY_METHODS
from planar_sym.errors import InputError

#: the methods the module docstring of planar_sym/dynamics/forward.py lists
METHODS = ("dopri5", "DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA", "cvodes", "idas")
IMPLICIT = ("Radau", "BDF", "LSODA")  # those given the compiled Jacobian
#: free swings: released at q1 = -60 deg (seed S1), the 3-DOF arm with its elbow bent and a
#: push on the wrist
SWINGS = {"serial_2dof": ([-np.pi / 3, 0.0], [0.0, 0.0]),
          "serial_3dof": ([-np.pi / 3, 0.4, -0.3], [0.0, 0.0, 2.0])}
T_END = 1.0
T = np.linspace(0.0, T_END, 101)
AGREE = 1e-6  # rad, rad/s
ENERGY_REL = 1e-7
JAC_REL = 1e-6


@pytest.fixture(scope="module", params=list(SWINGS))
def swing(request):
    name = request.param
    robot = ps.load(name)
    q0, qd0 = SWINGS[name]
    ref = ps.simulate(robot, q0, qd0, (0.0, T_END), t_eval=T, rtol=1e-12, atol=1e-14)
    return robot, q0, qd0, ref


def test_the_listed_methods_are_the_accepted_ones():
    assert set(SCIPY_METHODS) == set(METHODS[1:-2])
    with pytest.raises(InputError, match=r"unknown method 'rk4'; known: dopri5, cvodes, idas, "
                                         r"DOP853"):
        ps.simulate(ps.load("serial_2dof"), [0.0, 0.0], [0.0, 0.0], (0.0, 1.0), method="rk4")


def _check_against(ref, q, qd, kin, pot, label):
    err_q = float(np.max(np.abs(q - ref.q)))
    err_qd = float(np.max(np.abs(qd - ref.qd)))
    energy = kin + pot
    drift = float(np.max(np.abs(energy - energy[0])) / np.max(ref.kinetic_j))
    print(f"\n{label}: |q - dopri5| {err_q:.1e} rad, |qd - dopri5| {err_qd:.1e} rad/s, "
          f"energy drift {drift:.1e} of the peak kinetic energy")
    assert np.max(ref.kinetic_j) > 1.0e-2  # a real swing: energy moves between the forms
    assert err_q < AGREE and err_qd < AGREE
    assert drift < ENERGY_REL


@pytest.mark.parametrize("method", METHODS)
def test_every_method_agrees_with_dopri5(swing, method):
    robot, q0, qd0, ref = swing
    run = ps.simulate(robot, q0, qd0, (0.0, T_END), t_eval=T, rtol=1e-10, atol=1e-12,
                      method=method)
    assert run.method == method and np.array_equal(run.t_s, T)
    _check_against(ref, run.q, run.qd, run.kinetic_j, run.potential_j,
                   f"{robot.name} {method}")


@pytest.mark.parametrize("method", ["dopri5", "cvodes", "idas"])
def test_a_torque_table_in_the_engine_against_scipy(method):
    """A torque table (a cubic spline through samples of 0.05 sin(3 t), 0.02 cos(2 t) N*m)
    through ``simulate``: evaluated in C by the engine for dopri5 and SUNDIALS, and as a
    Python function of time by SciPy's DOP853 at rtol 1e-12 (the reference): 1e-7 rad."""
    from planar_sym.motion.signals import from_table

    robot = ps.load("serial_2dof")
    knots = np.linspace(0.0, 1.0, 41)
    values = np.column_stack([0.05 * np.sin(3 * knots), 0.02 * np.cos(2 * knots)])
    table = from_table(knots, values, "cubic")
    q0, qd0, t = np.array([-1.0, 0.5]), np.zeros(2), np.linspace(0.0, 1.0, 21)
    run = ps.simulate(robot, q0, qd0, (0.0, 1.0), t_eval=t, torque=table, method=method,
                      rtol=1e-11, atol=1e-12)
    ref = ps.simulate(robot, q0, qd0, (0.0, 1.0), t_eval=t, torque=lambda tt: table(tt)[0],
                      method="DOP853", rtol=1e-12, atol=1e-13)
    assert run.method == method
    assert np.max(np.abs(run.q - ref.q)) < 1e-7 * np.max(np.abs(ref.q))
    assert np.max(np.abs(run.tau - np.vstack([table(tt)[0] for tt in t]))) < 1e-12


def fd_jacobian(robot, x, tau, h=1e-6):
    """d/dx of [qd; forward_dynamics(q, qd, tau)] by central differences (4th order)."""
    n = robot.n
    steps = np.array([2, 1, -1, -2])[:, None, None] * h * np.eye(2 * n)[None]
    pts = (x[None, None] + steps).reshape(-1, 2 * n)
    qdd = robot.forward_dynamics(pts[:, :n], pts[:, n:], np.tile(tau, (len(pts), 1)))
    f = np.concatenate([pts[:, n:], qdd], axis=1).reshape(4, 2 * n, 2 * n)
    return ((-f[0] + 8 * f[1] - 8 * f[2] + f[3]) / (12 * h)).T  # rows: outputs


@pytest.mark.parametrize("method", IMPLICIT)
def test_the_jacobian_handed_to_scipy(swing, method, monkeypatch):
    """The ``jac`` simulate passes to solve_ivp (caught on its way there), at 20 random states
    under a constant torque, against central differences of robot.forward_dynamics; and Radau
    and BDF call it."""
    robot, q0, qd0, _ = swing
    n = robot.n
    caught, calls = {}, [0]
    real = forward.solve_ivp

    def spy(fun, t_span, y0, **kwargs):
        caught.update(kwargs)
        jac = kwargs.get("jac")
        if jac is not None:
            def counted(t, y):
                calls[0] += 1
                return jac(t, y)
            kwargs["jac"] = counted
        return real(fun, t_span, y0, **kwargs)

    monkeypatch.setattr(forward, "solve_ivp", spy)
    tau = np.linspace(0.3, -0.2, n)  # N*m on every joint
    ps.simulate(robot, q0, qd0, (0.0, 0.2), torque=tau, t_eval=[0.0, 0.2], rtol=1e-8,
                atol=1e-10, method=method)
    jac = caught.get("jac")
    assert callable(jac), f"{method} got no Jacobian"
    # LSODA starts non-stiff (Adams) and stays so on a swing: it holds the Jacobian unused
    assert calls[0] >= 1 or method == "LSODA", f"{method} never called the Jacobian"
    rng = np.random.default_rng(30)
    worst, tops = 0.0, []
    for _ in range(20):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.uniform(-3, 3, n)])
        got = np.asarray(jac(0.1, x))
        ref = fd_jacobian(robot, x, tau)
        assert got.shape == (2 * n, 2 * n)
        worst = max(worst, float(np.max(np.abs(got - ref)) / np.max(np.abs(ref))))
        tops.append(got[:n])
    print(f"\n{robot.name} {method}: |jac - differences| <= {worst:.1e} of the largest entry; "
          f"called {calls[0]} times")
    assert worst < JAC_REL, f"jac differs from the differences by {worst:.3g} of its largest entry"
    # d(q)'/d(q, qd) = [0, I] exactly
    assert all(np.array_equal(top, np.hstack([np.zeros((n, n)), np.eye(n)])) for top in tops)
