"""The catalogue of bad inputs: every mistake a user can make, with the error they see.

One table (``CATALOGUE``, built by the ``@bad`` entries below) drives both the test and the
documentation: each entry is the input (what you did), the exception class, a regular expression
the message must match, and an example of the message as a user sees it (paths shortened to the
file name). ``test_catalogue`` makes each mistake and checks the class and the message;
``test_docs_are_generated_from_the_catalogue`` checks that ``docs/errors.md`` is exactly what
``render_markdown()`` produces from the same table, so the two cannot drift apart. Regenerate it
with ``python tests/test_error_catalogue.py``.

Many entries are also tested in depth elsewhere (``see``): tests/test_description_errors.py,
tests/test_library_errors.py, tests/test_workspace_errors.py, tests/test_cli.py. Here each one is
a row of the catalogue: what the user sees, and that the example in the docs is still true.
"""

from __future__ import annotations

import json
import re
import shutil
import sys
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
ROBOTS = ROOT / "planar_sym" / "robots"
TEST_ROBOTS = ROOT / "tests" / "robots"
DOCS = ROOT / "docs" / "errors.md"
if str(ROOT) not in sys.path:  # run as a script (regenerating docs/errors.md)
    sys.path.insert(0, str(ROOT))

import planar_sym as ps
from planar_sym.dynamics import forward_closed
from planar_sym.errors import (
    DescriptionError,
    InputError,
    LibraryError,
    SimulationError,
    WorkspaceError,
)
from planar_sym.model import description
from planar_sym.model.compile import build, build_simd, library_path
from planar_sym.model.folders import read_manifest
from planar_sym.model.library import Library
from planar_sym.model.robot import Robot
from planar_sym.motion import closure
from planar_sym.motion.ik import inverse_kinematics
from planar_sym.motion.profiles import coeff_3rd, cubic
from planar_sym.study.checks import StudyError

SERIAL = (ROBOTS / "serial_2dof.toml").read_text()
FIVE_BAR = (ROBOTS / "five_bar_type1.toml").read_text()
RRR = (ROBOTS / "parallel_3rrr.toml").read_text()

DESC, ARRAYS, TRAJ, SIM, FILES, CLI = ("Robot descriptions", "Runtime arrays and parameters",
                                       "Trajectories and inverse kinematics",
                                       "Forward simulation", "Generated files and libraries",
                                       "Command line")
STUDY, LOOPS = "Study files", "Closed chains off their loops, passive joints"
CONTROL = "Control in the loop"
DESIGN = "Atlases and sweeps"
EXCHANGE = "Export to other engines, result files"
AREAS = (DESC, ARRAYS, TRAJ, SIM, LOOPS, CONTROL, DESIGN, STUDY, EXCHANGE, FILES, CLI)


class CommandFailed(Exception):
    """A command-line call that returned a non-zero exit code; the message is its stderr."""


class Warned(Exception):
    """Stands for a warning (the call succeeded); the message is the warning's text."""


@dataclass(frozen=True)
class Bad:
    id: str
    area: str
    did: str  # what the user did (Markdown)
    exc: type  # exception class (CommandFailed: exit code 2; Warned: RuntimeWarning)
    pattern: str  # regex that the message must match (re.search)
    example: str  # the message as a user sees it (paths shortened)
    run: Callable
    see: str = ""  # where it is tested in depth

    @property
    def shown_class(self) -> str:
        if self.exc is CommandFailed:
            return "exit code 2, on stderr"
        if self.exc is Warned:
            return "RuntimeWarning (then works)"
        return self.exc.__name__


CATALOGUE: list[Bad] = []


def bad(area: str, did: str, exc: type, pattern: str, example: str, see: str = ""):
    def register(fn):
        CATALOGUE.append(Bad(fn.__name__, area, did, exc, pattern, example, fn, see))
        return fn
    return register


class Ctx:
    """What an entry may use: a scratch folder and pytest's monkeypatch and capsys."""

    def __init__(self, tmp: Path, monkeypatch, capsys):
        self.tmp, self.monkeypatch, self.capsys = tmp, monkeypatch, capsys

    def edited(self, text: str, *edits: tuple[str, str], name: str = "bad") -> Path:
        for old, new in edits:
            assert old in text, f"catalogue edit does not apply: {old!r}"
            text = text.replace(old, new, 1)
        path = self.tmp / f"{name}.toml"
        path.write_text(text)
        return path

    def private_cache(self) -> Path:
        """An empty cache, with the libraries the install compiled set aside: the built-in
        robots then compile into it like any robot."""
        cache = self.tmp / "cache"
        self.monkeypatch.setenv("PLANAR_SYM_CACHE", str(cache))
        self.monkeypatch.setenv("PLANAR_SYM_PREBUILT", "0")
        return cache

    def generated_copy(self, robot: str = "serial_2dof") -> Path:
        dst = self.tmp / "generated" / robot
        shutil.copytree(GENERATED / robot, dst)
        return dst


def _desc(ctx: Ctx, text: str, *edits) -> None:
    description.load(ctx.edited(text, *edits))


TD = "tests/test_description_errors.py::"
TL = "tests/test_library_errors.py::"
TW = "tests/test_workspace_errors.py::"

# -- robot descriptions -------------------------------------------------------------------------


@bad(DESC, "malformed TOML: `[units` (no closing bracket)", DescriptionError,
     r"bad\.toml: not valid TOML: .*\(at line 10, column 7\)",
     "bad.toml: not valid TOML: Expected ']' at the end of a table declaration (at line 10, "
     "column 7)", TD + "test_malformed_toml")
def toml_syntax(ctx):
    _desc(ctx, SERIAL, ("[units]", "[units"))


@bad(DESC, "unknown key, a typo: `mas = 0.071`", DescriptionError,
     r"bad\.toml: bodies\[0\]\.mas: unknown key: did you mean 'mass'\? \(checked as mass "
     r"below\)\Z",
     "bad.toml: bodies[0].mas: unknown key: did you mean 'mass'? (checked as mass below)",
     TD + "test_unknown_key_typo")
def unknown_key(ctx):
    _desc(ctx, SERIAL, ("mass = 0.071", "mas = 0.071"))


@bad(DESC, "unknown top-level table `[colours]`", DescriptionError,
     r"bad\.toml: colours: unknown key \(known: assemble, bodies, constants, gravity, ground, "
     r"joints, name, notes, pose, symbols, task, title, units\)",
     "bad.toml: colours: unknown key (known: assemble, bodies, constants, gravity, ground, "
     "joints, name, notes, pose, symbols, task, title, units)")
def unknown_table(ctx):
    _desc(ctx, SERIAL, ("[ground]", "[colours]\nlink1 = \"red\"\n\n[ground]"))


@bad(DESC, "missing field: a body without `izz`", DescriptionError,
     r"bad\.toml: bodies\[0\] \(link1\)\.izz: missing$",
     "bad.toml: bodies[0] (link1).izz: missing", TD + "test_missing_field")
def missing_field(ctx):
    _desc(ctx, SERIAL, ("izz = 89.395\n", ""))


@bad(DESC, "missing `[units]` table", DescriptionError,
     r"bad\.toml: units: missing table \[units\] \(length, mass, inertia, angle, acceleration\)",
     "bad.toml: units: missing table [units] (length, mass, inertia, angle, acceleration)")
def missing_units(ctx):
    _desc(ctx, SERIAL, (('[units]\nlength = "m"\nmass = "kg"\ninertia = "kg*mm^2"\n'
                         'angle = "rad"\nacceleration = "m/s^2"\n'), ""))


@bad(DESC, "a word for a number: `mass = \"heavy\"`", DescriptionError,
     r"bad\.toml: bodies\[0\] \(link1\)\.mass: \"heavy\": unknown name heavy \(known: pi, "
     r"deg; a file's own go in \[constants\]\)",
     "bad.toml: bodies[0] (link1).mass: \"heavy\": unknown name heavy (known: pi, deg; a "
     "file's own go in [constants])")
def mass_string(ctx):
    _desc(ctx, SERIAL, ("mass = 0.071", 'mass = "heavy"'))


@bad(DESC, "wrong type: `points = \"CS1 CS2\"` (a string, not a table)", DescriptionError,
     r"bad\.toml: bodies\[0\] \(link1\)\.points: must be a non-empty table of name = \[x, y\]",
     "bad.toml: bodies[0] (link1).points: must be a non-empty table of name = [x, y]")
def points_string(ctx):
    _desc(ctx, SERIAL, ("points = { CS1 = [0.0, 0.0], CS2 = [0.1, 0.0] }", 'points = "CS1 CS2"'))


@bad(DESC, "wrong type: `cg = [0.0373]` (one number)", DescriptionError,
     r"bad\.toml: bodies\[0\] \(link1\)\.cg: must be a list of two numbers \[x, y\] "
     r"\(got \[0\.0373\]\)",
     "bad.toml: bodies[0] (link1).cg: must be a list of two numbers [x, y] (got [0.0373])")
def cg_one_number(ctx):
    _desc(ctx, SERIAL, ("cg = [0.0373, 0.0]", "cg = [0.0373]"))


@bad(DESC, "wrong type: `gravity = \"down\"`", DescriptionError,
     r"bad\.toml: gravity: must be a list of two numbers \[x, y\] \(got 'down'\)",
     "bad.toml: gravity: must be a list of two numbers [x, y] (got 'down')")
def gravity_string(ctx):
    _desc(ctx, SERIAL, ("gravity = [0.0, -9.81]", 'gravity = "down"'))


@bad(DESC, "wrong type: `actuated = \"yes\"`", DescriptionError,
     r"bad\.toml: joints\[0\] \(joint1\)\.actuated: must be true or false \(got 'yes'\)",
     "bad.toml: joints[0] (joint1).actuated: must be true or false (got 'yes')")
def actuated_string(ctx):
    _desc(ctx, SERIAL, ("actuated = true", 'actuated = "yes"'))


@bad(DESC, "zero mass: `mass = 0.0`", DescriptionError,
     r"bad\.toml: bodies\[0\] \(link1\)\.mass: must be > 0 kg \(got 0\)",
     "bad.toml: bodies[0] (link1).mass: must be > 0 kg (got 0)", TD + "test_non_positive_mass")
def zero_mass(ctx):
    _desc(ctx, SERIAL, ("mass = 0.071", "mass = 0.0"))


@bad(DESC, "negative mass: `mass = -0.071`", DescriptionError,
     r"bad\.toml: bodies\[0\] \(link1\)\.mass: must be > 0 kg \(got -0\.071\)",
     "bad.toml: bodies[0] (link1).mass: must be > 0 kg (got -0.071)", TD + "test_non_positive_mass")
def negative_mass(ctx):
    _desc(ctx, SERIAL, ("mass = 0.071", "mass = -0.071"))


@bad(DESC, "not a finite number: `mass = nan`", DescriptionError,
     r"bad\.toml: bodies\[0\] \(link1\)\.mass: must be finite \(got nan\)",
     "bad.toml: bodies[0] (link1).mass: must be finite (got nan)")
def nan_mass(ctx):
    _desc(ctx, SERIAL, ("mass = 0.071", "mass = nan"))


@bad(DESC, "negative inertia: `izz = -109.864`", DescriptionError,
     r"bad\.toml: bodies\[2\] \(link2\)\.izz: must be >= 0 kg\*mm\^2 \(got -109\.864\)",
     "bad.toml: bodies[2] (link2).izz: must be >= 0 kg*mm^2 (got -109.864)", TD + "test_negative_inertia")
def negative_inertia(ctx):
    _desc(ctx, SERIAL, ("izz = 109.864", "izz = -109.864"))


@bad(DESC, "zero inertia on a body with extent: link2 `izz = 0.0`", DescriptionError,
     r"bad\.toml: bodies\[2\] \(link2\)\.izz: must be > 0 for a body with extent \(its points "
     r"reach 58\.32 mm from its centre of gravity\); only a body with a single point may be a "
     r"point mass",
     "bad.toml: bodies[2] (link2).izz: must be > 0 for a body with extent (its points reach "
     "58.32 mm from its centre of gravity); only a body with a single point may be a point mass")
def zero_inertia(ctx):
    _desc(ctx, SERIAL, ("izz = 109.864", "izz = 0.0"))


@bad(DESC, "implausible inertia: the seed's 3-RRR typo `izz = 90992` (kg*mm^2) on Link1_2",
     DescriptionError,
     r"bad\.toml: bodies\[1\] \(Link1_2\)\.izz: implausible: 90992 kg\*mm\^2 gives a radius of "
     r"gyration of 1422 mm for a body whose points reach [0-9.]+ mm from its centre of gravity "
     r"\(more than 3 times\); a slip\? In \"g\*mm\^2\" it would be 9\.0992e-05 kg\*m\^2",
     "bad.toml: bodies[1] (Link1_2).izz: implausible: 90992 kg*mm^2 gives a radius of gyration "
     "of 1422 mm for a body whose points reach 50 mm from its centre of gravity (more than 3 "
     "times); a slip? In \"g*mm^2\" it would be 9.0992e-05 kg*m^2")
def inertia_typo_3rrr(ctx):
    _desc(ctx, RRR, ("izz = 90.992", "izz = 90992"))


@bad(DESC, "unit slip: `inertia = \"kg*m^2\"` with the table's kg*mm^2 values", DescriptionError,
     r"bad\.toml: bodies\[0\] \(link1\)\.izz: implausible: 89\.395 kg\*m\^2 gives a radius of "
     r"gyration of 3\.548e\+04 mm",
     "bad.toml: bodies[0] (link1).izz: implausible: 89.395 kg*m^2 gives a radius of gyration of "
     "3.548e+04 mm for a body whose points reach 62.7 mm from its centre of gravity (more than 3 "
     "times); a unit or decimal-point slip?")
def inertia_unit_slip(ctx):
    _desc(ctx, SERIAL, ('inertia = "kg*mm^2"', 'inertia = "kg*m^2"'))


@bad(DESC, "duplicate body name (link2 named `link1`)", DescriptionError,
     r"bad\.toml: bodies\[2\]\.name: duplicate body name 'link1'",
     "bad.toml: bodies[2].name: duplicate body name 'link1'", TD + "test_duplicate_body_name")
def duplicate_body(ctx):
    _desc(ctx, SERIAL, ('name = "link2"', 'name = "link1"'))


@bad(DESC, "duplicate joint name (joint2 named `joint1`)", DescriptionError,
     r"bad\.toml: joints: duplicate joint name 'joint1'",
     "bad.toml: joints: duplicate joint name 'joint1'")
def duplicate_joint(ctx):
    _desc(ctx, SERIAL, ('name = "joint2"', 'name = "joint1"'))


@bad(DESC, "joint refers to an unknown body: `child = \"link9.CS1\"`", DescriptionError,
     r"bad\.toml: joints\[2\] \(joint2\)\.child: unknown body 'link9' \(known: ground, link1, "
     r"motor2, link2\)",
     "bad.toml: joints[2] (joint2).child: unknown body 'link9' (known: ground, link1, motor2, "
     "link2)", TD + "test_unknown_body_in_a_joint")
def joint_unknown_body(ctx):
    _desc(ctx, SERIAL, ('child = "link2.CS1"', 'child = "link9.CS1"'))


@bad(DESC, "joint refers to an unknown point: `child = \"link2.CS9\"`", DescriptionError,
     r"bad\.toml: joints\[2\] \(joint2\)\.child: body 'link2' has no point 'CS9' \(it has CS1, "
     r"CS2\)",
     "bad.toml: joints[2] (joint2).child: body 'link2' has no point 'CS9' (it has CS1, CS2)",
     TD + "test_unknown_point")
def joint_unknown_point(ctx):
    _desc(ctx, SERIAL, ('child = "link2.CS1"', 'child = "link2.CS9"'))


@bad(DESC, "task point on an unknown body: `point = \"link3.CS2\"`", DescriptionError,
     r"bad\.toml: task\.point: unknown body 'link3'",
     "bad.toml: task.point: unknown body 'link3' (known: ground, link1, motor2, link2)")
def task_unknown_body(ctx):
    _desc(ctx, SERIAL, ('point = "link2.CS2"', 'point = "link3.CS2"'))


@bad(DESC, "joint type `slider`", DescriptionError,
     r"bad\.toml: joints\[0\] \(joint1\)\.type: must be 'revolute', 'prismatic' or 'weld' "
     r"\(got 'slider'\)",
     "bad.toml: joints[0] (joint1).type: must be 'revolute', 'prismatic' or 'weld' (got 'slider')")
def joint_type(ctx):
    _desc(ctx, SERIAL, ('type = "revolute"', 'type = "slider"'))


@bad(DESC, "an actuated weld", DescriptionError,
     r"bad\.toml: joints\[1\] \(weld_motor2\): a weld can be neither actuated nor a loop closure",
     "bad.toml: joints[1] (weld_motor2): a weld can be neither actuated nor a loop closure")
def actuated_weld(ctx):
    _desc(ctx, SERIAL, ('child = "motor2.CS1"', 'child = "motor2.CS1"\nactuated = true'))


@bad(DESC, "disconnected kinematic graph: the motor's weld joint deleted", DescriptionError,
     r"bad\.toml: joints: bodies \['motor2'\] are not connected to ground by a chain of joints "
     r"\(the kinematic graph is disconnected\)",
     "bad.toml: joints: bodies ['motor2'] are not connected to ground by a chain of joints (the "
     "kinematic graph is disconnected)")
def disconnected(ctx):
    _desc(ctx, SERIAL, (('[[joints]]\nname = "weld_motor2"\ntype = "weld"\n'
                         'parent = "link1.CS2"\nchild = "motor2.CS1"\n'), ""))


@bad(DESC, "ground made a child: joint1 `parent`/`child` swapped", DescriptionError,
     r"bad\.toml: joints: ground is the child of \['joint1'\]; ground is the root of the tree, "
     r"make it the parent",
     "bad.toml: joints: ground is the child of ['joint1']; ground is the root of the tree, make "
     "it the parent")
