"""Linearisation and LQR (issue 27, item 3), each against something independent: A and B
against the closed forms of the pendulum and the cart-pole at their upright equilibria and
against central differences of the compiled forward dynamics; the gain and the closed-loop
poles against python-control; the compiled LQR loop against SciPy integrating the same law in
Python, and it brings the cart-pole from a 10 degree tilt to rest."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import TEST_ROBOTS
from scipy.integrate import solve_ivp

import planar_sym as ps
from planar_sym.control import controller, simulate_controlled
from planar_sym.errors import InputError

control = pytest.importorskip("control")

UP = np.pi / 2  # the test robots' poles point along +x at q = 0: upright is a quarter turn
G = 9.81


def test_pendulum_upright_is_the_closed_form():
    """Rod of 1.5 kg, cg 0.25 m, Izz 0.02 kg*m^2: theta'' = (m g l / I_o) dtheta + u / I_o."""
    lin = ps.linearize(ps.load("tests/robots/pendulum.toml"), [UP])
    i_o = 0.02 + 1.5 * 0.25**2
    assert np.abs(lin.a - [[0, 1], [1.5 * G * 0.25 / i_o, 0]]).max() <= 1e-12 * 40
    assert np.abs(lin.b - [[0], [1 / i_o]]).max() <= 1e-12 * 10
    assert np.abs(lin.qdd).max() < 1e-12 and lin.tau == pytest.approx([0.0], abs=1e-12)
    assert lin.states == ("pivot (rad)", "pivot_rate (rad/s)") and lin.inputs == ("pivot (N*m)",)


def test_cart_pole_upright_is_the_closed_form():
    """Cart 2 kg, pole 0.5 kg with cg 0.25 m and Izz 0.004: M = [[M + m, -m l], [-m l, I +
    m l^2]] there, and the only stiffness is the pole's gravity, m g l."""
    lin = ps.linearize(ps.load("tests/robots/cart_pole.toml"), [0.0, UP])
    m_c, m, l, i = 2.0, 0.5, 0.25, 0.004
    m_inv = np.linalg.inv([[m_c + m, -m * l], [-m * l, i + m * l * l]])
    assert np.abs(lin.a[2:, :2] - m_inv @ [[0, 0], [0, m * G * l]]).max() <= 1e-12 * 50
    assert np.abs(lin.a[2:, 2:]).max() == 0 and np.array_equal(lin.a[:2], np.eye(4)[2:])
    assert np.abs(lin.b[2:, 0] - m_inv[:, 0]).max() <= 1e-12 and not lin.b[:2].any()
    assert lin.inputs == ("slide (N)",)


@pytest.mark.parametrize("ref, qd", [("serial_2dof", [0.7, -1.1]),
                                     ("examples/serial_2dof_geared.toml", [0.02, -0.5]),
                                     ("tests/robots/cart_pole.toml", [0.3, 1.2]),
                                     ("serial_rpr", [0.4, 0.1, -0.6])])
def test_jacobians_are_central_differences_of_the_forward_dynamics(ref, qd):
    """Away from rest, with rotors and smoothed friction: A and B against the compiled forward
    dynamics differenced (h = 1e-6, truncation about 1e-12 of the scale)."""
    robot = ps.load(ref)
    rng = np.random.default_rng(3)
    q = np.asarray(robot.q_drawn) + rng.uniform(-0.4, 0.4, robot.n)
    act = list(robot.actuated)
    tau = rng.uniform(-0.05, 0.05, len(act))
    lin = ps.linearize(robot, q, qd, tau)
    n, h = robot.n, 1e-6

    def f(x, u):
        full = np.zeros(n)
        full[act] = u
        return np.concatenate([x[n:], robot.tree_forward_dynamics(x[:n], x[n:], full)])

    x0 = np.concatenate([q, qd])
    a = np.column_stack([(f(x0 + h * e, tau) - f(x0 - h * e, tau)) / (2 * h)
                         for e in np.eye(2 * n)])
    b = np.column_stack([(f(x0, tau + h * e) - f(x0, tau - h * e)) / (2 * h)
                         for e in np.eye(len(act))])
    assert np.abs(lin.a - a).max() <= 1e-7 * np.abs(a).max()
    assert np.abs(lin.b - b).max() <= 1e-7 * np.abs(b).max()
    assert np.abs(lin.qdd - f(x0, tau)[n:]).max() <= 1e-12 * np.abs(lin.qdd).max()


