"""Values the analysis modules' other tests left unchecked (issue 30, mutation testing of
planar_sym/analysis/): each against something independent of the code under test, a closed form
(numpy's linspace, meshgrid and default_rng for a design space, the trapezoidal rule written out
for an RMS), a second route (a design's own Robot, ``dynamics.sizing`` of one run) or a number
worked out by hand in the test."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.analysis import designs
from planar_sym.analysis.designs import DesignSpace, design_space, unit_suffix
from planar_sym.errors import InputError

#: serial_2dof's parameters, in the manifest's order, and their SI units
ARM_KNOWN = ("g, m_link1, izz_link1, cgx_link1, m_motor2, izz_motor2, m_link2, izz_link2, "
             "cgx_link2, px_link1_CS2, px_link2_CS2")
TIED = " (or names tied together)"
ARM_NAMES = ["g", "m_link1", "izz_link1", "cgx_link1", "m_motor2", "izz_motor2", "m_link2",
             "izz_link2", "cgx_link2", "px_link1_CS2", "px_link2_CS2"]


@pytest.fixture(scope="module")
def arm():
    return ps.load("serial_2dof")


# -- designs.py --------------------------------------------------------------------------------
def test_unit_suffixes_by_hand():
    assert unit_suffix("kg*m^2") == "kg_m2"
    assert unit_suffix("m/s^2") == "m_s2"
    assert unit_suffix("N*m*s/rad") == "n_m_s_rad"
    assert unit_suffix("KG") == "kg"
    assert unit_suffix("1") == "1"
    assert unit_suffix("") == "1"  # a pure number with no unit written


def test_a_grid_is_every_combination_first_key_slowest(arm):
    """Two keys, one of them two tied parameters given as "a, b": the grid is numpy's
    meshgrid (indexing "ij": the first key varies slowest) of linspace's ends-included
    values; the tied parameters share their key's column; the rest of each P row is the
    robot's own vector."""
    space = design_space(arm, {"m_link2": (0.05, 0.08, 4),
                               " px_link1_CS2 , px_link2_CS2": [0.09, 0.11]})
    assert isinstance(space, DesignSpace) and space.sample == "grid" and len(space) == 8
    assert space.names == ("m_link2", "px_link1_CS2", "px_link2_CS2")
    assert space.units == ("kg", "m", "m")
    m = np.linspace(0.05, 0.08, 4)
    want = np.array([[mi, li, li] for mi in m for li in (0.09, 0.11)])
    np.testing.assert_array_equal(space.values, want)
    assert space.P.shape == (8, len(ARM_NAMES)) and space.P.flags["C_CONTIGUOUS"]
    for k, name in enumerate(ARM_NAMES):
        col = space.P[:, k]
        if name in space.names:
            np.testing.assert_array_equal(col, want[:, space.names.index(name)])
        else:
            np.testing.assert_array_equal(col, np.full(8, arm.parameters[name]))
    cols = space.columns()
    assert list(cols) == ["m_link2_kg", "px_link1_CS2_m", "px_link2_CS2_m"]
    for k, c in enumerate(cols.values()):
        np.testing.assert_array_equal(c, want[:, k])
    # a tuple of names is the same tie
    tied = design_space(arm, {"m_link2": (0.05, 0.08, 4),
                              ("px_link1_CS2", "px_link2_CS2"): [0.09, 0.11]})
    np.testing.assert_array_equal(tied.P, space.P)


def test_a_random_sample_is_numpys_uniform_draws(arm):
    """count designs, each key's column drawn by default_rng(seed).uniform(low, high, count)
    in the keys' order; a numpy integer count is a count."""
    space = design_space(arm, {"m_link2": (0.05, 0.1), "g": (1.0, 9.0)}, sample="random",
                         count=np.int64(5), seed=11)
    rng = np.random.default_rng(11)
    m, g = rng.uniform(0.05, 0.1, 5), rng.uniform(1.0, 9.0, 5)
    assert space.sample == "random" and len(space) == 5
    np.testing.assert_array_equal(space.values, np.column_stack([m, g]))
    np.testing.assert_array_equal(space.P[:, 6], m)
    np.testing.assert_array_equal(space.P[:, 0], g)
    one = design_space(arm, {"m_link2": (0.05, 0.1)}, sample="random", count=1)
    assert len(one) == 1 and one.values[0, 0] == np.random.default_rng(0).uniform(0.05, 0.1, 1)[0]


@pytest.mark.parametrize("vary, kwargs, message", [
    ({"m_link2": [0.1]}, {"sample": "grids"}, "sample must be 'grid' or 'random' (got 'grids')"),
    ({}, {}, "vary must name at least one parameter: {name: values}"),
    ([("m_link2", [0.1])], {}, "vary must name at least one parameter: {name: values}"),
    ({"m_lnk2": [0.1], "izz_lnk2": [1e-4]}, {},
     "unknown parameters 'm_lnk2', 'izz_lnk2' of serial_2dof; known: " + ARM_KNOWN),
    ({"m_lnk2": [0.1]}, {}, "unknown parameter 'm_lnk2' of serial_2dof; known: " + ARM_KNOWN),
    ({"m_link2": [0.1], "m_link2, g": [0.1]}, {}, "parameter 'm_link2' is varied twice in vary"),
    ({"": [0.1]}, {}, "vary: '' is not a parameter name (or names tied together)"),
    ({"m_link2,": [0.1]}, {}, "vary: 'm_link2,' is not a parameter name" + TIED),
    ({(): [0.1]}, {}, "vary: () is not a parameter name" + TIED),
    ({("m_link2", 3): [0.1]}, {}, "vary: ('m_link2', 3) is not a parameter name" + TIED),
    ({"m_link2": ["a"]}, {}, ("vary['m_link2'] must be numbers: a list of values, (low, high, "
     "count) or, for a random sample, (low, high); got ['a']")),
    ({"m_link2": [[0.1], [0.2, 0.3]]}, {}, ("vary['m_link2'] must be numbers: a list of values, "
     "(low, high, count) or, for a random sample, (low, high); got [[0.1], [0.2, 0.3]]")),
    ({"m_link2": [0.1, math.nan]}, {}, "vary['m_link2'] must be finite (got [0.1, nan])"),
    ({"m_link2": (0.1, math.inf, 3)}, {}, "vary['m_link2'] must be finite (got (0.1, inf, 3))"),
    ({"m_link2": (0.05, 0.1, 3)}, {"sample": "random", "count": 2},
     "vary['m_link2']: a random sample needs (low, high) with low < high (got (0.05, 0.1, 3))"),
    ({"m_link2": (0.1, 0.1)}, {"sample": "random", "count": 2},
     "vary['m_link2']: a random sample needs (low, high) with low < high (got (0.1, 0.1))"),
    ({"m_link2": (0.05, 0.1)}, {}, ("vary['m_link2']: a grid range is (low, high, count) with "
     "low < high and an integer count >= 2 (got (0.05, 0.1)); or give the values as a list")),
    ({"m_link2": (0.05, 0.1, 3, 4)}, {},
     ("vary['m_link2']: a grid range is (low, high, count) with low < high and an integer "
     "count >= 2 (got (0.05, 0.1, 3, 4)); or give the values as a list")),
    ({"m_link2": (0.1, 0.1, 3)}, {},
     ("vary['m_link2']: a grid range is (low, high, count) with low < high and an integer "
     "count >= 2 (got (0.1, 0.1, 3)); or give the values as a list")),
    ({"m_link2": (0.05, 0.1, 2.5)}, {},
     ("vary['m_link2']: a grid range is (low, high, count) with low < high and an integer "
     "count >= 2 (got (0.05, 0.1, 2.5)); or give the values as a list")),
    ({"m_link2": (0.05, 0.1, 1)}, {},
     ("vary['m_link2']: a grid range is (low, high, count) with low < high and an integer "
     "count >= 2 (got (0.05, 0.1, 1)); or give the values as a list")),
    ({"m_link2": []}, {}, "vary['m_link2'] has no values"),
    ({"m_link2": [0.05, 0.1]}, {"sample": "random", "count": 3},
     ("vary['m_link2']: a random sample draws between two bounds: give (low, high) as a tuple "
     "(got the list [0.05, 0.1])")),
    ({"m_link2": (0.05, 0.1)}, {"sample": "random", "count": 0},
     "a random sample needs a count of designs >= 1 (got 0)"),
    ({"m_link2": (0.05, 0.1)}, {"sample": "random", "count": 2.0},
     "a random sample needs a count of designs >= 1 (got 2.0)"),
    ({"m_link2": [0.05]}, {"count": 1},
     "count is for random samples; a grid has every combination"),
    ({"px_link1_CS2, px_link2_CS2": (0.1, 0.05, 3)}, {},
     ("vary['px_link1_CS2,px_link2_CS2']: a grid range is (low, high, count) with low < high and "
     "an integer count >= 2 (got (0.1, 0.05, 3)); or give the values as a list")),
])
def test_each_malformed_design_space_has_its_own_message(arm, vary, kwargs, message):
    with pytest.raises(InputError) as err:
        design_space(arm, vary, **kwargs)
    assert str(err.value) == message


def test_a_grid_of_two_values_is_its_ends(arm):
    """The smallest grid range: count 2 is allowed, and gives low and high exactly."""
    space = design_space(arm, {"m_link2": (0.05, 0.1, 2)})
    np.testing.assert_array_equal(space.values[:, 0], [0.05, 0.1])


def test_the_memory_limit_is_on_the_parameter_vectors_bytes(arm, monkeypatch):
    """8 bytes per design and parameter: 3 designs of 11 parameters take 264 bytes, allowed at
    a limit of exactly 264, refused at 263 with the size (in GB) and the limit."""
    monkeypatch.setattr(designs, "MEMORY_LIMIT_BYTES", 264.0)
    assert len(design_space(arm, {"m_link2": [0.05, 0.06, 0.07]})) == 3
    assert len(design_space(arm, {"m_link2": (0.05, 0.1)}, sample="random", count=3)) == 3
    monkeypatch.setattr(designs, "MEMORY_LIMIT_BYTES", 263.0)
    with pytest.raises(InputError) as err:
        design_space(arm, {"m_link2": [0.05, 0.06, 0.07]})
    assert str(err.value) == ("3 designs of 11 parameters would take 2.64e-07 GB for their "
                              "parameter vectors alone (limit 2.63e-07 GB): fewer values per "
                              "parameter, or a random sample")
    with pytest.raises(InputError, match="3 designs of 11 parameters"):
        design_space(arm, {"m_link2": (0.05, 0.1)}, sample="random", count=3)


def test_a_non_physical_design_is_named_with_its_values_and_count(arm):
    """The first failing design of the grid (m_link2 slowest, then g): m_link2 = -0.02 with
    g = 1 is design 2 (designs 0, 1 have m_link2 = -0.05); 4 of 6 designs fail."""
    with pytest.raises(InputError) as err:
        design_space(arm, {"m_link2": [0.05, -0.02, -0.01], "g": [1.0, 2.0]})
    msg = str(err.value)
    assert msg.startswith("design 2 (m_link2 = -0.02, g = 1) is not physical: parameter m_link2 "
                          "must be > 0 kg")
    assert msg.endswith(" (4 of 6 designs are not); narrow the range")