def ground_child(ctx):
    _desc(ctx, SERIAL, ('parent = "ground.O"\nchild = "link1.CS1"',
                        'parent = "link1.CS1"\nchild = "ground.O"'))


@bad(DESC, "a closed chain without `closes_loop = true` on its cut joint (5-bar, joint C)",
     DescriptionError,
     r"bad\.toml: joints: body 'R_Link2' is the child of several joints \['D', 'C'\]: mark all "
     r"but one closes_loop = true",
     "bad.toml: joints: body 'R_Link2' is the child of several joints ['D', 'C']: mark all but "
     "one closes_loop = true")
def loop_not_cut(ctx):
    _desc(ctx, FIVE_BAR, ("closes_loop = true", "closes_loop = false"))


@bad(DESC, "a loop that does not close: 5-bar R_Link2.CS2 moved 1 mm", DescriptionError,
     r"bad\.toml: joints \(C\): loop does not close in the drawn configuration: L_Link2\.CS2 and "
     r"R_Link2\.CS2 are 1 mm apart \(tolerance 0\.01 mm\)",
     "bad.toml: joints (C): loop does not close in the drawn configuration: L_Link2.CS2 and "
     "R_Link2.CS2 are 1 mm apart (tolerance 0.01 mm); set assemble = true to let planar-sym "
     "close it from this pose", TD + "test_loop_that_does_not_close")
def open_loop(ctx):
    _desc(ctx, FIVE_BAR, ("CS2 = [0.037, 0.140] }\nframe", "CS2 = [0.038, 0.140] }\nframe"))


@bad(DESC, "a joint that does not close: link2.CS1 drawn 2 mm from link1.CS2", DescriptionError,
     r"bad\.toml: joints \(joint2\): joint does not close in the drawn configuration: link1\.CS2 "
     r"and link2\.CS1 are 2 mm apart \(tolerance 0\.01 mm\)",
     "bad.toml: joints (joint2): joint does not close in the drawn configuration: link1.CS2 and "
     "link2.CS1 are 2 mm apart (tolerance 0.01 mm)")
def open_joint(ctx):
    _desc(ctx, SERIAL, ("points = { CS1 = [0.1, 0.0], CS2 = [0.2, 0.0] }",
                        "points = { CS1 = [0.102, 0.0], CS2 = [0.2, 0.0] }"))


@bad(DESC, "unknown length unit `\"in\"`", DescriptionError,
     r"bad\.toml: units\.length: unknown length unit 'in'; known: m, cm, mm \(got 'in'\)",
     "bad.toml: units.length: unknown length unit 'in'; known: m, cm, mm (got 'in')",
     TD + "test_unknown_length_unit")
def unit_length(ctx):
    _desc(ctx, SERIAL, ('length = "m"', 'length = "in"'))


@bad(DESC, "unknown mass unit `\"lb\"`", DescriptionError,
     r"bad\.toml: units\.mass: unknown mass unit 'lb'; known: kg, g \(got 'lb'\)",
     "bad.toml: units.mass: unknown mass unit 'lb'; known: kg, g (got 'lb')",
     TD + "test_unknown_mass_or_inertia_unit")
def unit_mass(ctx):
    _desc(ctx, SERIAL, ('mass = "kg"', 'mass = "lb"'))


@bad(DESC, "unknown inertia unit `\"kg*in^2\"`", DescriptionError,
     r"bad\.toml: units\.inertia: unknown inertia unit 'kg\*in\^2'; known: kg\*m\^2, kg\*cm\^2, "
     r"kg\*mm\^2, g\*mm\^2, g\*cm\^2",
     "bad.toml: units.inertia: unknown inertia unit 'kg*in^2'; known: kg*m^2, kg*cm^2, kg*mm^2, "
     "g*mm^2, g*cm^2 (got 'kg*in^2')", TD + "test_unknown_mass_or_inertia_unit")
def unit_inertia(ctx):
    _desc(ctx, SERIAL, ('inertia = "kg*mm^2"', 'inertia = "kg*in^2"'))


@bad(DESC, "unknown angle unit `\"grad\"`", DescriptionError,
     r"bad\.toml: units\.angle: unknown angle unit 'grad'; known: rad, deg \(got 'grad'\)",
     "bad.toml: units.angle: unknown angle unit 'grad'; known: rad, deg (got 'grad')")
def unit_angle(ctx):
    _desc(ctx, SERIAL, ('angle = "rad"', 'angle = "grad"'))


@bad(DESC, "a teaching symbol for a parameter that does not exist (`m_link7`)", DescriptionError,
     r"bad\.toml: symbols\.m_link7: not a parameter of this robot",
     "bad.toml: symbols.m_link7: not a parameter of this robot")
def unknown_symbol(ctx):
    _desc(ctx, SERIAL, ('m_link1 = "m_1"', 'm_link7 = "m_1"'))


@bad(DESC, "an unknown built-in robot name: `description.load(\"six_bar\")`", DescriptionError,
     r"unknown robot 'six_bar'; built in: .*five_bar_type1, .*serial_2dof, serial_3dof",
     "unknown robot 'six_bar'; built in: five_bar_type1, five_bar_type2, parallel_3rpr, "
     "parallel_3rrr, serial_2dof, serial_3dof, serial_rpr, slider_crank, "
     "slider_crank_slider_driven")
def unknown_builtin(ctx):
    description.load("six_bar")


@bad(DESC, "`assemble = true` with a coupler too short to reach the rocker", DescriptionError,
     r"bad\.toml: joints \(B\): loop B cannot be closed from the given pose: its points stay "
     r"[0-9.]+ mm apart",
     "bad.toml: joints (B): loop B cannot be closed from the given pose: its points stay 107.7 "
     "mm apart with the actuated joints at their given angles (the links cannot reach, or the "
     "pose is far from an assembled one); the gap is 1.46 times the median size of its ground "
     "and bodies (73.54 mm)",
     "tests/test_assembly.py")
def assemble_impossible(ctx):
    text = (ROOT / "examples" / "four_bar.toml").read_text()
    text = text.replace('name = "four_bar"', 'name = "four_bar"\nassemble = true')
    _desc(ctx, text, ("B = [133.880965996, 72.471236661], P", "B = [22.0, 36.0], P"))


TU = "tests/test_unit_slips.py::"
JOINTS = (ROOT / "examples" / "four_bar_joints.toml").read_text()


@bad(DESC, "a mass in kg with `mass = \"g\"`: the four-bar's coupler `mass = 0.12`",
     DescriptionError,
     r"bad\.toml: bodies\[1\] \(coupler\)\.mass: 0\.12 g \(read in g, 0\.00012 kg\) with izz = "
     r"144000 g\*mm\^2 gives a radius of gyration of 1095 mm .* The mass \(units\.mass = \"g\"\) "
     r"read in \"kg\" would be 0\.12 kg",
     "bad.toml: bodies[1] (coupler).mass: 0.12 g (read in g, 0.00012 kg) with izz = 144000 "
     "g*mm^2 gives a radius of gyration of 1095 mm for a body whose points reach 60 mm from its "
     "centre of gravity (more than 3 times; izz / (mass * reach^2) = 333, a uniform rod's is "
     "1/3): a unit slip? The mass (units.mass = \"g\") read in \"kg\" would be 0.12 kg, a "
     "radius of gyration of 34.64 mm",
     TU + "test_a_coupler_mass_typed_in_kg_for_g_is_blamed_on_the_mass")
def mass_unit_slip(ctx):
    _desc(ctx, FOUR, ("mass = 120.0", "mass = 0.12"))


@bad(DESC, "a body's lengths in m with `length = \"mm\"`: the sketch four-bar's coupler "
     "`B = [0.12, 0.0]`", DescriptionError,
     r"bad\.toml: bodies\[1\] \(coupler\)\.points: .* Its points and cg \(units\.length = "
     r"\"mm\"\) read in \"m\" would reach 60 mm",
     "bad.toml: bodies[1] (coupler).points: 120 g (read in g, 0.12 kg) with izz = 144000 "
     "g*mm^2 gives a radius of gyration of 34.64 mm for a body whose points reach 0.06 mm from "
     "its centre of gravity (more than 3 times; izz / (mass * reach^2) = 3.33e+05, a uniform "
     "rod's is 1/3): a unit slip? Its points and cg (units.length = \"mm\") read in \"m\" would "
     "reach 60 mm, the radius of gyration 0.577 times that",
     TU + "test_a_coupler_typed_in_m_is_one_message_at_its_points")
def points_unit_slip(ctx):
    _desc(ctx, JOINTS, ("cg = [60.0, 0.0]", "cg = [0.06, 0.0]"),
          ("B = [120.0, 0.0], P = [60.0, 30.0]", "B = [0.12, 0.0], P = [0.06, 0.03]"))


@bad(DESC, "ground points in m with `length = \"mm\"`: the sketch four-bar's `O4 = [0.1, 0.0]`",
     DescriptionError,
     r"bad\.toml: joints \(B\): loop B cannot be closed from the given pose: .*; a length unit "
     r"slip\? ground\.points read in \"m\" \(size 0\.1 mm as typed, 100 mm so read, the others' "
     r"median 80 mm\) would close every loop",
     "bad.toml: joints (B): loop B cannot be closed from the given pose: its points stay "
     "0.05011 mm apart with the actuated joints at their given angles (the links cannot reach, "
     "or the pose is far from an assembled one); the gap is 0.000835 times the median size of "
     "its ground and bodies (60 mm); a length unit slip? ground.points read in \"m\" (size 0.1 "
     "mm as typed, 100 mm so read, the others' median 80 mm) would close every loop: were they "
     "typed in \"m\", not units.length = \"mm\"?",
     TU + "test_ground_points_typed_in_m_hint_at_the_unit")
def loop_unit_slip(ctx):
    _desc(ctx, JOINTS, ("O4 = [100.0, 0.0]", "O4 = [0.1, 0.0]"))


# -- runtime arrays and parameters ----------------------------------------------------------------

def _arm() -> Robot:
    return ps.load("serial_2dof")


@bad(ARRAYS, "wrong shape: `q` of shape (10, 3) for the 2-joint arm", InputError,
     r"q must have shape \(N, 2\) or \(2,\), got last axis 3",
     "q must have shape (N, 2) or (2,), got last axis 3", TL + "test_wrong_shape")
def shape_width(ctx):
    z = np.zeros((10, 3))
    _arm().inverse_dynamics(z, z, z)


@bad(ARRAYS, "wrong shape on the exact path (`Robot(name, exact=True)`): (10, 3)", InputError,
     r"q must have shape \(N, 2\) or \(2,\), got \(10, 3\)",
     "q must have shape (N, 2) or (2,), got (10, 3)", TL + "test_wrong_shape")
def shape_width_exact(ctx):
    z = np.zeros((10, 3))
    Robot("serial_2dof", _arm().library, exact=True).inverse_dynamics(z, z, z)


@bad(ARRAYS, "wrong shape: a 3-D array (2, 5, 2)", InputError,
     r"q must be a float array of shape \(N, 2\) or \(2,\)",
     "q must be a float array of shape (N, 2) or (2,)", TL + "test_wrong_shape")
def shape_3d(ctx):
    _arm().mass_matrix(np.zeros((2, 5, 2)))


@bad(ARRAYS, "sample counts differ: q (4, 2), qd (5, 2)", InputError,
     r"inputs must have the same number of samples, got q: 4, qd: 5",
     "inputs must have the same number of samples, got q: 4, qd: 5",
     TL + "test_sample_counts_must_agree")
def sample_counts(ctx):
    _arm().inverse_dynamics(np.zeros((4, 2)), np.zeros((5, 2)), np.zeros((4, 2)))


@bad(ARRAYS, "NaN in an input array: `qd[7, 1] = nan`", InputError,
     r"qd\[7, 1\] is nan at sample 7: inputs must be finite",
     "qd[7, 1] is nan at sample 7: inputs must be finite", TL + "test_nan_input_names_the_sample")
def nan_sample(ctx):
    q = np.zeros((10, 2))
    qd = q.copy()
    qd[7, 1] = np.nan
    _arm().inverse_dynamics(q, qd, q)


@bad(ARRAYS, "infinity in an input array: `q[3, 0] = inf`", InputError,
     r"q\[3, 0\] is inf at sample 3: inputs must be finite",
     "q[3, 0] is inf at sample 3: inputs must be finite", TL + "test_nan_input_names_the_sample")
def inf_sample(ctx):
    q = np.zeros((10, 2))
    q[3, 0] = np.inf
    _arm().mass_matrix(q)


@bad(ARRAYS, "infinity in a closed chain's q with times given (3-RRR, sample 2)", InputError,
     r"q\[2, 0\] is inf at sample 2 \(t = 0\.2 s\): inputs must be finite",
     "q[2, 0] is inf at sample 2 (t = 0.2 s): inputs must be finite",
     TW + "test_nan_time_named_for_positions")
def inf_sample_timed(ctx):
    robot = ps.load("parallel_3rrr")
    q = np.tile(robot.q_drawn, (4, 1))
    q[2, 0] = np.inf
    z = np.zeros_like(q)
    robot.closed_chain_inverse_dynamics(q, z, z, t=np.array([0.0, 0.1, 0.2, 0.3]))


@bad(ARRAYS, "parameter vector of the wrong length: `Robot(\"serial_2dof\", library, "
     "parameters=np.ones(10))`", InputError,
     r"parameters must have shape \(N, 11\) or \(11,\), got \(10,\)",
     "parameters must have shape (N, 11) or (11,), got (10,)")
def parameter_length(ctx):
    Robot("serial_2dof", _arm().library, parameters=np.ones(10))


@bad(ARRAYS, "a NaN parameter: `with_parameters(m_link1=nan)`", InputError,
     r"serial_2dof: parameter m_link1 must be finite \(got nan\)",
     "serial_2dof: parameter m_link1 must be finite (got nan)")
def parameter_nan(ctx):
    _arm().with_parameters(m_link1=float("nan"))


@bad(ARRAYS, "unknown parameter: `with_parameters(m_link9=1.0)`", InputError,
     r"unknown parameter 'm_link9' of serial_2dof; known: g, m_link1, izz_link1, cgx_link1, "
     r"m_motor2, izz_motor2, m_link2, izz_link2, cgx_link2, px_link1_CS2, px_link2_CS2",
     "unknown parameter 'm_link9' of serial_2dof; known: g, m_link1, izz_link1, cgx_link1, "
     "m_motor2, izz_motor2, m_link2, izz_link2, cgx_link2, px_link1_CS2, px_link2_CS2",
     TL + "test_unknown_parameter_and_closed_chain_misuse")
def parameter_unknown(ctx):
    _arm().with_parameters(m_link9=1.0)


@bad(ARRAYS, "`inverse_dynamics` on a closed chain", InputError,
     r"five_bar_type1 is a closed chain: use closed_chain_inverse_dynamics \(torques and loop "
     r"reaction forces together\)",
     "five_bar_type1 is a closed chain: use closed_chain_inverse_dynamics (torques and loop "
     "reaction forces together)", TL + "test_unknown_parameter_and_closed_chain_misuse")
def closed_inverse(ctx):
    z = np.zeros(4)
    ps.load("five_bar_type1").inverse_dynamics(z, z, z)


@bad(ARRAYS, "`forward_dynamics` on a closed chain", InputError,
     r"five_bar_type1 is a closed chain: use planar_sym\.simulate, which keeps the loop "
     r"constraints",
     "five_bar_type1 is a closed chain: use planar_sym.simulate, which keeps the loop constraints")
def closed_forward(ctx):
    z = np.zeros(4)
    ps.load("five_bar_type1").forward_dynamics(z, z, z)


# -- trajectories and inverse kinematics ------------------------------------------------------------

T = 2.0
TIMES = np.linspace(0.0, T, 9)


def _ik(robot: str, x0, dx, t=TIMES):
    return inverse_kinematics(ps.load(robot), cubic(x0, dx, T, t))


@bad(TRAJ, "target outside the workspace: 2-DOF tip from (100, 100) mm by +300 mm in x",
     WorkspaceError,
     r"serial_2dof: target \(x = 194\.922 mm, y = 100 mm\) at t = 0\.75 s \(sample 3\) is "
     r"outside the workspace \(cos of the elbow angle would be 1\.39973, beyond \+-1\)",
     "serial_2dof: target (x = 194.922 mm, y = 100 mm) at t = 0.75 s (sample 3) is outside the "
     "workspace (cos of the elbow angle would be 1.39973, beyond +-1)",
     TW + "test_serial_2dof_beyond_reach")
def outside_workspace(ctx):
    _ik("serial_2dof", [0.1, 0.1], [0.3, 0.0])


@bad(TRAJ, "target outside a closed chain's workspace: 5-bar P by +200 mm in x",
     WorkspaceError,
     r"five_bar_type1: target \(x = [0-9.]+ mm, y = 154\.665 mm\) at t = [0-9.]+ s \(sample \d\) "
     r"is outside the workspace \((left|right) arm: cos of the elbow angle would be",
     "five_bar_type1: target (x = 197.571 mm, y = 154.665 mm) at t = 1.25 s (sample 5) is "
     "outside the workspace (left arm: cos of the elbow angle would be 1.42858, beyond +-1)",
     TW + "test_five_bar_type1_beyond_reach")
def outside_workspace_five_bar(ctx):
    _ik("five_bar_type1", [0.060852, 0.154665], [0.2, 0.0])


@bad(TRAJ, "a 3-RRR leg that cannot reach: platform by +200 mm in x", WorkspaceError,
     r"parallel_3rrr: target \(x = 100 mm, y = 0 mm, phi = 0 rad\) at t = 1 s \(sample 4\) is "
     r"outside the workspace \(leg 2 cannot reach: e1\^2 \+ e2\^2 - e3\^2 = -?[0-9.e-]+ < 0\)",
     "parallel_3rrr: target (x = 100 mm, y = 0 mm, phi = 0 rad) at t = 1 s (sample 4) is outside "
     "the workspace (leg 2 cannot reach: e1^2 + e2^2 - e3^2 = -0.000136 < 0)",
     TW + "test_parallel_3rrr_error_names_the_earliest_time")
