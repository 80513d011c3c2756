"""What ``planar_sym.dynamics.integrate`` provides to both forward-dynamics paths, checked by
values (issue 30):

* ``Simulation``: its columns, named as the study CSVs name them (a slider's ``q2_m``,
  ``qd2_m_s``, ``tau2_n``; a passive joint's torque column 0; a closed chain's actuated torques
  only), each the very array of the run; ``metadata`` exactly; the NPZ and DataFrame round trips
  bit for bit; ``energy_drift`` by its formula max |E - E0| / max(|E0|, max T); the refusals of
  a Simulation that cannot name its columns;
* the refusals of the inputs with their exact messages: tolerances, time spans and output
  times, torques (constant or functions of time, a wrong shape or a NaN named with its time);
* the C Dormand-Prince driver ``dopri5``: every failure code with its message (too many steps,
  the step size, a failing right-hand side, a robot too large, an unknown code), ``n_rhs`` =
  1 + 6 steps (the step budget that just suffices is (n_rhs - 1) / 6), inputs of any numeric
  dtype, the actuated joints of a closed chain (the C run against SciPy's on the Python KKT
  system, and the work of the torque), the helper loaded once.

Measured on this machine (asserted bound in brackets): the point pendulum through ``dopri5``
against its exact ODE (SciPy DOP853 at rtol 1e-13) 2e-11 [1e-9]; the five-bar under constant
torques over 0.2 s, C dopri5 against SciPy DOP853, 1e-11 rad [1e-9]; its energy gain against the
work tau . (q_act - q_act0): 1.6e-12 J [1e-9].
"""

from __future__ import annotations

import ctypes
import dataclasses
import re
import types

import numpy as np
import pytest
from conftest import TEST_ROBOTS
from scipy.integrate import solve_ivp

import planar_sym as ps
from planar_sym.dynamics import integrate
from planar_sym.dynamics.columns import load_npz
from planar_sym.dynamics.integrate import (
    check_tolerances,
    dopri5,
    time_grid,
    torque_function,
)
from planar_sym.errors import InputError, SimulationError

M_BOB, L_ROD, G = 1.5, 0.6, 9.81  # tests/robots/point_pendulum.toml
J_PIVOT = M_BOB * L_ROD**2
#: the generated ``<robot>_forward_dynamics_batch`` signature (n, q, qd, tau, p, qdd)
FD_BATCH = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_longlong, *[ctypes.c_void_p] * 5)


@pytest.fixture(scope="module")
def pendulum(derived):
    return derived(TEST_ROBOTS / "point_pendulum.toml")[1]


@pytest.fixture(scope="module")
def cart_pole(derived):
    return derived(TEST_ROBOTS / "cart_pole.toml")[1]


@pytest.fixture(scope="module")
def rpr_run():
    robot = ps.load("serial_rpr")  # revolute, prismatic (m), revolute
    return ps.simulate(robot, robot.q_drawn, [0.1, -0.05, 0.2], (0.0, 0.2),
                       t_eval=np.linspace(0.0, 0.2, 11), torque=[0.05, 1.5, -0.01])


@pytest.fixture(scope="module")
def five_run():
    five = ps.load("five_bar_type1")  # A, B, E, D; actuated A and E
    return ps.simulate(five, five.q_drawn, np.zeros(4), (0.0, 0.2), torque=[0.3, -0.2],
                       t_eval=np.linspace(0.0, 0.2, 21))


def same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def message(info) -> str:
    return str(info.value)


# -- Simulation: columns, metadata, files ------------------------------------------------------

def test_columns_of_a_robot_with_a_slider(rpr_run):
    cols = rpr_run.columns()
    assert list(cols) == ["t_s", "q1_rad", "q2_m", "q3_rad", "qd1_rad_s", "qd2_m_s",
                          "qd3_rad_s", "tau1_n_m", "tau2_n", "tau3_n_m", "kinetic_j",
                          "potential_j", "energy_j"]
    assert cols["t_s"] is rpr_run.t_s
    for k in range(3):
        name = ("q1_rad", "q2_m", "q3_rad")[k]
        assert same_bits(cols[name], rpr_run.q[:, k])
        assert same_bits(cols[("qd1_rad_s", "qd2_m_s", "qd3_rad_s")[k]], rpr_run.qd[:, k])
    assert np.all(cols["tau2_n"] == 1.5) and np.all(cols["tau3_n_m"] == -0.01)
    assert np.all(cols["tau1_n_m"] == 0.05)
    assert cols["kinetic_j"] is rpr_run.kinetic_j and cols["potential_j"] is rpr_run.potential_j
    assert same_bits(cols["energy_j"], rpr_run.kinetic_j + rpr_run.potential_j)
    assert np.ptp(cols["kinetic_j"]) > 0 and np.ptp(cols["potential_j"]) > 0