def test_a_unit_slip_is_warned_once_per_parameter_with_its_ends(arm):
    """Both ends of m_link1 are slips (60 and 70 'kg'): one warning for it; the slip of
    m_link2 is its larger end only (the range printed low to high as given unordered); an
    izz slip at the small end; a parameter in range says nothing."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        design_space(arm, {"m_link1": [70.0, 60.0], "m_link2": [50.0, 0.05],
                           "izz_link2": [1e-4, 1e-12], "g": [9.0, 9.81]})
    msgs = [str(w.message) for w in caught]
    assert all(w.category is RuntimeWarning for w in caught)
    assert len(msgs) == 3, msgs
    assert msgs[0].startswith("sweep range m_link1 from 60 to 70: parameter m_link1 = 60 kg "
                              "(read in kg) is more than osmium")
    assert msgs[1].startswith("sweep range m_link2 from 0.05 to 50: parameter m_link2 = 50 kg")
    assert msgs[2].startswith("sweep range izz_link2 from 1e-12 to 0.0001: parameter izz_link2 "
                              "= 1e-12 kg*m^2")
    assert all(m.endswith(" (sweeps take SI units)") for m in msgs)


# -- figures.py --------------------------------------------------------------------------------
def test_a_figure_is_named_from_its_fields():
    from planar_sym.analysis.figures import COND, ENERGY_CHANGE, Figure, named, parameter_figure

    f = Figure.of("peak", "tau", "N*m", 1)
    assert (f.name, f.stem, f.unit, f.statistic, f.quantity, f.index, f.joint) == (
        "peak_tau2_n_m", "peak_tau2", "N*m", "peak", "tau", 1, None)
    assert f.label == "peak_tau2 (N*m)"
    cut = Figure.of("peak", "fx", "N", joint="C")
    assert (cut.name, cut.stem, cut.index, cut.joint) == ("peak_fx_C_n", "peak_fx_C", None, "C")
    assert Figure("max_cond_phi_p", "max_cond_phi_p").label == "max_cond_phi_p"
    assert Figure("gear_joint1_1", "gear_joint1", "1").label == "gear_joint1_1"
    assert (COND.name, COND.unit, COND.statistic, COND.quantity) == (
        "max_cond_phi_p", "", "max", "cond_phi_p")
    assert (ENERGY_CHANGE.name, ENERGY_CHANGE.stem, ENERGY_CHANGE.unit, ENERGY_CHANGE.statistic,
            ENERGY_CHANGE.quantity) == ("energy_change_j", "energy_change", "J", "change",
                                        "energy")
    p = parameter_figure("izz_link2", "kg*m^2", "plant_")
    assert (p.name, p.stem, p.unit, p.statistic, p.quantity, p.label) == (
        "plant_izz_link2_kg_m2", "plant_izz_link2", "kg*m^2", "", "izz_link2",
        "plant_izz_link2 (kg*m^2)")
    assert parameter_figure("m_link2", "kg").name == "m_link2_kg"
    values, kinds = named({f: 1.5, cut: 2.5})
    assert values == {"peak_tau2_n_m": 1.5, "peak_fx_C_n": 2.5}
    assert kinds == {"peak_tau2_n_m": f, "peak_fx_C_n": cut}


def test_a_figure_of_a_series_takes_its_fields():
    from planar_sym.analysis.figures import Figure
    from planar_sym.dynamics.series import Series

    s = Series("tau", "N", np.zeros(3), index=1)
    assert Figure.of_series("rms", s) == Figure("rms_tau2_n", "rms_tau2", "N", "rms", "tau", 1)
    cut = Series("fy", "N", np.zeros(3), joint="B2")
    assert Figure.of_series("peak", cut) == Figure("peak_fy_B2_n", "peak_fy_B2", "N", "peak",
                                                   "fy", None, "B2")


# -- sweep_figures.py --------------------------------------------------------------------------
def test_torque_figures_of_a_closed_chain_from_hand_made_statistics():
    """parallel_3rrr: actuated coordinates 0, 3, 5; two cuts (B2, B3); the C loop's
    components are the 3 actuated torques, fx, fy of B2, fx, fy of B3, then the condition
    number: each peak max(-min, max), each RMS sqrt(mean square), the condition its max."""
    from planar_sym.analysis.figures import COND
    from planar_sym.analysis.sweep_figures import torque_figures

    robot = ps.load("parallel_3rrr")
    rng = np.random.default_rng(4)
    stats = np.empty((5, 8, 3))
    stats[..., 0] = -rng.uniform(0, 2, (5, 8))
    stats[..., 1] = rng.uniform(0, 2, (5, 8))
    stats[..., 2] = rng.uniform(0, 2, (5, 8))
    figs = {f.name: v for f, v in torque_figures(robot, stats, True).items()}
    want = {}
    for k, i in enumerate((0, 3, 5)):
        want[f"peak_tau{i + 1}_n_m"] = np.maximum(-stats[:, k, 0], stats[:, k, 1])
        want[f"rms_tau{i + 1}_n_m"] = np.sqrt(stats[:, k, 2])
    for c, name in enumerate(("peak_fx_B2_n", "peak_fy_B2_n", "peak_fx_B3_n", "peak_fy_B3_n")):
        want[name] = np.maximum(-stats[:, 3 + c, 0], stats[:, 3 + c, 1])
    want[COND.name] = stats[:, 7, 1]
    assert list(figs) == list(want)
    for name, v in want.items():
        np.testing.assert_array_equal(figs[name], v, err_msg=name)


def test_torque_figures_of_a_tree_with_a_slider():
    """serial_rpr: every coordinate actuated, the slider's in N; no cuts, no condition."""
    from planar_sym.analysis.sweep_figures import torque_figures

    robot = ps.load("serial_rpr")
    stats = np.arange(2 * 3 * 3, dtype=float).reshape(2, 3, 3) - 7.0
    stats[..., 2] = np.abs(stats[..., 2])  # mean squares
    figs = {f.name: v for f, v in torque_figures(robot, stats, False).items()}
    assert list(figs) == ["peak_tau1_n_m", "rms_tau1_n_m", "peak_tau2_n", "rms_tau2_n",
                          "peak_tau3_n_m", "rms_tau3_n_m"]
    np.testing.assert_array_equal(figs["peak_tau2_n"], [4.0, 6.0])  # max(-min, max) = (4, 6)
    np.testing.assert_array_equal(figs["rms_tau3_n_m"], np.sqrt([1.0, 10.0]))


def test_singular_designs_are_those_past_the_limit_numbered_from_start():
    from planar_sym.analysis.figures import COND, Figure
    from planar_sym.analysis.sweep_figures import singular_designs
    from planar_sym.model.loops import COND_LIMIT

    cond = np.array([10.0, COND_LIMIT, np.nextafter(COND_LIMIT, np.inf), np.nan, 3e7])
    found = singular_designs({COND: cond}, 100)
    assert list(found) == [102, 103, 104]
    assert found[104] == ("singular pose on the move: the passive-joint constraint Jacobian "
                          "Phi_p has condition number 3e+07 > 1e+06")
    assert singular_designs({Figure("x", "x"): cond}, 0) == {}


def test_run_figures_are_the_runs_columns_reduced():
    """A 5-bar's inverse-dynamics run (cut forces) and its controlled run (tracking errors,
    work, friction, energy), each figure against numpy on the study's own columns."""
    from planar_sym.analysis.sweep_figures import run_figures
    from planar_sym.study.run import load_study, robot_of

    for study in ("five_bar_type1_move_x", "five_bar_type1_track_x"):
        st = load_study(study)
        figs = {f.name: v for f, v in run_figures(st, robot_of(st)).items()}
        c = ps.run_study(st).columns
        want = {}
        for k in (1, 3):
            want[f"peak_tau{k}_n_m"] = np.max(np.abs(c[f"tau{k}_n_m"]))
            t = c["t_s"]  # the RMS over time, by the trapezoidal rule
            want[f"rms_tau{k}_n_m"] = np.sqrt(np.trapezoid(c[f"tau{k}_n_m"] ** 2, t) / t[-1])
        if "track" in study:
            want["max_abs_e_task_mm"] = np.max(np.abs(c["e_task_mm"]))
            for k in (1, 3):
                want[f"max_abs_e{k}_rad"] = np.max(np.abs(c[f"e{k}_rad"]))
            want["energy_change_j"] = c["energy_j"][-1] - c["energy_j"][0]
            want["final_work_j"] = c["work_j"][-1]
            want["final_friction_j"] = c["friction_j"][-1]
        else:
            want["peak_fx_C_n"] = np.max(np.abs(c["fx_C_n"]))
            want["peak_fy_C_n"] = np.max(np.abs(c["fy_C_n"]))
        assert sorted(figs) == sorted(want), study
        for name, v in want.items():
            assert figs[name] == pytest.approx(v, rel=1e-12, abs=1e-15), (study, name)
            assert type(figs[name]) is float


def test_atlas_figures_carry_their_units():
    """The summary's numbers as figures: areas in m^2, the acceleration in m/s^2, the time
    in s, the rest pure numbers (a bool as 0 or 1); its lists and labels left out."""
    from planar_sym.analysis.atlas import atlas
    from planar_sym.analysis.sweep_figures import atlas_figures

    robot = ps.load("serial_2dof")
    figs = atlas_figures(robot, {"points": 9, "q_start": [0.0, 1.0]})
    summary = atlas(robot, points=9, q_start=[0.0, 1.0]).summary()
    by = {f.name: (f, v) for f, v in figs.items()}
    assert set(by) == {k for k, v in summary.items()
                       if isinstance(v, (bool, int, float)) and k != "robot"}
    for name, (stem, unit) in {"area_m2": ("area", "m^2"), "accel_m_s2": ("accel", "m/s^2"),
                               "time_s": ("time", "s"),
                               "area_same_assembly_m2": ("area_same_assembly", "m^2")}.items():
        assert (by[name][0].stem, by[name][0].unit) == (stem, unit)
    f, v = by["type2_inside"]
    assert (f.stem, f.unit) == ("type2_inside", "") and v == 0.0 and type(v) is float
    assert by["area_m2"][1] == summary["area_m2"] and by["cells"][1] == 81.0
    assert by["accel_m_s2"][1] == 1.0


# -- sweep_motor.py ----------------------------------------------------------------------------
def test_trapezoid_weights_are_the_trapezoidal_rule():
    from planar_sym.dynamics.sizing import rms_weights as _trapezoid_weights

    t = np.array([0.0, 0.1, 0.35, 0.4, 1.0])
    v = np.array([1.0, -2.0, 0.5, 3.0, -1.0])
    w = _trapezoid_weights(t)
    by_hand = sum((t[k + 1] - t[k]) * (v[k] ** 2 + v[k + 1] ** 2) / 2 for k in range(4)) / 1.0
    assert w @ v**2 == pytest.approx(by_hand, rel=1e-15)
    np.testing.assert_allclose(w, [0.05, 0.175, 0.15, 0.325, 0.3], rtol=1e-15)
    # shifted in time, the same weights; one sample: its own square
    np.testing.assert_allclose(_trapezoid_weights(t + 2.0), w, rtol=1e-14)
    np.testing.assert_array_equal(_trapezoid_weights(np.array([0.3])), [1.0])


def test_drives_and_gear_ratios_per_actuator():
    """has_drives: any actuator modelled; gear_ratios: the design's gear_<joint> column where
    the robot has that parameter, else the drive's own ratio."""
    from types import SimpleNamespace as NS

    from planar_sym.analysis.sweep_motor import gear_ratios, has_drives

    assert not has_drives(ps.load("serial_2dof"))
    geared = ps.load(ps.__file__.rsplit("/planar_sym/", 1)[0] + "/examples/serial_2dof_geared.toml")
    assert has_drives(geared)
    one = NS(drive_train=NS(drives=[NS(modelled=False), NS(modelled=True)]))
    assert has_drives(one)
    names = [p.name for p in geared.parameter_list]
    P = np.tile(geared.p, (3, 1))
    P[:, names.index("gear_joint1")] = [10.0, 20.0, 30.0]
    P[:, names.index("gear_joint2")] = [7.0, 8.0, 9.0]
    np.testing.assert_array_equal(gear_ratios(geared, P), [[10, 7], [20, 8], [30, 9]])
    np.testing.assert_array_equal(gear_ratios(ps.load("serial_2dof"), np.zeros((2, 11))),
                                  np.ones((2, 2)))
    mixed = NS(parameter_list=[NS(name="g"), NS(name="gear_b")], actuated=(0, 2),
               drive_train=NS(drives=[NS(joint="a", gear_ratio=12.0),
                                      NS(joint="b", gear_ratio=99.0)]))
    np.testing.assert_array_equal(gear_ratios(mixed, np.array([[9.8, 40.0], [9.8, 41.0]])),
                                  [[12.0, 40.0], [12.0, 41.0]])