def leg_cannot_reach(ctx):
    _ik("parallel_3rrr", [0.0, 0.0, 0.0], [0.2, 0.0, 0.0])


@bad(TRAJ, "joint limit: 2-DOF tip toward |p| = 195 mm needs q2 < 30 deg", WorkspaceError,
     r"serial_2dof: target \(x = [0-9.]+ mm, y = [0-9.]+ mm\) at t = [0-9.]+ s \(sample \d\) "
     r"violates the joint limit 30 <= q2 <= 150 deg \(q2 = [0-9.]+ deg\)",
     "serial_2dof: target (x = 137.886 mm, y = 137.886 mm) at t = 2 s (sample 8) violates the "
     "joint limit 30 <= q2 <= 150 deg (q2 = 25.6771 deg)", TW + "test_serial_2dof_elbow_joint_limit")
def joint_limit_q2(ctx):
    end = 0.195 / np.sqrt(2) * np.ones(2)
    _ik("serial_2dof", [0.1, 0.1], end - [0.1, 0.1])


@bad(TRAJ, "joint limit: 2-DOF tip toward (-50, -50) mm needs q1 < 0", WorkspaceError,
     r"serial_2dof: target \(x = -?[0-9.]+ mm, y = -?[0-9.]+ mm\) at t = [0-9.]+ s \(sample \d\) "
     r"violates the joint limit 0 <= q1 <= 180 deg \(q1 = [0-9.]+ deg\)",
     "serial_2dof: target (x = 93.5547 mm, y = 93.5547 mm) at t = 0.25 s (sample 1) violates "
     "the joint limit 0 <= q1 <= 180 deg (q1 = 356.417 deg)", TW + "test_serial_2dof_shoulder_joint_limit")
def joint_limit_q1(ctx):
    _ik("serial_2dof", [0.1, 0.1], [-0.15, -0.15])


@bad(TRAJ, "singular pose: 3-DOF tool driven until the arm is stretched (q2 = 0)",
     WorkspaceError,
     r"serial_3dof: target \(x = 220 mm, y = 0 mm, phi = 0 rad\) at t = 2 s \(sample 8\) is at a "
     r"singular pose \(Jacobian condition number [0-9.e+inf]+ > 1e\+06\)",
     "serial_3dof: target (x = 220 mm, y = 0 mm, phi = 0 rad) at t = 2 s (sample 8) is at a "
     "singular pose (Jacobian condition number 1.32e+09 > 1e+06)",
     TW + "test_serial_3dof_driven_to_stretched_arm")
def singular_pose(ctx):
    _ik("serial_3dof", [0.1, 0.0, 0.0], [0.12, 0.0, 0.0])


@bad(TRAJ, "singular pose of a closed chain driven by its actuated joints (5-bar Type II, "
     "distal links in line)", WorkspaceError,
     r"five_bar_type2: singular pose at t = 1 s \(sample 4\): the passive-joint constraint "
     r"Jacobian Phi_p .*condition number [0-9.e+inf]+ > 1e\+06",
     "five_bar_type2: singular pose at t = 1 s (sample 4): the passive-joint constraint Jacobian "
     "Phi_p has 1-norm condition number 1.14e+06 > 1e+06",
     TW + "test_five_bar_type2_actuated_route_to_parallel_singularity")
def singular_closed(ctx):
    t = np.linspace(0.0, 1.0, 5)
    tr = cubic([0.0, np.pi / 2], [np.pi / 2, 0.0], 1.0, t)
    closure.from_actuated(ps.load("five_bar_type2"), t, tr.x, tr.xd, tr.xdd)


@bad(TRAJ, "closed-chain torques at a singular pose (actuation matrix)", WorkspaceError,
     r"five_bar_type2: singular pose at t = 0\.5 s \(sample 0\): the .*\[S\^T Phi_q\^T\].* "
     r"condition number [0-9.e+inf]+ > 1e\+06",
     "five_bar_type2: singular pose at t = 0.5 s (sample 0): the passive-joint constraint "
     "Jacobian Phi_p (which the actuation matrix [S^T Phi_q^T] needs) has 1-norm condition "
     "number 1.63e+16 > 1e+06",
     TW + "test_closed_chain_inverse_dynamics_at_parallel_singularity")
def singular_actuation(ctx):
    q = np.array([[np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2]])
    z = np.zeros_like(q)
    ps.load("five_bar_type2").closed_chain_inverse_dynamics(q, z, z, t=np.array([0.5]))


@bad(TRAJ, "zero duration: `cubic(x0, dx, 0.0, t)`", InputError,
     r"trajectory duration must be a positive number of seconds \(got 0\.0\)",
     "trajectory duration must be a positive number of seconds (got 0.0)",
     TW + "test_non_positive_duration")
def zero_duration(ctx):
    cubic([0.1, 0.1], [0.05, 0.0], 0.0, [0.0])


@bad(TRAJ, "negative duration: `coeff_3rd(..., -1.0)`", InputError,
     r"trajectory duration must be a positive number of seconds \(got -1\.0\)",
     "trajectory duration must be a positive number of seconds (got -1.0)",
     TW + "test_non_positive_duration")
def negative_duration(ctx):
    coeff_3rd([0.0], [0.0], [1.0], [0.0], -1.0)


@bad(TRAJ, "sample times outside the trajectory: t = 2.5 s for a 2 s move", InputError,
     r"time t = 2\.5 s \(sample 1\) is outside the trajectory \[0, 2\.0\] s",
     "time t = 2.5 s (sample 1) is outside the trajectory [0, 2.0] s",
     TW + "test_times_outside_trajectory")
def time_outside(ctx):
    cubic([0.1], [0.05], 2.0, [0.0, 2.5])


@bad(TRAJ, "start and displacement of different lengths", InputError,
     r"x0 and dx must have the same length \(got 2 and 3\)",
     "x0 and dx must have the same length (got 2 and 3)")
def length_mismatch(ctx):
    cubic([0.1, 0.1], [0.05, 0.0, 0.0], 2.0, [0.0])


@bad(TRAJ, "NaN in a trajectory's start", InputError,
     r"trajectory start must be finite \(got \[nan, 0\.1\]\)",
     "trajectory start must be finite (got [nan, 0.1])")
def nan_start(ctx):
    cubic([np.nan, 0.1], [0.05, 0.0], 2.0, [0.0])


@bad(TRAJ, "task-space inverse kinematics of a 1-DOF pendulum along an (x, y) path: task and "
     "actuation do not match", WorkspaceError,
     r"pendulum: no inverse kinematics in task space: it has 1 coordinate, 0 loop equations "
     r"\(1 degree of freedom\), a 2-coordinate task \(x, y\)",
     "pendulum: no inverse kinematics in task space: it has 1 coordinate, 0 loop equations (1 "
     "degree of freedom), a 2-coordinate task (x, y) and 1 actuated joint; the task must fix "
     "the 1 degree of freedom, so 2 != 1: drive its actuated joint in joint space instead (a "
     "study's motion.space = \"joint\", or ps.from_actuated)")
def no_ik(ctx):
    from derive.__main__ import main as derive_main

    ctx.private_cache()
    assert derive_main([str(TEST_ROBOTS / "pendulum.toml"), "--out", str(ctx.tmp), "--quiet"]) == 0
    robot = Robot("pendulum", Library("pendulum", folder=ctx.tmp / "pendulum"), exact=True)
    inverse_kinematics(robot, cubic([0.1, 0.0], [0.0, 0.1], 1.0, [0.0, 1.0]))


# -- forward simulation ---------------------------------------------------------------------------

@bad(SIM, "`max_steps` too small: `simulate(arm, q0, qd0, (0, 1), max_steps=5)`",
     SimulationError,
     r"serial_2dof: integration failed at t = [0-9.e-]+ s: too many steps \(raise max_steps or "
     r"loosen the tolerances\)",
     "serial_2dof: integration failed at t = 0.002 s: too many steps (raise max_steps or "
     "loosen the tolerances)")
def max_steps(ctx):
    ps.simulate(_arm(), np.radians([-60.0, 0.0]), [0.0, 0.0], (0.0, 1.0), max_steps=5)


@bad(SIM, "an impossible tolerance: `rtol = atol = 1e-300`", SimulationError,
     r"serial_2dof: integration failed at t = 0 s: the step size fell below 1e-14 s: the problem "
     r"is stiff or singular here",
     "serial_2dof: integration failed at t = 0 s: the step size fell below 1e-14 s: the problem "
     "is stiff or singular here")
def tiny_tolerance(ctx):
    ps.simulate(_arm(), np.radians([-60.0, 0.0]), [0.0, 0.0], (0.0, 1.0), rtol=1e-300,
                atol=1e-300)


@bad(SIM, "a closed chain with a tiny `drift_limit_m` (1e-20 m)", SimulationError,
     r"five_bar_type1: the loops drifted apart by [0-9.e-]+ m between t = 0 s and 0\.1 s "
     r"\(limit 1e-20 m\): tighten rtol/atol or shorten segment_s",
     "five_bar_type1: the loops drifted apart by 7.44e-14 m between t = 0 s and 0.1 s (limit "
     "1e-20 m): tighten rtol/atol or shorten segment_s; near a singular pose the constraints "
     "cannot hold")
def drift_limit(ctx):
    five = ps.load("five_bar_type1")
    forward_closed.simulate_closed(five, five.q_drawn, np.zeros(4), (0.0, 1.0), drift_limit_m=1e-20)


@bad(SIM, "non-positive tolerance: `rtol=0`", InputError,
     r"rtol must be a positive number \(got 0\)",
     "rtol must be a positive number (got 0)")
def zero_tolerance(ctx):
    ps.simulate(_arm(), [0.0, 0.0], [0.0, 0.0], (0.0, 1.0), rtol=0)


@bad(SIM, "an empty time span `(1, 1)`", InputError,
     r"time span must be finite with end > start \(got \(1, 1\)\)",
     "time span must be finite with end > start (got (1, 1))")
def empty_span(ctx):
    ps.simulate(_arm(), [0.0, 0.0], [0.0, 0.0], (1, 1))


@bad(SIM, "`t_eval` not increasing", InputError,
     r"t_eval must be at least 2 increasing times inside \(0, 1\)",
     "t_eval must be at least 2 increasing times inside (0, 1)")
def bad_t_eval(ctx):
    ps.simulate(_arm(), [0.0, 0.0], [0.0, 0.0], (0, 1), t_eval=[0.5, 0.2])


@bad(SIM, "a NaN initial velocity", InputError,
     r"qd0\[0, 0\] is nan at sample 0: inputs must be finite",
     "qd0[0, 0] is nan at sample 0: inputs must be finite")
def nan_initial(ctx):
    ps.simulate(_arm(), [0.0, 0.0], [np.nan, 0.0], (0, 1))


@bad(SIM, "a torque function returning 3 values for 2 joints", InputError,
     r"torque function returned array\(\[1\., 2\., 3\.\]\) at t = 0 s; expected 2 finite values "
     r"\(N\*m\)",
     "torque function returned array([1., 2., 3.]) at t = 0 s; expected 2 finite values (N*m)")
def torque_shape(ctx):
    ps.simulate(_arm(), [0.0, 0.0], [0.0, 0.0], (0, 1), torque=lambda t: [1, 2, 3])


@bad(SIM, "a torque function that turns NaN at t = 0.5 s", InputError,
     r"torque function returned array\(\[nan, +0\.\]\) at t = 0\.5\d* s; expected 2 finite values",
     "torque function returned array([nan,  0.]) at t = 0.50096 s; expected 2 finite values (N*m)")
def torque_nan(ctx):
    ps.simulate(_arm(), [0.0, 0.0], [0.0, 0.0], (0, 1),
                torque=lambda t: [0.0, 0.0] if t < 0.5 else [np.nan, 0.0])


@bad(SIM, "a non-finite constant torque", InputError,
     r"torque must be finite \(got \[inf, 0\.0\]\)",
     "torque must be finite (got [inf, 0.0])")
def torque_inf(ctx):
    ps.simulate(_arm(), [0.0, 0.0], [0.0, 0.0], (0, 1), torque=[np.inf, 0.0])


# -- generated files and compiled libraries --------------------------------------------------------

@bad(FILES, "an unknown robot name: `ps.load(\"six_bar\")`", LibraryError,
     r"unknown robot 'six_bar': not a built-in robot \(cart_pole, five_bar_type1, .*\), nor a "
     r"description file \(\.toml\) or a generated folder \(a path\)",
     "unknown robot 'six_bar': not a built-in robot (cart_pole, five_bar_type1, five_bar_type2, "
     "parallel_3rpr, parallel_3rrr, serial_2dof, serial_3dof, serial_rpr, slider_crank, "
     "slider_crank_slider_driven), nor a description file (.toml) or a generated folder (a "
     "path)")
def never_derived(ctx):
    ps.load("six_bar")


@bad(FILES, "a missing generated folder: `ps.load(\"out/four_bar\")` before deriving",
     LibraryError,
     r"four_bar is not a generated robot folder \(no manifest\.json\): derive one with "
     r"`planar-sym derive ROBOT\.toml --out DIR`, then load DIR/<name>",
     "out/four_bar is not a generated robot folder (no manifest.json): derive one with "
     "`planar-sym derive ROBOT.toml --out DIR`, then load DIR/<name>")
def missing_folder(ctx):
    ps.load(ctx.tmp / "out" / "four_bar")


@bad(FILES, "a name not in the folder given: `ps.load(\"four_bar\", generated=\"out\")`",
     LibraryError,
     r"no generated robot 'four_bar' in .*out \(no .*manifest\.json\): run `planar-sym derive "
     r"four_bar\.toml --out .*out`",
     "no generated robot 'four_bar' in out (no out/four_bar/manifest.json): run `planar-sym "
     "derive four_bar.toml --out out`")
def not_in_generated(ctx):
    (ctx.tmp / "out").mkdir()
    ps.load("four_bar", generated=ctx.tmp / "out")


@bad(FILES, "a plain name for a folder in the working directory: `ps.load(\"four_bar\")`",
     LibraryError,
     r"no robot 'four_bar' among the built-in ones or on PLANAR_SYM_GENERATED; to load the folder "
     r"\./four_bar, pass a path: load\('\./four_bar'\)",
     "no robot 'four_bar' among the built-in ones or on PLANAR_SYM_GENERATED; to load the folder "
     "./four_bar, pass a path: load('./four_bar')")
def folder_by_name(ctx):
    (ctx.tmp / "four_bar").mkdir()
    (ctx.tmp / "four_bar" / "manifest.json").write_text("{}")
    ctx.monkeypatch.chdir(ctx.tmp)
    ps.load("four_bar")


@bad(FILES, "a generated file deleted (`serial_2dof.h`)", LibraryError,
     r"serial_2dof\.h is missing: run `make derive`",
     "generated/serial_2dof/serial_2dof.h is missing: run `make derive`",
     TL + "test_missing_generated_file")
def missing_file(ctx):
    folder = ctx.generated_copy()
    (folder / "serial_2dof.h").unlink()
    Library("serial_2dof", folder=folder)


@bad(FILES, "generated C edited by hand (one byte): the manifest's sha256 no longer matches",
     LibraryError,
     r"serial_2dof\.c does not match .*manifest\.json \(edited by hand or half-written\): run "
     r"`make derive`",
     "generated/serial_2dof/serial_2dof.c does not match generated/serial_2dof/manifest.json "
     "(edited by hand or half-written): run `make derive`",
     TL + "test_one_byte_changed_in_the_c_source")
def edited_c(ctx):
    folder = ctx.generated_copy()
    src = folder / "serial_2dof.c"
    src.write_text(src.read_text().replace("casadi_real", "casadi_reel", 1))
    Library("serial_2dof", folder=folder)


@bad(FILES, "a truncated (unreadable) `manifest.json`", LibraryError,
     r"manifest\.json is unreadable \(.*\): run `make derive`",
     "generated/serial_2dof/manifest.json is unreadable (Unterminated string starting at: line 2 "
     "column 12 (char 13)): run `make derive`")
def broken_manifest(ctx):
    folder = ctx.generated_copy()
    (folder / "manifest.json").write_text('{\n  "robot": "serial')
    Library("serial_2dof", folder=folder)


@bad(FILES, "a generated folder of another robot loaded under this name", LibraryError,
     r"manifest\.json is for robot 'serial_2dof', not 'serial_3dof': run `make derive`",
     "generated/serial_2dof/manifest.json is for robot 'serial_2dof', not 'serial_3dof': run "
     "`make derive`", TL + "test_manifest_of_another_robot")
def another_robot_folder(ctx):
    Library("serial_3dof", folder=ctx.generated_copy())


@bad(FILES, "a compiled library built for another input hash (generated sources re-derived, "
     "library not rebuilt)", LibraryError,
     r"compiled library .*serial_2dof-0123456789abcdef-\S+\.so was built from input hash "
     r"\S+\.\.\., but .*manifest\.json says 0123456789abcdef\.\.\.: delete it and run "
     r"`make build` \(or `make derive` if the generated sources are stale\)",
     "compiled library cache/serial_2dof-0123456789abcdef-<key>.so was built from input hash "
     "<input_hash>..., but generated/serial_2dof/manifest.json says 0123456789abcdef...: "
     "delete it and run `make build` (or `make derive` if the generated sources are stale)",
     TL + "test_library_built_from_another_input_hash")
def another_hash(ctx):
    built = build(GENERATED / "serial_2dof", read_manifest(GENERATED / "serial_2dof"))
    folder = ctx.generated_copy()
    manifest = json.loads((folder / "manifest.json").read_text())
    manifest["input_hash"] = "0123456789abcdef" * 4
    (folder / "manifest.json").write_text(json.dumps(manifest, indent=2))
    ctx.private_cache()
    target = library_path(folder, read_manifest(folder))
    target.parent.mkdir(parents=True)
    shutil.copyfile(built, target)  # the old library where the new hash expects one
    Library("serial_2dof", folder=folder)


