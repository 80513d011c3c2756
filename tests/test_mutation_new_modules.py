"""Tests written from mutation testing of five modules (``python -m mutation``): the
identified robot's description file, the TOML writer, linearisation, LQR and the regressor.
Each closes a surviving mutant, against something independent: the description reader
reading the written file back, ``tomllib``, closed forms, python-control, the compiled
dynamics. Fast: small descriptions read without deriving (the robot and the identified robot
are stand-ins with the attributes ``identified_description`` reads), and no simulation."""

from __future__ import annotations

import tomllib
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from planar_sym.errors import InputError
from planar_sym.identify.description_file import identified_description
from planar_sym.model.description import load as read_description
from planar_sym.toml_write import dumps

# --- identify/description_file.py ------------------------------------------------------------

#: world pose in mm: a point mass whose points are already named cg and cg1 (the moved mass
#: needs cg2), a body without a frame whose first point is off the origin and whose cg is
#: typed from "world", a turned frame (not along an axis) with the cg typed from a point off
#: both axes, and a body whose cg lies on its y axis only (no cgx parameter)
WORLD_MM = """\
name = "mixed_frames"
title = "Mixed frames (test)"
gravity = [0.0, -9.81]

[units]
length = "mm"
mass = "kg"
inertia = "kg*m^2"
angle = "rad"
acceleration = "m/s^2"

[ground]
points = { O = [0.0, 0.0] }

[[bodies]]
name = "a"
mass = 0.4
mass_at = "cg1"
points = { cg = [0.0, 0.0], cg1 = [100.0, 0.0] }
frame = ["cg", "cg1"]

[[bodies]]
name = "b"
mass = 0.5
izz = 0.0005
cg = [150.0, 20.0]
cg_from = "world"
points = { B = [100.0, 0.0], C = [200.0, 10.0] }

[[bodies]]
name = "c"
mass = 0.5
izz = 0.0005
cg = [10.0, 5.0]
cg_from = "D"
points = { C = [200.0, 10.0], D = [230.0, 40.0], E = [260.0, 90.0] }
frame = ["C", "E"]

[[bodies]]
name = "d"
mass = 0.3
izz = 0.0003
cg = [0.0, 30.0]
cg_from = "E"
points = { E = [260.0, 90.0], F = [360.0, 90.0] }
frame = ["E", "F"]

[[joints]]
name = "j1"
type = "revolute"
parent = "ground.O"
child = "a.cg"
actuated = true

[[joints]]
name = "j2"
type = "revolute"
parent = "a.cg1"
child = "b.B"
actuated = true
actuator = { viscous_friction = 0.01, coulomb_friction = 0.02 }

[[joints]]
name = "j3"
type = "revolute"
parent = "b.C"
child = "c.C"
actuated = true

[[joints]]
name = "j4"
type = "revolute"
parent = "c.E"
child = "d.E"
actuated = true
"""

#: pose = "joints": a body without a frame typed away from its coordinates' origin (the cg is
#: from that origin, not from the first point as in the world pose)
JOINTS_POSE = """\
name = "typed_offsets"
title = "A body typed away from its origin (test)"
pose = "joints"
gravity = [0.0, -9.81]

[units]
length = "m"
mass = "kg"
inertia = "kg*m^2"
angle = "deg"
acceleration = "m/s^2"

[ground]
points = { O = [0.0, 0.0] }

[[bodies]]
name = "arm"
mass = 1.0
izz = 0.01
cg = [0.25, 0.02]
points = { P = [0.1, 0.05], Q = [0.4, 0.05] }

[[joints]]
name = "shoulder"
type = "revolute"
parent = "ground.O"
child = "arm.P"
actuated = true
angle = 10.0
"""

IDENTIFIED = ("m_", "izz_", "cgx_", "cgy_", "jm_", "fv_", "fc_")


def _source(tmp_path: Path, text: str, name: str = "source.toml"):
    path = tmp_path / name
    path.write_text(text)
    values = {p.name: p.value for p in read_description(path).parameters()}
    return SimpleNamespace(name=tomllib.loads(text)["name"], description_file=path), values


