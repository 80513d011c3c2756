"""The controlled engine's survivors of mutation testing (issue 30): ``engine_c`` (the C struct
the compiled loop reads), ``engine_inputs`` (the checks before it runs), ``sundials`` (the same
loop on CVODES and IDAS) and ``engine`` (``simulate_controlled``), each figure against something
computed another way:

* LQR about a fixed state (``Controller("lqr", gain, x_ref, u_ref)``, as ``LQR.controller``
  makes it) on the cart-pole (one actuated coordinate of two: K is 1 x 4) and on the 2-dof arm
  (K 2 x 4), with an input torque beside it: the applied torque at every output sample equals
  u_ref + K (x_ref - x) + the input, written out here with numpy, and the motion equals SciPy's
  DOP853 on M(q) qdd + h(q, qd) = S tau with that law written out too; on dopri5, CVODES and
  IDAS;
* a time-varying LQR (a schedule Signal: x_ref, u_ref and K of time, channels in that order;
  9 on the cart-pole, 14 on the arm): the same, the schedule and an input torque table
  evaluated by the Signal's own Python code; the held reference is the schedule's x_ref;
* the LQR laws' refusals word for word: a schedule or a gain of the wrong size, a reference
  given to an LQR law;
* SUNDIALS as the integrator reports it (``casadi.integrator`` recorded): n_rhs is the sum of
  the nfevals of every integrator a closed chain's segments make; IDAS starts from the
  accelerations of the forward dynamics at the start state (M^-1 (tau - h) by numpy).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import planar_sym as ps
from planar_sym.control import from_table, simulate_controlled
from planar_sym.dynamics.laws import Controller
from planar_sym.errors import InputError
from planar_sym.motion.signals import Signal


def law_by_hand(t, q, qd, gain, x_ref, u_ref, na):
    """u_ref + K (x_ref - x) at each sample; gain, x_ref, u_ref either constants or functions
    of t."""
    out = []
    for k, tt in enumerate(t):
        g = gain(tt) if callable(gain) else gain
        xr = x_ref(tt) if callable(x_ref) else x_ref
        ur = u_ref(tt) if callable(u_ref) else u_ref
        K = np.reshape(g, (na, -1))
        out.append(np.asarray(ur) + K @ (np.asarray(xr) - np.concatenate([q[k], qd[k]])))
    return np.array(out)


def motion_by_hand(robot, t, q0, qd0, tau_of):
    """q(t), qd(t) of M(q) qdd + h(q, qd) = S tau(t, q, qd) by SciPy's DOP853, the mass matrix
    and the bias from the robot's compiled functions, the solve by numpy."""
    n, act = robot.n, list(robot.actuated)

    def rhs(tt, x):
        q, qd = x[:n], x[n:]
        tau = np.zeros(n)
        tau[act] = tau_of(tt, q, qd)
        M = robot.mass_matrix(q[None])[0]
        h = robot.bias(q[None], qd[None])[0]
        return np.concatenate([qd, np.linalg.solve(M, tau - h)])

    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([q0, qd0]), method="DOP853",
                    rtol=1e-12, atol=1e-13, t_eval=t)
    return sol.y[:n].T, sol.y[n:].T


# -- LQR about a fixed state ---------------------------------------------------------------------

#: laws over (q, qd): not designed gains (any numbers do for the law's arithmetic), mild enough
#: for a short run. The cart-pole has one actuated coordinate of two (K is 1 x 4), the arm two
#: of two (K is 2 x 4, row-major: its rows tell a transposed layout apart)
LAWS = {
    "cart_pole": {"gain": (1.5, -4.0, 0.8, -0.6), "x_ref": (0.1, 0.05, 0.0, 0.2), "u_ref": (0.3,),
                      "q0": (0.0, 0.1), "qd0": (0.05, 0.0), "input": (-0.1,)},
    "serial_2dof": {"gain": (0.8, 0.1, 0.05, 0.01, -0.2, 0.5, 0.02, 0.03),
                        "x_ref": (-1.0, 0.6, 0.1, -0.2), "u_ref": (0.2, 0.05),
                        "q0": (-1.1, 0.4), "qd0": (0.0, 0.3), "input": (0.02, -0.03)},
}
T_LQR = np.linspace(0.0, 0.5, 11)