@bad(FILES, "a library of another robot (serial_3dof's) where this robot's should be: rebuilt, "
     "and the torques are right afterwards", Warned,
     r"compiled library .*serial_2dof-\S+\.so does not match the hash recorded when it was "
     r"built \(truncated or replaced\): rebuilding it",
     "compiled library cache/serial_2dof-<input_hash>-<key>.so does not match the hash recorded "
     "when it was built (truncated or replaced): rebuilding it")
def another_robot_library(ctx):
    other = build(GENERATED / "serial_3dof", read_manifest(GENERATED / "serial_3dof"))
    folder = ctx.generated_copy()
    ctx.private_cache()
    target = library_path(folder, read_manifest(folder))
    target.parent.mkdir(parents=True)
    shutil.copyfile(other, target)
    _rebuilt_and_right(folder)


@bad(FILES, "a corrupt cached library (garbage bytes in the cache's serial_2dof `.so`): rebuilt, "
     "and the torques are right afterwards", Warned,
     r"compiled library .*serial_2dof-\S+\.so does not match the hash recorded when it was "
     r"built \(truncated or replaced\): rebuilding it",
     "compiled library cache/serial_2dof-<input_hash>-<key>.so does not match the hash recorded "
     "when it was built (truncated or replaced): rebuilding it")
def corrupt_library(ctx):
    folder = GENERATED / "serial_2dof"
    manifest = read_manifest(folder)
    simd = build_simd(folder, manifest)  # in the user's cache
    ctx.private_cache()
    target = library_path(folder, manifest)
    target.parent.mkdir(parents=True)
    target.write_bytes(b"\x00garbage, not a shared library\n" * 64)  # never loaded: new path
    if simd is not None:  # only the exact library needs rebuilding: copy simd and its stamp
        shutil.copyfile(simd, library_path(folder, manifest, "simd"))
        shutil.copyfile(f"{simd}.sha256", f"{library_path(folder, manifest, 'simd')}.sha256")
    _rebuilt_and_right(folder)