def test_columns_of_a_passive_joint_and_of_a_closed_chain(cart_pole, five_run):
    """A tree's tau covers every coordinate (0 at the passive hinge); a closed chain's only
    the actuated ones, named by coordinate (A = 1, E = 3)."""
    run = ps.simulate(cart_pole, [0.0, 0.3], [0.0, 0.0], (0.0, 0.1), torque=[0.7],
                      t_eval=[0.0, 0.05, 0.1])
    cols = run.columns()
    assert [k for k in cols if k.startswith(("q", "tau"))] == [
        "q1_m", "q2_rad", "qd1_m_s", "qd2_rad_s", "tau1_n", "tau2_n_m"]
    assert np.all(cols["tau1_n"] == 0.7) and np.all(cols["tau2_n_m"] == 0.0)
    cols = five_run.columns()
    assert [k for k in cols if k.startswith("tau")] == ["tau1_n_m", "tau3_n_m"]
    assert np.all(cols["tau1_n_m"] == 0.3) and np.all(cols["tau3_n_m"] == -0.2)
    assert same_bits(cols["q4_rad"], five_run.q[:, 3]) and len(cols) == 1 + 4 + 4 + 2 + 3


def test_columns_refused_when_they_cannot_be_named(rpr_run, five_run, cart_pole):
    bare = dataclasses.replace(rpr_run, coordinate_units=())
    with pytest.raises(InputError) as info:
        bare.columns()
    assert message(info) == (
        "this Simulation does not know its 3 coordinates' units (made without a robot): use "
        "planar_sym.simulate's result, or dataclasses.replace(sim, coordinate_units=('rad', "
        "'m', ...))")
    with pytest.raises(InputError) as info:
        dataclasses.replace(five_run, tau=np.zeros((21, 3))).columns()
    assert message(info) == "tau has 3 columns, neither the 4 coordinates nor the 2 actuated ones"
    run = ps.simulate(cart_pole, [0.0, 0.3], [0.0, 0.0], (0.0, 0.1), t_eval=[0.0, 0.1])
    with pytest.raises(InputError) as info:  # one torque per sample, but not as a column
        dataclasses.replace(run, tau=run.tau[:, 0]).columns()
    assert message(info) == "tau has 0 columns, neither the 2 coordinates nor the 1 actuated ones"


def test_metadata(rpr_run, five_run):
    assert rpr_run.metadata() == {
        "robot": "serial_rpr", "method": "dopri5", "rtol": "1e-11", "atol": "1e-12",
        "n_rhs": str(rpr_run.n_rhs), "constraint_drift_m": "0.0", "writer": "planar-sym"}
    meta = five_run.metadata()
    assert meta["robot"] == "five_bar_type1" and meta["n_rhs"] == str(five_run.n_rhs)
    assert meta["constraint_drift_m"] == repr(five_run.constraint_drift_m)
    assert 0.0 < five_run.constraint_drift_m < 1e-9  # a real figure, not a default


def test_npz_and_dataframe_round_trips(rpr_run, tmp_path):
    path = rpr_run.save_npz(tmp_path / "sub" / "run.npz")
    assert path == tmp_path / "sub" / "run.npz" and path.is_file()
    columns, meta = load_npz(path)
    want = rpr_run.columns()
    assert list(columns) == list(want)
    assert all(same_bits(columns[k], v) for k, v in want.items())
    assert meta == rpr_run.metadata()
    df = rpr_run.to_dataframe()
    assert list(df.columns) == list(want) and df.attrs == rpr_run.metadata()
    assert all(same_bits(df[k].to_numpy(), v) for k, v in want.items())


def test_energy_drift_by_its_formula(rpr_run):
    """max |E - E0| / max(|E0|, max |T|, 1e-300)."""
    def drift(kin, pot):
        return dataclasses.replace(rpr_run, kinetic_j=np.array(kin, float),
                                   potential_j=np.array(pot, float)).energy_drift

    assert drift([1.0, 0.5, 2.0], [0.0, 0.4, -1.2]) == pytest.approx(0.2 / 2.0, rel=1e-15)
    assert drift([0.0, 1.0, 0.5], [-8.0, -9.0, -8.6]) == pytest.approx(0.1 / 8.0, rel=1e-13)
    assert drift([0.0, 0.0], [0.0, 0.0]) == 0.0
    e = rpr_run.energy_j
    assert rpr_run.energy_drift == float(
        np.max(np.abs(e - e[0])) / max(abs(e[0]), np.max(np.abs(rpr_run.kinetic_j))))


