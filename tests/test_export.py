"""``planar-sym export``: the written MJCF and URDF files, loaded from disk by MuJoCo and
Pinocchio, against planar-sym's own dynamics.

- trees (the built-in open chains, a prismatic tree, a tilted slider with point masses, a
  rotated weld): MuJoCo's ``mj_inverse`` on the MJCF file and Pinocchio's ``rnea`` on the URDF
  file give our ``tree_inverse_dynamics`` to ``GATE`` (1e-10, relative to each sample's torque
  scale: ``conftest.rel_err``) at random states, joints matched by name;
- a robot from ``with_parameters`` exports its own values (and they matter);
- closed chains (5-bar type 1, the four-bar example): released from rest on their loops,
  MuJoCo (soft ``connect`` constraints) follows ``planar_sym.simulate``: with the step and
  ``solref`` tightened to ``RELEASE_DT`` the agreement is about 4e-8 rad (5-bar) and 3e-9 rad
  (four-bar) over 0.5 s, the loops closed to 5e-10 m; with the file's own settings (1e-3 s)
  5e-4 and 5e-5 rad, loops closed to 1e-5 m;
- round trip: every file parses, with the right numbers of bodies, joints and loop
  constraints; each body's mass and inertia are the robot's parameters bit for bit (repr);
  the visual geoms change nothing (the file without them gives identical mass data and
  mj_inverse);
- the command line and its errors.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from conftest import ROOT, TEST_ROBOTS, random_states, rel_err

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.errors import InputError
from planar_sym.outputs.export import format_of, to_mjcf, to_urdf, write
from planar_sym.outputs.export_mjcf import USER_SOLIMP, USER_SOLREF, USER_TIMESTEP_S

GATE = 1e-10
TREES = ("serial_2dof", "serial_3dof", "serial_rpr")
#: derived test robots: a slider on a 20 deg rail with point masses, a rotated weld and tilted
#: gravity, a plain cart-pole; the four-bar and the geared arm from examples/
DERIVED = {"cart_pole_incline": TEST_ROBOTS / "cart_pole_incline.toml",
           "bent_arm": TEST_ROBOTS / "bent_arm.toml", "cart_pole": TEST_ROBOTS / "cart_pole.toml",
           "four_bar": ROOT / "examples" / "four_bar.toml",
           "serial_2dof_geared": ROOT / "examples" / "serial_2dof_geared.toml"}
#: closed-chain release: MuJoCo's step (s) and constraint softness for the comparison
RELEASE_DT = 1e-5
RELEASE_SOLREF = (2 * RELEASE_DT, 1.0)  # 2 steps: the least MuJoCo's refsafe allows
RELEASE_SOLIMP = (0.9999, 0.9999, 0.001)  # 0.9999: MuJoCo's largest impedance
RELEASE_T = 0.5  # s
#: measured max |q_mujoco - q_ours| (rad) over the release, and the bound asserted (about 2.5x)
RELEASE = {"five_bar_type1": (4.4e-8, 1e-7), "four_bar": (3.1e-9, 1e-8)}
#: the same with the file as written (USER_TIMESTEP_S, USER_SOLREF, USER_SOLIMP)
RELEASE_AS_WRITTEN = {"five_bar_type1": (4.6e-4, 1e-3), "four_bar": (4.8e-5, 1e-4)}


@pytest.fixture(scope="module")
def derived(tmp_path_factory):
    """The test and example robots, derived through the CLI (description.toml kept beside
    the code) and compiled into a private cache."""
    out = tmp_path_factory.mktemp("export_robots")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("PLANAR_SYM_CACHE", str(tmp_path_factory.mktemp("cache")))
        assert main(["derive", *map(str, DERIVED.values()), "--out", str(out), "--quiet"]) == 0
        robots = {name: ps.load(out / name) for name in DERIVED}
    return robots


def robot_of(name: str, derived) -> ps.Robot:
    return derived[name] if name in DERIVED else ps.load(name)


def gravity(robot) -> np.ndarray:
    """The robot's gravity (m/s^2) from its parameter g and its manifest's direction."""
    ux, uy = robot.library.manifest["gravity_direction"]
    return robot.parameters["g"] * np.array([ux, uy, 0.0])


def total_mass(robot) -> float:
    return math.fsum(v for k, v in robot.parameters.items() if k.startswith("m_"))


# -- MuJoCo and Pinocchio on the files ------------------------------------------------------

def mj_inverse(path, robot, q, qd, qdd) -> np.ndarray:
    """``mj_inverse`` of the MJCF file, in our coordinate order (joints matched by name)."""
    model = mujoco.MjModel.from_xml_path(str(path))
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


def pin_model(path, robot):
    model = pin.buildModelFromUrdf(str(path))
    model.gravity.linear = gravity(robot)  # URDF has no gravity: the engine's is set
    return model


def pin_rnea(path, robot, q, qd, qdd) -> np.ndarray:
    """``pinocchio.rnea`` of the URDF file, in our coordinate order: a continuous joint's
    configuration is (cos q, sin q), a prismatic joint's d."""
    model = pin_model(path, robot)
    data = model.createData()
    ids = [model.getJointId(c) for c in robot.coordinates]
    assert sorted(model.names[1:]) == sorted(robot.coordinates)
    out = np.empty_like(q)
    for k in range(len(q)):
        cq, v, a = pin.neutral(model), np.zeros(model.nv), np.zeros(model.nv)
        for i, jid in enumerate(ids):
            iq, iv, nq = model.idx_qs[jid], model.idx_vs[jid], model.nqs[jid]
            cq[iq:iq + nq] = (np.cos(q[k, i]), np.sin(q[k, i])) if nq == 2 else q[k, i]
            v[iv], a[iv] = qd[k, i], qdd[k, i]
        tau = pin.rnea(model, data, cq, v, a)
        out[k] = [tau[model.idx_vs[j]] for j in ids]
    return out


