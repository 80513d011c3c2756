"""Structural mistakes in closed chains (issue 10, item 7): degrees of freedom counted
(Gruebler/Kutzbach) and measured (rank of Phi_q at the drawn pose) against the actuated joints,
each mistake refused in one line naming the joints and the counts; and the DOF of every robot
that ships."""

from __future__ import annotations

from pathlib import Path

import pytest

from planar_sym.cli import main
from planar_sym.errors import DescriptionError
from planar_sym.model import description
from planar_sym.model.description import mobility

ROOT = Path(__file__).resolve().parent.parent
FOUR_BAR = (ROOT / "examples" / "four_bar.toml").read_text()
FIVE_BAR = (ROOT / "planar_sym" / "robots" / "five_bar_type1.toml").read_text()
DATA = ROOT / "tests" / "data" / "mobility"


def _edit(text: str, *edits: tuple[str, str]) -> str:
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    return text


def _fails(tmp_path, text: str) -> str:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(DescriptionError) as info:
        description.load(path)
    problems = info.value.problems
    assert len(problems) == 1, problems  # one clear line, no cascade
    return problems[0]


CUT_B = ('name = "B"\ntype = "revolute"\nparent = "coupler.B"\nchild = "rocker.B"\n'
         'actuated = false\ncloses_loop = true\n')
# a parallelogram with an extra parallel link; a change-point four-bar drawn flat; two bars
# pinned into a triangle
PARALLEL, FLAT, TRIANGLE = ((DATA / f"{n}.toml").read_text()
                            for n in ("parallelogram", "flat_four_bar", "triangle"))
COUNT_4BAR = (r"F = 3 x 3 moving bodies - 2 x 4 revolute joints = 3 coordinates - 2 x 1 cut "
              "joint (B) = 1")


def test_over_actuated(tmp_path):
    msg = _fails(tmp_path, _edit(FOUR_BAR, ("child = \"rocker.O4\"\nactuated = false",
                                            "child = \"rocker.O4\"\nactuated = true")))
    assert msg.endswith(
        "joints: over-actuated: 2 actuated joints (crank_joint, rocker_joint) for "
        f"{COUNT_4BAR} degree of freedom: the motors fight each other and the closed-chain "
        "torques are not unique; mark 1 of them actuated = false")


def test_over_actuated_with_assembled_pose_says_why_the_loop_stays_open(tmp_path):
    text = (ROOT / "examples" / "four_bar_joints.toml").read_text()
    at = text.index('name = "rocker_joint"')
    text = text[:at] + _edit(text[at:], ("actuated = false", "actuated = true"))
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(DescriptionError) as info:
        description.load(path)
    assert any("over-actuated: 2 actuated joints (crank_joint, rocker_joint)" in p
               and "the loops cannot close with them all held" in p
               for p in info.value.problems), info.value.problems


def test_under_actuated(tmp_path):
    msg = _fails(tmp_path, _edit(FIVE_BAR, ('child = "R_Link1.CS1"\nactuated = true',
                                            'child = "R_Link1.CS1"\nactuated = false')))
    assert ("joints: under-actuated: 1 actuated joint (A) for F = 3 x 4 moving bodies - 2 x 5 "
            "revolute joints = 4 coordinates - 2 x 1 cut joint (C) = 2 degrees of freedom: the "
            "actuated joints do not determine the motion") in msg
    assert msg.endswith("mark 1 of B, E, D actuated = true")


def test_no_actuator_at_all(tmp_path):
    msg = _fails(tmp_path, _edit(FOUR_BAR, ('child = "crank.O2"\nactuated = true',
                                            'child = "crank.O2"\nactuated = false')))
    assert f"joints: no actuated joint for {COUNT_4BAR} degree of freedom" in msg
    assert msg.endswith("mark 1 of crank_joint, coupler_joint, rocker_joint actuated = true")


def test_tree_with_passive_joint_is_legitimate(tmp_path):
    serial = (ROOT / "planar_sym" / "robots" / "serial_2dof.toml").read_text()
    path = tmp_path / "arm.toml"
    path.write_text(serial.replace("actuated = true", "actuated = false", 1))
    m = mobility.of(description.load(path))
    assert (m.dof, m.gruebler, len(m.actuated)) == (2, 2, 1)