def test_state_space_is_python_controls():
    lin = ps.linearize(ps.load("tests/robots/cart_pole.toml"), [0.0, UP])
    sys = lin.state_space()
    assert np.array_equal(sys.A, lin.a) and np.array_equal(sys.B, lin.b)
    assert sorted(sys.poles().real) == pytest.approx(sorted(np.linalg.eigvals(lin.a).real))


def _cart_pole_lqr():
    robot = ps.load("tests/robots/cart_pole.toml")
    return robot, ps.lqr(robot, [0.0, UP], q_weight=[10.0, 50.0, 1.0, 1.0], r_weight=0.1)


def test_gain_and_poles_are_python_controls():
    _, design = _cart_pole_lqr()
    lin = design.linearization
    k, _, poles = control.lqr(lin.a, lin.b, np.diag([10.0, 50.0, 1.0, 1.0]), [[0.1]])
    assert np.abs(design.gain - k).max() <= 1e-9 * np.abs(k).max()
    key = np.lexsort  # poles compared as sorted (real, imag) pairs
    ours = design.poles[key((design.poles.imag, design.poles.real))]
    theirs = np.asarray(poles)[key((np.asarray(poles).imag, np.asarray(poles).real))]
    assert np.abs(ours - theirs).max() <= 1e-9 * np.abs(theirs).max()
    assert np.all(design.poles.real < 0)


def test_compiled_loop_brings_the_cart_pole_from_a_tilt_to_rest():
    """10 degrees off upright, at rest: the compiled loop (C dopri5) agrees with SciPy
    integrating u = u_ref + K (x_ref - x) on the compiled forward dynamics, and both end at
    the equilibrium."""
    robot, design = _cart_pole_lqr()
    ctl = design.controller(saturate=False)
    q0 = np.array([0.0, UP + np.radians(10.0)])
    t = np.linspace(0.0, 8.0, 81)
    run = simulate_controlled(robot, ctl, (0.0, 8.0), q0=q0, qd0=np.zeros(2), t_eval=t)
    x_ref = np.array([0.0, UP, 0.0, 0.0])

    def rhs(_, x):
        u = design.linearization.tau + design.gain @ (x_ref - x)
        return np.concatenate([x[2:], robot.tree_forward_dynamics(x[:2], x[2:], [u[0], 0.0])])

    ref = solve_ivp(rhs, (0.0, 8.0), np.concatenate([q0, [0.0, 0.0]]), t_eval=t, rtol=1e-11,
                    atol=1e-12)
    assert np.abs(run.q - ref.y[:2].T).max() < 1e-7
    assert np.abs(run.q[-1] - x_ref[:2]).max() < 1e-4 and np.abs(run.qd[-1]).max() < 1e-3
    # the pole came back up and the cart moved to catch it, then returned
    assert abs(run.q[:, 1] - UP).max() == pytest.approx(np.radians(10.0), rel=1e-9)
    assert np.abs(run.q[:, 0]).max() > 0.01


def test_sundials_runs_the_same_law():
    robot, design = _cart_pole_lqr()
    q0 = np.array([0.0, UP + np.radians(5.0)])
    kw = {"q0": q0, "qd0": np.zeros(2), "t_eval": np.linspace(0.0, 3.0, 31)}
    a = simulate_controlled(robot, design.controller(saturate=False), (0.0, 3.0), **kw)
    b = simulate_controlled(robot, design.controller(saturate=False), (0.0, 3.0),
                            method="cvodes", rtol=1e-10, atol=1e-12, **kw)
    assert np.abs(a.q - b.q).max() < 1e-7