# -- inputs: tolerances, time grids, torques ---------------------------------------------------

@pytest.mark.parametrize("rtol, atol, text", [
    (0.0, 1e-12, "rtol must be a positive number (got 0.0)"),
    (0, 1e-12, "rtol must be a positive number (got 0)"),
    (-1e-9, 1e-12, "rtol must be a positive number (got -1e-09)"),
    (True, 1e-12, "rtol must be a positive number (got True)"),
    ("1e-6", 1e-12, "rtol must be a positive number (got '1e-6')"),
    (float("nan"), 1e-12, "rtol must be a positive number (got nan)"),
    (1e-9, 0.0, "atol must be a positive number (got 0.0)"),
    (1e-9, None, "atol must be a positive number (got None)"),
    (1e-9, False, "atol must be a positive number (got False)")])
def test_tolerances_refused(pendulum, rtol, atol, text):
    with pytest.raises(InputError) as info:
        check_tolerances(rtol, atol)
    assert message(info) == text
    with pytest.raises(InputError) as info:  # before any integrator sees them
        ps.simulate(pendulum, [0.0], [0.0], (0.0, 1.0), rtol=rtol, atol=atol)
    assert message(info) == text


def test_tolerances_accepted():
    for rtol, atol in ((1, 1), (1e-300, 5e-324), (np.float32(1e-6), np.float64(1e-9))):
        assert check_tolerances(rtol, atol) is None


@pytest.mark.parametrize("span, text", [
    ("ab", "time span must be two numbers (t0, t1) in s (got 'ab')"),
    ((0.0, 1.0, 2.0), "time span must be two numbers (t0, t1) in s (got (0.0, 1.0, 2.0))"),
    ((1.0, 0.0), "time span must be finite with end > start (got (1.0, 0.0))"),
    ((1.0, 1.0), "time span must be finite with end > start (got (1.0, 1.0))"),
    ((-np.inf, 1.0), "time span must be finite with end > start (got (-inf, 1.0))"),
    ((0.0, np.inf), "time span must be finite with end > start (got (0.0, inf))"),
    ((0.0, np.nan), "time span must be finite with end > start (got (0.0, nan))")])
def test_time_spans_refused(span, text):
    with pytest.raises(InputError) as info:
        time_grid(span, None)
    assert message(info) == text


INSIDE = "t_eval must be at least 2 increasing times inside (0.0, 1.0)"


@pytest.mark.parametrize("t_eval, text", [
    ([[0.0, 1.0]], "t_eval must be a 1-D array of times, got shape (1, 2)"),
    (["a", 1.0], ("t_eval must be an array of times in s (could not convert string to float: "
                 "'a')")),
    ([0.0, None, 1.0], "t_eval[1] is nan: times must be finite"),
    ([0.0, 0.5, np.inf], "t_eval[2] is inf: times must be finite"),
    ([0.5], INSIDE),
    ([0.0, 0.5, 0.3, 1.0], INSIDE),  # not increasing
    ([0.0, 0.5, 0.5, 1.0], INSIDE),  # a time twice
    ([-0.1, 0.5], INSIDE),  # starts before t0
    ([0.0, 0.5, 1.2], INSIDE),  # ends after t1
    ([0.0, 1.0 + 1e-15], INSIDE)])
def test_output_times_refused(pendulum, t_eval, text):
    with pytest.raises(InputError) as info:
        time_grid((0.0, 1.0), t_eval)
    assert message(info) == text
    with pytest.raises(InputError) as info:
        ps.simulate(pendulum, [0.0], [0.0], (0.0, 1.0), t_eval=t_eval)
    assert message(info) == text


def test_output_times_accepted():
    t = time_grid((0, 1), [0, 1])  # the ends included; integers become float seconds
    assert t.dtype == np.float64 and t.tolist() == [0.0, 1.0]
    assert time_grid((0.0, 2.0), np.array([0.5, 0.75])).tolist() == [0.5, 0.75]
    default = time_grid((0.5, 2.5), None)
    assert default.shape == (1001,) and default[0] == 0.5 and default[-1] == 2.5
    assert np.allclose(np.diff(default), 0.002, rtol=1e-12, atol=0)


