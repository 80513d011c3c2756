"""Forward dynamics of closed chains (``planar_sym.dynamics.forward_closed``) checked by values
(issue 30): every figure is compared with something computed here independently.

* the loop invariants along a run: |Phi(q)| and |Phi_q qd| at every output sample, the
  reported ``constraint_drift_m``; energy conservation of a free motion and the work of a
  constant torque, E(t) - E(0) = tau . (q_act(t) - q_act(0)), exact for a constant torque;
* an independent formulation: the index-1 DAE solved here by the null-space method in numpy
  (robot.mass_matrix, bias, constraint_jacobian, constraint_bias; no KKT matrix) and
  integrated by SciPy's solve_ivp without any projection, compared at the output times;
* the initial state: refused off the loops with the exact message (q0 / qd0, the cut joint,
  the residual and its limit), or with ``project_state`` its passive joints and rates solved
  (checked against a Newton written here, ``solve_passive`` and Phi_q qd = 0), in the
  assembly mode of the state given;
* the options: the integrator named, the tolerances, the output times and the segments (each
  restarting from the state projected onto the loops), the drift limit (inclusive) and its
  message; ``project`` (closest point, orthogonal rate projection, its tolerance, its
  refusal) and ``kkt_accelerations``.

Measured on this machine (asserted with the margins in brackets), over the five built-in
closed chains: the C Dormand-Prince under constant torques agrees with the reference DAE to
5.7e-11 rad in q and 1.7e-9 rad/s in qd over 0.3 s [1e-8, 1e-6], SciPy under a torque f(t) to
2.9e-11 rad [1e-8]; over 2 s free motions max |Phi| 2.5e-12 m [1e-11], max |Phi_q qd|
1.8e-11 m/s [1e-9], energy drift 5.9e-11 of the peak kinetic energy [1e-9]; the work of a
constant torque balanced to 1.4e-11 J [1e-9], of f(t) to 4.7e-9 J (Simpson's rule over 401
samples) [1e-7]; RK23 at the reference's tolerances reproduces it to 3e-15 rad [1e-12] with
the same number of evaluations; kkt_accelerations matches the null-space solution to 2.8e-15
relative [1e-10].
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.integrate import simpson, solve_ivp

import planar_sym as ps
from planar_sym.dynamics.forward_closed import kkt_accelerations, project, simulate_closed
from planar_sym.errors import InputError, SimulationError
from planar_sym.motion.closure import solve_passive

CLOSED = ("five_bar_type1", "five_bar_type2", "parallel_3rrr", "slider_crank", "parallel_3rpr")
HINT = ("give a state on the loops (planar_sym.from_actuated), or pass "
        "project=True (planar_sym.simulate) to solve the passive joints from the actuated "
        "ones")
DRIFT_HINT = ("tighten rtol/atol or shorten segment_s; near a singular pose the constraints "
              "cannot hold")


# -- independent references ---------------------------------------------------------------------

def passive(robot) -> list[int]:
    return [i for i in range(robot.n) if i not in robot.actuated]


def accel_nullspace(robot, q, qd, tau_act) -> np.ndarray:
    """qdd of M qdd + h = S^T tau + Phi_q^T lambda, Phi_q qdd = gamma, by the null-space method:
    qdd = qdd_p + Z a with Phi_q Z = 0 (SVD), Z^T (M qdd - S^T tau + h) = 0."""
    n, m = robot.n, robot.n_constraints
    mass = np.asarray(robot.mass_matrix(q)).reshape(n, n)
    h = np.asarray(robot.bias(q, qd)).reshape(n)
    jac = np.asarray(robot.constraint_jacobian(q)).reshape(m, n)
    gamma = np.asarray(robot.constraint_bias(q, qd)).reshape(m)
    force = -h
    force[list(robot.actuated)] += tau_act
    z = np.linalg.svd(jac)[2][m:].T
    particular = np.linalg.lstsq(jac, gamma, rcond=None)[0]
    a = np.linalg.solve(z.T @ mass @ z, z.T @ (force - mass @ particular))
    return particular + z @ a


def reference(robot, q0, qd0, t, tau_of, method="DOP853", rtol=1e-12, atol=1e-13):
    """The chain integrated by solve_ivp on accel_nullspace, no projection, outputs at t."""
    n = robot.n

    def rhs(tt, x):
        return np.concatenate([x[n:], accel_nullspace(robot, x[:n], x[n:], tau_of(tt))])

    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([q0, qd0]), method=method, t_eval=t,
                    rtol=rtol, atol=atol)
    assert sol.success, sol.message
    return sol


def newton_passive(robot, q_start) -> np.ndarray:
    """Newton on Phi(q) = 0 over the passive coordinates, from q_start (actuated ones fixed)."""
    q = np.array(q_start, dtype=float)
    pas = passive(robot)
    for _ in range(12):  # quadratic: converged long before; extra steps change nothing
        jac = np.asarray(robot.constraint_jacobian(q)).reshape(robot.n_constraints, robot.n)
        q[pas] -= np.linalg.solve(jac[:, pas], robot.constraint(q))
    return q


def passive_rates(robot, q, qd_act) -> np.ndarray:
    """Every rate from the actuated ones: Phi_p qd_p = -Phi_a qd_a."""
    act, pas = list(robot.actuated), passive(robot)
    jac = np.asarray(robot.constraint_jacobian(q)).reshape(robot.n_constraints, robot.n)
    qd = np.zeros(robot.n)
    qd[act] = qd_act
    qd[pas] = np.linalg.solve(jac[:, pas], -jac[:, act] @ qd[act])
    return qd


def loop_residuals(robot, q, qd) -> tuple[np.ndarray, np.ndarray]:
    """max |Phi| and max |Phi_q qd| per sample."""
    jac = np.asarray(robot.constraint_jacobian(q)).reshape(len(q), robot.n_constraints, robot.n)
    phi = np.abs(np.asarray(robot.constraint(q)).reshape(len(q), -1)).max(axis=1)
    return phi, np.abs(np.einsum("kij,kj->ki", jac, qd)).max(axis=1)


def constant_torque(robot) -> np.ndarray:
    return 0.02 * np.arange(1, len(robot.actuated) + 1)  # N*m (N at a slider)


# -- runs against the reference, invariants, energy -----------------------------------------------

@pytest.mark.parametrize("name", CLOSED)
def test_constant_torque_run_matches_an_independent_dae(name):
    """The C integrator (default) under a constant torque, three segments of 0.1 s with two
    projections, against the null-space DAE integrated without projection; the torque acts on
    the actuated joints (the work it does is tau . delta q_act, exactly)."""
    robot = ps.load(name)
    act = list(robot.actuated)
    t = np.linspace(0.0, 0.3, 31)
    tau = constant_torque(robot)
    sim = ps.simulate(robot, robot.q_drawn, np.zeros(robot.n), (0.0, 0.3), t_eval=t, torque=tau)
    ref = reference(robot, robot.q_drawn, np.zeros(robot.n), t, lambda tt: tau)
    assert sim.method == "dopri5" and (sim.rtol, sim.atol) == (1e-11, 1e-12)
    assert np.array_equal(sim.t_s, t)
    assert sim.q.shape == sim.qd.shape == (31, robot.n)
    assert np.array_equal(sim.q[0], robot.q_drawn) and sim.initial_correction_rad == 0.0
    err_q = np.max(np.abs(sim.q - ref.y[:robot.n].T))
    err_qd = np.max(np.abs(sim.qd - ref.y[robot.n:].T))
    print(f"{name}: vs reference DAE: q {err_q:.1e} rad, qd {err_qd:.1e} rad/s")
    assert err_q < 1e-8 and err_qd < 1e-6
    assert np.ptp(sim.q, axis=0).max() > 0.1  # it moved
    phi, phi_v = loop_residuals(robot, sim.q, sim.qd)
    assert phi.max() < 1e-11 and phi_v.max() < 1e-9
    assert sim.constraint_drift_m == phi.max()
    assert np.array_equal(sim.tau, np.tile(tau, (31, 1)))
    kin, pot = robot.energy(sim.q, sim.qd)
    assert np.array_equal(sim.kinetic_j, kin) and np.array_equal(sim.potential_j, pot)
    work = (sim.q[:, act] - sim.q[0, act]) @ tau
    err_w = np.max(np.abs(sim.energy_j - sim.energy_j[0] - work))
    print(f"{name}: work {np.max(np.abs(work)):.3g} J balanced to {err_w:.1e} J")
    assert np.max(np.abs(work)) > 1e-3 and err_w < 1e-9
    assert sim.n_rhs > 100


@pytest.mark.parametrize("name", CLOSED)
def test_free_motion_keeps_energy_and_the_loops(name):
    robot = ps.load(name)
    sim = ps.simulate(robot, robot.q_drawn, np.zeros(robot.n), (0.0, 2.0),
                      t_eval=np.linspace(0.0, 2.0, 201))
    phi, phi_v = loop_residuals(robot, sim.q, sim.qd)
    e = sim.energy_j
    drift_e = np.max(np.abs(e - e[0])) / np.max(sim.kinetic_j)
    print(f"{name}: 2 s free: |Phi| {phi.max():.1e} m, |Phi_q qd| {phi_v.max():.1e} m/s, "
          f"energy {drift_e:.1e} of peak kinetic")
    assert np.max(sim.kinetic_j) > 0.05  # it fell: the check means something
    assert phi.max() < 1e-11 and phi_v.max() < 1e-9 and drift_e < 1e-9
    assert sim.constraint_drift_m == phi.max()
    assert np.array_equal(sim.tau, np.zeros((201, len(robot.actuated))))


@pytest.mark.parametrize("name,method", [("five_bar_type1", None), ("parallel_3rrr", None),
                                         ("slider_crank", "RK45"), ("five_bar_type2", "RK45")])
def test_a_torque_function_of_time_runs_in_scipy(name, method):
    """A callable torque goes through SciPy (DOP853 unless another method is named), evaluated
    at every step: against the reference DAE under the same torque, and the power balance
    d(T + V)/dt = tau(t) . qd_act integrated over the run."""
    robot = ps.load(name)
    act = list(robot.actuated)
    amp = constant_torque(robot) * 3

    def torque(tt):
        return amp * np.sin(2 * np.pi * 10.0 * tt)

    t = np.linspace(0.0, 0.2, 401)
    kw = {} if method is None else {"method": method}
    sim = ps.simulate(robot, robot.q_drawn, np.zeros(robot.n), (0.0, 0.2), t_eval=t,
                      torque=torque, **kw)
    assert sim.method == (method or "DOP853")
    ref = reference(robot, robot.q_drawn, np.zeros(robot.n), t, torque)
    err_q = np.max(np.abs(sim.q - ref.y[:robot.n].T))
    print(f"{name}: torque f(t), {sim.method}: vs reference DAE: q {err_q:.1e} rad")
    # a torque frozen at each segment's start (the C path) is about 1 rad off
    assert err_q < 1e-8
    assert np.array_equal(sim.tau, np.array([torque(tt) for tt in t]))
    phi, phi_v = loop_residuals(robot, sim.q, sim.qd)
    assert phi.max() < 1e-11 and phi_v.max() < 1e-9
    power = np.einsum("ka,ka->k", sim.tau, sim.qd[:, act])
    work = np.array([simpson(power[:k + 1], x=t[:k + 1]) if k else 0.0 for k in range(0, 401, 40)])
    gain = sim.energy_j[::40] - sim.energy_j[0]
    print(f"{name}: power balance {np.max(np.abs(gain - work)):.1e} J of "
          f"{np.max(np.abs(work)):.2g} J")
    assert np.max(np.abs(work)) > 1e-3 and np.max(np.abs(gain - work)) < 1e-7


def test_a_scipy_method_runs_with_the_given_tolerances():
    """RK23 at rtol 1e-6, atol 1e-9 on one segment is solve_ivp's RK23 at those tolerances on
    the reference DAE: same values to rounding, same number of evaluations; the method and both
    tolerances each change the result by far more (checked: the comparison can tell)."""
    robot = ps.load("five_bar_type1")
    t = np.linspace(0.0, 0.1, 11)
    tau = constant_torque(robot)  # a constant torque with a SciPy method: not the C path
    sim = simulate_closed(robot, robot.q_drawn, np.zeros(4), (0.0, 0.1), t_eval=t, torque=tau,
                          method="RK23", rtol=1e-6, atol=1e-9)
    assert (sim.method, sim.rtol, sim.atol) == ("RK23", 1e-6, 1e-9)
    q_of = {}
    for method, rtol, atol in (("RK23", 1e-6, 1e-9), ("RK45", 1e-6, 1e-9),
                               ("RK23", 1e-3, 1e-9), ("RK23", 1e-6, 1e-6)):
        sol = reference(robot, robot.q_drawn, np.zeros(4), t, lambda tt: tau, method, rtol, atol)
        q_of[method, rtol, atol] = (sol.y[:4].T, sol.nfev)
    same, nfev = q_of["RK23", 1e-6, 1e-9]
    assert np.max(np.abs(sim.q - same)) < 1e-12
    assert sim.n_rhs == nfev
    for key, (other, _) in q_of.items():
        if key != ("RK23", 1e-6, 1e-9):
            assert np.max(np.abs(sim.q - other)) > 1e-8, key


def test_simulate_closed_defaults():
    """Called directly without options: the C integrator at rtol 1e-11, atol 1e-12, 1001
    outputs, and values as accurate as the reference."""
    robot = ps.load("slider_crank")
    sim = simulate_closed(robot, robot.q_drawn, np.zeros(3), (0.0, 0.2))
    assert (sim.method, sim.rtol, sim.atol) == ("dopri5", 1e-11, 1e-12)
    assert np.array_equal(sim.t_s, np.linspace(0.0, 0.2, 1001))
    ref = reference(robot, robot.q_drawn, np.zeros(3), sim.t_s, lambda tt: np.zeros(1))
    assert np.max(np.abs(sim.q - ref.y[:3].T)) < 1e-9
    assert np.max(np.abs(sim.qd - ref.y[3:].T)) < 1e-8


# -- segments and output times ------------------------------------------------------------------

@pytest.mark.parametrize("name,method", [("five_bar_type1", "dopri5"), ("slider_crank", "dopri5"),
                                         ("slider_crank", "RK45")])
def test_outputs_wider_than_a_segment_restart_at_each(name, method):
    """Output times 0.25 s apart (segment_s 0.1 s): every interval is its own segment, so the
    run is exactly the chain of one-interval runs, each started from the previous end state
    projected onto the loops; its evaluations are their sum."""
    robot = ps.load(name)
    tau = constant_torque(robot)
    t = np.array([0.0, 0.25, 0.5, 0.75])
    sim = simulate_closed(robot, robot.q_drawn, np.zeros(robot.n), (0.0, 0.75), t_eval=t,
                          torque=tau, method=method)
    q, qd, rows, n_rhs = robot.q_drawn.copy(), np.zeros(robot.n), [robot.q_drawn], 0
    rates = [np.zeros(robot.n)]
    for k in range(3):
        part = simulate_closed(robot, q, qd, (t[k], t[k + 1]), t_eval=t[k:k + 2], torque=tau,
                               method=method)
        rows.append(part.q[-1])
        rates.append(part.qd[-1])
        n_rhs += part.n_rhs
        q, qd = project(robot, part.q[-1], part.qd[-1])
    assert np.array_equal(sim.q, np.array(rows)) and np.array_equal(sim.qd, np.array(rates))
    assert sim.n_rhs == n_rhs


@pytest.mark.parametrize("t_eval", [[0.0, 0.05, 0.1, 0.15], [0.0, 0.2], [0.0, 0.03, 0.23]])
@pytest.mark.parametrize("method", ["dopri5", "DOP853"])
def test_short_and_single_interval_segments(t_eval, method):
    """Grids whose last segment is one interval, or a single interval longer than a segment:
    every output time is there, with the reference's values."""
    robot = ps.load("five_bar_type2")
    t = np.array(t_eval)
    tau = constant_torque(robot)
    sim = simulate_closed(robot, robot.q_drawn, np.zeros(4), (0.0, t[-1]), t_eval=t,
                          torque=tau, method=method)
    assert np.array_equal(sim.t_s, t) and sim.q.shape == (len(t), 4) == sim.qd.shape
    assert sim.kinetic_j.shape == (len(t),) and sim.tau.shape == (len(t), 2)
    ref = reference(robot, robot.q_drawn, np.zeros(4), t, lambda tt: tau)
    assert np.max(np.abs(sim.q - ref.y[:4].T)) < 1e-8
    assert np.max(np.abs(sim.qd - ref.y[4:].T)) < 1e-6
    assert sim.n_rhs > 0