@pytest.mark.parametrize("name", TREES + ("cart_pole_incline", "bent_arm", "cart_pole"))
def test_tree_files_give_our_inverse_dynamics_in_mujoco_and_pinocchio(name, derived, tmp_path,
                                                                     rng, worst_errors):
    from conftest import record

    robot = robot_of(name, derived)
    mjcf, urdf = write(robot, tmp_path / "r.xml"), write(robot, tmp_path / "r.urdf")
    q, qd, qdd = random_states(rng, 50, robot.n)
    ours = robot.tree_inverse_dynamics(q, qd, qdd)
    e_mj = record(worst_errors, f"export mj_inverse {name}", rel_err(mj_inverse(mjcf, robot, q,
                                                                              qd, qdd), ours))
    e_pin = record(worst_errors, f"export pin.rnea {name}", rel_err(pin_rnea(urdf, robot, q,
                                                                             qd, qdd), ours))
    assert e_mj < GATE, e_mj
    assert e_pin < GATE, e_pin


def test_a_changed_robot_exports_its_own_values(tmp_path, rng):
    base = ps.load("serial_rpr")
    changed = base.with_parameters(m_boom=2.0, izz_wrist=0.003, cgx_sleeve=0.2, px_boom_W=0.6,
                                   s0_extend=0.25, g=3.7)
    q, qd, qdd = random_states(rng, 30, 3)
    ours, before = changed.tree_inverse_dynamics(q, qd, qdd), base.tree_inverse_dynamics(q, qd,
                                                                                          qdd)
    assert rel_err(before, ours) > 1e-2  # the change matters, so agreement below says something
    mjcf, urdf = write(changed, tmp_path / "c.xml"), write(changed, tmp_path / "c.urdf")
    assert rel_err(mj_inverse(mjcf, changed, q, qd, qdd), ours) < GATE
    assert rel_err(pin_rnea(urdf, changed, q, qd, qdd), ours) < GATE
    text = mjcf.read_text()
    assert "m_boom = 2.0 kg (description: 1.2)" in text and "g = 3.7" in text
    model = mujoco.MjModel.from_xml_path(str(mjcf))
    np.testing.assert_array_equal(model.opt.gravity, [0.0, -3.7, 0.0])


