"""Open-loop forward dynamics of trees (``planar_sym.dynamics.forward.simulate``) checked by
values (issue 30): every figure is compared with something computed here independently.

* the point-mass pendulum (tests/robots/point_pendulum.toml: m = 1.5 kg at L = 0.6 m, angle
  from +x, gravity -y): its exact equation of motion m L^2 qdd = tau - m g L cos q written in
  numpy and integrated by SciPy's DOP853 at rtol 1e-13 is the reference for every method
  (dopri5 in C, the six SciPy methods, cvodes and idas in the engine); the small-angle solution
  q + pi/2 = a cos(w t), w = sqrt(g / L) (1 - a^2 / 16); the work of a constant torque,
  E(t) - E(0) = tau (q(t) - q(0)); T = m L^2 qd^2 / 2 and V = m g L sin q from the state;
* a torque f(t): the default method becomes SciPy's DOP853, f is called at the output times
  (``tau``), SciPy's implicit methods get the Jacobian at the same torque; ``n_rhs`` is the count
  SciPy itself reports (``nfev``);
* the cart-pole (tests/robots/cart_pole.toml: an actuated slider, a passive hinge): no
  horizontal force but the cart's F, so the horizontal momentum
  (M + m) x' - m l sin(q2) q2' equals the impulse int F dt (F t, or A (1 - cos w t) / w),
  the energy grows by F (x(t) - x(0)) under a constant F, and ``tau`` holds F on the slider and
  0 on the hinge;
* what is passed on to a closed chain (the output times, the tolerances, ``project``) and to
  the C integrator (the step budget: a run needing k steps passes with max_steps = k, not
  k - 1); a SciPy failure named with its time; the refusals with their exact messages.

Measured on this machine (asserted bound in brackets), |q, qd - exact| over 1.5 s at rtol 1e-10
(RK23 at 1e-8), and the energy less the work of the torque, about as large: dopri5 3.0e-10,
DOP853 6.7e-10, RK45 3.5e-10, Radau 3.5e-11 [1e-8]; BDF 9.8e-9, LSODA 1.7e-9, cvodes 5.1e-9,
idas 6.1e-9 [1e-7]; RK23 2.1e-7 [2e-6]. The small-angle cosine (period corrected by a^2 / 16)
to 8e-12 rad [1e-10]; the cart-pole's momentum = impulse to 4.7e-12 N*s under a constant F
(energy less work 3.5e-12 J) and 3.2e-11 N*s under F(t) [1e-9].
"""

from __future__ import annotations

import inspect
import re
import warnings

import numpy as np
import pytest
from conftest import ROOT, TEST_ROBOTS
from scipy.integrate import solve_ivp

import planar_sym as ps
from planar_sym.dynamics import forward
from planar_sym.errors import InputError, SimulationError

M_BOB, L_ROD, G = 1.5, 0.6, 9.81  # tests/robots/point_pendulum.toml
J_PIVOT = M_BOB * L_ROD**2
M_CART, M_POLE, L_CG = 2.0, 0.5, 0.25  # tests/robots/cart_pole.toml
SCIPY = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")
#: |q, qd - exact| and |E - E0 - work| bounds per method (about 10x the measured errors)
BOUND = {"RK23": 2e-6, "BDF": 1e-7, "LSODA": 1e-7, "cvodes": 1e-7, "idas": 1e-7}
T_END = 1.5
T = np.linspace(0.0, T_END, 31)
Q0, QD0, TAU0 = -np.pi / 2 + 0.4, 0.3, 0.5  # rad, rad/s, N*m


@pytest.fixture(scope="module")
def pendulum(derived):
    return derived(TEST_ROBOTS / "point_pendulum.toml")[1]


@pytest.fixture(scope="module")
def cart_pole(derived):
    return derived(TEST_ROBOTS / "cart_pole.toml")[1]


@pytest.fixture
def nfev(monkeypatch):
    """SciPy's own count of right-hand-side evaluations of the last solve_ivp simulate ran."""
    seen = {}
    real = forward.solve_ivp

    def spy(*args, **kwargs):
        sol = real(*args, **kwargs)
        seen["nfev"] = sol.nfev
        return sol

    monkeypatch.setattr(forward, "solve_ivp", spy)
    return seen