# -- drift limit ---------------------------------------------------------------------------------

def test_drift_limit_is_inclusive_and_names_the_segment():
    """A segment whose largest |Phi| equals drift_limit_m passes; one above it is refused with
    the exact message naming its times, its drift and the limit."""
    robot = ps.load("slider_crank")
    t = np.linspace(0.0, 0.3, 31)
    free = simulate_closed(robot, robot.q_drawn, np.zeros(3), (0.0, 0.3), t_eval=t)
    drift = [np.max(np.abs(robot.constraint(free.q[1 + 10 * s:11 + 10 * s]))) for s in range(3)]
    print(f"slider_crank: drift per segment {[f'{d:.2e}' for d in drift]} m")
    assert min(drift) > 0
    first = drift[0]
    # the limit exactly the first segment's drift: it passes; the first larger one is refused
    over = [s for s in range(3) if drift[s] > first]
    assert over, "need a segment drifting more than the first"
    s = over[0]
    with pytest.raises(SimulationError) as info:
        simulate_closed(robot, robot.q_drawn, np.zeros(3), (0.0, 0.3), t_eval=t,
                        drift_limit_m=first)
    assert str(info.value) == (
        f"slider_crank: the loops drifted apart by {drift[s]:.3g} m between t = {t[10 * s]:.6g} s "
        f"and {t[10 * s + 10]:.6g} s (limit {first:g} m): {DRIFT_HINT}")
    # the largest drift as the limit: the whole run passes, identical to the free one
    same = simulate_closed(robot, robot.q_drawn, np.zeros(3), (0.0, 0.3), t_eval=t,
                           drift_limit_m=max(drift))
    assert np.array_equal(same.q, free.q)
    # the first segment refused, half its drift as the limit
    with pytest.raises(SimulationError) as info:
        simulate_closed(robot, robot.q_drawn, np.zeros(3), (0.0, 0.3), t_eval=t,
                        drift_limit_m=first / 2)
    assert str(info.value) == (
        f"slider_crank: the loops drifted apart by {first:.3g} m between t = 0 s and 0.1 s "
        f"(limit {first / 2:g} m): {DRIFT_HINT}")