def test_the_ideal_machine_leaves_the_drive_train_out(derived, tmp_path, rng):
    """``ideal=True``: the geared arm's rotor inertia, friction and gears are not in the file
    (a warning names them): the file is the arm with those figures zero, and differs from the
    geared arm."""
    geared = derived["serial_2dof_geared"]
    with pytest.warns(RuntimeWarning, match=r"actuator figures jm_joint1, fv_joint1, fc_joint1, "
                                         r"jm_joint2 are not exported"):
        path = write(geared, tmp_path / "g.xml", ideal=True)
    text = path.read_text()
    assert "NOT exported" in text and "armature" not in text and 'gear="1"' in text
    rigid = geared.with_parameters(**{k: 0.0 for k in geared.parameters
                                      if k.startswith(("jm_", "fv_", "fc_"))})
    q, qd, qdd = random_states(rng, 30, 2)
    from_file = mj_inverse(path, geared, q, qd, qdd)
    assert rel_err(from_file, rigid.tree_inverse_dynamics(q, qd, qdd)) < GATE
    assert rel_err(from_file, geared.tree_inverse_dynamics(q, qd, qdd)) > 1e-3


def test_the_drive_train_with_motors_on_the_ground(derived, tmp_path, rng):
    """The geared arm with its only rotor on the ground (the elbow's rotor inertia set to 0)
    and viscous friction only: armature N^2 J_m and damping b make MuJoCo's inverse dynamics
    ours to 1e-10; the motor's gear and limits are in the file."""
    geared = derived["serial_2dof_geared"].with_parameters(jm_joint2=0.0, fc_joint1=0.0)
    path = write(geared, tmp_path / "ground.xml")
    text = path.read_text()
    p = geared.parameters
    assert f'armature="{p["gear_joint1"] ** 2 * p["jm_joint1"]!r}"' in text
    assert f'damping="{p["fv_joint1"]!r}"' in text and 'frictionloss="' not in text
    assert 'gear="50.0" ctrllimited="true" ctrlrange="-0.01 0.01"' in text
    q, qd, qdd = random_states(rng, 30, 2)
    assert rel_err(mj_inverse(path, geared, q, qd, qdd),
                   geared.tree_inverse_dynamics(q, qd, qdd)) < GATE


def test_a_rotor_on_a_moving_link_differs_by_the_documented_coupling(derived, tmp_path, rng):
    """The elbow's rotor turns with link1: MuJoCo (armature on the elbow, J_m added to link1's
    inertia) lacks the coupling N J_m, so its torques are ours less N J_m qdd2 at the shoulder
    and N J_m qdd1 at the elbow (alpha_link1 = qdd1), exactly as the file's header says."""
    geared = derived["serial_2dof_geared"].with_parameters(fc_joint1=0.0)
    with pytest.warns(RuntimeWarning, match=r"jm_joint2: the rotor turns with link1"):
        path = write(geared, tmp_path / "moving.xml")
    assert "coupling N J_m" in path.read_text()
    p = geared.parameters
    coupling = p["gear_joint2"] * p["jm_joint2"]
    q, qd, qdd = random_states(rng, 30, 2)
    ours = geared.tree_inverse_dynamics(q, qd, qdd)
    documented = ours - coupling * qdd[:, ::-1]
    mujoco_tau = mj_inverse(path, geared, q, qd, qdd)
    assert rel_err(mujoco_tau, documented) < GATE
    assert rel_err(mujoco_tau, ours) > 1e-6  # the difference is real, and it is this one


def test_coulomb_friction_becomes_frictionloss_with_a_warning(derived, tmp_path):
    geared = derived["serial_2dof_geared"]
    with pytest.warns(RuntimeWarning, match=r"fc_joint1: Coulomb friction 0.005 is exported as "
                                         r"MuJoCo's frictionloss"):
        text = write(geared, tmp_path / "c.xml").read_text()
    assert 'frictionloss="0.005"' in text and "Drive train, NOT exact here" in text


# -- closed chains: released from rest, MuJoCo against planar_sym.simulate ------------------

