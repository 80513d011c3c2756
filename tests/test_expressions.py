"""Numbers as expressions (``planar_sym.expressions``, issue 29 item 4): wherever a robot
description or a study file takes a number, a string holding an expression is taken too.

Every value is checked against an independent one: Python's ``math`` on the same formula, or the
same file with the numbers typed out (the ``repr`` of the value computed here), which must read
to the same Description, Study, parameter vector and torques. Every mistake is one problem
naming the file, the field and the expression.
"""

from __future__ import annotations

import dataclasses
import math
import time
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT, TEST_ROBOTS

import planar_sym as ps
from planar_sym.errors import DescriptionError, InputError
from planar_sym.expressions import ExpressionError, constants, evaluate, quantity
from planar_sym.model import description
from planar_sym.study import spec
from planar_sym.study.run import run
from planar_sym.toml_write import dumps

DEG = math.pi / 180.0


# -- the evaluator --------------------------------------------------------------------------------

@pytest.mark.parametrize(("text", "want"), [
    ("2*3^2", 18.0), ("2*3**2", 18.0), ("2^3^2", 2.0 ** 9), ("-2^2", -4.0), ("(-2)^2", 4.0),
    ("(1 + 2)*-3", -9.0), ("7/2 - 1", 2.5), ("+-+3", -3.0), ("1e-3 + 1_000", 1000.001),
    ("100*cos(30*deg)", 100.0 * math.cos(math.radians(30.0))),
    ("100*sin(30*deg)", 100.0 * math.sin(math.radians(30.0))),
    ("atan2(1, 2)/deg", math.degrees(math.atan2(1.0, 2.0))), ("atan(1)*4", math.pi),
    ("sqrt(3)/2", math.sqrt(3.0) / 2.0), ("hypot(3, 4)", 5.0), ("asin(1)", math.pi / 2.0),
    ("acos(-1)", math.pi), ("tan(45*deg)", 1.0), ("deg*180", math.pi), (" pi ", math.pi),
    ("41.5^2 + 40.1^2", 41.5 ** 2 + 40.1 ** 2),
])
def test_values_against_python_math(text, want):
    assert evaluate(text) == pytest.approx(want, rel=1e-15, abs=1e-15)


def test_constants_in_any_order_and_in_expressions():
    values, problems = constants({"h": "L*sin(60*deg)", "L": "2*a", "a": 0.5, "n": 3})
    assert problems == []
    assert values == {"a": 0.5, "L": 1.0, "h": math.sin(math.radians(60.0)), "n": 3.0}
    assert evaluate("h/L + n", values) == math.sin(math.radians(60.0)) + 3.0


FUNCTIONS = "(known: sqrt, sin, cos, tan, asin, acos, atan, atan2, hypot)"
ONLY = "is not allowed (only numbers, + - * / ** ^, parentheses, functions and names)"
SIDE_BY_SIDE = "two terms side by side: a product needs * (30*deg), and no unit is written here"


@pytest.mark.parametrize(("text", "reason"), [
    ("x + 1", "unknown name x (known: pi, deg; a file's own go in [constants])"),
    ("100*cso(30*deg)", f"unknown function cso {FUNCTIONS}"),
    ("1/(2 - 2)", "division by zero in 1/(2 - 2)"),
    ("2*(3", "not an expression ('(' was never closed)"),
    ("30 deg", f"{SIDE_BY_SIDE} (the file's [units] give it)"),
    ("9**9**9", "9**9**9 is too large"), ("9^9^9", "9^9^9 is too large"),
    ('__import__("os")', f"unknown function __import__ {FUNCTIONS}"),
    ("().__class__", f"attribute access (.) {ONLY}"), ("(1).real", f"attribute access (.) {ONLY}"),
    ("[1, 2]", f"a list {ONLY}"), ("1 if 1 else 2", f"if/else {ONLY}"),
    ("1e308*10", "1e308*10 is too large"), ("1e400", "1e400 is too large"),
    ("sqrt(-1)", "sqrt(-1) is undefined"), ("(-8)^(1/3)", "(-8)^(1/3) is undefined"),
    ("sin", "sin is a function: call it, sin(x)"), ("pi(2)", "pi is a number, not a function"),
    ("atan2(1)", "atan2 takes 2 arguments (got 1)"),
    ("sin(x=1)", "sin: keyword arguments are not allowed"),
    ("'1'", "'1' is not a number"), ("True", "True is not a number"),
    ("2 % 3", "operator % is not allowed (only + - * / ** ^)"),
    ("", "empty: give a number or an expression"),
    ("1+" * 300 + "1", "longer than 500 characters"),
    ("-" * 150 + "1", "more than 100 operations deep"),
])
def test_each_mistake_says_what_is_wrong(text, reason):
    with pytest.raises(ExpressionError) as info:
        evaluate(text)
    assert info.value.reason == reason
    assert isinstance(info.value, InputError)