def exact_pendulum(q0, qd0, t, tau_of):
    """The point pendulum's ODE in numpy: m L^2 qdd = tau(t) - m g L cos q; (q, qd) at t."""
    def rhs(tt, x):
        return [x[1], (tau_of(tt) - M_BOB * G * L_ROD * np.cos(x[0])) / J_PIVOT]

    sol = solve_ivp(rhs, (t[0], t[-1]), [q0, qd0], method="DOP853", t_eval=t, rtol=1e-13,
                    atol=1e-14)
    assert sol.success
    return sol.y[0], sol.y[1]


# -- the pendulum: every method against the exact ODE ------------------------------------------

@pytest.mark.parametrize("method", ["dopri5", *SCIPY, "cvodes", "idas"])
def test_pendulum_under_a_constant_torque_every_method(pendulum, nfev, method):
    rtol = 1e-8 if method == "RK23" else 1e-10  # RK23 is third order: 12 000 steps at 1e-10
    run = ps.simulate(pendulum, [Q0], [QD0], (0.0, T_END), torque=[TAU0], t_eval=T, rtol=rtol,
                      atol=1e-12, method=method)
    q_ref, qd_ref = exact_pendulum(Q0, QD0, T, lambda _t: TAU0)
    err = max(np.max(np.abs(run.q[:, 0] - q_ref)), np.max(np.abs(run.qd[:, 0] - qd_ref)))
    print(f"\n{method}: |q, qd - exact| {err:.2g}, {run.n_rhs} right-hand sides")
    assert err < BOUND.get(method, 1e-8)
    assert np.ptp(run.q) > 0.5  # a real swing
    # what the run says about itself
    assert run.method == method and run.rtol == rtol and run.atol == 1e-12
    assert np.array_equal(run.t_s, T) and run.q.shape == run.qd.shape == (31, 1)
    assert run.tau.shape == (31, 1) and np.all(run.tau == TAU0)
    assert (run.robot, run.coordinate_units, run.actuated) == ("point_pendulum", ("rad",), (0,))
    assert run.constraint_drift_m == 0.0 and run.initial_correction_rad == 0.0
    assert isinstance(run.n_rhs, int) and run.n_rhs > 30
    if method in SCIPY:
        assert run.n_rhs == nfev["nfev"]  # every evaluation SciPy made, counted once
    # energies from the state, and the work of the constant torque
    assert np.allclose(run.kinetic_j, 0.5 * J_PIVOT * run.qd[:, 0] ** 2, rtol=1e-13, atol=1e-15)
    assert np.allclose(run.potential_j, M_BOB * G * L_ROD * np.sin(run.q[:, 0]), rtol=1e-13,
                       atol=1e-13)
    work = TAU0 * (run.q[:, 0] - run.q[0, 0])
    balance = float(np.max(np.abs(run.energy_j - run.energy_j[0] - work)))
    print(f"{method}: energy - work of the torque {balance:.2g} J")
    assert balance < BOUND.get(method, 1e-8)


def test_small_oscillations_are_a_cosine(pendulum):
    """a = 1e-3 rad about the hanging pose: q + pi/2 = a cos(w t), w = sqrt(g / L) (1 - a^2 / 16)
    (the finite-amplitude lengthening of the period), to O(a^3) = 1e-9 / 192."""
    amp, t = 1e-3, np.linspace(0.0, 2.0, 201)
    run = ps.simulate(pendulum, [-np.pi / 2 + amp], [0.0], (0.0, 2.0), t_eval=t)
    assert run.method == "dopri5"
    swing = amp * np.cos(np.sqrt(G / L_ROD) * (1.0 - amp**2 / 16.0) * t)
    err = float(np.max(np.abs(run.q[:, 0] + np.pi / 2 - swing)))
    print(f"\nsmall-angle: |q + pi/2 - a cos(w t)| {err:.2g} rad")
    assert err < 1e-10
    assert np.all(run.tau == 0.0) and run.tau.shape == (201, 1)
    assert run.energy_drift < 1e-9