@pytest.mark.parametrize("method", ["dopri5", "cvodes", "idas"])
@pytest.mark.parametrize("name", ["cart_pole", "serial_2dof"])
def test_lqr_about_a_fixed_state_applies_u_ref_plus_k_times_the_error(name, method):
    """Catches a gain, x_ref or u_ref that does not reach the compiled loop (a null or a
    zero array in engine_c._Setup, the CasADi law of sundials written another way): the
    torque at every sample is u_ref + K (x_ref - x), and the motion is the ODE with that law."""
    robot, law = ps.load(name), LAWS[name]
    gain, x_ref, u_ref = law["gain"], law["x_ref"], law["u_ref"]
    na, n = len(u_ref), robot.n
    ctl = Controller("lqr", saturate=False, gain=gain, x_ref=x_ref, u_ref=u_ref)
    q0, qd0 = np.array(law["q0"]), np.array(law["qd0"])
    extra = np.array(law["input"])  # an input torque, added to the law's
    run = simulate_controlled(robot, ctl, (0.0, 0.5), q0=q0, qd0=qd0, t_eval=T_LQR,
                              method=method, torque=extra)
    u_in = np.array(u_ref) + extra
    want = law_by_hand(run.t_s, run.q, run.qd, gain, x_ref, u_in, na)
    assert np.max(np.abs(run.tau - want)) < 1e-12
    assert np.max(np.abs(run.tau_cmd - want)) < 1e-12
    q, qd = motion_by_hand(robot, T_LQR, q0, qd0,
                           lambda tt, q, qd: law_by_hand([tt], [q], [qd], gain, x_ref, u_in,
                                                         na)[0])
    assert np.max(np.abs(run.q - q)) < 1e-7
    assert np.max(np.abs(run.qd - qd)) < 1e-7
    # the law holds its own state: the reference columns are x_ref's actuated ones
    act = list(robot.actuated)
    assert np.all(run.q_ref == np.array(x_ref)[act])
    assert np.all(run.qd_ref == np.array(x_ref)[[n + i for i in act]])
    assert np.max(np.abs(run.q[-1] - q0)) > 1e-3  # it moved


# -- LQR along a schedule (x_ref, u_ref and K of time) --------------------------------------------

def schedule_of(name):
    """x_ref (2n), u_ref (actuated), K (actuated x 2n) over 0..1 s, linear between the law
    above and a second row: 9 channels on the cart-pole, 14 on the arm."""
    law = LAWS[name]
    start = np.concatenate([law["x_ref"], law["u_ref"], law["gain"]])
    end = start * np.linspace(0.7, 1.3, len(start)) + 0.05
    return from_table([0.0, 1.0], [start, end], "linear")


@pytest.mark.parametrize("method", ["dopri5", "cvodes", "idas"])
@pytest.mark.parametrize("name", ["cart_pole", "serial_2dof"])
def test_lqr_along_a_schedule_reads_its_channels_at_each_time(name, method):
    """Catches a schedule that does not reach the compiled loop (engine_c._Setup's c.sched,
    its scratch values) or whose channels are read in another order (sundials'
    closed_loop_rhs), or a channel count refused though right (engine_inputs): the torque at
    every sample is u_ref(t) + K(t) (x_ref(t) - x) plus an input torque table's, the Signals
    evaluated by their own Python code, and the motion is the ODE with that law."""
    robot, law = ps.load(name), LAWS[name]
    n, na = robot.n, len(law["u_ref"])
    sched = schedule_of(name)
    ctl = Controller("lqr", saturate=False, schedule=sched)
    q0, qd0 = np.array(law["q0"]), np.array(law["qd0"])

    extra = from_table([0.0, 0.5], [np.zeros(na), 2 * np.array(law["input"])])

    def parts(tt):  # the input table's torque rides on u_ref
        v = sched(tt)[0]
        return v[2 * n + na:], v[:2 * n], v[2 * n:2 * n + na] + extra(tt)[0]

    run = simulate_controlled(robot, ctl, (0.0, 0.5), q0=q0, qd0=qd0, t_eval=T_LQR,
                              method=method, torque=extra)
    want = law_by_hand(run.t_s, run.q, run.qd, lambda tt: parts(tt)[0],
                       lambda tt: parts(tt)[1], lambda tt: parts(tt)[2], na)
    assert np.max(np.abs(run.tau - want)) < 1e-12
    q, qd = motion_by_hand(robot, T_LQR, q0, qd0,
                           lambda tt, q, qd: law_by_hand([tt], [q], [qd], *parts(tt), na)[0])
    assert np.max(np.abs(run.q - q)) < 1e-7
    assert np.max(np.abs(run.qd - qd)) < 1e-7
    # the held state is the schedule's x_ref at each time (actuated coordinates and rates)
    act = list(robot.actuated)
    xr = sched(run.t_s)[:, :2 * n]
    assert np.max(np.abs(run.q_ref - xr[:, act])) < 1e-15
    assert np.max(np.abs(run.qd_ref - xr[:, [n + i for i in act]])) < 1e-15