def test_hostile_texts_are_refused_at_once():
    """Floats only: no power is computed in integers, so none can run for long."""
    start = time.perf_counter()
    for text in ("9**9**9**9", "2^2^2^2^2^2", "(10^300)^(10^300)", "9" * 499, "(" * 200 + ")"):
        with pytest.raises(ExpressionError):
            evaluate(text)
    assert time.perf_counter() - start < 1.0


@pytest.mark.parametrize(("table", "problems"), [
    ({"a": "b", "b": "a", "c": "a + 1"}, [("constants.a", "a cycle: a -> b -> a")]),
    ({"a": "a + 1"}, [("constants.a", "a cycle: a -> a")]),
    ({"a": "2*k"}, [("constants.a", '"2*k": unknown name k (known: pi, deg; [constants]: a)')]),
    ({"pi": 3.0}, [("constants.pi", "'pi' is built in: choose another name")]),
    ({"a": True}, [("constants.a", "must be a number or an expression (got True)")]),
    ("a = 1", [("constants", "must be a table of name = number or expression (got 'a = 1')")]),
])
def test_constants_problems_one_each(table, problems):
    assert constants(table) == ({}, problems)


@pytest.mark.parametrize(("text", "want"), [
    ("0.5 kg", (0.5, "kg")), ("2*0.3 kg", (2 * 0.3, "kg")), ("90.992 kg*mm^2", (90.992, "kg*mm^2")),
    (" -1  m ", (-1.0, "m")), ("30 deg", (30.0, "deg")), ("2 * pi", (2 * math.pi, None)),
    ("m1/2", (0.125, None)), ("m1 kg", (0.25, "kg")),
])
def test_quantity_strings(text, want):
    assert quantity(text, {"m1": 0.25}) == want


# -- descriptions ---------------------------------------------------------------------------------

PLATE = """name = "plate"
gravity = [0.0, {g}]
{constants}
[units]
length = "mm"
mass = "kg"
inertia = "kg*mm^2"
angle = "rad"
acceleration = "m/s^2"

[ground]
points = {{ O = [0.0, 0.0] }}

[[bodies]]
name = "plate"
mass = {m}
izz = {izz}
cg = [{cgx}, {cgy}]
cg_from = "A"
points = {{ A = [0.0, 0.0], B = [{side}, 0.0], C = [{cx}, {cy}] }}
frame = ["A", "B"]

[[joints]]
name = "pivot"
type = "revolute"
parent = "ground.O"
child = "plate.A"
actuated = true
[joints.actuator]
gear_ratio = {gear}
"""
CONSTANTS = '[constants]\nside = 120\nm = "3/10"\n'
EXPRESSIONS = {"g": '"-9.81"', "m": '"m"', "izz": '"m*side^2/12"', "cgx": '"side/2"',
               "cgy": '"side/(2*sqrt(3))"', "side": '"side"', "cx": '"side*cos(60*deg)"',
               "cy": '"side*sin(60*deg)"', "gear": '"2^5 + 1"', "constants": CONSTANTS}
SIDE, MASS = 120.0, 3.0 / 10.0
TYPED = {"g": -9.81, "m": MASS, "izz": MASS * SIDE ** 2 / 12.0, "cgx": SIDE / 2.0,
         "cgy": SIDE / (2.0 * math.sqrt(3.0)), "side": SIDE,
         "cx": SIDE * math.cos(math.radians(60.0)), "cy": SIDE * math.sin(math.radians(60.0)),
         "gear": 33.0}


def _plate(tmp_path: Path, name: str, values: dict, *edits: tuple[str, str]) -> Path:
    text = PLATE.format(**{"constants": "", **{k: (v if isinstance(v, str) else repr(v))
                                               for k, v in values.items()}})
    for old, new in edits:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def _same_as(desc, other):
    """``desc`` with ``other``'s file (path and hash): the rest must be equal."""
    return dataclasses.replace(desc, path=other.path, sha256=other.sha256)