def test_a_torque_function_runs_in_scipy(pendulum, nfev):
    """f(t) = 0.4 sin(3 t) N*m: the default method becomes DOP853 (C dopri5 takes constant
    torques only), tau holds f at the output times, the motion follows the exact ODE."""
    def f(t):
        return [0.4 * np.sin(3.0 * t)]

    run = ps.simulate(pendulum, [Q0], [QD0], (0.0, T_END), torque=f, t_eval=T, rtol=1e-11,
                      atol=1e-12)
    q_ref, qd_ref = exact_pendulum(Q0, QD0, T, lambda tt: f(tt)[0])
    assert run.method == "DOP853" and run.rtol == 1e-11 and run.atol == 1e-12
    assert np.max(np.abs(run.q[:, 0] - q_ref)) < 1e-8
    assert np.max(np.abs(run.qd[:, 0] - qd_ref)) < 1e-8
    assert run.tau.shape == (31, 1) and np.array_equal(run.tau[:, 0], 0.4 * np.sin(3.0 * T))
    assert run.n_rhs == nfev["nfev"] and run.n_rhs > 30
    assert (run.robot, run.coordinate_units, run.actuated) == ("point_pendulum", ("rad",), (0,))


@pytest.mark.parametrize("method", ["Radau", "BDF"])
def test_implicit_methods_take_the_jacobian_at_the_torque_of_the_time(pendulum, method,
                                                                      monkeypatch):
    """The Jacobian handed to Radau and BDF under f(t): d qdd / d q = m g L sin q / (m L^2),
    d qdd / d qd = 0 here, and it is evaluated at the torque of its time (a torque function
    called at a time, not at None); the run follows the exact ODE."""
    caught = {}
    real = forward.solve_ivp

    def spy(fun, t_span, y0, **kwargs):
        caught.update(kwargs)
        return real(fun, t_span, y0, **kwargs)

    monkeypatch.setattr(forward, "solve_ivp", spy)
    calls = []

    def f(t):
        calls.append(t)
        return [0.2 + 0.1 * t]

    run = ps.simulate(pendulum, [Q0], [QD0], (0.0, 1.0), torque=f, t_eval=T[:21], rtol=1e-10,
                      atol=1e-12, method=method)
    q_ref, _ = exact_pendulum(Q0, QD0, T[:21], lambda tt: f(tt)[0])
    assert run.method == method and np.max(np.abs(run.q[:, 0] - q_ref)) < 1e-7
    jac = caught["jac"]
    got = np.asarray(jac(0.7, np.array([0.3, -1.0])))
    assert np.allclose(got, [[0.0, 1.0], [M_BOB * G * L_ROD * np.sin(0.3) / J_PIVOT, 0.0]],
                       rtol=1e-12, atol=1e-12)
    assert calls[-1] == 0.7  # the Jacobian asked f at its own time


@pytest.mark.parametrize("method", ["dopri5", "DOP853", "RK45", "RK23"])
def test_explicit_methods_get_no_jacobian(pendulum, method):
    """SciPy warns about a ``jac`` its explicit methods cannot use: none is passed (the
    default dopri5 with a torque function runs DOP853 too)."""
    torque = (lambda t: [0.1 * t]) if method == "dopri5" else [0.1]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        run = ps.simulate(pendulum, [Q0], [0.0], (0.0, 0.2), torque=torque, method=method,
                          t_eval=[0.0, 0.1, 0.2], rtol=1e-6, atol=1e-9)
    assert run.method == ("DOP853" if method == "dopri5" else method)


# -- the cart-pole: a slider driven, a hinge passive --------------------------------------------

def momentum_x(run) -> np.ndarray:
    """Horizontal momentum (N*s): the cart's (M + m) x' less the pole's m l sin(q2) q2'."""
    return ((M_CART + M_POLE) * run.qd[:, 0]
            - M_POLE * L_CG * np.sin(run.q[:, 1]) * run.qd[:, 1])


