"""Typed results (issue 24, items 3 and 4): every result holds typed series (quantity, unit,
coordinate or joint), and every run, open loop or controlled, is one type.

- every study kind (inverse dynamics of a tree with a slider and of a closed chain driven at
  its slider, forward dynamics with and without input torques, control of a tree with a slider
  and of a closed chain) gives series whose column names are the CSV's header, in order, whose
  values are the CSV's (17 digits: the same bits) and whose units are those of the robot's
  coordinates (a slider's q in m, its force in N), the task in mm, forces in N, energies in J;
- values through the typed accessors: a slider's peak force (``peak_torques_with_units``: "N")
  against the inverse dynamics recomputed from the result's own q, qd, qdd; the power series
  against tau * qd; the figure's axes drawn from the series (a slider's force in N);
- ``simulate`` and ``simulate_controlled`` return one type (``ControlledRun`` is
  ``Simulation``); both name their columns by the same code (a controlled run's reference and
  commanded torques on the actuated coordinates), and round-trip through NPZ bit for bit; an
  open-loop run through SUNDIALS has no control fields and the columns of any other method;
- a sweep's figures are typed too: its largest tracking error equals max |q_ref - q| from the
  run's arrays, a slider's peak figure is in N, and the plot's labels and default figures come
  from those types.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.analysis.figures import Figure
from planar_sym.analysis.sweep_figures import run_figures
from planar_sym.control import ControlledRun, controller, simulate_controlled
from planar_sym.dynamics.columns import load_npz
from planar_sym.dynamics.run_result import Simulation
from planar_sym.dynamics.series import Series
from planar_sym.errors import InputError
from planar_sym.outputs.plots import figure
from planar_sym.outputs.results import write
from planar_sym.study.result import Result
from planar_sym.study.run import load_study, robot_of, run_on

RPR_GEARED = ROOT / "tests" / "robots" / "rpr_geared.toml"

#: a coordinate's quantities -> their unit, for a coordinate in rad and one in m (written out
#: here, independently of the package's table)
COORDINATE_UNITS = {
    "rad": {"q": "rad", "q_ref": "rad", "e": "rad", "qd": "rad/s", "qd_ref": "rad/s",
            "qdd": "rad/s^2", "tau": "N*m", "tau_cmd": "N*m"},
    "m": {"q": "m", "q_ref": "m", "e": "m", "qd": "m/s", "qd_ref": "m/s", "qdd": "m/s^2",
          "tau": "N", "tau_cmd": "N"},
}
#: every other quantity's unit
UNITS = {"t": "s", "x": "mm", "y": "mm", "phi": "rad", "x_ref": "mm", "y_ref": "mm",
         "phi_ref": "rad", "e_task": "mm", "p": "W", "fx": "N", "fy": "N", "jfx": "N",
         "jfy": "N", "jload": "N", "jm": "N*m", "jfn": "N", "energy": "J", "kinetic": "J",
         "potential": "J", "work": "J", "friction": "J", "balance": "J"}

FORWARD_RPR = """
title = "RPR arm under constant inputs"
robot = "serial_rpr"
kind = "forward"
[units]
length = "mm"
angle = "deg"
[simulation]
q0 = [30.0, 0.0, 60.0]
duration = 0.3
samples = 31
torque = [2.0, 15.0, -0.05]
"""

CONTROL_RPR = f"""
title = "geared RPR arm: the tool move tracked by computed torque"
robot = "{RPR_GEARED}"
kind = "control"
[units]
length = "mm"
angle = "deg"
[motion]
space = "task"
profile = "quintic"
start = [692.820323027551, 600.0, 90.0]
by = [-100.0, 0.0, 0.0]
duration = 1.0
samples = 51
[control]
law = "computed_torque"
natural_frequency_hz = 5.0
samples = 51
start_error = [1.0, 2.0, -1.0]
[control.plant]
m_boom = 1.5
"""


def expected_unit(robot, s: Series) -> str:
    if s.quantity in COORDINATE_UNITS["rad"]:
        return COORDINATE_UNITS[robot.coordinate_units[s.index]][s.quantity]
    return UNITS[s.quantity]


def read_csv(path) -> tuple[list[str], np.ndarray]:
    header, *rows = path.read_text().splitlines()
    return header.split(","), np.array([[float(v) for v in row.split(",")] for row in rows])


def same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    folder = tmp_path_factory.mktemp("studies")
    (folder / "forward_rpr.toml").write_text(FORWARD_RPR)
    (folder / "control_rpr.toml").write_text(CONTROL_RPR)
    return {"inverse, tree with a slider": ("serial_rpr_tool_move", 41),
            "inverse, closed chain driven at its slider": ("slider_crank_slider_driven_stroke",
                                                           41),
            "forward, zero torque": ("serial_2dof_free_swing", 101),
            "forward, torques on a slider": (str(folder / "forward_rpr.toml"), None),
            "control, tree with a slider": (str(folder / "control_rpr.toml"), None),
            "control, closed chain": ("five_bar_type1_track_x", 41)}


@pytest.mark.parametrize("kind", ["inverse, tree with a slider",
                                  "inverse, closed chain driven at its slider",
                                  "forward, zero torque", "forward, torques on a slider",
                                  "control, tree with a slider", "control, closed chain"])
def test_series_are_the_csv_and_carry_the_coordinates_units(studies, kind, tmp_path):
    study, samples = studies[kind]
    result = ps.run_study(study, samples)
    robot = robot_of(load_study(study))
    (csv,) = write(result, tmp_path, plot=False)
    header, table = read_csv(csv)
    assert header == [s.column for s in result.data] == list(result.columns)
    for k, s in enumerate(result.data):
        assert same_bits(table[:, k], s.values), s.column  # 17 digits: the very values
        assert s.unit == expected_unit(robot, s), s.column
        assert (s.index is None) or 0 <= s.index < robot.n
    assert result.get("t").values[0] == 0.0
    # one series per coordinate for q; tau on the actuated ones (forward: with inputs only)
    assert [s.index for s in result.series("q")] == list(range(robot.n))
    taus = [s.index for s in result.series("tau")]
    assert taus == ([] if kind == "forward, zero torque" else list(robot.actuated))
    if "slider" in kind:
        assert "m" in {s.unit for s in result.series("q")}
        assert "N" in {s.unit for s in result.series("tau")}
    for s in result.series("p"):  # the power each actuator delivers: tau qd, in W
        assert same_bits(s.values, result.get("tau", s.index).values
                         * result.get("qd", s.index).values)
    if kind.startswith("control"):
        for i in robot.actuated:
            e = result.get("e", i)
            assert np.array_equal(e.values, result.get("q_ref", i).values
                                  - result.get("q", i).values)
            assert result.get("tau_cmd", i).unit == result.get("tau", i).unit
    if kind == "control, tree with a slider":  # the figure, drawn from the series' units
        fig = figure(result)
        assert [ax.get_ylabel() for ax in fig.axes[:3]] == ["q1 (deg)", "q2 (mm)", "q3 (deg)"]
        assert np.array_equal(fig.axes[1].lines[1].get_ydata(), result.get("q", 1).values * 1e3)
        legend = [text.get_text() for text in fig.axes[4].get_legend().get_texts()]
        assert legend == ["tau1 (N*m)", "tau2 (N)", "tau3 (N*m)"]


def test_a_sliders_peak_force_in_newtons_from_the_series():
    """serial_rpr's boom (q2) is prismatic: its peak is a force in N, the others in N*m; each
    peak equals the inverse dynamics recomputed from the result's own q, qd, qdd series."""
    result = ps.run_study("serial_rpr_tool_move", 41)
    robot = ps.load("serial_rpr")
    q, qd, qdd = (np.column_stack([result.get(kind, i).values for i in range(robot.n)])
                  for kind in ("q", "qd", "qdd"))
    tau = robot.inverse_dynamics(q, qd, qdd)
    peaks = result.peak_torques_with_units()
    assert list(peaks) == ["tau1", "tau2", "tau3"]
    assert [unit for _, unit in peaks.values()] == ["N*m", "N", "N*m"]
    for k, (peak, _) in enumerate(peaks.values()):
        assert peak == pytest.approx(np.max(np.abs(tau[:, k])), rel=1e-12)
    assert result.peak_torques() == {k: v for k, (v, _) in peaks.items()}
    force = result.get("tau", 1)
    assert force.column == "tau2_n" and force.stem == "tau2"
    assert list(result.torques()) == ["tau1_n_m", "tau2_n", "tau3_n_m"]
    assert list(result.angles()) == ["q1_rad", "q2_m", "q3_rad"]
    # the figure draws the series: the boom's force axis in N, its values the series'
    fig = figure(result)
    assert [ax.get_ylabel() for ax in fig.axes[:3]] == [
        "torque tau1 (N*m)", "force tau2 (N)", "torque tau3 (N*m)"]
    assert np.array_equal(fig.axes[1].lines[0].get_ydata(), force.values)
    loads = [line.get_label() for line in fig.axes[3].lines]
    assert loads == [s.joint for s in result.series("jload")] == ["shoulder", "extend", "wrist"]