def test_refusals_name_the_mistake():
    robot = ps.load("tests/robots/cart_pole.toml")
    with pytest.raises(InputError, match="not an equilibrium"):
        ps.lqr(robot, [0.0, UP + 0.2], q_weight=1.0, r_weight=1.0)
    with pytest.raises(InputError, match="r_weight must be positive definite"):
        ps.lqr(robot, [0.0, UP], q_weight=1.0, r_weight=0.0)
    with pytest.raises(InputError, match=r"q_weight must have 4 values"):
        ps.lqr(robot, [0.0, UP], q_weight=[1.0, 2.0], r_weight=1.0)
    with pytest.raises(InputError, match="off five_bar_type1's loops"):
        ps.linearize(ps.load("five_bar_type1"), np.zeros(4))
    with pytest.raises(InputError, match="planar_sym.lqr"):
        controller("lqr", 1.0, 1.0)
    _, design = _cart_pole_lqr()
    with pytest.raises(InputError, match="designed for another robot"):
        simulate_controlled(ps.load("serial_2dof"), design.controller(), (0.0, 1.0),
                            q0=[0.0, 0.0])


def _reduced_forward(robot, qa, qda, ta, q_guess):
    """qdd of the actuated coordinates by plain NumPy on the compiled functions: the passive
    joints by the loops' Newton, then the constrained equations solved as one linear system."""
    from planar_sym.motion.closure import complete_state

    q, qd = complete_state(robot, qa, qda, q_guess)
    n, act = robot.n, list(robot.actuated)
    m_mat, h = robot.mass_matrix(q), robot.bias(q, qd)
    jac = robot.constraint_jacobian(q)
    gamma = robot.constraint_bias(q, qd)
    tau = np.zeros(n)
    tau[act] = ta
    k = jac.shape[0]
    kkt = np.block([[m_mat, -jac.T], [jac, np.zeros((k, k))]])
    return np.linalg.solve(kkt, np.concatenate([tau - h, gamma]))[:n][act]


def test_closed_chain_jacobians_are_central_differences_of_its_reduced_dynamics():
    """The 5-bar in its actuated coordinates: CasADi's derivatives through the loops'
    rootfinder against central differences of the same dynamics done in NumPy."""
    fb = ps.load("five_bar_type1")
    q0 = np.asarray(fb.q_drawn)
    act = list(fb.actuated)
    qda, ta = np.array([0.4, -0.7]), np.array([0.02, -0.01])
    lin = ps.linearize(fb, q0, qd=np.array([0.4, 0.0, -0.7, 0.0]), tau=ta)
    assert lin.coordinates == tuple(act) and lin.a.shape == (4, 4) and lin.b.shape == (4, 2)
    h, x0 = 1e-6, np.concatenate([q0[act], qda])

    def f(x, u):
        return np.concatenate([x[2:], _reduced_forward(fb, x[:2], x[2:], u, q0)])

    a = np.column_stack([(f(x0 + h * e, ta) - f(x0 - h * e, ta)) / (2 * h) for e in np.eye(4)])
    b = np.column_stack([(f(x0, ta + h * e) - f(x0, ta - h * e)) / (2 * h) for e in np.eye(2)])
    assert np.abs(lin.a - a).max() <= 1e-6 * np.abs(a).max()
    assert np.abs(lin.b - b).max() <= 1e-6 * np.abs(b).max()
    assert np.abs(lin.qdd[act] - f(x0, ta)[2:]).max() <= 1e-9 * np.abs(lin.qdd).max()
    assert np.abs(fb.constraint(lin.q)).max() < 1e-12
    # the passive accelerations come from the same KKT solve: they are the loops' own
    # (Phi_p qdd_p = gamma - Phi_a qdd_a, NumPy on the compiled constraint functions)
    from planar_sym.motion.closure import complete_rates

    qd_loops, qdd_loops = complete_rates(fb, lin.q[None], qda[None], lin.qdd[act][None])
    assert np.abs(lin.qd - qd_loops[0]).max() <= 1e-12
    assert np.abs(lin.qdd - qdd_loops[0]).max() <= 1e-9 * np.abs(lin.qdd).max()


