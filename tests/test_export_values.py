"""The exported files' numbers and words (``outputs/export.py``, ``export_model.py``,
``export_mjcf.py``) against references independent of the exporter (issue 30: the survivors of
the first mutation runs showed which of these were unpinned):

- MuJoCo on the MJCF text: ``mj_inverse`` gives our ``tree_inverse_dynamics`` to ``GATE`` at
  random states for a tilted slider with point masses, a rotated weld with tilted gravity, a
  slider drawn turned to its rail, a geared RPR arm whose rotors ride on moving links (less the
  coupling ``N J_m`` the header documents, computed here from the parameters) and the trees of
  closed chains (equality off); MuJoCo's body frames are our ``frames`` (all in the plane
  z = 0); laid out at any pose (joint ``ref``), qpos stays q. Two variants written here and
  derived once (a slide with no drawn offset and an upright point mass; joints off their
  bodies' frame origins on a turned carriage) reach the structural zeros and every placement
  term;
- MuJoCo's compiled model read back: masses, inertias (a rotor's J_m on the body carrying its
  stator; a moving point mass raised to 1e-12 m size^2, at least 1e-14), armature N^2 J_m,
  damping, frictionloss, gear, control and force ranges, gravity, timestep, loop softness, each
  against the robot's parameters and drive train; the viewer's camera, statistic and geom sizes
  against the span of the drawn pose measured on the geoms MuJoCo placed;
- the benchmarks' bare model (``mjcf(from_description(...))``) against the robot's dynamics
  and the user file: the same bodies, no geoms, motors or comment;
- ``from_robot`` against ``from_description`` (a second reading of the same description), and
  a generated folder copied and edited: no description, another description, an old manifest;
- the file itself: elements only (no stray text), no empty sections, nested bodies indented;
  the format rules, the output checks and the header, warnings and refusals word for word.
"""

from __future__ import annotations

import json
import math
import re
import shutil
import warnings
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pytest
from conftest import ROBOTS_DIR as ROBOTS
from conftest import ROOT, TEST_ROBOTS, random_states, rel_err

import planar_sym as ps
from planar_sym.errors import InputError, LibraryError
from planar_sym.model.description import load as load_description
from planar_sym.outputs import export, export_mjcf, export_model
from planar_sym.outputs.export import check_out, format_of, text, to_mjcf, to_urdf, write
from planar_sym.outputs.export_mjcf import mjcf
from planar_sym.outputs.export_model import from_description, from_robot, header, numbers

GATE = 1e-10
#: test robots (derived once into the user cache by planar_sym.load)
FILES = {"rpr_geared": TEST_ROBOTS / "rpr_geared.toml",
         "actuated_2dof": TEST_ROBOTS / "actuated_2dof.toml",
         "cart_pole_incline": TEST_ROBOTS / "cart_pole_incline.toml",
         "bent_arm": TEST_ROBOTS / "bent_arm.toml",
         "rotated_slider": TEST_ROBOTS / "rotated_slider.toml"}


def load(name: str) -> ps.Robot:
    return ps.load(FILES.get(name, name))


def quiet(fn, *args, **kw):
    """``fn`` with the drive train's RuntimeWarnings silenced (tested on their own below)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return fn(*args, **kw)


def rigid(robot: ps.Robot) -> ps.Robot:
    """The robot without Coulomb friction (MuJoCo's frictionloss is a soft constraint, not a
    torque that mj_inverse can be compared with)."""
    return robot.with_parameters(**{k: 0.0 for k in robot.parameters if k.startswith("fc_")})


def mj_model(xml: str) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(xml)


def mj_inverse(model, robot, q, qd, qdd, equality: bool = True) -> np.ndarray:
    """``mj_inverse`` in our coordinate order (joints matched by name)."""
    if not equality:  # the spanning tree: the cut joints open
        model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_EQUALITY
    data = mujoco.MjData(model)
    qa = [model.joint(c).qposadr[0] for c in robot.coordinates]
    va = [model.joint(c).dofadr[0] for c in robot.coordinates]
    assert model.nq == model.nv == robot.n
    out = np.empty_like(q)
    for k in range(len(q)):
        data.qpos[qa], data.qvel[va], data.qacc[va] = q[k], qd[k], qdd[k]
        mujoco.mj_inverse(model, data)
        out[k] = data.qfrc_inverse[va]
    return out


def assert_frames_are_ours(model, robot, q) -> None:
    """MuJoCo's body frames (origin, angle) at qpos = q are our ``frames``; every joint's
    anchor lies in the plane z = 0."""
    data = mujoco.MjData(model)
    qa = [model.joint(c).qposadr[0] for c in robot.coordinates]
    ids = [model.body(b).id for b in robot.body_names]
    frames = robot.frames(q)
    for k in range(len(q)):
        data.qpos[qa] = q[k]
        mujoco.mj_kinematics(model, data)
        np.testing.assert_allclose(data.xpos[ids, :2], frames[k, :, :2], rtol=0, atol=1e-13)
        turn = 2 * np.arctan2(data.xquat[ids, 3], data.xquat[ids, 0]) - frames[k, :, 2]
        np.testing.assert_allclose(np.angle(np.exp(1j * turn)), 0.0, rtol=0, atol=1e-13)
        np.testing.assert_allclose(data.xpos[:, 2], 0.0, rtol=0, atol=1e-15)
        np.testing.assert_allclose(data.xanchor[:, 2], 0.0, rtol=0, atol=1e-15)


def assert_clean(xml: str) -> None:
    """Elements only: no stray text between or inside them (MJCF elements hold none)."""
    for el in ET.fromstring(xml).iter():
        assert not (el.text or "").strip() and not (el.tail or "").strip(), el.tag


def comment(xml: str) -> list[str]:
    """The header comment's lines, stripped."""
    return [line.strip() for line in xml[xml.index("<!--") + 4:xml.index("-->")].splitlines()
            if line.strip()]


