"""Sweeps and the machine's two parameter sets and two sides (issue 24, "one machine").

* A control study has a controller's model and a plant: ``sweep(..., on=...)`` changes both
  (default), the model only or the plant only, and each design's figures equal the study run
  directly with that design's parameter sets (the study changed by ``dataclasses.replace``):
  the model's ``[parameters]`` and the plant's ``[control.plant]``.
* With actuator models (``examples/serial_2dof_geared.toml``: N = 50, rotors, friction) an
  inverse-dynamics sweep has the motor side per actuator, each design at its own gear ratio,
  equal to ``dynamics.sizing.size`` of the design's own run (``Result.sizing``) on every route.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.analysis import sweep_motor
from planar_sym.analysis.sweep import sweep
from planar_sym.cli import main
from planar_sym.errors import InputError
from planar_sym.study.result import coordinate_column
from planar_sym.study.run import load_study

ROOT = Path(__file__).resolve().parent.parent
GEARED = ROOT / "examples" / "serial_2dof_geared.toml"

#: S3 (serial_2dof_cartesian_move) on the geared arm, 1 s so that the motors work
MOVE = f"""title = "S3 on the geared arm in 1 s"
robot = "{GEARED}"
kind = "inverse"
[units]
length = "mm"
[motion]
space = "task"
profile = "cubic"
start = [100.0, 100.0]
by = [-200.0, 0.0]
duration = 1.0
samples = 101
start_pose = [0.0, 1.5708]   # rad: elbow down, as the seed's closed form
"""

#: S3 tracked (serial_2dof_cartesian_track) on the geared arm, from the reference: the only
#: error is the model's, so a plant equal to the model tracks to the integrator's accuracy
TRACK = f"""title = "S3 tracked on the geared arm, forearm mass +20 % in the plant"
robot = "{GEARED}"
kind = "control"
[units]
length = "mm"
angle = "deg"
[motion]
space = "task"
profile = "cubic"
start = [100.0, 100.0]
by = [-200.0, 0.0]
duration = 1.0
samples = 51
start_pose = [0.0, 90.0]
[control]
law = "computed_torque"
natural_frequency_hz = 5.0
samples = 101
[control.plant]
m_link2 = 0.09               # kg (the controller's model: 0.075)
"""

M_MODEL, M_PLANT = 0.075, 0.09
MASSES = [0.06, M_MODEL, M_PLANT, 0.105]


@pytest.fixture()
def track(tmp_path) -> Path:
    path = tmp_path / "geared_track.toml"
    path.write_text(TRACK)
    return path


@pytest.fixture()
def rpr(tmp_path) -> Path:
    """The built-in RPR tool move on tests/robots/rpr_geared.toml (a screw-driven boom)."""
    text = (ROOT / "planar_sym" / "studies" / "serial_rpr_tool_move.toml").read_text()
    path = tmp_path / "rpr_geared_move.toml"
    path.write_text(text.replace('robot = "serial_rpr"',
                                 f'robot = "{ROOT / "tests" / "robots" / "rpr_geared.toml"}"'))
    return path


@pytest.fixture()
def move(tmp_path) -> Path:
    path = tmp_path / "geared_move.toml"
    path.write_text(MOVE)
    return path


def control_figures(res) -> dict[str, float]:
    """A controlled run's figures, reduced here from its columns."""
    c = res.columns
    out = {"max_abs_e_task_mm": np.max(np.abs(c["e_task_mm"])),
           "final_work_j": c["work_j"][-1], "energy_change_j": c["energy_j"][-1] - c["energy_j"][0]}
    for k in (1, 2):
        out[f"max_abs_e{k}_rad"] = np.max(np.abs(c[f"e{k}_rad"]))
        out[f"peak_tau{k}_n_m"] = np.max(np.abs(c[f"tau{k}_n_m"]))
        t = c["t_s"]  # the RMS over time, by the trapezoidal rule
        out[f"rms_tau{k}_n_m"] = np.sqrt(np.trapezoid(c[f"tau{k}_n_m"] ** 2, t) / t[-1])
    return out


def direct(st, model: dict, plant: dict):
    """The study run as a user would: its [parameters] and its [control.plant] replaced (SI,
    with units)."""
    st = replace(st, parameters={**st.parameters, **model},
                 control=replace(st.control, plant=plant))
    return ps.run_study(st)