def test_cart_pole_constant_force(cart_pole):
    """F = 1.2 N on the cart (dopri5 in C): momentum F t, energy + F (x - x0), tau [F, 0]."""
    t = np.linspace(0.0, 1.0, 41)
    run = ps.simulate(cart_pole, [0.0, 0.3], [0.0, 0.0], (0.0, 1.0), torque=[1.2], t_eval=t)
    assert run.method == "dopri5" and run.coordinate_units == ("m", "rad")
    assert run.actuated == (0,) and run.robot == "cart_pole"
    assert run.tau.shape == (41, 2)
    assert np.all(run.tau[:, 0] == 1.2) and np.all(run.tau[:, 1] == 0.0)
    err = float(np.max(np.abs(momentum_x(run) - 1.2 * t)))
    work = 1.2 * (run.q[:, 0] - run.q[0, 0])
    balance = float(np.max(np.abs(run.energy_j - run.energy_j[0] - work)))
    print(f"\ncart-pole, F = 1.2 N: |p_x - F t| {err:.2g} N*s, energy - work {balance:.2g} J")
    assert err < 1e-9 and balance < 1e-9
    assert np.ptp(run.q[:, 1]) > 0.1  # the pole swings: the passive joint got no force
    assert isinstance(run.n_rhs, int) and run.n_rhs > 40


def test_cart_pole_force_of_time(cart_pole, nfev):
    """F(t) = 0.8 sin(2 t) N through SciPy: momentum 0.8 (1 - cos 2t) / 2, tau [F(t), 0]."""
    t = np.linspace(0.0, 1.0, 41)
    run = ps.simulate(cart_pole, [0.0, 0.3], [0.0, 0.0], (0.0, 1.0),
                      torque=lambda tt: [0.8 * np.sin(2.0 * tt)], t_eval=t, rtol=1e-11,
                      atol=1e-12)
    assert run.method == "DOP853" and run.n_rhs == nfev["nfev"]
    assert run.tau.shape == (41, 2)
    assert np.array_equal(run.tau[:, 0], 0.8 * np.sin(2.0 * t)) and np.all(run.tau[:, 1] == 0)
    err = float(np.max(np.abs(momentum_x(run) - 0.8 * (1.0 - np.cos(2.0 * t)) / 2.0)))
    print(f"\ncart-pole, F(t): |p_x - impulse| {err:.2g} N*s")
    assert err < 1e-9


# -- closed chains: what simulate passes on ----------------------------------------------------

def test_closed_chain_gets_the_output_times_and_tolerances():
    five = ps.load("five_bar_type1")
    t = np.array([0.0, 0.01, 0.025, 0.05])
    run = ps.simulate(five, five.q_drawn, np.zeros(4), (0.0, 0.05), t_eval=t, rtol=1e-9,
                      atol=1e-10, torque=[0.01, -0.02])
    assert np.array_equal(run.t_s, t) and run.q.shape == (4, 4)
    assert run.rtol == 1e-9 and run.atol == 1e-10 and run.method == "dopri5"
    assert run.tau.shape == (4, 2) and np.all(run.tau == [0.01, -0.02])
    assert np.max(np.abs(five.constraint(run.q))) < 1e-9


@pytest.mark.parametrize("method", ["dopri5", "cvodes"])
def test_closed_chain_project(method):
    """Off the loops by 0.01 rad at a passive joint: refused by default (naming q0 and the
    way out), solved back onto the loops with project=True (the correction reported)."""
    five = ps.load("five_bar_type1")  # A, B, E, D; actuated A and E
    q0 = five.q_drawn.copy()
    q0[1] += 0.01
    with pytest.raises(InputError, match=r"q0.*pass project=True \(planar_sym.simulate\) to solve "
                                         r"the passive joints from the actuated ones"):
        ps.simulate(five, q0, np.zeros(4), (0.0, 0.02), method=method)
    run = ps.simulate(five, q0, np.zeros(4), (0.0, 0.02), t_eval=[0.0, 0.02], method=method,
                      project=True)
    assert abs(run.initial_correction_rad - 0.01) < 1e-9
    assert np.allclose(run.q[0], five.q_drawn, atol=1e-9)  # the actuated joints kept
    assert np.max(np.abs(five.constraint(run.q))) < 1e-9


