"""Actuator models (gearbox, rotor, friction, limits) and actuator sizing, against analytic forms
and energy balances.

tests/robots/actuated_2dof.toml is the seed's 2-DOF arm with, at joint 1 (stator on ground):
N1 = 50, J1 = 0.5 kg*mm^2, b = 0.01 N*m*s/rad, c = 0.02 N*m (smoothed over 0.01 rad/s), limits;
at joint 2 (stator on link 1): N2 = 30, J2 = 0.3 kg*mm^2. The rotors add, exactly::

    T_r = 1/2 J1 (N1 qd1)^2 + 1/2 J2 (qd1 + N2 qd2)^2
    dM  = [[J1 N1^2 + J2, J2 N2], [J2 N2, J2 N2^2]]   (constant)

and friction D1 = b qd1 + c tanh(qd1 / 0.01) at joint 1.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from conftest import TEST_ROBOTS, rel_err

from planar_sym.errors import DescriptionError
from planar_sym.model import description
from planar_sym.model.locate import load

N1, J1, N2, J2 = 50.0, 0.5e-6, 30.0, 0.3e-6
B, C, VS = 0.01, 0.02, 0.01


@pytest.fixture(scope="module")
def pair(derived):
    return derived(TEST_ROBOTS / "actuated_2dof.toml")[1], load("serial_2dof")


def test_rotor_inertia_enters_the_mass_matrix_exactly(pair, rng):
    act, plain = pair
    q = rng.uniform(-3, 3, (40, 2))
    dm = act.mass_matrix(q) - plain.mass_matrix(q)
    ref = np.array([[J1 * N1**2 + J2, J2 * N2], [J2 * N2, J2 * N2**2]])
    assert np.max(np.abs(dm - ref)) < 1e-15 * np.max(np.abs(act.mass_matrix(q)))


def test_friction_enters_the_bias(pair, rng):
    act, plain = pair
    q, qd = rng.uniform(-3, 3, (40, 2)), rng.uniform(-0.05, 0.05, (40, 2))
    dh = act.bias(q, qd) - plain.bias(q, qd)
    ref = np.column_stack([B * qd[:, 0] + C * np.tanh(qd[:, 0] / VS), np.zeros(40)])
    assert rel_err(dh, ref, floor=1e-12) < 1e-12
    assert act.has_friction and not plain.has_friction


def test_free_motion_loses_exactly_the_friction_work(pair):
    """E(T) - E(0) = -int D(qd) . qd dt in a free swing (tau = 0)."""
    from planar_sym.dynamics.forward import simulate

    act, _ = pair
    t = np.linspace(0.0, 1.0, 4001)
    sim = simulate(act, [-1.2, 0.4], [0.0, 0.0], (0.0, 1.0), t_eval=t)
    qd1 = sim.qd[:, 0]
    loss = np.trapezoid((B * qd1 + C * np.tanh(qd1 / VS)) * qd1, t)
    change = sim.energy_j[-1] - sim.energy_j[0]
    assert change < 0
    assert abs(change + loss) < 1e-6 * loss


def test_sizing_against_the_columns_and_the_energy(derived, tmp_path):
    """Motor torque = tau / N, motor speed = N qd, and the net work equals the change of
    potential energy plus the friction work (rest to rest)."""
    from planar_sym.study import spec
    from planar_sym.study.run import run

    folder = derived(TEST_ROBOTS / "actuated_2dof.toml")[0]
    st = tmp_path / "move.toml"
    st.write_text(f'title = "move"\nrobot = "{folder}"\nkind = "inverse"\n[units]\n'
                  'angle = "deg"\n[motion]\nspace = "joint"\nprofile = "cubic"\n'
                  'start = [0.0, 0.0]\nby = [90.0, 45.0]\nduration = 1.0\nsamples = 4001\n')
    r = run(spec.load(st))
    s1, s2 = r.sizing
    tau1, qd1 = r.columns["tau1_n_m"], r.columns["qd1_rad_s"]
    assert s1.peak_motor_torque_n_m == pytest.approx(np.max(np.abs(tau1)) / N1, rel=1e-15)
    assert s1.peak_motor_speed_rad_s == pytest.approx(np.max(np.abs(qd1)) * N1, rel=1e-15)
    assert s2.gear_ratio == N2
    robot = derived(TEST_ROBOTS / "actuated_2dof.toml")[1]
    q = np.column_stack([r.columns["q1_rad"], r.columns["q2_rad"]])
    _, v = robot.energy(q, np.zeros_like(q))
    t = r.columns["t_s"]
    friction = np.trapezoid((B * qd1 + C * np.tanh(qd1 / VS)) * qd1, t)
    net = s1.energy_j + s2.energy_j
    assert net == pytest.approx(v[-1] - v[0] + friction, rel=1e-6)
    assert s1.rms_torque <= s1.peak_torque


def test_limits_exceeded_are_reported_with_the_time(derived, tmp_path):
    from planar_sym.study import spec
    from planar_sym.study.run import run

    folder = derived(TEST_ROBOTS / "actuated_2dof.toml")[0]
    st = tmp_path / "fast.toml"
    st.write_text(f'title = "fast"\nrobot = "{folder}"\nkind = "inverse"\n[units]\n'
                  'angle = "deg"\n[motion]\nspace = "joint"\nprofile = "cubic"\n'
                  'start = [0.0, 0.0]\nby = [90.0, 0.0]\nduration = 0.3\nsamples = 301\n')
    r = run(spec.load(st))
    s1 = r.sizing[0]
    t, tau1, qd1 = r.columns["t_s"], r.columns["tau1_n_m"], r.columns["qd1_rad_s"]
    first_torque = int(np.argmax(np.abs(tau1) > 0.8))
    first_motor = int(np.argmax(np.abs(tau1) / N1 > 0.02))
    first_speed = int(np.argmax(np.abs(qd1) * N1 * 60 / (2 * np.pi) > 3000))
    text = " | ".join(s1.exceeded)
    assert f"joint torque exceeds its limit 0.8 N*m from t = {t[first_torque]:.6g} s" in text
    assert f"motor torque exceeds its limit 0.02 N*m from t = {t[first_motor]:.6g} s" in text
    assert f"motor speed exceeds its limit 3000 rpm from t = {t[first_speed]:.6g} s" in text
    assert "ACTUATOR LIMITS EXCEEDED" in r.note


def _bad(tmp_path, old: str, new: str):
    src = (TEST_ROBOTS / "actuated_2dof.toml").read_text()
    assert old in src
    p = tmp_path / "bad.toml"
    p.write_text(src.replace(old, new, 1))
    with pytest.raises(DescriptionError) as info:
        description.load(p)
    return info.value.problems


@pytest.mark.parametrize("old,new,field,message", [
    ("gear_ratio = 50", "gear_ratio = 0", "actuator.gear_ratio", "must be > 0 (got 0)"),
    ("rotor_inertia = 0.5", "rotor_inertia = -0.5", "actuator.rotor_inertia",
     "must be >= 0 kg*mm^2 (got -0.5)"),
    ("torque_limit = 0.8", "torque_limit = 0", "actuator.torque_limit", "must be > 0"),
    ("motor_speed_limit_rpm = 3000", "motor_speed_limit_rpm = -1",
     "actuator.motor_speed_limit_rpm", "must be > 0"),
    ("gear_ratio = 50", "gear = 50", "actuator.gear", "unknown key"),
    ("gear_ratio = 50", "gear_ratio = 50\ntorque_constant = 0.05", "actuator.torque_constant",
     "only with winding_resistance"),
    ("gear_ratio = 50", "gear_ratio = 50\nwinding_resistance = 1.0\ntorque_constant = 0",
     "actuator.torque_constant", "must be > 0"),
])
def test_bad_actuators(tmp_path, old, new, field, message):
    problems = _bad(tmp_path, old, new)
    assert len(problems) == 1, problems
    assert f"joints[0] (joint1).{field}: " in problems[0] and message in problems[0], problems


def test_every_problem_at_once(tmp_path):
    src = (TEST_ROBOTS / "actuated_2dof.toml").read_text()
    src = src.replace("gear_ratio = 50", "gear_ratio = 0").replace(
        "rotor_inertia = 0.3", "rotor_inertia = -1")
    p = tmp_path / "bad.toml"
    p.write_text(src)
    with pytest.raises(DescriptionError) as info:
        description.load(p)
    assert len(info.value.problems) == 2
    assert "joint1).actuator.gear_ratio" in info.value.problems[0]
    assert "joint2).actuator.rotor_inertia" in info.value.problems[1]


def test_an_actuator_on_a_passive_joint_is_refused(tmp_path):
    problems = _bad(tmp_path, "actuated = true\n[joints.actuator]",
                    "actuated = false\n[joints.actuator]")
    assert any("only an actuated joint has an actuator" in p for p in problems), problems


@pytest.mark.parametrize("typed, accel, hint", [
    # a kg*m^2 figure typed in this kg*mm^2 file: 5e-13 kg*m^2, 4e10 rad/s^2
    ("5e-07", "4e+10", "in kg*m^2 it would be 4e+04 rad/s^2"),
    # a g*mm^2 figure typed as kg*mm^2: 5e-4 kg*m^2, 40 rad/s^2
    ("500", "40", "in g*mm^2 it would be 4e+04 rad/s^2; in g*cm^2 it would be 400 rad/s^2"),
])
def test_a_rotor_its_motor_could_not_turn_is_asked_about(tmp_path, typed, accel, hint):
    """A trial: a rotor inertia typed in the wrong unit (a kg*cm^2 catalogue figure in a
    g*mm^2 description) passed every check and made the motor torque 3.7 times too low. The
    motor torque limit over J_m, the unloaded rotor's acceleration, is outside 1e2 to 1e7
    rad/s^2 (catalogue motors: 3e3 to 2e5): a warning names the field, the figure and the
    units that would make it plausible. The robot as shipped (0.5 kg*mm^2, 0.02 N*m: 4e4
    rad/s^2) loads without one."""
    src = (TEST_ROBOTS / "actuated_2dof.toml").read_text()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        description.load(TEST_ROBOTS / "actuated_2dof.toml")
    p = tmp_path / "slip.toml"
    p.write_text(src.replace("rotor_inertia = 0.5", f"rotor_inertia = {typed}", 1))
    with pytest.warns(RuntimeWarning) as rec:
        description.load(p)
    said = [str(w.message) for w in rec if "rotor_inertia" in str(w.message)]
    assert len(said) == 1, said
    assert f"joints[0] (joint1).actuator.rotor_inertia: {float(typed):g} kg*mm^2" in said[0]
    assert f"the motor would turn its own rotor at {accel} rad/s^2 unloaded" in said[0]
    assert said[0].endswith(f"a unit slip? ({hint})")