def test_a_closed_chains_slider_force_and_cut_forces():
    result = ps.run_study("slider_crank_slider_driven_stroke", 21)
    robot = ps.load("slider_crank_slider_driven")
    ((k, (peak, unit)),) = result.peak_torques_with_units().items()
    (i,) = robot.actuated
    assert robot.coordinate_units[i] == "m" and unit == "N" and k == f"tau{i + 1}"
    assert peak == np.max(np.abs(result.get("tau", i).values))
    for loop in robot.loops:
        assert result.get("fx", joint=loop).unit == result.get("fy", joint=loop).unit == "N"


def test_accessors_and_refusals():
    t = np.linspace(0.0, 1.0, 3)
    res = Result("r", "one", [Series("t", "s", t), Series("fx", "N", t, joint="C")], "torques")
    assert isinstance(res.data, tuple) and res.columns == {"t_s": t, "fx_C_n": t}
    assert res.get("fx", joint="C").values is t and res.series("tau") == ()
    with pytest.raises(KeyError, match=r"no series of 'tau' in this result \(its quantities: t, "
                                        r"fx\)"):
        res.get("tau", 1)
    with pytest.raises(InputError, match="two series are named 't_s'"):
        Result("r", "one", [Series("t", "s", t), Series("t", "s", t)], "torques")
    with pytest.raises(InputError, match="unknown unit 'furlong'"):
        Series("x", "furlong", t)
    for s, name in [(Series("tau_cmd", "N", t, index=1), "tau_cmd2_n"),
                    (Series("q_ref", "m", t, index=0), "q1_ref_m"),
                    (Series("qd_ref", "rad/s", t, index=2), "qd3_ref_rad_s"),
                    (Series("qdd", "rad/s^2", t, index=0), "qdd1_rad_s2"),
                    (Series("jm", "N*m", t, joint="A"), "jm_A_n_m"),
                    (Series("e_task", "mm", t), "e_task_mm"), (Series("phi", "rad", t), "phi_rad"),
                    (Series("p", "W", t, index=3), "p4_w"), (Series("balance", "J", t), "balance_j")]:
        assert s.column == name