# -- refusals and defaults -----------------------------------------------------------------------

def test_refusals_name_what_is_wrong(pendulum):
    with pytest.raises(InputError) as info:
        ps.simulate("point_pendulum", [0.0], [0.0], (0.0, 1.0))
    assert str(info.value) == "simulate needs a Robot (planar_sym.load), got str"
    with pytest.raises(InputError) as info:
        ps.simulate(pendulum, [0.0], [0.0], (0.0, 1.0), method="rk4")
    assert str(info.value) == ("unknown method 'rk4'; known: dopri5, cvodes, idas, DOP853, "
                               "RK45, RK23, Radau, BDF, LSODA")
    with pytest.raises(InputError) as info:
        ps.simulate(pendulum, [0.0, 1.0], [0.0], (0.0, 1.0))
    assert str(info.value) == "q0 must have shape (N, 1) or (1,), got (2,)"
    with pytest.raises(InputError) as info:
        ps.simulate(pendulum, [0.0], [[0.0], [1.0]], (0.0, 1.0))
    assert str(info.value) == "qd0 must be one vector of 1 values, got 2 rows (shape (2, 1))"


def test_a_failing_scipy_run_names_the_time(pendulum):
    """tau = 1 / (0.5 - t) N*m: qd grows like -log(0.5 - t), SciPy's steps shrink to nothing
    at t = 0.5 s; the error names that time (the last the dynamics were asked at) and SciPy's
    reason."""
    with pytest.raises(SimulationError) as info:
        ps.simulate(pendulum, [-1.0], [0.0], (0.0, 1.0), t_eval=[0.0, 1.0], method="DOP853",
                    torque=lambda t: [1.0 / (0.5 - t) if t < 0.5 else 0.0], rtol=1e-6,
                    atol=1e-9)
    assert str(info.value) == ("point_pendulum: integration failed at t = 0.5 s: Required step "
                               "size is less than spacing between numbers.")


def test_the_default_step_budget():
    """Ten million steps of the C integrator unless told (a run needing exactly one more step
    would tell 10_000_001 apart, but takes 10^7 outputs: 5 s and 250 MB)."""
    params = inspect.signature(ps.simulate).parameters
    assert params["max_steps"].default == 10_000_000
    assert params["project"].default is False and params["method"].default == "dopri5"
    assert params["rtol"].default == 1e-11 and params["atol"].default == 1e-12


def test_the_step_budget_reaches_the_c_integrator(pendulum):
    """max_steps k: the run that needs k steps passes, with k - 1 it stops naming a time."""
    run = ps.simulate(pendulum, [Q0], [0.0], (0.0, 1.0), t_eval=T[:21])
    steps = (run.n_rhs - 1) // 6
    again = ps.simulate(pendulum, [Q0], [0.0], (0.0, 1.0), t_eval=T[:21], max_steps=steps)
    assert np.array_equal(again.q, run.q)
    with pytest.raises(Exception, match=r"integration failed at t = ([0-9.e-]+) s: too many "
                                        r"steps") as info:
        ps.simulate(pendulum, [Q0], [0.0], (0.0, 1.0), t_eval=T[:21], max_steps=steps - 1)
    assert 0.0 < float(re.search(r"t = ([0-9.e-]+) s", str(info.value)).group(1)) < 1.0


# -- a watched run (progress=...) ---------------------------------------------------------------