def test_motor_figure_names():
    from planar_sym.analysis.sweep_motor import motor_figure_keys, peak_torque

    assert [f.name for f in motor_figure_keys(1)] == [
        "peak_motor_tau2_n_m", "rms_motor_tau2_n_m", "peak_motor_speed2_rpm", "peak_power2_w"]
    assert [(f.statistic, f.quantity, f.unit, f.index) for f in motor_figure_keys(0)] == [
        ("peak", "motor_tau", "N*m", 0), ("rms", "motor_tau", "N*m", 0),
        ("peak", "motor_speed", "rpm", 0), ("peak", "power", "W", 0)]
    rpr = ps.load("serial_rpr")
    assert peak_torque(rpr, 1).name == "peak_tau2_n" and peak_torque(rpr, 2).name == "peak_tau3_n_m"


# -- sweep_result.py ---------------------------------------------------------------------------
def test_a_sweep_table_as_csv_by_hand(tmp_path):
    from planar_sym.analysis.sweep_result import SweepResult

    cols = {"m_link2_kg": np.array([0.05, 0.1, 0.15]),
            "peak_tau1_n_m": np.array([1.0 / 3.0, np.nan, -np.inf])}
    res = SweepResult("s", cols, ("m_link2_kg",), ("m_link2",), {1: 'no "reach"'})
    assert len(res) == 3 and res.figures == ("peak_tau1_n_m",)
    assert res.csv_text() == ('m_link2_kg,peak_tau1_n_m,error\n'
                              '0.05,0.333333333333,""\n'
                              '0.1,,"no \'reach\'"\n'
                              '0.15,,""\n')
    clean = SweepResult("s", cols, ("m_link2_kg",))
    assert clean.csv_text().splitlines() == ["m_link2_kg,peak_tau1_n_m", "0.05,0.333333333333",
                                             "0.1,", "0.15,"]
    path = clean.write_csv(tmp_path / "t.csv")
    assert path == tmp_path / "t.csv" and path.read_text() == clean.csv_text()


# -- sweep_plant.py ----------------------------------------------------------------------------
def test_a_designs_plant_table_and_the_note(arm):
    """plant_overrides: exactly the parameters where the plant differs, SI with SI units;
    on_note: what was varied where, and the held values the other set keeps."""
    from types import SimpleNamespace as NS

    from planar_sym.analysis.sweep_plant import on_note, parameter_index, plant_overrides

    assert parameter_index(arm, "g") == 0 and parameter_index(arm, "px_link2_CS2") == 10
    p = arm.p.copy()
    plant = p.copy()
    plant[6], plant[7] = 0.09, 2e-4
    assert plant_overrides(arm, p, plant) == {"m_link2": (0.09, "kg"),
                                              "izz_link2": (2e-4, "kg*m^2")}
    assert plant_overrides(arm, p, p.copy()) == {}
    space = design_space(arm, {"m_link2": [0.06, 0.08], "g": [9.0]})
    st = NS(control=NS(plant={"izz_link2": (2e-4, "kg*m^2")}))
    plant_P = np.tile(plant, (2, 1))
    assert on_note(st, arm, space, plant_P, "both") == (
        "m_link2, g varied on the controller's model and the plant")
    st_m = NS(control=NS(plant={"m_link2": (0.09, "kg"), "g": (9.5, "m/s^2")}))
    assert on_note(st_m, arm, space, plant_P, "both") == (
        "m_link2, g varied on the controller's model and the plant ([control.plant]'s "
        "m_link2, g replaced by the design's)")
    plant_P[:, 0] = 9.5
    assert on_note(st, arm, space, plant_P, "model") == (
        "m_link2, g varied on the controller's model only: the plant keeps m_link2 = 0.09 kg, "
        "g = 9.5 m/s^2")
    model = NS(names=space.names, P=np.tile(arm.p, (2, 1)))
    assert on_note(st, arm, model, plant_P, "plant") == (
        "m_link2, g varied on the plant only: the controller's model keeps m_link2 = 0.075 kg, "
        "g = 9.81 m/s^2")


def test_plant_designs_draw_the_same_random_designs_on_either_set(tmp_path):
    """A random sample (seed 5, 3 designs) of the geared arm's tracking study: the designs are
    default_rng(5)'s draws whichever set they change, the other set keeps its own values."""
    from test_sweep_drive_plant import TRACK

    from planar_sym.analysis.sweep_plant import plant_designs
    from planar_sym.study.run import load_study, robot_of

    path = tmp_path / "track.toml"
    path.write_text(TRACK)
    st = load_study(path)
    robot = robot_of(st)
    k = [p.name for p in robot.parameter_list].index("m_link2")
    m = np.random.default_rng(5).uniform(0.05, 0.1, 3)
    model_p = np.tile(robot.p, (3, 1))
    plant_p = model_p.copy()
    plant_p[:, k] = 0.09  # the study's [control.plant]
    args = {"sample": "random", "count": 3, "seed": 5}
    space, plant_P = plant_designs(st, robot, {"m_link2": (0.05, 0.1)}, "model", control=True,
                                   **args)
    np.testing.assert_array_equal(space.values[:, 0], m)
    np.testing.assert_array_equal(space.P[:, k], m)
    np.testing.assert_array_equal(plant_P, plant_p)
    space, plant_P = plant_designs(st, robot, {"m_link2": (0.05, 0.1)}, "plant", control=True,
                                   **args)
    np.testing.assert_array_equal(space.P, model_p)
    np.testing.assert_array_equal(space.values[:, 0], np.full(3, 0.075))
    assert space.names == ("m_link2",) and space.units == ("kg",) and space.sample == "random"
    want = plant_p.copy()
    want[:, k] = m
    np.testing.assert_array_equal(plant_P, want)
    space, plant_P = plant_designs(st, robot, {"m_link2": (0.05, 0.1)}, "both", control=True,
                                   **args)
    np.testing.assert_array_equal(space.P[:, k], m)
    np.testing.assert_array_equal(plant_P, want)
    space, plant_P = plant_designs(st, robot, {"m_link2": (0.05, 0.1)}, "both", control=False,
                                   **args)
    assert plant_P is None
    np.testing.assert_array_equal(space.P[:, k], m)


# -- sweep.py ----------------------------------------------------------------------------------
S3 = "serial_2dof_cartesian_move"


@pytest.mark.parametrize("vary, kwargs, heard", [
    # shared motion: one batch per worker, 10 designs on 2 workers
    ({"m_link2": (0.05, 0.1, 10)}, {"workers": 2}, [(5, 10), (10, 10)]),
    # motion per design: four batches per worker, 10 designs on 1 worker (batches of 3)
    ({"px_link1_CS2": (0.09, 0.12, 10)}, {"workers": 1}, [(3, 10), (6, 10), (9, 10), (10, 10)]),
    # a batch of one design
    ({"m_link2": (0.05, 0.1, 3)}, {"workers": 1, "batch": 1}, [(1, 3), (2, 3), (3, 3)]),
    # a batch size given: 7 designs in batches of 3
    ({"m_link2": (0.05, 0.1, 7)}, {"workers": 1, "batch": np.int64(3)},
     [(3, 7), (6, 7), (7, 7)]),
    # at most FAST_BATCH designs per batch
    ({"m_link2": (0.05, 0.1, 4100)}, {"workers": 1}, [(4096, 4100), (4100, 4100)]),
])
def test_the_designs_are_split_into_batches_as_documented(vary, kwargs, heard):
    from planar_sym.analysis.sweep import sweep

    got = []
    res = sweep(S3, vary, progress=lambda done, total: got.append((done, total)), **kwargs)
    assert got == heard and not res.failed


def test_one_design_a_batch_at_least():
    """Two designs on two workers: a batch of one design each."""
    from planar_sym.analysis.sweep import sweep

    got = []
    sweep(S3, {"m_link2": [0.06, 0.07]}, workers=2, progress=lambda *a: got.append(a))
    assert got == [(1, 2), (2, 2)]


@pytest.mark.parametrize("kwargs, message", [
    ({"workers": 0}, "workers must be an integer >= 1 (got 0)"),
    ({"workers": 1.0}, "workers must be an integer >= 1 (got 1.0)"),
    ({"batch": 0}, "batch must be an integer >= 1 (got 0)"),
    ({"batch": "2"}, "batch must be an integer >= 1 (got '2')"),
    ({"on": None}, "on must be 'both', 'model' or 'plant' (got None)"),
])
def test_bad_workers_and_batches_are_refused(kwargs, message):
    from planar_sym.analysis.sweep import sweep

    with pytest.raises(InputError) as err:
        sweep(S3, {"m_link2": [0.06]}, **kwargs)
    assert str(err.value) == message


class _Refusing:
    """An executor that refuses to take its second batch (a closed pool), and runs the rest."""

    def __init__(self):
        self.calls = 0

    def submit(self, fn, *args):
        from concurrent.futures import Future

        self.calls += 1
        if self.calls == 2:
            raise RuntimeError("pool closed")
        fut = Future()
        fut.set_result(fn(*args))
        return fut


def test_a_refused_batch_is_lost_alone_and_said_once():
    from planar_sym.analysis.sweep import sweep

    got = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = sweep(S3, {"m_link2": (0.05, 0.1, 6)}, executor=_Refusing(), batch=2,
                    progress=lambda *a: got.append(a))
    assert got == [(2, 6), (4, 6), (6, 6)]
    assert res.failed == {2: "worker error: RuntimeError: pool closed",
                          3: "worker error: RuntimeError: pool closed"}
    lost = [w for w in caught if "lost" in str(w.message)]
    assert [str(w.message) for w in lost] == [
        ("2 of 6 designs were lost to worker errors (first: design 2, worker error: "
        "RuntimeError: pool closed); the other designs' figures are kept")]
    assert lost[0].category is RuntimeWarning
    assert res.note == "6 designs (grid), shared motion; 2 failed"
    assert res.study == S3 and res.route == "shared motion" and res.on == "both"
    whole = sweep(S3, {"m_link2": (0.05, 0.1, 6)})
    for name in res.figures:
        np.testing.assert_array_equal(res.columns[name][[0, 1, 4, 5]],
                                      whole.columns[name][[0, 1, 4, 5]])
        assert np.isnan(res.columns[name][[2, 3]]).all()


def test_a_non_physical_slider_design_is_named_in_the_sliders_unit():
    """tests/robots/rpr_geared.toml's boom is a screw-driven slider: its friction is in N*s/m
    and its gear in rad/m (the manifest's units), which the refusal names."""
    from pathlib import Path

    rpr = ps.load(Path(__file__).parent / "robots" / "rpr_geared.toml")
    with pytest.raises(InputError) as err:
        design_space(rpr, {"fv_extend": [1.0, -2.0]})
    assert str(err.value) == ("design 1 (fv_extend = -2) is not physical: parameter fv_extend "
                              "(viscous friction) must be >= 0 N*s/m (got -2) (1 of 2 designs "
                              "are not); narrow the range")
    with pytest.raises(InputError, match=r"gear_extend \(gear ratio\) must be > 0 rad/m"):
        design_space(rpr, {"gear_extend": [0.0]})


def test_values_may_be_one_number_or_nested(arm):
    """A single value, or values nested one level (a column), are the values flattened."""
    np.testing.assert_array_equal(design_space(arm, {"m_link2": 0.05}).values, [[0.05]])
    np.testing.assert_array_equal(design_space(arm, {"m_link2": [[0.05], [0.1]]}).values,
                                  [[0.05], [0.1]])


def test_every_problem_of_the_first_bad_design_is_named(arm):
    with pytest.raises(InputError) as err:
        design_space(arm, {"m_link2": [-0.05], "izz_link1": [-1e-4]})
    assert str(err.value) == (
        "design 0 (m_link2 = -0.05, izz_link1 = -0.0001) is not physical: parameter izz_link1 "
        "must be >= 0 kg*m^2 (got -0.0001); parameter m_link2 must be > 0 kg (got -0.05) (1 of 1 "
        "designs are not); narrow the range")