def drawn_span(model: mujoco.MjModel) -> tuple[np.ndarray, float, float]:
    """Centre, size (m) and the capsule radius of the drawn pose, measured on the geoms MuJoCo
    placed at its reset state (a sphere at every centre of gravity and ground point, a capsule
    from a centre of gravity to each of its body's points) and the world origin (ground's
    frame, which the view keeps)."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    pts, radii = [], set()
    for g in range(model.ngeom):
        c = data.geom_xpos[g]
        if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE:
            axis = data.geom_xmat[g].reshape(3, 3)[:, 2] * model.geom_size[g, 1]
            pts += [c + axis, c - axis]
            radii.add(float(model.geom_size[g, 0]))
        else:
            pts.append(c.copy())
    pts = np.array([*pts, np.zeros(3)])
    np.testing.assert_allclose(pts[:, 2], 0.0, rtol=0, atol=1e-15)  # all in the plane z = 0
    pts = pts[:, :2]  # and ground's frame: the world origin
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    assert len(radii) == 1, radii
    return (lo + hi) / 2, float(np.max(hi - lo)), radii.pop()


# -- export.py: the format, the output file ---------------------------------------------------

def test_the_format_comes_from_the_option_or_the_suffix():
    assert format_of(None, None) == "mjcf"  # nothing said: MJCF
    assert format_of(None, Path("a.XML")) == format_of(None, Path("a.mjcf")) == "mjcf"
    assert format_of(None, Path("arm.URDF")) == "urdf"
    assert format_of("MJCF", None) == "mjcf" and format_of("Urdf", None) == "urdf"
    assert format_of("urdf", Path("a.urdf")) == "urdf"  # agreeing: fine
    assert format_of("mjcf", Path("a.mjcf")) == "mjcf"
    assert format_of("urdf", Path("notes.txt")) == "urdf"  # a suffix naming no format


@pytest.mark.parametrize(("fmt", "path", "message"), [
    ("sdf", None, "--format must be mjcf or urdf (got 'sdf')"),
    ("mjcf", "b.urdf", ("--format mjcf but --out b.urdf names a URDF file: give --format urdf, "
                       "or name the file .xml")),
    ("urdf", "b.mjcf", ("--format urdf but --out b.mjcf names an MJCF file: give --format mjcf, "
                       "or name the file .urdf")),
    (None, "r.sdf", ("--out r.sdf: cannot tell the format from the suffix '.sdf'; give --format "
                    "mjcf or urdf (or name the file .xml or .urdf)")),
    (None, "README", ("--out README: cannot tell the format from the suffix '(none)'; give "
                     "--format mjcf or urdf (or name the file .xml or .urdf)")),
])
def test_format_refusals_word_for_word(fmt, path, message):
    with pytest.raises(InputError) as err:
        format_of(fmt, None if path is None else Path(path))
    assert str(err.value) == message


def test_the_output_must_be_a_file_in_an_existing_folder(tmp_path):
    check_out(tmp_path / "ok.xml")  # a new file in an existing folder: fine
    with pytest.raises(InputError) as err:
        check_out(tmp_path, "arm")
    assert str(err.value) == (f"--out {tmp_path} is a folder; give a file name, such as "
                              f"{tmp_path / 'arm.xml'}")
    with pytest.raises(InputError) as err:
        check_out(tmp_path / "no" / "r.xml")
    assert str(err.value) == (f"--out {tmp_path / 'no' / 'r.xml'}: its folder {tmp_path / 'no'} "
                              "does not exist; create it first")
    (tmp_path / "f").write_text("")
    with pytest.raises(InputError) as err:
        check_out(tmp_path / "f" / "r.xml")
    assert str(err.value) == (f"--out {tmp_path / 'f' / 'r.xml'}: its folder {tmp_path / 'f'} "
                              "is a file, not a folder; create it first")
    with pytest.raises(InputError) as err:  # no robot named
        check_out(tmp_path)
    assert str(err.value).endswith(f"such as {tmp_path / 'ROBOT.xml'}")
    with pytest.raises(InputError) as err:  # write names the robot in its example
        write(ps.load("serial_2dof"), tmp_path)
    assert f"such as {tmp_path / 'serial_2dof.xml'}" in str(err.value)


def test_write_defaults_and_the_text_it_writes(tmp_path, monkeypatch):
    """The default file is ROBOT.xml (or ROBOT.urdf) in the working folder, holding ``text``:
    ``to_mjcf`` or ``to_urdf``; ``ideal`` reaches the MJCF."""
    monkeypatch.chdir(tmp_path)
    arm = ps.load("serial_2dof")
    assert write(arm) == Path("serial_2dof.xml")
    assert (tmp_path / "serial_2dof.xml").read_text() == to_mjcf(arm) == text(arm)
    assert write(arm, fmt="urdf") == Path("serial_2dof.urdf")
    assert (tmp_path / "serial_2dof.urdf").read_text() == to_urdf(arm) == text(arm, "URDF")
    geared = load("actuated_2dof")
    ideal = quiet(to_mjcf, geared, ideal=True)
    assert ideal != quiet(to_mjcf, geared)  # so the comparisons below say something
    assert quiet(text, geared, "mjcf", True) == ideal
    path = quiet(write, geared, tmp_path / "g.mjcf", ideal=True)
    assert path == tmp_path / "g.mjcf" and path.read_text() == ideal
    assert quiet(write, geared, str(tmp_path / "h.xml")).read_text() == quiet(to_mjcf, geared)
    assert write(arm, tmp_path / "u.URDF").read_text() == to_urdf(arm)  # format from the suffix
    with pytest.raises(InputError, match=r"names a URDF file"):
        write(arm, tmp_path / "v.urdf", fmt="mjcf")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.mjcf", "h.xml", "serial_2dof.urdf",
                                                          "serial_2dof.xml", "u.URDF"]


def test_the_formats_table():
    assert export.FORMATS == {"mjcf": (to_mjcf, ".xml", (".xml", ".mjcf")),
                              "urdf": (to_urdf, ".urdf", (".urdf",))}


# -- MuJoCo's dynamics on the file against ours ----------------------------------------------

@pytest.mark.parametrize("name", ["cart_pole_incline", "bent_arm", "rotated_slider",
                                  "serial_rpr"])
def test_tree_files_give_our_inverse_dynamics(name, rng):
    """A tilted rail with point masses, a rotated weld under tilted gravity, a slider drawn
    turned to its rail, a changed RPR arm (slide offset, point, gravity)."""
    robot = load(name)
    if name == "serial_rpr":
        robot = robot.with_parameters(s0_extend=0.25, px_boom_W=0.6, cgx_sleeve=0.2, g=3.7)
    q, qd, qdd = random_states(rng, 20, robot.n)
    model = mj_model(to_mjcf(robot))
    assert rel_err(mj_inverse(model, robot, q, qd, qdd),
                   robot.tree_inverse_dynamics(q, qd, qdd)) < GATE
    assert_frames_are_ours(model, robot, q)


@pytest.mark.parametrize("name", ["five_bar_type1", "slider_crank", "parallel_3rpr"])
def test_closed_chain_trees_give_our_tree_dynamics(name, rng):
    """With MuJoCo's equality constraints off, the file is the spanning tree, cut joints open."""
    robot = ps.load(name)
    q, qd, qdd = random_states(rng, 10, robot.n)
    model = mj_model(to_mjcf(robot))
    assert model.neq == len(robot.loops)
    assert rel_err(mj_inverse(model, robot, q, qd, qdd, equality=False),
                   robot.tree_inverse_dynamics(q, qd, qdd)) < GATE
    assert_frames_are_ours(model, robot, q)


@pytest.mark.parametrize(("name", "changes"), [
    ("bent_arm", {"cgy_link2": 0.004, "py_ground_O": 0.03, "cgy_bracket": -0.01}),
    ("parallel_3rrr", {"py_platform_CS1": 0.02, "py_ground_A2": 0.05, "cgy_Link2_1": 0.01}),
])
def test_changed_points_and_centres_of_gravity_reach_mujoco(name, changes, rng):
    """Body-frame y coordinates changed by ``with_parameters``: MuJoCo's body frames (origin,
    angle) are our ``frames`` at random q, and its inverse dynamics ours (cut joints open)."""
    base = load(name)
    robot = base.with_parameters(**changes)
    q, qd, qdd = random_states(rng, 10, robot.n)
    ours = robot.tree_inverse_dynamics(q, qd, qdd)
    assert rel_err(base.tree_inverse_dynamics(q, qd, qdd), ours) > 1e-3  # the change matters
    m = mj_model(to_mjcf(robot))
    assert rel_err(mj_inverse(m, robot, q, qd, qdd, equality=False), ours) < GATE
    assert_frames_are_ours(m, robot, q)