def _written_and_read_back(tmp_path, robot, identified: dict) -> dict:
    out = tmp_path / "identified_robot.toml"
    out.write_text(identified_description(robot, SimpleNamespace(parameters=identified)))
    return {p.name: p.value for p in read_description(out).parameters()}


def _assert_read_back(back: dict, identified: dict) -> None:
    assert list(back) == list(identified)  # no parameter added or lost: the same structure
    for k, v in identified.items():
        assert back[k] == pytest.approx(v, rel=1e-12, abs=1e-15), k


def test_every_frame_kind_in_mm_reads_back_to_the_identified_values(tmp_path):
    """Every identified value changed by its own factor: the point mass gets a point of its own
    (cg2: cg and cg1 are taken), and each cg, re-typed in mm in its body's typed frame, reads
    back (through the reader's own frames) as the identified body-frame value."""
    robot, values = _source(tmp_path, WORLD_MM)
    factors = iter(np.linspace(0.75, 1.3, len(values)).tolist())  # Python floats
    identified = {k: (v * next(factors) if k.startswith(IDENTIFIED) else v)
                  for k, v in values.items()}
    assert "cgx_d" not in values and "cgy_d" in values  # d's cg is on its y axis only
    back = _written_and_read_back(tmp_path, robot, identified)
    _assert_read_back(back, identified)
    raw = tomllib.loads((tmp_path / "identified_robot.toml").read_text())
    a = raw["bodies"][0]
    assert a["mass_at"] == "cg2"  # a free name: the joint's point cg and cg1 are kept
    assert a["points"]["cg"] == [0.0, 0.0] and a["points"]["cg1"] == [100.0, 0.0]
    assert a["points"]["cg2"] == pytest.approx([1000 * identified["cgx_a"], 0.0])  # in mm
    assert raw["bodies"][1]["cg_from"] == "world"


def test_a_body_typed_in_its_own_coordinates_keeps_them(tmp_path):
    """pose = "joints", no frame: the cg is typed from the coordinates' origin, not from the
    first point (0.1, 0.05)."""
    robot, values = _source(tmp_path, JOINTS_POSE)
    identified = dict(values, m_arm=1.2, izz_arm=0.012, cgx_arm=0.3, cgy_arm=-0.01)
    back = _written_and_read_back(tmp_path, robot, identified)
    _assert_read_back(back, identified)
    raw = tomllib.loads((tmp_path / "identified_robot.toml").read_text())
    assert raw["pose"] == "joints" and raw["bodies"][0]["cg"] == pytest.approx([0.3, -0.01])


def test_the_header_names_the_source_and_the_note(tmp_path):
    robot, values = _source(tmp_path, JOINTS_POSE, "arm_source.toml")
    ident = SimpleNamespace(parameters=values)
    first = ("# typed_offsets as identified by planar-sym identify, from arm_source.toml: "
             "masses, centres of gravity,")
    second = ("# inertias, rotor inertias and friction are the physically consistent "
              "identified values, in [units].")
    default = identified_description(robot, ident).split("\n")
    assert default[:2] == [first, second]  # no note: no trailing space
    noted = identified_description(robot, ident, "From run 3.").split("\n")
    assert noted[:2] == [first, second + " From run 3."]
    assert tomllib.loads("\n".join(default)) == tomllib.loads(JOINTS_POSE)  # values unchanged


@pytest.mark.parametrize("where", [None, "missing.toml"])
def test_a_robot_without_its_file_is_refused_by_name(tmp_path, where):
    robot = SimpleNamespace(name="arm", description_file=None if where is None
                            else tmp_path / where)
    with pytest.raises(InputError) as err:
        identified_description(robot, robot)
    assert str(err.value) == ("arm: no description file to start from (the robot was not "
                              "loaded from one): the identified values are in "
                              "identified_parameters.toml")


# --- toml_write.py -----------------------------------------------------------------------------

def test_keys_are_bare_where_toml_allows_and_quoted_elsewhere():
    table = {"name": "x", "cg_from": "world", "rotor-inertia": 1.5, "a b": 1, "x.y": 2,
             "": 3, "units": {"inertia": "kg*m^2", "kg*m": 1}}
    text = dumps(table)
    assert text == ('name = "x"\ncg_from = "world"\nrotor-inertia = 1.5\n"a b" = 1\n'
                    '"x.y" = 2\n"" = 3\n\n[units]\ninertia = "kg*m^2"\n"kg*m" = 1\n')
    assert tomllib.loads(text) == table


