"""Plausibility rules (issue 10, "never silently wrong"): values that read cleanly but cannot be
what was meant. Lengths against their unit (the robot's span), gravity against the planets', a
centre of gravity far outside its body, display names the equation report could not show.

Each rule is checked on a single slip of a real description (a message naming the file and the
field, with the figure), at its boundary, and on every description the project ships (none
trips a rule).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import pytest
from conftest import ROBOTS_DIR, ROOT, TEST_ROBOTS

from planar_sym.errors import DescriptionError
from planar_sym.model import description
from planar_sym.model.description import types
from planar_sym.model.parameters import problems as parameter_problems

SERIAL = (ROBOTS_DIR / "serial_2dof.toml").read_text()
FOUR_BAR = (ROOT / "examples" / "four_bar.toml").read_text()
FOUR_BAR_JOINTS = (ROOT / "examples" / "four_bar_joints.toml").read_text()
PENDULUM = (TEST_ROBOTS / "pendulum.toml").read_text()


def edited(tmp_path: Path, text: str, *edits: tuple[str, str], name: str = "bad") -> Path:
    for old, new in edits:
        assert old in text, f"test edit does not apply: {old!r}"
        text = text.replace(old, new, 1)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def refused(path: Path) -> str:
    """The one problem of ``path`` (asserting there is exactly one, naming the file)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(DescriptionError) as info:
            description.load(path)
    assert len(info.value.problems) == 1, info.value.problems
    assert not caught, "a description with errors shows no warning"
    problem = info.value.problems[0]
    assert problem.startswith(f"{path}: "), problem
    return problem.removeprefix(f"{path}: ")


