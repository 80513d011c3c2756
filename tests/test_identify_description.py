"""The identified robot's description file (``identify/description_file.py``): written with
perturbed values and read back by the description reader (an independent inverse: it turns
typed units, cg_from points and frames into body-frame SI), it gives those values and the same
parameter list (only values changed, no structure). Read without deriving (fast); the CLI test
runs a study on a written file end to end."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import InputError
from planar_sym.identify.description_file import identified_description
from planar_sym.identify.report import IDENTIFIED
from planar_sym.model.description import load as read_description
from planar_sym.toml_write import dumps

# units (g, mm, kg*mm^2), actuators, closed chains, pose = "joints", sliders, a tilted slide,
# a body frame turned from the world, a point mass, cg typed from points and from the origin
ROBOTS = ["examples/serial_2dof_geared.toml", "five_bar_type1", "serial_rpr", "parallel_3rpr",
          "slider_crank", "examples/four_bar_joints.toml", "examples/jansen_linkage.toml",
          "tests/robots/rotated_slider.toml", "tests/robots/point_pendulum.toml",
          "tests/robots/rpr_geared.toml", "tests/robots/cart_pole_incline.toml"]


def _perturbed(robot, seed):
    rng = np.random.default_rng(seed)
    par = robot.parameters
    return robot.with_parameters(**{k: par[k] * rng.uniform(0.7, 1.3) for k in par
                                    if k.startswith(IDENTIFIED) and par[k] != 0.0})


@pytest.mark.parametrize("ref", ROBOTS)
def test_written_description_reads_back_to_the_identified_values(ref, tmp_path):
    robot = ps.load(ref)
    ident = _perturbed(robot, seed=len(ref))
    path = tmp_path / "identified_robot.toml"
    path.write_text(identified_description(robot, ident, "test"))
    back = {p.name: p.value for p in read_description(path).parameters()}
    assert list(back) == list(robot.parameters)  # the same structure, in the same order
    changed = [k for k in ident.parameters if ident.parameters[k] != robot.parameters[k]]
    assert changed, "nothing was perturbed"
    for k in ident.parameters:  # identified values, geometry and gravity unchanged
        assert back[k] == pytest.approx(ident.parameters[k], rel=1e-10, abs=1e-15), k
    assert path.read_text().startswith(f"# {robot.name} as identified by planar-sym identify")


def test_a_moved_point_mass_gets_a_point_of_its_own(tmp_path):
    robot = ps.load("tests/robots/point_pendulum.toml")
    ident = robot.with_parameters(m_rod=1.2, cgx_rod=0.45)
    path = tmp_path / "p.toml"
    path.write_text(identified_description(robot, ident))
    raw = tomllib.loads(path.read_text())
    rod = raw["bodies"][0]
    assert rod["mass_at"] == "cg" and rod["points"]["cg"] == pytest.approx([0.45, 0.0])
    assert rod["points"]["bob"] == [0.6, 0.0]  # the frame's point stays
    back = {p.name: p.value for p in read_description(path).parameters()}
    assert list(back) == list(robot.parameters)
    assert (back["m_rod"], back["cgx_rod"]) == pytest.approx((1.2, 0.45))


def test_values_are_written_in_the_files_units(tmp_path):
    """serial_2dof_geared types inertia in kg*mm^2: the identified 1e-4 kg*m^2 is 100 there."""
    robot = ps.load("examples/serial_2dof_geared.toml")
    ident = robot.with_parameters(izz_link1=1e-4, jm_joint1=2e-7, fv_joint1=0.003)
    raw = tomllib.loads(identified_description(robot, ident))
    assert raw["units"]["inertia"] == "kg*mm^2"
    assert raw["bodies"][0]["izz"] == pytest.approx(100.0)
    act = raw["joints"][0]["actuator"]
    assert act["rotor_inertia"] == pytest.approx(0.2) and act["viscous_friction"] == 0.003
    assert act["gear_ratio"] == 50  # what identification does not touch stays as typed


def test_toml_writer_round_trips_a_whole_description():
    for ref in ("five_bar_type1", "examples/serial_2dof_geared.toml"):
        raw = tomllib.loads(ps.load(ref).description_file.read_text())
        assert tomllib.loads(dumps(raw)) == raw


def test_a_robot_without_a_file_is_refused_with_where_the_values_are(monkeypatch):
    robot = ps.load("serial_2dof")
    monkeypatch.setattr(type(robot), "description_file", property(lambda self: None))
    with pytest.raises(InputError, match="identified_parameters.toml"):
        identified_description(robot, robot)