def mujoco_release(path, robot, q0, t_end, dt=None, solref=None, solimp=None, n_out=11):
    """MuJoCo RK4 from (q0, 0), zero control, on the MJCF file; optionally with a tighter step
    and loop softness. Returns (t, q in our order, max loop gap in m)."""
    model = mujoco.MjModel.from_xml_path(str(path))
    if dt is not None:
        model.opt.timestep = dt
        model.eq_solref[:] = solref
        model.eq_solimp[:, :3] = solimp  # d0, dwidth, width (midpoint, power: defaults)
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4
    data = mujoco.MjData(model)
    qa = [model.joint(c).qposadr[0] for c in robot.coordinates]
    data.qpos[qa] = q0
    dt = model.opt.timestep
    steps = round(t_end / dt)
    marks = np.round(np.linspace(0, steps, n_out)).astype(int)
    pairs = [(model.site(f"{c}_a").id, model.site(f"{c}_b").id) for c in robot.loops]
    mujoco.mj_forward(model, data)
    q, gap, k = [data.qpos[qa].copy()], 0.0, 1
    for i in range(1, steps + 1):
        mujoco.mj_step(model, data)
        gap = max(gap, max(np.linalg.norm(data.site_xpos[a] - data.site_xpos[b]) for a, b in pairs))
        if i == marks[k]:
            q.append(data.qpos[qa].copy())
            k += 1
    return marks * dt, np.array(q), gap


@pytest.mark.parametrize("name", sorted(RELEASE))
def test_closed_chain_released_in_mujoco_follows_our_simulation(name, derived, tmp_path,
                                                                worst_errors):
    from conftest import record

    robot = robot_of(name, derived)
    path = write(robot, tmp_path / f"{name}.xml")
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.neq == len(robot.loops) and not model.opt.disableflags  # equality on
    q0 = robot.q_drawn  # on the loops (assembled)
    t, q_tight, gap_tight = mujoco_release(path, robot, q0, RELEASE_T, RELEASE_DT,
                                           RELEASE_SOLREF, RELEASE_SOLIMP)
    ours = ps.simulate(robot, q0, np.zeros(robot.n), (0.0, RELEASE_T), t_eval=t)
    assert np.max(np.abs(ours.q - q0)) > 1.0  # it falls a long way: not a trivial agreement
    err = record(worst_errors, f"export release {name} (rad)", np.max(np.abs(q_tight - ours.q)))
    assert err < RELEASE[name][1], err
    assert gap_tight < 1e-9, gap_tight  # the loops stay closed: measured 4.6e-10, 5.7e-11 m
    _, q_file, gap_file = mujoco_release(path, robot, q0, RELEASE_T)
    assert (USER_TIMESTEP_S, *USER_SOLREF) == (model.opt.timestep, *model.eq_solref[0])
    assert tuple(model.eq_solimp[0, :3]) == USER_SOLIMP
    err_file = record(worst_errors, f"export release {name} as written (rad)",
                      np.max(np.abs(q_file - ours.q)))
    assert err_file < RELEASE_AS_WRITTEN[name][1], err_file
    assert gap_file < 3e-5, gap_file  # measured 1.0e-5 m (5-bar), 8.4e-7 m (four-bar)


# -- round trip and file structure ----------------------------------------------------------

ALL = ("serial_2dof", "serial_3dof", "serial_rpr", "five_bar_type1", "five_bar_type2",
       "parallel_3rrr", "parallel_3rpr", "slider_crank", "slider_crank_slider_driven",
       "four_bar", "cart_pole_incline", "bent_arm")