def test_loop_cut_twice(tmp_path):
    msg = _fails(tmp_path, FOUR_BAR.replace("[task]", "[[joints]]\n" + CUT_B.replace(
        'name = "B"', 'name = "B2"') + "\n[task]"))
    assert msg.endswith("joints: loop cut twice: B and B2 both join coupler.B to rocker.B, so "
                        "B2 closes no new loop, it only repeats B's 2 equations; remove B2")


def test_cut_repeating_a_tree_joint(tmp_path):
    msg = _fails(tmp_path, FOUR_BAR.replace("[task]", "[[joints]]\n" + _edit(
        CUT_B, ('name = "B"', 'name = "A2"'), ('"coupler.B"', '"coupler.A"'),
        ('"rocker.B"', '"crank.A"')) + "\n[task]"))
    assert "joint repeated: coupler_joint and A2 both join coupler.A to crank.A" in msg


def test_cut_that_disconnects_the_tree(tmp_path):
    cut = 'child = "rocker.O4"\nactuated = false\ncloses_loop = true'
    msg = _fails(tmp_path, _edit(FOUR_BAR, ('child = "rocker.O4"\nactuated = false', cut)))
    assert msg.endswith("joints: bodies ['rocker'] reach ground only through cut joints "
                        "(rocker_joint, B): 2 cuts for 1 independent loop leave the tree "
                        "disconnected; make rocker_joint or B a tree joint (closes_loop = false)")


def test_structure(tmp_path):
    msg = _fails(tmp_path, TRIANGLE)
    assert msg.endswith(
        "joints: a structure, not a mechanism: F = 3 x 2 moving bodies - 2 x 3 revolute joints "
        "= 2 coordinates - 2 x 1 cut joint (A) = 0 degrees of freedom and Phi_q has full rank 2 "
        "at the drawn pose, so nothing moves; remove a link, or split one with a joint")


def test_redundant_constraint_parallelogram_with_extra_link(tmp_path):
    msg = _fails(tmp_path, PARALLEL)
    assert ("joints: redundant constraint: the 4 loop-closure equations of loops B, C have rank "
            "3 at the drawn pose (Phi_q 4 x 4, ") in msg
    assert ("it moves with 1 degree of freedom where F = 3 x 4 moving bodies - 2 x 6 revolute "
            "joints = 4 coordinates - 2 x 2 cut joints (B, C) = 0") in msg


def test_singular_drawn_pose(tmp_path):
    msg = _fails(tmp_path, FLAT)
    assert ("joints: singular drawn pose: the 2 loop-closure equations of loop B have rank 1 at "
            "the drawn pose (Phi_q 2 x 3, ") in msg
    assert f"2 degrees of freedom there where the count gives {COUNT_4BAR}; links are aligned" in msg


@pytest.mark.parametrize("robot, dof", [
    ("serial_2dof", 2), ("serial_3dof", 3), ("five_bar_type1", 2), ("five_bar_type2", 2),
    ("parallel_3rrr", 3), (ROOT / "examples" / "four_bar.toml", 1),
    (ROOT / "examples" / "four_bar_joints.toml", 1), (ROOT / "examples" / "six_bar_watt.toml", 1),
    (ROOT / "tests" / "robots" / "bent_arm.toml", 2),
    (ROOT / "tests" / "robots" / "horizontal_2dof.toml", 2),
    (ROOT / "tests" / "robots" / "pendulum.toml", 1),
    # with prismatic joints (issue 11): the coordinate count takes them like revolute joints
    ("slider_crank", 1), ("slider_crank_slider_driven", 1), ("serial_rpr", 3),
    ("parallel_3rpr", 3), (ROOT / "tests" / "robots" / "cart_pole_incline.toml", 2),
    (ROOT / "tests" / "robots" / "actuated_2dof.toml", 2),
    (ROOT / "tests" / "robots" / "point_pendulum.toml", 1),
    (ROOT / "tests" / "robots" / "rotated_slider.toml", 3),
    (ROOT / "tests" / "robots" / "rpr_geared.toml", 3),
    (ROOT / "tests" / "robots" / "parallelogram.toml", 1),
    (ROOT / "tests" / "robots" / "carriage_arm.toml", 3),
    (ROOT / "tests" / "robots" / "geared_cart_arm.toml", 3),
    (ROOT / "tests" / "robots" / "pend_lim.toml", 1),
    (ROOT / "tests" / "robots" / "five_bar_unequal.toml", 2),
])
def test_dof_of_every_robot_that_ships(robot, dof):
    m = mobility.of(description.load(robot))
    assert m.dof == m.gruebler == dof
    assert len(m.actuated) == dof
    assert m.rank == 2 * len(m.cuts)


