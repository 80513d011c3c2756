"""One table of quantities (``model.description.quantities``), one rule on every route a value
can enter by: for each quantity a parameter holds and each route (``with_parameters``, a study's
``[parameters]``, ``[control.plant]``, ``planar-sym move --set``, a sweep's range), one likely
slip is warned about, naming the parameter, the value, the unit it was read in and the reading
it probably meant, and one impossible value is refused naming the parameter. The description's
own fields (and the fields only a description has: limits, rpm) by the same table, below.

Before the table, only a sweep warned about a slip (a bare ratio, no reading); ``--set
m_link2=75`` for a 75 g forearm ran silently with a 75 kg one.
"""

from __future__ import annotations

import math
import re
import warnings

import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.errors import DescriptionError, InputError
from planar_sym.model.description.quantities import QUANTITIES, doubt

GEARED = ROOT / "examples" / "serial_2dof_geared.toml"

#: parameter -> (a likely slip in SI as a route reads it, what the warning must say)
SLIPS = {
    "m_link2": (75.0, (r'm_link2 = 75 kg \(read in kg\) is more than osmium .* In "g" it would '
                      r"be 0\.075 kg")),
    "izz_link2": (1.09864e-10, (r"izz_link2 = 1\.09864e-10 kg\*m\^2 \(read in kg\*m\^2\) gives "
                               r"a radius of gyration of 0\.03\d+ mm")),
    # ten times (a cm read as mm): 3.17 times the link's size outside it, the outline's warning
    # (a thousand times is refused, as in the description)
    "cgx_link2": (0.4168, (r"cgx_link2 puts the centre of gravity 316\.8 mm outside the outline "
                          r"of the body's points, 3\.17 times the body's size of 100 mm")),
    "g": (0.00981, r"g = 0\.00981 m/s\^2 \(read in m/s\^2\) is below the plausible 0\.1"),
    "gear_joint1": (0.02, (r"gear_joint1 = 0\.02 is 0\.0004 times the robot's own 50; a slip\? "
                          r"Upside down \(joint turns per motor turn\) it would be 50")),
    "jm_joint1": (0.5, (r'jm_joint1 = 0\.5 kg\*m\^2 \(read in kg\*m\^2\) is 1e\+06 times the '
                       r'robot\'s own 5e-07 kg\*m\^2; a slip\? In "kg\*mm\^2" it would be 5e-07')),
    "fv_joint1": (1.745e-5, (r"fv_joint1 = 1\.745e-05 N\*m\*s/rad \(read in N\*m\*s/rad\) is "
                            r"0\.01745 times .* Per deg/s it would be 0\.0009998")),
    "fc_joint1": (5.0, (r"fc_joint1 = 5 N\*m \(read in N\*m\) is 1000 times the robot's own "
                       r"0\.005 N\*m; a slip\? In N\*mm it would be 0\.005 N\*m")),
    "vs_joint1": (5.0, (r"vs_joint1 = 5 rad/s \(read in rad/s\) is above the plausible 1 rad/s "
                       r"for a Coulomb smoothing speed; a slip\? In deg/s it would be 0\.087266")),
}
#: parameter -> (an impossible value, what the refusal must say)
IMPOSSIBLE = {
    "m_link2": (-0.075, r"m_link2 must be > 0 kg \(got -0\.075\)"),
    "izz_link2": (-1e-4, r"izz_link2 must be >= 0 kg\*m\^2"),
    "cgx_link2": (math.inf, r"cgx_link2\W{0,3} must be finite"),
    "g": (9810.0, r"g \(gravity magnitude\) must be from 0 to 300 m/s\^2 \(got 9810\)"),
    "gear_joint1": (-50.0, r"gear_joint1 \(gear ratio\) must be > 0 \(got -50\)"),
    "jm_joint1": (-1e-7, r"jm_joint1 \(rotor inertia\) must be >= 0 kg\*m\^2"),
    "fv_joint1": (-1e-3, r"fv_joint1 \(viscous friction\) must be >= 0 N\*m\*s/rad"),
    "fc_joint1": (-5e-3, r"fc_joint1 \(Coulomb friction\) must be >= 0 N\*m"),
    "vs_joint1": (0.0, r"vs_joint1 \(Coulomb smoothing speed\) must be > 0 rad/s"),
}
NAMES = list(SLIPS)


@pytest.fixture(scope="module")
def geared():
    return ps.load(GEARED)


def _toml(v: float) -> str:
    return "inf" if v == math.inf else repr(v)