# -- one type for every run --------------------------------------------------------------------
@pytest.fixture(scope="module")
def rpr_runs():
    robot = ps.load("serial_rpr")
    t = np.linspace(0.0, 0.2, 21)
    free = ps.simulate(robot, robot.q_drawn, [0.1, -0.05, 0.2], (0.0, 0.2), t_eval=t,
                       torque=[0.05, 1.5, -0.01])
    ref = ps.inverse_kinematics(robot, ps.cubic([0.6928, 0.6, np.pi / 2],
                                                 [0.5928, 0.6, np.pi / 2], 0.2, t))
    ctl = controller("pd", kp=[400.0, 2000.0, 5.0], kd=[40.0, 200.0, 0.5], width=3)
    run = simulate_controlled(robot, ctl, (0.0, 0.2), reference=ref, t_eval=t)
    return robot, free, run, ref


def test_open_loop_and_controlled_runs_are_one_type(rpr_runs):
    _, free, run, ref = rpr_runs
    assert ControlledRun is Simulation and type(free) is type(run) is Simulation
    assert not free.controlled and run.controlled
    assert free.q_ref is None and free.error is None
    assert free.balance_residual < 1e-8  # energy gained = tau . (q - q0), exactly the work
    assert free.stopped is None and run.stopped is None
    assert run.balance_residual < 1e-9
    assert np.array_equal(run.error, run.q_ref - run.q)
    np.testing.assert_allclose(run.q_ref, ref.q, rtol=0, atol=1e-9)
    base = ["t_s", "q1_rad", "q2_m", "q3_rad", "qd1_rad_s", "qd2_m_s", "qd3_rad_s"]
    taus = ["tau1_n_m", "tau2_n", "tau3_n_m"]
    energies = ["kinetic_j", "potential_j", "energy_j"]
    assert list(free.columns()) == base + taus + energies
    assert list(run.columns()) == (base + ["q1_ref_rad", "q2_ref_m", "q3_ref_rad",
                                           "qd1_ref_rad_s", "qd2_ref_m_s", "qd3_ref_rad_s",
                                           "tau_cmd1_n_m", "tau_cmd2_n", "tau_cmd3_n_m"]
                                   + taus + energies + ["work_j", "friction_j"])
    cols = run.columns()
    assert same_bits(cols["tau_cmd2_n"], run.tau_cmd[:, 1])
    assert same_bits(cols["q2_ref_m"], run.q_ref[:, 1]) and cols["work_j"] is run.work_j
    assert run.get("tau", 1).unit == "N" and run.get("qd_ref", 1).unit == "m/s"
    # no friction on this arm: the actuators' work is the energy the plant gained
    assert run.work_j[0] == 0.0 and np.all(run.friction_j == 0.0)
    gained = run.energy_j - run.energy_j[0]
    assert np.max(np.abs(run.work_j - gained)) < 1e-9 * np.max(np.abs(run.work_j))
    meta = run.metadata()
    assert meta["controller"] == "pd" and meta["events"] == "" and meta["robot"] == "serial_rpr"
    assert "controller" not in free.metadata()