# -- atlas_grid.py -----------------------------------------------------------------------------
REACH = "(x in (-0.21, 0.21) m, y in (-0.21, 0.21) m): ranges are in m"
POINTS = "points must be an integer >= 2 per axis, or a pair (nx, ny) "
def test_the_reach_bound_in_closed_form():
    """serial_2dof: one leg of two 0.1 m links from the origin, R = 1.05 x 0.2 m; the Type II
    5-bar: two legs of 0.1 + 0.128 m (to P along the distal link) and 0.1 + 0.1 + 0.028 m,
    from A = 0 and E = (0.2, 0): the box is the intersection of their discs' boxes; a slider
    on every leg (serial_rpr): no bound."""
    from planar_sym.analysis.atlas_grid import REACH_MARGIN, reach

    assert REACH_MARGIN == 1.05
    box, R = reach(ps.load("serial_2dof"))
    np.testing.assert_allclose(box, [-0.21, 0.21, -0.21, 0.21], rtol=1e-14)
    assert R == pytest.approx(0.21, rel=1e-14)
    box, R = reach(ps.load("five_bar_type2"))
    r = 1.05 * 0.228
    np.testing.assert_allclose(box, [0.2 - r, r, -r, r], rtol=1e-12)
    assert R == pytest.approx(r, rel=1e-12)
    assert reach(ps.load("serial_rpr")) is None


def test_the_default_grid_of_the_arm(arm):
    from planar_sym.analysis.atlas_grid import make_grid

    g = make_grid(arm)
    assert g.shape == (1, 101, 101) and len(g.phi_rad) == 0
    np.testing.assert_allclose(g.x_m, np.linspace(-0.21, 0.21, 101), rtol=0, atol=1e-15)
    np.testing.assert_allclose(g.y_m, np.linspace(-0.21, 0.21, 101), rtol=0, atol=1e-15)
    assert g.length_scale_m == pytest.approx(0.21, rel=1e-14)
    np.testing.assert_allclose(g.reach_box_m, [-0.21, 0.21, -0.21, 0.21], rtol=1e-14)
    t = g.targets()
    assert t.shape == (101 * 101, 2)
    np.testing.assert_array_equal(t[:3], [[g.x_m[0], g.y_m[0]], [g.x_m[1], g.y_m[0]],
                                          [g.x_m[2], g.y_m[0]]])  # x fastest
    np.testing.assert_array_equal(t[101], [g.x_m[0], g.y_m[1]])


def test_a_step_and_points_on_a_given_region(arm):
    """A step that divides the range in exact arithmetic keeps its end (0.3 / 0.1 is
    2.9999999999999996 in floating point: still 4 points); points are numpy's linspace."""
    from planar_sym.analysis.atlas_grid import make_grid

    g = make_grid(arm, x_range=(0.0, 0.3), y_range=(-0.1, 0.0), step=0.1)
    np.testing.assert_allclose(g.x_m, [0.0, 0.1, 0.2, 0.3], rtol=0, atol=1e-16)
    np.testing.assert_allclose(g.y_m, [-0.1, 0.0], rtol=0, atol=1e-16)
    g = make_grid(arm, x_range=(0.0, 0.25), y_range=(-0.1, 0.05), step=0.1)
    np.testing.assert_allclose(g.x_m, [0.0, 0.1, 0.2], rtol=0, atol=1e-16)
    g = make_grid(arm, x_range=(-0.1, 0.1), y_range=(0.0, 0.2), points=(5, np.int64(3)),
                  length_scale=0.5)
    np.testing.assert_array_equal(g.x_m, np.linspace(-0.1, 0.1, 5))
    np.testing.assert_array_equal(g.y_m, np.linspace(0.0, 0.2, 3))
    assert g.length_scale_m == 0.5 and g.shape == (1, 3, 5)
    g = make_grid(arm, x_range=(-0.1, 0.1), y_range=(0.0, 0.2), points=4)
    assert g.shape == (1, 4, 4)


def test_orientations_and_an_unbounded_robot():
    """serial_rpr: no reach bound, so L_c is half the longer side; the orientations are
    sorted without repeats; phi0 is the one layer when none are given."""
    from planar_sym.analysis.atlas_grid import make_grid

    rpr = ps.load("serial_rpr")
    g = make_grid(rpr, x_range=(-0.6, 0.9), y_range=(-0.6, 0.5), points=3,
                  orientations=[1.5, 1.2, 1.5])
    np.testing.assert_array_equal(g.phi_rad, [1.2, 1.5])
    assert g.reach_box_m is None and g.length_scale_m == 0.75 and g.shape == (2, 3, 3)
    t = g.targets()
    assert t.shape == (18, 3)
    np.testing.assert_array_equal(t[0], [-0.6, -0.6, 1.2])
    np.testing.assert_array_equal(t[9], [-0.6, -0.6, 1.5])
    np.testing.assert_array_equal(t[4], [g.x_m[1], g.y_m[1], 1.2])
    g = make_grid(rpr, x_range=(-0.6, 0.9), y_range=(-0.6, 0.5), points=3, phi0=0.7)
    np.testing.assert_array_equal(g.phi_rad, [0.7])
    g = make_grid(rpr, x_range=(-0.6, 0.9), y_range=(-0.6, 0.5), points=3)  # phi0 = 0 rad
    np.testing.assert_array_equal(g.phi_rad, [0.0])
    g = make_grid(rpr, x_range=(-0.6, 0.9), y_range=(-0.6, 0.5), points=3, phi0=1)
    assert g.phi_rad.dtype == np.float64 and g.phi_rad.tolist() == [1.0]


@pytest.mark.parametrize("kwargs, message", [
    ({"x_range": (0.3, 0.4)}, ("serial_2dof: the region x_range = (0.3, 0.4) m, y_range = (-0.21, "
     "0.21) m lies outside the robot's reach (x in (-0.21, 0.21) m, y in (-0.21, 0.21) m): "
     "ranges are in m")),
    ({"x_range": (-0.4, -0.3)}, "serial_2dof: the region x_range = (-0.4, -0.3) m, y_range = "
     "(-0.21, 0.21) m lies outside the robot's reach " + REACH),
    ({"y_range": (0.3, 0.4)}, "serial_2dof: the region x_range = (-0.21, 0.21) m, y_range = "
     "(0.3, 0.4) m lies outside the robot's reach " + REACH),
    ({"y_range": (-0.4, -0.3)}, "serial_2dof: the region x_range = (-0.21, 0.21) m, y_range = "
     "(-0.4, -0.3) m lies outside the robot's reach " + REACH),
    ({"x_range": (0.0, 0.1), "y_range": (0.0, 0.1), "step": 0.2},
     "step = 0.2 m leaves fewer than 2 points along x (0 to 0.1 m): use a smaller step"),
    ({"x_range": (0.0, 0.3), "y_range": (0.0, 0.1), "step": 0.2},
     "step = 0.2 m leaves fewer than 2 points along y (0 to 0.1 m): use a smaller step"),
    ({"x_range": (0.0, 0.1, 0.2)}, ("x_range must be two numbers (min, max) in m (got (0.0, 0.1, "
     "0.2))")),
    ({"y_range": ("a", 0.1)}, "y_range must be two numbers (min, max) in m (got ('a', 0.1))"),
    ({"x_range": (np.nan, 0.1)}, "x_range = (nan, 0.1) m: both ends must be finite"),
    ({"x_range": (0.1, 0.1)}, "x_range = (0.1, 0.1) m: the minimum must be below the maximum"),
    ({"step": np.inf}, "step must be a positive length in m (got inf)"),
    ({"step": [0.1]}, "step must be a positive length in m (got [0.1])"),
    ({"step": 0.0}, "step must be a positive length in m (got 0.0)"),
    ({"points": 2.0}, "points must be an integer >= 2 per axis, or a pair (nx, ny) (got 2.0)"),
    ({"points": (3,)}, POINTS + "(got (3,))"),
    ({"points": (3, 4, 5)}, POINTS + "(got (3, 4, 5))"),
    ({"points": (3, 1)}, POINTS + "(got (3, 1))"),
    ({"length_scale": np.inf}, "length_scale must be a positive length in m (got inf)"),
    ({"length_scale": [0.1]}, "length_scale must be a positive length in m (got [0.1])"),
    ({"length_scale": -0.1}, "length_scale must be a positive length in m (got -0.1)"),
])
def test_each_bad_grid_has_its_message(arm, kwargs, message):
    from planar_sym.analysis.atlas_grid import make_grid

    with pytest.raises(InputError) as err:
        make_grid(arm, **kwargs)
    assert str(err.value) == message


def test_bad_orientations_are_named():
    from planar_sym.analysis.atlas_grid import make_grid

    rpr = ps.load("serial_rpr")
    for bad in ([], [0.1, np.inf]):
        with pytest.raises(InputError) as err:
            make_grid(rpr, x_range=(-0.6, 0.9), y_range=(-0.6, 0.5), points=3, orientations=bad)
        assert str(err.value) == f"orientations must be finite angles in rad (got {bad!r})"
    with pytest.raises(InputError) as err:
        make_grid(ps.load("serial_2dof"), orientations=[0.0])
    assert str(err.value) == ("orientations: serial_2dof has no orientation in its task (x, y): "
                              "leave them out")
    with pytest.raises(InputError) as err:
        make_grid(rpr)
    assert str(err.value) == ("serial_rpr: a slider on every leg to the task point leaves its "
                              "reach unbounded: give the region (x_range and y_range, m; --x and "
                              "--y, mm)")


def test_the_grids_memory_by_hand(arm, monkeypatch):
    """Per cell 8 bytes x (4 n + nt + 20 + 9 na) = 8 x 48 = 384 bytes for the arm (n = nt =
    na = 2): 100 cells take 3.84e-5 GB, allowed at that limit, refused just below it."""
    from planar_sym.analysis import atlas_grid
    from planar_sym.analysis.atlas_grid import make_grid

    need = 100 * 8 * 48 / 1e9
    monkeypatch.setattr(atlas_grid, "MEMORY_LIMIT_GB", need)
    assert make_grid(arm, points=10).shape == (1, 10, 10)
    monkeypatch.setattr(atlas_grid, "MEMORY_LIMIT_GB", need * (1 - 1e-12))
    with pytest.raises(InputError) as err:
        make_grid(arm, points=10)
    assert str(err.value) == ("serial_2dof: a grid of 100 points (10 x 10) would take 3.84e-05 GB "
                              "of memory (limit 3.84e-05 GB): use a larger step or fewer points")
    rpr = ps.load("serial_rpr")  # n = nt = na = 3: 8 x 62 bytes a cell, 2 layers of 5 x 4
    monkeypatch.setattr(atlas_grid, "MEMORY_LIMIT_GB", 40 * 8 * 62 / 1e9 * (1 - 1e-12))
    with pytest.raises(InputError) as err:
        make_grid(rpr, x_range=(-0.6, 0.9), y_range=(-0.6, 0.5), points=(5, 4),
                  orientations=[1.0, 2.0])
    assert "a grid of 40 points (5 x 4 x 2 orientations) would take 1.98e-05 GB" in str(err.value)


def test_the_memory_refusal_prints_bytes_over_1e9_as_gb(arm, monkeypatch):
    """14375 designs of 11 parameters are 1 265 000 bytes: 0.001265 GB, which the message
    rounds to 3 digits (0.00127: the double nearest 0.001265 lies above it); a limit of
    265 500.5 bytes is 0.0002655005 GB, 0.000265501 to 6 digits."""
    monkeypatch.setattr(designs, "MEMORY_LIMIT_BYTES", 265500.5)
    with pytest.raises(InputError) as err:
        design_space(arm, {"m_link2": (0.05, 0.1, 14375)})
    assert str(err.value) == ("1.44e+04 designs of 11 parameters would take 0.00127 GB for their "
                              "parameter vectors alone (limit 0.000265501 GB): fewer values per "
                              "parameter, or a random sample")