def test_constant_torques():
    assert torque_function(None, 2)(0.3).tolist() == [0.0, 0.0]
    f = torque_function(2, 3)
    assert f(0.0).tolist() == [2.0, 2.0, 2.0] and f(None).dtype == np.float64
    assert torque_function([1, 2], 2)(5.0).dtype == np.float64
    with pytest.raises(InputError) as info:
        torque_function("abc", 2)
    rule = ("torque must be None, 2 numbers (N*m; N at a slider), one for every actuated joint, "
            "or a function of time")
    assert message(info) == f"{rule} (got 'abc': could not convert string to float: 'abc')"
    with pytest.raises(InputError) as info:
        torque_function([1, 2, 3], 2)
    assert message(info) == f"{rule} (got shape (3,): [1. 2. 3.])"
    with pytest.raises(InputError) as info:
        torque_function([[1, 2]], 2)  # one row of a table is not a constant
    assert message(info) == f"{rule} (got shape (1, 2): [[1. 2.]])"
    with pytest.raises(InputError) as info:
        torque_function([None, 1], 2)
    assert message(info) == "torque must be finite (got [nan, 1.0])"
    with pytest.raises(InputError) as info:
        torque_function([np.inf, 1], 2)
    assert message(info) == "torque must be finite (got [inf, 1.0])"


def test_torque_functions_checked_at_their_time():
    f = torque_function(lambda t: [t, 2 * t], 2)
    assert f(0.5).tolist() == [0.5, 1.0]
    ints = torque_function(lambda t: [1, 2], 2)(0.0)
    assert ints.dtype == np.float64 and ints.tolist() == [1.0, 2.0]
    cases = [(lambda t: ["x", 1.0], ("torque function returned something that is not numbers at "
                                    "t = 0.25 s (could not convert string to float: 'x')")),
             (lambda t: [1.0, 2.0, 3.0], ("torque function returned array([1., 2., 3.]) at "
                                         "t = 0.25 s; expected 2 finite values (N*m)")),
             (lambda t: [np.nan, 0.0], ("torque function returned array([nan,  0.]) at "
                                       "t = 0.25 s; expected 2 finite values (N*m)")),
             (lambda t: None, ("torque function returned array(nan) at t = 0.25 s; expected 2 "
                              "finite values (N*m)"))]
    for fn, text in cases:
        checked = torque_function(fn, 2)
        with pytest.raises(InputError) as info:
            checked(0.25)
        assert message(info) == text


def test_a_torque_function_failing_mid_run_names_its_time(pendulum):
    """NaN from t = 0.3 s on: the run stops at the first time SciPy asks past it."""
    with pytest.raises(InputError) as info:
        ps.simulate(pendulum, [-1.0], [0.0], (0.0, 1.0),
                    torque=lambda t: [np.nan if t > 0.3 else 0.1])
    found = re.fullmatch(r"torque function returned array\(\[nan\]\) at t = ([0-9.]+) s; "
                         r"expected 1 finite values \(N\*m\)", message(info))
    assert found and 0.3 < float(found.group(1)) < 0.4
    with pytest.raises(InputError) as info:
        ps.simulate(pendulum, [-1.0], [0.0], (0.0, 1.0), torque=lambda t: [1.0, 2.0])
    assert message(info) == ("torque function returned array([1., 2.]) at t = 0 s; expected 1 "
                             "finite values (N*m)")


# -- the C integrator --------------------------------------------------------------------------

def exact_pendulum(q0, qd0, t, tau):
    def rhs(_t, x):
        return [x[1], (tau - M_BOB * G * L_ROD * np.cos(x[0])) / J_PIVOT]

    sol = solve_ivp(rhs, (t[0], t[-1]), [q0, qd0], method="DOP853", t_eval=t, rtol=1e-13,
                    atol=1e-14)
    return sol.y.T