def test_a_slider_without_offset_and_a_centre_of_gravity_on_the_y_axis(tmp_path, rng):
    """The inclined cart-pole drawn with the cart on the rail's origin (no offset parameter
    s0: a structural 0) and the pole upright without a frame (its centre of gravity (0, 0.5)
    in its own frame: cgx a structural 0, cgy a parameter)."""
    text = (TEST_ROBOTS / "cart_pole_incline.toml").read_text()
    for old, new in (('"cart_pole_incline"', '"cart_pole_on_g"'),
                     ("[0.1879385241571817, 0.06840402866513375]", "[0.0, 0.0]"),
                     ('T = [0.10111443532371656, 0.5608079051712378] }\nframe = ["C", "T"]',
                      "T = [0.0, 0.5] }")):
        assert old in text
        text = text.replace(old, new)
    (tmp_path / "cart_pole_on_g.toml").write_text(text)
    robot = ps.load(tmp_path / "cart_pole_on_g.toml")  # derived once, then from the cache
    assert "s0_rail" not in robot.parameters and "cgx_pole" not in robot.parameters
    model = from_robot(robot)
    assert model.offsets_m == {"rail": 0.0} and model.bodies["pole"].cg_m == (0.0, 0.5)
    q, qd, qdd = random_states(rng, 10, robot.n)
    assert rel_err(mj_inverse(mj_model(to_mjcf(robot)), robot, q, qd, qdd),
                   robot.tree_inverse_dynamics(q, qd, qdd)) < GATE


def test_joints_off_the_frames_origins_on_a_turned_carriage(tmp_path, rng):
    """The rotated slider with the slide leaving the arm off its frame's origin and entering
    the carriage off its own, the wrist likewise: every term of a child body's placement
    matters. MuJoCo's frames and torques are ours, laid out at the drawn pose or elsewhere."""
    text = (TEST_ROBOTS / "rotated_slider.toml").read_text()
    for old, new in (('"rotated_slider"', '"offset_slider"'),
                     ("O = [0.0, 0.0], S = [0.5, 0.0] }", ("O = [0.0, 0.0], S = [0.5, 0.0], "
                                                           "G = [0.1, 0.04] }")),
                     ('parent = "arm.O"', 'parent = "arm.G"'),
                     ("C = [0.0, 0.0], P = [0.12, 0.0]", "C = [0.05, 0.03], P = [0.12, 0.0]"),
                     ("P = [0.0, 0.0], T = [0.2, 0.0]", "P = [0.02, -0.01], T = [0.2, 0.0]")):
        assert old in text
        text = text.replace(old, new)
    (tmp_path / "offset_slider.toml").write_text(text)
    robot = ps.load(tmp_path / "offset_slider.toml")  # derived once, then from the cache
    q, qd, qdd = random_states(rng, 10, robot.n)
    m = mj_model(to_mjcf(robot))
    assert rel_err(mj_inverse(m, robot, q, qd, qdd),
                   robot.tree_inverse_dynamics(q, qd, qdd)) < GATE
    assert_frames_are_ours(m, robot, q)
    laid = mj_model(mjcf(from_robot(robot), ref={"shoulder": 0.3, "slide": 0.1, "wrist": -1.0}))
    assert_frames_are_ours(laid, robot, q)


def test_a_tilted_slide_axis_is_in_the_parent_s_frame():
    """The rotated slider's axis tilted to (0.6, 0.8) in the arm's frame (the carriage turned
    30 deg to the arm; no derived robot here: the axis as the description would give it):
    MuJoCo's slide axis is the arm's frame turned onto (0.6, 0.8) at any pose, and sliding by
    d moves the carriage d along it."""
    model = from_robot(load("rotated_slider"))
    tilted = replace(model, tree=tuple(replace(j, axis=(0.6, 0.8)) if j.type == "prismatic"
                                       else j for j in model.tree))
    m = mj_model(mjcf(tilted, ref={"shoulder": 0.4, "slide": 0.05}))
    data = mujoco.MjData(m)
    slide, carriage, arm = m.joint("slide"), m.body("carriage").id, m.body("arm").id
    for qpos in ([0.4, 0.05, 0.0], [-1.1, 0.0, 0.7], [2.0, 0.3, -0.2]):
        data.qpos[:] = qpos
        mujoco.mj_kinematics(m, data)
        a = 2 * math.atan2(data.xquat[arm, 3], data.xquat[arm, 0])
        u = [0.6 * math.cos(a) - 0.8 * math.sin(a), 0.6 * math.sin(a) + 0.8 * math.cos(a), 0.0]
        np.testing.assert_allclose(data.xaxis[slide.id], u, rtol=0, atol=1e-15)
        before = data.xpos[carriage].copy()
        data.qpos[slide.qposadr[0]] += 0.2
        mujoco.mj_kinematics(m, data)
        np.testing.assert_allclose(data.xpos[carriage] - before, 0.2 * np.array(u), rtol=0,
                                   atol=1e-15)


def test_two_rotors_on_one_body_both_add_to_its_inertia():
    """The 2-DOF arm with its welded motor mass turned into a second driven elbow: link1 then
    carries both elbows' stators, and its inertia takes both rotors."""
    model = quiet(from_robot, load("actuated_2dof"), drives=True)
    weld = next(j for j in model.tree if j.type == "weld")
    elbow = replace(weld, type="revolute")
    d2 = model.drives[1]
    d3 = replace(d2, joint=elbow.name, rotor_inertia=7e-7)
    y = replace(model, tree=tuple(elbow if j is weld else j for j in model.tree),
                drives=(*model.drives, d3))
    m = mj_model(mjcf(y, viewer=True))
    izz = model.bodies["link1"].izz_kg_m2 + d2.rotor_inertia + 7e-7
    np.testing.assert_array_equal(m.body("link1").inertia, [izz / 2, izz / 2, izz])


def test_rotors_on_moving_links_differ_by_the_documented_coupling(rng):
    """The geared RPR arm (fc = 0): the boom's screw motor sits on the sleeve and the wrist's
    motor on the boom, both turned by the shoulder. MuJoCo's torques are ours less
    N J_m qdd_shoulder at that joint and N J_m qdd_joint at the shoulder, each coupling
    N J_m from the parameters, as the header says."""
    robot = rigid(load("rpr_geared"))
    p = robot.parameters
    ce, cw = p["gear_extend"] * p["jm_extend"], p["gear_wrist"] * p["jm_wrist"]
    q, qd, qdd = random_states(rng, 20, 3)
    ours = robot.tree_inverse_dynamics(q, qd, qdd)
    documented = ours - np.column_stack([ce * qdd[:, 1] + cw * qdd[:, 2], ce * qdd[:, 0],
                                         cw * qdd[:, 0]])
    xml = quiet(to_mjcf, robot)
    theirs = mj_inverse(mj_model(xml), robot, q, qd, qdd)
    assert rel_err(theirs, documented) < GATE
    assert rel_err(theirs, ours) > 1e-4  # the coupling is real
    drive = comment(xml)[-1]
    assert f"coupling N J_m = {ce!r} kg*m^2 between extend" in drive
    assert f"coupling N J_m = {cw!r} kg*m^2 between wrist" in drive


def test_laid_out_anywhere_qpos_stays_q(rng):
    """``ref``: the bodies laid out at any pose (revolute and prismatic), MuJoCo's reset state
    is that pose and mj_inverse still gives ours at q."""
    robot = load("rotated_slider")
    model = from_robot(robot)
    ref = dict(zip(robot.coordinates, (0.7, -0.15, 1.9)))
    m = mj_model(mjcf(model, ref=ref))
    np.testing.assert_array_equal(m.qpos0, [ref[c] for c in robot.coordinates])
    q, qd, qdd = random_states(rng, 10, robot.n)
    assert rel_err(mj_inverse(m, robot, q, qd, qdd),
                   robot.tree_inverse_dynamics(q, qd, qdd)) < GATE
    data = mujoco.MjData(m)  # the slider's body moved 0.15 m back along its rail
    mujoco.mj_forward(m, data)
    frames = robot.frames(np.array([list(ref.values())]))[0]
    for i, body in enumerate(robot.body_names):
        np.testing.assert_allclose(data.xpos[m.body(body).id][:2], frames[i, :2], atol=1e-14)


# -- MuJoCo's compiled model against the parameters and the drive train ----------------------