@pytest.mark.parametrize("which", ["open loop", "controlled"])
def test_columns_round_trip_through_npz_bit_for_bit(rpr_runs, which, tmp_path):
    _, free, run, _ = rpr_runs
    sim = free if which == "open loop" else run
    path = sim.save_npz(tmp_path / f"{which}.npz")
    columns, meta = load_npz(path)
    want = sim.columns()
    assert list(columns) == list(want) and meta == sim.metadata()
    assert all(same_bits(columns[k], v) for k, v in want.items())
    assert all(same_bits(want[s.column], s.values) for s in sim.series())


def test_sundials_open_loop_has_the_columns_of_any_open_loop_run():
    robot = ps.load("serial_2dof")
    t = np.linspace(0.0, 0.3, 7)
    runs = [ps.simulate(robot, [-1.0, 0.2], [0.0, 0.0], (0.0, 0.3), t_eval=t, torque=[0.1, 0.0],
                        method=m) for m in ("dopri5", "cvodes")]
    assert [type(r) for r in runs] == [Simulation, Simulation]
    assert list(runs[0].columns()) == list(runs[1].columns())
    assert runs[1].controller is None and runs[1].tau_cmd is None
    # the engine's work integral and the free path's exact tau . (q - q0) (constant torque)
    np.testing.assert_allclose(runs[1].work_j, runs[0].work_j, atol=1e-8)
    assert runs[0].work_j[-1] != 0.0 and np.all(runs[0].friction_j == 0.0)
    np.testing.assert_allclose(runs[1].q, runs[0].q, atol=1e-7)


