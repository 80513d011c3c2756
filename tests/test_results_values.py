"""Typed series (``planar_sym.dynamics.series``) and the run result (``dynamics.run_result``),
called directly, by value: the survivors of mutation testing of both modules.

- column names made from a quantity, a unit, a coordinate or a joint, written out by hand
  (``fx_C_n``, ``q2_ref_m``); the refusal of an unknown unit word for word, its list of known
  units written out here, not read from the module's table;
- ``one``: the series selected by joint among several joints' series; the KeyError's words for
  none, for several, for a joint, for an index and a joint together, "none" when the quantity
  has no series at all;
- a ``Simulation`` made by hand (2 coordinates, the second a slider; 3 samples): its series
  and columns hold the hand-written arrays in their units; ``series``/``get`` select by index
  and by joint (a run has no joint series: asking for one is a KeyError); ``tau`` on every
  coordinate when it has n columns even if fewer are actuated, on the actuated ones when it
  has as many columns as they; the refusals of a 1-D ``tau``, of a ``tau`` of neither width
  and of a run without coordinate units, word for word;
- ``metadata``: the whole dict, open loop and controlled, written out by hand (a controlled
  run's events joined with "; " in the words of ``Event``), and the DataFrame (columns, bits,
  ``attrs``) and NPZ it gives;
- real runs of serial_2dof: under constant torques the energy gained is the work
  tau . (q(T) - q(0)) (power balance), the columns read back from a DataFrame and an NPZ are
  the run's arrays bit for bit; a controlled run that crosses two joint limits carries both
  events in its metadata.
"""

from __future__ import annotations

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.control import controller, simulate_controlled
from planar_sym.dynamics.columns import load_npz
from planar_sym.dynamics.events import Event
from planar_sym.dynamics.run_result import Simulation
from planar_sym.dynamics.series import Series, column_name, column_stem, one, select
from planar_sym.errors import InputError
from planar_sym.motion.signals import Signal

#: the units a series may have, written out here (not read from the module)
KNOWN = "s, rad, m, mm, rad/s, m/s, rad/s^2, m/s^2, N*m, N, W, J, rpm"


def same_bits(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


# -- series.py --------------------------------------------------------------------------------

def test_column_names_of_joints_and_coordinates():
    assert column_name("fx", "N", joint="C") == "fx_C_n"
    assert column_name("jm", "N*m", None, "A") == "jm_A_n_m"
    assert column_name("q_ref", "m", index=1) == "q2_ref_m"
    assert column_name("qd", "rad/s", 0) == "qd1_rad_s"
    assert column_name("t", "s") == "t_s"
    assert column_name("speed", "rpm", joint="motor") == "speed_motor_rpm"
    assert column_stem("fy", joint="D") == "fy_D" and column_stem("qd_ref", 2) == "qd3_ref"
    assert Series("fx", "N", np.zeros(2), joint="C").column == column_name("fx", "N", joint="C")


def test_unknown_unit_refused_word_for_word():
    with pytest.raises(InputError) as exc:
        column_name("x", "furlong")
    assert str(exc.value) == f"unknown unit 'furlong' of 'x'; known: {KNOWN}"
    with pytest.raises(InputError) as exc:
        column_name("tau", "lbf", index=0)
    assert str(exc.value) == f"unknown unit 'lbf' of 'tau'; known: {KNOWN}"
    with pytest.raises(InputError) as exc:
        Series("x", "furlong", np.zeros(3))
    assert str(exc.value) == f"unknown unit 'furlong' of 'x'; known: {KNOWN}"


@pytest.fixture()
def mixed():
    t = np.array([0.0, 0.5, 1.0])
    return (Series("t", "s", t), Series("q", "rad", t * 2.0, index=0),
            Series("q", "m", t * 3.0, index=1), Series("fx", "N", t + 1.0, joint="C"),
            Series("fx", "N", t + 2.0, joint="D"), Series("fy", "N", t + 3.0, joint="C"))


def test_one_selects_by_joint(mixed):
    fx_c = one(mixed, "fx", joint="C")
    assert fx_c is mixed[3] and np.array_equal(fx_c.values, [1.0, 1.5, 2.0])
    assert one(mixed, "fx", None, "D") is mixed[4]
    assert one(mixed, "q", 1) is mixed[2] and one(mixed, "q", 1).column == "q2_m"
    assert select(mixed, "fx", joint="D") == (mixed[4],)
    assert select(mixed, joint="C") == (mixed[3], mixed[5])


NAME_ONE = "name one with index= (the 0-based coordinate number) or joint="
HINT = ("(index is the 0-based coordinate number: a coordinate missing here has no {!r}, as a "
        "passive joint has no torque)")
FX_HAVE = "fx_C_n (joint 'C'), fx_D_n (joint 'D')"
Q_HAVE = "q1_rad (index 0), q2_m (index 1)"


@pytest.mark.parametrize("args, words", [
    (("fx",), f"2 series of 'fx': {NAME_ONE} ({FX_HAVE})"),
    (("fx", None, "E"), f"no series of 'fx' with joint='E'; 'fx' has {FX_HAVE}"),
    (("q",), f"2 series of 'q': {NAME_ONE} ({Q_HAVE})"),
    (("q", 0, "C"), f"no series of 'q' with index=0 and joint='C' {HINT.format('q')}; 'q' has {Q_HAVE}"),
    (("q", 2), f"no series of 'q' with index=2 {HINT.format('q')}; 'q' has {Q_HAVE}"),
    (("tau", 1), "no series of 'tau' in this result (its quantities: t, q, fx, fy)"),
    (("fy", 0, "C"), (f"no series of 'fy' with index=0 and joint='C' {HINT.format('fy')}; 'fy' "
                     "has fy_C_n (joint 'C')")),
])
def test_one_refuses_word_for_word(mixed, args, words):
    """A refusal is an InputError (a message, not a traceback, on the command line) and a
    KeyError, and prints as its words (a KeyError alone prints them quoted)."""
    with pytest.raises(InputError) as exc:
        one(mixed, *args)
    assert isinstance(exc.value, KeyError) and str(exc.value) == words
    assert exc.value.args == (words,)


# -- run_result.py: a Simulation made by hand ------------------------------------------------

T = np.array([0.0, 0.1, 0.2])
Q = np.array([[0.1, 0.2], [0.3, 0.4], [0.5, 0.6]])
QD = np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]])
KIN = np.array([1.0, 2.0, 3.0])
POT = np.array([0.5, -0.25, 4.0])