def test_masses_inertias_and_stators_read_back():
    """Every body's mass, centre of gravity and inertia (izz/2, izz/2, izz); a rotor's J_m
    added to the body carrying its stator (the elbow's motor on link1); a welded point mass
    keeps izz = 0."""
    robot = load("actuated_2dof")
    p = robot.parameters
    m = mj_model(quiet(to_mjcf, robot))
    for body in robot.body_names:
        b = m.body(body)
        izz = p[f"izz_{body}"] + (p["jm_joint2"] if body == "link1" else 0.0)
        assert b.mass[0] == p[f"m_{body}"]
        np.testing.assert_array_equal(b.inertia, [izz / 2, izz / 2, izz])
        np.testing.assert_array_equal(b.ipos, [p.get(f"cgx_{body}", 0.0), 0.0, 0.0])
    assert m.body("motor2").inertia[2] == 0.0
    ideal = mj_model(quiet(to_mjcf, robot, ideal=True))
    assert ideal.body("link1").inertia[2] == p["izz_link1"]  # the ideal machine: no rotor


def test_the_drive_train_read_back():
    """armature N^2 J_m, damping b, frictionloss c per joint; the motors' gear N, the motor
    torque limit as ctrlrange and the joint's over N as forcerange (MuJoCo clips the
    actuator's force before its gear); the ideal machine none of them."""
    robot = load("rpr_geared")
    p = robot.parameters
    m = mj_model(quiet(to_mjcf, robot))
    for c in robot.coordinates:
        dof = m.joint(c).dofadr[0]
        assert m.dof_armature[dof] == p[f"gear_{c}"] ** 2 * p[f"jm_{c}"]
        assert m.dof_damping[dof] == p[f"fv_{c}"]
        assert m.dof_frictionloss[dof] == p[f"fc_{c}"]
        assert m.actuator(c).gear[0] == p[f"gear_{c}"]
        assert m.actuator(c).trnid[0] == m.joint(c).id
    assert m.nu == 3 and not m.actuator_ctrllimited.any() and not m.actuator_forcelimited.any()
    arm = load("actuated_2dof")
    m = mj_model(quiet(to_mjcf, arm))
    j1, j2 = m.actuator("joint1"), m.actuator("joint2")
    assert (j1.gear[0], j2.gear[0]) == (50.0, 30.0)
    assert j1.ctrllimited[0] and tuple(j1.ctrlrange) == (-0.02, 0.02)
    assert j1.forcelimited[0] and tuple(j1.forcerange) == (-0.8 / 50, 0.8 / 50)
    assert not j2.ctrllimited[0] and not j2.forcelimited[0]
    assert m.dof_frictionloss[m.joint("joint2").dofadr[0]] == 0.0  # no friction given
    for r in (robot, arm):
        ideal = mj_model(quiet(to_mjcf, r, ideal=True))
        assert not ideal.dof_armature.any() and not ideal.dof_damping.any()
        assert not ideal.dof_frictionloss.any() and (ideal.actuator_gear[:, 0] == 1.0).all()
        assert not ideal.actuator_ctrllimited.any() and not ideal.actuator_forcelimited.any()
        assert ideal.nu == len(r.actuated)


def test_a_joint_limit_alone_is_a_force_range():
    """A drive with a joint-side limit and no motor limit: forcerange only, and what MuJoCo
    applies at the joint under any command is at most that limit (a trial: the joint-side
    limit written as forcerange let the joint take 50 times it through the gear)."""
    model = quiet(from_robot, load("actuated_2dof"), drives=True)
    d1 = replace(model.drives[0], motor_torque_limit=None, torque_limit=1.5)
    m = mj_model(mjcf(replace(model, drives=(d1, *model.drives[1:])), viewer=True))
    a = m.actuator("joint1")
    assert not a.ctrllimited[0] and a.forcelimited[0] and tuple(a.forcerange) == (-0.03, 0.03)
    data = mujoco.MjData(m)
    for command, applied in ((1e3, 1.5), (-1e3, -1.5), (0.01, 0.5)):  # motor N*m, joint N*m
        data.ctrl[:] = 0.0
        data.ctrl[a.id] = command
        mujoco.mj_forward(m, data)
        assert data.qfrc_actuator[m.joint("joint1").dofadr[0]] == pytest.approx(applied,
                                                                                rel=1e-12)


def test_point_masses_get_the_documented_inertia():
    """A moving point mass: izz = 1e-12 m size^2 (size: the drawn pose's span), at least
    1e-14 kg*m^2; the bare model keeps the exact 0, the header names the bodies."""
    robot = load("cart_pole_incline")
    for r in (robot, robot.with_parameters(m_pole=1e-4)):  # 3e-17: the floor
        xml = to_mjcf(r)
        m = mj_model(xml)
        _, size, _ = drawn_span(m)
        for body in ("cart", "pole"):
            mass = r.parameters[f"m_{body}"]
            izz = m.body(body).inertia[2]
            assert math.isclose(izz, max(1e-12 * mass * size**2, 1e-14), rel_tol=1e-12)
            assert export_mjcf.point_mass_inertia(from_robot(r), mass) == izz
        assert ("Point masses on their own joint (cart, pole): izz = 0 raised to 1e-12 m size^2 "
                "(at least 1e-14 kg*m^2), since MuJoCo refuses a moving body without inertia."
                ) in comment(xml)
    assert math.isclose(izz, 1e-14, rel_tol=1e-15)
    bare = mjcf(from_description(load_description(robot.description_file)))
    assert bare.count('diaginertia="0.0 0.0 0.0"') == 2  # the exact model, as benchmarks want


def test_options_gravity_and_loop_softness():
    robot = ps.load("five_bar_type1").with_parameters(g=3.7)
    xml = to_mjcf(robot)
    m = mj_model(xml)
    assert (m.opt.timestep, m.opt.integrator) == (1e-3, mujoco.mjtIntegrator.mjINT_RK4)
    np.testing.assert_array_equal(m.opt.gravity, [0.0, -3.7, 0.0])
    np.testing.assert_array_equal(m.eq_solref[0], [2e-3, 1.0])
    np.testing.assert_array_equal(m.eq_solimp[0, :3], [0.9999, 0.9999, 0.001])
    assert (export_mjcf.USER_SOLREF, export_mjcf.USER_SOLIMP) == ((2e-3, 1.0),
                                                                  (0.9999, 0.9999, 0.001))
    assert m.opt.disableflags == 0 and m.neq == 1
    assert ("Closed chain: each cut joint (C) is an <equality><connect> of two sites. MuJoCo's "
            "constraints are soft: solref 0.002 1.0, solimp 0.9999 0.9999 0.001 here; a smaller "
            "timestep and solref closes the loops tighter.") in comment(xml)
    tilted = load("bent_arm")
    g = mj_model(to_mjcf(tilted)).opt.gravity  # the description's gravity, [1.2, -9.7] m/s^2
    np.testing.assert_allclose(g, [1.2, -9.7, 0.0], rtol=1e-15, atol=0)


