"""The interactive view ``ps.explore`` (planar_sym/outputs/explore.py): its numbers against the
inverse dynamics computed independently, the loops and assembly mode kept as a slider moves, a
pose out of reach reported (never raised), the widget built and driven headless (ipywidgets
needs no front end to set a slider's value), and its notebook run in a kernel."""

from __future__ import annotations

import re
import subprocess
import sys

import jupytext
import numpy as np
import pytest
from conftest import ROOT
from test_notebooks import NOTEBOOKS, execute, kernel_env, printed  # noqa: F401 (a fixture)

import planar_sym as ps
from planar_sym.dynamics.reactions import joint_loads
from planar_sym.outputs.explore import ExploreState, pose_report, task_report

pytest.importorskip("ipywidgets")

TOL = 1e-12


def closed_chain_reference(robot, q_act, qd_act, qdd_act, q_guess=None):
    """Every coordinate, torques, cut forces and loads of a closed chain at one pose, computed
    the library's usual way: ``ps.from_actuated`` on a one-sample motion, then
    ``closed_chain_inverse_dynamics`` and ``ps.inverse_along``."""
    jt = ps.from_actuated(robot, np.zeros(1), np.reshape(q_act, (1, -1)),
                          np.reshape(qd_act, (1, -1)), np.reshape(qdd_act, (1, -1)), q_guess)
    tau, lam = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
    along = ps.inverse_along(robot, np.zeros(1), jt.q, jt.qd, jt.qdd)
    return jt, tau[0], lam[0], along


# -- the numbers -------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["serial_2dof", "serial_3dof", "serial_rpr"])
def test_tree_torques_and_loads_equal_the_inverse_dynamics(name):
    robot = ps.load(name)
    rng = np.random.default_rng(7)
    for _ in range(3):
        q = robot.q_drawn + rng.uniform(-0.5, 0.5, robot.n)
        qd, qdd = rng.uniform(-2, 2, robot.n), rng.uniform(-5, 5, robot.n)
        report = pose_report(robot, q[list(robot.actuated)], qd, qdd)
        assert report.ok and report.reached
        np.testing.assert_array_equal(report.q, q)
        tau = robot.inverse_dynamics(q, qd, qdd)
        assert np.max(np.abs(report.tau - tau)) <= TOL * max(1.0, np.max(np.abs(tau)))
        loads = joint_loads(robot, q, qd, qdd)
        assert np.max(np.abs(report.loads.force - loads.force)) <= TOL * max(
            1.0, np.max(np.abs(loads.force)))
        assert np.max(np.abs(report.loads.couple - loads.couple)) <= TOL * max(
            1.0, np.max(np.abs(loads.couple)))


@pytest.mark.parametrize("name", ["five_bar_type1", "five_bar_type2", "parallel_3rrr",
                                  "slider_crank_slider_driven"])
