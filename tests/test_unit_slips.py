"""Values typed in another unit than the description's [units] say (a design-engineer trial):
each slip is named at its field with the unit that would make it plausible, once, and a loop
left open says how far it misses against the mechanism's size, in the description's unit.

1. A coupler's mass typed in kg in a description in g was blamed on its izz.
2. A body's lengths typed in m in a description in mm (or the ground's) gave a loop-closure
   error with no word about units.
3. A loop that Newton cannot close was reported in mm whatever the description's unit (11860 mm
   for a 10 cm four-bar); ``draw``'s assembly report too.
"""

from __future__ import annotations

import math
import re
import statistics
import warnings
from pathlib import Path

import pytest
from conftest import ROOT

from planar_sym.cli import main
from planar_sym.errors import DescriptionError
from planar_sym.model.description import load

FOUR_BAR = (ROOT / "examples" / "four_bar.toml").read_text()
JOINTS = (ROOT / "examples" / "four_bar_joints.toml").read_text()
COUPLER = "points = { A = [0.0, 0.0], B = [120.0, 0.0], P = [60.0, 30.0] }"
#: the sketch four-bar's lengths in m (a 10 cm mechanism): ground 0.1, crank 0.04, rocker 0.08
IN_M = (('length = "mm"', 'length = "m"'), ("O4 = [100.0, 0.0]", "O4 = [0.1, 0.0]"),
        ("cg = [20.0, 0.0]", "cg = [0.02, 0.0]"), ("A = [40.0, 0.0]", "A = [0.04, 0.0]"),
        ("cg = [40.0, 0.0]", "cg = [0.04, 0.0]"), ("B = [80.0, 0.0]", "B = [0.08, 0.0]"))


def write(tmp_path: Path, text: str, *edits: tuple[str, str]) -> Path:
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    path = tmp_path / "bad.toml"
    path.write_text(text)
    return path


def problems(path: Path) -> list[str]:
    with pytest.raises(DescriptionError) as info:
        load(path)
    assert all(p.startswith(f"{path}: ") for p in info.value.problems)
    return [p.removeprefix(f"{path}: ") for p in info.value.problems]


def warned(path: Path) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load(path)
    return [str(w.message).removeprefix(f"{path}: ") for w in caught
            if issubclass(w.category, RuntimeWarning)]


# -- 1. a mass in the wrong unit is named at the mass, not at izz ---------------------------------

def test_a_coupler_mass_typed_in_kg_for_g_is_blamed_on_the_mass(tmp_path):
    """mass = 0.12 (kg meant) with units.mass = "g": 0.12 g and izz = 144000 g*mm^2 give a
    radius of gyration sqrt(1.44e-4 / 1.2e-4) m = 1095 mm, 18 times the coupler's 60 mm reach
    (A and B 60 mm from its cg); read in kg it is sqrt(1.44e-4 / 0.12) m = 34.64 mm."""
    (got,) = problems(write(tmp_path, FOUR_BAR, ("mass = 120.0", "mass = 0.12")))
    assert got.startswith("bodies[1] (coupler).mass: 0.12 g (read in g, 0.00012 kg) with izz = "
                          "144000 g*mm^2 gives a radius of gyration of "
                          f"{math.sqrt(144000e-9 / 0.12e-3) * 1e3:.4g} mm for a body whose points "
                          "reach 60 mm from its centre of gravity (more than 3 times; izz / "
                          f"(mass * reach^2) = {144000e-9 / (0.12e-3 * 0.06**2):.3g}"), got
    assert got.endswith('a unit slip? The mass (units.mass = "g") read in "kg" would be 0.12 kg, '
                        f"a radius of gyration of {math.sqrt(144000e-9 / 0.12) * 1e3:.4g} mm")
    assert ".izz" not in got


def test_an_inertia_1000_times_too_large_is_still_blamed_on_izz(tmp_path):
    """izz typed 1000 times too large: the mass read in kg (120 kg) would fit the radius, but
    120 kg within 60 mm of the cg is denser than osmium (20.4 kg fill that ball), so izz is
    named, as before."""
    assert 22_590 * 4 / 3 * math.pi * 0.06**3 == pytest.approx(20.44, abs=0.01)
    (got,) = problems(write(tmp_path, FOUR_BAR, ("izz = 144000.0", "izz = 144000000.0")))
    assert got.startswith("bodies[1] (coupler).izz: implausible: 144000000.0 g*mm^2 gives a "
                          "radius of gyration of 1095 mm"), got