def test_the_viewer_s_camera_statistic_and_geoms_follow_the_drawn_pose():
    """The camera looks down from 2 spans above the centre of the drawn pose, the statistic is
    that centre and span, capsules are 1 % of the span thick, spheres and sites 1.5 and 1 times
    that; one sphere per ground point and centre of gravity, one capsule per body point away
    from it; the loops' sites coincide in the drawn pose (the reset state)."""
    for name in ("five_bar_type1", "parallel_3rpr", "parallel_3rrr", "bent_arm"):
        # parallel_3rrr: taller than wide, reaching below the ground's frame (y < 0)
        robot = load(name)
        m = mj_model(to_mjcf(robot))
        centre, size, radius = drawn_span(m)
        assert math.isclose(m.stat.extent, size, rel_tol=1e-12)
        np.testing.assert_allclose(m.stat.center, [*centre, 0.0], rtol=0, atol=1e-12 * size)
        np.testing.assert_allclose(m.cam_pos[0], [*centre, 2 * size], rtol=0, atol=1e-12 * size)
        assert math.isclose(radius, 0.01 * size, rel_tol=1e-12)
        spheres = m.geom_type == mujoco.mjtGeom.mjGEOM_SPHERE
        np.testing.assert_allclose(m.geom_size[spheres, 0], 1.5 * radius, rtol=1e-15)
        if m.nsite:
            np.testing.assert_allclose(m.site_size[:, 0], radius, rtol=1e-15)
        desc = load_description(robot.description_file)
        world = m.body("world").id
        assert spheres[m.geom_bodyid == world].sum() == len(desc.bodies["ground"].points_m)
        for body in robot.body_names:
            b = desc.bodies[body]
            away = sum(math.hypot(x - b.cg_m[0], y - b.cg_m[1]) > 1e-9
                       for x, y in b.points_m.values())
            assert m.body(body).geomnum[0] == 1 + away, body
        data = mujoco.MjData(m)
        mujoco.mj_forward(m, data)
        for cut in robot.loops:
            gap = data.site(f"{cut}_a").xpos - data.site(f"{cut}_b").xpos
            assert np.linalg.norm(gap) < 1e-12


def test_a_point_on_the_centre_of_gravity_draws_no_capsule():
    """A point 1e-10 m from the centre of gravity gets no capsule (MuJoCo refuses one that
    short: "fromto points too close")."""
    model = from_robot(ps.load("serial_2dof"))
    link = model.bodies["link1"]
    near = replace(link, points_m={**link.points_m, "N": (link.cg_m[0] + 1e-10, link.cg_m[1])})
    m = mj_model(mjcf(replace(model, bodies={**model.bodies, "link1": near}), viewer=True))
    assert m.body("link1").geomnum[0] == 1 + len(link.points_m)  # as without the point
    # off the link's axis: the centre of gravity at y = 0.01; a point straight above it gets a
    # capsule, one 1e-10 m beside it none, one exactly 1e-9 m from a centre at 0 none either
    off = replace(link, cg_m=(0.03, 0.01),
                  points_m={**link.points_m, "A": (0.03, 0.06), "N": (0.03 + 1e-10, 0.01)})
    link2 = model.bodies["link2"]  # CS1 at (0, 0), CS2 at (0.1, 0)
    at0 = replace(link2, cg_m=(0.0, 0.0), points_m={**link2.points_m, "E": (1e-9, 0.0)})
    m = mj_model(mjcf(replace(model, bodies={**model.bodies, "link1": off, "link2": at0}),
                      viewer=True))
    assert m.body("link1").geomnum[0] == 1 + 3  # CS1, CS2, A
    assert m.body("link2").geomnum[0] == 1 + 1  # CS2


def test_the_nesting_order_in_the_header_is_mujoco_s_qpos_order():
    """The header names the joints depth-first from ground, MuJoCo's qpos order: checked on a
    tree listed breadth-first (both chains' first joints before their second ones)."""
    model = from_robot(ps.load("five_bar_type1"))
    by = {j.name: j for j in model.tree}
    shuffled = replace(model, tree=tuple(by[k] for k in ("A", "E", "B", "D")))
    xml = mjcf(shuffled, viewer=True, loops=True, solref=(0.01, 1.0), solimp=(0.9, 0.95, 0.001))
    m = mj_model(xml)
    order = [m.joint(i).name for i in range(m.njnt)]
    assert order == ["A", "B", "E", "D"]
    assert f"depth-first from ground: {', '.join(order)})." in " ".join(comment(xml))
    assert [j.name for j in shuffled.depth_first()] == order
    assert {k: [j.name for j in v] for k, v in shuffled.children().items()} == {
        "ground": ["A", "E"], "L_Link1": ["B"], "R_Link1": ["D"]}


def test_a_prismatic_cut_is_refused():
    model = from_robot(ps.load("slider_crank"))
    cut = replace(model.cuts[0], type="prismatic")
    broken = replace(model, cuts=(cut,))
    mjcf(broken)  # without the loops: nothing to refuse
    with pytest.raises(InputError) as err:
        mjcf(broken, loops=True)
    assert str(err.value) == (f"slider_crank: cut joint {cut.name} is prismatic; only revolute "
                              "cut joints have an MJCF equality (connect)")


def test_a_loop_cut_at_the_ground_has_its_site_on_the_world(tmp_path):
    """The 5-bar cut at its ground joint E instead of C (D turned round): E's site on the world
    body at ground point E, the other on R_Link1; laid out at the drawn relative angles, the
    two coincide."""
    text = (ROBOTS / "five_bar_type1.toml").read_text()
    for old, new in (('child = "R_Link1.CS1"\nactuated = true',
                      'child = "R_Link1.CS1"\nactuated = false\ncloses_loop = true'),
                     ("actuated = false\ncloses_loop = true  #", "actuated = true  #"),
                     ('parent = "R_Link1.CS2"\nchild = "R_Link2.CS1"',
                      'parent = "R_Link2.CS1"\nchild = "R_Link1.CS2"')):
        assert old in text
        text = text.replace(old, new)
    (tmp_path / "cut_at_e.toml").write_text(text)
    model = from_description(load_description(tmp_path / "cut_at_e.toml"))
    assert [(j.name, j.parent) for j in model.cuts] == [("E", "ground")]
    b = model.bodies
    ref = {j.name: b[j.child].drawn_angle_rad - b[j.parent].drawn_angle_rad for j in model.tree}
    xml = mjcf(model, loops=True, ref=ref, viewer=True, solref=(0.01, 1.0),
               solimp=(0.9, 0.95, 0.001))
    assert_clean(xml)
    m = mj_model(xml)
    assert m.site("E_a").bodyid[0] == m.body("world").id
    np.testing.assert_array_equal(m.site("E_a").pos, [*b["ground"].points_m["E"], 0.0])
    assert m.site("E_b").bodyid[0] == m.body("R_Link1").id
    data = mujoco.MjData(m)
    mujoco.mj_forward(m, data)
    np.testing.assert_allclose(data.site("E_b").xpos, data.site("E_a").xpos, rtol=0, atol=1e-12)


def test_several_cuts_are_named_in_the_header():
    xml = to_mjcf(ps.load("parallel_3rrr"))
    assert any(line.startswith("Closed chain: each cut joint (B2, B3) is an <equality>")
               for line in comment(xml))
    assert mj_model(xml).neq == 2


@pytest.mark.parametrize("name", ["five_bar_type1", "parallel_3rrr", "rpr_geared", "bent_arm"])
def test_the_file_is_clean_xml(name):  # parallel_3rrr: two sites on its platform
    """Elements only (no stray text between them), no empty sections, and laid out for a
    reader: the worldbody's children aligned, each nested body 2 spaces in from its parent."""
    robot = load(name)
    for xml in (quiet(to_mjcf, robot), quiet(to_mjcf, robot, ideal=True),
                mjcf(from_description(load_description(robot.description_file)))):
        assert_clean(xml)
        root = ET.fromstring(xml)
        for section in ("equality", "actuator"):
            assert all(len(el) for el in root.iter(section)), section
        lines = xml.split("\n")
        start = lines.index("  <worldbody>")
        stop = lines.index("  </worldbody>")
        depth, top = 0, set()
        for line in lines[start + 1:stop]:
            indent = len(line) - len(line.lstrip(" "))
            if line.lstrip().startswith("</body>"):
                depth -= 1
                assert indent == 6 + 2 * depth, line
                continue
            assert indent == 6 + 2 * depth, line
            if depth == 0:
                top.add(indent)
            depth += line.lstrip().startswith("<body ")
        assert depth == 0 and top == {6}
        assert lines[0] in ("<!--", f'<mujoco model="{robot.name}">')
        assert lines[-2:] == ["</mujoco>", ""]