def warned(path: Path) -> list[str]:
    """The warnings of loading ``path`` (which must load), file prefix removed."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        description.load(path)
    texts = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert all(t.startswith(f"{path}: ") for t in texts), texts
    return [t.removeprefix(f"{path}: ") for t in texts]


# -- joint angles against units.angle --------------------------------------------------------------

def test_joint_angles_in_degrees_typed_with_rad_warn(tmp_path):
    """-60 with units.angle = "rad": 9.55 turns, drawn at 162.3 deg; one warning per angle
    beyond a turn, none for angles within one (the other two joints)."""
    shown = warned(edited(tmp_path, FOUR_BAR_JOINTS, ('angle = "deg"', 'angle = "rad"'),
                          ("angle = 60.0", "angle = -60.0"), ("angle = -40.0", "angle = -0.349"),
                          ("angle = 65.0", "angle = 2.618")))
    assert shown == [('joints[0] (crank_joint).angle: -60 rad is 9.55 turns (a warning beyond '
                     'one): the drawn pose takes it as 162.3 deg; were the angles typed in '
                     'degrees? (units.angle = "deg" makes it -60 deg)')]


def test_an_angle_of_one_turn_does_not_warn(tmp_path):
    assert types.ANGLE_TURN_RAD == pytest.approx(6.283185307179586)
    # the sketch's own angles (60, -40, 65 deg), the first a turn away: -300 deg = -5.236 rad
    path = edited(tmp_path, FOUR_BAR_JOINTS, ('angle = "deg"', 'angle = "rad"'),
                  ("angle = 60.0", "angle = -5.236"), ("angle = -40.0", "angle = -0.698"),
                  ("angle = 65.0", "angle = 1.134"))
    assert warned(path) == []


# -- the robot's span against units.length ------------------------------------------------------

def test_lengths_in_m_typed_with_mm_is_an_error(tmp_path):
    problem = refused(edited(tmp_path, SERIAL, ('length = "m"', 'length = "mm"')))
    assert problem.startswith("units.length: the robot spans 0.2 mm (from ground.O to "
                              "link2.CS2): below 1 mm")
    assert 'units.length = "m" makes it 200 mm' in problem
    # the radius-of-gyration check of each link says nothing more about the same slip
    assert "izz" not in problem


def test_lengths_in_mm_typed_with_m_warns(tmp_path):
    texts = warned(edited(tmp_path, FOUR_BAR, ('length = "mm"', 'length = "m"')))
    assert texts == [(
        'units.length: the robot spans 152.2 m (from ground.O2 to coupler.B) (a warning above '
        '100 m: only the largest cranes are that big); were the lengths typed in another unit? '
        '(units.length = "cm" makes it 1.522 m, "mm" makes it 152.2 mm)')]


def test_one_link_of_150_typed_in_m_warns(tmp_path):
    texts = warned(edited(tmp_path, SERIAL, ("CS2 = [0.2, 0.0] }", "CS2 = [150.0, 0.0] }")))
    assert len(texts) == 1
    assert texts[0].startswith("units.length: the robot spans 150 m (from ground.O to "
                               "link2.CS2)")
    assert '"mm" makes it 150 mm' in texts[0]


def test_a_kilometre_is_an_error(tmp_path):
    problem = refused(edited(tmp_path, SERIAL, ("CS2 = [0.2, 0.0] }", "CS2 = [1500.0, 0.0] }")))
    assert problem.startswith("units.length: the robot spans 1500 m")
    assert "no planar linkage is a kilometre across" in problem


def test_span_just_below_the_warning_is_quiet(tmp_path):
    found = warned(edited(tmp_path, SERIAL, ("CS2 = [0.2, 0.0] }", "CS2 = [99.0, 0.0] }")))
    # no span warning; a 99 m forearm with its 75 g within 38 mm of its cg is doubted on its own,
    # at its points: read in mm they reach 98.86 mm, the radius of gyration 0.387 times that
    assert [w.split(":")[0] for w in found] == ["bodies[2] (link2).points"]
    assert 'read in "mm" would reach 98.86 mm' in found[0]


def test_pose_joints_span_is_a_bound(tmp_path):
    """Bodies in their own coordinates: the largest body is a lower bound of the span."""
    texts = warned(edited(tmp_path, FOUR_BAR_JOINTS, ('length = "mm"', 'length = "m"')))
    assert len(texts) == 1
    assert texts[0].startswith("units.length: the robot spans at least 120 m (coupler.A to "
                               "coupler.B)")


def test_the_figures():
    assert (types.SIZE_MIN_M, types.SIZE_LARGE_M, types.SIZE_MAX_M) == (1e-3, 100.0, 1000.0)
    # the smallest span is 100 times the closure tolerance: the tolerance is 1% of it
    assert types.SIZE_MIN_M == 100 * types.CLOSURE_TOLERANCE_M
    assert (types.G_LOW, types.G_HIGH, types.G_LIMIT) == (0.1, 30.0, 300.0)
    assert (types.CG_WARN, types.CG_ERROR) == (1.0, 10.0)


# -- gravity ---------------------------------------------------------------------------------------

def test_gravity_in_mm_typed_with_m_is_an_error(tmp_path):
    problem = refused(edited(tmp_path, SERIAL, ("gravity = [0.0, -9.81]",
                                                "gravity = [0.0, -9810.0]")))
    assert problem == ("gravity: magnitude 9810 m/s^2 is above 300 m/s^2 (the Sun's surface "
                       "gives 274; run-time parameters are refused beyond it too); typed in "
                       'another unit? (units.acceleration = "mm/s^2" makes it 9.81 m/s^2)')


def test_gravity_in_m_typed_with_mm_warns(tmp_path):
    texts = warned(edited(tmp_path, SERIAL, ('acceleration = "m/s^2"',
                                             'acceleration = "mm/s^2"')))
    assert texts == [(
        "gravity: magnitude 0.00981 m/s^2 is less than any planet's (Pluto: 0.62; a warning "
        "below 0.1 m/s^2; gravity = [0, 0] says a horizontal robot); typed in another unit? "
        '(units.acceleration = "m/s^2" makes it 9.81 m/s^2)')]


@pytest.mark.parametrize(("g", "warns"), [("98.1", True), ("30.1", True), ("29.9", False),
                                          ("300.0", True), ("0.11", False), ("0.09", True),
                                          ("0.0", False), ("24.8", False), ("1.62", False)])
def test_gravity_bounds(tmp_path, g, warns):
    texts = warned(edited(tmp_path, SERIAL, ("gravity = [0.0, -9.81]", f"gravity = [0.0, -{g}]")))
    assert len(texts) == int(warns), texts
    if warns:
        assert texts[0].startswith(f"gravity: magnitude {float(g):.4g} m/s^2 is ")


def test_gravity_typed_in_cm_is_named_not_sent_to_mm(tmp_path):
    """-981 (cm/s^2 meant, a unit with no name here) with m/s^2 is refused, and the hint no
    longer sends the user to mm/s^2 (0.981 m/s^2: ten times too small, which passed without a
    word); typed with mm/s^2, that 0.981 m/s^2 is warned about as Earth's times 1e-1 (found in
    a user trial: the exported model fell ten times too slowly)."""
    problem = refused(edited(tmp_path, SERIAL, ("gravity = [0.0, -9.81]",
                                                "gravity = [0.0, -981.0]")))
    assert problem == ("gravity: magnitude 981 m/s^2 is above 300 m/s^2 (the Sun's surface "
                       "gives 274; run-time parameters are refused beyond it too); it is "
                       "Earth's 9.81 m/s^2 times 1e+2: a decimal slip, or cm/s^2 (no unit "
                       "here: give it in m/s^2)?")
    texts = warned(edited(tmp_path, SERIAL, ("gravity = [0.0, -9.81]", "gravity = [0.0, -981.0]"),
                          ('acceleration = "m/s^2"', 'acceleration = "mm/s^2"')))
    assert texts == [("gravity: magnitude 0.981 m/s^2 is Earth's 9.81 m/s^2 times 1e-1: a unit or "
                     "decimal slip? (cm/s^2 typed as mm/s^2 gives this: give gravity in m/s^2; "
                     "a robot on a tilted table feels g sin(tilt), which may be anything: then "
                     "ignore this)")]
    for g in ("1.0", "0.9", "3.71"):  # not Earth's times a power of ten (2%): no word
        assert warned(edited(tmp_path, SERIAL, ("gravity = [0.0, -9.81]",
                                                f"gravity = [0.0, -{g}]"))) == []


def test_gravity_just_above_the_limit_is_an_error(tmp_path):
    problem = refused(edited(tmp_path, SERIAL, ("gravity = [0.0, -9.81]",
                                                "gravity = [300.5, 0.0]")))
    assert problem.startswith("gravity: magnitude 300.5 m/s^2 is above 300 m/s^2")


def test_one_gravity_limit_for_descriptions_and_runtime():
    from planar_sym.model.description.quantities import QUANTITIES

    assert QUANTITIES["gravity"].high is description.G_LIMIT == 300.0
    assert parameter_problems({"g": 300.0}, ()) == []
    assert parameter_problems({"g": 300.5}, ()) == [
        "parameter g (gravity magnitude) must be from 0 to 300 m/s^2 (got 300.5); a unit slip?"]


# -- centre of gravity against its body ----------------------------------------------------------

def test_cg_in_world_coordinates_warns(tmp_path):
    """The rocker's cg typed as its world x (100 mm too far): 1.13 times its 80 mm beyond B."""
    texts = warned(edited(tmp_path, FOUR_BAR, ("cg = [16.940482998, 36.235618330]",
                                               "cg = [116.940482998, 36.235618330]")))
    assert texts == [(
        "bodies[2] (rocker).cg: the centre of gravity lies 90.62 mm outside the outline of the "
        "body's points, 1.13 times the body's size of 80 mm (a warning beyond 1 times, an error "
        "beyond 10); cg is measured from cg_from = 'O4' in world axes: does cg_from name the "
        "wrong point, or is cg in world coordinates or another unit? If the mass is really "
        "there, give the body a point there")]