# -- sweeps: typed figures ---------------------------------------------------------------------
def test_run_figures_by_value_and_type():
    st = load_study("serial_2dof_cartesian_track")
    robot = robot_of(st)
    figs = run_figures(st, robot)
    res = run_on(st, robot)
    for i in robot.actuated:
        err = np.max(np.abs(res.get("q_ref", i).values - res.get("q", i).values))
        (fig,) = [f for f in figs if (f.statistic, f.quantity, f.index) == ("max_abs", "e", i)]
        assert figs[fig] == err and fig.unit == "rad" and fig.name == f"max_abs_e{i + 1}_rad"
        tau = res.get("tau", i).values
        assert figs[Figure.of("peak", "tau", "N*m", i)] == np.max(np.abs(tau))
    work = res.get("work").values
    assert figs[Figure.of("final", "work", "J")] == work[-1]
    energy = res.get("energy").values
    (change,) = [f for f in figs if f.quantity == "energy"]
    assert figs[change] == energy[-1] - energy[0] and change.label == "energy_change (J)"


def test_a_sweeps_columns_are_typed():
    from planar_sym.outputs.sweep_plots import label, sweep_figure

    result = ps.sweep("serial_rpr_tool_move", {"m_boom": [1.0, 2.0]}, workers=1)
    assert result.info["peak_tau2_n"].unit == "N" and result.info["peak_tau1_n_m"].unit == "N*m"
    assert result.info["m_boom_kg"].unit == "kg" and set(result.info) == set(result.columns)
    st = load_study("serial_rpr_tool_move")
    for k, boom in enumerate((1.0, 2.0)):  # each design's peak force from its run's series
        res = run_on(st, robot_of(st).with_parameters(m_boom=boom))
        assert result.columns["peak_tau2_n"][k] == pytest.approx(
            np.max(np.abs(res.get("tau", 1).values)), rel=1e-12)
    fig = sweep_figure(result)  # the peak torques by default, labelled from their units
    assert [ax.get_ylabel() for ax in fig.axes] == ["peak_tau1 (N*m)", "peak_tau2 (N)",
                                                    "peak_tau3 (N*m)"]
    assert fig.axes[-1].get_xlabel() == label(result, "m_boom_kg") == "m_boom (kg)"


def test_a_control_figure_shows_the_passive_joints_a_full_state_law_tracks():
    """The cart-pole swing-up's figure showed only the cart (user trial): a coordinate with a
    tracking error series (a full-state law's passive one) gets its own panel, said passive,
    with the actuated ones'; the torque axis label fits its panel."""
    import matplotlib

    matplotlib.use("Agg")
    from planar_sym.outputs.plots import control_figure

    t = np.linspace(0.0, 1.0, 5)
    data = [Series("t", "s", t), Series("q", "m", t, index=0), Series("q", "rad", -t, index=1),
            Series("q_ref", "m", t, index=0), Series("e", "m", 0 * t, index=0),
            Series("e", "rad", 0 * t, index=1), Series("tau", "N", t, index=0),
            Series("tau_cmd", "N", t, index=0)]
    fig = control_figure(Result("r", "swing", data, "control", actuated=(0,)))
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert labels == ["q1 (mm)", "q2 (deg), passive", "error q_ref - q",
                      "torque (-- commanded)"], labels
    np.testing.assert_allclose(fig.axes[1].lines[0].get_ydata(), np.degrees(-t), rtol=1e-15)


def test_a_figure_of_an_untitled_study_names_it_once():
    """A study without a title has its name as its summary: the figure said 'swing' twice
    (user trial)."""
    import matplotlib

    matplotlib.use("Agg")
    from planar_sym.outputs.plots import figure

    t = np.linspace(0.0, 1.0, 3)
    data = [Series("t", "s", t), Series("q", "rad", t, index=0), Series("tau", "N*m", t, index=0)]
    assert figure(Result("swing", "swing", data, "angles"))._suptitle.get_text() == "swing"
    assert figure(Result("swing", "A pendulum", data, "angles"))._suptitle.get_text() == (
        "swing\nA pendulum")