# -- the benchmarks' bare model ---------------------------------------------------------------

@pytest.mark.parametrize("name", ["serial_rpr", "slider_crank"])
def test_the_bare_model_is_the_description_s_dynamics(name, rng):
    """``mjcf(from_description(desc))``: the same tree as the user file (masses, inertias),
    the description's values, no geoms, motors, camera or comment; loops only when asked, with
    MuJoCo's own softness unless given."""
    robot = ps.load(name)
    desc = load_description(robot.description_file)
    xml = mjcf(from_description(desc))
    assert "<!--" not in xml and "size=" not in xml
    m = mj_model(xml)
    user = mj_model(to_mjcf(robot))
    assert (m.ngeom, m.nu, m.ncam, m.neq, m.opt.timestep) == (0, 0, 0, 0, 1e-3)
    assert not m.qpos0.any()  # laid out at q = 0, MuJoCo's reset state
    assert_frames_are_ours(m, robot, np.zeros((1, robot.n)))
    for field in ("body_mass", "body_inertia", "body_ipos"):  # laid out at q = 0: other pos
        np.testing.assert_array_equal(getattr(m, field), getattr(user, field), err_msg=field)
    q, qd, qdd = random_states(rng, 10, robot.n)
    assert rel_err(mj_inverse(m, robot, q, qd, qdd, equality=False),
                   robot.tree_inverse_dynamics(q, qd, qdd)) < GATE
    if robot.loops:
        soft = mj_model(mjcf(from_description(desc), loops=True))
        default = mj_model("<mujoco><worldbody><site name='a'/><site name='b'/></worldbody>"
                           "<equality><connect site1='a' site2='b'/></equality></mujoco>")
        np.testing.assert_array_equal(soft.eq_solref, default.eq_solref)
        np.testing.assert_array_equal(soft.eq_solimp, default.eq_solimp)
        np.testing.assert_array_equal(soft.site_size, default.site_size[:1].repeat(2, axis=0))
        tight = mj_model(mjcf(from_description(desc), loops=True, timestep=2e-4,
                              solref=(4e-4, 1.0), solimp=(0.99, 0.999, 0.002)))
        assert tight.opt.timestep == 2e-4 and tight.neq == 1
        np.testing.assert_array_equal(tight.eq_solref[0], [4e-4, 1.0])
        np.testing.assert_array_equal(tight.eq_solimp[0, :3], [0.99, 0.999, 0.002])


# -- export_model: the robot's values, a second reading, edited folders -----------------------

@pytest.mark.parametrize("name", ["serial_rpr", "slider_crank", "five_bar_type2",
                                  "parallel_3rpr", "serial_3dof"])
def test_from_robot_is_from_description_for_an_unchanged_robot(name):
    robot = ps.load(name)
    a = from_robot(robot)
    b = from_description(load_description(robot.description_file))
    assert a.bodies == b.bodies and a.tree == b.tree and a.cuts == b.cuts
    assert a.offsets_m == pytest.approx(b.offsets_m, rel=1e-15, abs=0)
    assert a.gravity_m_s2 == pytest.approx(b.gravity_m_s2, rel=1e-15, abs=0)
    assert a.coordinates == b.coordinates == robot.coordinates
    assert a.actuated == b.actuated == tuple(robot.coordinates[i] for i in robot.actuated)
    assert a.source == b.source == f"{name}.toml" and b.input_hash == "" and a.changed == ()
    assert a.name == b.name == name and a.title == b.title == robot.title
    assert a.total_mass_kg == math.fsum(v for k, v in robot.parameters.items()
                                        if k.startswith("m_"))
    assert a.span_m() == b.span_m()


def test_rel_angle_is_the_drawn_turn_between_the_frames(rng):
    """A weld or a slider keeps its drawn relative angle; the generated frames say which."""
    for name, joint, parent, child in (("bent_arm", "weld_bracket", "link1", "bracket"),
                                       ("rotated_slider", "slide", "arm", "carriage")):
        robot = load(name)
        model = from_robot(robot)
        j = next(j for j in model.tree if j.name == joint)
        frames = robot.frames(rng.uniform(-3, 3, (5, robot.n)))
        i, k = robot.body_names.index(parent), robot.body_names.index(child)
        turn = np.angle(np.exp(1j * (frames[:, k, 2] - frames[:, i, 2])))
        np.testing.assert_allclose(turn, model.rel_angle(j), rtol=0, atol=1e-14)
        assert abs(model.rel_angle(j)) > 0.1
    hinge = next(j for j in model.tree if j.type == "revolute")
    assert model.rel_angle(hinge) == 0.0


def test_a_changed_robot_s_parameters_reach_the_model():
    base = ps.load("serial_rpr")
    robot = base.with_parameters(m_boom=2.0, izz_wrist=0.003, cgx_sleeve=0.2, px_wrist_T=0.3,
                                 s0_extend=0.25, g=3.7)
    model = from_robot(robot)
    assert model.bodies["boom"].mass_kg == 2.0 and model.bodies["wrist"].izz_kg_m2 == 0.003
    assert model.bodies["sleeve"].cg_m == (0.2, 0.0)
    assert model.bodies["wrist"].points_m["T"] == (0.3, 0.0)
    assert model.offsets_m == {"extend": 0.25} and model.gravity_m_s2 == (0.0, -3.7)
    assert model.changed == ("g = 3.7 m/s^2 (description: 9.81)",  # in parameter order
                             "cgx_sleeve = 0.2 m (description: 0.25)",
                             "m_boom = 2.0 kg (description: 1.2)",
                             "izz_wrist = 0.003 kg*m^2 (description: 0.002)",
                             "px_wrist_T = 0.3 m (description: 0.2)",
                             "s0_extend = 0.25 m (description: 0.3)")
    assert ("Parameters changed from the description: " + "; ".join(model.changed)
            ) in comment(to_mjcf(robot))
    assert not any(line.startswith("Parameters changed") for line in comment(to_mjcf(base)))


def copy_folder(robot, tmp_path) -> Path:
    folder = tmp_path / robot.name
    shutil.copytree(robot.library.folder, folder)
    return folder


def test_a_folder_without_its_description_is_refused(tmp_path):
    folder = copy_folder(load("cart_pole_incline"), tmp_path)
    (folder / "description.toml").unlink()
    with pytest.raises(InputError) as err:
        to_mjcf(ps.load(folder))
    assert str(err.value) == (f"cart_pole_incline: no description at hand to export it (its "
                              f"generated folder {folder} has no description.toml): export it "
                              "from its description file ROBOT.toml")


@pytest.mark.parametrize(("old", "new"), [(r'\bhinge\b', "pivot"),  # a joint: other q
                                          (r"\bpole\b", "rod")])  # a body: other parameters
def test_a_folder_whose_description_changed_is_refused(old, new, tmp_path):
    folder = copy_folder(load("cart_pole_incline"), tmp_path)
    desc = folder / "description.toml"
    desc.write_text(re.sub(old, new, desc.read_text()))
    with pytest.raises(LibraryError) as err:
        to_mjcf(ps.load(folder))
    assert str(err.value) == (f"cart_pole_incline: its description {desc} no longer matches its "
                              f"generated code in {folder} (other parameters or joints): "
                              "re-derive it (`make derive`, or `planar-sym derive` for your own "
                              "robot)")