def _rebuilt_and_right(folder: Path) -> None:
    """Load (with the warning recorded), check the library is serial_2dof's and the torques are
    the textbook's; then raise the warning as ``Warned`` for the catalogue."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = Robot("serial_2dof", Library("serial_2dof", folder=folder), exact=True)
    target = library_path(folder, robot.library.manifest)
    assert target.read_bytes()[:4] == b"\x7fELF", "not rebuilt"
    rng = np.random.default_rng(6)
    q, qd, qdd = (rng.uniform(-2, 2, (50, 2)) for _ in range(3))
    tau = robot.inverse_dynamics(q, qd, qdd)
    np.testing.assert_allclose(tau, _reference_torques(q, qd, qdd), rtol=1e-12, atol=1e-14)
    np.testing.assert_array_equal(tau, Robot("serial_2dof", _arm().library, exact=True)
                                  .inverse_dynamics(q, qd, qdd))
    rebuilt = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    assert len(rebuilt) == 1, [str(w.message) for w in caught]
    raise Warned(str(rebuilt[0].message))


def _reference_torques(q, qd, qdd) -> np.ndarray:
    """The textbook closed form of the 2-DOF arm (seed Table 1), independent of any library."""
    m1, i1, l1, a1 = 0.071, 89.395e-6, 0.0373, 0.1
    mm, m2, i2, l2 = 0.292, 0.075, 109.864e-6, 0.04168
    g = 9.81
    alpha = i1 + m1 * l1**2 + (mm + m2) * a1**2 + i2 + m2 * l2**2
    beta, delta = m2 * a1 * l2, i2 + m2 * l2**2
    c2, s2 = np.cos(q[:, 1]), np.sin(q[:, 1])
    m11, m12 = alpha + 2 * beta * c2, delta + beta * c2
    h1 = -beta * s2 * (2 * qd[:, 0] * qd[:, 1] + qd[:, 1] ** 2)
    h2 = beta * s2 * qd[:, 0] ** 2
    g1 = ((m1 * l1 + (mm + m2) * a1) * g * np.cos(q[:, 0])
          + m2 * l2 * g * np.cos(q[:, 0] + q[:, 1]))
    g2 = m2 * l2 * g * np.cos(q[:, 0] + q[:, 1])
    return np.column_stack([m11 * qdd[:, 0] + m12 * qdd[:, 1] + h1 + g1,
                            m12 * qdd[:, 0] + delta * qdd[:, 1] + h2 + g2])


@bad(FILES, "no C compiler (none on PATH, CC unset), empty cache: the robot runs on CasADi's "
     "evaluator, and its torques are right", Warned,
     r"\Aserial_2dof: no C compiler found; running on CasADi's own evaluator instead: the same "
     r"numbers, about 20x slower in batches and 500x in simulations and inverse kinematics "
     r"\(install gcc, or set CC to a C compiler, for compiled speed\)\Z",
     "serial_2dof: no C compiler found; running on CasADi's own evaluator instead: the same "
     "numbers, about 20x slower in batches and 500x in simulations and inverse kinematics "
     "(install gcc, or set CC to a C compiler, for compiled speed)",
     see="tests/test_casadi_evaluator.py")
def no_compiler(ctx):
    ctx.private_cache()
    ctx.monkeypatch.delenv("CC", raising=False)
    ctx.monkeypatch.setenv("PATH", str(ctx.tmp / "empty"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = Robot("serial_2dof", Library("serial_2dof", folder=GENERATED / "serial_2dof"))
    assert not robot.library.compiled
    rng = np.random.default_rng(8)
    q, qd, qdd = (rng.uniform(-2, 2, (20, 2)) for _ in range(3))
    np.testing.assert_allclose(robot.inverse_dynamics(q, qd, qdd),
                               _reference_torques(q, qd, qdd), rtol=1e-12, atol=1e-14)
    (shown,) = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    raise Warned(str(shown.message))


@bad(FILES, "no C compiler, and a generated folder made before the functions were saved for "
     "CasADi (no `<quantity>.casadi`)", LibraryError,
     r"no C compiler found \(set CC, or install gcc\): the generated code is compiled on first "
     r"use",
     "no C compiler found (set CC, or install gcc): the generated code is compiled on first use")
def no_compiler_old_folder(ctx):
    ctx.private_cache()
    folder = ctx.generated_copy()
    manifest = json.loads((folder / "manifest.json").read_text())
    for spec in manifest["functions"].values():
        (folder / spec.pop("casadi")).unlink()
    manifest["files"] = {k: v for k, v in manifest["files"].items() if not k.endswith(".casadi")}
    (folder / "manifest.json").write_text(json.dumps(manifest))
    ctx.monkeypatch.delenv("CC", raising=False)
    ctx.monkeypatch.setenv("PATH", str(ctx.tmp / "empty"))
    Library("serial_2dof", folder=folder)


@bad(FILES, "a compiler that fails (`CC=false`), empty cache", LibraryError,
     r"compiling .*serial_2dof\.c failed \(false -O3 -fPIC -std=c99 -c -o .*\):",
     "compiling generated/serial_2dof/serial_2dof.c failed (false -O3 -fPIC -std=c99 -c -o "
     "cache/tmpXXXXXXXX/serial_2dof.o generated/serial_2dof/serial_2dof.c): (then the "
     "compiler's own messages)")
def failing_compiler(ctx):
    ctx.private_cache()
    ctx.monkeypatch.setenv("CC", "false")
    Library("serial_2dof", folder=GENERATED / "serial_2dof")


# -- command line ---------------------------------------------------------------------------------

def _cli(ctx: Ctx, *args: str) -> None:
    from planar_sym.cli import main

    ctx.capsys.readouterr()
    code = main(list(args))
    err = ctx.capsys.readouterr().err
    if code != 0:
        assert code == 2 and "Traceback" not in err, (code, err)
        raise CommandFailed(err.strip())


@bad(CLI, "`planar-sym run serial_2dof_free_swing --samples 5 --samples 7`", CommandFailed,
     r"^error: option --samples is given more than once: give it once",
     "error: option --samples is given more than once: give it once (the last would silently "
     "win)", "tests/test_cli_checks.py::test_an_option_given_twice_is_refused")
def cli_repeated_option(ctx):
    _cli(ctx, "run", "serial_2dof_free_swing", "--samples", "5", "--samples", "7", "--out",
         str(ctx.tmp / "res"))
    assert not (ctx.tmp / "res").exists()


@bad(CLI, "`PLANAR_SYM_EXACT=yes planar-sym run ...`", CommandFailed,
     r"^error: environment variable PLANAR_SYM_EXACT='yes' must be 0 or 1",
     "error: environment variable PLANAR_SYM_EXACT='yes' must be 0 or 1 (1: CasADi's exact "
     "evaluator instead of the compiled C callers)",
     "tests/test_cli_checks.py::test_the_environment_is_read_by_one_rule")
def cli_bad_flag(ctx):
    ctx.monkeypatch.setenv("PLANAR_SYM_EXACT", "yes")
    _cli(ctx, "run", "serial_2dof_free_swing", "--samples", "5", "--out", str(ctx.tmp / "res"))


@bad(CLI, "`planar-sym run no_such_study --out res`", CommandFailed,
     r"^error: unknown study 'no_such_study': not a built-in study \(cart_pole_swing_up, ",
     "error: unknown study 'no_such_study': not a built-in study (cart_pole_swing_up, ...) "
     "nor a study file (.toml)",
     "tests/test_cli.py::test_run_unknown_scenario_writes_nothing")
def cli_unknown_study(ctx):
    _cli(ctx, "run", "no_such_study", "--out", str(ctx.tmp / "res"))
    assert not (ctx.tmp / "res").exists()


@bad(CLI, "`planar-sym derive bad.toml --out DIR` with a negative mass: nothing written",
     CommandFailed,
     r"^error: invalid robot description:\n  .*bad\.toml: bodies\[0\] \(link1\)\.mass: must be "
     r"> 0 kg \(got -1\)",
     "error: invalid robot description:\n  bad.toml: bodies[0] (link1).mass: must be > 0 kg "
     "(got -1)", TD + "test_derive_refuses_and_writes_nothing")
def cli_derive_bad(ctx):
    path = ctx.edited(SERIAL, ("mass = 0.071", "mass = -1.0"))
    out = ctx.tmp / "out"
    try:
        _cli(ctx, "derive", str(path), "--out", str(out), "--quiet")
    finally:
        assert not out.exists() or not any(out.iterdir())


@bad(CLI, "`planar-sym equations no_such_robot`", CommandFailed,
     r"^error: .*no_such_robot",
     "error: no generated code for robot 'no_such_robot' (looked in planar_sym/generated, "
     "generated): run `make derive`",
     "tests/test_cli.py::test_equations_unknown_robot")
def cli_equations_unknown(ctx):
    _cli(ctx, "equations", "no_such_robot")


# -- closed chains off their loops, passive joints --------------------------------------------------

def _five():
    return ps.load("five_bar_type1")


@bad(LOOPS, "inverse dynamics of a slider-driven slider-crank 1e-4 rad of crank from its dead "
     "centre (`ps.inverse_along`, an inverse study): the torques come back, with a warning",
     Warned, r"^slider_crank_slider_driven: near a singular pose from t = 0 s \(sample 0\): the "
     r"passive-joint constraint Jacobian Phi_p has 1-norm condition number [0-9.e+]+ ",
     "slider_crank_slider_driven: near a singular pose from t = 0 s (sample 0): the "
     "passive-joint constraint Jacobian Phi_p has 1-norm condition number 5e+04 (largest "
     "5e+04, at t = 0 s (sample 0); refused above 1e+06). Forces there grow like 1 / the "
     "distance to the singular pose, and so does any error in the geometry or the motion: keep "
     "the motion farther from it, or check the forces against the mechanism's strength",
     "tests/test_split_values.py::test_near_a_singular_pose_the_forces_are_warned_about_with_the_time")
def near_singular_warned(ctx):
    robot = ps.load("slider_crank_slider_driven")
    p = robot.parameters
    r, l, s0 = p["px_crank_A"], p["px_rod_B"], p["s0_slide"]
    theta = 1e-4
    x = r * np.cos(theta) + np.sqrt(l * l - (r * np.sin(theta)) ** 2)
    phi = np.arctan2(-r * np.sin(theta), x - r * np.cos(theta))
    q = np.array([[theta, phi - theta, x - s0]])
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        ps.inverse_along(robot, [0.0], q, 0 * q, 0 * q)
    raise Warned(str(shown[0].message))


@bad(LOOPS, "closed-chain torques for `q` off the loops (a passive angle 10 mrad off)",
     InputError, r"five_bar_type1: sample 0 is off the loop constraints: \|Phi\| = [0-9.e-]+ m "
     r"at cut joint C \(limit 1e-09\)",
     "five_bar_type1: sample 0 is off the loop constraints: |Phi| = 0.00101 m at cut joint C "
     "(limit 1e-09); give q, qd, qdd that close the loops (inverse_kinematics, from_actuated)",
     "tests/test_loop_inputs.py")
def off_loops_q(ctx):
    five = _five()
    q = five.q_drawn.copy()
    q[1] += 0.01
    five.closed_chain_inverse_dynamics(q, 0 * q, 0 * q)


@bad(LOOPS, "closed-chain torques for rates that break the loop (only A moving)", InputError,
     r"sample 0 is off the loop constraints: \|Phi_q qd\| = [0-9.e-]+ m/s at cut joint C",
     "five_bar_type1: sample 0 is off the loop constraints: |Phi_q qd| = 0.14 m/s at cut joint "
     "C (limit 2e-09); give q, qd, qdd that close the loops (inverse_kinematics, from_actuated)")
def off_loops_qd(ctx):
    five = _five()
    five.closed_chain_inverse_dynamics(five.q_drawn, [1.0, 0.0, 0.0, 0.0], np.zeros(4))


@bad(LOOPS, "closed-chain torques for accelerations that break the loop", InputError,
     r"sample 0 is off the loop constraints: \|Phi_q qdd - gamma\| = [0-9.e-]+ m/s\^2",
     "five_bar_type1: sample 0 is off the loop constraints: |Phi_q qdd - gamma| = 0.14 m/s^2 at "
     "cut joint C (limit 2e-09); give q, qd, qdd that close the loops (inverse_kinematics, "
     "from_actuated)")
def off_loops_qdd(ctx):
    five = _five()
    five.closed_chain_inverse_dynamics(five.q_drawn, np.zeros(4), [1.0, 0.0, 0.0, 0.0])


@bad(LOOPS, "`simulate` a closed chain from a `q0` off the loops (no longer projected silently)",
     InputError, r"five_bar_type1: q0 is off the loop constraints: \|Phi\| = .*project=True",
     "five_bar_type1: q0 is off the loop constraints: |Phi| = 0.00101 m at cut joint C (limit "
     "1e-09); give a state on the loops (planar_sym.from_actuated), or pass "
     "project=True (planar_sym.simulate) to solve the passive joints from the actuated ones",
     "tests/test_loop_inputs.py::test_simulate_does_not_move_a_state_off_the_loops")
def off_loops_q0(ctx):
    five = _five()
    q = five.q_drawn.copy()
    q[1] += 0.01
    ps.simulate(five, q, np.zeros(4), (0.0, 0.1))


@bad(LOOPS, "`simulate` a closed chain from rates that break the loop", InputError,
     r"five_bar_type1: qd0 is off the loop constraints: \|Phi_q qd\|",
     "five_bar_type1: qd0 is off the loop constraints: |Phi_q qd| = 0.14 m/s at cut joint C "
     "(limit 2e-09); give a state on the loops (planar_sym.from_actuated), or pass "
     "project=True (planar_sym.simulate) to solve the passive joints from the actuated ones")
def off_loops_qd0(ctx):
    five = _five()
    ps.simulate(five, five.q_drawn, [1.0, 0.0, 0.0, 0.0], (0.0, 0.1))


@bad(LOOPS, "joint torques of a serial arm whose elbow has no motor (`actuated = false`)",
     InputError, r"passive_elbow: joint joint2 has no motor \(actuated = false\)",
     "passive_elbow: joint joint2 has no motor (actuated = false): a serial robot cannot follow "
     "an arbitrary joint trajectory with a passive joint, so there is no torque to return "
     "there; simulate it under the actuated joints' torques (planar_sym.simulate) or mark the "
     "joint actuated", "tests/test_never_silent.py")
def passive_tree_joint(ctx):
    text = SERIAL.replace('name = "serial_2dof"', 'name = "passive_elbow"')
    head, tail = text.split('name = "joint2"')
    path = ctx.tmp / "passive_elbow.toml"
    path.write_text(head + 'name = "joint2"' + tail.replace("actuated = true", "actuated = false", 1))
    robot = ps.load(path)
    robot.inverse_dynamics(np.zeros(2), np.zeros(2), np.zeros(2))


@bad(LOOPS, "two initial states given to `simulate` (the first one used to be taken)", InputError,
     r"q0 must be one vector of 2 values, got 2 rows \(shape \(2, 2\)\)",
     "q0 must be one vector of 2 values, got 2 rows (shape (2, 2))",
     "tests/test_never_silent.py")
def two_initial_states(ctx):
    ps.simulate(_arm(), np.zeros((2, 2)), np.zeros(2), (0.0, 1.0))


@bad(LOOPS, "a NaN in `t_eval` (it used to fail later as an integrator error)", InputError,
     r"t_eval\[1\] is nan: times must be finite", "t_eval[1] is nan: times must be finite")
def nan_t_eval(ctx):
    ps.simulate(_arm(), np.zeros(2), np.zeros(2), (0.0, 1.0), t_eval=[0.0, np.nan, 1.0])


@bad(LOOPS, "a mass made negative at run time: `with_parameters(m_link1=-0.1)`", InputError,
     r"serial_2dof: parameter m_link1 must be > 0 kg \(got -0.1\)",
     "serial_2dof: parameter m_link1 must be > 0 kg (got -0.1)", "tests/test_study_files.py")
def runtime_negative_mass(ctx):
    _arm().with_parameters(m_link1=-0.1)


@bad(LOOPS, "an inertia in kg*mm^2 given as kg*m^2 at run time: `izz_link1=89.395`", InputError,
     r"parameter izz_link1 = 89.395 kg\*m\^2 with m_link1 = 0.071 kg gives a radius of gyration",
     "serial_2dof: parameter izz_link1 = 89.395 kg*m^2 with m_link1 = 0.071 kg gives a radius of "
     "gyration of 3.548e+04 mm for a body whose points reach 62.7 mm from its centre of "
     "gravity (more than 3 times); a unit or decimal-point slip?")
def runtime_inertia_slip(ctx):
    _arm().with_parameters(izz_link1=89.395)


@bad(LOOPS, "gravity in mm/s^2 at run time: `with_parameters(g=9810)`", InputError,
     r"parameter g \(gravity magnitude\) must be from 0 to 300 m/s\^2 \(got 9810\); a unit "
     r"slip\?",
     "serial_2dof: parameter g (gravity magnitude) must be from 0 to 300 m/s^2 (got 9810); a "
     "unit slip?")
def runtime_gravity_slip(ctx):
    _arm().with_parameters(g=9810.0)


@bad(LOOPS, "`ps.load(3)`: not a name, file or folder", InputError,
     r"a robot is a built-in name, a description file or a generated folder \(a str or Path\), "
     r"got int", "a robot is a built-in name, a description file or a generated folder (a str "
     "or Path), got int 3", "tests/test_never_silent.py")
def load_not_a_path(ctx):
    ps.load(3)


@bad(LOOPS, "`simulate(arm, q0, qd0, 5)`: a time span that is one number", InputError,
     r"time span must be two numbers \(t0, t1\) in s \(got 5\)",
     "time span must be two numbers (t0, t1) in s (got 5)")
def span_one_number(ctx):
    ps.simulate(_arm(), np.zeros(2), np.zeros(2), 5)


@bad(LOOPS, "a torque function that returns text", InputError,
     r"torque function returned something that is not numbers at t = 0 s",
     "torque function returned something that is not numbers at t = 0 s (could not convert "
     "string to float: 'x')")
def torque_text(ctx):
    ps.simulate(_arm(), np.zeros(2), np.zeros(2), (0.0, 1.0), torque=lambda t: "x")


# -- study files ------------------------------------------------------------------------------------

STUDY_OK = """
robot = "serial_2dof"
kind = "inverse"
[units]
length = "mm"
[motion]
space = "task"
start = [100.0, 100.0]
by = [-200.0, 0.0]
duration = 5.0
"""


def _study(ctx, text: str):
    from planar_sym.study.run import run

    path = ctx.tmp / "study.toml"
    path.write_text(text)
    return run(path)


@bad(STUDY, "a study with a typo, an unknown unit and a negative duration: all reported at once",
     InputError, r"study.toml: colour: unknown key(.|\n)*units.length: unknown length unit "
     r"'furlong'(.|\n)*motion.duration: must be > 0 \(got -5\)",
     "invalid study:\n  study.toml: colour: unknown key (known: kind, motion, notes, outputs, "
     "parameters, robot, simulation, title, units)\n  study.toml: units.length: unknown length "
     "unit 'furlong'; known: m, cm, mm (got 'furlong')\n  study.toml: motion.duration: must be "
     "> 0 (got -5)", "tests/test_study_files.py::test_every_problem_of_a_study_at_once")
def study_three_problems(ctx):
    _study(ctx, 'colour = "red"\n' + STUDY_OK.replace('"mm"', '"furlong"').replace(
        "duration = 5.0", "duration = -5"))


@bad(STUDY, "an inverse-dynamics study without its `[motion]` table", InputError,
     r"study.toml: motion: missing table \[motion\]",
     "invalid study:\n  study.toml: motion: missing table [motion]")
def study_no_motion(ctx):
    _study(ctx, 'robot = "serial_2dof"\nkind = "inverse"\n')


@bad(STUDY, "an unknown profile", InputError,
     r"motion.profile: must be one of cubic, quintic, trapezoid, via, table \(got 'zigzag'\)",
     "invalid study:\n  study.toml: motion.profile: must be one of cubic, quintic, trapezoid, "
     "via, table (got 'zigzag')")
def study_unknown_profile(ctx):
    _study(ctx, STUDY_OK.replace('space = "task"', 'space = "task"\nprofile = "zigzag"'))


@bad(STUDY, "an unknown parameter in `[parameters]`", InputError,
     r"parameters.m_motr2: not a parameter of serial_2dof \(known: g, m_link1, ",
     "study.toml: parameters.m_motr2: not a parameter of serial_2dof (known: g, m_link1, ...)",
     "tests/test_study_files.py")
def study_unknown_parameter(ctx):
    _study(ctx, STUDY_OK + "[parameters]\nm_motr2 = 0.5\n")


@bad(STUDY, "a parameter with a unit of the wrong kind: `m_link1 = \"71 mm\"`", InputError,
     r"parameters.m_link1: unknown mass unit 'mm'; known: kg, g for a mass \(got 'mm'\)",
     "study.toml: parameters.m_link1: unknown mass unit 'mm'; known: kg, g for a mass (got 'mm')")
def study_wrong_unit(ctx):
    _study(ctx, STUDY_OK + "[parameters]\nm_link1 = \"71 mm\"\n")


@bad(STUDY, "a start with 3 values for a robot with a 2-coordinate task", InputError,
     r"motion.start: serial_2dof needs 2 values, one per task coordinate \(x, y\) \(got 3\)",
     "study.toml: motion.start: serial_2dof needs 2 values, one per task coordinate (x, y) "
     "(got 3)")
def study_start_width(ctx):
    _study(ctx, STUDY_OK.replace("[100.0, 100.0]", "[100.0, 100.0, 0.0]").replace(
        "[-200.0, 0.0]", "[-200.0, 0.0, 0.0]"))


@bad(STUDY, "a closed chain's initial state off its loops in a forward study", InputError,
     r"simulation.q0 does not close the loop at cut joint C: the joint's two points are "
     r"[0-9.]+ mm apart \(limit 1e-06 mm\); give the actuated joints only \(2 values\)",
     "study.toml: simulation.q0 does not close the loop at cut joint C: the joint's two points "
     "are 2.62 mm apart (limit 1e-06 mm); give the actuated joints only (2 values) and the "
     "loops give the rest", "tests/test_study_files.py")
def study_q0_off_loops(ctx):
    _study(ctx, 'robot = "five_bar_type2"\nkind = "forward"\n[units]\nangle = "deg"\n'
                '[simulation]\nq0 = [0.0, 90.0, 92.0, 90.0]\nduration = 0.2\n')


@bad(STUDY, "a study naming a robot that does not exist", LibraryError,
     r"unknown robot 'no_such_robot': not a built-in robot",
     "unknown robot 'no_such_robot': not a built-in robot (cart_pole, ...), nor a "
     "description file (.toml) or a generated folder (a path)")
def study_unknown_robot(ctx):
    _study(ctx, STUDY_OK.replace('"serial_2dof"', '"no_such_robot"'))


@bad(CLI, "`planar-sym run STUDY --samples 10000000000`", CommandFailed,
     r"^error: --samples must be an integer from 2 to 1000000 \(got 10000000000\)",
     "error: --samples must be an integer from 2 to 1000000 (got 10000000000)",
     "tests/test_cli_edges.py")
def cli_absurd_samples(ctx):
    _cli(ctx, "run", "serial_2dof_joint_move", "--samples", "10000000000", "--out",
         str(ctx.tmp / "res"))


@bad(CLI, "`planar-sym animate STUDY --frames 99999`", CommandFailed,
     r"^error: --frames must be an integer from 2 to 2000 \(got 99999\)",
     "error: --frames must be an integer from 2 to 2000 (got 99999)")
def cli_absurd_frames(ctx):
    _cli(ctx, "animate", "serial_2dof_joint_move", "--frames", "99999", "--out",
         str(ctx.tmp / "a.gif"))


@bad(CLI, "`planar-sym animate STUDY --frames 2000 --dpi 600`: frames that would not fit in "
         "memory", CommandFailed,
     r"^error: --frames 2000 at --dpi 600 would hold 55\.64 GB of images in memory \(limit 2 "
     r"GB\): fewer frames or a lower dpi",
     "error: --frames 2000 at --dpi 600 would hold 55.64 GB of images in memory (limit 2 GB): "
     "fewer frames or a lower dpi", "tests/test_animation_frames.py")
def cli_frames_beyond_memory(ctx):
    _cli(ctx, "animate", "serial_2dof_joint_move", "--frames", "2000", "--dpi", "600", "--out",
         str(ctx.tmp / "a.gif"))


@bad(CLI, "`planar-sym run STUDY --out results.txt` where that is a file", CommandFailed,
     r"^error: --out .*results.txt is a file, not a folder",
     "error: --out results.txt is a file, not a folder", "tests/test_cli_edges.py")
def cli_out_is_a_file(ctx):
    target = ctx.tmp / "results.txt"
    target.write_text("mine")
    _cli(ctx, "run", "serial_2dof_joint_move", "--out", str(target))


@bad(CLI, "`planar-sym validate ROBOT --description missing.toml`", CommandFailed,
     r"^error: --description missing.toml: no such file",
     "error: --description missing.toml: no such file")
def cli_missing_description(ctx):
    _cli(ctx, "validate", "serial_2dof", "--description", "missing.toml")


@bad(CLI, "`planar-sym derive four_bar.toml --out DIR` where DIR/four_bar holds a file of yours",
     CommandFailed, r"^error: .*four_bar holds files planar-sym did not write \(notes.txt\)",
     "error: DIR/four_bar holds files planar-sym did not write (notes.txt): it is not replaced; "
     "move them or choose another --out", "tests/test_cli_edges.py")
def cli_derive_users_folder(ctx):
    out = ctx.tmp / "out"
    folder = out / "four_bar"
    folder.mkdir(parents=True)
    (folder / "manifest.json").write_text('{"files": {}}')
    (folder / "notes.txt").write_text("my notes")
    _cli(ctx, "derive", str(ROOT / "examples" / "four_bar.toml"), "--out", str(out),
         "--no-build")


# -- structure of closed chains: degrees of freedom (issue 10) --

MOBILITY = ROOT / "tests" / "data" / "mobility"
FOUR = (ROOT / "examples" / "four_bar.toml").read_text()
F_4BAR = ("F = 3 x 3 moving bodies - 2 x 4 revolute joints = 3 coordinates - 2 x 1 cut joint "
          "(B) = 1")


@bad(DESC, "a closed chain with more actuated joints than degrees of freedom (four-bar, rocker "
     "actuated too)", DescriptionError,
     r"bad\.toml: joints: over-actuated: 2 actuated joints \(crank_joint, rocker_joint\) for "
     r"F = 3 x 3 moving bodies - 2 x 4 revolute joints = 3 coordinates - 2 x 1 cut joint \(B\) "
     r"= 1 degree of freedom",
     f"bad.toml: joints: over-actuated: 2 actuated joints (crank_joint, rocker_joint) for "
     f"{F_4BAR} degree of freedom: the motors fight each other and the closed-chain torques "
     "are not unique; mark 1 of them actuated = false", "tests/test_mobility.py")
def over_actuated(ctx):
    _desc(ctx, FOUR, ('child = "rocker.O4"\nactuated = false',
                      'child = "rocker.O4"\nactuated = true'))


@bad(DESC, "a closed chain with fewer actuated joints than degrees of freedom (5-bar, E passive)",
     DescriptionError,
     r"bad\.toml: joints: under-actuated: 1 actuated joint \(A\) for F = .* = 2 degrees of "
     r"freedom: .*mark 1 of B, E, D actuated = true",
     "bad.toml: joints: under-actuated: 1 actuated joint (A) for F = 3 x 4 moving bodies - 2 x 5 "
     "revolute joints = 4 coordinates - 2 x 1 cut joint (C) = 2 degrees of freedom: the actuated "
     "joints do not determine the motion, so there is no closed-chain inverse dynamics along "
     "their trajectory (a closed chain needs exactly F actuated joints); mark 1 of B, E, D "
     "actuated = true", "tests/test_mobility.py")
def under_actuated(ctx):
    _desc(ctx, FIVE_BAR, ('child = "R_Link1.CS1"\nactuated = true',
                          'child = "R_Link1.CS1"\nactuated = false'))


@bad(DESC, "a closed chain with no actuated joint (free release)", DescriptionError,
     r"bad\.toml: joints: no actuated joint for F = .* = 1 degree of freedom: a free-release "
     r"closed chain is not supported",
     f"bad.toml: joints: no actuated joint for {F_4BAR} degree of freedom: a free-release closed "
     "chain is not supported (its compiled functions split the coordinates into F actuated and "
     "2 per cut passive ones); mark 1 of crank_joint, coupler_joint, rocker_joint actuated = "
     "true", "tests/test_mobility.py")
def no_actuator(ctx):
    _desc(ctx, FOUR, ('child = "crank.O2"\nactuated = true',
                      'child = "crank.O2"\nactuated = false'))


@bad(DESC, "a loop cut twice: a second cut joint `B2` joining coupler.B to rocker.B",
     DescriptionError,
     r"bad\.toml: joints: loop cut twice: B and B2 both join coupler\.B to rocker\.B",
     "bad.toml: joints: loop cut twice: B and B2 both join coupler.B to rocker.B, so B2 closes "
     "no new loop, it only repeats B's 2 equations; remove B2", "tests/test_mobility.py")
def loop_cut_twice(ctx):
    cut = ('[[joints]]\nname = "B2"\ntype = "revolute"\nparent = "coupler.B"\n'
           'child = "rocker.B"\nactuated = false\ncloses_loop = true\n\n[task]')
    _desc(ctx, FOUR, ("[task]", cut))


@bad(DESC, "a cut that leaves the tree disconnected: the rocker's ground joint marked "
     "`closes_loop = true` too", DescriptionError,
     r"bad\.toml: joints: bodies \['rocker'\] reach ground only through cut joints "
     r"\(rocker_joint, B\): 2 cuts for 1 independent loop",
     "bad.toml: joints: bodies ['rocker'] reach ground only through cut joints (rocker_joint, "
     "B): 2 cuts for 1 independent loop leave the tree disconnected; make rocker_joint or B a "
     "tree joint (closes_loop = false)", "tests/test_mobility.py")
def cut_disconnects_tree(ctx):
    _desc(ctx, FOUR, ('child = "rocker.O4"\nactuated = false',
                      'child = "rocker.O4"\nactuated = false\ncloses_loop = true'))


@bad(DESC, "no degree of freedom: two bars pinned to ground and to each other (a triangle)",
     DescriptionError,
     r"bad\.toml: joints: a structure, not a mechanism: F = .* = 0 degrees of freedom and Phi_q "
     r"has full rank 2",
     "bad.toml: joints: a structure, not a mechanism: F = 3 x 2 moving bodies - 2 x 3 revolute "
     "joints = 2 coordinates - 2 x 1 cut joint (A) = 0 degrees of freedom and Phi_q has full "
     "rank 2 at the drawn pose, so nothing moves; remove a link, or split one with a joint",
     "tests/test_mobility.py")
def structure(ctx):
    _desc(ctx, (MOBILITY / "triangle.toml").read_text())


@bad(DESC, "a redundant constraint: a parallelogram with an extra parallel link (Gruebler 0, "
     "yet it moves)", DescriptionError,
     r"bad\.toml: joints: redundant constraint: the 4 loop-closure equations of loops B, C have "
     r"rank 3 at the drawn pose .* it moves with 1 degree of freedom where F = .* = 0",
     "bad.toml: joints: redundant constraint: the 4 loop-closure equations of loops B, C have "
     "rank 3 at the drawn pose (Phi_q 4 x 4, smallest singular value 1.5e-18 m of 0.355 m) and "
     "keep it as the mechanism moves: it moves with 1 degree of freedom where F = 3 x 4 moving "
     "bodies - 2 x 6 revolute joints = 4 coordinates - 2 x 2 cut joints (B, C) = 0 (an extra "
     "link parallel to a parallelogram's, say); remove the redundant link or joint: the loop "
     "equations must be independent", "tests/test_mobility.py")
def redundant_constraint(ctx):
    _desc(ctx, (MOBILITY / "parallelogram.toml").read_text())


@bad(DESC, "a singular drawn pose: a change-point four-bar drawn flat", DescriptionError,
     r"bad\.toml: joints: singular drawn pose: the 2 loop-closure equations of loop B have rank "
     r"1 at the drawn pose .*: 2 degrees of freedom there where the count gives F = .* = 1",
     "bad.toml: joints: singular drawn pose: the 2 loop-closure equations of loop B have rank 1 "
     "at the drawn pose (Phi_q 2 x 3, smallest singular value 3.4e-17 m of 0.242 m): 2 degrees "
     "of freedom there where the count gives F = 3 x 3 moving bodies - 2 x 4 revolute joints = "
     "3 coordinates - 2 x 1 cut joint (B) = 1; links are aligned (a dead-centre or change "
     "point): draw the robot away from it, every Newton solve and simulation starts there",
     "tests/test_mobility.py")
def singular_drawn_pose(ctx):
    _desc(ctx, (MOBILITY / "flat_four_bar.toml").read_text())


# -- plausibility and cascades (issue 10) --
# (a pattern starting (?:\A|:\n  \S*) and ending \Z: the message is that one problem line)

def _warned(ctx: Ctx, text: str, *edits) -> None:
    """Load an edited description that must load; its one warning raised as ``Warned``."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        description.load(ctx.edited(text, *edits))
    shown = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    assert len(shown) == 1, [str(w.message) for w in caught]
    raise Warned(str(shown[0].message))


TP = "tests/test_plausibility.py::"
TC = "tests/test_cascades.py::"