def test_arrays_of_tables_are_written_as_tables():
    table = {"name": "r", "bodies": [{"name": "a", "points": {"O": [0.0, 1.0]}},
                                     {"name": "b", "mass": 2}], "empty": [], "nums": [1, 2]}
    text = dumps(table)
    assert text == ('name = "r"\nempty = []\nnums = [1, 2]\n\n[[bodies]]\nname = "a"\n'
                    'points = { O = [0.0, 1.0] }\n\n[[bodies]]\nname = "b"\nmass = 2\n')
    assert tomllib.loads(text) == table


def test_a_value_toml_cannot_hold_is_refused_by_name():
    with pytest.raises(TypeError) as err:
        dumps({"x": {1, 2}})
    assert str(err.value) == "cannot write {1, 2} as TOML"
    with pytest.raises(TypeError) as err:
        dumps({"t": {"y": None}})
    assert str(err.value) == "cannot write None as TOML"


# --- dynamics/linearize.py -----------------------------------------------------------------------

UP = np.pi / 2  # the cart-pole's pole points along +x at q = 0: upright is a quarter turn


def _cart_pole():
    import planar_sym as ps

    return ps.load("tests/robots/cart_pole.toml")


@pytest.mark.parametrize("kwargs, message", [
    ({"q": [0.0]}, "q must have shape (N, 2) or (2,), got (1,)"),
    ({"q": [0.0, UP], "qd": [0.0]}, "qd must have shape (N, 2) or (2,), got (1,)"),
    ({"q": [0.0, UP], "tau": [1.0, 2.0]}, "tau must have shape (N, 1) or (1,), got (2,)"),
])
def test_linearize_names_the_bad_input(kwargs, message):
    import planar_sym as ps

    with pytest.raises(InputError) as err:
        ps.linearize(_cart_pole(), **kwargs)
    assert str(err.value) == message


def test_linearize_refuses_a_closed_chain_off_its_loops_by_name():
    import planar_sym as ps

    robot = ps.load("five_bar_type1")
    with pytest.raises(InputError) as err:
        ps.linearize(robot, np.asarray(robot.q_drawn) + [0.0, 0.1, 0.0, 0.0])
    assert str(err.value).startswith("q is off five_bar_type1's loops (|Phi| = ")
    assert str(err.value).endswith("m): give a pose on the loops, or its actuated "
                                   "coordinates only")


def test_state_space_names_its_states_inputs_and_outputs():
    pytest.importorskip("control")
    import planar_sym as ps

    lin = ps.linearize(_cart_pole(), [0.0, UP])
    sys = lin.state_space()
    states = ["slide (m)", "hinge (rad)", "slide_rate (m/s)", "hinge_rate (rad/s)"]
    assert list(lin.states) == states and list(lin.inputs) == ["slide (N)"]
    assert sys.state_labels == states and sys.output_labels == states
    assert sys.input_labels == ["slide (N)"]
    assert np.array_equal(sys.C, np.eye(4)) and np.array_equal(sys.D, np.zeros((4, 1)))


def test_state_space_without_python_control_says_what_to_install(monkeypatch):
    import sys

    import planar_sym as ps

    lin = ps.linearize(_cart_pole(), [0.0, UP])
    monkeypatch.setitem(sys.modules, "control", None)  # import control raises ImportError
    with pytest.raises(InputError) as err:
        lin.state_space()
    assert str(err.value) == ("state_space() needs python-control: pip install control "
                              "(Linearization.a and .b are the matrices)")


# --- control/lqr.py ------------------------------------------------------------------------------

Q_W, R_W = [10.0, 50.0, 1.0, 1.0], 0.1


def _lqr(**kwargs):
    import planar_sym as ps

    kw = {"q_weight": Q_W, "r_weight": R_W, **kwargs}
    return ps.lqr(_cart_pole(), [0.0, UP], kw.pop("qd", None), kw.pop("tau", None), **kw)