def test_dopri5_against_the_exact_pendulum_and_its_step_count(pendulum):
    """One C call: states at t, and n_rhs = 1 + 6 (accepted + rejected steps) (FSAL: one
    evaluation at the start, six per step): a budget of (n_rhs - 1) / 6 steps just suffices."""
    fd = pendulum.library.address("forward_dynamics")
    t = np.linspace(0.0, 1.0, 11)
    y0 = np.array([-1.0, 0.5])
    y, n_rhs = dopri5(pendulum, 0, fd, y0, t, np.array([0.3]), 1e-11, 1e-12, 10_000)
    err = float(np.max(np.abs(y - exact_pendulum(-1.0, 0.5, t, 0.3))))
    print(f"\ndopri5 on the pendulum: |y - exact| {err:.2g}, {n_rhs} right-hand sides")
    assert y.shape == (11, 2) and err < 1e-9
    assert type(n_rhs) is int and (n_rhs - 1) % 6 == 0 and n_rhs > 6 * 10
    steps = (n_rhs - 1) // 6
    again, _ = dopri5(pendulum, 0, fd, y0, t, np.array([0.3]), 1e-11, 1e-12, steps)
    assert same_bits(again, y)
    with pytest.raises(SimulationError, match="too many steps"):
        dopri5(pendulum, 0, fd, y0, t, np.array([0.3]), 1e-11, 1e-12, steps - 1)


def test_dopri5_takes_any_numeric_dtype(pendulum):
    """Integers (state, times, torque) are converted, not reinterpreted."""
    fd = pendulum.library.address("forward_dynamics")
    as_int = dopri5(pendulum, 0, fd, [-1, 0], [0, 1, 2], [1], 1e-10, 1e-12, 100_000)
    as_float = dopri5(pendulum, 0, fd, np.array([-1.0, 0.0]), np.array([0.0, 1.0, 2.0]),
                      np.array([1.0]), 1e-10, 1e-12, 100_000)
    assert same_bits(as_int[0], as_float[0]) and as_int[1] == as_float[1]
    assert np.max(np.abs(as_float[0] - exact_pendulum(-1.0, 0.0, [0.0, 1.0, 2.0], 1.0))) < 1e-8


@pytest.mark.parametrize("rtol, atol", [(0.0, 1e-12), (1e-10, 0.0), (-1.0, 1e-12),
                                        (0.0, 0.0)])
def test_dopri5_refuses_tolerances(pendulum, rtol, atol):
    fd = pendulum.library.address("forward_dynamics")
    with pytest.raises(InputError) as info:
        dopri5(pendulum, 0, fd, np.array([-1.0, 0.0]), np.array([0.0, 1.0]), np.zeros(1), rtol,
               atol, 1000)
    assert message(info) == f"tolerances must be positive (rtol {rtol}, atol {atol})"


def test_dopri5_failure_codes(pendulum):
    fd = pendulum.library.address("forward_dynamics")
    y0, t, tau = np.array([-1.0, 0.0]), np.array([0.0, 1.0]), np.zeros(1)
    fail = "point_pendulum: integration failed at t = "
    with pytest.raises(SimulationError) as info:  # 3
        dopri5(pendulum, 0, fd, y0, t, tau, 1e-10, 1e-12, 0)
    assert message(info) == fail + "0 s: too many steps (raise max_steps or loosen the tolerances)"
    with pytest.raises(SimulationError) as info:  # 2
        dopri5(pendulum, 0, fd, y0, t, tau, 1e-300, 1e-300, 1000)
    assert message(info) == (fail + "0 s: the step size fell below 1e-14 s: the problem is stiff "
                             "or singular here")
    for rc, text in ((1, "the right-hand side failed (singular mass or KKT matrix?)"),
                     (7, "7")):  # a code the table does not know: the number itself
        failing = FD_BATCH(lambda *args, rc=rc: rc)
        with pytest.raises(SimulationError) as info:
            dopri5(pendulum, 0, ctypes.cast(failing, ctypes.c_void_p).value, y0, t, tau, 1e-10,
                   1e-12, 1000)
        assert message(info) == fail + "0 s: " + text
    big = types.SimpleNamespace(name="big", n=33, n_constraints=0, p=np.zeros(1))  # 4
    with pytest.raises(SimulationError) as info:
        dopri5(big, 0, fd, np.zeros(66), t, np.zeros(33), 1e-10, 1e-12, 1000)
    assert message(info) == ("big: integration failed at t = 0 s: the robot is too large for "
                             "the built-in integrator (32 coordinates)")


def test_the_step_limit_through_simulate_names_where_it_stopped(pendulum):
    """max_steps = 1 from rest at the hanging pose: the first step lands on the first output
    (1 ms of 1001 over 1 s), and there the budget is spent."""
    with pytest.raises(SimulationError) as info:
        ps.simulate(pendulum, [-np.pi / 2], [0.0], (0.0, 1.0), max_steps=1)
    assert message(info) == ("point_pendulum: integration failed at t = 0.001 s: too many steps "
                             "(raise max_steps or loosen the tolerances)")
    one = ps.simulate(pendulum, [-np.pi / 2], [0.0], (0.0, 0.001), t_eval=[0.0, 0.001],
                      max_steps=1)
    assert one.n_rhs == 7