@bad(DESC, "lengths in m with `length = \"mm\"` (the robot 0.2 mm across)", DescriptionError,
     r"bad\.toml: units\.length: the robot spans 0\.2 mm \(from ground\.O to link2\.CS2\): "
     r"below 1 mm the joints' closure tolerance \(0\.01 mm\) cannot tell its points apart; were "
     r"the lengths typed in another unit\? \(units\.length = \"m\" makes it 200 mm",
     "bad.toml: units.length: the robot spans 0.2 mm (from ground.O to link2.CS2): below 1 mm "
     "the joints' closure tolerance (0.01 mm) cannot tell its points apart; were the lengths "
     "typed in another unit? (units.length = \"m\" makes it 200 mm, \"cm\" makes it 2 mm)",
     TP + "test_lengths_in_m_typed_with_mm_is_an_error")
def length_unit_too_small(ctx):
    _desc(ctx, SERIAL, ('length = "m"', 'length = "mm"'))


@bad(DESC, "lengths in mm with `length = \"m\"` (the four-bar 152 m across)", Warned,
     r"bad\.toml: units\.length: the robot spans 152\.2 m \(from ground\.O2 to coupler\.B\) \(a "
     r"warning above 100 m: only the largest cranes are that big\); were the lengths typed in "
     r"another unit\? \(units\.length = \"cm\" makes it 1\.522 m, \"mm\" makes it 152\.2 mm\)",
     "bad.toml: units.length: the robot spans 152.2 m (from ground.O2 to coupler.B) (a warning "
     "above 100 m: only the largest cranes are that big); were the lengths typed in another "
     "unit? (units.length = \"cm\" makes it 1.522 m, \"mm\" makes it 152.2 mm)",
     TP + "test_lengths_in_mm_typed_with_m_warns")
def length_unit_too_large(ctx):
    _warned(ctx, FOUR, ('length = "mm"', 'length = "m"'))


@bad(DESC, "joint angles in degrees with `angle = \"rad\"` (`pose = \"joints\"`, crank at -60)",
     Warned,
     r"bad\.toml: joints\[0\] \(crank_joint\)\.angle: -60 rad is 9\.55 turns \(a warning "
     r"beyond one\): the drawn pose takes it as 162\.3 deg; were the angles typed in degrees\? "
     r"\(units\.angle = \"deg\" makes it -60 deg\)",
     "bad.toml: joints[0] (crank_joint).angle: -60 rad is 9.55 turns (a warning beyond one): the "
     "drawn pose takes it as 162.3 deg; were the angles typed in degrees? (units.angle = "
     "\"deg\" makes it -60 deg)", TP + "test_joint_angles_in_degrees_typed_with_rad_warn")
def angle_unit_slip(ctx):
    _warned(ctx, (ROOT / "examples" / "four_bar_joints.toml").read_text(),
            ('angle = "deg"', 'angle = "rad"'), ("angle = 60.0", "angle = -60.0"),
            ("angle = -40.0", "angle = -0.349"), ("angle = 65.0", "angle = 2.618"))


@bad(DESC, "a robot a kilometre across: link2's tip at `[1500.0, 0.0]` m", DescriptionError,
     r"bad\.toml: units\.length: the robot spans 1500 m \(from ground\.O to link2\.CS2\) \(no "
     r"planar linkage is a kilometre across\)",
     "bad.toml: units.length: the robot spans 1500 m (from ground.O to link2.CS2) (no planar "
     "linkage is a kilometre across); were the lengths typed in another unit? (units.length = "
     "\"cm\" makes it 15 m, \"mm\" makes it 1.5 m)", TP + "test_a_kilometre_is_an_error")
def length_kilometre(ctx):
    _desc(ctx, SERIAL, ("CS2 = [0.2, 0.0] }", "CS2 = [1500.0, 0.0] }"))


@bad(DESC, "gravity in mm/s^2 with `acceleration = \"m/s^2\"`: `gravity = [0.0, -9810.0]`",
     DescriptionError,
     r"bad\.toml: gravity: magnitude 9810 m/s\^2 is above 300 m/s\^2 \(the Sun's surface gives "
     r"274; run-time parameters are refused beyond it too\); typed in another unit\? "
     r"\(units\.acceleration = \"mm/s\^2\" makes it 9\.81 m/s\^2\)",
     "bad.toml: gravity: magnitude 9810 m/s^2 is above 300 m/s^2 (the Sun's surface gives 274; "
     "run-time parameters are refused beyond it too); typed in another unit? "
     "(units.acceleration = \"mm/s^2\" makes it 9.81 m/s^2)",
     TP + "test_gravity_in_mm_typed_with_m_is_an_error")
def gravity_too_large(ctx):
    _desc(ctx, SERIAL, ("gravity = [0.0, -9.81]", "gravity = [0.0, -9810.0]"))


@bad(DESC, "gravity in m/s^2 with `acceleration = \"mm/s^2\"` (0.00981 m/s^2)", Warned,
     r"bad\.toml: gravity: magnitude 0\.00981 m/s\^2 is less than any planet's \(Pluto: 0\.62; a "
     r"warning below 0\.1 m/s\^2; gravity = \[0, 0\] says a horizontal robot\); typed in another "
     r"unit\? \(units\.acceleration = \"m/s\^2\" makes it 9\.81 m/s\^2\)",
     "bad.toml: gravity: magnitude 0.00981 m/s^2 is less than any planet's (Pluto: 0.62; a "
     "warning below 0.1 m/s^2; gravity = [0, 0] says a horizontal robot); typed in another "
     "unit? (units.acceleration = \"m/s^2\" makes it 9.81 m/s^2)",
     TP + "test_gravity_in_m_typed_with_mm_warns")
def gravity_too_small(ctx):
    _warned(ctx, SERIAL, ('acceleration = "m/s^2"', 'acceleration = "mm/s^2"'))


@bad(DESC, "gravity in cm/s^2 typed with `acceleration = \"mm/s^2\"`: `gravity = [0.0, -981.0]`",
     Warned,
     r"bad\.toml: gravity: magnitude 0\.981 m/s\^2 is Earth's 9\.81 m/s\^2 times 1e-1: a unit or "
     r"decimal slip\? \(cm/s\^2 typed as mm/s\^2 gives this",
     "bad.toml: gravity: magnitude 0.981 m/s^2 is Earth's 9.81 m/s^2 times 1e-1: a unit or "
     "decimal slip? (cm/s^2 typed as mm/s^2 gives this: give gravity in m/s^2; a robot on a "
     "tilted table feels g sin(tilt), which may be anything: then ignore this)",
     TP + "test_gravity_typed_in_cm_is_named_not_sent_to_mm")
def gravity_cm_as_mm(ctx):
    _warned(ctx, SERIAL, ("gravity = [0.0, -9.81]", "gravity = [0.0, -981.0]"),
            ('acceleration = "m/s^2"', 'acceleration = "mm/s^2"'))


@bad(DESC, "gravity ten times Earth's: `gravity = [0.0, -98.1]`", Warned,
     r"bad\.toml: gravity: magnitude 98\.1 m/s\^2 is more than any planet's \(Jupiter: 24\.8; a "
     r"warning above 30 m/s\^2\); it is Earth's 9\.81 m/s\^2 times 1e\+1: a decimal slip\?",
     "bad.toml: gravity: magnitude 98.1 m/s^2 is more than any planet's (Jupiter: 24.8; a "
     "warning above 30 m/s^2); it is Earth's 9.81 m/s^2 times 1e+1: a decimal slip?",
     TP + "test_gravity_bounds")
def gravity_high(ctx):
    _warned(ctx, SERIAL, ("gravity = [0.0, -9.81]", "gravity = [0.0, -98.1]"))


@bad(DESC, "a cg typed as its world x: the four-bar rocker's `cg = [116.94..., 36.23...]` "
     "from O4", Warned,
     r"bad\.toml: bodies\[2\] \(rocker\)\.cg: the centre of gravity lies 90\.62 mm outside the "
     r"outline of the body's points, 1\.13 times the body's size of 80 mm \(a warning beyond 1 "
     r"times, an error beyond 10\); cg is measured from cg_from = 'O4' in world axes",
     "bad.toml: bodies[2] (rocker).cg: the centre of gravity lies 90.62 mm outside the outline "
     "of the body's points, 1.13 times the body's size of 80 mm (a warning beyond 1 times, an "
     "error beyond 10); cg is measured from cg_from = 'O4' in world axes: does cg_from name "
     "the wrong point, or is cg in world coordinates or another unit? If the mass is really "
     "there, give the body a point there", TP + "test_cg_in_world_coordinates_warns")
def cg_world(ctx):
    _warned(ctx, FOUR, ("cg = [16.940482998, 36.235618330]",
                        "cg = [116.940482998, 36.235618330]"))


@bad(DESC, "a cg typed in mm in a file in m: link2 `cg = [41.68, 0.0]`", DescriptionError,
     r"bad\.toml: bodies\[2\] \(link2\)\.cg: the centre of gravity lies 41\.58 m outside the "
     r"outline of the body's points, 416 times the body's size of 100 mm",
     "bad.toml: bodies[2] (link2).cg: the centre of gravity lies 41.58 m outside the outline of "
     "the body's points, 416 times the body's size of 100 mm (a warning beyond 1 times, an "
     "error beyond 10); cg is measured from cg_from = 'CS1' in world axes: does cg_from name "
     "the wrong point, or is cg in world coordinates or another unit? If the mass is really "
     "there, give the body a point there", TP + "test_cg_in_mm_in_a_metre_file_is_an_error")
def cg_unit(ctx):
    _desc(ctx, SERIAL, ("cg = [0.04168, 0.0]", "cg = [41.68, 0.0]"))


@bad(DESC, "an empty display name: `m_link1 = \"\"` in [symbols]", DescriptionError,
     r"bad\.toml: symbols\.m_link1: display name '' of parameter m_link1 is empty: the "
     r"equations would show nothing for it",
     "bad.toml: symbols.m_link1: display name '' of parameter m_link1 is empty: the equations "
     "would show nothing for it", TP + "test_bad_display_name_is_refused")
def symbol_empty(ctx):
    _desc(ctx, SERIAL, ('m_link1 = "m_1"', 'm_link1 = ""'))


@bad(DESC, "a display name that is not LaTeX: `m_link1 = \"m_{1\"` (a brace left open)",
     DescriptionError,
     r"bad\.toml: symbols\.m_link1: display name 'm_\{1' of parameter m_link1 is not valid LaTeX "
     r"\(Expected end_group, found end of text\): the equation report would lose the symbol",
     "bad.toml: symbols.m_link1: display name 'm_{1' of parameter m_link1 is not valid LaTeX "
     "(Expected end_group, found end of text): the equation report would lose the symbol",
     TP + "test_bad_display_name_is_refused")
def symbol_latex(ctx):
    _desc(ctx, SERIAL, ('m_link1 = "m_1"', 'm_link1 = "m_{1"'))


@bad(DESC, "a point written as a 3-vector: link1 `CS2 = [0.1, 0.0, 0.0]` (one message: no "
     "'points coincide' or 'joint does not close' after it)", DescriptionError,
     r"(?:\A|:\n  \S*)bad\.toml: bodies\[0\] \(link1\)\.points\.CS2: must be a list of two "
     r"numbers \[x, y\] \(got \[0\.1, 0\.0, 0\.0\]\)\Z",
     "bad.toml: bodies[0] (link1).points.CS2: must be a list of two numbers [x, y] (got [0.1, "
     "0.0, 0.0])", TC + "test_one_mistake_one_message")
def point_3_vector(ctx):
    _desc(ctx, SERIAL, ("CS1 = [0.0, 0.0], CS2 = [0.1, 0.0] }",
                        "CS1 = [0.0, 0.0], CS2 = [0.1, 0.0, 0.0] }"))


@bad(DESC, "a body without a name (link2's `name` deleted; one message: the joint and task "
     "naming link2 say nothing)", DescriptionError,
     r"(?:\A|:\n  \S*)bad\.toml: bodies\[2\]\.name: missing\Z", "bad.toml: bodies[2].name: missing",
     TC + "test_one_mistake_one_message")
def body_name_missing(ctx):
    _desc(ctx, SERIAL, ('name = "link2"\n', ""))


@bad(DESC, "a misspelt joint type `type = \"welded\"` (one message: no 'actuated' missing)",
     DescriptionError,
     r"(?:\A|:\n  \S*)bad\.toml: joints\[1\] \(weld_motor2\)\.type: must be 'revolute', "
     r"'prismatic' or 'weld' \(got 'welded'\)\Z",
     "bad.toml: joints[1] (weld_motor2).type: must be 'revolute', 'prismatic' or 'weld' (got "
     "'welded')",
     TC + "test_one_mistake_one_message")
def joint_type_misspelt(ctx):
    _desc(ctx, SERIAL, ('type = "weld"', 'type = "welded"'))


# -- joint loads (planar_sym.dynamics.reactions) ------------------------------------------------

def _old_folder(ctx) -> Robot:
    """serial_2dof from a generated folder derived before joint loads: its manifest has no
    joints, no gravity direction and no body_motion function."""
    folder = ctx.generated_copy()
    manifest = json.loads((folder / "manifest.json").read_text())
    for key in ("joints", "gravity_direction"):
        manifest.pop(key)
    manifest["functions"].pop("body_motion")
    (folder / "manifest.json").write_text(json.dumps(manifest, indent=2))
    return Robot("serial_2dof", Library("serial_2dof", folder=folder))


@bad(FILES, "joint loads (`joint_loads`, a study's `jfx_` columns) of a robot whose generated "
     "folder was derived before them", LibraryError,
     r"serial_2dof: the generated code in \S*serial_2dof predates joint loads \(its manifest "
     r"lists no joints\): re-derive it \(`make derive`, or `planar-sym derive` for your own "
     r"robot\)",
     "serial_2dof: the generated code in generated/serial_2dof predates joint loads (its "
     "manifest lists no joints): re-derive it (`make derive`, or `planar-sym derive` for your "
     "own robot)")
def joint_loads_old_folder(ctx):
    from planar_sym.dynamics.reactions import joint_loads

    joint_loads(_old_folder(ctx), [0.1, 0.2], [0.0, 0.0], [0.0, 0.0])


@bad(FILES, "`Robot.body_motion` of a robot whose generated folder was derived before it",
     LibraryError,
     r"serial_2dof: the generated code in \S*serial_2dof predates body_motion \(joint loads "
     r"need it\): re-derive it \(`make derive`, or `planar-sym derive` for your own robot\)",
     "serial_2dof: the generated code in generated/serial_2dof predates body_motion (joint "
     "loads need it): re-derive it (`make derive`, or `planar-sym derive` for your own robot)")
def body_motion_old_folder(ctx):
    _old_folder(ctx).body_motion([0.1, 0.2], [0.0, 0.0], [0.0, 0.0])


@bad(ARRAYS, "a joint the robot does not have: `loads.index(\"elbow\")` of serial_2dof's "
     "joint loads", InputError,
     r"no joint 'elbow'; joints: joint1, weld_motor2, joint2",
     "no joint 'elbow'; joints: joint1, weld_motor2, joint2")
def joint_loads_unknown_joint(ctx):
    from planar_sym.dynamics.reactions import joint_loads

    joint_loads(_arm(), [0.1, 0.2], [0.0, 0.0], [0.0, 0.0]).index("elbow")



# -- prismatic joints, point masses and actuators (issue 11) --------------------------------------
CART = (TEST_ROBOTS / "cart_pole.toml").read_text()
ACT = (TEST_ROBOTS / "actuated_2dof.toml").read_text()
TS = "tests/test_sliders.py::"
TA = "tests/test_actuators.py::"


@bad(DESC, "a prismatic joint's axis of zero length `axis = [0.0, 0.0]`", DescriptionError,
     r"bad\.toml: joints\[0\] \(slide\)\.axis: must have a length \(got \[0\.0, 0\.0\]: zero "
     r"length, no direction to slide along\)",
     "bad.toml: joints[0] (slide).axis: must have a length (got [0.0, 0.0]: zero length, no "
     "direction to slide along)", TS + "test_bad_prismatic_joints")
def prismatic_axis_zero(ctx):
    _desc(ctx, CART, ("axis = [1.0, 0.0]", "axis = [0.0, 0.0]"))


@bad(DESC, "a prismatic joint whose axis misses its child point", DescriptionError,
     r"bad\.toml: joints \(slide\): prismatic joint's axis does not pass both its points: "
     r"cart\.C is 49\.75\d* mm off the line through ground\.rail",
     "bad.toml: joints (slide): prismatic joint's axis does not pass both its points: cart.C is "
     "49.7519 mm off the line through ground.rail along the axis [0.995037, 0.0995037] in the "
     "drawn configuration (tolerance 0.01 mm): the child point slides along the axis through "
     "the parent point", TS + "test_bad_prismatic_joints")
def prismatic_axis_off_points(ctx):
    _desc(ctx, CART, ("axis = [1.0, 0.0]", "axis = [1.0, 0.1]"))


@bad(DESC, "a loop cut at a prismatic joint", DescriptionError,
     r"bad\.toml: joints\[0\] \(slide\)\.closes_loop: a loop cannot be cut at a prismatic "
     r"joint",
     "bad.toml: joints[0] (slide).closes_loop: a loop cannot be cut at a prismatic joint (its "
     "cut would need a slide and an angle equation, not the two point equations of a revolute "
     "cut): cut the loop at one of its revolute joints, and make this one a tree joint "
     "(closes_loop = false)", TS + "test_a_loop_cut_at_a_prismatic_joint_is_refused")
def prismatic_cut(ctx):
    _desc(ctx, CART, ('child = "cart.C"\nactuated = true',
                      'child = "cart.C"\nactuated = false\ncloses_loop = true'))


@bad(DESC, "a point mass (`mass_at`) given a cg as well", DescriptionError,
     r"bad\.toml: bodies\[0\] \(rod\)\.cg: not with mass_at",
     "bad.toml: bodies[0] (rod).cg: not with mass_at (a point mass at 'bob': its centre of "
     "gravity is that point and its inertia about it is 0)",
     TS + "test_mass_at_refuses_izz_and_cg")
def mass_at_with_cg(ctx):
    _desc(ctx, (TEST_ROBOTS / "point_pendulum.toml").read_text(),
          ('mass_at = "bob"\n', 'mass_at = "bob"\ncg = [0.1, 0.0]\n'))


