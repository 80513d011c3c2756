"""Your own robot through the command line: ``planar-sym derive X.toml --out DIR``, then
``planar_sym.load(DIR/<name>)``, checked against numbers that do not come from the derivation.

- four_bar (examples/four_bar.toml): power balance ``tau qd_crank = dE/dt`` along a crank
  motion (dE/dt by differences in time), and the loop closing, measured from the body frames;
- heavy_motor_2dof (serial_2dof with a 0.6 kg motor): a point mass dm at the elbow, a1 from
  joint 1, adds dm a1^2 to M11 and dm g a1 cos(q1) to g1, nothing else, so
  ``tau_heavy = tau_serial + [dm a1 (a1 qdd1 + g cos q1), 0]``;
- bad descriptions: every problem of every file printed, exit code 2, nothing written.
"""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest
from conftest import ROOT, copy_builtin

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.errors import LibraryError
from planar_sym.motion.closure import from_actuated

EXAMPLES = ROOT / "examples"
H = 1e-3  # s, time step of the differences
D1 = {-2: 1 / 12, -1: -8 / 12, 1: 8 / 12, 2: -1 / 12}  # 4th-order first derivative


@pytest.fixture(scope="module")
def own(tmp_path_factory):
    """Both example robots derived (and compiled into a private cache) through the CLI."""
    out = tmp_path_factory.mktemp("own")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("PLANAR_SYM_CACHE", str(tmp_path_factory.mktemp("cache")))
        assert main(["derive", str(EXAMPLES / "four_bar.toml"),
                     str(EXAMPLES / "heavy_motor_2dof.toml"), "--out", str(out), "--quiet"]) == 0
        robots = {name: ps.load(out / name) for name in ("four_bar", "heavy_motor_2dof")}
    return out, robots


def test_derived_folder_is_self_contained(own):
    out, robots = own
    folder = out / "four_bar"
    listed = set(json.loads((folder / "manifest.json").read_text())["files"])
    assert {"four_bar.c", "four_bar.h", "equations.txt"} <= listed
    # the generated files, and the description copied beside them
    assert {p.name for p in folder.iterdir()} == listed | {"manifest.json", "description.toml"}
    assert (folder / "description.toml").read_bytes() == (EXAMPLES / "four_bar.toml").read_bytes()
    assert "Phi1 =" in (folder / "equations.txt").read_text()
    four = robots["four_bar"]
    assert four.coordinates == ("crank_joint", "coupler_joint", "rocker_joint")
    assert four.actuated == (0,) and four.loops == ("B",)


def test_load_by_folder_or_by_name_in_a_folder(own):
    out, robots = own
    q = np.array([[0.3, -0.2, 1.0]])
    for robot in (ps.load(str(out / "four_bar")), ps.load("four_bar", generated=out)):
        assert robot.name == "four_bar"
        np.testing.assert_array_equal(robot.mass_matrix(q), robots["four_bar"].mass_matrix(q))
    with pytest.raises(LibraryError, match="four_bar"):
        ps.load("four_bar")  # not built in, not on PLANAR_SYM_GENERATED
    with pytest.raises(LibraryError, match="manifest.json"):
        ps.load(out / "no_such_robot")


def crank_motion(robot, t):
    """Crank at a varying speed, q = q0 + 2 pi t + 0.3 sin(2 pi t); passive joints solved."""
    w = 2 * np.pi
    q = robot.q_drawn[0] + w * t + 0.3 * np.sin(w * t)
    qd = w + 0.3 * w * np.cos(w * t)
    qdd = -0.3 * w ** 2 * np.sin(w * t)
    return from_actuated(robot, t, q[:, None], qd[:, None], qdd[:, None])


def test_four_bar_closes_in_its_drawn_configuration(own):
    four = own[1]["four_bar"]
    assert np.max(np.abs(four.constraint(four.q_drawn))) < 1e-11  # m


def test_four_bar_power_balance_along_a_crank_motion(own):
    """Crank power tau qd equals dE/dt, the energy differenced in time (passive joints and the
    cut joint do no work)."""
    four = own[1]["four_bar"]
    t = np.linspace(0.0, 1.0, 61)
    motion = crank_motion(four, t)
    tau, _ = four.closed_chain_inverse_dynamics(motion.q, motion.qd, motion.qdd)
    power = tau[:, 0] * motion.qd[:, 0]
    energy = {k: sum(four.energy(m.q, m.qd)) for k in D1
              for m in [crank_motion(four, t + k * H)]}
    de_dt = sum(c * energy[k] for k, c in D1.items()) / H
    assert np.max(np.abs(power)) > 0.1  # W: a real load, not a trivial zero
    # differences of Newton-solved positions (|Phi| < 1e-13 m) limit this to ~1e-8 relative
    assert np.max(np.abs(power - de_dt)) < 1e-6 * np.max(np.abs(power))


