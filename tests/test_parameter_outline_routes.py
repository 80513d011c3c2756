"""A body's outline rules hold on every route a value enters by (a user trial, trial H).

* **Centre of gravity**: more than 10 times the body's size outside the outline of its points is
  refused, beyond 1 time warned. The description had the rule; ``with_parameters``, a study's
  ``[parameters]``, ``move --set`` and a sweep took cgx = 1.2 m on a 0.1 m link without a word.
* **A body of a single point** (a motor at a joint, a bob) has no size of its own: its inertia's
  radius of gyration beyond 3 times the robot's span is refused, its mass above osmium filling a
  ball as wide as the span warned. No route checked it: izz = 1e8 kg*mm^2 on the 0.292 kg motor
  of the seed's arm turned S3's 0.386 N*m into 48 N*m; 2000 kg at its elbow passed.

Each route's message names the parameter and the same figures; the column-wise check of a
sweep (``failing``) agrees with the scalar one (``problems``) on random designs.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.analysis.sweep import sweep
from planar_sym.cli import main
from planar_sym.errors import DescriptionError, InputError
from planar_sym.model.description import load as load_description
from planar_sym.model.parameters import failing, problems

SEED = ROOT / "planar_sym" / "robots" / "serial_2dof.toml"
MOVE = ["move", "serial_2dof", "--task", "--from", "100,100", "--by=-200,0", "--duration", "2"]


def described(tmp_path, old: str, new: str):
    text = SEED.read_text()
    assert text.count(old) >= 1
    path = tmp_path / "arm.toml"
    path.write_text(text.replace(old, new, 1))
    return path


def study(tmp_path, line: str):
    path = tmp_path / "study.toml"
    path.write_text('robot = "serial_2dof"\nkind = "inverse"\n[units]\nlength = "mm"\n'
                    "[motion]\nspace = \"task\"\nstart = [100.0, 100.0]\nby = [-200.0, 0.0]\n"
                    f"duration = 2.0\n[parameters]\n{line}\n")
    return path


def test_a_centre_of_gravity_far_off_its_link_is_refused_on_every_route(tmp_path, capsys):
    # the description (cg typed 1.2 m from CS1 on the 0.1 m link1)
    with pytest.raises(DescriptionError, match=r"link1\)\.cg: the centre of gravity lies 1\.1 m "
                                               r"outside .* 11 times the body's size of 100 mm"):
        load_description(described(tmp_path, "cg = [0.0373, 0.0]", "cg = [1.2, 0.0]"))
    want = (r"parameter cgx_link1 puts the centre of gravity 1100 mm outside the outline of the "
            r"body's points, 11 times the body's size of 100 mm")
    arm = ps.load("serial_2dof")
    with pytest.raises(InputError, match=want):
        arm.with_parameters(cgx_link1=1.2)
    assert main([*MOVE, "--set", "cgx_link1=1.2", "--out", str(tmp_path / "a")]) == 2  # m
    assert re.search(want, capsys.readouterr().err)
    assert main(["run", str(study(tmp_path, "cgx_link1 = 1.2")), "--out",
                 str(tmp_path / "b")]) == 2
    assert re.search(want, capsys.readouterr().err)
    with pytest.raises(InputError, match="design 0 .* is not physical: " + want):
        sweep("serial_2dof_cartesian_move", {"cgx_link1": [1.2, 1.3]}, workers=1)
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


def test_a_centre_of_gravity_somewhat_off_is_warned_on_every_route(tmp_path):
    with pytest.warns(RuntimeWarning, match=r"link1\)\.cg: the centre of gravity lies 400 mm "):
        load_description(described(tmp_path, "cg = [0.0373, 0.0]", "cg = [0.5, 0.0]"))
    with pytest.warns(RuntimeWarning, match=r"cgx_link1 puts the centre of gravity 400 mm "
                                             r"outside .* 4 times the body's size of 100 mm"):
        ps.load("serial_2dof").with_parameters(cgx_link1=0.5)


def test_a_single_point_bodys_inertia_is_held_against_the_robots_span(tmp_path, capsys):
    with pytest.raises(DescriptionError, match=r"motor2\)\.izz: implausible: 100000000.0 "
                                               r"kg\*mm\^2 gives a radius of gyration of "
                                               r"1\.851e\+04 mm to a body of a single point in "
                                               r"a robot whose points span 200 mm"):
        load_description(described(tmp_path, "izz = 0.0", "izz = 1e8").with_suffix(".toml"))
    want = (r"parameter izz_motor2 = 100 kg\*m\^2 with m_motor2 = 0.292 kg gives a radius of "
            r"gyration of 1\.851e\+04 mm to a body of a single point in a robot that reaches "
            r"200 mm")
    with pytest.raises(InputError, match=want):
        ps.load("serial_2dof").with_parameters(izz_motor2=100.0)
    assert main([*MOVE, "--set", "izz_motor2=1e8", "--out", str(tmp_path / "a")]) == 2
    assert re.search(want, capsys.readouterr().err)
    # by hand: sqrt(100 / 0.292) m against 3 x (0.1 + 0.1) m
    assert np.sqrt(100 / 0.292) == pytest.approx(18.51, abs=0.01) and 18.51 > 3 * 0.2
    # a rotor's inertia where it belongs is no slip: 1e-5 kg*m^2 on the motor is fine
    ps.load("serial_2dof").with_parameters(izz_motor2=1e-5)


def test_a_heavy_single_point_is_warned(tmp_path):
    """osmium (22,590 kg/m^3) filling a ball of 0.2 m: 757 kg."""
    with pytest.warns(RuntimeWarning, match=r"motor2\)\.mass: 2000 kg .* more than osmium filling "
                                         r"a ball as wide as the robot's span \(200 mm\) would "
                                         r"weigh \(757 kg\)"):
        load_description(described(tmp_path, "mass = 0.292", "mass = 2000"))
    with pytest.warns(RuntimeWarning, match=r"m_motor2 = 2000 kg .* \(757 kg\)"):
        ps.load("serial_2dof").with_parameters(m_motor2=2000.0)
    assert 22590 * 4 / 3 * np.pi * 0.2**3 == pytest.approx(757, abs=0.5)


@pytest.mark.parametrize("robot", ["serial_2dof", "five_bar_type1", "serial_3dof", "slider_crank"])
def test_the_column_rules_agree_with_the_scalar_ones(robot):
    """Random designs moving the centres of gravity, points and single-point inertias around
    each robot's own values: ``failing`` (a sweep's check) is true exactly where ``problems``
    words a refusal, and some designs are refused, some not."""
    r = ps.load(robot)
    names = [*(p.name for p in r.parameter_list), *r.parameters.fixed]
    base = np.array([*r.p, *r.parameters.fixed.values()])
    rng = np.random.default_rng(11)
    moved = [k for k, n in enumerate(names) if n.startswith(("cgx_", "cgy_", "px_", "izz_"))]
    P = np.tile(base, (300, 1))
    for row in P:
        k = rng.choice(moved)
        row[k] = (row[k] or 0.05) * rng.choice([-30, -3, 0.5, 3, 14, 1e6])
    bad = failing(names, P, r.body_names)
    assert bad.any() and not bad.all()
    for k in range(len(P)):
        assert bad[k] == bool(problems(dict(zip(names, P[k])), r.body_names)), k