@bad(DESC, "a gear ratio of zero", DescriptionError,
     r"bad\.toml: joints\[0\] \(joint1\)\.actuator\.gear_ratio: must be > 0 \(got 0\)",
     "bad.toml: joints[0] (joint1).actuator.gear_ratio: must be > 0 (got 0): motor turns per "
     "joint turn (rad per m for a prismatic joint), > 0", TA + "test_bad_actuators")
def gear_ratio_zero(ctx):
    _desc(ctx, ACT, ("gear_ratio = 50", "gear_ratio = 0"))


@bad(DESC, "a negative rotor inertia", DescriptionError,
     r"bad\.toml: joints\[0\] \(joint1\)\.actuator\.rotor_inertia: must be >= 0 kg\*mm\^2 "
     r"\(got -0\.5\)",
     "bad.toml: joints[0] (joint1).actuator.rotor_inertia: must be >= 0 kg*mm^2 (got -0.5): rotor "
     "inertia about its axis, in [units].inertia, >= 0", TA + "test_bad_actuators")
def rotor_inertia_negative(ctx):
    _desc(ctx, ACT, ("rotor_inertia = 0.5", "rotor_inertia = -0.5"))


@bad(DESC, "a limit that is not positive", DescriptionError,
     r"bad\.toml: joints\[0\] \(joint1\)\.actuator\.torque_limit: must be > 0 N\*m \(got 0\)",
     "bad.toml: joints[0] (joint1).actuator.torque_limit: must be > 0 N*m (got 0): largest joint "
     "torque (force), N*m (N), > 0", TA + "test_bad_actuators")
def torque_limit_zero(ctx):
    _desc(ctx, ACT, ("torque_limit = 0.8", "torque_limit = 0"))


@bad(DESC, "a mass typed in grams with `mass = \"kg\"`: `mass = 75.0` for a 75 g forearm",
     Warned,
     r"bad\.toml: bodies\[2\] \(link2\)\.mass: 75 kg \(read in kg\) is more than osmium "
     r"filling the ball its points reach from its centre of gravity \(58\.32 mm\) would weigh "
     r"\(18\.77 kg\); a slip\? In \"g\" it would be 0\.075 kg",
     "bad.toml: bodies[2] (link2).mass: 75 kg (read in kg) is more than osmium filling the ball "
     "its points reach from its centre of gravity (58.32 mm) would weigh (18.77 kg); a slip? In "
     "\"g\" it would be 0.075 kg", "tests/test_quantity_routes.py")
def mass_in_grams(ctx):
    _warned(ctx, ACT, ("mass = 0.075", "mass = 75.0"))


@bad(DESC, "a gear ratio upside down: `gear_ratio = 0.02` for a 50:1 gearbox", Warned,
     r"bad\.toml: joints\[0\] \(joint1\)\.actuator\.gear_ratio: 0\.02 is below the plausible "
     r"0\.1 for a gear ratio; a slip\? Upside down \(joint turns per motor turn\) it would be "
     r"50",
     "bad.toml: joints[0] (joint1).actuator.gear_ratio: 0.02 is below the plausible 0.1 for a "
     "gear ratio; a slip? Upside down (joint turns per motor turn) it would be 50",
     "tests/test_quantity_routes.py")
def gear_ratio_upside_down(ctx):
    _warned(ctx, ACT, ("gear_ratio = 50", "gear_ratio = 0.02"))


@bad(ARRAYS, "a friction typed in N*mm at run time: `with_parameters(fc_joint1=5)` on the "
             "geared arm (5 N*mm meant)", Warned,
     r"serial_2dof_geared: parameter fc_joint1 = 5 N\*m \(read in N\*m\) is 1000 times the "
     r"robot's own 0\.005 N\*m; a slip\? In N\*mm it would be 0\.005 N\*m",
     "serial_2dof_geared: parameter fc_joint1 = 5 N*m (read in N*m) is 1000 times the robot's "
     "own 0.005 N*m; a slip? In N*mm it would be 0.005 N*m", "tests/test_quantity_routes.py")
def runtime_friction_slip(ctx):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ps.load(ROOT / "examples" / "serial_2dof_geared.toml").with_parameters(fc_joint1=5.0)
    slips = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    assert len(slips) == 1, [str(w.message) for w in caught]
    raise Warned(str(slips[0].message))


@bad(ARRAYS, "a torque at a joint with no motor: `forward_dynamics` of the cart-pole with 0.5 "
             "N*m at its hinge", InputError,
     r"cart_pole: joint hinge has no motor \(actuated = false\) but tau gives it 0\.5 at sample "
     r"0",
     "cart_pole: joint hinge has no motor (actuated = false) but tau gives it 0.5 at sample 0: "
     "give 0 there (a passive joint's torque is zero), or mark the joint actuated",
     "tests/test_quantity_routes.py")
def torque_at_passive_joint(ctx):
    ps.load(TEST_ROBOTS / "cart_pole.toml").forward_dynamics(np.zeros(2), np.zeros(2),
                                                            np.array([1.0, 0.5]))


@bad(DESC, "an actuator on a passive joint", DescriptionError,
     r"bad\.toml: joints\[0\] \(joint1\)\.actuator: only an actuated joint has an actuator",
     "bad.toml: joints[0] (joint1).actuator: only an actuated joint has an actuator (actuated = "
     "true)", TA + "test_an_actuator_on_a_passive_joint_is_refused")
def actuator_on_passive_joint(ctx):
    _desc(ctx, ACT, ("actuated = true\n[joints.actuator]", "actuated = false\n[joints.actuator]"))


# -- control in the loop (issue 12) ----------------------------------------------------------------

TC = "tests/test_control.py::"


def _tracking():
    from planar_sym.study.motion import joint_motion
    from planar_sym.study.run import load_study, robot_of

    st = load_study("serial_2dof_cartesian_move")
    robot = robot_of(st)
    return robot, joint_motion(st, robot, 51)[0]


@bad(CONTROL, "a negative gain: `controller(\"pd\", kp=-400, kd=40, width=2)`", InputError,
     r"kp\[0\] is -400: a negative gain pushes the joint away from its reference \(unstable\)",
     "kp[0] is -400: a negative gain pushes the joint away from its reference (unstable); gains "
     "must be >= 0", TC + "test_gains_that_make_no_sense_are_refused")
def negative_gain(ctx):
    from planar_sym.control import controller

    controller("pd", -400.0, 40.0, width=2)


@bad(CONTROL, "a gain that is not a number: `kd = nan`", InputError,
     r"kd\[0\] is nan: gains must be finite", "kd[0] is nan: gains must be finite",
     TC + "test_gains_that_make_no_sense_are_refused")
def nan_gain(ctx):
    from planar_sym.control import controller

    controller("pd", 400.0, float("nan"), width=2)


@bad(CONTROL, "computed torque with no damping: `kp = 100, kd = 0`", InputError,
     r"kd\[0\] is 0 with kp\[0\] = 100: the error would oscillate for ever",
     "kd[0] is 0 with kp[0] = 100: the error would oscillate for ever (e'' + Kp e = 0); give "
     "some damping, e.g. kd = 2 sqrt(kp) = 20 1/s for critical damping",
     TC + "test_gains_that_make_no_sense_are_refused")
def undamped_computed_torque(ctx):
    from planar_sym.control import controller

    controller("computed_torque", 100.0, 0.0, width=2)


@bad(CONTROL, "a joint limit the start is already beyond (the event would stop the run at "
              "t = 0)", InputError,
     r"an event fires at t = 0 s, before the run starts: joint joint2 reached its lower limit",
     "an event fires at t = 0 s, before the run starts: joint joint2 reached its lower limit "
     "2.03 rad (give a start inside the limits, or a reference that starts there)",
     TC + "test_an_event_at_the_start_is_refused")
def event_at_start(ctx):
    from planar_sym.control import controller, simulate_controlled

    robot, jt = _tracking()
    simulate_controlled(robot, controller("pd", 1.0, 0.1, width=2), (0.0, 1.0), reference=jt,
                        joint_limits={"joint2": (jt.q[0, 1] + 0.1, 3.0)})


@bad(CONTROL, "a run longer than its reference: 6 s along a 5 s motion", InputError,
     r"the reference motion covers 0 to 5 s, but the run goes from 0 to 6 s",
     "the reference motion covers 0 to 5 s, but the run goes from 0 to 6 s: extend the table, "
     "or shorten the run", TC + "test_a_table_that_does_not_cover_the_run_is_refused")
def reference_too_short(ctx):
    from planar_sym.control import controller, simulate_controlled

    robot, jt = _tracking()
    simulate_controlled(robot, controller("pd", 1.0, 0.1, width=2), (0.0, 6.0), reference=jt)


@bad(CONTROL, "a torque table (`control.torque = { file = \"tq.csv\" }`) that ends before the "
              "run", InputError,
     r"tq\.csv: the torque table covers 0 to 0\.5 s, but the run goes from 0 to 1 s",
     "tq.csv: the torque table covers 0 to 0.5 s, but the run goes from 0 to 1 s: extend the "
     "table, or shorten the run", TC + "test_a_torque_table_shorter_than_the_run_names_the_file")
def torque_table_short(ctx):
    from planar_sym.study.run import run

    (ctx.tmp / "tq.csv").write_text("t_s,tau1_n_m,tau2_n_m\n0,0,0\n0.5,0.01,0\n")
    path = ctx.tmp / "c.toml"
    path.write_text(_CONTROL_STUDY.format(dx=-200.0, control='law = "pd"\nnatural_frequency_hz = '
                                          '2.0\ntorque = { file = "tq.csv" }'))
    run(path)


_CONTROL_STUDY = """robot = "serial_2dof"
kind = "control"
[units]
length = "mm"
[motion]
space = "task"
profile = "cubic"
start = [100.0, 100.0]
by = [{dx}, 0.0]
duration = 1.0
samples = 51
[control]
{control}
"""


@bad(CONTROL, "a control study whose reference leaves the workspace (`by = [-400, 0]` mm)",
     WorkspaceError,
     r"serial_2dof: target \(x = [-0-9.]+ mm, y = 100 mm\) at t = 0\.62 s \(sample 31\)",
     "serial_2dof: target (x = -170.618 mm, y = 100 mm) at t = 0.62 s (sample 31) violates the "
     "joint limit 30 <= q2 <= 150 deg (q2 = 17.1535 deg)",
     TC + "test_a_reference_that_leaves_the_workspace_names_the_time")
def control_reference_outside(ctx):
    from planar_sym.study.run import run

    path = ctx.tmp / "c.toml"
    path.write_text(_CONTROL_STUDY.format(dx=-400.0, control='law = "pd"\nkp = [1.0]\n'
                                                              'kd = [0.1]'))
    run(path)


@bad(CONTROL, "a control study with a law and no gains: `[control] law = \"pd\"`", StudyError,
     r"c\.toml: control: law 'pd' needs gains: natural_frequency_hz = \.\.\. \(and damping\), "
     r"or kp = \[\.\.\.\] and kd = \[\.\.\.\]",
     "c.toml: control: law 'pd' needs gains: natural_frequency_hz = ... (and damping), or kp = "
     "[...] and kd = [...]", TC + "test_control_section_errors_name_the_field")
def control_without_gains(ctx):
    from planar_sym.study import spec

    path = ctx.tmp / "c.toml"
    path.write_text(_CONTROL_STUDY.format(dx=-200.0, control='law = "pd"'))
    spec.load(path)


@bad(CONTROL, "a control duration beyond a motion that ends moving (a table whose spline "
              "ends with a rate)", InputError,
     r"control\.duration 2 s outlasts the motion \(1 s\), which ends moving",
     "c.toml: control.duration 2 s outlasts the motion (1 s), which ends moving (0.1 per s): the "
     "reference cannot be held; end the motion at rest or shorten control.duration")
def control_hold_moving(ctx):
    from planar_sym.study.run import run

    (ctx.tmp / "move.csv").write_text("t_s,x_mm,y_mm\n0,100,100\n0.5,50,100\n1.0,0,100\n")
    text = _CONTROL_STUDY.format(dx=-200.0, control='law = "pd"\nnatural_frequency_hz = 2.0\n'
                                                    'duration = 2.0')
    text = text.replace('profile = "cubic"\nstart = [100.0, 100.0]\nby = [-200.0, 0.0]\n'
                        'duration = 1.0', 'profile = "table"\nfile = "move.csv"')
    path = ctx.tmp / "c.toml"
    path.write_text(text)
    run(path)


@bad(CONTROL, "a Python function as the input torque of the compiled loop", InputError,
     r"a torque function of time runs in Python; in the compiled loop give a table",
     "a torque function of time runs in Python; in the compiled loop give a table "
     "(planar_sym.motion.signals.from_table) or a constant")
def control_python_torque(ctx):
    from planar_sym.control import controller, simulate_controlled

    simulate_controlled(_arm(), controller("none", width=2), (0.0, 1.0), q0=[0.0, 0.0],
                        torque=lambda t: [0.0, 0.0])


@bad(CONTROL, "a plant that is another robot: `plant=ps.load(\"serial_3dof\")`", InputError,
     r"the plant must be the same robot as the controller's model \(serial_2dof\)",
     "the plant must be the same robot as the controller's model (serial_2dof), perhaps with "
     "other parameters (with_parameters)")
def control_other_plant(ctx):
    from planar_sym.control import controller, simulate_controlled

    robot, jt = _tracking()
    simulate_controlled(robot, controller("pd", 1.0, 0.1, width=2), (0.0, 1.0), reference=jt,
                        plant=ps.load("serial_3dof"))


# -- export and result files ---------------------------------------------------------------------
TE = "tests/test_export.py"


@bad(EXCHANGE, "`planar-sym export serial_2dof --format sdf`", CommandFailed,
     r"--format must be mjcf or urdf \(got 'sdf'\)",
     "error: --format must be mjcf or urdf (got 'sdf')", see=TE)
def export_format(ctx):
    _cli(ctx, "export", "serial_2dof", "--format", "sdf", "--out", str(ctx.tmp / "r.xml"))


@bad(EXCHANGE, "`planar-sym export serial_2dof --out r.sdf` (a suffix that names no format)",
     CommandFailed, r"--out .*r\.sdf: cannot tell the format from the suffix '\.sdf'; give "
                    r"--format mjcf or urdf",
     "error: --out r.sdf: cannot tell the format from the suffix '.sdf'; give --format mjcf or "
     "urdf (or name the file .xml or .urdf)", see=TE)
def export_suffix(ctx):
    _cli(ctx, "export", "serial_2dof", "--out", str(ctx.tmp / "r.sdf"))


@bad(EXCHANGE, "`planar-sym export serial_2dof --format mjcf --out arm.urdf` (the suffix says "
     "the other format)", CommandFailed,
     r"--format mjcf but --out .*arm\.urdf names a URDF file: give --format urdf, or name the "
     r"file \.xml",
     "error: --format mjcf but --out arm.urdf names a URDF file: give --format urdf, or name the "
     "file .xml", see=TE)
def export_format_against_suffix(ctx):
    _cli(ctx, "export", "serial_2dof", "--format", "mjcf", "--out", str(ctx.tmp / "arm.urdf"))


@bad(EXCHANGE, "`planar-sym export five_bar_type1 --format urdf` (a closed chain)", CommandFailed,
     r"five_bar_type1 is a closed chain \(cut joint C\): URDF describes trees only.*export "
     r"MJCF instead",
     "error: five_bar_type1 is a closed chain (cut joint C): URDF describes trees only, and no "
     "loop extension of it is read by the common parsers, so its spanning tree would load as a "
     "different mechanism; export MJCF instead (--format mjcf, or to_mjcf), which keeps every "
     "cut joint as an equality constraint", see=TE)
def export_urdf_closed(ctx):
    _cli(ctx, "export", "five_bar_type1", "--format", "urdf", "--out", str(ctx.tmp / "f.urdf"))


@bad(EXCHANGE, "`planar-sym export serial_2dof --out missing/r.xml` (no such folder)",
     CommandFailed, r"--out .*missing/r\.xml: its folder .*missing does not exist; create it "
                    r"first",
     "error: --out missing/r.xml: its folder missing does not exist; create it first", see=TE)
def export_missing_folder(ctx):
    _cli(ctx, "export", "serial_2dof", "--out", str(ctx.tmp / "missing" / "r.xml"))


@bad(EXCHANGE, "exporting a robot with actuator models to URDF (`examples/serial_2dof_geared."
               "toml`): friction and limits go in, the rotors cannot",
     Warned, r"serial_2dof_geared: jm_joint1: URDF has no rotor: its N\^2 J_m = 0\.00125 "
             r"kg\*m\^2 at joint1 \(and J_m on its stator's body\) is not exported",
     "serial_2dof_geared: jm_joint1: URDF has no rotor: its N^2 J_m = 0.00125 kg*m^2 at joint1 "
     "(and J_m on its stator's body) is not exported (Pinocchio: model.armature; the MJCF export "
     "carries it); fc_joint1: Coulomb friction 0.005 is URDF's dry friction here, not the smooth "
     "c tanh(qd / 0.01) of planar-sym; jm_joint2: URDF has no rotor: its N^2 J_m = 0.00125 "
     "kg*m^2 at joint2 (and J_m on its stator's body) is not exported (Pinocchio: "
     "model.armature; the MJCF export carries it)",
     see=TE)
def export_actuators(ctx):
    robot = ps.load(ROOT / "examples" / "serial_2dof_geared.toml")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        path = ps.export(robot, ctx.tmp / "geared.urdf")
    assert path.stat().st_size > 0
    (shown,) = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    raise Warned(str(shown.message))