def test_motor_figures_of_a_closed_chain_against_each_designs_torques(monkeypatch):
    """The 5-bar (actuated coordinates 0 and 2, no actuator model: gear 1) along S5, five
    designs in chunks of two: each motor figure against the design's own Robot
    (with_parameters) and its closed-chain inverse dynamics, reduced here (the trapezoidal RMS
    over the span, rpm = rad/s x 60 / 2 pi, the power the largest |tau qd|)."""
    from planar_sym.analysis import sweep_motor
    from planar_sym.analysis.sweep_figures import torque_figures
    from planar_sym.study.motion import joint_motion
    from planar_sym.study.run import load_study

    monkeypatch.setattr(sweep_motor, "MOTOR_CHUNK", 2)
    robot = ps.load("five_bar_type1")
    jt, _ = joint_motion(load_study("five_bar_type1_move_x"), robot)
    q, qd, qdd, t = jt.q, jt.qd, jt.qdd, jt.t_s
    k_m = [p.name for p in robot.parameter_list].index("m_R_Link2")
    P = np.tile(robot.p, (5, 1))
    P[:, k_m] = np.linspace(0.03, 0.09, 5)
    fn = robot._closed_inverse_dynamics
    joint = torque_figures(robot, fn.designs(P, q, qd, qdd, reduce=True), True)
    figs = {f.name: v for f, v in sweep_motor.motor_figures(robot, fn, P, (q, qd, qdd), t,
                                                            joint).items()}
    assert sorted(figs) == sorted(f"{s}{i}_{u}" for i in (1, 3) for s, u in (
        ("peak_motor_tau", "n_m"), ("rms_motor_tau", "n_m"), ("peak_motor_speed", "rpm"),
        ("peak_power", "w")))
    for d in range(5):
        tau = robot.with_parameters(m_R_Link2=P[d, k_m]).closed_chain_inverse_dynamics(
            q, qd, qdd)[0]
        for k, i in enumerate((0, 2)):
            sq = tau[:, k] ** 2
            rms = np.sqrt(np.sum(np.diff(t) * (sq[1:] + sq[:-1]) / 2) / (t[-1] - t[0]))
            n = i + 1
            assert figs[f"peak_motor_tau{n}_n_m"][d] == pytest.approx(np.max(np.abs(tau[:, k])),
                                                                      rel=1e-12)
            assert figs[f"rms_motor_tau{n}_n_m"][d] == pytest.approx(rms, rel=1e-12)
            assert figs[f"peak_motor_speed{n}_rpm"][d] == pytest.approx(
                np.max(np.abs(qd[:, i])) * 60 / (2 * np.pi), rel=1e-14)
            assert figs[f"peak_power{n}_w"][d] == pytest.approx(
                np.max(np.abs(tau[:, k] * qd[:, i])), rel=1e-12)


def test_motor_figures_of_a_tree_take_the_actuated_coordinates_column():
    """A tree's inverse dynamics gives every coordinate's torque: the motor of actuated
    coordinate 1 (the only one, gear 4) takes column 1, not column 0 (a passive joint's
    100 N*m). Two designs, three samples at t = 0, 1, 3 s, by hand."""
    from types import SimpleNamespace as NS

    from planar_sym.analysis.sweep_motor import motor_figures, peak_torque

    robot = NS(is_closed_chain=False, actuated=(1,), coordinate_units=("rad", "rad"),
               parameter_list=[NS(name="g")], drive_train=NS(drives=[NS(joint="b",
                                                                        gear_ratio=4.0)]))
    tau = np.zeros((2, 3, 2))
    tau[..., 0] = 100.0
    tau[0, :, 1] = [1.0, -2.0, 3.0]
    tau[1, :, 1] = [0.5, 0.5, -4.0]
    fn = NS(designs=lambda P, q, qd, qdd: tau[:len(P)])
    q = np.zeros((3, 2))
    qd = np.array([[0.0, 1.0], [0.0, -3.0], [0.0, 2.0]])
    t = np.array([0.0, 1.0, 3.0])
    joint = {peak_torque(robot, 1): np.array([3.0, 4.0])}
    figs = {f.name: v for f, v in motor_figures(robot, fn, np.zeros((2, 1)), (q, qd, q), t,
                                                joint).items()}
    np.testing.assert_allclose(figs["peak_motor_tau2_n_m"], [0.75, 1.0], rtol=1e-15)
    # trapezoid over 3 s: design 0 (1 + 4) / 2 x 1 + (4 + 9) / 2 x 2 = 15.5, mean 15.5 / 3
    ms = np.array([(1 + 4) / 2 + (4 + 9), (0.25 + 0.25) / 2 + (0.25 + 16)]) / 3
    np.testing.assert_allclose(figs["rms_motor_tau2_n_m"], np.sqrt(ms) / 4, rtol=1e-15)
    np.testing.assert_allclose(figs["peak_motor_speed2_rpm"], [3.0 * 4 * 60 / (2 * np.pi)] * 2,
                               rtol=1e-15)
    np.testing.assert_allclose(figs["peak_power2_w"], [6.0, 8.0], rtol=1e-15)


# -- sweep_routes.py ---------------------------------------------------------------------------
def test_each_study_takes_its_route(arm):
    """An atlas; a simulation; an [optimise] study (its timing depends on the design's
    dynamics); a length that moves the task-space IK; a mass on the same move (the motion solved
    once: the study's own joint motion, shared)."""
    from planar_sym.analysis.sweep_routes import _route
    from planar_sym.study.motion import joint_motion
    from planar_sym.study.run import load_study, robot_of

    st = load_study(S3)
    mass = design_space(arm, {"m_link2": [0.06, 0.07]})
    length = design_space(arm, {"px_link1_CS2": [0.09, 0.1]})
    assert _route(st, arm, mass, {"points": 5}) == ("atlas", ())
    free = load_study("serial_2dof_free_swing")
    assert _route(free, robot_of(free), mass, None) == ("per design", ())
    fastest = load_study("serial_2dof_cartesian_fastest")
    assert _route(fastest, robot_of(fastest), mass, None) == ("per design", ())
    assert _route(st, arm, length, None) == ("motion per design", ())
    route, shared = _route(st, arm, mass, None)
    jt, _ = joint_motion(st, arm)
    assert route == "shared motion" and len(shared) == 4
    for got, want in zip(shared, (jt.q, jt.qd, jt.qdd, jt.t_s)):
        np.testing.assert_array_equal(got, want)


def test_torque_figures_of_a_five_bar_and_of_a_tree_with_a_passive_joint():
    """five_bar_type1: actuated 0 and 2, one cut (C): components tau1, tau3, fx_C, fy_C, cond
    (index 4 = 2 actuated + 2 loop equations). A tree's C loop reduces every coordinate: the
    figures of actuated coordinate 1 (the only one) come from component 1."""
    from types import SimpleNamespace as NS

    from planar_sym.analysis.figures import COND
    from planar_sym.analysis.sweep_figures import torque_figures

    stats = np.zeros((1, 5, 3))
    stats[0, :, 0] = [-1.0, -2.0, -3.0, -4.0, 1.0]
    stats[0, :, 1] = [0.5, 2.5, 1.0, 5.0, 7.0]
    stats[0, :, 2] = [4.0, 9.0, 16.0, 25.0, 36.0]
    figs = {f.name: v for f, v in torque_figures(ps.load("five_bar_type1"), stats, True).items()}
    assert figs == {"peak_tau1_n_m": [1.0], "rms_tau1_n_m": [2.0], "peak_tau3_n_m": [2.5],
                    "rms_tau3_n_m": [3.0], "peak_fx_C_n": [3.0], "peak_fy_C_n": [5.0],
                    COND.name: [7.0]}
    tree = NS(actuated=(1,), coordinate_units=("rad", "m"))
    stats = np.array([[[-9.0, 9.0, 81.0], [-1.0, 2.0, 2.25]]])
    figs = {f.name: v for f, v in torque_figures(tree, stats, False).items()}
    assert figs == {"peak_tau2_n": [2.0], "rms_tau2_n": [1.5]}


def test_a_bad_plant_is_named_by_its_study(tmp_path):
    """A [control.plant] value the physical rules refuse (set on a loaded study, past the
    file's own checks): the sweep names the study's file, or its name when it has none."""
    from dataclasses import replace

    from test_sweep_drive_plant import TRACK

    from planar_sym.analysis.sweep import sweep
    from planar_sym.study.run import load_study

    path = tmp_path / "track.toml"
    path.write_text(TRACK)
    st = load_study(path)
    bad = replace(st, control=replace(st.control, plant={"m_link2": (-0.09, "kg")}))
    for study, where in ((bad, str(path)), (replace(bad, path=None), "track")):
        with pytest.raises(InputError) as err:
            sweep(study, {"m_link2": [0.06]})
        assert str(err.value) == (f"{where}: control.plant: parameter m_link2 must be > 0 kg "
                                  "(got -0.09)")


def test_the_note_of_a_single_design_on_the_model(arm):
    from types import SimpleNamespace as NS

    from planar_sym.analysis.sweep_plant import on_note

    space = design_space(arm, {"m_link2": [0.06]})
    plant_P = np.tile(arm.p, (1, 1))
    plant_P[0, 6] = 0.09
    assert on_note(NS(control=NS(plant={})), arm, space, plant_P, "model") == (
        "m_link2 varied on the controller's model only: the plant keeps m_link2 = 0.09 kg")