# -- plant and model ---------------------------------------------------------------------------
@pytest.mark.parametrize("on", ["both", "model", "plant"])
def test_control_sweep_equals_the_study_with_its_parameter_sets_changed(track, on):
    """Two parameters: the forearm's mass (which [control.plant] sets) and its inertia (which
    it does not). Per design, the study's two parameter sets as ``on`` says:
    both: the model and the plant take the design (the plant's m_link2 = 0.09 gone);
    model: the model takes it, the plant stays the study's (m_link2 0.09, izz_link2 the base);
    plant: the plant takes it, the model stays the study's."""
    izz = [1.0e-4, 1.3e-4]  # kg*m^2 (the description: 109.864 kg*mm^2)
    res = sweep(track, {"m_link2": MASSES, "izz_link2": izz}, on=on, workers=1)
    assert res.route == "per design" and not res.failed and len(res) == 8 and res.on == on
    assert res.varied == ("m_link2_kg", "izz_link2_kg_m2", "plant_m_link2_kg",
                          "plant_izz_link2_kg_m2")
    st = load_study(track)
    base_izz = 109.864e-6
    for k in range(len(res)):
        m, j = res.columns["m_link2_kg"][k], res.columns["izz_link2_kg_m2"][k]
        pm, pj = res.columns["plant_m_link2_kg"][k], res.columns["plant_izz_link2_kg_m2"][k]
        dm, dj = MASSES[k // 2], izz[k % 2]  # the design (grid order: m_link2 slowest)
        if on == "both":
            assert (m, j, pm, pj) == (dm, dj, dm, dj)
            ref = direct(st, {"m_link2": (dm, "kg"), "izz_link2": (dj, "kg*m^2")}, {})
        elif on == "model":
            assert (m, j, pm, pj) == (dm, dj, M_PLANT, pytest.approx(base_izz, rel=1e-15))
            ref = direct(st, {"m_link2": (dm, "kg"), "izz_link2": (dj, "kg*m^2")},
                         {"m_link2": (M_PLANT, "kg"), "izz_link2": (109.864, "kg*mm^2")})
        else:
            assert (m, j, pm, pj) == (M_MODEL, pytest.approx(base_izz, rel=1e-15), dm, dj)
            ref = direct(st, {}, {"m_link2": (dm, "kg"), "izz_link2": (dj, "kg*m^2")})
        for name, want in control_figures(ref).items():
            np.testing.assert_allclose(res.columns[name][k], want, rtol=1e-12, atol=1e-15,
                                       err_msg=f"{on}, design {k}: {name}")


#: a pendulum swung up by an optimal plan and tracked by a TVLQR, its plant's rod 10 % heavier
SWING = f"""title = "pendulum swing-up, plant heavier"
robot = "{ROOT / 'tests' / 'robots' / 'pendulum.toml'}"
kind = "optimal"
[units]
angle = "deg"
[optimal]
start = [-90.0]
end = [90.0]
objective = "effort"
duration = 1.5
intervals = 30
torque_limit = [6.0]
[control]
law = "lqr"
q_weight = [100.0, 1.0]
r_weight = [1.0]
saturate = false
duration = 2.0
samples = 101
[control.plant]
m_rod = 1.65
"""


def test_an_optimal_study_with_control_has_a_plant_too(tmp_path):
    """An optimal study tracked by [control] is swept on its plant as a control study is (every
    design ran on the study's 1.65 kg plant, in silence, and --on plant was refused as "one
    robot, no plant"): each design equals the study run with its parameter sets, and the
    energy it gains equals m g (2 l) of the design's rod, raised from hanging to upright."""
    path = tmp_path / "swing.toml"
    path.write_text(SWING)
    st = load_study(path)
    for on in ("both", "plant"):
        res = sweep(path, {"m_rod": [1.4, 1.6]}, on=on, workers=1)
        assert res.varied == ("m_rod_kg", "plant_m_rod_kg") and not res.failed
        for k, m in enumerate((1.4, 1.6)):
            assert res.columns["plant_m_rod_kg"][k] == m
            model = {"m_rod": (m, "kg")} if on == "both" else {}
            ref = direct(st, model, {"m_rod": (m, "kg")})
            gained = ref.columns["energy_j"][-1] - ref.columns["energy_j"][0]
            assert res.columns["energy_change_j"][k] == pytest.approx(gained, rel=1e-12)
            assert gained == pytest.approx(m * 9.81 * 2 * 0.25, rel=1e-3)


def test_model_and_plant_differ_where_they_should(track):
    """Computed torque with a model equal to the plant tracks to the integrator's accuracy
    (about 1e-12 rad); a mismatch leaves an error of millirads. So: on both every design
    tracks; on the model only, only the design that equals the plant's 0.09 kg; on the plant
    only, only the one that equals the model's 0.075 kg. The old silent behaviour (the plant
    kept its [control.plant] value whatever the sweep) tracked exactly at 0.09 kg only."""
    err = {on: sweep(track, {"m_link2": MASSES}, on=on, workers=1).columns["max_abs_e2_rad"]
           for on in ("both", "model", "plant")}
    exact = {on: err[on] < 1e-9 for on in err}
    assert exact["both"].tolist() == [True, True, True, True]
    assert exact["model"].tolist() == [False, False, True, False]
    assert exact["plant"].tolist() == [False, True, False, False]
    assert err["model"][[0, 1, 3]].min() > 1e-3 and err["plant"][[0, 2, 3]].min() > 1e-3


def test_the_note_and_the_table_say_what_was_varied_on_which(track, tmp_path):
    from planar_sym.outputs.sweep_plots import sweep_figure

    results = {on: sweep(track, {"m_link2": [0.06, 0.08]}, on=on, workers=1)
               for on in ("both", "model", "plant")}
    notes = {on: r.note for on, r in results.items()}
    assert notes["both"].endswith("m_link2 varied on the controller's model and the plant "
                                  "([control.plant]'s m_link2 replaced by the design's)")
    assert notes["model"].endswith("m_link2 varied on the controller's model only: the plant "
                                   "keeps m_link2 = 0.09 kg")
    assert notes["plant"].endswith("m_link2 varied on the plant only: the controller's model "
                                   "keeps m_link2 = 0.075 kg")
    # the figure is drawn against what changed: the plant's column, the model's held one no
    # second dimension (no legend)
    for on, x in (("both", "m_link2 (kg)"), ("model", "m_link2 (kg)"),
                  ("plant", "plant_m_link2 (kg)")):
        fig = sweep_figure(results[on])
        assert fig.axes[-1].get_xlabel() == x and fig.axes[0].get_legend() is None, on
    out = tmp_path / "out"
    assert main(["sweep", str(track), "--vary", "m_link2=0.06,0.08", "--on", "plant",
                 "--workers", "1", "--out", str(out)]) == 0
    lines = (out / "geared_track_sweep.csv").read_text().splitlines()
    assert lines[0].startswith("m_link2_kg,plant_m_link2_kg,peak_tau1_n_m,")
    assert [row.split(",")[:2] for row in lines[1:]] == [["0.075", "0.06"], ["0.075", "0.08"]]


def test_on_is_refused_where_there_is_no_plant(track, move, capsys, tmp_path):
    with pytest.raises(InputError, match=r"on must be 'both', 'model' or 'plant' \(got 'plnt'\)"):
        sweep(track, {"m_link2": [0.06]}, on="plnt")
    with pytest.raises(InputError, match=r"on = 'plant' is for control studies \(a controller's "
                                         r"model and a plant\): geared_move is a study of kind = "
                                         r"\"inverse\": one robot, no plant; leave on = 'both'"):
        sweep(move, {"m_link2": [0.06]}, on="plant")
    with pytest.raises(InputError, match=r"on = 'model' .*: an atlas sweep runs on one robot"):
        sweep(track, {"m_link2": [0.06]}, on="model", atlas={"points": 10})
    assert main(["sweep", str(track), "--vary", "m_link2=0.06", "--on", "plnt",
                 "--out", str(tmp_path)]) == 2
    assert "error: --on 'plnt': choose both, model or plant" in capsys.readouterr().err
    # each parameter set's designs are checked against its own base: the forearm's inertia
    # may reach 2.30e-3 kg*m^2 with the model's 0.075 kg (a radius of gyration of 3 times its
    # extent, 58.3 mm), 2.76e-3 with the plant's 0.09 kg
    with pytest.raises(InputError, match=r"^design 0 \(izz_link2 = 0\.0025\) is not physical: "
                                         r"parameter izz_link2 = 0\.0025 kg\*m\^2 with m_link2 = "
                                         r"0\.075 kg gives a radius of gyration"):
        sweep(track, {"izz_link2": [2.5e-3]}, on="model")
    assert not sweep(track, {"izz_link2": [2.5e-3]}, on="plant").failed
    with pytest.raises(InputError, match=r"^the plant: design 0 \(izz_link2 = 0\.003\) is not "
                                         r"physical: parameter izz_link2 = 0\.003 kg\*m\^2 with "
                                         r"m_link2 = 0\.09 kg gives a radius of gyration"):
        sweep(track, {"izz_link2": [3e-3]}, on="plant")
    # on both, the plant's designs too: a lighter plant forearm (0.06 kg) allows 1.84e-3
    st = load_study(track)
    light = replace(st, control=replace(st.control, plant={"m_link2": (0.06, "kg")}))
    with pytest.raises(InputError, match=r"^the plant: design 0 \(izz_link2 = 0\.002\) is not "
                                         r"physical: parameter izz_link2 = 0\.002 kg\*m\^2 with "
                                         r"m_link2 = 0\.06 kg gives a radius of gyration"):
        sweep(light, {"izz_link2": [2e-3]}, on="both")


# -- the motor side ----------------------------------------------------------------------------
def sizing_of(st, values: dict[str, float]):
    """The design's own run (the study's [parameters] replaced, SI) and its sizing."""
    units = {p.name: p.unit for p in ps.load(st.robot).parameter_list}
    res = ps.run_study(replace(st, parameters={**st.parameters,
                                               **{n: (v, units[n]) for n, v in values.items()}}))
    return res.sizing


@pytest.mark.parametrize("kind, vary, route", [
    ("move", {"m_link2": [0.06, 0.1], "gear_joint1": [20.0, 50.0, 120.0],
              "gear_joint2": [35.0, 80.0]}, "shared motion"),
    ("move", {"px_link1_CS2": [0.095, 0.11], "gear_joint1": [30.0, 70.0]},
     "motion per design"),
    ("track", {"gear_joint1": [30.0, 70.0], "gear_joint2": [40.0, 60.0]}, "per design"),
    # a slider driven through a screw (N in rad/m, the joint's force tau2_n, motor N*m)
    ("rpr", {"gear_extend": [600.0, 1256.6, 2500.0], "m_boom": [1.0, 1.5]}, "shared motion"),
])
def test_motor_figures_equal_the_sizing_of_each_designs_run(kind, vary, route, move, track,
                                                            rpr, monkeypatch):
    """Every motor figure, design by design, against ``Result.sizing`` of the study run with
    that design's parameters (its own gear ratios), to 1e-12; batches of 3 designs in chunks
    of 2, so that the numpy pass crosses chunk boundaries and a worker robot holds several
    designs' parameters in turn."""
    monkeypatch.setattr(sweep_motor, "MOTOR_CHUNK", 2)
    path = {"move": move, "track": track, "rpr": rpr}[kind]
    res = sweep(path, vary, workers=1, batch=3)
    assert res.route == route and not res.failed
    st = load_study(path)
    for k in range(len(res)):
        values = {n: res.columns[c][k] for n, c in zip(res.parameters, res.varied)}
        for a in sizing_of(st, values):
            n = a.coordinate + 1
            assert a.gear_ratio == values.get(f"gear_{a.joint}", a.gear_ratio)
            for column, want in ((f"peak_motor_tau{n}_n_m", a.peak_motor_torque_n_m),
                                 (f"rms_motor_tau{n}_n_m", a.rms_motor_torque_n_m),
                                 (f"peak_motor_speed{n}_rpm", a.peak_motor_speed_rpm),
                                 (f"peak_power{n}_w", a.peak_power_w)):
                np.testing.assert_allclose(res.columns[column][k], want, rtol=1e-12, atol=0,
                                           err_msg=f"{route}, design {k}: {column}")
    # the motor torque is the joint's over each design's own N
    gear = next(c for c in res.varied if c.startswith("gear_"))
    robot = ps.load(st.robot)
    i = next(d.coordinate for d in robot.drive_train.drives if gear.startswith(f"gear_{d.joint}_"))
    joint = "peak_" + coordinate_column("tau", i, robot.coordinate_units[i])
    np.testing.assert_allclose(res.columns[f"peak_motor_tau{i + 1}_n_m"] * res.columns[gear],
                               res.columns[joint], rtol=1e-15)


def test_motor_figures_by_value_on_a_shared_motion(move):
    """The figures at N = 50 against numpy on the study's own run (trapezoidal RMS, as
    ``sizing``), and the scaling with N: the motor speed grows as N, the motor torque falls."""
    res = sweep(move, {"gear_joint1": [25.0, 50.0, 100.0]}, workers=1)
    run = ps.run_study(move)
    t, tau, qd = run.columns["t_s"], run.columns["tau1_n_m"], run.columns["qd1_rad_s"]
    rms = np.sqrt(np.sum(np.diff(t) * (tau[1:] ** 2 + tau[:-1] ** 2) / 2) / (t[-1] - t[0]))
    np.testing.assert_allclose(res.columns["peak_motor_tau1_n_m"][1], np.abs(tau).max() / 50,
                               rtol=1e-13)
    np.testing.assert_allclose(res.columns["rms_motor_tau1_n_m"][1], rms / 50, rtol=1e-13)
    np.testing.assert_allclose(res.columns["peak_motor_speed1_rpm"][1],
                               np.abs(qd).max() * 50 * 60 / (2 * np.pi), rtol=1e-13)
    np.testing.assert_allclose(res.columns["peak_power1_w"][1], np.abs(tau * qd).max(),
                               rtol=1e-13)
    np.testing.assert_allclose(res.columns["peak_motor_speed1_rpm"],
                               res.columns["peak_motor_speed1_rpm"][1] * np.array([0.5, 1, 2]),
                               rtol=1e-15)
    # the rotor's reflected inertia N^2 J_m grows with N: so does the joint torque
    assert np.all(np.diff(res.columns["peak_tau1_n_m"]) > 0)
    assert np.all(np.diff(res.columns["peak_motor_tau1_n_m"]) < 0)


def test_no_motor_columns_without_actuator_models():
    """The seed's arm has no [joints.actuator]: gear 1, motor torque = joint torque; the
    table keeps its joint-side columns only."""
    res = sweep("serial_2dof_cartesian_move", {"m_link2": [0.06, 0.09]})
    assert not [c for c in res.columns if "motor" in c or "power" in c]


def test_the_tool_is_where_the_plants_geometry_puts_it(tmp_path):
    """A plant whose upper arm is 10 mm longer than the model's (px_link1_CS2 0.11 m, model
    0.1 m): x, y are the plant's forward kinematics of the joints it reached, by hand,
    a1 cos q1 + a2 cos(q1 + q2); the model's put the tool about 10 mm off where it was and
    reported a tracking error of under a millimetre."""
    text = (ROOT / "planar_sym" / "studies" / "serial_2dof_cartesian_track.toml").read_text()
    path = tmp_path / "long_arm.toml"
    path.write_text(text.replace("m_link2 = 0.09              # kg (the controller assumes "
                                 "0.075)", "px_link1_CS2 = 0.11").split("[outputs]")[0])
    res = ps.run_study(path)
    c = res.columns
    q1, q2 = c["q1_rad"], c["q2_rad"]
    a1, a2 = 0.11, 0.1
    np.testing.assert_allclose(c["x_mm"], 1e3 * (a1 * np.cos(q1) + a2 * np.cos(q1 + q2)),
                               rtol=0, atol=1e-10)
    np.testing.assert_allclose(c["y_mm"], 1e3 * (a1 * np.sin(q1) + a2 * np.sin(q1 + q2)),
                               rtol=0, atol=1e-10)
    e = np.hypot(c["x_ref_mm"] - c["x_mm"], c["y_ref_mm"] - c["y_mm"])
    np.testing.assert_allclose(c["e_task_mm"], e, rtol=1e-12, atol=1e-12)
    assert c["e_task_mm"][-1] > 5.0  # the joints track; the longer arm puts the tool off


def test_a_misspelt_plant_parameter_gets_the_nearest_name(tmp_path):
    """`[control.plant] m_lnk2` listed the known names only, where a misspelt key of the
    study got "did you mean"."""
    path = tmp_path / "typo.toml"
    path.write_text(TRACK.replace("m_link2 = 0.09 ", "m_lnk2 = 0.09 "))
    with pytest.raises(InputError, match=r"control.plant.m_lnk2: not a parameter of "
                                         r"serial_2dof_geared \(known: .*\); did you mean "
                                         r"'m_link2'\?$"):
        ps.run_study(path)