@pytest.mark.parametrize("name", ALL)
def test_mjcf_round_trip(name, derived, tmp_path, rng):
    robot = robot_of(name, derived)
    path = write(robot, tmp_path / "r.xml")
    text = path.read_text()
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.nbody - 1 == len(robot.body_names)
    assert model.njnt == model.nq == robot.n and model.neq == len(robot.loops)
    assert model.nu == len(robot.actuated)
    assert math.isclose(model.body_mass.sum(), total_mass(robot), rel_tol=1e-15)
    p = robot.parameters
    for body in robot.body_names:  # bit for bit: the text holds repr of every number
        b = model.body(body)
        assert b.mass[0] == p[f"m_{body}"]
        izz = p.get(f"izz_{body}", 0.0)
        if izz > 0:
            assert b.inertia[2] == izz and b.inertia[0] == b.inertia[1] == izz / 2
        assert tuple(b.ipos[:2]) == (p.get(f"cgx_{body}", 0.0), p.get(f"cgy_{body}", 0.0))
    assert (model.geom_contype == 0).all() and (model.geom_conaffinity == 0).all()
    assert model.ngeom > len(robot.body_names)  # something to see in the viewer
    # the geoms change nothing: the file without them has the same mass data and dynamics
    bare = mujoco.MjModel.from_xml_string(re.sub(r"<geom [^>]*/>", "", text))
    assert bare.ngeom == 0
    for field in ("body_mass", "body_inertia", "body_ipos", "body_iquat", "body_subtreemass"):
        np.testing.assert_array_equal(getattr(model, field), getattr(bare, field), err_msg=field)
    q, qd, qdd = random_states(rng, 5, robot.n)
    d1, d2 = mujoco.MjData(model), mujoco.MjData(bare)
    for k in range(5):
        for m, d in ((model, d1), (bare, d2)):
            d.qpos[:], d.qvel[:], d.qacc[:] = q[k], qd[k], qdd[k]
            mujoco.mj_inverse(m, d)
        np.testing.assert_array_equal(d1.qfrc_inverse, d2.qfrc_inverse)
    head = text[:text.index("-->")]
    assert "planar-sym" in head and name in head and "SI" in head
    assert robot.library.manifest["input_hash"] in head


@pytest.mark.parametrize("name", TREES + ("cart_pole_incline", "bent_arm"))
def test_urdf_round_trip(name, derived, tmp_path):
    robot = robot_of(name, derived)
    path = write(robot, tmp_path / "r.urdf")
    root = ET.parse(path).getroot()
    joints = root.findall("joint")
    assert len(root.findall("link")) == len(robot.body_names) + 1  # and ground
    assert sorted(j.get("name") for j in joints if j.get("type") != "fixed") == sorted(
        robot.coordinates)
    assert {j.get("type") for j in joints} <= {"continuous", "prismatic", "fixed"}
    model = pin_model(path, robot)
    assert model.nv == robot.n and model.njoints - 1 == robot.n
    assert math.isclose(sum(i.mass for i in model.inertias), total_mass(robot), rel_tol=1e-15)
    masses = {link.get("name"): float(link.find("inertial/mass").get("value"))
              for link in root.findall("link") if link.find("inertial") is not None}
    assert masses == {b: robot.parameters[f"m_{b}"] for b in robot.body_names}
    head = path.read_text().split("-->")[0]
    assert "GRAVITY IS NOT PART OF URDF" in head and robot.library.manifest["input_hash"] in head


def test_urdf_of_a_closed_chain_is_refused_and_points_to_mjcf(tmp_path):
    robot = ps.load("five_bar_type1")
    with pytest.raises(InputError, match=r"five_bar_type1 is a closed chain \(cut joint C\): "
                                         r"URDF describes trees only.*export MJCF instead"):
        to_urdf(robot)
    target = tmp_path / "five.urdf"
    target.write_text("old")
    with pytest.raises(InputError):
        write(robot, target)
    assert target.read_text() == "old"  # untouched
    assert [p.name for p in tmp_path.iterdir()] == ["five.urdf"]  # no temporary left


def test_to_mjcf_is_the_file_written(tmp_path):
    robot = ps.load("slider_crank")
    assert write(robot, tmp_path / "s.xml").read_text() == to_mjcf(robot)


# -- the command line ------------------------------------------------------------------------

def test_cli_writes_both_formats(tmp_path, capsys):
    assert main(["export", "serial_rpr", "--format", "urdf", "--out",
                 str(tmp_path / "rpr.urdf")]) == 0
    assert "serial_rpr: wrote" in capsys.readouterr().out
    assert pin_model(tmp_path / "rpr.urdf", ps.load("serial_rpr")).nv == 3
    assert main(["export", "five_bar_type1", "--out", str(tmp_path / "five.xml"),
                 "--quiet"]) == 0  # format from the suffix
    assert mujoco.MjModel.from_xml_path(str(tmp_path / "five.xml")).neq == 1
    assert capsys.readouterr().out == ""