def test_a_mass_typed_in_g_for_kg_warns_at_the_mass_not_izz(tmp_path):
    """A 1 m arm of 2 kg typed 2000 (g meant) with units.mass = "kg": izz = 0.05 kg*m^2 gives
    sqrt(0.05 / 2000) m = 5 mm, under 1% of its 800 mm reach, warned at izz before; read in g,
    sqrt(0.05 / 2) m = 158.1 mm."""
    path = tmp_path / "arm.toml"
    path.write_text(ARM)
    (got,) = warned(path)
    assert got.startswith("bodies[0] (arm).mass: 2000 kg (read in kg) with izz = 0.05 kg*m^2 "
                          "gives a radius of gyration of 5 mm for a body whose points reach "
                          "800 mm from its centre of gravity (less than 0.01 times"), got
    assert ('The mass (units.mass = "kg") read in "g" would be 2 kg, a radius of gyration of '
            f"{math.sqrt(0.05 / 2) * 1e3:.4g} mm") in got


ARM = """name = "arm"
gravity = [0.0, -9.81]
[units]
length = "m"
mass = "kg"
inertia = "kg*m^2"
angle = "rad"
acceleration = "m/s^2"
[ground]
points = { O = [0.0, 0.0] }
[[bodies]]
name = "arm"
mass = 2000.0
izz = 0.05
cg = [0.2, 0.0]
cg_from = "O"
points = { O = [0.0, 0.0], T = [1.0, 0.0] }
frame = ["O", "T"]
[[joints]]
name = "j1"
type = "revolute"
parent = "ground.O"
child = "arm.O"
actuated = true
"""


# -- 2. lengths in another unit: named at the body, or as a hint on the loop ----------------------

def test_a_coupler_typed_in_m_is_one_message_at_its_points(tmp_path):
    """The coupler typed in m in a description in mm: its 0.12 mm makes izz's 34.64 mm radius
    577 times its 0.06 mm reach, and the loop cannot close. One message, at its points, with the
    unit that gives a 60 mm reach (a radius 0.577 times it, a uniform rod's 1/sqrt(3))."""
    path = write(tmp_path, JOINTS, ("cg = [60.0, 0.0]", "cg = [0.06, 0.0]"),
                 (COUPLER, "points = { A = [0.0, 0.0], B = [0.12, 0.0], P = [0.06, 0.03] }"))
    (got,) = problems(path)
    assert got.startswith("bodies[1] (coupler).points: 120 g (read in g, 0.12 kg) with izz = "
                          "144000 g*mm^2 gives a radius of gyration of 34.64 mm for a body whose "
                          "points reach 0.06 mm"), got
    assert got.endswith('Its points and cg (units.length = "mm") read in "m" would reach 60 mm, '
                        f"the radius of gyration {1 / math.sqrt(3):.3g} times that")


def test_a_coupler_typed_in_m_in_world_points_is_one_message(tmp_path):
    """The same slip in the world-point four-bar: its joints at A and B do not meet the crank's
    and rocker's either (39.96 and 152.1 mm apart), which says nothing more: one message."""
    old = """cg = [56.940482998, 18.915110255]   # mid-length, from A
cg_from = "A"
# P: a coupler point 30 mm off the line AB, at mid-length (it traces the coupler curve)
points = { A = [20.0, 34.641016151], B = [133.880965996, 72.471236661], P = [67.482927871, 82.026367905] }"""
    new = """cg = [0.056940482998, 0.018915110255]
cg_from = "A"
points = { A = [0.020, 0.034641016151], B = [0.133880965996, 0.072471236661], P = [0.067482927871, 0.082026367905] }"""
    (got,) = problems(write(tmp_path, FOUR_BAR, (old, new)))
    assert got.startswith("bodies[1] (coupler).points: 120 g (read in g, 0.12 kg) with izz = "
                          "144000 g*mm^2 gives a radius of gyration of 34.64 mm"), got
    assert 'read in "m" would reach 60 mm' in got


def test_ground_points_typed_in_m_hint_at_the_unit(tmp_path):
    """O4 = [0.1, 0] (m) in a description in mm: a 0.1 mm ground under links of 40, 120 and
    80 mm (their median 80 mm); read in m it is 100 mm and the loop closes (the example)."""
    (got,) = problems(write(tmp_path, JOINTS, ("O4 = [100.0, 0.0]", "O4 = [0.1, 0.0]")))
    assert got.startswith("joints (B): loop B cannot be closed from the given pose"), got
    assert got.endswith('; a length unit slip? ground.points read in "m" (size 0.1 mm as typed, '
                        "100 mm so read, the others' median 80 mm) would close every loop: were "
                        'they typed in "m", not units.length = "mm"?'), got
    assert load(write(tmp_path, JOINTS)).assembly is not None  # so read: the shipped example