def test_riccati_solution_solves_the_riccati_equation():
    control = pytest.importorskip("control")
    design = _lqr()
    lin = design.linearization
    a, b, p = lin.a, lin.b, design.riccati
    q, r = np.diag(Q_W), np.array([[R_W]])
    residual = a.T @ p + p @ a - p @ b @ np.linalg.solve(r, b.T @ p) + q
    assert np.abs(residual).max() <= 1e-9 * np.abs(p).max() * np.abs(a).max()
    _, s, _ = control.lqr(a, b, q, r)
    assert np.abs(p - s).max() <= 1e-9 * np.abs(s).max()


def test_a_cart_moving_at_constant_speed_is_held_at_that_speed():
    """Upright pole, cart at 0.5 m/s: no acceleration (no friction), so an equilibrium; the law
    holds that speed: x_ref carries it."""
    design = _lqr(qd=[0.5, 0.0])
    assert design.linearization.qd.tolist() == [0.5, 0.0]
    assert design.controller().x_ref == pytest.approx((0.0, UP, 0.5, 0.0), abs=0)


def test_an_equilibrium_within_rounding_of_the_scale_is_accepted():
    """The cart-pole's largest entry of A is 42.3 1/s^2 (the pole's gravity stiffness): an
    acceleration 1e-9 of that is rounding, not a motion. tau = 1.2e-8 N gives qdd of 2.1e-8 m/s^2 (cart) and 2.0e-8 rad/s^2
    (pole) at the upright, below 1e-9 * 42.3: accepted; 1e-6 N is refused."""
    robot = _cart_pole()
    tau = 1.2e-8
    qdd = robot.tree_forward_dynamics([0.0, UP], [0.0, 0.0], [tau, 0.0])
    scale = np.abs(_lqr().linearization.a).max()
    assert 1e-9 < np.abs(qdd).max() < 1e-9 * scale
    design = _lqr(tau=[tau])
    assert design.linearization.tau.tolist() == [tau] and design.controller().u_ref == (tau,)
    with pytest.raises(InputError, match="not an equilibrium"):
        _lqr(tau=[1e-6])


def test_a_state_that_is_not_an_equilibrium_is_refused_with_its_acceleration():
    robot = _cart_pole()
    with pytest.raises(InputError) as err:
        _lqr(tau=[1.0])
    msg = str(err.value)
    head, tail = "cart_pole: not an equilibrium (qdd = [", ("] there): LQR holds a state that "
                                                            "stays put; give the torques that "
                                                            "hold it (tau) or another q")
    assert msg.startswith(head) and msg.endswith(tail)
    qdd = [float(v) for v in msg[len(head):-len(tail)].split(",")]
    expected = robot.tree_forward_dynamics([0.0, UP], [0.0, 0.0], [1.0, 0.0])
    assert qdd == pytest.approx(expected, rel=1e-12)
    assert expected[0] == pytest.approx(0.4862069, rel=1e-6)  # b: M^-1 of the cart's force


def test_an_unweighted_unstable_motion_is_refused():
    """Nothing weighs the cart: its double integrator is left where it is (poles at 0), or the
    Riccati solver finds no stabilising solution."""
    with pytest.raises(InputError) as err:
        _lqr(q_weight=[0.0, 1.0, 0.0, 1.0], r_weight=1.0)
    msg = str(err.value)
    assert msg.startswith("cart_pole: the LQR loop is not stable (poles [")
    assert msg.endswith("]): weight every state that can drift (q_weight)")
    with pytest.raises(InputError) as err:
        _lqr(q_weight=[0.0, 50.0, 0.0, 1.0], r_weight=1.0)
    msg = str(err.value)
    # which of the two refusals depends on rounding: SciPy's Riccati solver fails on one CPU
    # (Intel, AVX-512) and returns a gain whose loop keeps the cart's poles at 1e-16 on another
    # (AMD EPYC); either way no gain is given
    if msg.startswith("cart_pole: the LQR loop is not stable (poles ["):
        assert msg.endswith("]): weight every state that can drift (q_weight)")
    else:
        assert msg.startswith("cart_pole: no stabilising LQR gain at this state (")
        assert msg.endswith("): the motors cannot reach an unstable motion, or q_weight leaves "
                            "an unstable motion unweighted")