def _study(tmp_path, kind: str, table: str, name: str, v: float) -> str:
    """The S3 study (or its tracking twin) on the geared arm, 11 samples, with ``name = v``
    (SI, written with its unit where the description's units are not SI) in ``table``."""
    text = (ROOT / "planar_sym" / "studies" / f"serial_2dof_cartesian_{kind}.toml").read_text()
    text = text.replace('robot = "serial_2dof"', f'robot = "{GEARED}"').split("[outputs]")[0]
    text = re.sub(r"samples = \d+", "samples = 11", text)
    value = f'"{v!r} kg*m^2"' if name.startswith(("izz", "jm")) else _toml(v)
    if table == "control.plant":
        text = text.replace("m_link2 = 0.09", "m_link2 = 0.09" if name == "m_link2" else
                            f"m_link2 = 0.09\n{name} = {value}")
        if name == "m_link2":
            text = text.replace("m_link2 = 0.09", f"m_link2 = {value}")
    else:
        text += f"\n[{table}]\n{name} = {value}\n"
    path = tmp_path / f"{kind}.toml"
    path.write_text(text)
    return str(path)


def _api(geared, tmp_path, name, v):
    geared.with_parameters(**{name: v})


def _parameters(geared, tmp_path, name, v):
    ps.run_study(_study(tmp_path, "move", "parameters", name, v))


def _plant(geared, tmp_path, name, v):
    ps.run_study(_study(tmp_path, "track", "control.plant", name, v))


def _set(geared, tmp_path, name, v):
    """``planar-sym move --set``: the message comes back as the command printed it."""
    code = main(["move", str(GEARED), "--joint", "--from", "0,0", "--by", "30,0",
                 "--duration", "0.5", "--set", f"{name}={v!r}" + (" kg*m^2" if name.startswith(("izz", "jm"))
                                                       else ""), "--out", str(tmp_path / "o")])
    if code != 0:
        raise InputError("exit code 2")


def _sweep(geared, tmp_path, name, v):
    ps.sweep(_study(tmp_path, "move", "parameters", "m_link1", 0.071), {name: [v, v]})


ROUTES = {"with_parameters": _api, "study [parameters]": _parameters,
          "[control.plant]": _plant, "move --set": _set, "sweep range": _sweep}


@pytest.mark.parametrize("route", ROUTES)
@pytest.mark.parametrize("name", NAMES)
def test_a_slip_is_warned_about(geared, tmp_path, capsys, route, name):
    value, message = SLIPS[name]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            ROUTES[route](geared, tmp_path, name, value)
        except (InputError, ValueError):
            pass  # the slipped robot may fail later (a study it cannot follow): not this test's
    said = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    said += capsys.readouterr().err.splitlines()
    hits = [s for s in said if re.search(message, s)]
    assert len(hits) == 1, said
    if route != "with_parameters":  # the file and table (or the sweep) it came from
        assert re.search(r"(parameters|control\.plant|sweep range|--set)", hits[0]), hits[0]


@pytest.mark.parametrize("route", ROUTES)
@pytest.mark.parametrize("name", NAMES)
def test_an_impossible_value_is_refused(geared, tmp_path, capsys, route, name):
    value, message = IMPOSSIBLE[name]
    with pytest.raises(InputError) as caught:
        ROUTES[route](geared, tmp_path, name, value)
    text = str(caught.value) + capsys.readouterr().err
    assert re.search(message, text), text


def test_a_value_of_ordinary_size_is_quiet(geared):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        geared.with_parameters(m_link2=0.2, izz_link2=2e-4, cgx_link2=0.05, g=3.7,
                               gear_joint1=120.0, jm_joint1=2e-6, fv_joint1=0.01,
                               fc_joint1=0.02, vs_joint1=0.05)


# -- the description's fields, by the same table -------------------------------------------------

