"""One mistake, one message (issue 10): a single slip in a built-in description is reported once,
naming its field, and never followed by what it causes downstream (points that coincide, joints
or loops that do not close, unknown bodies or points, a degree-of-freedom count of a robot with
a part left out, radius-of-gyration errors of a length-unit slip).

Each case edits one thing of a real description; before the fix 19 of 83 such single mistakes
gave two to four messages (a bad point became (0, 0) and opened every joint at it, a body with a
broken name made every joint naming it 'unknown', a misspelt joint type also made 'actuated'
missing...).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest
from conftest import ROBOTS_DIR, ROOT

from planar_sym.errors import DescriptionError
from planar_sym.model import description

SERIAL = (ROBOTS_DIR / "serial_2dof.toml").read_text()
FIVE_BAR = (ROBOTS_DIR / "five_bar_type1.toml").read_text()
RRR = (ROBOTS_DIR / "parallel_3rrr.toml").read_text()
FOUR_BAR = (ROOT / "examples" / "four_bar.toml").read_text()
ASSEMBLED = FOUR_BAR.replace('name = "four_bar"', 'name = "four_bar"\nassemble = true', 1)
JOINTS = (ROOT / "examples" / "four_bar_joints.toml").read_text()

UNITS = '[units]\nlength = "m"\nmass = "kg"\ninertia = "kg*mm^2"\nangle = "rad"\n' \
        'acceleration = "m/s^2"\n'

#: (id, description, old, new, the field the one message names)
CASES = [
    # a point that is not [x, y]: the body is not built, so nothing is closed against (0, 0)
    ("point_3_vector", SERIAL, "CS1 = [0.0, 0.0], CS2 = [0.1, 0.0] }",
     "CS1 = [0.0, 0.0], CS2 = [0.1, 0.0, 0.0] }", "bodies[0] (link1).points.CS2"),
    ("point_table", SERIAL, "CS1 = [0.0, 0.0], CS2 = [0.1, 0.0] }",
     "CS1 = [0.0, 0.0], CS2 = {x = 0.1} }", "bodies[0] (link1).points.CS2"),
    ("point_not_a_number", SERIAL, "CS1 = [0.0, 0.0], CS2 = [0.1, 0.0] }",
     'CS1 = [0.0, 0.0], CS2 = [0.1, "zero"] }', "bodies[0] (link1).points.CS2[1]"),
    ("point_nan", SERIAL, "CS1 = [0.0, 0.0], CS2 = [0.1, 0.0] }",
     "CS1 = [0.0, 0.0], CS2 = [0.1, nan] }", "bodies[0] (link1).points.CS2"),
    ("point_name_not_identifier", SERIAL, "CS2 = [0.2, 0.0] }", '"C S2" = [0.2, 0.0] }',
     "bodies[2] (link2).points.C S2"),
    ("loop_point_3_vector", FIVE_BAR, "CS2 = [0.037, 0.140] }\nframe",
     "CS2 = [0.037, 0.140, 0.0] }\nframe", "bodies[3] (R_Link2).points.CS2"),
    ("ground_point_one_number", FIVE_BAR, "E = [0.074, 0.0]", "E = [0.074]", "ground.points.E"),
    ("rrr_point_3_vector", RRR, "CS2 = [", "CS2 = [0, ", "bodies[0] (Link1_1).points.CS2"),
    ("four_bar_point_3_vector", FOUR_BAR, "B = [133.880965996, 72.471236661] }",
     "B = [133.880965996, 72.471236661, 0] }", "bodies[2] (rocker).points.B"),
    ("assembled_point_one_number", ASSEMBLED, "B = [133.880965996, 72.471236661] }",
     "B = [133.880965996] }", "bodies[2] (rocker).points.B"),
    ("joints_pose_point_table", JOINTS, "B = [80.0, 0.0] }", "B = {x = 80.0} }",
     "bodies[2] (rocker).points.B"),
    ("points_missing", SERIAL, "points = { CS1 = [0.1, 0.0], CS2 = [0.2, 0.0] }\n", "",
     "bodies[2] (link2).points"),
    ("points_string", SERIAL, "points = { CS1 = [0.1, 0.0], CS2 = [0.2, 0.0] }",
     'points = "CS1 CS2"', "bodies[2] (link2).points"),
    # the centre of gravity, the frame
    ("cg_3_vector", SERIAL, "cg = [0.0373, 0.0]", "cg = [0.0373, 0.0, 0.0]",
     "bodies[0] (link1).cg"),
    ("cg_from_unknown_point", FOUR_BAR, 'cg_from = "A"', 'cg_from = "AA"',
     "bodies[1] (coupler).cg_from"),
    ("cg_typed_in_mm", SERIAL, "cg = [0.04168, 0.0]", "cg = [41.68, 0.0]",
     "bodies[2] (link2).cg"),
    ("frame_unknown_point", SERIAL, 'frame = ["CS1", "CS2"]', 'frame = ["CS1", "CS9"]',
     "bodies[0] (link1).frame"),
    ("frame_points_coincide", SERIAL, 'frame = ["CS1", "CS2"]', 'frame = ["CS1", "CS1"]',
     "bodies[0] (link1).frame"),
    ("frame_in_assembled_robot", ASSEMBLED, 'frame = ["O4", "B"]', 'frame = ["O4", "BB"]',
     "bodies[2] (rocker).frame"),
    # units
    ("units_length_unknown", SERIAL, 'length = "m"', 'length = "in"', "units.length"),
    ("units_length_unknown_3rrr", RRR, 'length = "m"', 'length = "km"', "units.length"),
    ("units_length_slip", SERIAL, 'length = "m"', 'length = "mm"', "units.length"),
    ("units_length_slip_5bar", FIVE_BAR, 'length = "m"', 'length = "mm"', "units.length"),
    ("units_angle_unknown_joints_pose", JOINTS, 'angle = "deg"', 'angle = "degree"',
     "units.angle"),
    ("units_not_a_table", SERIAL, UNITS, 'units = "SI"\n', "units"),
    # bodies' names, joints naming bodies
    ("body_name_missing", SERIAL, 'name = "link2"\n', "", "bodies[2].name"),
    ("body_name_not_a_string", SERIAL, 'name = "link2"', "name = 2", "bodies[2].name"),
    ("body_name_not_identifier", SERIAL, 'name = "link2"', 'name = "link 2"',
     "bodies[2] (link 2).name"),
    ("body_named_ground", SERIAL, 'name = "link2"', 'name = "ground"', "bodies[2] (ground).name"),
    ("body_name_duplicate", SERIAL, 'name = "link2"', 'name = "link1"', "bodies[2].name"),
    ("loop_body_name_missing", FIVE_BAR, 'name = "R_Link2"  # D -> C\n', "", "bodies[3].name"),
    ("bodies_header_misspelt", SERIAL, '[[bodies]]\nname = "link1"', '[[bodys]]\nname = "link1"',
     "bodys"),
    ("joint_body_misspelt", SERIAL, 'child = "link2.CS1"', 'child = "link9.CS1"',
     "joints[2] (joint2).child"),
    ("loop_joint_body_misspelt", FIVE_BAR, 'child = "R_Link2.CS1"', 'child = "R_Link9.CS1"',
     "joints[3] (D).child"),
    ("joint_point_misspelt", SERIAL, 'child = "link2.CS1"', 'child = "link2.CS9"',
     "joints[2] (joint2).child"),
    ("joint_type_misspelt", SERIAL, 'type = "weld"', 'type = "welded"',
     "joints[1] (weld_motor2).type"),
    ("joint_prismatic_without_axis", FIVE_BAR, 'type = "revolute"', 'type = "prismatic"',
     "joints[0] (A).axis"),
    ("joint_type_unknown", FIVE_BAR, 'type = "revolute"', 'type = "slider"',
     "joints[0] (A).type"),
    ("loop_joint_name_missing", FIVE_BAR, 'name = "D"\n', "", "joints[3].name"),
    ("joint_angle_not_a_number", JOINTS, "angle = -40.0", 'angle = "-40 deg"',
     "joints[1] (coupler_joint).angle"),
    ("task_body_misspelt", SERIAL, 'point = "link2.CS2"', 'point = "link3.CS2"', "task.point"),
    # gravity, masses
    ("gravity_string", SERIAL, "gravity = [0.0, -9.81]", 'gravity = "down"', "gravity"),
    ("gravity_3_vector", SERIAL, "gravity = [0.0, -9.81]", "gravity = [0.0, -9.81, 0.0]",
     "gravity"),
    ("gravity_in_mm", SERIAL, "gravity = [0.0, -9.81]", "gravity = [0.0, -9810.0]", "gravity"),
    ("mass_string", SERIAL, "mass = 0.071", 'mass = "heavy"', "bodies[0] (link1).mass"),
    ("mass_negative_joints_pose", JOINTS, "mass = 120.0", "mass = -120.0",
     "bodies[1] (coupler).mass"),
    ("inertia_negative", FIVE_BAR, "izz = 90.992", "izz = -90.992", "bodies[3] (R_Link2).izz"),
    # display names
    ("symbol_empty", SERIAL, 'm_link1 = "m_1"', 'm_link1 = ""', "symbols.m_link1"),
    ("symbol_bad_latex", SERIAL, 'm_link1 = "m_1"', 'm_link1 = "m_{1"', "symbols.m_link1"),
]


@pytest.mark.parametrize(("text", "old", "new", "field"), [c[1:] for c in CASES],
                         ids=[c[0] for c in CASES])
def test_one_mistake_one_message(tmp_path: Path, text, old, new, field):
    assert text.count(old) >= 1, f"edit does not apply: {old!r}"
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(DescriptionError) as info:
            description.load(path)
    problems = info.value.problems
    assert len(problems) == 1, "\n".join(problems)
    assert problems[0].startswith(f"{path}: {field}: "), problems[0]
    assert not caught, [str(w.message) for w in caught]


def test_enough_cases():
    assert len(CASES) >= 40
    assert len({c[0] for c in CASES}) == len(CASES)


def test_the_unedited_descriptions_load(tmp_path):
    for k, text in enumerate((SERIAL, FIVE_BAR, RRR, FOUR_BAR, ASSEMBLED, JOINTS)):
        path = tmp_path / f"ok{k}.toml"
        path.write_text(text)
        assert description.load(path).bodies


def test_two_independent_mistakes_are_both_reported(tmp_path):
    """Skipping follow-ons does not hide a second, unrelated mistake."""
    text = SERIAL.replace("mass = 0.071", "mass = -0.071", 1).replace(
        'child = "link2.CS1"', 'child = "link2.CS9"', 1)
    path = tmp_path / "two.toml"
    path.write_text(text)
    with pytest.raises(DescriptionError) as info:
        description.load(path)
    assert [p.removeprefix(f"{path}: ").split(":")[0] for p in info.value.problems] == [
        "bodies[0] (link1).mass", "joints[2] (joint2).child"]