def test_a_semi_definite_state_weight_is_enough():
    """No weight on the cart's speed (a zero eigenvalue of Q): still a design, whose gain is
    python-control's."""
    control = pytest.importorskip("control")
    design = _lqr(q_weight=[10.0, 50.0, 0.0, 1.0])
    k, _, _ = control.lqr(design.linearization.a, design.linearization.b,
                          np.diag([10.0, 50.0, 0.0, 1.0]), [[R_W]])
    assert np.abs(design.gain - k).max() <= 1e-9 * np.abs(k).max()
    assert np.all(design.poles.real < 0)


@pytest.mark.parametrize("kwargs, message", [
    ({"q_weight": [1.0, -1.0, 1.0, 1.0]},
     "q_weight must be positive semi-definite (smallest eigenvalue -1)"),
    ({"r_weight": -2.0}, "r_weight must be positive definite (smallest eigenvalue -2)"),
    ({"q_weight": "heavy"}, "q_weight must be numbers: 4 (a diagonal) or 4x4, got 'heavy'"),
    ({"q_weight": [1.0, np.inf, 1.0, 1.0]}, "q_weight must be finite and symmetric"),
    ({"q_weight": np.diag(Q_W) + np.triu(np.full((4, 4), 1e-3), 1)},
     "q_weight must be finite and symmetric"),
    # 1e-6-scale weights off symmetric by 1e-13 (1e-7 of them, not rounding)
    ({"q_weight": np.diag([1e-6] * 4) + np.triu(np.full((4, 4), 1e-13), 1)},
     "q_weight must be finite and symmetric"),
])
def test_weights_are_refused_by_name(kwargs, message):
    with pytest.raises(InputError) as err:
        _lqr(**kwargs)
    assert str(err.value) == message


def test_a_weight_symmetric_to_rounding_is_taken():
    """1e6-scale weights off symmetric by 1e-9 (1e-15 of them): rounding, accepted, and the
    gain is python-control's for the symmetric part."""
    control = pytest.importorskip("control")
    q = np.diag([1e6, 5e6, 1e5, 1e5])
    q[0, 1], q[1, 0] = 1e3 + 1e-9, 1e3
    design = _lqr(q_weight=q)
    lin = design.linearization
    k, _, _ = control.lqr(lin.a, lin.b, (q + q.T) / 2, [[R_W]])
    assert np.abs(design.gain - k).max() <= 1e-7 * np.abs(k).max()


def test_the_controller_saturates_unless_told_not_to():
    design = _lqr()
    assert design.controller().saturate is True
    assert design.controller(saturate=False).saturate is False
    assert design.controller().gain == pytest.approx(tuple(design.gain.ravel()), abs=0)


# --- identify/regressor.py -----------------------------------------------------------------------

def _regressor_module():
    import importlib

    # (the package exports the function regressor, which hides the module of that name)
    return importlib.import_module("planar_sym.identify.regressor")


def _tree_states(n_samples=6):
    import planar_sym as ps
    from planar_sym.identify.states import random_states

    robot = ps.load("serial_2dof").with_parameters()  # a new robot: no callers bound yet
    return robot, *random_states(robot, n_samples, seed=5)


def _spy(monkeypatch, module, name):
    calls, real = [], getattr(module, name)

    def spy(*args, **kwargs):
        calls.append(args[1] if name == "loop_caller" else args[0])
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, spy)
    return calls


def test_a_float64_batch_goes_straight_to_the_compiled_loop(monkeypatch):
    """A (N, n) float64 C-contiguous batch of q, qd and qdd skips the Python checks
    (as_samples); any one input that is not (float32, Fortran order, a list) sends all three
    through them. Either way Y pi is the compiled inverse dynamics."""
    from planar_sym.identify.standard import standard_parameters

    reg = _regressor_module()
    robot, q, qd, qdd = _tree_states()
    if reg.loop_caller(robot, "regressor") is None:
        pytest.skip("no vectorised regressor loop in this build (no compiler)")
    calls = _spy(monkeypatch, reg, "as_samples")
    pi = standard_parameters(robot).values
    tau = robot.tree_inverse_dynamics(q, qd, qdd)
    y = reg.regressor(robot, q, qd, qdd)
    assert calls == []
    assert np.abs(y.y @ pi - tau).max() <= 1e-12 * np.abs(tau).max()
    for k in range(3):
        for other in (np.float32, "F", list):
            arrays = [q, qd, qdd]
            arrays[k] = (arrays[k].tolist() if other is list else np.asfortranarray(arrays[k])
                         if other == "F" else arrays[k].astype(np.float32))
            calls.clear()
            got = reg.regressor(robot, *arrays)
            assert calls == ["q", "qd", "qdd"], (k, other)
            if other is not np.float32:
                assert np.array_equal(got.y, y.y)