# -- envelope_along.py -------------------------------------------------------------------------
def test_the_envelope_along_a_slider_arms_move():
    """serial_rpr's tool move (a tree with a slider and an orientation): the study's torques
    and task positions against its own run, tau = b + A xdd, and the envelope over the x-y
    plane in closed form, |b_k| + a ||A_k[x, y]||, at the angle of sign(b_k) A_k[x, y]; the
    table's columns with their units, and 5 samples spanning the same time."""
    from planar_sym.analysis.envelope_along import envelope_along

    study = "serial_rpr_tool_move"
    e = envelope_along(study, accel_m_s2=2.0)
    run = ps.run_study(study).columns
    assert (e.study, e.robot, e.accel_m_s2) == (study, "serial_rpr", 2.0)
    assert e.actuator_units == ("N*m", "N", "N*m") and e.task_names == ("x", "y", "phi")
    tau = np.column_stack([run["tau1_n_m"], run["tau2_n"], run["tau3_n_m"]])
    peak = np.max(np.abs(tau))
    np.testing.assert_allclose(e.tau_study, tau, rtol=0, atol=1e-12 * peak)
    np.testing.assert_allclose(e.t_s, run["t_s"], rtol=0, atol=0)
    np.testing.assert_allclose(e.x[:, :2] * 1e3, np.column_stack([run["x_mm"], run["y_mm"]]),
                               rtol=0, atol=1e-9)
    np.testing.assert_allclose(e.x[:, 2], run["phi_rad"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(e.b + np.einsum("nkj,nj->nk", e.A, e.xdd), tau, rtol=0,
                               atol=1e-9 * peak)
    Axy = e.A[..., :2]
    np.testing.assert_allclose(e.envelope, np.abs(e.b) + 2.0 * np.hypot(Axy[..., 0], Axy[..., 1]),
                               rtol=1e-12)
    s = np.where(e.b >= 0, 1.0, -1.0)
    angle = np.arctan2(s * Axy[..., 1], s * Axy[..., 0])
    np.testing.assert_allclose(np.cos(e.angle_rad - angle), 1.0, rtol=0, atol=1e-9)
    names, values = e.table()
    assert names == ["t_s", "x_mm", "y_mm", "phi_rad",
                     "tau1_n_m", "tau_b1_n_m", "tau_env1_n_m", "env_angle1_deg",
                     "tau2_n", "tau_b2_n", "tau_env2_n", "env_angle2_deg",
                     "tau3_n_m", "tau_b3_n_m", "tau_env3_n_m", "env_angle3_deg"]
    np.testing.assert_array_equal(values[:, 1], e.x[:, 0] * 1e3)
    np.testing.assert_array_equal(values[:, 3], e.x[:, 2])
    np.testing.assert_array_equal(values[:, 9], e.b[:, 1])
    np.testing.assert_array_equal(values[:, 10], e.envelope[:, 1])
    np.testing.assert_array_equal(values[:, 15], np.degrees(e.angle_rad[:, 2]))
    few = envelope_along(study, samples=5)
    assert len(few.t_s) == 5 and few.t_s[-1] == run["t_s"][-1] and few.accel_m_s2 == 1.0
    rest = envelope_along(study, accel_m_s2=0)
    np.testing.assert_array_equal(rest.envelope, np.abs(rest.b))


@pytest.mark.parametrize("study, accel, message", [
    ("serial_rpr_tool_move", -1.0, ("accel_m_s2 must be a finite acceleration >= 0 in m/s^2 "
                                   "(got -1.0)")),
    ("serial_rpr_tool_move", math.nan, ("accel_m_s2 must be a finite acceleration >= 0 in m/s^2 "
                                       "(got nan)")),
    ("serial_rpr_tool_move", [1.0], ("accel_m_s2 must be a finite acceleration >= 0 in m/s^2 "
                                    "(got [1.0])")),
    ("slider_crank_turn", 1.0, "slider_crank has no task point: no task acceleration to size"),
])
def test_an_envelope_that_cannot_be_sized_is_refused(study, accel, message):
    from planar_sym.analysis.envelope_along import envelope_along

    with pytest.raises(InputError) as err:
        envelope_along(study, accel_m_s2=accel)
    assert str(err.value) == message


def test_singular_designs_after_a_failed_one_are_named_and_emptied(monkeypatch):
    """The 5-bar's proximal links (both legs) from 0.05 to 0.125 m, in batches of 3: 0.05 m
    cannot reach the move's targets (design 1); with the condition limit lowered to 2.5 the
    designs whose worst conditioning passes it (2, 3, 4, 5: 2.63 to 3.81) fail as singular,
    by their own numbers, their figures NaN; design 0 (2.36) keeps its figures."""
    from planar_sym.analysis import sweep_figures
    from planar_sym.analysis.sweep import sweep

    vary = {("px_L_Link1_CS2", "px_R_Link1_CS2"): [0.09, 0.05, 0.1, 0.11, 0.12, 0.125]}
    whole = sweep("five_bar_type1_move_x", vary, batch=3, workers=1)
    assert list(whole.failed) == [1] and "outside the workspace" in whole.failed[1]
    cond = whole.columns["max_cond_phi_p"]
    monkeypatch.setattr(sweep_figures, "COND_LIMIT", 2.5)
    res = sweep("five_bar_type1_move_x", vary, batch=3, workers=1)
    assert list(res.failed) == [1, 2, 3, 4, 5] and res.failed[1] == whole.failed[1]
    for k in (2, 3, 4, 5):
        assert res.failed[k] == ("singular pose on the move: the passive-joint constraint "
                                 f"Jacobian Phi_p has condition number {cond[k]:.3g} > 2.5")
    assert res.note == "6 designs (grid), motion per design; 5 failed"
    for name in res.figures:
        assert res.columns[name][0] == whole.columns[name][0], name
        assert np.isnan(res.columns[name][1:]).all(), name


# -- atlas.py ----------------------------------------------------------------------------------
def hand_atlas(**over):
    """A 1 x 2 x 3 atlas made by hand (x = 0, 0.1, 0.2 m; y = 0, 0.05 m): cell (0, 2) out of
    reach, two actuators (N*m, N)."""
    from planar_sym.analysis.atlas import Atlas

    nan = np.nan
    reach = np.array([[[True, True, False], [True, True, True]]])
    fields = {
        "robot": "hand", "x_m": np.array([0.0, 0.1, 0.2]), "y_m": np.array([0.0, 0.05]),
        "phi_rad": np.array([]), "q": np.zeros((1, 2, 3, 2)), "reachable": reach,
        "same_assembly": np.array([[[True, False, False], [True, True, False]]]),
        "det_type1": np.ones((1, 2, 3)),
        "det_type2": np.array([[[1.0, 1.0, nan], [1.0, 1.0, 1.0]]]),
        "type1": np.array([[[0.5, 0.005, nan], [0.5, 0.5, 0.5]]]),
        "type2": np.array([[[0.5, 0.5, nan], [0.05, 0.005, 0.5]]]),
        "dexterity": np.array([[[0.4, 0.1, nan], [0.3, 0.2, 0.9]]]),
        "gravity": np.zeros((1, 2, 3, 2)), "envelope": np.zeros((1, 2, 3, 2)),
        "envelope_angle_rad": np.zeros((1, 2, 3, 2)), "accel_m_s2": 2.0, "start_pose": np.zeros(2),
        "length_scale_m": 0.2, "reach_box_m": None, "time_s": 0.25, "coordinates": ("a", "b"),
        "coordinate_units": ("rad", "m"), "actuated": (0, 1), "actuator_units": ("N*m", "N"),
        "task_names": ("x", "y")}
    g = fields["gravity"]
    g[0, 0, :, 0] = [1.0, -3.0, nan]
    g[0, 1, :, 0] = [2.0, -5.0, 0.5]
    g[0, :, :, 1] = [[nan, nan, nan], [nan, 4.0, nan]]
    env = fields["envelope"]
    env[0, 0, :, 0] = [2.0, 6.0, nan]
    env[0, 1, :, 0] = [3.0, 7.0, 1.0]
    env[0, ..., 1] = [[1.0, 9.0, nan], [2.0, 8.0, 3.0]]
    fields.update(over)
    return Atlas(**fields)


def test_an_atlas_summary_by_hand():
    """Cells 0.1 m x 0.05 m; 5 reachable (area 0.025 m^2), 3 in the start's assembly mode;
    dexterity 0.1 to 0.9, median 0.3; type2 below 0.01 at one cell of 5; the peaks over the
    reachable cells, and over the regular ones (type2 >= 0.1: cells (0, 0), (0, 1), (1, 2);
    for the envelope also type1 >= 0.01: (0, 0), (1, 2))."""
    s = hand_atlas().summary()
    assert hand_atlas().cell_area_m2 == pytest.approx(0.005, rel=1e-15)
    assert s["robot"] == "hand" and s["cells"] == 6 and s["reachable_cells"] == 5
    assert s["area_m2"] == pytest.approx(0.025, rel=1e-15)
    assert s["area_same_assembly_m2"] == pytest.approx(0.015, rel=1e-15)
    assert s["worst_dexterity"] == 0.1 and s["median_dexterity"] == 0.3
    assert s["type2_near_fraction"] == pytest.approx(0.2, rel=1e-15)
    assert s["type2_inside"] is False
    assert s["peak_gravity"] == [5.0, 4.0]
    assert s["peak_envelope"] == [7.0, 9.0]
    assert s["peak_gravity_regular"][0] == 3.0 and math.isnan(s["peak_gravity_regular"][1])
    assert s["peak_envelope_regular"] == [2.0, 3.0]
    assert s["actuator_units"] == ["N*m", "N"] and s["accel_m_s2"] == 2.0 and s["time_s"] == 0.25
    # with orientations, a cell is in the area if it is reached at any of them
    two = hand_atlas(reachable=np.concatenate([hand_atlas().reachable] * 2),
                     same_assembly=np.zeros((2, 2, 3), bool),
                     dexterity=np.concatenate([hand_atlas().dexterity] * 2),
                     type1=np.concatenate([hand_atlas().type1] * 2),
                     type2=np.concatenate([hand_atlas().type2] * 2),
                     det_type2=np.ones((2, 2, 3)),
                     gravity=np.concatenate([hand_atlas().gravity] * 2),
                     envelope=np.concatenate([hand_atlas().envelope] * 2))
    s2 = two.summary()
    assert s2["cells"] == 12 and s2["reachable_cells"] == 10
    assert s2["area_m2"] == pytest.approx(0.025, rel=1e-15) and s2["area_same_assembly_m2"] == 0.0
    empty = hand_atlas(reachable=np.zeros((1, 2, 3), bool)).summary()
    assert empty["area_m2"] == 0.0 and math.isnan(empty["worst_dexterity"])
    assert math.isnan(empty["median_dexterity"]) and math.isnan(empty["type2_near_fraction"])


def test_type2_crossings_between_reachable_neighbours_by_hand():
    from planar_sym.analysis.atlas import type2_crossed

    d = np.array([[[1.0, 1.0, -1.0], [1.0, 1.0, 1.0]]])
    # (0, 1) -> (0, 2) changes sign but (0, 2) is out of reach
    assert not type2_crossed(hand_atlas(det_type2=d))
    d = np.array([[[1.0, 1.0, 1.0], [1.0, 1.0, -1.0]]])  # along x on row 1
    assert type2_crossed(hand_atlas(det_type2=d))
    d = np.array([[[1.0, -1.0, 1.0], [1.0, 1.0, 1.0]]])  # along x and y at (0, 1)
    assert type2_crossed(hand_atlas(det_type2=d))
    d = np.array([[[1.0, 1.0, 1.0], [-1.0, 1.0, 1.0]]])  # along y at x = 0 (and x on row 1)
    assert type2_crossed(hand_atlas(det_type2=d))
    reach = np.array([[[True, False, False], [True, False, False]]])
    d = np.array([[[1.0, 1.0, 1.0], [-1.0, 1.0, 1.0]]])  # only along y
    assert type2_crossed(hand_atlas(det_type2=d, reachable=reach))
    # between orientations (axis 0)
    two = hand_atlas(reachable=np.ones((2, 2, 3), bool),
                     det_type2=np.concatenate([np.ones((1, 2, 3)), -np.ones((1, 2, 3))]))
    assert type2_crossed(two)


def test_an_atlas_table_and_arrays_by_hand(tmp_path):
    from planar_sym.analysis.atlas import write_csv

    a = hand_atlas()
    names, values = a.table()
    assert names == ["x_mm", "y_mm", "reachable", "same_assembly", "q1_rad", "q2_m", "type1",
                     "type2", "dexterity", "det_type1", "det_type2", "tau_g1_n_m",
                     "tau_env1_n_m", "env_angle1_deg", "tau_g2_n", "tau_env2_n",
                     "env_angle2_deg"]
    assert values.shape == (6, 17)
    np.testing.assert_allclose(values[:, 0], [0, 100, 200, 0, 100, 200], rtol=1e-15)
    np.testing.assert_allclose(values[:, 1], [0, 0, 0, 50, 50, 50], rtol=1e-15)
    np.testing.assert_array_equal(values[:, 2], [1, 1, 0, 1, 1, 1])
    np.testing.assert_array_equal(values[:, 3], [1, 0, 0, 1, 1, 0])
    np.testing.assert_array_equal(values[:, 8], [0.4, 0.1, np.nan, 0.3, 0.2, 0.9])
    np.testing.assert_array_equal(values[:, 11], [1.0, -3.0, np.nan, 2.0, -5.0, 0.5])
    np.testing.assert_array_equal(values[:, 15], [1.0, 9.0, np.nan, 2.0, 8.0, 3.0])
    arr = a.arrays()
    assert sorted(arr) == sorted(
        ["x_m", "y_m", "phi_rad", "q", "reachable", "same_assembly", "det_type1", "det_type2",
         "type1", "type2", "dexterity", "gravity", "envelope", "envelope_angle_rad",
         "start_pose", "accel_m_s2", "length_scale_m", "robot", "coordinates",
         "coordinate_units", "actuated", "actuator_units"])
    assert arr["accel_m_s2"] == 2.0 and arr["length_scale_m"] == 0.2 and str(arr["robot"]) == "hand"
    assert list(arr["coordinate_units"]) == ["rad", "m"] and list(arr["actuated"]) == [0, 1]
    write_csv(a, tmp_path / "a.csv")
    lines = (tmp_path / "a.csv").read_text().splitlines()
    assert lines[0] == ",".join(names) and len(lines) == 7
    assert lines[2].split(",")[:3] == ["100", "0", "1"]
    a.to_csv(tmp_path / "b.csv")
    assert (tmp_path / "b.csv").read_text() == (tmp_path / "a.csv").read_text()
    a.to_npz(tmp_path / "a.npz")
    with np.load(tmp_path / "a.npz") as npz:
        np.testing.assert_array_equal(npz["dexterity"], a.dexterity)
        assert str(npz["robot"]) == "hand"
    with_phi = hand_atlas(phi_rad=np.array([np.pi / 2]))
    names, values = with_phi.table()
    assert names[:3] == ["x_mm", "y_mm", "phi_deg"]
    np.testing.assert_allclose(values[:, 2], 90.0, rtol=1e-15)


def test_the_plants_own_check_draws_the_models_random_designs(tmp_path):
    """On both sets, a plant with a lighter forearm (0.06 kg against the model's 0.075) is
    checked as a design of its own base with the same random designs: izz_link2 drawn by
    default_rng(1) between 1e-4 and 2.2e-3 kg*m^2 (0.00117, 0.00210, 0.00040, 0.00209) passes
    the model's rule (a radius of gyration up to 3 times the extent: 2.30e-3 at 0.075 kg) but
    designs 1 and 3 break the plant's (1.84e-3 at 0.06 kg); with default_rng(0) (all below
    1.44e-3) both sets pass."""
    from dataclasses import replace

    from test_sweep_drive_plant import TRACK

    from planar_sym.analysis.sweep_plant import plant_designs
    from planar_sym.study.run import load_study, robot_of

    path = tmp_path / "track.toml"
    path.write_text(TRACK)
    st = load_study(path)
    light = replace(st, control=replace(st.control, plant={"m_link2": (0.06, "kg")}))
    robot = robot_of(light)
    vary = {"izz_link2": (1e-4, 2.2e-3)}
    draws = np.random.default_rng(1).uniform(1e-4, 2.2e-3, 4)
    with pytest.raises(InputError) as err:
        plant_designs(light, robot, vary, "both", sample="random", count=4, seed=1, control=True)
    msg = str(err.value)
    assert msg.startswith(f"the plant: design 1 (izz_link2 = {draws[1]:.6g}) is not physical: "
                          "parameter izz_link2 = ")
    assert msg.endswith(" (2 of 4 designs are not); narrow the range")
    _space, plant_P = plant_designs(light, robot, vary, "both", sample="random", count=4, seed=0,
                                   control=True)
    k = [p.name for p in robot.parameter_list].index("izz_link2")
    np.testing.assert_array_equal(plant_P[:, k], np.random.default_rng(0).uniform(1e-4, 2.2e-3, 4))
    np.testing.assert_array_equal(plant_P[:, k - 1], 0.06)  # m_link2, the plant's own


# -- atlas_flood.py ----------------------------------------------------------------------------
def test_grid_neighbours_by_hand():
    """Flat index = (phi, y, x) row-major; directions +x, -x, +y, -y (and +-phi with more than
    one layer); -1 off the grid."""
    from planar_sym.analysis.atlas_flood import _neighbours

    dirs, of = _neighbours((1, 2, 3))
    assert dirs == [(2, 1), (2, -1), (1, 1), (1, -1)]
    np.testing.assert_array_equal(of(np.arange(6)), [[1, -1, 3, -1], [2, 0, 4, -1],
                                                     [-1, 1, 5, -1], [4, -1, -1, 0],
                                                     [5, 3, -1, 1], [-1, 4, -1, 2]])
    dirs, of = _neighbours((2, 1, 2))
    assert dirs == [(2, 1), (2, -1), (0, 1), (0, -1)]
    np.testing.assert_array_equal(of(np.array([3, 0])), [[-1, 2, -1, 1], [1, -1, 2, -1]])


def test_start_poses_and_their_notes():
    """A stretched arm starts bent by 30 deg at every revolute joint after the first; a 5-bar
    whose ground pivot moved 6 mm keeps its drawn actuated angles and solves its passive
    joints; a q_start 0.26 mm off the loops is closed the same way."""
    from planar_sym.analysis.atlas_flood import start

    q, note = start(ps.load("serial_2dof"), None)
    np.testing.assert_allclose(q, [0.0, np.pi / 6], rtol=1e-15, atol=0)
    assert note == ("the drawn configuration is singular: started from it with joints joint2 "
                    "bent by 30 deg (give q_start for another working mode)")
    q, note = start(ps.load("serial_3dof"), None)
    np.testing.assert_allclose(q, [0.0, np.pi / 6, np.pi / 6], rtol=1e-15, atol=0)
    assert "with joints joint2, joint3 bent by 30 deg" in note
    q, note = start(ps.load("serial_2dof"), np.array([0.0, 1.0]))
    np.testing.assert_array_equal(q, [0.0, 1.0])
    assert note == ""
    five = ps.load("five_bar_type1")
    moved = five.with_parameters(px_ground_E=five.parameters["px_ground_E"] + 0.006)
    q, note = start(moved, None)
    assert note == ("the drawn configuration misses the loops by 6 mm with these parameters: "
                    "started from its actuated angles, the passive joints solved")
    np.testing.assert_array_equal(q[[0, 2]], five.q_drawn[[0, 2]])
    assert np.max(np.abs(moved.constraint(q))) < 1e-12
    q, note = start(five, None)
    np.testing.assert_array_equal(q, five.q_drawn)
    assert note == ""
    off = five.q_drawn.copy()
    off[1] += 0.003
    q, note = start(five, off)
    assert note == "" and np.max(np.abs(five.constraint(q))) < 1e-12
    np.testing.assert_array_equal(q[[0, 2]], off[[0, 2]])
    np.testing.assert_allclose(q, five.q_drawn, rtol=0, atol=1e-9)


def test_the_start_pose_as_lines_by_hand():
    """serial_2dof with the elbow at 90 deg: link1 from the origin to (0.1, 0), link2 up to the
    tip (0.1, 0.1); the elbow's point mass (one point) is no line; the ground is the origin."""
    from planar_sym.analysis.atlas import _order, stick

    s = stick(ps.load("serial_2dof"), np.array([0.0, np.pi / 2]))
    assert len(s["bodies"]) == 2
    np.testing.assert_allclose(s["bodies"][0], [[0.0, 0.0], [0.1, 0.0]], rtol=0, atol=1e-16)
    np.testing.assert_allclose(s["bodies"][1], [[0.1, 0.0], [0.1, 0.1]], rtol=0, atol=1e-16)
    np.testing.assert_array_equal(s["ground"], [[0.0, 0.0]])
    np.testing.assert_allclose(s["joints"], [[0, 0], [0.1, 0], [0.1, 0]], rtol=0, atol=1e-16)
    np.testing.assert_allclose(s["task"], [0.1, 0.1], rtol=0, atol=1e-16)
    # a thin body: its points along its axis; a wide one: around its centre, closed
    line = np.array([[2.0, 0.0], [0.0, 0.0], [1.0, 0.1]])  # 2 m long, 0.1 m bent: sigma ratio 0.058
    np.testing.assert_array_equal(np.abs(np.diff(_order(line)[:, 0])), [1.0, 1.0])
    tri = np.array([[0.0, 1.0], [1.0, -1.0], [-1.0, -1.0]])
    ring = _order(tri)
    assert len(ring) == 4 and np.array_equal(ring[0], ring[-1])
    np.testing.assert_array_equal(ring[:3], [[-1.0, -1.0], [1.0, -1.0], [0.0, 1.0]])
    two = np.array([[1.0, 0.0], [0.0, 0.0]])
    np.testing.assert_array_equal(_order(two), two)


def test_a_wrist_with_its_centre_of_gravity_on_its_axis_holds_no_gravity_torque():
    """serial_rpr's wrist: its gravity torque is rounding beside its envelope, mapped as 0
    exactly wherever the arm reaches; the shoulder's is not; the one orientation mapped is the
    start pose's (its three angles summed, phi = 1.5708 rad)."""
    from planar_sym.analysis.atlas import atlas

    a = atlas("serial_rpr", x_range=(-0.6, 0.9), y_range=(-0.6, 0.9), points=5)
    r = a.reachable
    assert r.sum() > 10
    np.testing.assert_array_equal(a.gravity[..., 2][r], 0.0)
    assert np.all(np.isnan(a.gravity[..., 2][~r]))
    assert np.abs(a.gravity[..., 0][r]).max() > 1.0
    assert a.phi_rad == pytest.approx([a.start_pose[0] + a.start_pose[2]], rel=1e-15)


def test_a_design_that_fails_on_the_per_design_route_keeps_the_others():
    """A controlled run per design: a 0.03 m upper arm cannot reach the reference's first
    target (design 0, the inverse kinematics' own message); design 1 (the study's own 0.1 m)
    has the figures of the study's run."""
    from planar_sym.analysis.sweep import sweep
    from planar_sym.analysis.sweep_figures import run_figures
    from planar_sym.study.run import load_study, robot_of

    study = "serial_2dof_cartesian_track_pd"
    st = load_study(study)
    want = {f.name: v for f, v in run_figures(st, robot_of(st)).items()}
    for vary, batch, bad, good in (([0.03, 0.1], None, 0, 1), ([0.1, 0.03], 2, 1, 0),
                                   ([0.1, 0.1, 0.03], 2, 2, 0)):
        res = sweep(study, {"px_link1_CS2": vary}, workers=1, batch=batch)
        assert res.route == "per design" and list(res.failed) == [bad]
        assert res.failed[bad].startswith("serial_2dof: target (x = 100 mm, y = 100 mm) at t = "
                                          "0 s (sample 0) is outside the workspace")
        assert list(res.figures) == list(want)
        for name, v in want.items():
            assert np.isnan(res.columns[name][bad]) and res.columns[name][good] == v, name


@pytest.mark.parametrize("robot, kwargs, message", [
    ("slider_crank", {}, ("slider_crank has no task point (its description has no [task]): an "
                         "atlas maps the task point's positions")),
    ("five_bar_type1", {"accel_m_s2": -1.0},
     "accel_m_s2 must be a finite acceleration >= 0 in m/s^2 (got -1.0)"),
    ("five_bar_type1", {"accel_m_s2": np.inf},
     "accel_m_s2 must be a finite acceleration >= 0 in m/s^2 (got inf)"),
    ("five_bar_type1", {"accel_m_s2": [1.0]},
     "accel_m_s2 must be a finite acceleration >= 0 in m/s^2 (got [1.0])"),
    ("serial_2dof", {"q_start": [0.0, 1.0, 2.0]},
     "q_start must have shape (N, 2) or (2,), got (3,)"),
])
def test_an_atlas_refused_before_it_starts(robot, kwargs, message):
    from planar_sym.analysis.atlas import atlas

    with pytest.raises(InputError) as err:
        atlas(robot, **kwargs)
    assert str(err.value) == message


def test_a_region_the_start_pose_cannot_reach_in_its_working_mode():
    """The arm from q = (0, 1 rad) and a region whose grid point nearest the start, (150,
    -150) mm, is 212 mm from the shoulder: beyond the two 100 mm links."""
    from planar_sym.analysis.atlas import atlas
    from planar_sym.errors import WorkspaceError

    with pytest.raises(WorkspaceError) as err:
        atlas("serial_2dof", x_range=(0.15, 0.2), y_range=(-0.2, -0.15), points=3,
              q_start=[0.0, 1.0])
    assert str(err.value) == ("serial_2dof: the grid point nearest the start pose (x 150 mm, "
                              "y -150 mm) cannot be reached from it in its working mode: choose a "
                              "region around the start pose or another start pose (q_start)")


class _RefusingTwo(_Refusing):
    """Refuses its second and third batches."""

    def submit(self, fn, *args):
        if self.calls == 2:
            self.calls += 1
            raise RuntimeError("pool closed")
        return super().submit(fn, *args)


def test_two_lost_batches_are_counted_together():
    from planar_sym.analysis.sweep import sweep

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = sweep(S3, {"m_link2": (0.05, 0.1, 6)}, executor=_RefusingTwo(), batch=2)
    assert sorted(res.failed) == [2, 3, 4, 5]
    assert [str(w.message)[:38] for w in caught if "lost" in str(w.message)] == [
        "4 of 6 designs were lost to worker err"]


def test_a_random_sweep_draws_with_its_seed():
    """sample="random": count designs drawn by default_rng(seed), seed 0 by default."""
    from planar_sym.analysis.sweep import sweep

    res = sweep(S3, {"m_link2": (0.05, 0.1)}, sample="random", count=3)
    np.testing.assert_array_equal(res.columns["m_link2_kg"],
                                  np.random.default_rng(0).uniform(0.05, 0.1, 3))
    res = sweep(S3, {"m_link2": (0.05, 0.1)}, sample="random", count=2, seed=4)
    np.testing.assert_array_equal(res.columns["m_link2_kg"],
                                  np.random.default_rng(4).uniform(0.05, 0.1, 2))
    assert res.note == "2 designs (random), shared motion"


def test_the_note_of_a_control_sweep_in_full():
    """serial_2dof_cartesian_track_pd's plant has a 0.09 kg forearm ([control.plant])."""
    from planar_sym.analysis.sweep import sweep

    res = sweep("serial_2dof_cartesian_track_pd", {"m_link2": [0.06, 0.07]}, workers=1,
                on="model")
    assert res.note == ("2 designs (grid), per design; m_link2 varied on the controller's model "
                        "only: the plant keeps m_link2 = 0.09 kg")


def test_the_lengths_that_move_the_joints_whatever_their_values():
    """The tool of serial_rpr is at the boom's end (s0 + extension + boom length) plus the
    wrist's length: all three, whatever their values (0.5, 0.2, 0.3 m, and 0.3 and 0.2 m for
    the arm's links); a 5-bar's task point (P at CS3 on the distal link) moves with its
    offset, which no loop equation holds; the loops with every length on them, the Type II
    pivot distance 0.2 m among them."""
    from planar_sym.analysis.sweep_routes import kinematic_parameters

    assert kinematic_parameters(ps.load("serial_rpr"), "task") == {"px_boom_W", "px_wrist_T",
                                                                   "s0_extend"}
    assert kinematic_parameters(ps.load("serial_rpr"), "joint") == set()
    arm = ps.load("serial_2dof").with_parameters(px_link1_CS2=0.3, px_link2_CS2=0.2)
    assert kinematic_parameters(arm, "task") == {"px_link1_CS2", "px_link2_CS2"}
    # 0.2 m and one ulp (0.20000000000000004): a fixed point of x -> 1.5 x - 0.1 in floating
    # point, which a perturbation of that form would leave unchanged
    arm = ps.load("serial_2dof").with_parameters(px_link2_CS2=float(np.nextafter(0.2, 1.0)))
    assert kinematic_parameters(arm, "task") == {"px_link1_CS2", "px_link2_CS2"}
    # fixed points of x -> 2.5 x + 0.1 and x -> 1.5 x + 1.1 (signed offsets may take them)
    for py in (-0.06666666666666668, -2.2):
        off = ps.load("five_bar_type1").with_parameters(py_L_Link2_CS2=py)
        assert "py_L_Link2_CS2" in kinematic_parameters(off, "joint")
    five = ps.load("five_bar_type1")
    loops = {"px_L_Link1_CS2", "px_L_Link2_CS2", "px_R_Link1_CS2", "px_R_Link2_CS2",
             "px_ground_E", "py_L_Link2_CS2"}
    assert kinematic_parameters(five, "joint") == loops
    assert kinematic_parameters(five, "task") == loops | {"px_L_Link2_CS3"}
    assert kinematic_parameters(ps.load("five_bar_type2"), "joint") == loops - {"py_L_Link2_CS2"}


def test_the_default_workers_are_the_cores(monkeypatch):
    """Without workers, one batch per core (os.cpu_count()); where the count of cores is
    unknown (None), one worker: one batch."""
    import os

    from planar_sym.analysis.sweep import sweep

    got = []
    sweep(S3, {"m_link2": (0.05, 0.1, 6)}, progress=lambda *a: got.append(a))
    size = math.ceil(6 / (os.cpu_count() or 1))
    assert got == [(min(k + size, 6), 6) for k in range(0, 6, size)]
    monkeypatch.setattr(os, "cpu_count", lambda: None)
    got = []
    sweep(S3, {"m_link2": (0.05, 0.1, 6)}, progress=lambda *a: got.append(a))
    assert got == [(6, 6)]


def test_singular_designs_on_the_shared_route_numbered_across_batches(monkeypatch):
    """The 5-bar's right forearm mass on S5 (the motion shared): every design has the move's
    worst conditioning; with the limit below it, all four fail as singular, numbered from
    each batch's start (batches of 2)."""
    from planar_sym.analysis import sweep_figures
    from planar_sym.analysis.sweep import sweep

    vary = {"m_R_Link2": [0.03, 0.04, 0.05, 0.06]}
    cond = sweep("five_bar_type1_move_x", vary).columns["max_cond_phi_p"]
    assert np.ptp(cond) == 0.0
    monkeypatch.setattr(sweep_figures, "COND_LIMIT", 0.5 * cond[0])
    res = sweep("five_bar_type1_move_x", vary, batch=2, workers=1)
    assert res.route == "shared motion" and list(res.failed) == [0, 1, 2, 3]
    assert all(why.startswith("singular pose on the move: the passive-joint constraint "
                              f"Jacobian Phi_p has condition number {cond[0]:.3g} > ")
               for why in res.failed.values())


def test_a_unit_slip_is_said_once_on_the_per_design_route():
    """A 50 'kg' forearm (grams typed as kg) in a simulation sweep: the range's warning once;
    each design's robot is made from the checked columns without saying it again."""
    from planar_sym.analysis.sweep import sweep

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = sweep("serial_2dof_free_swing", {"m_link2": [0.06, 50.0]}, workers=1)
    assert res.route == "per design" and not res.failed
    said = [str(w.message) for w in caught if "m_link2" in str(w.message)]
    assert len(said) == 1 and said[0].startswith("sweep range m_link2 from 0.06 to 50:")


def test_a_robot_without_the_designs_loop_runs_per_design(arm):
    """The exact path (or no C extension): no C loop over designs, so each design runs whole."""
    from types import SimpleNamespace as NS

    from planar_sym.analysis.sweep_routes import _route
    from planar_sym.study.run import load_study

    exact = NS(tree_inverse_dynamics=NS(), is_closed_chain=False)
    assert _route(load_study(S3), exact, design_space(arm, {"m_link2": [0.06]}), None) == (
        "per design", ())


def test_the_smallest_grid_and_the_largest_count():
    """Two points per axis is the smallest grid; a step of 1e-18 m over the arm's 0.42 m would
    be 4.2e17 points per axis: the count is capped at 1e15 + 1 (the memory refusal names it)."""
    from planar_sym.analysis.atlas_grid import make_grid

    arm = ps.load("serial_2dof")
    assert make_grid(arm, points=2).shape == (1, 2, 2)
    assert make_grid(arm, points=(2, 3)).shape == (1, 3, 2)
    with pytest.raises(InputError) as err:
        make_grid(arm, step=1e-18)
    n = 10**15 + 1
    assert str(err.value).startswith(f"serial_2dof: a grid of {n * n:,} points ({n} x {n}) "
                                     "would take ")


def test_the_reach_of_a_three_legged_platform():
    """parallel_3rrr: three legs A_i -> elbow_i -> B_i -> the platform's task point (which has
    an orientation too: only x, y bound it); each bounds the point to a disc of radius 1.05 x
    the polyline's length about A_i (from the joints' drawn positions); the box is the
    intersection of the three discs' boxes, R the smallest radius."""
    from planar_sym.analysis.atlas_grid import reach

    robot = ps.load("parallel_3rrr")
    z = np.zeros((1, robot.n))
    pts = np.asarray(robot.body_motion(robot.q_drawn[None], z, z)[2]).reshape(2, -1).T
    names = [j["name"] for j in robot.library.manifest["joints"]]
    tip = np.reshape(robot.task(robot.q_drawn[None])[0], -1)[:2]
    lo, hi, radii = np.full(2, -np.inf), np.full(2, np.inf), []
    for leg in ("1", "2", "3"):
        line = np.array([pts[names.index(n)] for n in (f"A{leg}", f"elbow{leg}", f"B{leg}")]
                        + [tip])
        r = 1.05 * np.sum(np.hypot(*np.diff(line, axis=0).T))
        lo, hi = np.maximum(lo, line[0] - r), np.minimum(hi, line[0] + r)
        radii.append(r)
    box, R = reach(robot)
    np.testing.assert_allclose(box, [lo[0], hi[0], lo[1], hi[1]], rtol=1e-14)
    assert R == pytest.approx(min(radii), rel=1e-14) and np.ptp(radii) > 1e-6


def test_the_legs_to_the_task_body_by_hand():
    """five_bar_type1's joints A (ground-L_Link1), B (L_Link1-L_Link2), E (ground-R_Link1), D
    (R_Link1-R_Link2), C (L_Link2-R_Link2, the cut): the task point is on L_Link2, reached by
    A, B and by E, D, C; no path passes the ground twice; a limit keeps the first paths.
    parallel_3rrr: one leg per pivot to the platform."""
    from planar_sym.analysis.atlas_grid import _paths, _task_body

    five = ps.load("five_bar_type1")
    joints = five.library.manifest["joints"]
    J = np.reshape(five.task(five.q_drawn[None])[1], (2, five.n))
    assert _task_body(joints, J) == "L_Link2"
    assert _paths(joints, "L_Link2") == [[0, 1], [2, 3, 4]]
    assert _paths(joints, "L_Link2", limit=1) == [[0, 1]]
    assert _paths(joints, "R_Link1") == [[0, 1, 4, 3], [2]]
    rrr = ps.load("parallel_3rrr")
    assert _paths(rrr.library.manifest["joints"], "platform") == [[0, 1, 2], [3, 4, 7],
                                                                   [5, 6, 8]]


def test_a_leg_with_a_slider_bounds_nothing_the_others_still_do():
    """The Type II 5-bar with its left pivot A made a slider (its description's joints, A's
    type changed): the left leg bounds nothing, the right leg's disc about E = (0.2, 0) of
    radius 1.05 x (0.1 + 0.1 + 0.028) m is the box."""
    from types import SimpleNamespace as NS

    from planar_sym.analysis.atlas_grid import reach

    five = ps.load("five_bar_type2")
    joints = [dict(j) for j in five.library.manifest["joints"]]
    assert joints[0]["name"] == "A"
    joints[0]["type"] = "prismatic"

    class Slid:
        library = NS(manifest={**five.library.manifest, "joints": joints})

        def __getattr__(self, name):
            return getattr(five, name)

    box, R = reach(Slid())
    r = 1.05 * 0.228
    np.testing.assert_allclose(box, [0.2 - r, 0.2 + r, -r, r], rtol=1e-12)
    assert R == pytest.approx(r, rel=1e-12)


def test_at_most_64_paths_are_followed():
    """70 joints side by side between the ground and one body: 70 simple paths, of which the
    first 64 are kept (the reach bound's cost stays bounded on a machine of many loops)."""
    from planar_sym.analysis.atlas_grid import _paths

    joints = [{"parent": "ground", "child": "b"} for _ in range(70)]
    assert _paths(joints, "b") == [[k] for k in range(64)]


def test_the_task_acceleration_along_s5_is_the_paths_own():
    """S5 moves the 5-bar's point along x: xdd (J qdd + Jdot qd) against central differences
    of its own positions x(t) (the profile's quadratic pieces: exact up to rounding)."""
    from planar_sym.analysis.envelope_along import envelope_along

    e = envelope_along("five_bar_type1_move_x")
    fd = np.gradient(np.gradient(e.x, e.t_s, axis=0), e.t_s, axis=0)
    assert np.abs(e.xdd).max() > 0.07
    np.testing.assert_allclose(e.xdd[5:-5], fd[5:-5], rtol=0, atol=1e-9)


def test_the_newton_step_limit_per_coordinate():
    """DQ_LIMIT (0.5) per step: in rad at a revolute joint, in L_c (here 0.4 m) at a slider."""
    from planar_sym.analysis.atlas_flood import DQ_LIMIT, _Newton

    assert DQ_LIMIT == 0.5
    newton = _Newton(ps.load("serial_rpr"), 0.4, 1.0)
    np.testing.assert_array_equal(newton.limit, [0.5, 0.2, 0.5])
    assert newton.sign0 == 1.0


def test_regions_touching_the_reach_box_and_half_given_regions():
    """A region that touches the reach box at its edge is allowed (it shares a line with it);
    a slider robot needs both ranges; integer orientations are angles in rad all the same."""
    from planar_sym.analysis.atlas_grid import make_grid, reach

    arm = ps.load("serial_2dof")
    (x0, x1, y0, y1), _ = reach(arm)
    for xr, yr in (((x1, x1 + 0.1), (0.0, 0.1)), ((x0 - 0.1, x0), (0.0, 0.1)),
                   ((0.0, 0.1), (y1, y1 + 0.1)), ((0.0, 0.1), (y0 - 0.1, y0))):
        assert make_grid(arm, x_range=xr, y_range=yr, points=2).shape == (1, 2, 2)
    rpr = ps.load("serial_rpr")
    with pytest.raises(InputError) as err:
        make_grid(rpr, x_range=(-0.6, 0.9))
    assert str(err.value).startswith("serial_rpr: a slider on every leg to the task point")
    g = make_grid(rpr, x_range=(-0.6, 0.9), y_range=(-0.6, 0.5), points=3, orientations=[2, 1])
    assert g.phi_rad.dtype == np.float64 and g.phi_rad.tolist() == [1.0, 2.0]
    with pytest.raises(InputError) as err:
        make_grid(arm, step=0.01, points=3)
    assert str(err.value) == "give a step or a number of points, not both"