# -- refusals -------------------------------------------------------------------------------------

def test_unknown_method_refused_listing_the_known_ones():
    robot = ps.load("five_bar_type1")
    with pytest.raises(InputError) as info:
        ps.simulate(robot, robot.q_drawn, np.zeros(4), (0.0, 0.1), method="euler")
    assert str(info.value) == ("unknown method 'euler'; known: dopri5, DOP853, RK45, RK23, "
                               "Radau, BDF, LSODA")


def test_initial_vectors_of_the_wrong_shape_are_named():
    robot = ps.load("five_bar_type1")
    with pytest.raises(InputError) as info:
        simulate_closed(robot, robot.q_drawn[:3], np.zeros(4), (0.0, 0.1))
    assert str(info.value) == "q0 must have shape (N, 4) or (4,), got (3,)"
    with pytest.raises(InputError) as info:
        simulate_closed(robot, robot.q_drawn, np.zeros(5), (0.0, 0.1))
    assert str(info.value) == "qd0 must have shape (N, 4) or (4,), got (5,)"


def _expected_off_loops(robot, label, residual, limit, unit, what):
    cut = robot.loops[int(np.argmax(np.abs(residual))) // 2]
    return (f"{robot.name}: {label} is off the loop constraints: |{what}| = "
            f"{np.max(np.abs(residual)):.3g} {unit} at cut joint {cut} (limit {limit:.3g}); "
            f"{HINT}")


@pytest.mark.parametrize("name,joint,delta,cut", [
    ("five_bar_type1", 1, 2e-3, "C"),   # |Phi_y| > |Phi_x|
    ("five_bar_type2", 3, -1e-3, "C"),
    ("parallel_3rrr", 6, 1e-3, "B3"),   # elbow3: only the second loop opens
    ("parallel_3rrr", 4, 1e-3, "B2"),
    ("slider_crank", 2, 1e-6, "B"),     # the slider 1 um off
])
def test_a_q0_off_the_loops_is_refused_naming_the_cut_joint(name, joint, delta, cut):
    robot = ps.load(name)
    q0 = robot.q_drawn.copy()
    q0[joint] += delta
    phi = robot.constraint(q0)
    with pytest.raises(InputError) as info:
        ps.simulate(robot, q0, np.zeros(robot.n), (0.0, 0.1))
    assert str(info.value) == _expected_off_loops(robot, "q0", phi, 1e-9, "m", "Phi")
    assert f"at cut joint {cut} " in str(info.value)


@pytest.mark.parametrize("name,rates,cut", [
    ("five_bar_type1", [1.0, 0.0, 0.0, 0.0], "C"),                    # only A turning
    ("parallel_3rrr", [0.0, 0.0, 0.0, 0.0, 0.0, -2.0, 0.0], "B3"),    # only A3 turning
    ("parallel_3rpr", [0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0], "B2"),     # only slider 2 moving
])
def test_a_qd0_off_the_loops_is_refused_naming_the_cut_joint(name, rates, cut):
    robot = ps.load(name)
    qd0 = np.array(rates)
    jac = np.asarray(robot.constraint_jacobian(robot.q_drawn))
    with pytest.raises(InputError) as info:
        ps.simulate(robot, robot.q_drawn, qd0, (0.0, 0.1))
    limit = 1e-9 * (1 + np.max(np.abs(qd0)))
    assert str(info.value) == _expected_off_loops(robot, "qd0", jac @ qd0, limit, "m/s",
                                                  "Phi_q qd")
    assert f"at cut joint {cut} " in str(info.value)


# -- project_state: the passive joints and rates solved ------------------------------------------

@pytest.mark.parametrize("name", CLOSED)
def test_project_state_solves_the_passive_joints_and_rates(name):
    """A state given by its actuated joints (moved from the drawn pose; the passive ones a
    few mrad off, their rates anything): the actuated angles and rates are kept exactly, the passive angles are the
    Newton solution from q0 (this file's and solve_passive's), the rates satisfy Phi_q qd = 0,
    and initial_correction_rad says how far the passive joints moved."""
    robot = ps.load(name)
    act, pas = list(robot.actuated), passive(robot)
    rng = np.random.default_rng(30)
    q0 = robot.q_drawn.copy()
    q0[act] += rng.uniform(-0.05, 0.05, len(act))
    q0[pas] += rng.uniform(-3e-3, 3e-3, len(pas))
    qd0 = rng.uniform(-2.0, 2.0, robot.n)
    sim = ps.simulate(robot, q0, qd0, (0.0, 0.01), t_eval=[0.0, 0.01], project=True)
    q, qd = sim.q[0], sim.qd[0]
    assert np.array_equal(q[act], q0[act]) and np.array_equal(qd[act], qd0[act])
    mine = newton_passive(robot, q0)
    assert np.max(np.abs(robot.constraint(mine))) < 1e-13
    assert np.max(np.abs(q - mine)) < 1e-12
    assert np.max(np.abs(q - solve_passive(robot, q0[act], q_guess=q0)[0])) < 1e-12
    assert np.max(np.abs(robot.constraint(q))) < 1e-13
    expected_qd = passive_rates(robot, q, qd0[act])
    assert np.max(np.abs(qd - expected_qd)) < 1e-12 * (1 + np.max(np.abs(expected_qd)))
    assert np.max(np.abs(np.asarray(robot.constraint_jacobian(q)) @ qd)) < 1e-12
    assert sim.initial_correction_rad == np.max(np.abs(q - q0)) > 1e-4
    # one step later the run still agrees with the reference from the solved state
    ref = reference(robot, q, qd, np.array([0.0, 0.01]), lambda tt: np.zeros(len(act)))
    assert np.max(np.abs(sim.q[1] - ref.y[:robot.n, 1])) < 1e-9


@pytest.mark.parametrize("name,guess", [("five_bar_type1", {1: -2.62, 3: 2.62}),
                                        ("slider_crank", {1: 2.54, 2: -0.55})])
def test_project_state_keeps_the_assembly_mode_of_q0(name, guess):
    """q0 near the other assembly mode (not the drawn one): the passive joints are solved
    from q0, so they stay in that mode, a few mrad from q0."""
    robot = ps.load(name)
    start = robot.q_drawn.copy()
    for i, v in guess.items():
        start[i] = v
    other = newton_passive(robot, start)
    drawn_mode = newton_passive(robot, robot.q_drawn)
    assert np.max(np.abs(other - drawn_mode)) > 0.5  # really another mode
    q0 = other.copy()
    q0[passive(robot)] += 2e-3
    sim = ps.simulate(robot, q0, np.zeros(robot.n), (0.0, 0.01), t_eval=[0.0, 0.01],
                      project=True)
    assert np.max(np.abs(sim.q[0] - other)) < 1e-12
    assert sim.initial_correction_rad == pytest.approx(2e-3, rel=1e-6)


# -- project ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["five_bar_type1", "parallel_3rrr", "parallel_3rpr"])
def test_project_is_the_closest_point_and_the_orthogonal_rate_projection(name):
    """From a point moved off the loops along Phi_q^T (the normal), Gauss-Newton returns the
    point it left (to the square of the move); the rates become their orthogonal projection
    onto the null space of Phi_q, Z Z^T qd (Z from an SVD here)."""
    robot = ps.load(name)
    rng = np.random.default_rng(7)
    q_on = newton_passive(robot, robot.q_drawn)
    jac = np.asarray(robot.constraint_jacobian(q_on))
    normal = jac.T @ rng.uniform(-1, 1, robot.n_constraints)
    q_off = q_on + 1e-5 * normal / np.max(np.abs(normal))
    qd = rng.uniform(-2, 2, robot.n)
    q_in, qd_in = q_off.copy(), qd.copy()
    q, qd_out = project(robot, q_off, qd)
    assert np.array_equal(q_off, q_in) and np.array_equal(qd, qd_in)  # inputs untouched
    assert q.dtype == qd_out.dtype == np.float64
    assert np.max(np.abs(robot.constraint(q))) < 1e-13
    assert np.max(np.abs(q - q_on)) < 1e-9
    jac = np.asarray(robot.constraint_jacobian(q))
    z = np.linalg.svd(jac)[2][robot.n_constraints:].T
    assert np.max(np.abs(qd_out - z @ (z.T @ qd))) < 1e-13
    assert np.max(np.abs(jac @ qd_out)) < 1e-13


def test_project_works_in_double_precision_whatever_it_is_given():
    """float32 angles and integer rates are taken as float64: the projection reaches
    |Phi| < 1e-13 m and Phi_q qd = 0 to rounding (in float32 neither could)."""
    robot = ps.load("five_bar_type1")
    q32 = (robot.q_drawn + np.array([0.0, 3e-3, 0.0, -2e-3])).astype(np.float32)
    q, qd = project(robot, q32, [1, 0, 0, 2])
    assert q.dtype == qd.dtype == np.float64
    assert np.max(np.abs(robot.constraint(q))) < 1e-13
    assert np.max(np.abs(np.asarray(robot.constraint_jacobian(q)) @ qd)) < 1e-14
    assert np.max(np.abs(q - q32.astype(float))) < 5e-3


def test_project_steps_until_the_residual_is_below_the_tolerance():
    """A slider-crank pose whose residual is exactly NEWTON_TOL_M = 1e-13 m (crank at 0, rod a
    hair off the line): it is not yet converged, projection takes a step and ends below it."""
    robot = ps.load("slider_crank")
    rod, crank, offset = robot.p[10], robot.p[9], robot.p[11]
    # Phi = [crank cos q1 + rod cos(q1 + q2) - (s + offset), crank sin q1 + rod sin(q1 + q2)]
    q2 = 1e-13 / rod + np.arange(-200, 201) * np.spacing(1e-13 / rod)
    cand = np.zeros((len(q2), 3))
    cand[:, 1] = q2
    cand[:, 2] = crank + rod - offset
    phi = np.asarray(robot.constraint(cand))
    tie = np.flatnonzero(np.max(np.abs(phi), axis=1) == 1e-13)
    assert tie.size, "no pose with |Phi| exactly 1e-13 m among the candidates"
    q_tie = cand[tie[0]]
    q, _ = project(robot, q_tie, np.zeros(3))
    assert np.max(np.abs(robot.constraint(q))) < 1e-13
    assert not np.array_equal(q, q_tie)


def test_project_refuses_loops_that_cannot_close():
    """A five-bar whose base is 1 m wide with 0.2 m arms cannot close: Gauss-Newton gives up
    after its iterations, naming the robot, where it stopped and the residual (at least the
    gap / sqrt 2, the gap being 1 - 0.2 - 0.2 = 0.6 m)."""
    robot = ps.load("five_bar_type1").with_parameters(px_ground_E=1.0)
    with pytest.raises(SimulationError) as info:
        project(robot, robot.q_drawn, np.zeros(4))
    found = re.fullmatch(r"five_bar_type1: cannot project q = \[(.*)\] onto the loop "
                         r"constraints \(\|Phi\| = (\S+) m\)", str(info.value))
    assert found, str(info.value)
    assert len(found.group(1).split(", ")) == 4
    gap = 1.0 - 2 * 0.1 - 2 * 0.1  # base - left arm (two 0.1 m links to C) - right arm
    assert float(found.group(2)) >= 0.99 * gap / np.sqrt(2)


# -- kkt_accelerations ----------------------------------------------------------------------------

def states_on_loops(robot, count, seed):
    rng = np.random.default_rng(seed)
    act = list(robot.actuated)
    qs, qds = [], []
    for _ in range(count):
        q = robot.q_drawn.copy()
        q[act] += rng.uniform(-0.1, 0.1, len(act))
        q = newton_passive(robot, q)
        qs.append(q)
        qds.append(passive_rates(robot, q, rng.uniform(-2, 2, len(act))))
    tau = rng.uniform(-0.5, 0.5, (count, len(act)))
    return np.array(qs), np.array(qds), tau


@pytest.mark.parametrize("name", CLOSED)
def test_kkt_accelerations_match_the_null_space_solution(name):
    robot = ps.load(name)
    q, qd, tau = states_on_loops(robot, 6, 11)
    qdd = kkt_accelerations(robot, q, qd, tau)
    assert qdd.shape == (6, robot.n)
    expected = np.array([accel_nullspace(robot, *row) for row in zip(q, qd, tau)])
    err = np.max(np.abs(qdd - expected)) / np.max(np.abs(expected))
    print(f"{name}: KKT vs null space {err:.1e}")
    assert err < 1e-10
    jac = np.asarray(robot.constraint_jacobian(q)).reshape(6, robot.n_constraints, robot.n)
    gamma = np.asarray(robot.constraint_bias(q, qd)).reshape(6, -1)
    assert np.max(np.abs(np.einsum("kij,kj->ki", jac, qdd) - gamma)) < 1e-9 * (
        1 + np.max(np.abs(qdd)))
    # the torques matter, with their sign: without them the accelerations differ
    assert np.max(np.abs(kkt_accelerations(robot, q, qd, 0 * tau) - qdd)) > 1e-3
    # one state as vectors: shape (1, n), the same numbers
    one = kkt_accelerations(robot, q[2], qd[2], tau[2])
    assert one.shape == (1, robot.n)
    assert np.max(np.abs(one[0] - qdd[2])) <= 1e-12 * np.max(np.abs(qdd[2]))


def test_kkt_accelerations_take_their_inputs_as_float64():
    """Inputs of another dtype are converted first: extended-precision torques give the
    accelerations of their float64 values, bit for bit (not a sum rounded twice); integer
    lists work."""
    robot = ps.load("five_bar_type1")
    q, qd, tau = states_on_loops(robot, 8, 5)
    tau_ld = tau.astype(np.longdouble) / np.longdouble(3)
    assert np.any(tau_ld.astype(float).astype(np.longdouble) != tau_ld)  # really more digits
    assert np.array_equal(kkt_accelerations(robot, q, qd, tau_ld),
                          kkt_accelerations(robot, q, qd, tau_ld.astype(float)))
    ints = kkt_accelerations(robot, q[0], [0, 0, 0, 0], [1, -1])
    assert np.array_equal(ints, kkt_accelerations(robot, q[0], np.zeros(4), [1.0, -1.0]))


def test_every_route_types_its_run_with_the_robot():
    """A closed chain's run under SciPy and under the C integrator carries the robot's name,
    units and actuated coordinates (its series are named from them, not guessed)."""
    five = ps.load("five_bar_type1")
    for method in ("dopri5", "RK45"):
        sim = ps.simulate(five, five.q_drawn, np.zeros(five.n), (0.0, 0.05), method=method)
        assert (sim.robot, sim.actuated, sim.coordinate_units) == (
            "five_bar_type1", (0, 2), ("rad",) * 4), method
        assert [s.unit for s in sim.series("q")] == ["rad"] * 4
