"""The simulation engine by value (``planar_sym.dynamics.engine``: ``simulate_controlled`` and its
compiled dopri5 loop; ``planar_sym.dynamics.sundials``: the same loop on CVODES and IDAS), each
figure against something computed another way:

* a pendulum (tests/robots/pendulum.toml, I = izz + m l^2 = 0.11375 kg*m^2, gravity torque
  m g l cos q) given a 2 N*m torque limit, driven open loop by a ramp tau = 5 t N*m: on every
  route q(t) equals SciPy's DOP853 on I q'' = sat(5 t) - m g l cos q written here; the limit is
  reached at t = 0.4 s exactly (the event's time: bisection on dopri5, the output grid's linear
  interpolation on SUNDIALS, exact for a ramp); the applied torque is min(5 t, 2), or 5 t
  when the controller does not saturate; the energy equals the work of the torques; a plant
  with viscous and Coulomb friction (the model without) loses int D q' dt, integrated here too;
* joint limits of the 2-dof arm held by a PD law: the upper limit of joint 2 stops the run where
  q2 = 0.3 rad; a limit already passed at the start is logged at t = 0 and fires again only
  where a run without limits crosses it upward (interpolated on a fine grid);
* the refusals of ``simulate_controlled`` and ``check_controller`` word for word;
* failures of the compiled loop: too many steps and a step size underflow (a finite torque of
  1e30 N*m) name the robot, the time and the reason; on a closed chain the underflow is the
  loops' event at its time; the RHS count is DOPRI5's with FSAL (1 + 6 k per call, one call
  per 0.1 s segment of a closed chain); SUNDIALS failing at its first evaluation (1e308 N*m)
  names the robot, the method, the span of the call and CasADi's last line;
* ``assembly_changes`` on poses given directly: the first sign change of det Phi_p between
  samples, its two times, and none through or from a pose exactly singular (det Phi_p = 0);
* ``control_values`` naming the sample where the controller's model is singular;
* PD and computed torque with a model error, an input torque and a plant whose library was
  loaded apart: CVODES and IDAS against the compiled dopri5 (measured 1.7e-10 rad).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import TEST_ROBOTS
from scipy.integrate import solve_ivp

import planar_sym as ps
from planar_sym.control import controller, from_table, simulate_controlled
from planar_sym.dynamics.events import Event
from planar_sym.errors import InputError, SimulationError
from planar_sym.motion.signals import Signal

# tests/robots/pendulum.toml: a rod of 1.5 kg, izz 0.02 kg*m^2 about its centre of gravity at
# 0.25 m from the pivot; q from +x, gravity along -y
M, L_CG, IZZ, G = 1.5, 0.25, 0.02, 9.81
I_PIVOT = IZZ + M * L_CG ** 2
LIMIT = 2.0  # N*m, the torque limit added to the pivot below
RAMP = 5.0  # N*m/s: the limit is reached at t = 0.4 s


@pytest.fixture(scope="module")
def pendulum(derived, tmp_path_factory):
    """The test pendulum with ``torque_limit = 2`` N*m at its pivot: one event spec."""
    text = (TEST_ROBOTS / "pendulum.toml").read_text()
    text = text.replace('name = "pendulum"', 'name = "pendulum_limited"')
    # no friction in the description, but its parameters: a plant may have some
    text = text.replace("actuated = true", "actuated = true\n[joints.actuator]\n"
                        f"torque_limit = {LIMIT}\nviscous_friction = 0.0\n"
                        "coulomb_friction = 0.0")
    path = tmp_path_factory.mktemp("engine") / "pendulum_limited.toml"
    path.write_text(text)
    return derived(path)[1]


@pytest.fixture(scope="module")
def arm():
    return ps.load("serial_2dof")


@pytest.fixture(scope="module")
def five():
    return ps.load("five_bar_type1")  # A, B, E, D; actuated A and E (coordinates 0 and 2)


def ramp():
    """tau = 5 t N*m over 0..1 s (a linear table is exact for a line)."""
    return from_table([0.0, 1.0], [[0.0], [RAMP]], "linear")


def pendulum_by_hand(t, q0, saturate: bool, b=0.0, c=0.0, vs=0.01):
    """q(t) of I q'' = tau - m g l cos q - D(q'), D = b q' + c tanh(q' / vs), and the friction
    loss int D q' dt, by SciPy's DOP853."""
    def rhs(tt, x):
        tau = RAMP * tt
        if saturate:
            tau = min(tau, LIMIT)
        d = b * x[1] + c * np.tanh(x[1] / vs)
        return [x[1], (tau - M * G * L_CG * np.cos(x[0]) - d) / I_PIVOT, d * x[1]]

    # the kink of the saturated torque at 0.4 s: integrate across it in two pieces
    pieces = [(t[0], 0.4), (0.4, t[-1])]
    x, out = [q0, 0.0, 0.0], {}
    for a, b_ in pieces:
        sol = solve_ivp(rhs, (a, b_), x, method="DOP853", rtol=1e-12, atol=1e-13,
                        dense_output=True)
        x = sol.y[:, -1]
        for k, tt in enumerate(t):
            if a <= tt <= b_:
                out[k] = sol.sol(tt)
    rows = np.array([out[k] for k in range(len(t))])
    return (rows[:, 0], rows[:, 2]) if b or c else rows[:, 0]


# -- the pendulum at its torque limit ----------------------------------------------------------

T_RAMP = np.linspace(0.0, 1.0, 8)  # 0.4 s falls between 2/7 and 3/7


@pytest.mark.parametrize("method", ["dopri5", "cvodes", "idas"])
def test_a_ramp_into_the_torque_limit_against_the_pendulum_by_hand(pendulum, method):
    run = simulate_controlled(pendulum, controller("none", width=1), (0.0, 1.0), torque=ramp(),
                              q0=[-np.pi / 2], qd0=[0.0], t_eval=T_RAMP, method=method,
                              on_actuator_limit="continue")
    want = pendulum_by_hand(T_RAMP, -np.pi / 2, saturate=True)
    assert np.max(np.abs(run.q[:, 0] - want)) < 1e-7  # measured 2.4e-9 rad at most
    # commanded 5 t, applied clipped at the limit: the C loop and CasADi clip alike
    assert np.max(np.abs(run.tau_cmd[:, 0] - RAMP * T_RAMP)) < 1e-14
    assert np.max(np.abs(run.tau[:, 0] - np.minimum(RAMP * T_RAMP, LIMIT))) < 1e-14
    assert run.balance_residual < 1e-7
    # the one event: 2 - |5 t| crosses zero at 0.4 s (located, or interpolated on a line)
    assert [e.name for e in run.events] == [("actuator pivot commanded beyond its torque "
                                             "limit 2 N*m")]
    assert run.events[0].time_s == pytest.approx(0.4, abs=1e-12)
    assert not run.events[0].stopped


@pytest.mark.parametrize("method", ["dopri5", "cvodes"])
def test_a_controller_that_does_not_saturate_applies_what_it_commands(pendulum, method):
    run = simulate_controlled(pendulum, controller("none", width=1, saturate=False), (0.0, 1.0),
                              torque=ramp(), q0=[-np.pi / 2], qd0=[0.0], t_eval=T_RAMP,
                              method=method, on_actuator_limit="continue")
    assert np.max(np.abs(run.tau[:, 0] - RAMP * T_RAMP)) < 1e-14  # up to 5 N*m
    want = pendulum_by_hand(T_RAMP, -np.pi / 2, saturate=False)
    assert np.max(np.abs(run.q[:, 0] - want)) < 1e-7


@pytest.mark.parametrize("method", ["dopri5", "cvodes", "idas"])
def test_a_plant_with_friction_loses_what_the_pendulum_by_hand_loses(pendulum, method):
    """The model has no friction, the plant 0.05 N*m*s/rad viscous and 0.1 N*m Coulomb
    (smoothed over 0.01 rad/s): the motion and the loss int D q' dt against the ODE above."""
    plant = pendulum.with_parameters(fv_pivot=0.05, fc_pivot=0.1)
    run = simulate_controlled(pendulum, controller("none", width=1), (0.0, 1.0), torque=ramp(),
                              plant=plant, q0=[-np.pi / 2], qd0=[0.0], t_eval=T_RAMP,
                              method=method, on_actuator_limit="continue")
    q, loss = pendulum_by_hand(T_RAMP, -np.pi / 2, saturate=True, b=0.05, c=0.1)
    # measured 6.2e-10 rad, 5.7e-10 J (cvodes) at most; the loss is 0.198 J by 1 s
    assert np.max(np.abs(run.q[:, 0] - q)) < 1e-7
    assert np.max(np.abs(run.friction_j - loss)) < 1e-8
    assert run.balance_residual < 1e-8


def test_the_torque_limit_stops_the_run_at_its_time(pendulum):
    run = simulate_controlled(pendulum, controller("none", width=1), (0.0, 1.0), torque=ramp(),
                              q0=[-np.pi / 2], qd0=[0.0], t_eval=T_RAMP,
                              on_actuator_limit="stop")
    assert run.stopped is not None and run.stopped.time_s == pytest.approx(0.4, abs=1e-12)
    assert run.t_s[-1] == pytest.approx(0.4, abs=1e-12)
    assert run.t_s[:-1].tolist() == T_RAMP[:3].tolist()
    want = pendulum_by_hand(np.array([0.0, 0.4]), -np.pi / 2, saturate=True)
    assert run.q[-1, 0] == pytest.approx(want[-1], abs=1e-9)


# -- joint limits on the compiled loop -----------------------------------------------------------

HOLD = Signal(np.array([0.0, 3.0]), np.array([[[0.0], [0.0]]]))  # hold q = 0 for 3 s
#: PD about q = 0, lightly damped (zeta about 0.05): released 0.5 rad off, joint 2 swings through
LIGHT = controller("pd", 0.5, 0.001, width=2)


def upward_crossings(arm, q0, level, t_end):
    """Where a run without limits, sampled every 0.5 ms, has q2 cross ``level`` upward: the
    roots of the cubic Hermite interpolant of (q2, qd2) between the samples."""
    from scipy.interpolate import CubicHermiteSpline

    t = np.linspace(0.0, t_end, round(t_end / 5e-4) + 1)
    run = simulate_controlled(arm, LIGHT, (0.0, t_end), reference=HOLD, q0=q0, qd0=[0.0, 0.0],
                              t_eval=t)
    spline = CubicHermiteSpline(t, run.q[:, 1] - level, run.qd[:, 1])
    roots = spline.roots(extrapolate=False)
    return roots[spline(roots, 1) > 0]


def test_the_upper_limit_of_the_second_joint_stops_the_run_there(arm):
    """The upper limit is the second event of the pair: its index (joint 2) and its "stop"
    reach the compiled loop."""
    first = upward_crossings(arm, [0.0, -0.5], 0.3, 3.0)[0]
    run = simulate_controlled(arm, LIGHT, (0.0, 3.0), reference=HOLD, q0=[0.0, -0.5],
                              qd0=[0.0, 0.0], joint_limits={"joint2": (-1.0, 0.3)},
                              t_eval=np.linspace(0.0, 3.0, 31))
    assert run.stopped.name == "joint joint2 reached its upper limit 0.3 rad (17.1887 deg)"
    assert run.stopped.time_s == pytest.approx(first, abs=1e-6)  # the 0.5 ms grid's chord
    assert run.t_s[-1] == run.stopped.time_s
    assert run.q[-1, 1] == pytest.approx(0.3, abs=1e-9)
    assert [e.name for e in run.events] == [run.stopped.name]


@pytest.mark.parametrize("method", ["dopri5", "cvodes"])
def test_a_limit_passed_at_the_start_fires_again_only_on_its_next_crossing(arm, method):
    """Joint 2 starts 0.2 rad above its upper limit (the second of the two events): logged at
    t = 0, then again where it next crosses the limit upward, and nowhere in between."""
    crossings = upward_crossings(arm, [0.0, 0.5], 0.3, 1.0)
    assert len(crossings) == 1  # at 0.1074 s
    run = simulate_controlled(arm, LIGHT, (0.0, 1.0), reference=HOLD, q0=[0.0, 0.5],
                              qd0=[0.0, 0.0], joint_limits={"joint2": (-1.0, 0.3)},
                              on_joint_limit="continue", t_eval=np.linspace(0.0, 1.0, 201),
                              method=method)
    assert run.events[0].time_s == 0.0
    assert [e.name for e in run.events] == [
        "joint joint2 reached its upper limit 0.3 rad (17.1887 deg)"] * 2
    # dopri5 locates the crossing (measured 1e-12 off); SUNDIALS interpolates a chord on its
    # 5 ms output grid (measured 2.8e-4 s off)
    assert run.events[1].time_s == pytest.approx(crossings[0],
                                                 abs=1e-6 if method == "dopri5" else 1e-3)
    assert not any(e.stopped for e in run.events)


# -- refusals, word for word ---------------------------------------------------------------------

NONE2 = controller("none", width=2)
ZERO_REF = Signal(np.array([0.0, 1.0]), np.zeros((1, 2, 1)))


@pytest.mark.parametrize("call, message", [
    (lambda arm, five: simulate_controlled("serial_2dof", NONE2, (0, 1)),
     "simulate_controlled needs a Robot (planar_sym.load), got str"),
    (lambda arm, five: simulate_controlled(arm, "pd", (0, 1)),
     "controller: make one with planar_sym.control.controller(kind, kp, kd)"),
    (lambda arm, five: simulate_controlled(arm, NONE2, (0, 1), plant=five, q0=[0, 0]),
     ("the plant must be the same robot as the controller's model (serial_2dof), perhaps "
      "with other parameters (with_parameters)")),
    (lambda arm, five: simulate_controlled(arm, NONE2, (0, 1), plant="serial_2dof", q0=[0, 0]),
     ("the plant must be the same robot as the controller's model (serial_2dof), perhaps "
      "with other parameters (with_parameters)")),
    (lambda arm, five: simulate_controlled(arm, NONE2, (0, 1), q0=[0, 0], method="rk4"),
     "unknown method 'rk4'; known: dopri5, cvodes, idas"),
    (lambda arm, five: simulate_controlled(arm, controller("pd", [1.0, 2, 3], [0.1, 0.1, 0.1]),
                                           (0, 1), q0=[0, 0]),
     "serial_2dof: 3 gains for 2 actuated joints"),
    (lambda arm, five: simulate_controlled(arm, controller("pd", 1.0, 0.1), (0, 1), q0=[0, 0]),
     "controller 'pd' needs a reference motion to track"),
    (lambda arm, five: simulate_controlled(
        arm, controller("pd", 1.0, 0.1), (0, 1), q0=[0, 0],
        reference=Signal(np.array([0.0, 1.0]), np.zeros((1, 3, 1)))),
     "the reference has 3 channels; serial_2dof has 2 actuated joints"),
    (lambda arm, five: simulate_controlled(arm, controller("pd", 1.0, 0.1), (0, 1), q0=[0, 0],
                                           reference=np.zeros((2, 2))),
     ("reference: a JointTrajectory (every coordinate) or a Signal over the actuated joints "
      "(got ndarray)")),
    (lambda arm, five: simulate_controlled(arm, NONE2, (0, 1), q0=[0, 0],
                                           torque=from_table([0, 1], [[0, 0, 0], [1, 1, 1]])),
     "the torque table has 3 columns for 2 actuated joints"),
    (lambda arm, five: simulate_controlled(arm, NONE2, (0, 1), q0=[0, 0], torque=[1, 2, 3]),
     "torque must have shape (N, 2) or (2,), got (3,)"),
    (lambda arm, five: simulate_controlled(arm, NONE2, (0, 1), q0=[0, 0],
                                           torque=lambda t: [0, 0]),
     ("a torque function of time runs in Python; in the compiled loop give a table "
      "(planar_sym.motion.signals.from_table) or a constant")),
    # a closed chain's reference covers only its actuated joints: where do A's partners start?
    (lambda arm, five: simulate_controlled(five, controller("pd", 1.0, 0.1), (0, 1),
                                           reference=ZERO_REF),
     "give q0 (every coordinate): the reference does not say where the passive joints start"),
], ids=["robot", "controller", "plant", "plant-name", "method", "gains", "no-reference",
        "channels", "reference-type", "table-width", "torque-shape", "torque-function",
        "no-q0"])
def test_refusals_word_for_word(arm, five, call, message):
    with pytest.raises(InputError) as err:
        call(arm, five)
    assert str(err.value) == message


def test_laws_a_robot_cannot_carry_out_are_refused_word_for_word():
    """``check_controller`` reads only the robot's shape: stand-ins with one and two passive
    joints of a tree, and a closed chain with more passive coordinates than loop equations."""
    from types import SimpleNamespace

    from planar_sym.dynamics.engine import check_controller

    tree = SimpleNamespace(name="stand_in", n=3, actuated=(0,), coordinates=("a", "b", "c"),
                           is_closed_chain=False, n_constraints=0)
    with pytest.raises(InputError) as err:
        check_controller(tree, controller("computed_torque", 4.0, 4.0, width=1))
    assert str(err.value) == ("stand_in: computed-torque control needs every coordinate "
                              "actuated or set by the loops; b, c are passive (underactuated): "
                              "use controller \"pd\"")
    check_controller(tree, controller("pd", 4.0, 1.0, width=1))  # PD is fine
    cart = SimpleNamespace(name="cart_pole", n=2, actuated=(0,), coordinates=("cart", "hinge"),
                           is_closed_chain=False, n_constraints=0)
    with pytest.raises(InputError) as err:
        check_controller(cart, controller("computed_torque", 4.0, 4.0, width=1))
    assert str(err.value) == ("cart_pole: computed-torque control needs every coordinate "
                              "actuated or set by the loops; hinge is passive (underactuated): "
                              "use controller \"pd\"")
    loop = SimpleNamespace(name="stand_in", n=4, actuated=(0,), coordinates=("a", "b", "c", "d"),
                           is_closed_chain=True, n_constraints=2)
    with pytest.raises(InputError) as err:
        check_controller(loop, controller("pd", 4.0, 1.0, width=1))
    assert str(err.value) == ("stand_in: control of a closed chain needs as many passive "
                              "coordinates (3) as loop equations (2)")

# -- failures of the compiled loop ---------------------------------------------------------------

def test_too_many_steps_names_the_robot_the_time_and_the_reason(arm, five):
    for robot, q0 in ((arm, [-1.0, 0.5]), (five, five.q_drawn)):
        with pytest.raises(SimulationError) as err:
            simulate_controlled(robot, NONE2, (0.0, 0.3), q0=q0, torque=[0.001, 0.0],
                                t_eval=np.linspace(0.0, 0.3, 7), max_steps=5)
        assert str(err.value).startswith(f"{robot.name}: integration failed at t = ")
        assert str(err.value).endswith(" s: too many steps (raise max_steps or loosen the "
                                       "tolerances)")
        # five steps of the first segment: well inside it
        assert 0.0 < float(str(err.value).split("t = ")[1].split(" s")[0]) < 0.05


def test_a_step_size_underflow_on_a_tree_names_its_time(arm):
    """1e30 N*m on a 2-dof arm: accelerations near 1e33 rad/s^2, every step rejected until the
    step size underflows at the start."""
    with pytest.raises(SimulationError) as err:
        simulate_controlled(arm, NONE2, (0.05, 0.35), q0=[-1.0, 0.5], torque=[1e30, 0.0])
    assert str(err.value) == ("serial_2dof: integration failed at t = 0.05 s: the step size "
                              "fell below 1e-14 s: the problem is stiff or singular here")


@pytest.mark.parametrize("start", [0.05, 0.0])
def test_a_step_size_underflow_on_a_closed_chain_is_the_loops_event(five, start):
    """On a closed chain the same failure is where the loops could not be kept: an event that
    stops the run at its time, the start. At t = 0 exactly too: the failure time 0.0 used to
    read as "no failure", and the run went on over unfilled rows (found by this file's
    author; segments now take None for no failure)."""
    run = simulate_controlled(five, NONE2, (start, start + 0.3), q0=five.q_drawn,
                              torque=[1e30, 0.0], t_eval=np.linspace(start, start + 0.3, 7))
    assert [(e.name, e.time_s, e.stopped) for e in run.events] == [
        ("the loops could not stay assembled (singular constraint matrix)", start, True)]
    assert run.t_s.tolist() == [start]
    assert run.q[0] == pytest.approx(five.q_drawn, abs=1e-9)



def test_the_rhs_count_is_that_of_dopri5_with_fsal(arm, five):
    """Each call of the compiled DOPRI5 evaluates the dynamics once to start and six times per
    step it tries (the seventh stage is the next step's first): a tree runs in one call,
    1 + 6 k; the five-bar over 0.3 s in three calls of 0.1 s (re-projected between them),
    3 + 6 k."""
    for robot, q0, calls in ((arm, [-1.0, 0.5], 1), (five, five.q_drawn, 3)):
        run = simulate_controlled(robot, NONE2, (0.0, 0.3), q0=q0, torque=[0.001, 0.0],
                                  t_eval=np.linspace(0.0, 0.3, 7))
        assert run.n_rhs % 6 == calls
        assert run.n_rhs > 6 * 20  # at rtol 1e-10, many steps (measured over 1000)

# -- assembly modes and the controller's singular poses -----------------------------------------

def det_signs(robot, q):
    jac = robot.constraint_jacobian(q).reshape(len(q), robot.n_constraints, robot.n)
    return np.sign(np.linalg.det(jac[:, :, [1, 3]])).tolist()  # B and D are passive


def test_assembly_changes_report_the_first_sign_change_of_det_phi_p(five):
    """Poses given directly (``assembly_changes`` reads only det Phi_p at each sample): the drawn
    assembly mode (det < 0) and the other one, found by Newton from the passive joints flipped."""
    from planar_sym.dynamics.engine import assembly_changes
    from planar_sym.motion.closure import solve_passive

    drawn = five.q_drawn
    other = solve_passive(five, drawn[None, [0, 2]], q_guess=drawn + [0.0, 2.0, 0.0, -2.0])[0]
    t = np.array([0.0, 0.1, 0.2, 0.3, 0.4])
    q = np.array([drawn, drawn, other, other, drawn])
    assert det_signs(five, q) == [-1, -1, 1, 1, -1]
    sentence = ("the mechanism passed through a singular pose (det Phi_p changed sign between "
                "t = {} and {} s) and changed assembly mode")
    # the first change only, between 0.1 and 0.2 s, dated at the later sample
    assert assembly_changes(five, t, q) == [Event(sentence.format(0.1, 0.2), 0.2, False)]
    # the sign of the first sample is the reference, from the first sample on
    assert assembly_changes(five, t[:3], q[[2, 0, 0]]) == [
        Event(sentence.format(0, 0.1), 0.1, False)]
    assert assembly_changes(five, t[:3], q[[2, 2, 0]]) == [
        Event(sentence.format(0.1, 0.2), 0.2, False)]
    assert assembly_changes(five, t[:3], q[[0, 2, 0]]) == [
        Event(sentence.format(0, 0.1), 0.1, False)]
    assert assembly_changes(five, t[:3], q[[0, 0, 0]]) == []


def test_a_pose_exactly_singular_is_no_change_by_itself(five):
    """With the small y offset of the left distal link's end set to 0, every link lies on the
    x axis at q = 0 and det Phi_p is exactly 0 there: a run through it between two poses of
    the same mode changes nothing; a start exactly there has no mode to leave."""
    from planar_sym.dynamics.engine import assembly_changes
    from planar_sym.motion.closure import solve_passive

    flat = five.with_parameters(py_L_Link2_CS2=0.0)
    drawn = solve_passive(flat, five.q_drawn[None, [0, 2]], q_guess=five.q_drawn)[0]
    other = solve_passive(flat, drawn[None, [0, 2]], q_guess=drawn + [0.0, 2.0, 0.0, -2.0])[0]
    singular = np.zeros(4)
    t = np.array([0.0, 0.1, 0.2])
    assert det_signs(flat, np.array([drawn, singular, other])) == [-1, 0, 1]
    sentence = ("the mechanism passed through a singular pose (det Phi_p changed sign between "
                "t = 0.1 and 0.2 s) and changed assembly mode")
    assert assembly_changes(flat, t, np.array([drawn, singular, other])) == [
        Event(sentence, 0.2, False)]
    assert assembly_changes(flat, t, np.array([drawn, singular, drawn])) == []
    assert assembly_changes(flat, t, np.array([singular, drawn, other])) == []


def test_control_values_name_the_sample_where_the_model_is_singular(five):
    """Computed torque on the flat five-bar above: its passive accelerations solve Phi_p
    qdd_p = ..., which has no solution at q = 0 (det Phi_p exactly 0), the third sample."""
    from planar_sym.dynamics.engine import _Setup, control_values

    flat = five.with_parameters(py_L_Link2_CS2=0.0)
    ctl = controller("computed_torque", 4.0, 4.0, width=2)
    setup = _Setup(flat, flat, ctl, ZERO_REF, None, [], np.full(2, np.inf))
    y = np.zeros((4, 8))
    y[:2, :4] = five.q_drawn
    y[3, :4] = five.q_drawn
    with pytest.raises(SimulationError) as err:
        control_values(flat, setup, np.array([0.0, 0.1, 0.25, 0.3]), y)
    assert str(err.value) == ("five_bar_type1: the controller failed at t = 0.25 s (a singular "
                              "pose of the controller's model?)")


# -- SUNDIALS against the compiled loop ---------------------------------------------------------

@pytest.mark.parametrize("method", ["cvodes", "idas"])
@pytest.mark.parametrize("name", ["serial_2dof", "five_bar_type1"])
@pytest.mark.parametrize("law, kp, kd", [("pd", [0.4, 0.2], [0.02, 0.01]),
                                         ("computed_torque", 100.0, 20.0)])
def test_a_model_error_and_an_input_torque_on_sundials_against_dopri5(name, method, law, kp,
                                                                      kd):
    """PD with gravity compensation (a tree's g(q); a closed chain's inverse dynamics at rest)
    and computed torque, on a plant 20 % heavier whose compiled library was loaded apart from
    the model's, with a constant input torque added to the controller's: SUNDIALS and the C
    loop integrate the same closed loop."""
    from planar_sym.model.library import Library
    from planar_sym.model.robot import Robot

    robot = ps.load(name)
    plant = Robot(name, Library(name)).with_parameters(
        **{k: 1.2 * v for k, v in robot.parameters.items() if k.startswith("m_")})
    assert plant.library is not robot.library
    act = list(robot.actuated)
    q0 = robot.q_drawn if name == "five_bar_type1" else np.array([-1.0, 0.5])
    ref = Signal(np.array([0.0, 1.0]), np.array([[[a + 0.05] for a in q0[act]]]))
    t = np.linspace(0.0, 0.5, 11)
    runs = [simulate_controlled(robot, controller(law, kp, kd), (0.0, 0.5), reference=ref,
                                plant=plant, q0=q0, t_eval=t, method=m, torque=[0.01, -0.005])
            for m in ("dopri5", method)]
    # measured 1.7e-10 rad and 4.5e-11 N*m at most, balance 9e-11
    assert np.max(np.abs(runs[0].q - runs[1].q)) < 1e-8
    assert np.max(np.abs(runs[0].tau - runs[1].tau)) < 1e-8
    assert np.max(np.abs(runs[1].error[0] - 0.05)) < 1e-12
    assert runs[1].balance_residual < 1e-9
    assert np.max(np.abs(runs[0].q[-1] - q0)) > 1e-3  # it moved


@pytest.mark.parametrize("method", ["cvodes", "idas"])
def test_a_sundials_failure_names_the_robot_the_method_and_the_span(arm, five, method):
    """1e308 N*m: the first evaluation of the dynamics is not finite. The message names the
    span of the call that failed: the whole run for a tree, the first 0.1 s segment of a closed
    chain; its last words are CasADi's."""
    what = {"cvodes": 'CVode returned "CV_FIRST_RHSFUNC_ERR". Consult CVODES documentation.',
            "idas": 'IDACalcIC returned "IDA_FIRST_RES_FAIL". Consult IDAS documentation.'}
    for robot, q0, span in ((arm, [-1.0, 0.5], "0.05 and 0.35"),
                            (five, five.q_drawn, "0.05 and 0.15")):
        with pytest.raises(SimulationError) as err:
            simulate_controlled(robot, NONE2, (0.05, 0.35), q0=q0, torque=[1e308, 0.0],
                                t_eval=np.linspace(0.05, 0.35, 7), method=method)
        text = str(err.value)
        assert text.startswith(f"{robot.name}: {method} failed between t = {span} s: ")
        assert text.endswith(what[method])
        assert "\n" not in text