@pytest.mark.parametrize("method", ["dopri5", "Radau"])
def test_a_watched_run_is_the_direct_run_argument_for_argument(pendulum, method):
    """Catches an argument dropped or emptied where simulate calls itself again inside
    ``watching(progress)``: with and without a progress callback the run is the same, bit for
    bit, where every argument differs from its default and changes the run (a start state of
    its own, a torque, a span from 0.1 s, output times, tolerances looser than the defaults),
    a step budget that fails the run the same way, and a closed chain off its loops that only
    ``project=True`` starts (the correction, 0.01 rad, reported by both)."""
    args = {"torque": [0.4], "t_eval": np.linspace(0.1, 0.9, 9), "rtol": 1e-7, "atol": 1e-9,
            "method": method}
    heard = []
    runs = [ps.simulate(pendulum, [Q0], [QD0], (0.1, 0.9), **args),
            ps.simulate(pendulum, [Q0], [QD0], (0.1, 0.9), **args,
                        progress=lambda done, total: heard.append((done, total)))]
    for name in ("t_s", "q", "qd", "tau", "work_j", "friction_j"):
        assert np.array_equal(getattr(runs[0], name), getattr(runs[1], name)), name
    assert runs[1].method == runs[0].method and runs[1].n_rhs == runs[0].n_rhs
    assert (runs[1].rtol, runs[1].atol) == (1e-7, 1e-9)
    assert np.array_equal(runs[1].t_s, args["t_eval"]) and np.all(runs[1].tau == 0.4)
    # the torque's work is tau (q - q0) = the energy gained (the run really had the torque)
    assert np.max(np.abs(runs[1].energy_j - runs[1].energy_j[0]
                         - 0.4 * (runs[1].q[:, 0] - runs[1].q[0, 0]))) < 1e-5
    if method == "dopri5":  # the C loop reports the time it reached, up to the end 0.9 s
        assert heard and heard[-1] == (0.9, 0.9)
        steps = (runs[0].n_rhs - 1) // 6
        for progress in (None, lambda done, total: None):  # the step budget reaches the loop
            with pytest.raises(SimulationError, match="too many steps"):
                ps.simulate(pendulum, [Q0], [QD0], (0.1, 0.9), **args, max_steps=steps - 1,
                            progress=progress)
    five = ps.load("five_bar_type1")
    q0 = five.q_drawn.copy()
    q0[1] += 0.01
    closed = [ps.simulate(five, q0, np.zeros(4), (0.0, 0.02), t_eval=[0.0, 0.02], project=True,
                          progress=progress) for progress in (None, lambda done, total: None)]
    assert np.array_equal(closed[0].q, closed[1].q)
    assert abs(closed[1].initial_correction_rad - 0.01) < 1e-9


@pytest.mark.parametrize("case", ["torque of time", "rubbing joints"])
def test_scipy_runs_report_no_work_they_did_not_integrate(pendulum, case):
    """Catches the exact work tau . (q - q0) given where it does not hold (simulate's
    ``if callable(torque) or robot.has_friction``): SciPy integrates the state alone, so a
    torque f(t) (whose work is not tau(0) . (q - q0)) and a robot whose joints rub (whose
    friction loss is not zero) get no work or friction integral. The energy balance shows
    why: here E - E0 differs from tau(0) . (q - q0) by far more than the integrator's error
    (the mutant's integrals would fail balance_residual)."""
    if case == "torque of time":
        robot, q0, tau = pendulum, [Q0], lambda t: [0.5 + 0.3 * np.sin(5.0 * t)]
        tau0 = np.array([0.5])
    else:
        robot = ps.load(str(ROOT / "examples" / "serial_2dof_geared.toml"))
        q0, tau, tau0 = [-1.0, 0.5], [0.02, -0.01], np.array([0.02, -0.01])
        assert robot.has_friction
    run = ps.simulate(robot, q0, np.zeros(len(q0)), (0.0, 1.0), t_eval=np.linspace(0, 1, 21),
                      torque=tau, method="DOP853", rtol=1e-10, atol=1e-12)
    assert run.work_j is None and run.friction_j is None and run.balance_residual is None
    gap = float(np.max(np.abs(run.energy_j - run.energy_j[0] - (run.q - run.q[0]) @ tau0)))
    print(f"\n{case}: |E - E0 - tau(0) . (q - q0)| up to {gap:.3g} J")
    assert gap > 1e-5  # 4+ orders above the integrator's error at rtol 1e-10 (header)