def test_four_bar_loop_closes_along_the_motion_measured_from_the_frames(own):
    """B from the coupler (A + b along its axis) and from the rocker (O4 + c along its axis),
    using only the body frames: they coincide wherever the solver put the passive joints."""
    four = own[1]["four_bar"]
    motion = crank_motion(four, np.linspace(0.0, 1.0, 61))
    frames = four.frames(motion.q)  # (N, bodies, [x, y, angle])
    body = {name: frames[:, i] for i, name in enumerate(four.body_names)}
    b, c = four.parameters["px_coupler_B"], four.parameters["px_rocker_B"]
    cp, rk = body["coupler"], body["rocker"]
    from_coupler = cp[:, :2] + b * np.column_stack([np.cos(cp[:, 2]), np.sin(cp[:, 2])])
    from_rocker = rk[:, :2] + c * np.column_stack([np.cos(rk[:, 2]), np.sin(rk[:, 2])])
    assert np.max(np.abs(from_coupler - from_rocker)) < 1e-12  # m
    assert np.max(np.abs(four.constraint(motion.q))) < 1e-12


def test_heavy_motor_adds_exactly_the_point_mass_terms(own, rng):
    heavy, serial = own[1]["heavy_motor_2dof"], ps.load("serial_2dof")
    dm = heavy.parameters["m_motor2"] - serial.parameters["m_motor2"]
    a1, g = serial.parameters["px_link1_CS2"], serial.parameters["g"]
    assert dm == pytest.approx(0.308) and a1 == 0.1 and g == 9.81
    q, qd, qdd = (rng.uniform(-3, 3, (50, 2)) for _ in range(3))
    extra = np.zeros((50, 2))
    extra[:, 0] = dm * a1 * (a1 * qdd[:, 0] + g * np.cos(q[:, 0]))
    tau_h = heavy.inverse_dynamics(q, qd, qdd)
    scale = np.max(np.abs(tau_h))
    assert np.max(np.abs(tau_h - (serial.inverse_dynamics(q, qd, qdd) + extra))) < 1e-12 * scale
    dM = heavy.mass_matrix(q) - serial.mass_matrix(q)
    np.testing.assert_allclose(dM, np.broadcast_to([[dm * a1**2, 0], [0, 0]], dM.shape),
                               rtol=1e-12, atol=1e-15)
    assert heavy.with_parameters(m_motor2=0.292).parameters == serial.parameters


def test_bad_descriptions_are_all_reported_and_nothing_is_written(tmp_path, capsys):
    good = copy_builtin(tmp_path, "serial_2dof", "good")
    bad = copy_builtin(tmp_path, "serial_2dof", "bad")
    text = bad.read_text().replace("mass = 0.071", "mass = -0.071")
    bad.write_text("colour = 1\n" + text.replace("izz = 109.864", "izz = -1.0"))
    out = tmp_path / "out"
    assert main(["derive", str(good), str(bad), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    for field in ("bodies[0] (link1).mass", "bodies[2] (link2).izz", "colour"):
        assert f"{bad}: {field}" in err, err
    assert str(good) not in err
    assert not out.exists()


def test_two_descriptions_with_one_name_are_refused(tmp_path, capsys):
    one, two = copy_builtin(tmp_path, "serial_2dof", "one"), copy_builtin(tmp_path, "serial_2dof",
                                                                          "two")
    assert main(["derive", str(one), str(two), "--out", str(tmp_path / "out")]) == 2
    assert "'serial_2dof' is used by several descriptions" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_derive_without_sympy_says_how_to_get_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "sympy", None)  # import sympy now raises ImportError
    code = main(["derive", str(EXAMPLES / "four_bar.toml"), "--out", str(tmp_path / "out")])
    assert code == 2
    assert "deriving needs SymPy: pip install planar-sym[derive]" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_re_deriving_into_the_same_folder_loads_the_new_robot(tmp_path, monkeypatch):
    """Edit the description, derive again into the same folder: load() gives the new one."""
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    toml = tmp_path / "heavy_motor_2dof.toml"
    toml.write_text((EXAMPLES / "heavy_motor_2dof.toml").read_text())
    out = tmp_path / "out"
    assert main(["derive", str(toml), "--out", str(out), "--quiet"]) == 0
    assert ps.load(out / "heavy_motor_2dof").parameters["m_motor2"] == 0.6
    toml.write_text(toml.read_text().replace("mass = 0.6 ", "mass = 0.7 "))
    assert main(["derive", str(toml), "--out", str(out), "--quiet"]) == 0
    assert ps.load(out / "heavy_motor_2dof").parameters["m_motor2"] == 0.7