def test_cg_in_mm_in_a_metre_file_is_an_error(tmp_path):
    problem = refused(edited(tmp_path, SERIAL, ("cg = [0.04168, 0.0]", "cg = [41.68, 0.0]")))
    assert problem.startswith("bodies[2] (link2).cg: the centre of gravity lies 41.58 m outside "
                              "the outline of the body's points, 416 times the body's size of "
                              "100 mm")


def test_single_point_body_is_measured_against_the_robot(tmp_path):
    problem = refused(edited(tmp_path, SERIAL, ("cg = [0.0, 0.0]", "cg = [5.0, 0.0]")))
    assert problem.startswith("bodies[1] (motor2).cg: the centre of gravity lies 5 m outside")
    assert "times the robot's span (the body has a single point)" in problem


@pytest.mark.parametrize(("across", "warns"), [(0.36, False), (0.44, True)])
def test_cg_off_a_link_at_the_figure(tmp_path, across, warns):
    """The pendulum's rod is 0.4 m long: 0.9 times that off its axis is quiet, 1.1 warns."""
    texts = warned(edited(tmp_path, PENDULUM, ("cg = [0.25, 0.0]", f"cg = [0.2, {across}]")))
    assert len(texts) == int(warns)
    if warns:
        assert texts[0].startswith("bodies[0] (rod).cg: the centre of gravity lies 440 mm "
                                   "outside the outline of the body's points, 1.1 times")


def test_cg_inside_a_triangle_is_quiet(tmp_path):
    text = PENDULUM.replace("CS2 = [0.4, 0.0] }", "CS2 = [0.4, 0.0], T = [0.2, 0.3] }")
    assert warned(edited(tmp_path, text, ("cg = [0.25, 0.0]", "cg = [0.2, 0.1]"))) == []


def test_cg_in_pose_joints_names_the_body_coordinates(tmp_path):
    texts = warned(edited(tmp_path, FOUR_BAR_JOINTS, ("cg = [40.0, 0.0]", "cg = [40.0, 100.0]")))
    assert len(texts) == 1
    assert texts[0].startswith("bodies[2] (rocker).cg: the centre of gravity lies 100 mm "
                               "outside the outline of the body's points, 1.25 times")
    assert "measured from the origin in the body's own coordinates" in texts[0]


# -- display names ([symbols]) -------------------------------------------------------------------