def test_a_description_with_expressions_reads_as_its_numbers_typed_out(tmp_path):
    exprs = description.load(_plate(tmp_path, "exprs", EXPRESSIONS))
    typed = description.load(_plate(tmp_path, "typed", TYPED))
    assert _same_as(exprs, typed) == typed  # every body, point, joint, actuator and parameter
    p = {q.name: q.value for q in exprs.parameters()}
    assert p["m_plate"] == 0.3 and p["gear_pivot"] == 33.0
    assert p["izz_plate"] == pytest.approx(0.3 * 0.12 ** 2 / 12.0, rel=1e-15)
    plate = exprs.bodies["plate"]  # in its frame: at A, x along A -> B (m)
    assert plate.points_m["C"] == pytest.approx((0.06, 0.12 * math.sqrt(3.0) / 2.0), rel=1e-15)
    assert plate.cg_m == pytest.approx((0.06, 0.12 / (2.0 * math.sqrt(3.0))), rel=1e-15)


def _as_expressions(v, ints: bool = True):
    """Every number of a TOML table as the expression "2*(v)/2" (exactly v again)."""
    if isinstance(v, dict):
        return {k: _as_expressions(x, ints) for k, x in v.items()}
    if isinstance(v, list):
        return [_as_expressions(x, ints) for x in v]
    if isinstance(v, float) or (ints and isinstance(v, int) and not isinstance(v, bool)):
        return f"2*({v!r})/2"
    return v


def _files(*globs: str, key: str) -> list[Path]:
    return [p for g in globs for p in sorted(ROOT.glob(g))
            if key in tomllib.loads(p.read_text())]


DESCRIPTIONS = _files("planar_sym/robots/*.toml", "examples/*.toml", "tests/robots/*.toml",
                      key="bodies")
STUDIES = _files("planar_sym/studies/*.toml", "examples/*.toml", key="kind")