def test_lqr_holds_a_closed_chain_and_its_small_motion_is_the_linear_models():
    """The 5-bar held at its drawn pose against gravity from a 0.01 rad push on one motor: the
    compiled loop (feedback on the motors' angles and rates only) follows the linear model's
    exp((A - B K) t) x0 to second order, and settles."""
    from scipy.linalg import expm

    fb = ps.load("five_bar_type1")
    act = list(fb.actuated)
    design = ps.lqr(fb, fb.q_drawn, q_weight=[100.0, 100.0, 1.0, 1.0], r_weight=1e3)
    k = design.gain
    _, _, poles = control.lqr(design.linearization.a, design.linearization.b,
                              np.diag([100.0, 100.0, 1.0, 1.0]), [[1e3, 0], [0, 1e3]])
    assert np.sort_complex(design.poles) == pytest.approx(np.sort_complex(poles), rel=1e-9)
    from planar_sym.motion.closure import complete_state

    push = np.array([0.01, 0.0])
    q0, qd0 = complete_state(fb, design.linearization.q[act] + push, np.zeros(2),
                             design.linearization.q)
    t = np.linspace(0.0, 2.0, 21)
    run = simulate_controlled(fb, design.controller(saturate=False), (0.0, 2.0), q0=q0,
                              qd0=qd0, t_eval=t)
    closed = design.linearization.a - design.linearization.b @ k
    x_lin = np.array([expm(closed * tt) @ np.concatenate([push, [0.0, 0.0]]) for tt in t])
    dev = run.q[:, act] - design.linearization.q[act]
    assert np.abs(dev - x_lin[:, :2]).max() < 5e-3 * 0.01  # second order: seen 1.8e-5 rad
    assert np.abs(dev[-1]).max() < 1e-8  # settled (poles -10 to -38 1/s): seen 3e-11 rad
    assert np.abs(fb.constraint(run.q)).max() < 1e-8


def test_closed_chain_state_by_its_motors_or_in_another_assembly_mode():
    """Given by its actuated coordinates only, a closed chain's state is the drawn assembly
    mode's, as given in full; a pose in the other mode is kept (its A differs); the state and
    input names are the motors'; a wrong-length torque is named."""
    from planar_sym.motion.closure import solve_passive

    fb = ps.load("five_bar_type1")
    q0, act = np.asarray(fb.q_drawn), list(fb.actuated)
    full = ps.linearize(fb, q0, qd=np.zeros(4))
    short = ps.linearize(fb, q0[act], qd=np.zeros(2))
    assert np.array_equal(short.a, full.a) and np.array_equal(short.q, full.q)
    assert full.states == ("A (rad)", "E (rad)", "A_rate (rad/s)", "E_rate (rad/s)")
    assert full.inputs == ("A (N*m)", "E (N*m)")
    guess = q0.copy()
    guess[list(fb.passive)] += [2.0, -2.0]
    other = solve_passive(fb, q0[act][None], guess)[0]  # elbows the other way round
    flipped = ps.linearize(fb, other)
    assert np.abs(flipped.q - other).max() < 1e-12 and np.abs(flipped.q - q0).max() > 1.0
    assert np.abs(flipped.a - full.a).max() > 1.0
    with pytest.raises(InputError, match=r"tau must have shape \(N, 2\) or \(2,\)"):
        ps.linearize(fb, q0, tau=[0.1, 0.2, 0.3])


def test_closed_chain_driven_by_a_slider_and_its_refusals_name_the_array():
    """The slider-driven slider-crank: its state is the slider's (m, m/s), its input a force
    (N), and B is 1 / (the effective mass the slider drives) there; bad arrays are named."""
    sc = ps.load("slider_crank_slider_driven")
    lin = ps.linearize(sc, sc.q_drawn)
    assert lin.states == ("slide (m)", "slide_rate (m/s)") and lin.inputs == ("slide (N)",)
    from planar_sym.motion.closure import complete_rates

    q = lin.q[None]  # the effective mass: the closed-chain force for a unit slider acceleration
    _, unit = complete_rates(sc, q, np.zeros((1, 1)), np.ones((1, 1)))
    f1 = sc.closed_chain_inverse_dynamics(q, np.zeros((1, 3)), unit)[0][0, 0]
    f0 = sc.closed_chain_inverse_dynamics(q, np.zeros((1, 3)), np.zeros((1, 3)))[0][0, 0]
    assert lin.b[1, 0] == pytest.approx(1.0 / (f1 - f0), rel=1e-9)
    with pytest.raises(InputError, match=r"^q\[0, 0\] is nan"):
        ps.linearize(sc, [np.nan])
    with pytest.raises(InputError, match=r"^qd must have shape \(N, 1\) or \(1,\)"):
        ps.linearize(sc, sc.q_drawn, qd=[0.0, 0.0])