def test_cli_exports_a_description_file(tmp_path, monkeypatch):
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    assert main(["export", str(ROOT / "examples" / "four_bar.toml"), "--quiet"]) == 0
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "four_bar.xml"))  # the default name
    assert model.neq == 1 and model.nq == 3


@pytest.mark.parametrize(("argv", "message"), [
    (["serial_2dof", "--format", "sdf"], "--format must be mjcf or urdf (got 'sdf')"),
    (["serial_2dof", "--out", "{tmp}/r.sdf"], "--out {tmp}/r.sdf: cannot tell the format"),
    (["five_bar_type1", "--format", "urdf", "--out", "{tmp}/f.urdf"],
     "five_bar_type1 is a closed chain (cut joint C): URDF describes trees only"),
    (["serial_2dof", "--out", "{tmp}/missing/r.xml"],
     "--out {tmp}/missing/r.xml: its folder {tmp}/missing does not exist; create it first"),
    (["serial_2dof", "--out", "{tmp}"], "--out {tmp} is a folder; give a file name"),
])
def test_cli_errors_name_the_option_and_write_nothing(argv, message, tmp_path, capsys):
    argv = [a.format(tmp=tmp_path) for a in argv]
    assert main(["export", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and message.format(tmp=tmp_path) in err, err
    assert err.count("\n") == 1  # one line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["serial_2dof", "serial_rpr", "five_bar_type1", "parallel_3rrr",
                                  "slider_crank", "four_bar"])
def test_mujoco_reset_state_is_the_drawn_pose_on_the_loops(name, tmp_path):
    """The user file is laid out in the drawn pose (joint ``ref``): MuJoCo's reset state is
    q_drawn, where every cut joint's two sites coincide. Laid out at q = 0 instead, a closed
    chain's cut joints gaped by centimetres and the viewer's first steps blew it apart."""
    robot = ps.load(ROOT / "examples" / "four_bar.toml" if name == "four_bar" else name)
    path = write(robot, tmp_path / f"{name}.xml")
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    mujoco.mj_resetData(m, d)
    mujoco.mj_forward(m, d)
    order = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, i) for i in range(m.njnt)]
    qpos = dict(zip(order, d.qpos))
    np.testing.assert_allclose([qpos[c] for c in robot.coordinates], robot.q_drawn, rtol=0,
                               atol=1e-15)
    sites = {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, i): d.site_xpos[i]
             for i in range(m.nsite)}
    cuts = [n[:-2] for n in sites if n.endswith("_a")]
    assert len(cuts) == robot.n_constraints // 2
    for cut in cuts:  # each cut joint: sites <cut>_a and <cut>_b, on its two bodies
        assert np.linalg.norm(sites[f"{cut}_a"] - sites[f"{cut}_b"]) < 1e-12, cut
    for _ in range(50):  # and it moves off from there without blowing up
        mujoco.mj_step(m, d)
    assert np.all(np.isfinite(d.qpos)) and np.max(np.abs(d.qvel)) < 100.0


def test_format_is_read_as_typed_and_must_agree_with_the_suffix(tmp_path):
    """`--format URDF` is urdf; an explicit format that the file's suffix contradicts (MJCF in
    an .urdf file) is refused, while a suffix that names no format (.txt) is left to --format."""
    assert main(["export", "serial_2dof", "--format", "URDF", "--out",
                 str(tmp_path / "a.urdf")]) == 0
    assert "<robot " in (tmp_path / "a.urdf").read_text()
    with pytest.raises(InputError, match=r"names a URDF file"):
        format_of("mjcf", tmp_path / "b.urdf")
    with pytest.raises(InputError, match=r"names an MJCF file"):
        format_of("urdf", tmp_path / "b.xml")
    assert format_of("urdf", tmp_path / "b.txt") == "urdf"
    assert main(["export", "serial_2dof", "--format", "mjcf", "--out",
                 str(tmp_path / "c.urdf")]) == 2
    assert not (tmp_path / "c.urdf").exists()
