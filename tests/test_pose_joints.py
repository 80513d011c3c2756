"""pose = "joints": a robot described link by link (points in each body's own coordinates) with
rough joint angles is placed along the tree and its loops closed numerically. Checked against
the same robots typed as world tables, the four-bar's closed-form circle intersection in both
assembly modes, and the compiled body frames; drawing a description needs no derivation."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import DescriptionError
from planar_sym.model.description import load, wrap_angle
from planar_sym.outputs.drawing import drawn_frames

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
ROBOTS = ROOT / "planar_sym" / "robots"

SERIAL_JOINTS = """
name = "serial_2dof"
title = "the seed's 2-DOF arm, link by link"
pose = "joints"
gravity = [0.0, -9.81]
[units]
length = "m"
mass = "kg"
inertia = "kg*mm^2"
angle = "deg"
acceleration = "m/s^2"
[ground]
points = { O = [0.0, 0.0] }
[[bodies]]
name = "link1"
mass = 0.071
izz = 89.395
cg = [0.0373, 0.0]
points = { CS1 = [0.0, 0.0], CS2 = [0.1, 0.0] }
[[bodies]]
name = "motor2"
mass = 0.292
izz = 0.0
cg = [0.0, 0.0]
points = { CS1 = [0.0, 0.0] }
[[bodies]]
name = "link2"
mass = 0.075
izz = 109.864
cg = [0.04168, 0.0]
points = { CS1 = [0.0, 0.0], CS2 = [0.1, 0.0] }
[[joints]]
name = "joint1"
type = "revolute"
parent = "ground.O"
child = "link1.CS1"
actuated = true
angle = ANGLE1
[[joints]]
name = "weld_motor2"
type = "weld"
parent = "link1.CS2"
child = "motor2.CS1"
[[joints]]
name = "joint2"
type = "revolute"
parent = "link1.CS2"
child = "link2.CS1"
actuated = true
angle = ANGLE2
[task]
point = "link2.CS2"
"""


def write(tmp_path: Path, text: str, name: str = "robot.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def world(body, point) -> np.ndarray:
    return np.array(body.world(body.points_m[point]))


def test_a_tree_link_by_link_is_the_seed_table(tmp_path):
    """Same parameters, bit for bit, as the world table of the seed's 2-DOF arm."""
    mine = load(write(tmp_path, SERIAL_JOINTS.replace("ANGLE1", "0.0").replace("ANGLE2", "0.0")))
    seed = load(ROBOTS / "serial_2dof.toml")
    assert [(p.name, p.value) for p in mine.parameters()] == \
           [(p.name, p.value) for p in seed.parameters()]
    assert mine.q_drawn() == seed.q_drawn() == (0.0, 0.0)
    assert mine.assembly is None  # a tree: the angles place it exactly, nothing to close


def test_a_tree_is_placed_by_its_angles_and_wrapped(tmp_path):
    """Angles 30 and 350 deg: the tip where forward kinematics puts it, q2 wrapped to -10 deg."""
    mine = load(write(tmp_path, SERIAL_JOINTS.replace("ANGLE1", "30.0")
                      .replace("ANGLE2", "350.0")))
    q1, q2 = mine.q_drawn()
    assert q1 == pytest.approx(math.radians(30.0), abs=1e-15)
    assert q2 == pytest.approx(math.radians(-10.0), abs=1e-14)
    tip = world(mine.bodies["link2"], "CS2")
    exact = 0.1 * np.array([math.cos(q1) + math.cos(q1 + q2), math.sin(q1) + math.sin(q1 + q2)])
    assert np.max(np.abs(tip - exact)) < 1e-16


def test_every_drawn_coordinate_is_wrapped():
    for name in ("serial_2dof", "serial_3dof", "five_bar_type1", "five_bar_type2",
                 "parallel_3rrr"):
        q = load(ROBOTS / f"{name}.toml").q_drawn()
        assert all(-math.pi < v <= math.pi for v in q), (name, q)
    assert wrap_angle(math.pi) == math.pi and wrap_angle(-math.pi) == math.pi
    assert wrap_angle(0.5) == 0.5  # inside: bit for bit
    assert wrap_angle(-4.366768483376379) == pytest.approx(1.9164168238032069, abs=1e-15)


def test_the_four_bar_link_by_link_assembles_to_the_world_table():
    """examples/four_bar_joints.toml (rough angles, 3.3 mm gap) against four_bar.toml, whose B
    was solved by hand to 1e-9 mm: same pose to 1e-10 rad, same parameters to 1e-11 m."""
    mine, table = load(EXAMPLES / "four_bar_joints.toml"), load(EXAMPLES / "four_bar.toml")
    np.testing.assert_allclose(mine.q_drawn(), table.q_drawn(), rtol=0, atol=1e-10)
    assert mine.q_drawn()[0] == math.radians(60.0)  # the actuated crank is never turned
    a = {p.name: p.value for p in mine.parameters()}
    b = {p.name: p.value for p in table.parameters()}
    assert a.keys() == b.keys()
    assert max(abs(a[k] - b[k]) for k in a) < 1e-11
    report = mine.assembly.report()
    assert "loop B: gap 3.347 mm closed" in report
    assert "joint crank_joint: 60 deg (given 60 deg, kept)" in report