def test_test_robots_are_all_counted():
    """Every test robot is in the table above, but cart_pole.toml (its hinge is passive, so its
    2 degrees of freedom have 1 motor: an underactuated tree, tests/test_sliders.py)."""
    assert sorted(p.name for p in (ROOT / "tests" / "robots").glob("*.toml")) == [
        "actuated_2dof.toml", "bent_arm.toml", "carriage_arm.toml", "cart_pole.toml",
        "cart_pole_incline.toml", "five_bar_unequal.toml", "geared_cart_arm.toml",
        "horizontal_2dof.toml", "parallelogram.toml", "pend_lim.toml", "pendulum.toml",
        "point_pendulum.toml",
        "rotated_slider.toml", "rpr_geared.toml"]
    m = mobility.of(description.load(ROOT / "tests" / "robots" / "cart_pole.toml"))
    assert m.dof == m.gruebler == 2 and len(m.actuated) == 1


def test_cli_refuses_in_one_line_and_leaves_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    bad = tmp_path / "over.toml"
    bad.write_text(_edit(FOUR_BAR, ("child = \"rocker.O4\"\nactuated = false",
                                    "child = \"rocker.O4\"\nactuated = true")))
    study = tmp_path / "study.toml"
    study.write_text('title = "t"\nrobot = "over.toml"\nkind = "inverse"\n\n[motion]\n'
                     'space = "joint"\nprofile = "cubic"\nstart = [1.0]\nby = [0.1]\n'
                     'duration = 1.0\nsamples = 11\n')
    before = sorted(p.name for p in tmp_path.iterdir())
    for argv in (["draw", str(bad)], ["run", str(study), "--out", str(tmp_path / "out")],
                 ["derive", str(bad), "--out", str(tmp_path / "gen"), "--no-build"]):
        capsys.readouterr()
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert "Traceback" not in err
        problems = [line for line in err.splitlines() if line.startswith("  ")]
        assert len(problems) == 1 and "over-actuated: 2 actuated joints" in problems[0], err
        assert err.startswith("error: invalid robot description:\n"), err
        assert sorted(p.name for p in tmp_path.iterdir()) == before, argv


def test_weld_counts_three(tmp_path):
    """The coupler welded to the crank: 3 x 3 - 2 x 3 - 3 x 1 = 0, a structure."""
    msg = _fails(tmp_path, _edit(FOUR_BAR, ('name = "coupler_joint"\ntype = "revolute"',
                                            'name = "coupler_joint"\ntype = "weld"')))
    assert ("a structure, not a mechanism: F = 3 x 3 moving bodies - 2 x 3 revolute joints - "
            "3 x 1 weld = 2 coordinates - 2 x 1 cut joint (B) = 0 degrees of freedom") in msg


def test_a_robot_off_its_tree_with_another_mistake_is_refused_not_crashed(tmp_path):
    """Found by Hypothesis: the five-bar without its name and its first and third joints has
    loops but no coordinate on a tree that reaches every body; the count must not run on it
    (it raised IndexError). One message: the missing name."""
    blocks = FIVE_BAR.split("[[joints]]")
    text = "[[joints]]".join([blocks[0], blocks[2], *blocks[4:]])
    text = "\n".join(line for line in text.splitlines() if not line.startswith("name = \"five"))
    path = tmp_path / "broken.toml"
    path.write_text(text)
    with pytest.raises(DescriptionError) as info:
        description.load(path)
    assert [p.split(": ", 1)[1] for p in info.value.problems] == ["name: missing"]