@pytest.mark.parametrize("path", DESCRIPTIONS, ids=[p.stem for p in DESCRIPTIONS])
def test_every_shipped_description_reads_the_same_with_every_number_an_expression(path,
                                                                                    tmp_path):
    """Every number place of every shipped description takes an expression (the schema misses
    none of them), and an expression's value is the number's, to the last bit."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        typed = description.load(path)
        copy = tmp_path / path.name
        copy.write_text(dumps(_as_expressions(tomllib.loads(path.read_text()))))
        exprs = description.load(copy)
    assert _same_as(exprs, typed) == typed


@pytest.mark.parametrize("path", STUDIES, ids=[p.stem for p in STUDIES])
def test_every_shipped_study_reads_the_same_with_every_number_an_expression(path):
    """Floats only: an integer (samples, frames) is no number place."""
    data = tomllib.loads(path.read_text())
    exprs = _as_expressions(data, ints=False)
    assert exprs != data
    assert spec.parse(exprs, path.stem, path) == spec.parse(data, path.stem, path)


PLATE_MISTAKES = [  # (name, (old, new) in the expressions' file, field, what is said)
    ("unknown_name", ('mass = "m"', 'mass = "mm"'), "bodies[0] (plate).mass",
     '"mm": unknown name mm (known: pi, deg; [constants]: m, side)'),
    ("unknown_function", ('"side*cos(60*deg)"', '"side*cso(60*deg)"'),
     "bodies[0] (plate).points.C[0]", f'"side*cso(60*deg)": unknown function cso {FUNCTIONS}'),
    ("division_by_zero", ('"m*side^2/12"', '"m*side^2/(side - side)"'), "bodies[0] (plate).izz",
     '"m*side^2/(side - side)": division by zero in m*side^2/(side - side)'),
    ("syntax_error", ('"side/(2*sqrt(3))"', '"side/(2*sqrt(3)"'), "bodies[0] (plate).cg[1]",
     '"side/(2*sqrt(3)": not an expression (\'(\' was never closed)'),
    ("huge_exponent", ('"-9.81"', '"9**9**9"'), "gravity[1]", '"9**9**9": 9**9**9 is too large'),
    ("import", ('mass = "m"', "mass = \"__import__('os')\""), "bodies[0] (plate).mass",
     "\"__import__('os')\": unknown function __import__"),
    ("attribute", ('mass = "m"', 'mass = "m.real"'), "bodies[0] (plate).mass",
     '"m.real": attribute access (.) is not allowed'),
    ("not_finite", ('"2^5 + 1"', '"1e308*10 - 1e308"'), "joints[0] (pivot).actuator.gear_ratio",
     '"1e308*10 - 1e308": 1e308*10 is too large'),
    ("ground_point", ("O = [0.0, 0.0]", 'O = [0.0, "1/0"]'), "ground.points.O[1]",
     '"1/0": division by zero in 1/0'),
    ("unit_typed", ('mass = "m"', 'mass = "0.3 kg"'), "bodies[0] (plate).mass",
     f'"0.3 kg": {SIDE_BY_SIDE}'),
    ("cycle", ('side = 120\nm = "3/10"', 'side = "m*400"\nm = "side/400"'), "constants.side",
     "a cycle: side -> m -> side"),
    ("constant_unknown_name", ('side = 120', 'side = "12*ten"'), "constants.side",
     '"12*ten": unknown name ten (known: pi, deg; [constants]: m, side)'),
    ("constant_builtin_name", ('side = 120', 'side = 120\ndeg = 1'), "constants.deg",
     "'deg' is built in: choose another name"),
]


@pytest.mark.parametrize(("edit", "field", "said"), [c[1:] for c in PLATE_MISTAKES],
                         ids=[c[0] for c in PLATE_MISTAKES])
def test_one_mistake_in_a_description_one_message(tmp_path, edit, field, said):
    """A DescriptionError (every description problem is one) with one problem: nothing that
    depends on the field (the ground point's joint, the body, the fields using a constant)
    says it again."""
    values = dict(EXPRESSIONS)
    if edit[0] in CONSTANTS:  # the edit is in [constants]
        values["constants"] = CONSTANTS.replace(*edit)
        edit = None
    path = _plate(tmp_path, "bad", values, *([edit] if edit else []))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(DescriptionError) as info:
            description.load(path)
    assert len(info.value.problems) == 1, info.value.problems
    assert info.value.problems[0].startswith(f"{path}: {field}: {said}"), info.value.problems[0]
    assert not caught


def test_strings_that_were_refused_before_are_still_refused_where_no_number_is_taken(tmp_path):
    """A whole vector as one string is no expression place: the message is the old one."""
    path = _plate(tmp_path, "bad", EXPRESSIONS, ('gravity = [0.0, "-9.81"]', 'gravity = "down"'))
    with pytest.raises(DescriptionError) as info:
        description.load(path)
    old = "must be a list of two numbers [x, y] (got 'down')"
    assert info.value.problems == [f"{path}: gravity: {old}"]


# -- studies --------------------------------------------------------------------------------------

STUDY = """robot = "{robot}"
kind = "inverse"
{constants}
[units]
angle = "deg"

[parameters]
m_rod = {m}
izz_rod = {izz}

[motion]
space = "joint"
profile = "cubic"
start = [{start}]
by = [{by}]
duration = {duration}
samples = 41
"""
STUDY_CONSTANTS = '[constants]\nswing = "atan2(1, 1)/deg"\n'
STUDY_EXPRESSIONS = {"m": '"2*0.9 kg"', "izz": '"3*0.01"', "start": '"-90 + swing/3"',
                     "by": '"swing"', "duration": '"3/2"', "constants": STUDY_CONSTANTS}
SWING = math.atan2(1.0, 1.0) / DEG
STUDY_TYPED = {"m": f'"{2 * 0.9!r} kg"', "izz": repr(3 * 0.01), "start": repr(-90 + SWING / 3),
               "by": repr(SWING), "duration": "1.5", "constants": ""}

PENDULUM = """name = "pendulum"
gravity = [0.0, "-9.81"]

[constants]
L = "2/5"                 # m, the rod
m = 1.5                   # kg

[units]
length = "m"
mass = "kg"
inertia = "kg*m^2"
angle = "rad"
acceleration = "m/s^2"

[ground]
points = { O = [0.0, 0.0] }

[[bodies]]
name = "rod"
mass = "m"
izz = "2*0.01"
cg = ["L*5/8", 0.0]
cg_from = "CS1"
points = { CS1 = [0.0, 0.0], CS2 = ["L", 0.0] }
frame = ["CS1", "CS2"]

[[joints]]
name = "pivot"
type = "revolute"
parent = "ground.O"
child = "rod.CS1"
actuated = true

[task]
point = "rod.CS2"
"""


def _study(tmp_path: Path, name: str, values: dict, robot: Path, *edits) -> Path:
    text = STUDY.format(robot=robot, **values)
    for old, new in edits:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def pendulum(tmp_path_factory) -> Path:
    """tests/robots/pendulum.toml with its numbers as expressions and constants."""
    path = tmp_path_factory.mktemp("robot") / "pendulum.toml"
    path.write_text(PENDULUM)
    return path


def test_a_robot_from_a_description_with_expressions(pendulum):
    """Derived and compiled (once, cached): its parameter vector is the typed pendulum's."""
    robot = ps.load(pendulum)
    typed = {p.name: p.value for p in description.load(TEST_ROBOTS / "pendulum.toml").parameters()}
    got = dict(zip([p.name for p in robot.parameter_list], robot.p, strict=True))
    assert got.keys() == typed.keys()
    for name, value in typed.items():
        assert got[name] == pytest.approx(value, rel=1e-15, abs=1e-15), name


def test_a_study_with_expressions_gives_the_torques_of_its_numbers_typed_out(pendulum, tmp_path):
    exprs = spec.load(_study(tmp_path, "exprs", STUDY_EXPRESSIONS, pendulum))
    typed = spec.load(_study(tmp_path, "typed", STUDY_TYPED, pendulum))
    assert exprs.parameters == {"m_rod": (1.8, "kg"), "izz_rod": (3 * 0.01, None)}
    assert exprs.motion.start == pytest.approx((-75.0,), rel=1e-15)
    assert dataclasses.replace(exprs, name="typed", title="typed", path=typed.path) == typed
    a, b = run(exprs), run(typed)
    assert np.array_equal(a.table(), b.table())
    tau = a.torques()["tau1_n_m"]
    assert np.abs(tau).max() > 1.0  # a real move: gravity on a 1.8 kg rod
    assert np.array_equal(tau, b.torques()["tau1_n_m"])


STUDY_MISTAKES = [  # (name, (old, new), field, what is said)
    ("parameter_unknown_name", ('"2*0.9 kg"', '"2*x kg"'), "parameters.m_rod",
     '"2*x kg": unknown name x (known: pi, deg; [constants]: swing)'),
    ("division_by_zero", ('by = ["swing"]', 'by = ["swing/0"]'), "motion.by[0]",
     '"swing/0": division by zero in swing/0'),
    ("huge_exponent", ('"3/2"', '"9^9^9"'), "motion.duration", '"9^9^9": 9^9^9 is too large'),
    ("import", ('"-90 + swing/3"', "\"__import__('os')\""), "motion.start[0]",
     "\"__import__('os')\": unknown function __import__"),
    ("cycle", ('swing = "atan2(1, 1)/deg"', 'swing = "2*swing"'), "constants.swing",
     "a cycle: swing -> swing"),
]


@pytest.mark.parametrize(("edit", "field", "said"), [c[1:] for c in STUDY_MISTAKES],
                         ids=[c[0] for c in STUDY_MISTAKES])
def test_one_mistake_in_a_study_one_message(tmp_path, edit, field, said):
    path = _study(tmp_path, "bad", STUDY_EXPRESSIONS, TEST_ROBOTS / "pendulum.toml", edit)
    with pytest.raises(InputError) as info:  # a StudyError
        spec.load(path)
    assert len(info.value.problems) == 1, info.value.problems
    assert info.value.problems[0].startswith(f"{path}: {field}: {said}"), info.value.problems[0]


def test_study_numbers_a_reader_checks_itself_take_expressions_too():
    """kp as one number for every joint, and events.joint_limits, read by control_spec."""
    data = {"robot": "serial_2dof", "kind": "control", "constants": {"w": 10.0},
            "motion": {"space": "joint", "start": [0.0, 0.0], "by": [90.0, 0.0],
                       "duration": 1.0},
            "control": {"law": "pd", "kp": "w^2", "kd": ["2*w", "2*w"]},
            "events": {"joint_limits": {"q1": ["-pi", "pi"]}}}
    st = spec.parse(data, "pd")
    assert st.control.kp == (100.0,) and st.control.kd == (20.0, 20.0)
    assert st.events.joint_limits == {"q1": (-math.pi, math.pi)}