def circle_intersections(c1, r1, c2, r2):
    d = np.linalg.norm(c2 - c1)
    u = (c2 - c1) / d
    n = np.array([-u[1], u[0]])
    along = (r1**2 - r2**2 + d**2) / (2 * d)
    h = math.sqrt(r1**2 - along**2)
    return c1 + along * u + h * n, c1 + along * u - h * n


@pytest.mark.parametrize("rocker_deg, branch", [(65.0, "up"), (-65.0, "down"),
                                                (40.0, "up"), (-100.0, "down")])
def test_the_assembly_mode_of_the_rough_pose_is_kept(tmp_path, rocker_deg, branch):
    """B lands on the closed-form circle intersection on the side the rough rocker points to."""
    text = (EXAMPLES / "four_bar_joints.toml").read_text()
    text = text.replace("angle = 65.0", f"angle = {rocker_deg}")
    if branch == "down":
        text = text.replace("angle = -40.0", "angle = -80.0")
    desc = load(write(tmp_path, text))
    b = desc.bodies
    a_pt, o4 = world(b["crank"], "A"), np.array(b["ground"].points_m["O4"])
    up, down = circle_intersections(a_pt, 0.120, o4, 0.080)
    expected = up if branch == "up" else down
    assert np.max(np.abs(world(b["rocker"], "B") - expected)) < 1e-12
    assert np.max(np.abs(world(b["coupler"], "B") - expected)) < 1e-12


def test_a_link_too_short_is_refused_naming_the_loop(tmp_path):
    text = (EXAMPLES / "four_bar_joints.toml").read_text()
    # A sits 87.2 mm from O4 and the rocker is 80 mm: a 5 mm coupler cannot span the 7.2 mm
    text = text.replace("B = [120.0, 0.0], P", "B = [5.0, 0.0], P")
    with pytest.raises(DescriptionError, match=r"joints \(B\): loop B cannot be closed from the "
                                               r"given pose: its points stay [0-9.]+ mm apart "
                                               r"with the actuated joints at their given angles"):
        load(write(tmp_path, text))


@pytest.mark.parametrize("edit, message", [
    (("angle = 60.0", "angle = \"sixty\""), r"joints\[0\] \(crank_joint\)\.angle: \"sixty\": unknown name sixty"),
    (("closes_loop = true", "closes_loop = true\nangle = 3.0"),
     r"joints\[3\] \(B\)\.angle: a loop-closing joint is cut"),
    (('pose = "joints"', 'pose = "joints"\nassemble = false'), r"assemble: pose = 'joints'"),
    (('pose = "joints"', 'pose = "local"'), r"pose: must be"),
])
def test_mistakes_in_the_joints_form_are_named(tmp_path, edit, message):
    text = (EXAMPLES / "four_bar_joints.toml").read_text()
    assert edit[0] in text
    with pytest.raises(DescriptionError, match=message) as err:
        load(write(tmp_path, text.replace(edit[0], edit[1], 1)))
    assert len(err.value.problems) == 1, err.value.problems  # one mistake, one message


@pytest.mark.parametrize("robot", ["serial_2dof", "five_bar_type2", "parallel_3rrr",
                                   str(EXAMPLES / "four_bar.toml")])
def test_the_description_alone_draws_what_the_compiled_frames_compute(robot):
    """drawn_frames (no derivation) against Robot.frames(q_drawn) (the generated C)."""
    r = ps.load(robot)
    names, frames = drawn_frames(load(r.description_file))
    assert list(names) == list(r.body_names)
    compiled = np.asarray(r.frames(r.q_drawn[None, :])).reshape(frames.shape)
    assert np.max(np.abs(frames[..., :2] - compiled[..., :2])) < 1e-12
    turn = frames[..., 2] - compiled[..., 2]  # frame angles agree up to whole turns (wrapped q)
    assert np.max(np.abs(np.remainder(turn + math.pi, 2 * math.pi) - math.pi)) < 1e-12


def test_draw_a_new_description_without_deriving(tmp_path):
    """The user's first check of a description: no SymPy imported, nothing compiled."""
    out = tmp_path / "four.png"
    code = ("import sys; from planar_sym.cli import main; "
            f"rc = main(['draw', {str(EXAMPLES / 'four_bar_joints.toml')!r}, '--out', "
            f"{str(out)!r}]); assert rc == 0; "
            "assert 'sympy' not in sys.modules and 'casadi' not in sys.modules, 'derived'")
    env = dict(os.environ, PLANAR_SYM_CACHE=str(tmp_path / "cache"))
    res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=120, check=False)
    assert res.returncode == 0, res.stderr[-2000:]
    assert out.stat().st_size > 10_000
    assert "loop B: gap 3.347 mm closed" in res.stdout
    assert not (tmp_path / "cache").exists() or not any((tmp_path / "cache").rglob("*.so"))