def test_the_actuated_joints_of_a_closed_chain_reach_the_c_integrator(five_run):
    """Five-bar (actuated A = 0 and E = 2) under [0.3, -0.2] N*m: the C run (torques placed by
    the ``act`` indices in C) against SciPy's DOP853 on the Python KKT system, and the energy
    gained equals the work of the torques, tau . (q_act(t) - q_act(0))."""
    five = ps.load("five_bar_type1")
    ref = ps.simulate(five, five.q_drawn, np.zeros(4), (0.0, 0.2), torque=[0.3, -0.2],
                      t_eval=five_run.t_s, method="DOP853", rtol=1e-12, atol=1e-13)
    err = float(np.max(np.abs(five_run.q - ref.q)))
    work = (five_run.q[:, [0, 2]] - five_run.q[0, [0, 2]]) @ np.array([0.3, -0.2])
    balance = float(np.max(np.abs(five_run.energy_j - five_run.energy_j[0] - work)))
    print(f"\nfive-bar: |q C - q SciPy| {err:.2g} rad, energy - work {balance:.2g} J")
    assert five_run.method == "dopri5" and err < 1e-9 and balance < 1e-9
    assert np.ptp(five_run.q[:, 0]) > 0.05 and np.ptp(five_run.q[:, 2]) > 0.05


def test_the_c_helper_loads_once(pendulum, monkeypatch):
    """From nothing loaded: helper() loads _integrate.c's library once, integrator() sets the
    ctypes signature once, and a run through them gives the exact pendulum."""
    monkeypatch.setattr(integrate, "_HELPER", None)
    monkeypatch.setattr(integrate, "_INTEGRATOR", None)
    lib = integrate.helper()
    assert isinstance(lib, ctypes.CDLL) and integrate.helper() is lib
    fn = integrate.integrator()
    assert fn is not None and integrate.integrator() is fn and fn is lib.planar_sym_dopri5
    assert fn.restype is ctypes.c_int and len(fn.argtypes) == 18
    assert fn.argtypes[4] is ctypes.c_void_p and fn.argtypes[14] is ctypes.c_longlong
    t = np.linspace(0.0, 1.0, 5)
    run = ps.simulate(pendulum, [-1.0], [0.5], (0.0, 1.0), t_eval=t, torque=[0.3])
    assert np.max(np.abs(np.column_stack([run.q, run.qd]) - exact_pendulum(-1.0, 0.5, t, 0.3))
                  ) < 1e-9


def test_check_torque_one_rule_for_every_route():
    """``check_torque``: what simulate does to a torque before choosing a route. Constants become
    a float (n,) array (one number or (1,) for every joint); a function of time and a Signal of
    the right width pass as they are; a wrong width is refused, a long vector summarised."""
    from planar_sym.dynamics.integrate import check_torque
    from planar_sym.motion.signals import from_table

    assert check_torque(None, 2) is None
    def f(t):
        return [t, t]

    assert check_torque(f, 2) is f
    table = from_table([0.0, 1.0], [[0.0, 1.0], [2.0, 3.0]], "linear")
    assert check_torque(table, 2) is table
    for given, n, want in (([1, 2], 2, [1.0, 2.0]), (3, 3, [3.0] * 3), ([2.5], 1, [2.5])):
        got = check_torque(given, n)
        assert isinstance(got, np.ndarray) and got.dtype == np.float64 and got.tolist() == want
    with pytest.raises(InputError) as info:  # the first joint's, or every joint's? not guessed
        check_torque([2.5], 3)
    assert str(info.value) == ("torque [2.5] is one value for 3 actuated joints: give a number "
                               "(2.5) for every joint, or 3 values")
    with pytest.raises(InputError) as info:
        check_torque(table, 3)
    assert str(info.value) == "the torque table has 2 columns for 3 actuated joints"
    rule = ("torque must be None, 3 numbers (N*m; N at a slider), one for every actuated joint, "
            "or a function of time")
    with pytest.raises(InputError) as info:
        check_torque([1.0, 2.0], 3)  # two numbers for three joints: not one for all
    assert str(info.value) == f"{rule} (got shape (2,): [1. 2.])"
    with pytest.raises(InputError) as info:
        check_torque(np.arange(12.0), 3)
    assert str(info.value) == f"{rule} (got shape (12,): [ 0.  1.  2. ...  9. 10. 11.])"