# -- the LQR laws' refusals, word for word -------------------------------------------------------

def test_lqr_laws_for_another_robot_or_with_a_reference_are_refused_word_for_word():
    """Catches a refusal dropped or reworded in engine_inputs (check_controller's channel and
    gain counts, _reference's "lqr" branch): a schedule one channel short of 2n + na + 2n na
    (14 on the arm), a constant gain one number short of 2n na (8), and an LQR law given a
    reference motion; the right counts run (the tests above)."""
    arm, law = ps.load("serial_2dof"), LAWS["serial_2dof"]
    short = from_table([0.0, 1.0], np.zeros((2, 13)))
    with pytest.raises(InputError) as err:
        simulate_controlled(arm, Controller("lqr", schedule=short), (0.0, 0.5), q0=law["q0"])
    assert str(err.value) == ("serial_2dof: this time-varying LQR law was designed for another "
                              "robot (make it with planar_sym.tvlqr on this one)")
    with pytest.raises(InputError) as err:
        simulate_controlled(arm, Controller("lqr", gain=law["gain"][:-1], x_ref=law["x_ref"],
                                            u_ref=law["u_ref"]), (0.0, 0.5), q0=law["q0"])
    assert str(err.value) == ("serial_2dof: this LQR law was designed for another robot (make "
                              "it with planar_sym.lqr on this one)")
    hold = Signal(np.array([0.0, 1.0]), np.zeros((1, 2, 1)))
    for ctl in (Controller("lqr", gain=law["gain"], x_ref=law["x_ref"], u_ref=law["u_ref"]),
                Controller("lqr", schedule=schedule_of("serial_2dof"))):
        with pytest.raises(InputError) as err:
            simulate_controlled(arm, ctl, (0.0, 0.5), q0=law["q0"], reference=hold)
        assert str(err.value) == ("controller \"lqr\" holds the state it was designed about "
                                  "and takes no reference motion")


# -- SUNDIALS: what the integrator is given and what it reports -----------------------------------

class _Spy:
    """casadi.integrator recorded: every integrator the run makes, and the arguments of its
    calls (x0, z0)."""

    def __init__(self, real):
        self.real, self.made = real, []

    def __call__(self, *args, **kwargs):
        spy = _Called(self.real(*args, **kwargs))
        self.made.append(spy)
        return spy


class _Called:
    def __init__(self, f):
        self.f, self.calls = f, []

    def __call__(self, **kwargs):
        self.calls.append({k: np.array(v, dtype=float).ravel() for k, v in kwargs.items()})
        return self.f(**kwargs)

    def stats(self):
        return self.f.stats()


@pytest.fixture
def spy(monkeypatch):
    import casadi

    s = _Spy(casadi.integrator)
    monkeypatch.setattr(casadi, "integrator", s)
    return s


@pytest.mark.parametrize("method", ["cvodes", "idas"])
def test_the_rhs_count_of_sundials_is_what_the_integrators_report(spy, method):
    """Catches a count that starts at 1, keeps only the last segment's evaluations or counts
    a segment that reports none (sundials.integrate's count): the five-bar over 0.35 s runs
    in four calls of at most 0.1 s, and n_rhs is the sum of the nfevals each integrator's own
    statistics give."""
    five = ps.load("five_bar_type1")
    run = simulate_controlled(five, Controller("none"), (0.0, 0.35), q0=five.q_drawn,
                              torque=[0.01, -0.005], t_eval=np.linspace(0.0, 0.35, 8),
                              method=method)
    reported = [int(f.stats()["nfevals"]) for f in spy.made]
    assert len(reported) == 4 and min(reported) > 0
    assert run.n_rhs == sum(reported)