def hand(**kw) -> Simulation:
    """2 coordinates (a revolute one in rad, a slider in m), the slider actuated; 3 samples."""
    base = {"t_s": T, "q": Q, "qd": QD, "tau": np.array([[0.0, 7.0], [0.0, 8.0], [0.0, 9.0]]),
            "kinetic_j": KIN, "potential_j": POT, "method": "dopri5", "rtol": 1e-9,
            "atol": 2.5e-12, "n_rhs": 321, "constraint_drift_m": 3e-15, "robot": "hand_rp",
            "coordinate_units": ("rad", "m"), "actuated": (1,)}
    base.update(kw)
    return Simulation(**base)


def controlled(**kw) -> Simulation:
    return hand(tau=np.array([[7.0], [8.0], [9.0]]), q_ref=np.array([[0.25], [0.5], [0.75]]),
                qd_ref=np.array([[2.5], [2.5], [2.5]]), tau_cmd=np.array([[7.5], [8.5], [9.5]]),
                work_j=np.array([0.0, 1.0, 2.0]), friction_j=np.array([0.0, 0.5, 1.5]),
                controller=controller("pd", 100.0, 10.0, width=1),
                events=(Event("joint q2 reached its upper limit 0.6 m", 0.15, False),
                        Event("actuator q2 beyond 9 N", 0.2, True)), **kw)


def test_open_loop_series_and_columns_by_hand():
    sim = hand()
    cols = sim.columns()
    assert list(cols) == ["t_s", "q1_rad", "q2_m", "qd1_rad_s", "qd2_m_s", "tau1_n_m", "tau2_n",
                          "kinetic_j", "potential_j", "energy_j"]
    assert np.array_equal(cols["q2_m"], [0.2, 0.4, 0.6])
    assert np.array_equal(cols["qd1_rad_s"], [1.0, 3.0, 5.0])
    assert np.array_equal(cols["tau1_n_m"], [0.0, 0.0, 0.0])  # the passive joint's
    assert np.array_equal(cols["tau2_n"], [7.0, 8.0, 9.0])
    assert np.array_equal(cols["energy_j"], [1.5, 1.75, 7.0])
    assert [(s.quantity, s.index, s.unit) for s in sim.series("tau")] == [
        ("tau", 0, "N*m"), ("tau", 1, "N")]
    assert [s.unit for s in sim.series(index=1)] == ["m", "m/s", "N"]


