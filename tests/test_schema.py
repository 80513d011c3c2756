"""The JSON Schemas of the description and study formats (``planar_sym/schemas``), for editors.

* The shipped files are what ``planar_sym.study.schema`` writes now (as tests/test_generated_fresh
  does for generated code): regenerate with ``planar-sym schema``.
* They are draft-07 schemas, and every shipped description and study validates against them.
* The other way: mistakes the validators refuse for an unknown key, a wrong choice or a wrong
  type (cases of tests/test_cascades.py and of the error catalogue) are refused by the schema
  too; those only the validators can see (a point a joint names, a unit slip) are listed.
* The rules repeated as if/then (which kind needs which section) agree with ``spec.parse``.
* The generator refuses to build a schema that has drifted from a validator's table.
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import pytest
from conftest import ROBOTS_DIR, ROOT, TEST_ROBOTS
from test_cascades import CASES

from planar_sym.cli import main, parser
from planar_sym.commands.list import classify
from planar_sym.commands.move import study_table
from planar_sym.errors import DescriptionError
from planar_sym.model import description
from planar_sym.study import schema, spec
from planar_sym.study.checks import StudyError

jsonschema = pytest.importorskip("jsonschema")

SCHEMAS = schema.schemas()
VALIDATORS = {k: jsonschema.Draft7Validator(s) for k, s in SCHEMAS.items()}


def schema_errors(kind: str, data: dict) -> list[str]:
    return [f"{'.'.join(map(str, e.absolute_path))}: {e.message}"
            for e in VALIDATORS[kind].iter_errors(data)]


def shipped() -> list[tuple[str, Path]]:
    files = [*ROBOTS_DIR.glob("*.toml"), *(ROOT / "planar_sym" / "studies").glob("*.toml"),
             *(ROOT / "examples").glob("*.toml"), *TEST_ROBOTS.glob("*.toml"),
             *(ROOT / "tests" / "data").rglob("*.toml")]
    kinds = {"robot": "description", "study": "study"}
    return [(kinds[classify(p)], p) for p in sorted(files)]


# -- the files ----------------------------------------------------------------------------------

def test_shipped_schemas_are_what_the_generator_writes():
    stale = schema.stale()
    assert not stale, (f"{[str(p.relative_to(ROOT)) for p in stale]} differ from what "
                       "planar_sym.study.schema writes: run `planar-sym schema`")


def test_schemas_are_draft_07_and_ship_in_the_package():
    for kind, s in SCHEMAS.items():
        jsonschema.Draft7Validator.check_schema(s)
        assert s["$schema"] == "http://json-schema.org/draft-07/schema#"
        assert (schema.FOLDER / schema.FILES[kind]).is_file()
    assert schema.FOLDER == ROOT / "planar_sym" / "schemas"


def test_every_key_has_a_description_and_numbers_take_expressions():
    """Every key of every table (if/then/else only repeat keys) says what it holds."""
    def walk(node, path):
        for key, sub in node.get("properties", {}).items():
            assert sub.get("description"), f"{path}.{key} has no description"
            walk(sub, f"{path}.{key}")
        for word in ("items", "additionalProperties"):
            if isinstance(node.get(word), dict):
                walk(node[word], f"{path}[]")
        for sub in node.get("anyOf", ()):
            walk(sub, path)

    for kind, s in SCHEMAS.items():
        walk(s, kind)
    mass = SCHEMAS["description"]["properties"]["bodies"]["items"]["properties"]["mass"]
    assert mass["type"] == ["number", "string"]
    assert SCHEMAS["study"]["properties"]["motion"]["additionalProperties"] is False


@pytest.mark.parametrize(("kind", "path"), shipped(),
                         ids=[str(p.relative_to(ROOT)) for _, p in shipped()])
def test_every_shipped_file_validates(kind, path):
    errors = schema_errors(kind, tomllib.loads(path.read_text()))
    assert not errors, f"{path.relative_to(ROOT)}: {errors}"


def test_enough_files():
    kinds = [k for k, _ in shipped()]
    assert kinds.count("description") >= 30 and kinds.count("study") >= 20


# -- mistakes: descriptions ---------------------------------------------------------------------

#: tests/test_cascades.py cases the schema refuses too: unknown keys, wrong types and choices,
#: points that are not [x, y], names that are not identifiers, missing keys
SCHEMA_REFUSES = {
    "point_3_vector", "point_table", "point_name_not_identifier", "loop_point_3_vector",
    "ground_point_one_number", "rrr_point_3_vector", "four_bar_point_3_vector",
    "assembled_point_one_number", "joints_pose_point_table", "points_missing", "points_string",
    "cg_3_vector", "units_length_unknown", "units_length_unknown_3rrr",
    "units_angle_unknown_joints_pose", "units_not_a_table", "body_name_missing",
    "body_name_not_a_string", "body_name_not_identifier", "body_named_ground",
    "loop_body_name_missing", "bodies_header_misspelt", "joint_type_misspelt",
    "joint_prismatic_without_axis", "joint_type_unknown", "loop_joint_name_missing",
    "gravity_string", "gravity_3_vector",
}
#: those only the validator sees: what a name refers to, values (a string at a number's place
#: is an expression to the schema), unit slips, duplicates, geometry
VALIDATOR_ONLY = {
    "point_not_a_number", "point_nan", "cg_from_unknown_point", "cg_typed_in_mm",
    "frame_unknown_point", "frame_points_coincide", "frame_in_assembled_robot",
    "units_length_slip", "units_length_slip_5bar", "body_name_duplicate", "joint_body_misspelt",
    "loop_joint_body_misspelt", "joint_point_misspelt", "joint_angle_not_a_number",
    "task_body_misspelt", "gravity_in_mm", "mass_string", "mass_negative_joints_pose",
    "inertia_negative", "symbol_empty", "symbol_bad_latex",
}
CASE = {c[0]: c[1:] for c in CASES}


def edited(text: str, old: str, new: str) -> dict:
    assert old in text, old
    return tomllib.loads(text.replace(old, new, 1))


def test_the_case_lists_name_cascade_cases():
    assert SCHEMA_REFUSES | VALIDATOR_ONLY <= set(CASE)
    assert not SCHEMA_REFUSES & VALIDATOR_ONLY


@pytest.mark.parametrize("case", sorted(SCHEMA_REFUSES))
def test_cascade_mistakes_the_schema_refuses(case):
    text, old, new, _ = CASE[case]
    assert schema_errors("description", edited(text, old, new)), case


@pytest.mark.parametrize("case", sorted(VALIDATOR_ONLY))
def test_cascade_mistakes_only_the_validator_sees(case):
    text, old, new, _ = CASE[case]
    assert not schema_errors("description", edited(text, old, new)), case


SERIAL = (ROBOTS_DIR / "serial_2dof.toml").read_text()
JOINTS = (ROOT / "examples" / "four_bar_joints.toml").read_text()
SLIDER = (ROBOTS_DIR / "slider_crank.toml").read_text()

#: (id, text, old, new): more mistakes, each refused by both (the error catalogue's among them)
DESCRIPTION_MISTAKES = [
    ("body_key_typo", SERIAL, "mass = 0.071", "mas = 0.071"),
    ("unknown_table", SERIAL, "[ground]", "[colours]\nlink1 = \"red\"\n\n[ground]"),
    ("actuated_string", SERIAL, "actuated = true", 'actuated = "yes"'),
    ("actuated_missing", SERIAL, "actuated = true\n", ""),
    ("mass_unit", SERIAL, 'mass = "kg"', 'mass = "lb"'),
    ("inertia_unit", SERIAL, 'inertia = "kg*mm^2"', 'inertia = "kg*in^2"'),
    ("angle_unit", SERIAL, 'angle = "rad"', 'angle = "grad"'),
    ("ground_key", SERIAL, "points = { O = [0.0, 0.0] }",
     "points = { O = [0.0, 0.0] }\ncolour = 1"),
    ("task_key", SERIAL, 'point = "link2.CS2"', 'point = "link2.CS2"\ntool = "gripper"'),
    ("task_point_not_a_reference", SERIAL, 'point = "link2.CS2"', 'point = "link2"'),
    ("pose_choice", SERIAL, 'name = "serial_2dof"', 'name = "serial_2dof"\npose = "local"'),
    ("assemble_string", SERIAL, 'name = "serial_2dof"', 'name = "serial_2dof"\nassemble = "yes"'),
    ("robot_name_not_identifier", SERIAL, 'name = "serial_2dof"', 'name = "serial 2dof"'),
    ("angle_with_pose_world", SERIAL, "actuated = true\n", "actuated = true\nangle = 0.5\n"),
    ("izz_with_mass_at", SERIAL, 'cg = [0.0, 0.0]\ncg_from = "CS1"\npoints = { CS1 = [0.1, 0.0] }',
     'mass_at = "CS1"\ncg = [0.0, 0.0]\npoints = { CS1 = [0.1, 0.0] }'),
    ("cg_from_missing", SERIAL, 'cg_from = "CS1"\npoints = { CS1 = [0.0, 0.0]',
     "points = { CS1 = [0.0, 0.0]"),
    ("axis_on_a_hinge", SERIAL, "actuated = true\n", "actuated = true\naxis = [1.0, 0.0]\n"),
    ("actuator_key", SLIDER, "actuated = true", "actuated = true\nactuator = { gear = 10.0 }"),
    ("actuator_figure_string_list", SLIDER, "actuated = true",
     "actuated = true\nactuator = { gear_ratio = [10.0] }"),
    ("constant_built_in", SERIAL, "[units]", "[constants]\npi = 3.0\n\n[units]"),
    ("symbols_not_strings", SERIAL, 'm_link1 = "m_1"', "m_link1 = 1"),
    ("frame_three_points", SERIAL, 'frame = ["CS1", "CS2"]', 'frame = ["CS1", "CS2", "CS1"]'),
]


@pytest.mark.parametrize(("text", "old", "new"), [m[1:] for m in DESCRIPTION_MISTAKES],
                         ids=[m[0] for m in DESCRIPTION_MISTAKES])
def test_description_mistakes_refused_by_both(tmp_path, text, old, new):
    data = edited(text, old, new)
    assert schema_errors("description", data)
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(DescriptionError):
        description.load(path)


# -- mistakes: studies --------------------------------------------------------------------------

SECTIONS = {
    "motion": 'space = "task"\nstart = [100.0, 100.0]\nby = [-200.0, 0.0]\nduration = 5.0',
    "simulation": "q0 = [0.0, 0.0]\nduration = 1.0",
    "control": 'law = "computed_torque"\nnatural_frequency_hz = 4.0',
    "events": 'on_joint_limit = "stop"',
    "optimise": "torque_limit = [1.0, 1.0]",
    "optimal": "start = [0.0, 0.0]\nend = [10.0, 10.0]\nduration = 1.0",
}


def study(kind: str, *sections: str, edit: tuple[str, str] | None = None) -> str:
    text = f'robot = "serial_2dof"\nkind = "{kind}"\n\n[units]\nlength = "mm"\n'
    text += "".join(f"\n[{s}]\n{SECTIONS[s]}\n" for s in sections)
    if edit is not None:
        assert edit[0] in text, edit
        text = text.replace(*edit, 1)
    return text


def validator_problems(data: dict) -> list[str]:
    try:
        spec.parse(data, "study")
    except StudyError as exc:
        return exc.problems
    return []


def both(text: str) -> tuple[list[str], list[str]]:
    data = tomllib.loads(text)
    return validator_problems(data), schema_errors("study", data)


INVERSE = ("inverse", "motion")
CONTROL = ("control", "motion", "control")
FORWARD = ("forward", "simulation")
#: (id, study, (old, new)): each refused by both
STUDY_MISTAKES = [
    ("unknown_key", INVERSE, ('kind = "inverse"', 'kind = "inverse"\ncolour = "red"')),
    ("robot_number", INVERSE, ('robot = "serial_2dof"', "robot = 3")),
    ("kind_choice", INVERSE, ('kind = "inverse"', 'kind = "backward"')),
    ("length_unit", INVERSE, ('length = "mm"', 'length = "furlong"')),
    ("units_key", INVERSE, ('length = "mm"', 'length = "mm"\ntime = "ms"')),
    ("space_choice", INVERSE, ('space = "task"', 'space = "sideways"')),
    ("profile_choice", INVERSE, ('space = "task"', 'space = "task"\nprofile = "zigzag"')),
    ("samples_too_few", INVERSE, ("duration = 5.0", "duration = 5.0\nsamples = 1")),
    ("samples_text", INVERSE, ("duration = 5.0", 'duration = 5.0\nsamples = "many"')),
    ("start_string", INVERSE, ("start = [100.0, 100.0]", 'start = "100, 100"')),
    ("motion_key", INVERSE, ("duration = 5.0", "duration = 5.0\nspeed = 1.0")),
    ("ik_choice", INVERSE, ('space = "task"', 'space = "task"\nik = "jacobian"')),
    ("method_choice", FORWARD, ("duration = 1.0", 'duration = 1.0\nmethod = "euler"')),
    ("torque_word", FORWARD, ("duration = 1.0", 'duration = 1.0\ntorque = "none"')),
    ("torque_interpolation", FORWARD,
     ("duration = 1.0", 'duration = 1.0\ntorque = { file = "t.csv", interpolation = "spline" }')),
    ("torque_profile_key", FORWARD,
     ("duration = 1.0", ('duration = 1.0\ntorque = { profile = "cubic", start = [0.0, 0.0], '
                         'end = [1.0, 1.0], duration = 1.0, hold = true }'))),
    ("law_choice", CONTROL, ('law = "computed_torque"', 'law = "pid"')),
    ("control_method_choice", CONTROL,
     ("natural_frequency_hz = 4.0", 'natural_frequency_hz = 4.0\nmethod = "RK45"')),
    ("saturate_string", CONTROL, ("natural_frequency_hz = 4.0",
                                  'natural_frequency_hz = 4.0\nsaturate = "yes"')),
    ("plant_boolean", CONTROL, ("natural_frequency_hz = 4.0",
                                "natural_frequency_hz = 4.0\nplant = { m_link1 = true }")),
    ("on_limit_choice", ("control", "motion", "control", "events"),
     ('on_joint_limit = "stop"', 'on_joint_limit = "halt"')),
    ("joint_limit_one_number", ("control", "motion", "control", "events"),
     ('on_joint_limit = "stop"', "joint_limits = { q1 = [-1.0] }")),
    ("objective_choice", ("optimal", "optimal"), ("duration = 1.0", ('duration = 1.0\n'
                                                                     'objective = "fast"'))),
    ("intervals_too_many", ("optimal", "optimal"), ("duration = 1.0", ("duration = 1.0\n"
                                                                       "intervals = 100000"))),
    ("animation_format", INVERSE, ("duration = 5.0", ('duration = 5.0\n\n[outputs]\n'
                                                      'animation = "avi"'))),
    ("frames_too_few", INVERSE, ("duration = 5.0", "duration = 5.0\n\n[outputs]\nframes = 1")),
    ("csv_string", INVERSE, ("duration = 5.0", 'duration = 5.0\n\n[outputs]\ncsv = "yes"')),
    ("parameter_boolean", INVERSE, ('length = "mm"', ('length = "mm"\n\n[parameters]\n'
                                                      "m_link1 = false"))),
    ("constant_name", INVERSE, ('length = "mm"', ('length = "mm"\n\n[constants]\n'
                                                  '"2a" = 1.0'))),
]


@pytest.mark.parametrize(("sections", "edit"), [m[1:] for m in STUDY_MISTAKES],
                         ids=[m[0] for m in STUDY_MISTAKES])
def test_study_mistakes_refused_by_both(sections, edit):
    problems, errors = both(study(*sections, edit=edit))
    assert problems, "the validator accepts it"
    assert errors, f"the schema accepts it (the validator: {problems})"


@pytest.mark.parametrize("kind", spec.KINDS)
def test_sections_by_kind_agree_with_the_validator(kind):
    """``schema.KIND_SECTIONS``: a section a kind requires, left out, and one it refuses,
    added, are refused by both, the refusal naming the section."""
    requires, refuses = schema.KIND_SECTIONS[kind]
    problems, errors = both(study(kind, *requires))
    assert not problems and not errors, (problems, errors)
    for section in requires:
        rest = [s for s in requires if s != section]
        problems, errors = both(study(kind, *rest))
        assert any(p.startswith(f"{section}: ") for p in problems), (kind, section, problems)
        assert errors, (kind, section)
    for section in refuses:
        problems, errors = both(study(kind, *requires, section))
        assert any(p.startswith(f"{section}: ") for p in problems), (kind, section, problems)
        assert errors, (kind, section)
    allowed = set(SECTIONS) - set(requires) - set(refuses)
    if kind == "optimal":  # events go with its optional control: the next test
        allowed.discard("events")
    for section in sorted(allowed):
        problems, errors = both(study(kind, *requires, section))
        assert not problems and not errors, (kind, section, problems, errors)


def test_an_optimal_study_takes_events_only_with_its_control():
    problems, errors = both(study("optimal", "optimal", "events"))
    assert any(p.startswith("events: ") for p in problems) and errors
    problems, errors = both(study("optimal", "optimal", "control", "events"))
    assert not problems and not errors, (problems, errors)


def test_a_study_the_move_command_saves_validates(tmp_path):
    """``planar-sym move ... --save-study FILE`` writes a study file: it fits the schema."""
    args = parser().parse_args(["move", "five_bar_type1", "--task", "--from", "60.852,154.665",
                                "--by", "30,30", "--duration", "1.5", "--set", "m_L_Link2=0.06 kg",
                                "--animate", "--out", str(tmp_path)])
    table = study_table(args)
    assert not validator_problems(table)
    assert not schema_errors("study", table)


# -- drift -----------------------------------------------------------------------------------------

def test_a_key_the_validator_gains_stops_the_generator(monkeypatch):
    monkeypatch.setattr(schema, "BODY_KEYS", schema.BODY_KEYS | {"colour"})
    with pytest.raises(schema.SchemaDrift, match=r"bodies: keys the validator knows but this "
                                                 r"module does not describe: \['colour'\]"):
        schema.schemas()


def test_a_number_place_the_validator_loses_stops_the_generator(monkeypatch):
    numbers = copy.deepcopy(spec.NUMBERS)
    del numbers["motion"]["duration"]
    monkeypatch.setattr(spec, "NUMBERS", numbers)
    with pytest.raises(schema.SchemaDrift, match=r"motion\.duration: the validator's NUMBERS"):
        schema.schemas()


def test_the_schemas_follow_the_validators_tables():
    d, s = SCHEMAS["description"], SCHEMAS["study"]
    joint = d["properties"]["joints"]["items"]
    assert joint["properties"]["type"]["enum"] == list(schema.JOINT_TYPES)
    assert set(joint["properties"]) == schema.JOINT_KEYS
    assert set(d["properties"]) == schema.TOP_KEYS
    assert d["properties"]["units"]["properties"]["inertia"]["enum"] == list(
        schema.UNITS["inertia"])
    motion = s["properties"]["motion"]["properties"]
    assert motion["profile"]["enum"] == list(spec.PROFILES)
    assert motion["samples"]["maximum"] == spec.MAX_SAMPLES
    assert set(s["properties"]) == spec._TOP


# -- the command --------------------------------------------------------------------------------

def test_the_command_writes_the_shipped_files(tmp_path, capsys):
    assert main(["schema", "--check"]) == 0
    assert main(["schema", "--out", str(tmp_path)]) == 0
    for name in schema.FILES.values():
        assert (tmp_path / name).read_text() == (schema.FOLDER / name).read_text()
    (tmp_path / schema.FILES["study"]).write_text("{}\n")
    assert main(["schema", "--check", "--out", str(tmp_path)]) == 1
    assert "study.schema.json" in capsys.readouterr().err



def test_without_out_up_to_date_files_are_named_not_rewritten(tmp_path, capsys, monkeypatch):
    """A user's ``planar-sym schema`` rewrote the installed package's files (identical bytes);
    now it names them, and rewrites the package's folder only where a file is stale."""
    import shutil

    folder = tmp_path / "schemas"
    shutil.copytree(schema.FOLDER, folder)
    monkeypatch.setattr(schema, "FOLDER", folder)
    stamps = {p.name: p.stat().st_mtime_ns for p in folder.iterdir()}
    assert main(["schema"]) == 0
    assert "up to date: " in capsys.readouterr().out
    assert {p.name: p.stat().st_mtime_ns for p in folder.iterdir()} == stamps
    (folder / schema.FILES["study"]).write_text("{}\n")
    assert main(["schema"]) == 0
    assert "wrote " in capsys.readouterr().out
    assert main(["schema", "--check"]) == 0