def test_idas_starts_from_the_accelerations_of_the_forward_dynamics(spy):
    """Catches a wrong start for IDAS's algebraic unknowns (sundials.integrate's z0: its sign,
    or the linearisation taken at the segment's end instead of its start): under a torque
    ramp, the z0 the integrator is given is qdd = M^-1 (tau(t0) - h) at the start state,
    the robot's compiled mass matrix and bias solved by numpy, at t0 = 0.2 s."""
    arm = ps.load("serial_2dof")
    q0, qd0 = np.array([-1.0, 0.5]), np.array([0.3, -0.2])
    ramp = from_table([0.0, 1.0], [[0.0, 0.0], [2.0, -1.0]])  # tau = (2 t, -t) N*m
    simulate_controlled(arm, Controller("none"), (0.2, 0.4), q0=q0, qd0=qd0, torque=ramp,
                        t_eval=np.linspace(0.2, 0.4, 5), method="idas")
    (f,) = spy.made
    z0 = f.calls[0]["z0"]
    M, h = arm.mass_matrix(q0[None])[0], arm.bias(q0[None], qd0[None])[0]
    want = np.linalg.solve(M, np.array([0.4, -0.2]) - h)
    assert np.max(np.abs(z0 - want)) < 1e-9 * np.max(np.abs(want))


# -- the compiled loop watched -------------------------------------------------------------------

@pytest.mark.parametrize("name, ends", [("serial_2dof", [0.35]),
                                        ("five_bar_type1", [0.15, 0.25, 0.35])])
def test_progress_hears_the_time_reached_and_the_end_of_the_run(name, ends):
    """Catches the watcher given no clock, no callback or another end time (engine._dopri5's
    call_watched: t_fail, ambient(), t[-1]): a tree runs in one call and reports its end once;
    the five-bar runs in 0.1 s segments from 0.05 s, each reporting the time it reached; the
    end is always the run's, 0.35 s (not the first output time, 0.1 s)."""
    robot = ps.load(name)
    q0 = robot.q_drawn if name == "five_bar_type1" else [-1.0, 0.5]
    heard = []
    simulate_controlled(robot, Controller("none"), (0.05, 0.35), q0=q0, torque=[0.001, 0.0],
                        t_eval=np.linspace(0.05, 0.35, 7),
                        progress=lambda done, total: heard.append((done, total)))
    assert [d for d, _ in heard] == pytest.approx(ends, abs=1e-12)
    assert [t for _, t in heard] == [0.35] * len(ends)


@pytest.mark.parametrize("method", ["dopri5", "cvodes"])
def test_a_watched_run_is_the_direct_run_argument_for_argument(method):
    """Catches an argument dropped or emptied where simulate_controlled calls itself again
    inside ``watching(progress)``: the same call with and without a progress callback gives
    the same run, bit for bit, where every argument differs from its default and changes the
    run (tests/robots/actuated_2dof.toml: joint 1 limited to 0.8 N*m; a plant 20 % heavier
    at link 2; PD with an input torque along a reference whose rate jumps at 0.3 s, from a
    start state of its own; joint 2's upper limit crossed at 0.067 s and passed
    ("continue"); the torque limit reached at 0.303 s stops the run; tolerances looser
    than the defaults; and a step limit that fails the run the same way)."""
    from conftest import TEST_ROBOTS

    from planar_sym.control import controller
    from planar_sym.errors import SimulationError

    robot = ps.load(TEST_ROBOTS / "actuated_2dof.toml")
    args = {"reference": from_table([0.0, 0.3, 1.0], [[0.1, -0.2], [0.97, 0.04], [6.0, 0.6]]),
                "plant": robot.with_parameters(m_link2=0.09), "q0": [0.1, -0.2], "qd0": [2.9, 0.8],
                "torque": [0.01, 0.0], "t_eval": np.linspace(0.0, 0.6, 13),
                "joint_limits": {"joint2": (-1.0, -0.15)}, "on_joint_limit": "continue",
                "on_actuator_limit": "stop", "method": method, "rtol": 1e-8, "atol": 1e-10}
    law = controller("pd", [8.0, 1.0], [0.1, 0.05])
    heard = []
    runs = [simulate_controlled(robot, law, (0.0, 0.6), **args),
            simulate_controlled(robot, law, (0.0, 0.6), **args,
                                progress=lambda done, total: heard.append(done))]
    assert (len(heard) > 0) == (method == "dopri5")  # SUNDIALS runs unwatched
    for name in ("t_s", "q", "qd", "tau", "tau_cmd", "work_j", "friction_j"):
        assert np.array_equal(getattr(runs[0], name), getattr(runs[1], name)), name
    assert runs[0].n_rhs == runs[1].n_rhs
    assert runs[0].events == runs[1].events
    assert [(e.name, e.stopped) for e in runs[1].events] == [
        ("joint joint2 reached its upper limit -0.15 rad (-8.59437 deg)", False),
        ("actuator joint1 commanded beyond its torque limit 0.8 N*m", True)]
    # located within a step on dopri5 (0.30300 s); on SUNDIALS by a chord of the 50 ms grid
    assert runs[1].events[1].time_s == pytest.approx(0.303, abs=1e-3 if method == "dopri5"
                                                     else 1e-2)
    for progress in (None, lambda done, total: None):
        with pytest.raises(SimulationError, match="too many steps"):
            simulate_controlled(robot, law, (0.0, 0.6), **{**args, "method": "dopri5"},
                                max_steps=20, progress=progress)