def test_closed_chain_torques_equal_the_inverse_dynamics_along_one_sample(name):
    robot = ps.load(name)
    act = list(robot.actuated)
    q_act = robot.q_drawn[act] + 0.02 * np.arange(1, len(act) + 1)
    qd, qdd = np.linspace(-0.5, 0.8, len(act)), np.linspace(3.0, -2.0, len(act))
    report = pose_report(robot, q_act, qd, qdd)
    assert report.ok, report.message
    jt, tau, lam, along = closed_chain_reference(robot, q_act, qd, qdd)
    scale = max(1.0, np.max(np.abs(tau)))
    np.testing.assert_allclose(report.q, jt.q[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(report.qd, jt.qd[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(report.qdd, jt.qdd[0], rtol=0, atol=1e-11)
    assert np.max(np.abs(report.tau - tau)) <= TOL * scale
    assert np.max(np.abs(report.tau - along.tau[0])) <= TOL * scale
    assert np.max(np.abs(report.cut_forces - lam)) <= TOL * max(1.0, np.max(np.abs(lam)))
    force = along.loads.force
    assert np.max(np.abs(report.loads.force - force)) <= TOL * max(1.0, np.max(np.abs(force)))
    assert report.loads.names == along.loads.names
    assert report.loop_residual_m < 1e-12


def test_static_torques_of_serial_2dof_are_its_gravity_torques():
    robot = ps.load("serial_2dof")
    state = ExploreState(robot)
    biggest = 0.0
    for q in ([0.0, 0.0], [0.4, -1.2], [-2.0, 2.5], [np.pi / 2, 0.3]):
        report = state.move_actuated(q)
        g = robot.gravity(np.array(q))
        assert np.max(np.abs(report.tau - g)) <= TOL * max(1.0, np.max(np.abs(g)))
        biggest = max(biggest, np.abs(g).max())
    assert biggest > 0.1  # gravity does show in these poses
    # and in the widget: its default rates are zero
    view = ps.explore(robot)
    view.sliders["joint1"].value = 30.0
    view.sliders["joint2"].value = -45.0
    q = np.radians([30.0, -45.0])
    np.testing.assert_allclose(view.report.q, q, rtol=0, atol=1e-15)
    g = robot.gravity(q)
    assert np.max(np.abs(view.report.tau - g)) <= TOL * np.max(np.abs(g))


# -- closed chains: the loops and the assembly mode ------------------------------------------

def passive_sign(robot, q) -> float:
    jac = np.reshape(robot.constraint_jacobian(q), (robot.n_constraints, robot.n))
    return float(np.sign(np.linalg.det(jac[:, list(robot.passive)])))


@pytest.mark.parametrize("name, joint, steps", [
    ("five_bar_type1", "A", [5.0, 10.0, 3.0, -25.0, -20.0, 40.0]),
    ("five_bar_type2", "E", [10.0, 20.0, -45.0, 30.0]),
    ("parallel_3rrr", "A1", [5.0, -12.0, 4.0]),
])
def test_moving_a_closed_chain_slider_keeps_the_loops_and_the_assembly_mode(name, joint, steps):
    robot = ps.load(name)
    view = ps.explore(robot)
    sign = passive_sign(robot, view.report.q)
    slider = view.sliders[joint]
    moved = 0
    for step in steps:  # each a jump of several degrees: continued, not Newton from afar
        slider.value += step
        report = view.report
        assert report.ok, report.message
        assert np.max(np.abs(robot.constraint(report.q))) < 1e-9
        assert passive_sign(robot, report.q) == sign
        i = robot.coordinates.index(joint)
        assert np.degrees(report.q[i]) == pytest.approx(slider.value, abs=1e-9)
        moved += 1
    assert moved == len(steps)


def test_large_jumps_keep_the_assembly_mode_where_the_other_one_closes_too():
    """Large jumps of both sliders: each pose reached is the one continued along the loop,
    though the five-bar's other assembly mode (B flipped) closes the loop there as well."""
    robot = ps.load("five_bar_type1")
    state = ExploreState(robot)
    sign = passive_sign(robot, state.q)
    for target in ([140.0, 85.0], [80.0, 30.0], [125.0, 100.0]):
        q_act = np.radians(target)
        report = state.move_actuated(q_act)
        assert report.ok, report.message
        assert passive_sign(robot, report.q) == sign
        assert np.max(np.abs(robot.constraint(report.q))) < 1e-9
        other = other_mode(robot, q_act, report.q)
        assert passive_sign(robot, other) == -sign  # the other mode is there too
        assert np.max(np.abs(other - report.q)) > 1.0


def other_mode(robot, q_act, q):
    """The loops closed at ``q_act`` (rad) in the other assembly mode than ``q``: Newton from
    guesses with the passive joints turned (a grid of -3 to 3 rad), the first that lands in it."""
    pas = list(robot.passive)
    turns = np.linspace(-3.0, 3.0, 7)
    for turn in np.array(np.meshgrid(*[turns] * len(pas))).reshape(len(pas), -1).T:
        guess = q.copy()
        guess[pas] += turn
        try:
            found = ps.from_actuated(robot, [0.0], [q_act], [[0.0, 0.0]], [[0.0, 0.0]],
                                     q_guess=guess).q[0]
        except ps.PlanarSymError:
            continue
        if passive_sign(robot, found) != passive_sign(robot, q):
            return found
    raise AssertionError("no other assembly mode found")


# -- out of reach -----------------------------------------------------------------------------

def test_an_unreachable_pose_gives_a_message_not_an_exception():
    robot = ps.load("five_bar_type1")
    state = ExploreState(robot)
    start = state.q.copy()
    report = state.move_actuated(start[[0, 2]] + np.radians([170.0, 0.0]))
    assert not report.reached and not report.ok
    assert report.message.startswith("Outside the workspace: A = ")
    np.testing.assert_array_equal(report.q, start)  # the last pose reached, still drawn
    assert report.tau is not None  # ... with its torques
    # a rate change keeps saying the pose asked for is out of reach
    assert state.set_rates(qdd=[1.0, 0.0]).message == report.message
    # and the next reachable move works from the last pose reached
    back = state.move_actuated(start[[0, 2]] + np.radians([5.0, 0.0]))
    assert back.ok and back.reached
    # the task point out of reach
    far = task_report(robot, [1.0, 0.1], q_previous=start)
    assert not far.reached and far.message.startswith("Out of reach: the task point")
    # a start pose that picks no working mode (the 2-DOF arm drawn stretched out)
    arm = ps.load("serial_2dof")
    flat = task_report(arm, [0.2, 0.05])
    assert not flat.reached and "picks no working mode" in flat.message


def test_the_widget_shows_the_message_and_recovers():
    view = ps.explore("five_bar_type1")
    picture = view.picture.value
    view.sliders["A"].value += 170.0
    assert "Outside the workspace" in view.readout.value and "color:#b00020" in view.readout.value
    assert view.picture.value != picture  # redrawn, titled as the last pose reached
    view.sliders["A"].value -= 165.0
    assert "Outside the workspace" not in view.readout.value and view.report.ok


def test_a_passive_joint_of_a_tree_is_a_message():
    report = pose_report(ps.load("cart_pole"), [0.1])
    assert report.reached and report.tau is None
    assert report.message.startswith("No torques at this pose: cart_pole: joint hinge has no motor")


# -- the widget -------------------------------------------------------------------------------

def test_the_widget_builds_headless_and_follows_its_sliders_and_boxes():
    robot = ps.load("five_bar_type1")
    view = ps.explore(robot)
    assert set(view.sliders) == {"A", "E"} and view.sliders["A"].description == "A (deg)"
    assert view.qdd["E"].description == "qdd E (deg/s^2)"
    assert "application/vnd.jupyter.widget-view+json" in view._repr_mimebundle_()
    first = (view.picture.value, view.readout.value)
    assert first[0][:8] == b"\x89PNG\r\n\x1a\n"
    view.sliders["E"].value -= 8.0
    assert view.picture.value != first[0] and view.readout.value != first[1]
    q_act = np.radians([view.sliders["A"].value, view.sliders["E"].value])
    _, tau, _, _ = closed_chain_reference(robot, q_act, [0.0, 0.0], [0.0, 0.0])
    for name, value in zip("AE", tau):
        assert f"<td>tau {name}</td><td>{value:.6g} N*m</td>" in view.readout.value
    # accelerations in deg/s^2 and rates in deg/s: the torques are those of rad/s^2, rad/s
    view.qdd["A"].value = 300.0
    view.qd["E"].value = -90.0
    _, tau, _, _ = closed_chain_reference(robot, q_act, np.radians([0.0, -90.0]),
                                          np.radians([300.0, 0.0]))
    assert np.max(np.abs(view.report.tau - tau)) <= TOL * np.max(np.abs(tau))
    assert f"<td>tau A</td><td>{tau[0]:.6g} N*m</td>" in view.readout.value
    assert "<th>|F| (N)</th>" in view.readout.value and "<td>C</td><td>revolute</td>" in \
        view.readout.value


def test_task_sliders_move_the_task_point_in_its_working_mode():
    robot = ps.load("serial_2dof")
    view = ps.explore(robot, task=True, q_start=[0.3, 1.0])
    assert view.report.ok and set(view.sliders) == {"x", "y"}
    # the arm is typed in m: its sliders read m, to 0.1 mm
    assert view.sliders["x"].description == "task x (m)"
    assert view.sliders["x"].readout_format == ".4f"
    view.sliders["x"].value -= 0.02
    view.sliders["y"].value += 0.015
    report = view.report
    assert report.ok, report.message
    np.testing.assert_allclose(report.task, [view.sliders["x"].value,
                                             view.sliders["y"].value], atol=1e-12)
    assert report.q[1] > 0  # the elbow stays bent the way it started
    tau = robot.inverse_dynamics(report.q, np.zeros(2), np.zeros(2))
    assert np.max(np.abs(report.tau - tau)) <= TOL * np.max(np.abs(tau))
    # a closed chain with an orientation: the 3-RRR's platform turned by its phi slider
    rrr = ps.explore("parallel_3rrr", task=True)
    rrr.sliders["phi"].value += 10.0
    assert rrr.report.ok, rrr.report.message
    assert np.degrees(rrr.report.task[2]) == pytest.approx(rrr.sliders["phi"].value, abs=1e-9)
    assert np.max(np.abs(rrr.robot.constraint(rrr.report.q))) < 1e-9


def test_a_robot_typed_in_cm_is_explored_in_cm(tmp_path):
    """The seed's arm typed in cm: its task sliders read cm (to 0.1 mm), a move of 2 cm is
    0.02 m in the report, the picture's axes are in cm, and the torques are those of the arm
    typed in m at the same pose."""
    from conftest import serial_2dof_in_cm

    view = ps.explore(str(serial_2dof_in_cm(tmp_path)), task=True, q_start=[0.3, 1.0])
    assert view.sliders["x"].description == "task x (cm)"
    assert view.sliders["x"].readout_format == ".2f"
    start = view.report.task.copy()
    view.sliders["x"].value -= 2.0
    assert view.report.ok, view.report.message
    np.testing.assert_allclose(view.report.task - start, [-0.02, 0.0], atol=1e-12)
    fig = ps.outputs.explore.pose_figure(view.robot, view._desc, view.report.q)
    assert fig.axes[0].get_xlabel() == "x (cm)"
    in_m = ps.load("serial_2dof")
    tau = in_m.inverse_dynamics(view.report.q, np.zeros(2), np.zeros(2))
    assert np.max(np.abs(view.report.tau - tau)) <= 1e-12 * np.max(np.abs(tau))


def test_a_slider_driven_chain_shows_newtons_and_metres():
    view = ps.explore("slider_crank_slider_driven")
    assert view.sliders["slide"].description == "slide (m)"
    view.sliders["slide"].value += 0.005
    assert view.report.ok, view.report.message
    assert re.search(r"<td>tau slide</td><td>\S+ N</td>", view.readout.value)


def test_importing_stays_light_and_a_missing_ipywidgets_is_named(monkeypatch):
    code = ("import sys, planar_sym as ps, planar_sym.outputs.explore; ps.explore; "
            "print('ipywidgets' in sys.modules, 'matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, check=True, timeout=120).stdout.split()
    assert out == ["False", "False"]
    monkeypatch.setitem(sys.modules, "ipywidgets", None)  # as if not installed
    with pytest.raises(ImportError, match=r"pip install ipywidgets"):
        ps.explore("serial_2dof")


# -- the notebook -----------------------------------------------------------------------------

STATIC = re.compile(r"^static torques at the drawn pose: tau A = (\S+) N\*m, tau E = (\S+) N\*m$",
                    re.MULTILINE)
MOVED = re.compile(r"^moved: A = (\S+) deg, B = (\S+) deg, E = (\S+) deg, D = (\S+) deg$",
                   re.MULTILINE)
ACCEL = re.compile(r"^accelerated torques: tau A = (\S+) N\*m, tau E = (\S+) N\*m$", re.MULTILINE)


def test_the_explore_notebook_runs(kernel_env):  # noqa: F811 (the fixture)
    nb = execute(jupytext.read(NOTEBOOKS / "explore_five_bar.py"), NOTEBOOKS)
    text = printed(nb)
    robot = ps.load("five_bar_type1")
    ((a, e),) = STATIC.findall(text)
    tau, _ = robot.closed_chain_inverse_dynamics(robot.q_drawn, np.zeros(4), np.zeros(4))
    np.testing.assert_allclose([float(a), float(e)], tau[0], rtol=1e-11)
    ((qa, qb, qe, qdd), ) = MOVED.findall(text)
    q_act = robot.q_drawn[[0, 2]] + np.radians([10.0, 0.0])
    jt, tau, _, _ = closed_chain_reference(robot, q_act, [0.0, 0.0], np.radians([200.0, 0.0]))
    np.testing.assert_allclose(np.radians([float(qa), float(qb), float(qe), float(qdd)]),
                               jt.q[0], atol=1e-7)
    ((a, e),) = ACCEL.findall(text)
    np.testing.assert_allclose([float(a), float(e)], tau, rtol=1e-11)
    assert "reached: False" in text and "Outside the workspace: A = " in text
    # the two views are widgets in the saved notebook
    views = [out for cell in nb.cells if cell.cell_type == "code"
             for out in cell.get("outputs", ())
             if "application/vnd.jupyter.widget-view+json" in out.get("data", {})]
    assert len(views) == 2