#: (field as typed, slip, what the warning says, impossible, what the refusal says)
FIELDS = [
    ("mass = 0.075", "mass = 75.0",
     r'\.mass: 75 kg \(read in kg\) is more than osmium.* In "g" it would be 0\.075 kg',
     "mass = 0.0", r"\.mass: must be > 0 kg \(got 0\)"),
    ("izz = 109.864", "izz = 1.09864e-4",
     (r"\.izz: 0\.000109864 kg\*mm\^2 \(read in kg\*mm\^2, 1\.09864e-10 kg\*m\^2\) gives a "
     r"radius of gyration"), "izz = -1.0", r"\.izz: must be >= 0 kg\*mm\^2 \(got -1\)"),
    ("gear_ratio = 50", "gear_ratio = 0.02",
     r"gear_ratio: 0\.02 is below the plausible 0\.1 for a gear ratio; a slip\? Upside down",
     "gear_ratio = -50", r"gear_ratio: must be > 0 \(got -50\)"),
    ("rotor_inertia = 0.5", "rotor_inertia = 5e6",
     (r'rotor_inertia: 5e\+06 kg\*mm\^2 \(read in kg\*mm\^2, 5 kg\*m\^2\) is above the plausible '
     r'1 kg\*m\^2 for a rotor inertia; a slip\? In "g\*mm\^2"'),
     "rotor_inertia = -0.5", r"rotor_inertia: must be >= 0 kg\*mm\^2"),
    ("viscous_friction = 0.001", "viscous_friction = 2e4",
     r"viscous_friction: 20000 N\*m\*s/rad \(read in N\*m\*s/rad\) is above the plausible",
     "viscous_friction = -1", r"viscous_friction: must be >= 0 N\*m\*s/rad"),
    ("coulomb_friction = 0.005", "coulomb_friction = 5e5",
     (r"coulomb_friction: 500000 N\*m \(read in N\*m\) is above the plausible 100000 N\*m for a "
     r"Coulomb friction; a slip\? In N\*mm it would be 500 N\*m"),
     "coulomb_friction = -1", r"coulomb_friction: must be >= 0 N\*m"),
    ("torque_limit = 0.8", "torque_limit = 8e5",
     r"torque_limit: 800000 N\*m .* above the plausible 100000 N\*m .* In N\*mm it would be 800",
     "torque_limit = 0", r"torque_limit: must be > 0 N\*m \(got 0\)"),
    ("motor_torque_limit = 0.05", "motor_torque_limit = 50000",
     r"motor_torque_limit: 50000 N\*m .* In N\*mm \(mN\*m\) it would be 50 N\*m",
     "motor_torque_limit = -0.05", r"motor_torque_limit: must be > 0 N\*m"),
    ("motor_speed_limit_rpm = 6000", "motor_speed_limit_rpm = 6",
     (r"motor_speed_limit_rpm: 6 rpm \(read in rpm\) is below the plausible 10 rpm for a motor "
     r"speed limit; a slip\? In rad/s it would be 57\.2958 rpm or in thousands of rpm it would "
     r"be 6000 rpm or in rev/s it would be 360 rpm"),
     "motor_speed_limit_rpm = 0", r"motor_speed_limit_rpm: must be > 0 rpm"),
    # the electrical figures go together (one without the other is refused)
    ("torque_constant = 0.05", "torque_constant = 50.0\nwinding_resistance = 1.2",
     (r"torque_constant: 50 N\*m/A \(read in N\*m/A\) is above the plausible 10 N\*m/A for a "
      r"motor torque constant; a slip\? In mN\*m/A it would be 0\.05 N\*m/A"),
     "torque_constant = 0\nwinding_resistance = 1.2", r"torque_constant: must be > 0 N\*m/A"),
    ("winding_resistance = 1.2", "winding_resistance = 1200.0\ntorque_constant = 0.05",
     (r"winding_resistance: 1200 ohm \(read in ohm\) is above the plausible 1000 ohm for a motor "
      r"winding resistance; a slip\? In milliohm it would be 1\.2 ohm"),
     "winding_resistance = -1\ntorque_constant = 0.05", r"winding_resistance: must be > 0 ohm"),
]


def _description(tmp_path, old: str, new: str):
    text = (ROOT / "tests" / "robots" / "actuated_2dof.toml").read_text()
    if "[joints.actuator]" not in text:
        pytest.skip("the actuated test robot lost its actuator table")
    path = tmp_path / "bad.toml"
    # the forearm's figures for the body fields, the first actuator's for the others
    if old.startswith(("mass", "izz")):
        assert old in text, old
        head, _, tail = text.rpartition(old)
        path.write_text(head + new + tail)
    else:
        key = old.split(" = ")[0]
        if re.search(rf"(?m)^{key} = ", text):
            text = re.sub(rf"(?m)^{key} = .*$", new, text, count=1)
        else:
            text = text.replace("[joints.actuator]\n", f"[joints.actuator]\n{new}\n", 1)
        path.write_text(text)
    return path


@pytest.mark.parametrize("field", FIELDS, ids=[f[0].split(" = ")[0] for f in FIELDS])
def test_a_description_field_by_the_same_table(tmp_path, field):
    from planar_sym.model import description

    old, slip, warned, impossible, refused = field
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        description.load(_description(tmp_path, old, slip))
    said = [str(w.message) for w in caught]
    assert sum(bool(re.search(warned, s)) for s in said) == 1, said
    with pytest.raises(DescriptionError, match=refused):
        description.load(_description(tmp_path, old, impossible))