@pytest.mark.parametrize("method", ["dopri5", "cvodes"])
def test_the_reference_columns_are_the_reference_and_its_rate(method):
    """Catches the reference's rate taken at other times or of another order (the compiled
    controller's reference, ``control_values``), and a start state not the reference's (simulate_controlled's default q0, qd0
    for a Signal over every coordinate): PD along a straight-line reference
    q_r(t) = a + (b - a) t on the 2-dof arm, run from 0.2 s: q_ref is that line and qd_ref its
    slope b - a at every output sample, and the run starts on the line at 0.2 s with its
    slope (or with the rate given)."""
    from planar_sym.control import controller

    arm = ps.load("serial_2dof")
    a, b = np.array([-1.0, 0.5]), np.array([-0.5, 0.2])
    t = np.linspace(0.2, 0.5, 7)
    ref = from_table([0.0, 1.0], [a, b])
    run = simulate_controlled(arm, controller("pd", 0.5, 0.05), (0.2, 0.5), reference=ref,
                              t_eval=t, method=method)
    assert np.max(np.abs(run.q_ref - (a + np.outer(t, b - a)))) < 1e-15
    assert np.max(np.abs(run.qd_ref - (b - a))) < 1e-15
    assert np.max(np.abs(run.q[0] - (a + 0.2 * (b - a)))) < 1e-15
    assert np.max(np.abs(run.qd[0] - (b - a))) < 1e-15
    run = simulate_controlled(arm, controller("pd", 0.5, 0.05), (0.2, 0.5), reference=ref,
                              t_eval=t, method=method, qd0=[0.1, 0.2])
    assert run.qd[0].tolist() == [0.1, 0.2]


def _line(t0, t1, a, v, n=21):
    """A JointTrajectory of q = a + v (t - t0) from t0 to t1 s: constant rate v, no
    acceleration."""
    from planar_sym.motion.profiles import JointTrajectory

    t = np.linspace(t0, t1, n)
    return JointTrajectory(t, a + np.outer(t - t0, v), np.tile(v, (n, 1)), np.zeros((n, len(a))))


def test_a_joint_trajectory_gives_the_start_state_only_where_it_starts():
    """Catches the start state taken from a JointTrajectory wrongly (simulate_controlled's
    defaults of q0 and qd0): starting where the trajectory starts, the run starts at its first
    sample and rate; a rate given beside it is kept; a run starting later (0.2 s) than the
    trajectory (0 s) has no start from it and asks for q0, word for word."""
    from planar_sym.control import controller

    arm = ps.load("serial_2dof")
    a, v = np.array([-1.0, 0.5]), np.array([0.4, -0.3])
    ref, law = _line(0.0, 1.0, a, v), controller("pd", 0.5, 0.05)
    t = np.linspace(0.0, 0.2, 5)
    run = simulate_controlled(arm, law, (0.0, 0.2), reference=ref, t_eval=t)
    assert run.q[0].tolist() == a.tolist() and run.qd[0].tolist() == v.tolist()
    run = simulate_controlled(arm, law, (0.0, 0.2), reference=ref, t_eval=t, qd0=[0.1, 0.2])
    assert run.q[0].tolist() == a.tolist() and run.qd[0].tolist() == [0.1, 0.2]
    with pytest.raises(InputError) as err:
        simulate_controlled(arm, law, (0.2, 0.4), reference=ref)
    assert str(err.value) == ("give q0 (every coordinate): the reference does not say where "
                              "the passive joints start")