def test_series_and_get_select_by_index_and_joint():
    sim = hand()
    (q2,) = sim.series("q", 1)
    assert q2.column == "q2_m" and np.array_equal(q2.values, [0.2, 0.4, 0.6])
    assert [s.column for s in sim.series(None, 0)] == ["q1_rad", "qd1_rad_s", "tau1_n_m"]
    assert sim.series("q", joint="A") == () and sim.series(joint="C") == ()
    assert sim.series("q", 0, "A") == ()
    assert sim.get("qd", 1).unit == "m/s" and np.array_equal(sim.get("qd", 1).values, QD[:, 1])
    with pytest.raises(KeyError) as exc:
        sim.get("q", 0, joint="A")
    assert exc.value.args == ((f"no series of 'q' with index=0 and joint='A' {HINT.format('q')}; "
                              f"'q' has {Q_HAVE}"),)
    with pytest.raises(KeyError) as exc:
        sim.get("energy", joint="C")
    assert exc.value.args == ("no series of 'energy' with joint='C'; 'energy' has energy_j",)


def test_tau_on_the_actuated_coordinates_only():
    sim = controlled()
    taus = sim.series("tau")
    assert [(s.index, s.column) for s in taus] == [(1, "tau2_n")]
    assert np.array_equal(taus[0].values, [7.0, 8.0, 9.0])
    # n columns on a run whose actuated coordinates are fewer still means every coordinate
    assert [s.index for s in hand(actuated=()).series("tau")] == [0, 1]


def test_controlled_columns_by_hand():
    cols = controlled().columns()
    assert list(cols) == ["t_s", "q1_rad", "q2_m", "qd1_rad_s", "qd2_m_s", "q2_ref_m",
                          "qd2_ref_m_s", "tau_cmd2_n", "tau2_n", "kinetic_j", "potential_j",
                          "energy_j", "work_j", "friction_j"]
    assert np.array_equal(cols["tau_cmd2_n"], [7.5, 8.5, 9.5])
    assert np.array_equal(cols["friction_j"], [0.0, 0.5, 1.5])
    np.testing.assert_allclose(controlled().error, [[0.05], [0.1], [0.15]], rtol=0, atol=1e-15)


def test_refusals_word_for_word():
    with pytest.raises(InputError) as exc:
        hand(coordinate_units=()).series()
    assert str(exc.value) == (
        "this Simulation does not know its 2 coordinates' units (made without a robot): use "
        "planar_sym.simulate's result, or dataclasses.replace(sim, coordinate_units=('rad', "
        "'m', ...))")
    with pytest.raises(InputError) as exc:
        hand(tau=np.array([7.0, 8.0, 9.0])).series()  # 1-D: no columns at all
    assert str(exc.value) == "tau has 0 columns, neither the 2 coordinates nor the 1 actuated ones"
    with pytest.raises(InputError) as exc:
        hand(tau=np.zeros((3, 3))).columns()
    assert str(exc.value) == "tau has 3 columns, neither the 2 coordinates nor the 1 actuated ones"
    with pytest.raises(InputError) as exc:
        hand(tau=np.zeros((3, 1)), actuated=()).get("q", 0)
    assert str(exc.value) == "tau has 1 columns, neither the 2 coordinates nor the 0 actuated ones"


def test_metadata_by_hand():
    assert hand().metadata() == {"robot": "hand_rp", "method": "dopri5", "rtol": "1e-09",
                                 "atol": "2.5e-12", "n_rhs": "321",
                                 "constraint_drift_m": "3e-15", "writer": "planar-sym"}
    meta = controlled().metadata()
    assert meta == {"robot": "hand_rp", "method": "dopri5", "rtol": "1e-09", "atol": "2.5e-12",
                    "n_rhs": "321", "constraint_drift_m": "3e-15", "writer": "planar-sym",
                    "controller": "pd",
                    "events": "joint q2 reached its upper limit 0.6 m at t = 0.15 s; "
                              "actuator q2 beyond 9 N at t = 0.2 s (run stopped)"}
    assert list(meta) == ["robot", "method", "rtol", "atol", "n_rhs", "constraint_drift_m",
                          "writer", "controller", "events"]