@bad(EXCHANGE, "exporting to MJCF a drive train MJCF cannot hold exactly: Coulomb friction and "
               "a rotor on a moving link (`examples/serial_2dof_geared.toml`)",
     Warned, r"serial_2dof_geared: fc_joint1: Coulomb friction 0\.005 is exported as MuJoCo's "
             r"frictionloss .*; jm_joint2: the rotor turns with link1; its coupling N J_m",
     "serial_2dof_geared: fc_joint1: Coulomb friction 0.005 is exported as MuJoCo's "
     "frictionloss (dry friction, a soft constraint), not as the smooth c tanh(qd / 0.01) of "
     "planar-sym; jm_joint2: the rotor turns with link1; its coupling N J_m = "
     "2.4999999999999998e-05 kg*m^2 between joint2 and the joints that turn link1 is not "
     "exported (armature is diagonal): MuJoCo's torques differ by N J_m alpha_link1 at joint2 "
     "and N J_m qdd_joint2 at each of those joints", see=TE)
def export_drive_not_exact(ctx):
    robot = ps.load(ROOT / "examples" / "serial_2dof_geared.toml")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        path = ps.export(robot, ctx.tmp / "geared.xml")
    assert path.stat().st_size > 0
    (shown,) = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    raise Warned(str(shown.message))


# -- atlases and sweeps ---------------------------------------------------------------------------
@bad(DESIGN, "an atlas region with its ends reversed: `x_range=(0.1, -0.1)`", InputError,
     r"x_range = \(0\.1, -0\.1\) m: the minimum must be below the maximum",
     "x_range = (0.1, -0.1) m: the minimum must be below the maximum",
     see="tests/test_atlas.py")
def atlas_reversed(ctx):
    ps.atlas("five_bar_type1", x_range=(0.1, -0.1))


@bad(DESIGN, "an atlas grid too large for memory: `step=1e-6` (a micrometre)", InputError,
     r"five_bar_type1: a grid of 193,818,240,000 points \(404800 x 478800\) would take "
     r"8\.68e\+04 GB of memory \(limit 2 GB\)",
     "five_bar_type1: a grid of 193,818,240,000 points (404800 x 478800) would take 8.68e+04 GB "
     "of memory (limit 2 GB): use a larger step or fewer points", see="tests/test_atlas.py")
def atlas_too_large(ctx):
    ps.atlas("five_bar_type1", step=1e-6)


@bad(DESIGN, "an atlas of a robot whose reach a slider leaves unbounded, with no region",
     InputError, r"serial_rpr: a slider on every leg to the task point leaves its reach "
                 r"unbounded: give the region",
     "serial_rpr: a slider on every leg to the task point leaves its reach unbounded: give the "
     "region (x_range and y_range, m; --x and --y, mm)", see="tests/test_atlas.py")
def atlas_slider_region(ctx):
    ps.atlas("serial_rpr")


@bad(DESIGN, "`planar-sym atlas five_bar_type2 --x 100 -100`", CommandFailed,
     r"--x 100 -100: give MIN MAX in mm, finite, MIN below MAX",
     "error: --x 100 -100: give MIN MAX in mm, finite, MIN below MAX")
def atlas_cli_range(ctx):
    _cli(ctx, "atlas", "five_bar_type2", "--x", "100", "-100", "--out", str(ctx.tmp))


@bad(DESIGN, "a torque envelope along a simulation (not an inverse-dynamics study)", InputError,
     r"\(kind = \"inverse\"\); this one is kind = \"forward\"",
     "serial_2dof_free_swing: the torque envelope follows an inverse-dynamics study's path "
     "(kind = \"inverse\"); this one is kind = \"forward\"")
def atlas_along_forward(ctx):
    from planar_sym.analysis.atlas import envelope_along

    envelope_along("serial_2dof_free_swing")


@bad(DESIGN, "a sweep of a parameter the robot does not have: `vary={\"m_lnk2\": ...}`",
     InputError, r"unknown parameter 'm_lnk2' of serial_2dof; known: g, m_link1",
     "unknown parameter 'm_lnk2' of serial_2dof; known: g, m_link1, izz_link1, cgx_link1, "
     "m_motor2, izz_motor2, m_link2, izz_link2, cgx_link2, px_link1_CS2, px_link2_CS2",
     see="tests/test_sweep.py::test_bad_sweeps_get_one_clear_message")
def sweep_unknown_parameter(ctx):
    ps.sweep("serial_2dof_cartesian_move", {"m_lnk2": (0.05, 0.1, 3)})


@bad(DESIGN, "a sweep range that reaches non-physical values (a mass from -0.05 kg)",
     InputError, r"design 0 \(m_link2 = -0\.05\) is not physical: parameter m_link2 must be > 0",
     "design 0 (m_link2 = -0.05) is not physical: parameter m_link2 must be > 0 kg (got -0.05) "
     "(2 of 4 designs are not); narrow the range")
def sweep_not_physical(ctx):
    ps.sweep("serial_2dof_cartesian_move", {"m_link2": (-0.05, 0.1, 4)})


@bad(DESIGN, "a sweep range typed in grams as kg: `vary={\"m_link2\": [50, 100]}` for a 75 g "
             "forearm", Warned,
     r"sweep range m_link2 from 50 to 100: parameter m_link2 = 50 kg \(read in kg\) is more than "
     r"osmium filling the ball its points reach from its centre of gravity \(58\.32 mm\) would "
     r"weigh \(18\.77 kg\); a slip\? In \"g\" it would be 0\.05 kg \(sweeps take SI units\)",
     "sweep range m_link2 from 50 to 100: parameter m_link2 = 50 kg (read in kg) is more than "
     "osmium filling the ball its points reach from its centre of gravity (58.32 mm) would weigh "
     "(18.77 kg); a slip? In \"g\" it would be 0.05 kg (sweeps take SI units)", see="tests/test_sweep.py")
def sweep_unit_slip(ctx):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ps.sweep("serial_2dof_cartesian_move", {"m_link2": [50.0, 100.0]})
    slips = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    assert len(slips) == 1, [str(w.message) for w in caught]
    raise Warned(str(slips[0].message))


@bad(DESIGN, "a sweep grid too large for memory (three parameters at 2000 x 2000 x 100 values)",
     InputError, r"4e\+08 designs of 11 parameters would take 35\.2 GB",
     "4e+08 designs of 11 parameters would take 35.2 GB for their parameter vectors alone "
     "(limit 2 GB): fewer values per parameter, or a random sample")
def sweep_too_large(ctx):
    ps.sweep("serial_2dof_cartesian_move", {"m_link1": (0.05, 0.1, 2000),
                                            "m_link2": (0.05, 0.1, 2000), "g": (1.0, 9.0, 100)})


@bad(DESIGN, "an executor whose worker dies during a sweep (one batch of three lost)", Warned,
     r"3 of 9 designs were lost to worker errors \(first: design 3, worker error: RuntimeError: "
     r"worker 2 was killed\); the other designs' figures are kept",
     "3 of 9 designs were lost to worker errors (first: design 3, worker error: RuntimeError: "
     "worker 2 was killed); the other designs' figures are kept",
     see="tests/test_sweep.py::test_a_failing_executor_loses_only_its_batch")
def sweep_worker_dies(ctx):
    from concurrent.futures import Future

    class Flaky:
        calls = 0

        def submit(self, fn, *args):
            self.calls += 1
            fut = Future()
            if self.calls == 2:
                fut.set_exception(RuntimeError("worker 2 was killed"))
            else:
                fut.set_result(fn(*args))
            return fut

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = ps.sweep("serial_2dof_cartesian_move", {"m_link2": (0.05, 0.1, 9)},
                       executor=Flaky(), batch=3)
    assert sorted(res.failed) == [3, 4, 5] and np.isfinite(res.columns["peak_tau1_n_m"][6:]).all()
    lost = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    assert len(lost) == 1, [str(w.message) for w in caught]
    raise Warned(str(lost[0].message))


@bad(DESIGN, "`planar-sym sweep STUDY --vary m_link2=0.05:0.1` (a grid without its count)",
     CommandFailed, r"--vary 'm_link2=0\.05:0\.1': LOW:HIGH:COUNT expected on a grid",
     "error: --vary 'm_link2=0.05:0.1': LOW:HIGH:COUNT expected on a grid")
def sweep_cli_range(ctx):
    _cli(ctx, "sweep", "serial_2dof_cartesian_move", "--vary", "m_link2=0.05:0.1", "--out",
         str(ctx.tmp))


@bad(DESIGN, "a sweep of the plant only (`on=\"plant\"`) of a study that has no plant (kind = "
             "\"inverse\")", InputError,
     r"on = 'plant' is for control studies \(a controller's model and a plant\): "
     r"serial_2dof_cartesian_move is a study of kind = \"inverse\": one robot, no plant",
     "on = 'plant' is for control studies (a controller's model and a plant): "
     "serial_2dof_cartesian_move is a study of kind = \"inverse\": one robot, no plant; leave "
     "on = 'both'", see="tests/test_sweep_drive_plant.py::test_on_is_refused_where_there_is_no_plant")
def sweep_on_without_plant(ctx):
    ps.sweep("serial_2dof_cartesian_move", {"m_link2": (0.05, 0.1, 3)}, on="plant")


@bad(DESIGN, "a sweep's parameter set misspelt: `on=\"plants\"`", InputError,
     r"on must be 'both', 'model' or 'plant' \(got 'plants'\)",
     "on must be 'both', 'model' or 'plant' (got 'plants')",
     see="tests/test_sweep_drive_plant.py::test_on_is_refused_where_there_is_no_plant")
def sweep_on_unknown(ctx):
    ps.sweep("serial_2dof_cartesian_track", {"m_link2": (0.05, 0.1, 3)}, on="plants")


@bad(DESIGN, "`planar-sym sweep serial_2dof_cartesian_track --vary m_link2=0.06,0.08 --on "
             "plants`", CommandFailed, r"--on 'plants': choose both, model or plant",
     "error: --on 'plants': choose both, model or plant",
     see="tests/test_sweep_drive_plant.py::test_on_is_refused_where_there_is_no_plant")
def sweep_cli_on(ctx):
    _cli(ctx, "sweep", "serial_2dof_cartesian_track", "--vary", "m_link2=0.06,0.08", "--on",
         "plants", "--out", str(ctx.tmp))


# -- the test ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module", autouse=True)
def _process_wide_helpers():
    """Build the process-wide C helpers (_fastcall, _integrate) in the normal cache first, so that
    no entry's private cache or broken compiler decides them for later tests."""
    from planar_sym.dynamics.integrate import integrator
    from planar_sym.model.compile import fastcall

    fastcall()
    integrator()


def _normalise(text: str, ctx: Ctx) -> str:
    return text.replace(str(ctx.tmp) + "/", "").replace(str(ROOT) + "/", "")


@pytest.mark.parametrize("entry", CATALOGUE, ids=[e.id for e in CATALOGUE])
def test_catalogue(entry: Bad, tmp_path, monkeypatch, capsys):
    ctx = Ctx(tmp_path, monkeypatch, capsys)
    with pytest.raises(entry.exc) as info:
        entry.run(ctx)
    msg = str(info.value)
    assert re.search(entry.pattern, msg, re.MULTILINE), (
        f"{entry.id}: message does not match the catalogue\n  got:     {_normalise(msg, ctx)!r}"
        f"\n  pattern: {entry.pattern!r}")
    if isinstance(info.value, DescriptionError):
        assert all(p.startswith(f"{tmp_path}/") or not p.startswith("/")
                   for p in info.value.problems), info.value.problems


@pytest.mark.parametrize("entry", CATALOGUE, ids=[e.id for e in CATALOGUE])
def test_example_matches_its_pattern(entry: Bad):
    """The example in the docs is an instance of what the test checks."""
    assert re.search(entry.pattern, entry.example, re.MULTILINE), (entry.id, entry.example)


def test_catalogue_is_complete_and_unique():
    ids = [e.id for e in CATALOGUE]
    assert len(ids) == len(set(ids))
    assert {e.area for e in CATALOGUE} == set(AREAS)
    assert len(CATALOGUE) >= 60


# -- docs/errors.md -------------------------------------------------------------------------------

def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _code(text: str) -> str:
    """The message in code spans, one per line of it."""
    spans = []
    for line in text.splitlines():
        line = _cell(line.strip())
        fence = "``" if "`" in line else "`"
        pad = " " if fence == "``" else ""
        spans.append(f"{fence}{pad}{line}{pad}{fence}")
    return "<br>".join(spans)


def render_markdown() -> str:
    lines = [
        "# Errors: the catalogue of bad inputs",
        "",
        ("<!-- generated by `python tests/test_error_catalogue.py` from the table in that file; "
         "do not edit: tests/test_error_catalogue.py checks that this file is exactly that -->"),
        "",
        (f"{len(CATALOGUE)} bad inputs, each with the exception and the message you see. Every "
         "error is a subclass of `planar_sym.PlanarSymError` (the command line prints it after "
         "`error: ` with exit code 2). Paths are shortened to the file name; a description "
         "error lists every problem of the file, each starting with the file's path."),
        "",
        ("Each row is checked by `tests/test_error_catalogue.py` (the message must match a "
         "regular expression of which the example is an instance); \"tested in\" names the "
         "test that checks the case in more depth."),
        "",
    ]
    for area in AREAS:
        rows = [e for e in CATALOGUE if e.area == area]
        lines += [f"## {area} ({len(rows)})", "",
                  "| # | what you did | what you see | message | tested in |",
                  "|---|---|---|---|---|"]
        for e in rows:
            k = CATALOGUE.index(e) + 1
            see = f"`{e.see}`" if e.see else ""
            lines.append(f"| {k} | {_cell(e.did)} | {e.shown_class} | {_code(e.example)} | "
                         f"{see} |")
        lines.append("")
    return "\n".join(lines)


def test_docs_are_generated_from_the_catalogue():
    assert DOCS.is_file(), "docs/errors.md is missing: run python tests/test_error_catalogue.py"
    text = DOCS.read_text()
    for e in CATALOGUE:
        assert _code(e.example) in text, f"docs/errors.md lacks the example of {e.id}"
    assert text == render_markdown(), ("docs/errors.md is out of date: run "
                                       "python tests/test_error_catalogue.py")


# -- known bugs (strict xfail: each shows the behaviour the catalogue should have; remove the
#    marker once fixed) ---------------------------------------------------------------------------

TRUNCATED = """
import shutil, sys, warnings
from pathlib import Path
import numpy as np
from planar_sym.model.compile import build, library_path
from planar_sym.model.folders import read_manifest
from planar_sym.model.library import Library
from planar_sym.model.robot import Robot

folder = Path(sys.argv[1])
built = Path(sys.argv[2])
manifest = read_manifest(folder)
target = library_path(folder, manifest)  # in the private cache ($PLANAR_SYM_CACHE)
target.parent.mkdir(parents=True, exist_ok=True)
data = built.read_bytes()
target.write_bytes(data[: len(data) // 2])  # a half-copied library
warnings.simplefilter("always")
robot = Robot("serial_2dof", Library("serial_2dof", folder=folder), exact=True)
print(robot.inverse_dynamics([0.1, 0.2], [0.3, 0.4], [0.5, 0.6]).tolist())
"""


def test_known_bug_truncated_library_crashes_the_process(tmp_path):
    import os
    import subprocess

    folder = GENERATED / "serial_2dof"
    built = build(folder, read_manifest(folder))
    script = tmp_path / "truncated.py"
    script.write_text(TRUNCATED)
    env = dict(os.environ, PLANAR_SYM_CACHE=str(tmp_path / "cache"), PYTHONPATH=str(ROOT),
               PLANAR_SYM_PREBUILT="0")  # the cache's copy, not the install's
    res = subprocess.run([sys.executable, str(script), str(folder), str(built)], env=env,
                         capture_output=True, text=True, timeout=120, check=False)
    assert res.returncode == 0, f"exit code {res.returncode} (-7: SIGBUS)\n{res.stderr[-500:]}"
    assert "rebuilding it" in res.stderr


def test_known_bug_corrupt_simd_library_is_not_rebuilt(tmp_path, monkeypatch):
    folder = GENERATED / "serial_2dof"
    manifest = read_manifest(folder)
    exact = build(folder, manifest)
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    monkeypatch.setenv("PLANAR_SYM_PREBUILT", "0")  # the cache's copies, not the install's
    (tmp_path / "cache").mkdir()
    shutil.copyfile(exact, library_path(folder, manifest))
    library_path(folder, manifest, "simd").write_bytes(b"garbage" * 100)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        library = Library("serial_2dof", folder=folder)
    assert library.simd is not None
    assert any("rebuilding it" in str(w.message) for w in caught)


def test_known_bug_corrupt_integrator_library(tmp_path, monkeypatch):
    import hashlib

    from planar_sym.dynamics import integrate
    from planar_sym.model import compile as lib

    arm = _arm()  # loaded from the normal cache first
    src = Path(integrate.__file__).parent / "_integrate.c"
    key = hashlib.sha256(src.read_bytes() + " ".join(lib.CFLAGS).encode()).hexdigest()[:12]
    (tmp_path / f"_integrate-{key}.so").write_bytes(b"garbage" * 100)
    monkeypatch.setattr(integrate, "_INTEGRATOR", None)
    monkeypatch.setattr(lib, "cache_dir", lambda: tmp_path)
    try:
        ps.simulate(arm, [0.0, 0.0], [0.0, 0.0], (0.0, 0.1))
    except LibraryError:
        return


def test_known_bug_cc_names_a_missing_compiler(tmp_path, monkeypatch):
    """CC naming no program: the warning that switches to CasADi's evaluator names it."""
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    monkeypatch.setenv("PLANAR_SYM_PREBUILT", "0")
    monkeypatch.setenv("CC", str(tmp_path / "no_such_cc"))
    with pytest.warns(RuntimeWarning, match=r"cannot run the C compiler '.*no_such_cc'; running "
                                            r"on CasADi's own evaluator"):
        lib = Library("serial_2dof", folder=GENERATED / "serial_2dof")
    assert not lib.compiled


def test_known_bug_constant_torque_of_wrong_length():
    try:
        ps.simulate(_arm(), [0.0, 0.0], [0.0, 0.0], (0.0, 1.0), torque=[1.0, 2.0, 3.0])
    except InputError:
        return


if __name__ == "__main__":
    DOCS.parent.mkdir(exist_ok=True)
    DOCS.write_text(render_markdown())
    print(f"wrote {DOCS} ({len(CATALOGUE)} entries)")