@pytest.mark.parametrize(("shown", "why"), [
    ('""', "is empty: the equations would show nothing for it"),
    ('"   "', "is empty"),
    ('"m_{1"', "is not valid LaTeX (Expected end_group, found end of text)"),
    (r'"\\thetaa"', r"is not valid LaTeX (Unknown symbol: \thetaa)"),
    ('"{}"', "is not valid LaTeX (it shows nothing)"),
    ('"x^"', "is not valid LaTeX"),
    ('"$m_1$"', "contains '$': write it without math delimiters"),
])
def test_bad_display_name_is_refused(tmp_path, shown, why):
    problem = refused(edited(tmp_path, SERIAL, ('m_link1 = "m_1"', f"m_link1 = {shown}")))
    assert problem.startswith("symbols.m_link1: display name ")
    assert "of parameter m_link1" in problem
    assert why in problem


@pytest.mark.parametrize("shown", [r"\\theta_{2}", r"m_{\\mathrm{motor}}", "I_{zz}",
                                   r"\\text{motor}", "l_c1", r"\\dot{m}_1", "m'"])
def test_latex_the_reports_use_is_kept(tmp_path, shown):
    desc = description.load(edited(tmp_path, SERIAL, ('m_link1 = "m_1"', f'm_link1 = "{shown}"')))
    assert desc.display["m_link1"] == shown.replace("\\\\", "\\")


def test_mathtext_is_imported_only_for_a_symbols_table():
    code = ("import sys, planar_sym\n"
            "from planar_sym.model import description\n"
            f"description.load({str(TEST_ROBOTS / 'pendulum.toml')!r})\n"
            "print('mathtext' if 'matplotlib.mathtext' in sys.modules else 'none')\n"
            "description.load('serial_2dof')\n"
            "print('mathtext' if 'matplotlib.mathtext' in sys.modules else 'none')\n"
            "print('sympy' if 'sympy' in sys.modules else 'no sympy')\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=ROOT).stdout.split()
    assert out == ["none", "mathtext", "no", "sympy"]


# -- how warnings are shown ------------------------------------------------------------------------

def test_a_warning_is_shown_once_per_file(tmp_path):
    path = edited(tmp_path, FOUR_BAR, ('length = "mm"', 'length = "m"'))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(3):
            description.load(path)
    assert len(caught) == 1
    assert "units.length" in str(caught[0].message)


def test_errors_hide_the_warnings(tmp_path):
    path = edited(tmp_path, FOUR_BAR, ('length = "mm"', 'length = "m"'),
                  ("mass = 50.0", "mass = 0.0"))
    assert refused(path) == "bodies[0] (crank).mass: must be > 0 g (got 0)"


def test_command_line_prints_one_warning_line(tmp_path, capsys):
    from planar_sym.cli import main

    path = edited(tmp_path, FOUR_BAR, ('length = "mm"', 'length = "m"'))
    assert main(["draw", str(path), "--out", str(tmp_path / "big.png")]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err == [(f"warning: {path}: units.length: the robot spans 152.2 m (from ground.O2 "
                    "to coupler.B) (a warning above 100 m: only the largest cranes are that "
                    'big); were the lengths typed in another unit? (units.length = "cm" makes '
                    'it 1.522 m, "mm" makes it 152.2 mm)')]


# -- everything the project ships passes every rule --------------------------------------------

SHIPPED = sorted([*ROBOTS_DIR.glob("*.toml"), *TEST_ROBOTS.glob("*.toml"),
                  *(p for p in (ROOT / "examples").glob("*.toml")
                    if "[[bodies]]" in p.read_text())])


@pytest.mark.parametrize("path", SHIPPED, ids=[p.name for p in SHIPPED])
def test_shipped_descriptions_trip_no_rule(tmp_path, path):
    copy = tmp_path / path.name  # a fresh path: no warning already shown for it
    shutil.copyfile(path, copy)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        description.load(copy)


def test_every_shipped_kind_is_there():
    names = {p.name for p in SHIPPED}
    assert {"serial_2dof.toml", "parallel_3rrr.toml", "pendulum.toml", "four_bar.toml",
            "four_bar_joints.toml"} <= names


def test_an_inertia_typed_in_another_unit_names_the_unit_that_fits(tmp_path):
    """A link's izz = 109.864 (kg*mm^2) read in kg*m^2: refused, and the hint names the unit
    that gives it a plausible radius of gyration, as the mass and the warnings already did
    (it said only 'a unit or decimal-point slip?'; user trial)."""
    problem = refused(edited(tmp_path, SERIAL, ("izz = 109.864", "izz = 109864.0")))
    assert problem.endswith('a slip? In "g*mm^2" it would be 0.000109864 kg*m^2'), problem
    problem = refused(edited(tmp_path, SERIAL, ('inertia = "kg*mm^2"', 'inertia = "kg*m^2"'),
                             ("izz = 89.395", "izz = 0.000089395")))
    assert 'a slip? In "kg*mm^2" it would be 0.000109864 kg*m^2 or' in problem, problem