@pytest.mark.parametrize("make", [hand, controlled])
def test_dataframe_and_npz_of_a_hand_made_run(make, tmp_path):
    pytest.importorskip("pandas")
    sim = make()
    df = sim.to_dataframe()
    assert list(df.columns) == list(sim.columns())
    assert df.attrs == sim.metadata() and df.attrs["writer"] == "planar-sym"
    assert df.attrs["n_rhs"] == "321" and df.attrs["robot"] == "hand_rp"
    assert df.shape == (3, len(sim.columns()))
    assert same_bits(df["q2_m"].to_numpy(), Q[:, 1])
    assert same_bits(df["energy_j"].to_numpy(), np.array([1.5, 1.75, 7.0]))
    assert same_bits(df["t_s"].to_numpy(), T)
    columns, meta = load_npz(sim.save_npz(tmp_path / "run.npz"))
    assert meta == dict(df.attrs) and list(columns) == list(df.columns)
    assert all(same_bits(columns[k], df[k].to_numpy()) for k in columns)


# -- real runs ---------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def pushed():
    robot = ps.load("serial_2dof")
    t = np.linspace(0.0, 0.4, 9)
    return ps.simulate(robot, [-1.0, 0.2], [0.3, -0.1], (0.0, 0.4), t_eval=t,
                       torque=[0.4, -0.15], rtol=1e-11, atol=1e-12)


def test_constant_torques_power_balance(pushed):
    """Under constant torques, the work int tau . qd dt is tau . (q(T) - q(0)): what the
    energy gained."""
    sim = pushed
    tau = np.array([0.4, -0.15])
    assert sim.get("tau", 0).unit == "N*m" and np.all(sim.get("tau", 0).values == 0.4)
    assert np.all(sim.get("tau", 1).values == -0.15)
    q = np.column_stack([sim.get("q", i).values for i in range(2)])
    work = (q - q[0]) @ tau
    gained = sim.get("energy").values - sim.get("energy").values[0]
    assert np.max(np.abs(work)) > 1e-3  # the torques did do work
    np.testing.assert_allclose(gained, work, rtol=0, atol=1e-8)
    assert same_bits(sim.get("energy").values,
                     sim.get("kinetic").values + sim.get("potential").values)
    assert sim.get("q", 0).values[0] == -1.0 and sim.get("qd", 1).values[0] == -0.1


def test_a_real_runs_metadata_and_tables(pushed, tmp_path):
    pytest.importorskip("pandas")
    sim = pushed
    assert sim.metadata() == {"robot": "serial_2dof", "method": "dopri5", "rtol": "1e-11",
                              "atol": "1e-12", "n_rhs": str(sim.n_rhs),
                              "constraint_drift_m": "0.0", "writer": "planar-sym"}
    assert sim.n_rhs > 9
    df = sim.to_dataframe()
    assert list(df.columns) == ["t_s", "q1_rad", "q2_rad", "qd1_rad_s", "qd2_rad_s",
                                "tau1_n_m", "tau2_n_m", "kinetic_j", "potential_j", "energy_j"]
    assert same_bits(df["q2_rad"].to_numpy(), sim.q[:, 1])
    assert same_bits(df["qd1_rad_s"].to_numpy(), sim.qd[:, 0])
    assert same_bits(df["potential_j"].to_numpy(), sim.potential_j)
    assert df.attrs == sim.metadata()
    columns, meta = load_npz(sim.save_npz(tmp_path / "pushed.npz"))
    assert meta == df.attrs and same_bits(columns["t_s"], np.linspace(0.0, 0.4, 9))


def test_a_controlled_run_reports_both_limit_crossings():
    """serial_2dof held at q = 0 by a soft PD loop, released with joint 2 0.5 rad off: joint 1
    is thrown up through 0.05 rad, joint 2 swings down through -0.3 rad; both are events."""
    robot = ps.load("serial_2dof")
    ref = Signal(np.array([0.0, 0.2]), np.array([[[0.0], [0.0]]]))
    ctl = controller("pd", 0.5, 0.001, width=2)
    run = simulate_controlled(robot, ctl, (0.0, 0.2), reference=ref, q0=[0.0, 0.5],
                              qd0=[0.0, 0.0],
                              joint_limits={"joint1": (-0.05, 0.05), "joint2": (-0.3, 0.51)},
                              on_joint_limit="continue", t_eval=np.linspace(0.0, 0.2, 11))
    upper, lower = run.events
    assert upper.name == "joint joint1 reached its upper limit 0.05 rad (2.86479 deg)"
    assert lower.name == "joint joint2 reached its lower limit -0.3 rad (-17.1887 deg)"
    assert 0.0 < upper.time_s < lower.time_s < 0.2 and not (lower.stopped or upper.stopped)
    meta = run.metadata()
    assert meta["controller"] == "pd"
    assert meta["events"] == (f"{upper.name} at t = {upper.time_s:.6g} s; "
                              f"{lower.name} at t = {lower.time_s:.6g} s")
    assert run.balance_residual < 1e-8