def test_every_quantity_is_tried():
    """The table and these tests move together: each quantity a parameter or a description
    field holds has a slip and an impossible value above."""
    tried = {"mass", "inertia", "length", "gravity", "gear_ratio", "rotor_inertia", "viscous",
             "coulomb", "smoothing", "torque_limit", "motor_torque_limit", "motor_speed_rpm",
             "gear_ratio_slider", "viscous_slider", "coulomb_slider", "smoothing_slider",
             "force_limit", "torque_constant", "winding_resistance"}
    assert set(QUANTITIES) == tried


@pytest.mark.parametrize("name", ["gear_ratio_slider", "viscous_slider", "coulomb_slider",
                                  "smoothing_slider", "force_limit"])
def test_a_slider_quantity_slip_and_impossible_value(name):
    """A prismatic joint's rows: their SI unit in the messages, a slip beyond the plausible
    range warned about, a negative value refused."""
    q = QUANTITIES[name]
    hi = q.plausible[1]
    assert q.unit in doubt(q, hi * 10.0)
    assert doubt(q, hi / 10.0) is None
    assert q.error(-1.0) is not None and q.unit in q.error(-1.0)


def test_a_torque_at_a_passive_joint_is_refused_on_every_route():
    """``simulate`` takes the actuated joints' torques only; ``forward_dynamics`` takes every
    coordinate's, and applied a torque given at a motorless joint (the cart-pole's hinge)
    silently: now refused, naming the joint and the sample. Zero there is fine, and gives
    the generated function's value."""
    import numpy as np

    robot = ps.load(ROOT / "tests" / "robots" / "cart_pole.toml")
    q, qd = np.zeros((3, 2)), np.zeros((3, 2))
    tau = np.array([[1.0, 0.0], [1.0, 0.0], [1.0, 0.5]])
    with pytest.raises(InputError, match=r"joint hinge has no motor .* gives it 0\.5 at sample 2"):
        robot.forward_dynamics(q, qd, tau)
    with pytest.raises(InputError, match=r"one for every actuated joint.*got shape \(2,\)"):
        ps.simulate(robot, [0.0, 0.0], [0.0, 0.0], (0.0, 0.1), torque=[1.0, 0.5])
    qdd = robot.forward_dynamics(q[:2], qd[:2], tau[:2])
    assert np.array_equal(qdd, robot.tree_forward_dynamics(q[:2], qd[:2], tau[:2]))


def test_a_study_s_warnings_reach_its_result_and_page(tmp_path):
    """A slip warned about on stderr is also carried by the study's Result (its metadata, the
    results page and the notebook), once, so a page read later still says it."""
    from planar_sym.outputs.html_index import study_section
    from planar_sym.outputs.notebook import result_html

    def study_with(mass: float) -> str:
        text = (ROOT / "planar_sym" / "studies" / "serial_2dof_joint_move.toml").read_text()
        path = tmp_path / f"joint_move_{mass:g}.toml"
        path.write_text(text.replace('robot = "serial_2dof"', f'robot = "{GEARED}"')
                        .split("[outputs]")[0] + f"\n[parameters]\nm_link2 = {mass!r}\n")
        return str(path)

    study = study_with(75.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = ps.run_study(study)
    shown = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert len(shown) == 1 and result.warnings == (shown[0],)
    assert re.search(SLIPS["m_link2"][1], result.metadata()["warnings"])
    page = study_section(result, tmp_path, embed=False)
    assert page.count('class="warning"') == 1 and "In &quot;g&quot; it would be 0.075 kg" in page
    assert "0.075 kg" in result_html(result, picture=False)
    quiet = ps.run_study(study_with(0.08))
    assert quiet.warnings == () and quiet.metadata()["warnings"] == ""


def test_a_refusal_quotes_what_was_typed_in_the_description_s_units(tmp_path, capsys):
    """`--set m_crank=-5` on a four-bar whose masses are in grams: the rule speaks SI (-0.005
    kg); the refusal also quotes what the student typed, so the two can be matched."""
    code = main(["move", str(ROOT / "examples" / "four_bar.toml"), "--joint", "--from", "60",
                 "--by", "90", "--duration", "1", "--set", "m_crank=-5", "--out",
                 str(tmp_path / "o")])
    assert code == 2
    assert capsys.readouterr().err.strip() == (
        "error: --set: parameter m_crank must be > 0 kg (got -0.005) (typed -5 g)")