def test_a_start_exactly_on_a_stopping_limit_is_refused_word_for_word():
    """Catches an event value of exactly 0 at the start taken as not fired (simulate_controlled:
    g0 > 0 is inside), and the refusal's wording: joint 2 of the arm starting exactly at its
    upper limit 0.3 rad, the limit stopping the run; passed instead, it is logged at t = 0 with
    stopped False (not None)."""
    arm = ps.load("serial_2dof")
    with pytest.raises(InputError) as err:
        simulate_controlled(arm, Controller("none"), (0.0, 0.1), q0=[0.0, 0.3],
                            joint_limits={"joint2": (-1.0, 0.3)})
    assert str(err.value) == ("an event fires at t = 0 s, before the run starts: joint joint2 "
                              "reached its upper limit 0.3 rad (17.1887 deg) (give a start "
                              "inside the limits, or a reference that starts there)")
    # passed ("continue"): logged at the start as an Event that did not stop the run, a bool
    from planar_sym.dynamics.events import Event

    run = simulate_controlled(arm, Controller("none"), (0.0, 0.1), q0=[0.0, 0.3],
                              joint_limits={"joint2": (-1.0, 0.3)}, on_joint_limit="continue")
    assert run.events[0] == Event("joint joint2 reached its upper limit 0.3 rad (17.1887 deg)",
                                  0.0, False)


def test_a_closed_chain_started_off_its_loops_is_refused_not_projected():
    """Catches the start of a closed chain projected onto the loops instead of checked
    (simulate_controlled's start_state(..., False)): the five-bar's drawn pose with its
    passive joint B turned 0.05 rad opens the loop (|Phi| > 1 mm, computed here), and the
    run is refused, naming q0 and what to do on this route. Asked (project=True, as
    ``simulate`` has it), B is solved back from the actuated joints: the drawn pose again, and
    the run says it moved B by 0.05 rad."""
    five = ps.load("five_bar_type1")
    q0 = five.q_drawn + np.array([0.0, 0.05, 0.0, 0.0])
    assert np.max(np.abs(five.constraint(q0))) > 1e-3
    with pytest.raises(InputError) as err:
        simulate_controlled(five, Controller("none"), (0.0, 0.1), q0=q0)
    assert str(err.value).startswith("five_bar_type1: q0 is off the loop constraints: ")
    assert str(err.value).endswith("give a state on the loops (planar_sym.from_actuated), pass "
                                   "project=True to solve the passive joints from the actuated "
                                   "ones, or leave q0 out to start on the reference (off it: "
                                   "track's start_error, on the actuated joints, keeps the "
                                   "loops closed)")
    run = simulate_controlled(five, Controller("none"), (0.0, 0.1), q0=q0, project=True,
                              t_eval=[0.0, 0.1])
    assert np.max(np.abs(run.q[0] - five.q_drawn)) < 1e-9
    assert run.initial_correction_rad == pytest.approx(0.05, abs=1e-9)
    assert np.max(np.abs(five.constraint(run.q[-1]))) < 1e-9


def test_an_lqr_law_with_a_reference_of_the_wrong_size_is_refused():
    """A hand-made LQR law whose x_ref or u_ref is shorter than the robot's 2n states and
    actuated joints: the C loop would read past their end, so it is refused before the run
    (found by the mutation runs of issue 30)."""
    arm = ps.load("serial_2dof")
    gain = tuple(np.zeros(8))
    for x_ref, u_ref in (((), (0.0, 0.0)), ((0.0,) * 4, ()), ((0.0,) * 3, (0.0, 0.0))):
        with pytest.raises(InputError, match="this LQR law was designed for another robot"):
            simulate_controlled(arm, Controller("lqr", gain=gain, x_ref=x_ref, u_ref=u_ref),
                                (0.0, 0.1),
                                q0=np.zeros(2), qd0=np.zeros(2))