@pytest.mark.parametrize("name", ["bent_arm", "horizontal_2dof"])
def test_an_old_manifest_takes_gravity_s_direction_from_the_description(name, tmp_path):
    robot = ps.load(TEST_ROBOTS / f"{name}.toml")
    folder = copy_folder(robot, tmp_path)
    manifest = json.loads((folder / "manifest.json").read_text())
    for key in ("gravity_direction", "input"):  # neither, as long ago
        del manifest[key]
    (folder / "manifest.json").write_text(json.dumps(manifest))
    old = ps.load(folder).with_parameters(g=5.0)
    assert from_robot(old).source == "description.toml"  # the file at hand
    gx, gy = load_description(robot.description_file).gravity_m_s2
    norm = math.hypot(gx, gy)
    expected = (5.0 * gx / norm, 5.0 * gy / norm) if norm else (0.0, 0.0)
    assert from_robot(old).gravity_m_s2 == pytest.approx(expected, rel=1e-15, abs=0)
    assert from_robot(old).gravity_m_s2 == pytest.approx(
        from_robot(robot.with_parameters(g=5.0)).gravity_m_s2, rel=1e-15, abs=0)


def test_the_manifest_s_gravity_direction_wins(tmp_path, rng):
    """The generated code's gravity direction (its manifest) is what the equations use: a
    description copy that says otherwise does not change the export."""
    robot = load("bent_arm")
    folder = copy_folder(robot, tmp_path)
    desc = folder / "description.toml"
    desc.write_text(desc.read_text().replace("gravity = [1.2, -9.7]", "gravity = [1.0, 0.0]"))
    moved = ps.load(folder)
    assert load_description(moved.description_file).gravity_m_s2 == (1.0, 0.0)
    ux, uy = robot.library.manifest["gravity_direction"]
    g = moved.parameters["g"]
    np.testing.assert_array_equal(mj_model(to_mjcf(moved)).opt.gravity, [g * ux, g * uy, 0.0])
    q, qd, qdd = random_states(rng, 5, robot.n)
    assert rel_err(mj_inverse(mj_model(to_mjcf(moved)), moved, q, qd, qdd),
                   robot.tree_inverse_dynamics(q, qd, qdd)) < GATE


# -- warnings, header, numbers ----------------------------------------------------------------

def test_the_ideal_machine_names_what_it_leaves_out():
    robot = load("rpr_geared").with_parameters(fc_wrist=0.0)
    with pytest.warns(RuntimeWarning) as rec:
        xml = to_mjcf(robot, ideal=True)
    assert len(rec) == 1
    left = ("jm_shoulder, fv_shoulder, fc_shoulder, jm_extend, fv_extend, fc_extend, jm_wrist, "
            "fv_wrist")  # fc_wrist = 0: nothing left out
    assert str(rec[0].message) == (f"rpr_geared: actuator figures {left} are not exported "
                                   "(--ideal: the ideal machine, as asked): the file holds the "
                                   "rigid bodies only")
    assert comment(xml)[-1] == (f"NOT exported (actuator models, no exact equivalent here): "
                                f"{', '.join(left.split(', '))}; the file holds the rigid bodies "
                                "only.")
    assert comment(xml)[-2] == ("Motors: one per actuated joint, ctrl = joint torque (N*m) or "
                                "force (N), unlimited (the ideal machine: no rotors, friction or "
                                "gears).")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        to_mjcf(ps.load("serial_2dof"), ideal=True)  # nothing to leave out: no warning
        to_mjcf(ps.load("serial_2dof"))


def test_the_drive_train_names_what_is_not_exact():
    robot = load("rpr_geared").with_parameters(fc_shoulder=0.0, jm_wrist=0.0)
    with pytest.warns(RuntimeWarning) as rec:
        xml = to_mjcf(robot)
    assert len(rec) == 1
    p = robot.parameters
    said = [("jm_extend: the rotor turns with sleeve; its coupling N J_m = "
            f"{p['gear_extend'] * p['jm_extend']!r} kg*m^2 between extend and the joints that "
            "turn sleeve is not exported (armature is diagonal): MuJoCo's torques differ by "
            "N J_m alpha_sleeve at extend and N J_m qdd_extend at each of those joints"),
            ("fc_extend: Coulomb friction 3.0 is exported as MuJoCo's frictionloss (dry friction, "
            "a soft constraint), not as the smooth c tanh(qd / 0.01) of planar-sym"),
            ("fc_wrist: Coulomb friction 0.1 is exported as MuJoCo's frictionloss (dry friction, "
            "a soft constraint), not as the smooth c tanh(qd / 0.01) of planar-sym")]
    # the shoulder's rotor is on the ground, the wrist has none: nothing to say about them
    assert str(rec[0].message) == "rpr_geared: " + "; ".join(said)
    assert comment(xml)[-1] == "Drive train, NOT exact here: " + "; ".join(said) + "."
    assert comment(xml)[-2] == (
        "Motors: one per actuated joint, gear = the gear ratio N, so ctrl = motor torque (N*m); "
        "ctrlrange = the motor torque limit, forcerange = the joint-side limit / N where given "
        "(MuJoCo clips the motor-side force before the gear). "
        "Drive train: armature = N^2 J_m (rotor), J_m added to the inertia of the body carrying "
        "the stator, damping = viscous friction, frictionloss = Coulomb friction.")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # rotors on the ground, no Coulomb friction: exact
        to_mjcf(robot.with_parameters(jm_extend=0.0, fc_extend=0.0, fc_wrist=0.0))


def test_the_header_word_for_word():
    robot = load("cart_pole_incline")
    xml = to_mjcf(robot)
    total = math.fsum(v for k, v in robot.parameters.items() if k.startswith("m_"))
    assert comment(xml) == [
        ("Written by planar-sym export (MJCF): robot cart_pole_incline, Cart-pole on a 20 deg "
        "rail, point masses (test robot)"),
        (f"description: cart_pole_incline.toml; generated code input hash "
        f"{robot.library.manifest['input_hash']}"),
        ("Values are SI: m, kg, kg*m^2, rad, s, m/s^2 (torques N*m, forces N), written with full "
        "float precision (repr)."),
        f"Total mass {total!r} kg; coordinates (our q order): rail, hinge; actuated: rail, hinge.",
        ("Planar: bodies move in the plane z = 0; gravity [gx, gy, 0] is in the file (<option "
        "gravity>). Body frames are planar-sym's, so qpos = q joint by joint (match joints by "
        "name: qpos follows the nesting, depth-first from ground: rail, hinge)."),
        ("Inertia: diaginertia izz/2, izz/2, izz (ixx, iyy never enter planar dynamics). Geoms "
        "are visual only (density 0, no contacts): mass and inertia come from <inertial>."),
        ("Motors: one per actuated joint, gear = the gear ratio N, so ctrl = motor torque (N*m); "
        "ctrlrange = the motor torque limit, forcerange = the joint-side limit / N where given "
        "(MuJoCo clips the motor-side force before the gear). "
        "Drive train: armature = N^2 J_m (rotor), J_m added to the inertia of the body carrying "
        "the stator, damping = viscous friction, frictionloss = Coulomb friction."),
        ("Point masses on their own joint (cart, pole): izz = 0 raised to 1e-12 m size^2 (at "
        "least 1e-14 kg*m^2), since MuJoCo refuses a moving body without inertia.")]
    assert xml.startswith("<!--\n  Written by") and "\n-->\n<mujoco " in xml