def test_a_design_leaning_on_smoothed_coulomb_friction_is_said():
    """At rest c tanh(qd / v_s) linearises to a damping c / v_s that holds only below v_s: a
    trial's geared arm got rate gains 10 times lower than without it, and no word. pend_lim:
    c = 0.05 N*m, v_s = 0.01 rad/s, viscous 0.01 N*m*s/rad: the slope c / v_s = 5 (by hand) is
    named; the rate gain without Coulomb friction is 10 times larger; no word without Coulomb
    friction, or moving at 100 v_s (slope 5 sech^2(100), nothing)."""
    import warnings

    robot = ps.load(TEST_ROBOTS / "pend_lim.toml")
    with pytest.warns(RuntimeWarning, match=r"pend_lim: the linearisation counts smoothed "
                                            r"Coulomb friction as damping: j1 5 N\*m\*s/rad "
                                            r"\(viscous 0\.01\)"):
        leaning = ps.lqr(robot, [-1.0], q_weight=[1, 1], r_weight=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        plain = ps.lqr(robot.with_parameters(fc_j1=0.0), [-1.0], q_weight=[1, 1], r_weight=1.0)
    assert plain.gain[0, 1] > 8 * leaning.gain[0, 1]
    # the slope the warning reads, from the drive train: c / v_s at rest, 5 sech^2(100) ~ 1e-86
    # at 100 v_s
    assert robot.drive_train.coulomb_slope([0.0])[0] == pytest.approx(5.0, rel=1e-15)
    assert robot.drive_train.coulomb_slope([1.0])[0] < 1e-80
    # the smoothing speed is a parameter too (vs_j1): doubled, the slope at rest halves
    assert robot.with_parameters(vs_j1=0.02).drive_train.coulomb_slope([0.0])[0] == (
        pytest.approx(2.5, rel=1e-15))


def test_the_coulomb_slope_is_read_at_its_own_coordinate_of_a_closed_chain():
    """A helper's review: the rates were paired with the state's coordinates by position, so on
    the five-bar (q = [A, B, E, D], A and E driven) E's drive read B's rate. A Coulomb drive on
    E (c = 0.05 N*m, v_s = 0.01 rad/s, no viscous friction): with E at rest and B at 100 v_s
    its slope is c / v_s = 5; with E at 100 v_s and B at rest, 5 sech^2(100), nothing."""
    from planar_sym.model.drive import Drive, DriveTrain

    e = Drive("E", 2, "N*m", 1.0, 0.0, 0.0, 0.05, 0.01, None, None, None, True)
    train = DriveTrain((e,), 4)
    slope = train.coulomb_slope(np.array([0.0, 1.0, 0.0, 0.3]))
    assert slope[2] == pytest.approx(5.0, rel=1e-15) and slope[[0, 1, 3]].tolist() == [0, 0, 0]
    assert train.coulomb_slope(np.array([0.0, 0.0, 1.0, 0.3]))[2] < 1e-80
    # between: at v_s, c / v_s sech^2(1) by NumPy's cosh (2.0999 N*m*s/rad), a list of rates too
    assert train.coulomb_slope([0.0, 0.0, 0.01, 0.0])[2] == pytest.approx(
        5.0 / np.cosh(1.0) ** 2, rel=1e-14)
    # the friction and the power it takes at E's rate: c tanh(1) and c tanh(1) v_s, per sample
    # of (N, n) rates or of one (n,) state
    assert train.friction([0.0, 0.0, 0.01, 0.0])[2] == pytest.approx(0.05 * np.tanh(1.0),
                                                                     rel=1e-15)
    power = 0.05 * np.tanh(1.0) * 0.01
    assert train.friction_power([0.0, 3.0, 0.01, 0.0]) == pytest.approx(power, rel=1e-15)
    assert np.allclose(train.friction_power(np.array([[0.0, 3.0, 0.01, 0.0]] * 2)), [power] * 2,
                       rtol=1e-15, atol=0.0)