def test_the_vectorised_loop_is_bound_once_per_robot_and_quantity(monkeypatch):
    """The first call binds the loop of the quantity it needs (the tree's regressor, a closed
    chain's closed_regressor), and Y pi is still the inverse dynamics."""
    import planar_sym as ps
    from planar_sym.identify.standard import standard_parameters
    from planar_sym.identify.states import random_states

    reg = _regressor_module()
    robot = ps.load("five_bar_type1").with_parameters()
    if reg.loop_caller(robot, "closed_regressor") is None:
        pytest.skip("no vectorised regressor loop in this build (no compiler)")
    calls = _spy(monkeypatch, reg, "loop_caller")
    q, qd, qdd = random_states(robot, 5, seed=2)
    for _ in range(2):
        out = reg.regressor(robot, q, qd, qdd)
    assert calls == ["closed_regressor"]
    assert out.rows == (0, 2)  # its actuated coordinates: A and E of (A, B, E, D)
    tau, lam = robot.closed_chain_inverse_dynamics(q, qd, qdd)
    pi = standard_parameters(robot).values
    assert np.abs(out.y @ pi - tau).max() <= 1e-12 * np.abs(tau).max()
    assert np.abs(out.y_lambda @ pi - lam).max() <= 1e-12 * np.abs(lam).max()
    tree, q, qd, qdd = _tree_states()
    calls.clear()
    for _ in range(2):
        out = reg.regressor(tree, q.tolist(), qd.tolist(), qdd.tolist())
    assert calls == ["regressor"] and out.rows == (0, 1) and out.y_lambda is None


@pytest.mark.parametrize("bad", [0, 1, 2])
def test_a_list_of_the_wrong_width_is_named(bad):
    robot, q, qd, qdd = _tree_states(5)
    arrays = [q.tolist(), qd.tolist(), qdd.tolist()]
    arrays[bad] = [[0.0] * 3] * 5
    with pytest.raises(InputError) as err:
        _regressor_module().regressor(robot, *arrays)
    assert str(err.value) == f"{('q', 'qd', 'qdd')[bad]} must have shape (N, 2) or (2,), got (5, 3)"


def test_a_refused_sample_is_named_with_its_time():
    import planar_sym as ps
    from planar_sym.identify.states import random_states

    reg = _regressor_module()
    robot, q, qd, qdd = _tree_states(5)
    t = np.linspace(0.0, 0.4, 5)
    qd[3, 1] = np.nan
    with pytest.raises(InputError) as err:
        reg.regressor(robot, q, qd, qdd, t=t)
    assert str(err.value) == "qd[3, 1] is nan at sample 3 (t = 0.3 s): inputs must be finite"
    closed = ps.load("five_bar_type1")
    q, qd, qdd = random_states(closed, 5, seed=1)
    q[3, 0] += 1e-3
    with pytest.raises(InputError, match=r"^five_bar_type1: sample 3 \(t = 0\.3 s\) is off the "
                                         r"loop constraints: \|Phi\| = "):
        reg.regressor(closed, q, qd, qdd, t=t)


def test_keys_outside_ascii_are_quoted_and_numpy_numbers_written_as_numbers():
    """Two bugs the mutation run found in toml_write: a non-ASCII key written bare (TOML
    refuses it) and a NumPy float written as np.float64(0.3)."""
    import tomllib

    import numpy as np

    from planar_sym.toml_write import dumps

    table = {"é": 1, "x²": 2.5, "a": {"b": np.float64(0.3), "c": np.int64(4),
                                      "d": np.bool_(True)}}
    back = tomllib.loads(dumps(table))
    assert back == {"é": 1, "x²": 2.5, "a": {"b": 0.3, "c": 4, "d": True}}
    assert type(back["a"]["c"]) is int