def test_header_fallbacks_and_no_double_dash():
    """No source, no hash, nothing actuated; ``--`` (which ends an XML comment) broken up."""
    model = replace(from_robot(ps.load("serial_2dof")), title="arm -- v2", source="",
                    input_hash="", actuated=(), not_exported=("jm_x",))
    lines = header(model, "X", ["extra -- line"]).split("\n")
    assert lines[0] == "  Written by planar-sym export (X): robot serial_2dof, arm - - v2"
    assert lines[1] == "  description: (none); generated code input hash (none)"
    assert lines[3].endswith("; actuated: none.")
    assert lines[4:] == ["  extra - - line", ("  NOT exported (actuator models, no exact "
                         "equivalent here): jm_x; the file holds the rigid bodies only.")]
    xml = mjcf(model, viewer=True)
    assert mj_model(xml).nu == 0 and "<actuator>" not in xml  # and MuJoCo reads the comment
    desc = replace(load_description(ps.load("serial_2dof").description_file), path=None)
    assert from_description(desc).source == ""


def test_numbers_round_trip_exactly():
    xs = (0.1, 1 / 3, -2.5e-17, 7, 1e300)
    assert numbers(*xs) == "0.1 0.3333333333333333 -2.5e-17 7.0 1e+300"
    assert [float(s) for s in numbers(*xs).split(" ")] == list(xs)


def test_span_of_a_single_point_is_one_metre():
    """All points in one place: the span would be 0; the camera then uses 1 m."""
    model = from_robot(ps.load("serial_2dof"))
    one = {k: replace(b, points_m={p: (0.0, 0.0) for p in b.points_m}, cg_m=(0.0, 0.0),
                      drawn_origin_m=(0.0, 0.0)) for k, b in model.bodies.items()}
    assert replace(model, bodies=one).span_m() == ((0.0, 0.0), 1.0)
    assert export_model.ACTUATOR_PREFIXES == ("jm_", "fv_", "fc_")




def test_a_rotor_on_a_body_that_only_slides_is_exported_whole(tmp_path, rng):
    """j1's stator rides the cart, which cannot turn: no coupling is missing (the export said
    one was, in its warning and the file's header), and MuJoCo's inverse dynamics differs from
    ours only by j2's coupling N J_m (its stator on link1, turned by j1), as documented."""
    robot = ps.load(str(TEST_ROBOTS / "geared_cart_arm.toml"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        xml = to_mjcf(robot)
    said = " ".join(str(w.message) for w in caught)
    assert "jm_j1" not in said and "the rotor turns with cart" not in xml
    assert "jm_j2: the rotor turns with link1" in said
    c2 = robot.parameters["gear_j2"] * robot.parameters["jm_j2"]
    q, qd, qdd = random_states(rng, 10, 3)
    ours = robot.tree_inverse_dynamics(q, qd, qdd)
    documented = ours - np.column_stack([np.zeros(len(q)), c2 * qdd[:, 2], c2 * qdd[:, 1]])
    assert rel_err(mj_inverse(mj_model(xml), robot, q, qd, qdd), documented) < GATE


def test_urdf_carries_friction_and_the_actuators_limits(tmp_path):
    """A trial: URDF's <dynamics damping friction> and <limit effort velocity> were said to have
    no place, and friction and limits were dropped. The geared arm's joint 1 (fv 0.001 N*m*s,
    fc 0.005 N*m, motor 0.01 N*m x N 50 = 0.5 N*m, 8000 rpm / 50 = 16.755 rad/s) and joint 2
    (0.5 N*m, no speed limit), read back by Pinocchio's own URDF parser; the rotors are named
    as not exported; --ideal writes neither."""
    import pinocchio as pin

    robot = ps.load(ROOT / "examples" / "serial_2dof_geared.toml")
    with pytest.warns(RuntimeWarning, match=r"jm_joint1: URDF has no rotor"):
        path = ps.export(robot, tmp_path / "geared.urdf")
    model = pin.buildModelFromUrdf(str(path))
    ids = [model.joints[model.getJointId(n)].idx_v for n in ("joint1", "joint2")]
    np.testing.assert_array_equal(model.damping[ids], [0.001, 0.0])
    np.testing.assert_array_equal(model.friction[ids], [0.005, 0.0])
    np.testing.assert_allclose(model.effortLimit[ids], [0.01 * 50, 0.01 * 50], rtol=1e-15)
    np.testing.assert_allclose(model.velocityLimit[ids],
                               [8000 * 2 * math.pi / 60 / 50, 1e9], rtol=1e-15)
    text = path.read_text()
    assert "Drive train, NOT exact here: jm_joint1: URDF has no rotor" in text
    with pytest.warns(RuntimeWarning, match="--ideal"):
        ideal = ps.export(robot, tmp_path / "ideal.urdf", ideal=True).read_text()
    body = ideal.split("-->", 1)[1]  # the elements, after the header comment
    assert "<dynamics" not in body and "effort" not in body


def test_mjcf_says_the_motor_speed_limit_has_no_place():
    """A trial: MJCF dropped the motor's speed limit without a word."""
    robot = ps.load(ROOT / "examples" / "serial_2dof_geared.toml")
    with pytest.warns(RuntimeWarning, match=r"joint1: the motor's speed limit 8000 rpm has no "
                                             r"place in MJCF"):
        xml = to_mjcf(robot)
    assert "joint1: the motor's speed limit 8000 rpm has no place in MJCF" in xml


PRESS = """name = "press"
title = "Offset slider-crank press (a trial's): the ram's centre of gravity below its pin"
pose = "joints"
gravity = [0.0, -9.81]
[units]
length = "m"
mass = "kg"
inertia = "kg*m^2"
angle = "deg"
acceleration = "m/s^2"
[ground]
points = { O = [0.0, 0.0], G = [0.02, 0.0] }
[[bodies]]
name = "crank"
mass = 0.5
izz = 1.0e-4
cg = [0.025, 0.0]
points = { O = [0.0, 0.0], A = [0.05, 0.0] }
[[bodies]]
name = "rod"
mass = 1.0
izz = 0.0033333333
cg = [0.1, 0.0]
points = { A = [0.0, 0.0], B = [0.2, 0.0] }
[[bodies]]
name = "ram"
mass = 5.0
izz = 0.01
cg = [0.0, -0.05]
points = { B = [0.0, 0.0] }
[[joints]]
name = "O"
type = "revolute"
parent = "ground.O"
child = "crank.O"
actuated = true
angle = 60.0
[[joints]]
name = "A"
type = "revolute"
parent = "crank.A"
child = "rod.A"
actuated = false
angle = -151.0
[[joints]]
name = "slide"
type = "prismatic"
parent = "ground.G"
child = "ram.B"
axis = [0.0, 1.0]
actuated = false
displacement = -0.156
[[joints]]
name = "B"
type = "revolute"
parent = "rod.B"
child = "ram.B"
actuated = false
closes_loop = true
"""


def test_numbers_are_written_as_numbers_whatever_their_type(tmp_path):
    """A trial: on this press (the ram's centre of gravity the lowest point, placed through a
    slide's displacement) the drawn span came out as numpy floats, written with repr as
    ``extent="np.float64(0.25)"`` in 13 attributes; export said "wrote press.xml" and MuJoCo
    refused the file. Every number goes through ``export_model.numbers``: the file loads, and
    its extent is the drawn span."""
    path = tmp_path / "press.toml"
    path.write_text(PRESS)
    model = export_model.from_description(load_description(path))
    (cx, cy), size = model.span_m()
    xml = mjcf(model, viewer=True, solref=(0.02, 1.0), solimp=(0.9, 0.95, 0.001))
    assert "np." not in xml and "float64" not in xml
    m = mj_model(xml)
    assert m.stat.extent == float(size) and tuple(m.stat.center[:2]) == (float(cx), float(cy))
