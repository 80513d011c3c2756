"""Control in the compiled loop (issue 12), against analytic error dynamics, an independent
SciPy loop with the controller written here in numpy, SUNDIALS, and the energy balance.

Analytic cases used:

* computed torque with an exact model: every error obeys e'' + Kd e' + Kp e = 0, so from a
  start error e0 (at rest relative to the reference), critically damped (Kp = w^2,
  Kd = 2 w): e(t) = e0 (1 + w t) exp(-w t), whatever the reference does;
* PD + gravity compensation holding a pose with a wrong mass in the model: the steady error
  solves Kp e = g_plant(q) - g_nom(q) at q = q_ref - e (a point pendulum: g = m g L cos q).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import TEST_ROBOTS

from planar_sym.control import controller, from_motion, from_table, simulate_controlled
from planar_sym.errors import InputError, WorkspaceError
from planar_sym.model.locate import load
from planar_sym.motion.signals import Signal
from planar_sym.study import spec
from planar_sym.study.checks import StudyError
from planar_sym.study.motion import joint_motion
from planar_sym.study.run import load_study, robot_of, run

W = 2 * np.pi * 4.0  # rad/s: a 4 Hz loop


def study_reference(name: str, samples: int = 201):
    st = load_study(name)
    robot = robot_of(st)
    jt, _ = joint_motion(st, robot, samples)
    return robot, jt


def critically_damped(width: int):
    return controller("computed_torque", W * W, 2 * W, width=width)


# -- computed torque with an exact model ----------------------------------------------------

@pytest.mark.parametrize("name", ["serial_2dof_cartesian_move", "serial_3dof_cartesian_move",
                                  "five_bar_type1_move_x", "parallel_3rrr_move_x",
                                  "slider_crank_turn"])
def test_computed_torque_tracks_to_integrator_accuracy(name):
    robot, jt = study_reference(name)
    span = (0.0, float(jt.t_s[-1]))
    res = simulate_controlled(robot, critically_damped(len(robot.actuated)), span,
                              reference=jt, t_eval=np.linspace(*span, 101))
    # the reference is a quintic Hermite interpolant of the samples: tracked exactly
    assert np.max(np.abs(res.error)) < 1e-8  # measured 1.1e-12 to 1.6e-9 (slider crank)
    assert res.balance_residual < 1e-9  # measured 2e-14 to 3.5e-11
    if robot.is_closed_chain:
        assert res.constraint_drift_m < 1e-10  # within DRIFT_LIMIT_M = 1e-6 by far
    assert not res.events


def test_computed_torque_error_decays_as_the_analytic_solution():
    robot, jt = study_reference("serial_2dof_cartesian_move")
    e0 = np.array([0.03, -0.02])  # rad
    q0 = jt.q[0] - e0
    t = np.linspace(0.0, 2.0, 81)
    res = simulate_controlled(robot, critically_damped(2), (0.0, 2.0), reference=jt,
                              q0=q0, qd0=jt.qd[0], t_eval=t)
    want = e0[None, :] * ((1 + W * t) * np.exp(-W * t))[:, None]
    assert np.max(np.abs(res.error - want)) < 1e-9  # measured 2e-12


def test_closed_chain_error_decays_as_the_analytic_solution():
    """The 5-bar: control at A and E, the passive joints completed through the loop."""
    from planar_sym.motion.closure import complete_rates, solve_passive

    robot, jt = study_reference("five_bar_type1_move_x")
    act = list(robot.actuated)
    e0 = np.array([0.01, -0.015])
    qa0 = jt.q[0, act] - e0
    q0 = solve_passive(robot, qa0[None], q_guess=jt.q[0])[0]
    qd0 = complete_rates(robot, q0[None], jt.qd[0, act][None], np.zeros((1, 2)))[0][0]
    t = np.linspace(0.0, 1.5, 61)
    res = simulate_controlled(robot, critically_damped(2), (0.0, 1.5), reference=jt, q0=q0,
                              qd0=qd0, t_eval=t)
    want = e0[None, :] * ((1 + W * t) * np.exp(-W * t))[:, None]
    assert np.max(np.abs(res.error - want)) < 1e-9
    assert res.constraint_drift_m < 1e-10


# -- a second implementation: SciPy with the controller in numpy ----------------------------

def scipy_loop(robot, plant, law, kp, kd, ref: Signal, q0, qd0, t):
    """The closed loop written independently: numpy controller, SciPy DOP853 integrator."""
    from scipy.integrate import solve_ivp

    n = robot.n

    def rhs(tt, x):
        q, qd = x[:n], x[n:]
        qr, qdr, qddr = ref(tt)[0], ref(tt, 1)[0], ref(tt, 2)[0]
        e, ed = qr - q, qdr - qd
        if law == "pd":
            tau = kp * e + kd * ed + robot.gravity(q)
        else:
            tau = robot.inverse_dynamics(q, qd, qddr + kd * ed + kp * e)
        return np.concatenate([qd, plant.forward_dynamics(q, qd, tau)])

    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([q0, qd0]), method="DOP853",
                    t_eval=t, rtol=1e-12, atol=1e-13)
    return sol.y[:n].T


@pytest.mark.parametrize("law", ["pd", "computed_torque"])
def test_model_error_run_matches_an_independent_scipy_loop(law):
    robot, jt = study_reference("serial_2dof_cartesian_move", 51)
    plant = robot.with_parameters(m_link2=0.09, izz_link2=1.3e-4)
    ref = from_motion(jt.t_s, jt.q, jt.qd, jt.qdd)
    kp, kd = (np.array([4.0, 0.3]), np.array([0.25, 0.02])) if law == "pd" else (W * W, 2 * W)
    t = np.linspace(0.0, 5.0, 51)
    q0 = jt.q[0] + [0.02, -0.01]
    ctl = controller(law, kp, kd, width=2)
    res = simulate_controlled(robot, ctl, (0.0, 5.0), reference=ref, plant=plant, q0=q0,
                              qd0=jt.qd[0], t_eval=t)
    q_ref = scipy_loop(robot, plant, law, np.broadcast_to(kp, 2), np.broadcast_to(kd, 2), ref,
                       q0, jt.qd[0], t)
    assert np.max(np.abs(res.q - q_ref)) < 1e-8  # measured ~1e-11
    assert np.max(np.abs(res.error)) > 1e-4  # the model error shows
    assert res.balance_residual < 1e-9


def test_pd_steady_error_against_the_fixed_point(derived):
    """A point pendulum (m L^2, g = m g L cos q) held at 30 deg by PD + gravity compensation
    whose model has the wrong mass: the steady error solves Kp e = (m_p - m_n) g L cos(q)."""
    from scipy.optimize import brentq

    robot = derived(TEST_ROBOTS / "point_pendulum.toml")[1]
    m_n = robot.parameters["m_rod"]
    plant = robot.with_parameters(m_rod=1.2 * m_n)
    L, g, kp, kd = 0.6, 9.81, 40.0, 6.0
    q_r = np.radians(30.0)
    ref = Signal(np.array([0.0, 20.0]), np.array([[[q_r]]]))
    res = simulate_controlled(robot, controller("pd", kp, kd, width=1), (0.0, 20.0),
                              reference=ref, plant=plant, q0=[q_r], qd0=[0.0],
                              t_eval=np.linspace(0, 20, 11))
    e = brentq(lambda e: kp * e - 0.2 * m_n * g * L * np.cos(q_r - e), -1.0, 1.0)
    assert res.error[-1, 0] == pytest.approx(e, rel=1e-8)  # e = 0.0364 rad
    assert res.balance_residual < 1e-9


# -- SUNDIALS against the C integrator -----------------------------------------------------

@pytest.mark.parametrize("name", ["serial_2dof_cartesian_move", "five_bar_type1_move_x"])
@pytest.mark.parametrize("method", ["cvodes", "idas"])
def test_sundials_and_the_c_integrator_agree(name, method):
    robot, jt = study_reference(name, 101)
    w = 2 * np.pi * 2.0
    plant = robot.with_parameters(**{k: 1.1 * v for k, v in robot.parameters.items()
                                     if k.startswith("m_")})
    ctl = controller("computed_torque", w * w, 2 * w, width=len(robot.actuated))
    span = (0.0, float(jt.t_s[-1]))
    t = np.linspace(*span, 41)
    runs = [simulate_controlled(robot, ctl, span, reference=jt, plant=plant, t_eval=t,
                                method=m) for m in ("dopri5", method)]
    assert np.max(np.abs(runs[0].q - runs[1].q)) < 1e-8  # measured 1e-10
    assert np.max(np.abs(runs[0].work_j - runs[1].work_j)) < 1e-8
    assert runs[1].balance_residual < 1e-7


# -- input tables in the compiled loop -------------------------------------------------------

@pytest.mark.parametrize("interpolation", ["hold", "linear", "cubic", "pchip"])
def test_table_torques_match_scipy_evaluating_the_same_table(interpolation):
    from planar_sym.dynamics.forward import simulate

    robot = load("serial_2dof")
    times = np.linspace(0.0, 1.0, 7)
    values = np.column_stack([0.05 * np.sin(5 * times), 0.01 * np.cos(3 * times)])
    sig = from_table(times, values, interpolation)
    t = np.linspace(0.0, 1.0, 21)
    q0, qd0 = [-1.0, 0.3], [0.0, 0.0]
    res = simulate_controlled(robot, controller("none", width=2), (0.0, 1.0), torque=sig,
                              q0=q0, qd0=qd0, t_eval=t, rtol=1e-11)
    ref = simulate(robot, q0, qd0, (0.0, 1.0), t_eval=t, method="DOP853", rtol=1e-12,
                   atol=1e-13, torque=lambda tt: sig(tt)[0])
    # a hold table jumps between rows, a linear one kinks: SciPy steps over them less exactly
    limit = {"hold": 1e-6, "linear": 1e-8}.get(interpolation, 1e-9)
    assert np.max(np.abs(res.q - ref.q)) < limit
    assert np.max(np.abs(res.tau - sig(t))) < 1e-14  # the C loop evaluates the same numbers
    assert res.balance_residual < 1e-9


def test_signal_interpolants_match_scipy():
    from scipy.interpolate import CubicSpline, PchipInterpolator

    t = np.array([0.0, 0.3, 0.7, 1.2, 2.0])
    v = np.column_stack([np.sin(t), t ** 2])
    tt = np.linspace(0, 2, 37)
    assert np.max(np.abs(from_table(t, v, "cubic")(tt) - CubicSpline(t, v)(tt))) < 1e-14
    assert np.max(np.abs(from_table(t, v, "pchip")(tt) - PchipInterpolator(t, v)(tt))) < 1e-14
    assert np.max(np.abs(from_table(t, v, "linear")(tt)[:, 0] - np.interp(tt, t, v[:, 0]))) \
        < 1e-14
    q = np.column_stack([t ** 5, np.cos(t)])
    s = from_motion(t, q, np.column_stack([5 * t ** 4, -np.sin(t)]),
                    np.column_stack([20 * t ** 3, -np.cos(t)]))
    assert np.max(np.abs(s(tt)[:, 0] - tt ** 5)) < 1e-12  # a quintic is exact
    assert np.max(np.abs(s(tt, 2)[:, 0] - 20 * tt ** 3)) < 1e-10
    # the closed form equals SciPy's Hermite construction
    from scipy.interpolate import BPoly

    bp = BPoly.from_derivatives(t, np.stack([q, s(t, 1), s(t, 2)], axis=1))
    for der in range(3):
        assert np.max(np.abs(s(tt, der) - bp.derivative(der)(tt) if der else s(tt) - bp(tt))) \
            < 1e-10


# -- saturation, friction and events ---------------------------------------------------------

@pytest.fixture(scope="module")
def geared(derived):
    return derived(TEST_ROBOTS / "actuated_2dof.toml")[1]


def test_saturation_clips_at_the_limit_and_the_event_has_its_time(geared):
    """Joint 1: torque limit 0.8 N*m, motor 0.02 N*m x 50 = 1 N*m: the bound is 0.8 N*m."""
    base = load("serial_2dof")
    jt = joint_motion(load_study("serial_2dof_joint_move"), base, 201)[0]
    ctl = controller("computed_torque", 4 * W * W, 4 * W, width=2)
    t = np.linspace(0.0, float(jt.t_s[-1]), 401)
    q0 = jt.q[0] + [0.4, 0.0]  # far off: the first commands exceed the limit
    res = simulate_controlled(geared, ctl, (0.0, t[-1]), reference=jt, q0=q0, qd0=jt.qd[0],
                              t_eval=t)
    assert np.max(np.abs(res.tau[:, 0])) <= 0.8 + 1e-12
    assert np.max(np.abs(res.tau_cmd[:, 0])) > 0.8
    assert np.array_equal(res.tau[:, 1], res.tau_cmd[:, 1])  # joint 2 has no limit
    assert res.balance_residual < 1e-8  # friction at joint 1 is in the balance
    assert res.friction_j[-1] > 0
    events = [e for e in res.events if "joint1" in e.name and "torque limit" in e.name]
    # beyond the limit from the start (logged at t = 0, the run goes on saturated), back
    # within it, then beyond again
    assert [e.time_s == 0.0 for e in events[:2]] == [True, False]
    assert not any(e.stopped for e in res.events)
    assert any("faster than its motor" in e.name for e in res.events)  # 3000 rpm / 50
    # at the second crossing the commanded torque is at the limit: on a 5 us output grid
    fine = np.linspace(0.0, 0.1, 20001)
    again = simulate_controlled(geared, ctl, (0.0, 0.1), reference=jt, q0=q0, qd0=jt.qd[0],
                                t_eval=fine)
    k = int(np.searchsorted(fine, events[1].time_s))
    assert abs(again.tau_cmd[k - 1, 0]) <= 0.8 <= abs(again.tau_cmd[k, 0])  # t = 0.04533 s


def test_a_joint_limit_stops_the_run_at_the_crossing():
    robot = load("serial_2dof")
    ref = Signal(np.array([0.0, 3.0]), np.array([[[0.0], [0.0]]]))  # hold q = 0
    ctl = controller("pd", 0.5, 0.001, width=2)
    # released 0.5 rad off, lightly damped (zeta about 0.05): joint 2 swings past -0.3 rad
    res = simulate_controlled(robot, ctl, (0.0, 3.0), reference=ref, q0=[0.0, 0.5],
                              qd0=[0.0, 0.0], joint_limits={"joint2": (-0.3, 1.0)},
                              t_eval=np.linspace(0, 3, 301))
    stop = res.stopped
    assert stop is not None and "joint2" in stop.name and "lower" in stop.name
    assert res.t_s[-1] == pytest.approx(stop.time_s)
    assert res.q[-1, 1] == pytest.approx(-0.3, abs=1e-9)  # located on the dense output
    again = simulate_controlled(robot, ctl, (0.0, 3.0), reference=ref, q0=[0.0, 0.5],
                                qd0=[0.0, 0.0], joint_limits={"joint2": (-0.3, 1.0)},
                                on_joint_limit="continue", t_eval=np.linspace(0, 3, 301))
    assert again.t_s[-1] == 3.0 and again.stopped is None
    assert again.events[0].time_s == pytest.approx(stop.time_s, abs=1e-12)


# -- bad input -------------------------------------------------------------------------------

@pytest.mark.parametrize("kp, kd, words", [(-1.0, 1.0, "negative gain"),
                                           (float("nan"), 1.0, "finite"),
                                           (10.0, 0.0, "oscillate"),
                                           ([1.0, 2.0, 3.0], 1.0, "one per actuated joint")])
def test_gains_that_make_no_sense_are_refused(kp, kd, words):
    with pytest.raises(InputError, match=words):
        controller("computed_torque", kp, kd, width=2)


def test_an_event_at_the_start_is_refused():
    robot, jt = study_reference("serial_2dof_cartesian_move", 51)
    with pytest.raises(InputError, match=r"fires at t = 0 s.*joint2"):
        simulate_controlled(robot, critically_damped(2), (0.0, 1.0), reference=jt,
                            joint_limits={"joint2": (jt.q[0, 1] + 0.1, 3.0)})


def test_a_table_that_does_not_cover_the_run_is_refused():
    robot, jt = study_reference("serial_2dof_cartesian_move", 51)
    with pytest.raises(InputError, match=r"reference motion covers 0 to 5 s.*to 6 s"):
        simulate_controlled(robot, critically_damped(2), (0.0, 6.0), reference=jt)
    sig = from_table([0.0, 0.5], [[0.0, 0.0], [0.1, 0.0]])
    with pytest.raises(InputError, match="torque table covers 0 to 0.5 s"):
        simulate_controlled(robot, controller("none", width=2), (0.0, 1.0), torque=sig,
                            q0=[0.0, 0.0])


def test_computed_torque_on_an_underactuated_arm_is_refused(derived):
    robot = derived(TEST_ROBOTS / "cart_pole.toml")[1]
    ref = Signal(np.array([0.0, 1.0]), np.zeros((1, 1, 1)))
    with pytest.raises(InputError, match="passive.*underactuated.*pd"):
        simulate_controlled(robot, critically_damped(1), (0.0, 1.0), reference=ref,
                            q0=[0.0, 0.0])


def _study(tmp_path, text: str):
    path = tmp_path / "c.toml"
    path.write_text(text)
    return path


BASE = """robot = "serial_2dof"
kind = "control"
[units]
length = "mm"
[motion]
space = "task"
profile = "cubic"
start = [100.0, 100.0]
by = [{dx}, 0.0]
duration = 1.0
samples = 51
[control]
{control}
"""


def test_a_reference_that_leaves_the_workspace_names_the_time(tmp_path):
    path = _study(tmp_path, BASE.format(dx=-400.0, control="law = \"pd\"\nkp = [1.0]\n"
                                                          "kd = [0.1]"))
    # (here the elbow's range 30..150 deg in the description is left at t = 0.62 s)
    with pytest.raises(WorkspaceError, match=r"at t = 0\.\d+ s \(sample \d+\)"):
        run(path)


@pytest.mark.parametrize("control, words", [
    ('law = "pd"', "needs gains"),
    ('law = "pd"\nkp = [1.0]\nkd = [0.1]\nnatural_frequency_hz = 2.0', "not both"),
    ('law = "pd"\nkp = [-1.0]\nkd = [0.1]', "control.kp: must be >= 0"),
    ('law = "pd"\nnatural_frequency_hz = -2.0', "natural_frequency_hz: must be > 0"),
    ('law = "none"', "needs input torques"),
    ('law = "pid"', "control.law: must be one of"),
    ('law = "pd"\nnatural_frequency_hz = 2.0\nmethod = "rk4"', "control.method"),
])
def test_control_section_errors_name_the_field(tmp_path, control, words):
    with pytest.raises(StudyError, match=words):
        spec.load(_study(tmp_path, BASE.format(dx=-200.0, control=control)))


def test_a_torque_table_shorter_than_the_run_names_the_file(tmp_path):
    (tmp_path / "tq.csv").write_text("t_s,tau1_n_m,tau2_n_m\n0,0,0\n0.5,0.01,0\n")
    path = _study(tmp_path, BASE.format(dx=-200.0, control='law = "pd"\nnatural_frequency_hz '
                                        '= 2.0\ntorque = { file = "tq.csv" }'))
    with pytest.raises(InputError, match=r"tq.csv: the torque table covers 0 to 0.5 s"):
        run(path)


# -- the built-in control studies -------------------------------------------------------------

@pytest.mark.parametrize("name", ["serial_2dof_cartesian_track",
                                  "serial_2dof_cartesian_track_pd", "five_bar_type1_track_x"])
def test_builtin_control_studies_balance_energy(name):
    res = run(name, 201)
    cols = res.columns
    scale = max(np.max(np.abs(cols["energy_j"])), np.max(np.abs(cols["work_j"])))
    assert np.max(np.abs(cols["balance_j"])) < 1e-9 * scale
    assert not res.events
    assert res.reference is not None and res.reference.shape == (201, len(res.actuated) + 2
                                                                 * ("five" in name))
    # the split of the applied torques adds up to them
    total = sum(res.split.values())
    taus = np.column_stack([v for k, v in res.torques().items()])
    assert np.max(np.abs(total - taus)) < 1e-9


def test_a_closed_chain_study_with_a_plant_of_other_lengths_starts_on_its_loops(tmp_path):
    """The built-in five-bar tracking study with the plant's left crank 4 mm longer (a model
    error in a length, typed "104 mm" in the study's [control.plant]): it was refused, q0 off
    the loop constraints, with the hint to leave q0 out, which the study had. It starts at the
    reference's actuated angles with B and D closed on the plant's loops (checked with the
    plant's own constraint), and the note says how far B moved from the reference."""
    import re
    from pathlib import Path

    import planar_sym as ps

    src = Path(ps.__file__).parent / "studies" / "five_bar_type1_track_x.toml"
    text = src.read_text().replace("m_R_Link2 = 0.0594\n",
                                   'm_R_Link2 = 0.0594\npx_L_Link1_CS2 = "104 mm"\n')
    text = text[:text.index("[outputs]")]
    path = tmp_path / "longer.toml"
    path.write_text(text)
    res = run(path, 101)
    plant = ps.load("five_bar_type1").with_parameters(px_L_Link1_CS2=0.104)
    q0 = np.array([res.get("q", index=i).values[0] for i in range(4)])
    assert np.max(np.abs(plant.constraint(q0))) < 1e-12
    assert [res.get("q", index=i).values[0] for i in (0, 2)] == [
        res.get("q_ref", index=i).values[0] for i in (0, 2)]
    moved = float(re.search(r"start: passive joints closed on the plant's loops \(B ([0-9.e-]+) "
                            r"rad from the reference\)", res.note).group(1))
    assert moved == pytest.approx(abs(q0[1] - res.reference[0, 1]), rel=1e-3)
    assert moved > 1e-2
    assert np.max(np.abs(res.columns["balance_j"])) < 1e-9 * np.max(np.abs(res.columns["work_j"]))


# -- as a student types it ---------------------------------------------------------------------

def test_one_gain_for_every_joint_in_a_study_and_in_python(tmp_path):
    """`kp = 100` (a number, not a list) in a study; `controller(...)` without width."""
    path = _study(tmp_path, BASE.format(dx=-200.0, control='law = "computed_torque"\nkp = 400\n'
                                                           'kd = 40'))
    res = run(path, 51)
    assert "Kp 400, 400 1/s^2" in res.note
    robot, jt = study_reference("serial_2dof_cartesian_move", 51)
    both = [simulate_controlled(robot, ctl, (0.0, 5.0), reference=jt,
                                t_eval=np.linspace(0, 5, 11)).q
            for ctl in (controller("pd", 2.0, 0.2), controller("pd", 2.0, 0.2, width=2))]
    assert np.array_equal(*both)


def test_a_joint_limit_named_q_k_says_its_degrees():
    robot = load("serial_2dof")
    ref = Signal(np.array([0.0, 3.0]), np.array([[[0.0], [0.0]]]))
    res = simulate_controlled(robot, controller("pd", 0.5, 0.001), (0.0, 3.0), reference=ref,
                              q0=[0.0, 0.5], joint_limits={"q2": (-0.3, 1.0)},
                              t_eval=np.linspace(0, 3, 31))
    assert res.stopped.name == "joint joint2 reached its lower limit -0.3 rad (-17.1887 deg)"


CART = """robot = "cart_pole"
kind = "control"
[units]
length = "m"
angle = "deg"
[motion]
space = "joint"
profile = "cubic"
start = [0.0, 90.0]
by = [0.5, {pole}]
duration = 1.0
samples = 51
[control]
law = "{law}"
{control}
[outputs]
animation = "gif"
frames = 4
"""


@pytest.mark.parametrize(("pole", "law", "control", "said"), [
    (45.0, "pd", "kp = [50.0]\nkd = [5.0]", "the motion moves the passive hinge, which law \"pd\""),
    (0.0, "pd", "kp = [50.0]\nkd = [5.0]\nsaturate = true",
     "control.saturate = true, but slide has no actuator limit to clip at"),
    (0.0, "pd", "kp = [50.0]\nkd = [5.0]", None),  # saturate by default: said only when asked
])
def test_what_the_law_cannot_do_is_said_once(tmp_path, capsys, pole, law, control, said):
    """A trial's cart-pole: told to turn its passive pole 45 degrees under PD, which drives the
    cart only, the pole fell to 211 degrees while only the cart's error was reported; asked to
    saturate with no actuator limit in the description, it pushed 0.273 N against the study's
    0.2 N, unclipped. Both said now, each once (the animation's second run of the study says
    nothing more); neither where the study asks nothing of the kind."""
    from planar_sym.cli import main

    path = _study(tmp_path, CART.format(pole=pole, law=law, control=control))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    err = capsys.readouterr().err
    if said is None:
        assert "passive hinge" not in err and "saturate" not in err, err
    else:
        assert err.count(said) == 1, err


def test_every_width_and_name_problem_of_a_control_study_at_once(tmp_path):
    """A trial's study with three values of kp, kd and start_error for a 2-motor arm, and two
    unknown joint names under joint_limits: one run said kp, the next start_error, kd never,
    and only the first name. Now one error lists each, with its field."""
    control = ("law = \"pd\"\nkp = [1.0, 2.0, 3.0]\nkd = [0.1, 0.2, 0.3]\n"
               "start_error = [1.0, 2.0, 3.0]\n[events]\n"
               "joint_limits = { j9 = [-1.0, 1.0], q7 = [-1.0, 1.0] }")
    path = _study(tmp_path, BASE.format(dx=-100.0, control=control))
    with pytest.raises(InputError) as err:
        run(path)
    text = str(err.value)
    assert text.startswith("invalid study:\n  ")
    for field in ("control.kp: serial_2dof needs 2 values", "control.kd: serial_2dof needs 2",
                  "control.start_error: serial_2dof needs 2", "events.joint_limits.j9:",
                  "events.joint_limits.q7:"):
        assert text.count(field) == 1, (field, text)
    # one problem alone reads as before: the file, the field, no heading
    path = _study(tmp_path, BASE.format(dx=-100.0, control="law = \"pd\"\nkp = [1.0, 2.0, 3.0]\n"
                                                          "kd = [0.1]"))
    with pytest.raises(InputError, match=r"^\S+c\.toml: control\.kp: serial_2dof needs 2 "):
        run(path)