def test_a_link_typed_in_cm_in_a_description_in_m(tmp_path):
    """The 10 cm four-bar in m with its coupler typed in cm (12 for 0.12): Newton leaves the
    loop open by at least 12 - |A O4| - 0.08 = 11.83 m and at most 12 + |A O4| + 0.08 m; the
    message gives it in m, against the median of the sizes 0.1, 0.04, 12 and 0.08 m (0.09 m),
    and names the coupler's points and cm."""
    path = write(tmp_path, JOINTS, *IN_M, ("cg = [60.0, 0.0]", "cg = [6.0, 0.0]"),
                 (COUPLER, "points = { A = [0.0, 0.0], B = [12.0, 0.0], P = [6.0, 3.0] }"))
    (got,) = problems(path)
    a_o4 = math.hypot(0.1 - 0.02, 0.04 * math.sin(math.radians(60)))
    gap = float(re.search(r"its points stay ([0-9.]+) m apart", got)[1])
    assert 12 - a_o4 - 0.08 - 1e-3 <= gap <= 12 + a_o4 + 0.08, got
    times = float(re.search(r"the gap is ([0-9.]+) times the median size of its ground and "
                            r"bodies \(0\.09 m\)", got)[1])
    assert times == pytest.approx(gap / 0.09, rel=5e-3)
    assert got.endswith('bodies[1] (coupler).points read in "cm" (size 12 m as typed, 0.12 m so '
                        "read, the others' median 0.08 m) would close every loop: were they "
                        'typed in "cm", not units.length = "m"?'), got


def test_a_link_merely_too_short_has_no_unit_hint(tmp_path):
    """A 5 mm coupler (A is 87.2 mm from O4, the rocker 80 mm: 7.2 mm is the least reach)
    cannot close. Read in cm it would (50 mm), but 5 mm against the others' median of 80 mm is
    16 times, under the 30 a unit slip needs: no hint. The gap is given against the median of
    the sizes 100, 40, 5 and 80 mm (60 mm)."""
    path = write(tmp_path, JOINTS, ("cg = [60.0, 0.0]", "cg = [2.5, 0.0]"),
                 ("izz = 144000.0", "izz = 250.0"),  # 120 g * (5 mm)^2 / 12
                 ("B = [120.0, 0.0], P = [60.0, 30.0]", "B = [5.0, 0.0], P = [2.5, 3.0]"))
    (got,) = problems(path)
    assert got.startswith("joints (B): loop B cannot be closed from the given pose: its points "
                          "stay "), got
    assert "unit slip" not in got
    gap = float(re.search(r"its points stay ([0-9.]+) mm apart", got)[1])
    times, median = map(float, re.search(r"the gap is ([0-9.]+) times the median size of its "
                                         r"ground and bodies \(([0-9.]+) mm\)", got).groups())
    assert median == pytest.approx(statistics.median([100.0, 40.0, 5.0, 80.0]))
    assert times == pytest.approx(gap / median, rel=5e-3)


# -- 3. the assembly report in the description's unit ---------------------------------------------

def test_draw_reports_the_assembly_in_the_description_unit(tmp_path, capsys):
    """The sketch four-bar typed in m: the 3.347 mm gap and coupler.B's 3.401 mm move of the
    example in mm (tests/test_pose_joints.py, docs) read 0.003347 m and 0.003401 m."""
    path = write(tmp_path, JOINTS, *IN_M, ("cg = [60.0, 0.0]", "cg = [0.06, 0.0]"),
                 (COUPLER, "points = { A = [0.0, 0.0], B = [0.12, 0.0], P = [0.06, 0.03] }"))
    assert main(["draw", str(path), "--out", str(tmp_path / "four.png")]) == 0
    out = capsys.readouterr().out
    assert "  loop B: gap 0.003347 m closed (now " in out, out
    assert "  point coupler.B moved 0.003401 m" in out
    assert " mm" not in out
    report = load(ROOT / "examples" / "four_bar_joints.toml").assembly.report()
    assert "loop B: gap 3.347 mm closed" in report and "point coupler.B moved 3.401 mm" in report
