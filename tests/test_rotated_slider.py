"""A slider whose child body is drawn turned to its parent (tests/robots/rotated_slider.toml: a
carriage turned 30 deg to the arm it slides on, a tip link on the carriage), exported and read
back by other engines, against planar-sym's own dynamics.

Every built-in slider's child is drawn at angle 0 to its parent, where the prismatic axis
written into the child's joint frame is the description's axis whichever way it is turned;
here it must be turned by -30 deg, and the wrong way moves the carriage 60 deg off its rail.

- the description: the carriage's frame stays 30 deg to the arm's at every pose, and it slides
  along the arm's x axis (from the generated frames);
- URDF read by Pinocchio (``buildModelFromUrdf``): ``rnea`` gives our
  ``tree_inverse_dynamics`` and ``crba`` our ``mass_matrix`` at random states, to ``GATE``
  (1e-10, ``conftest.rel_err``; measured 1.5e-15 and 7e-16);
- MJCF read by MuJoCo: ``mj_inverse`` and the mass matrix (``mj_mulM`` on unit vectors)
  likewise (as tests/test_export.py does for the other trees); measured about 2e-15.

With the axis turned the wrong way in either file, the torques err by about 6 (relative).
"""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from conftest import TEST_ROBOTS, random_states, rel_err

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.outputs.export import write

GATE = 1e-10
TILT = np.radians(30.0)  # the carriage's drawn angle to the arm


@pytest.fixture(scope="module")
def robot(tmp_path_factory):
    """Derived through the command line (which keeps description.toml beside the code, for the
    export), compiled into a private cache, as tests/test_export.py does."""
    out = tmp_path_factory.mktemp("rotated_slider")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("PLANAR_SYM_CACHE", str(tmp_path_factory.mktemp("cache")))
        assert main(["derive", str(TEST_ROBOTS / "rotated_slider.toml"), "--out", str(out),
                     "--quiet"]) == 0
        return ps.load(out / "rotated_slider")


def test_the_carriage_is_turned_to_its_rail(robot, rng):
    """Reference: the description's numbers (30 deg, axis along the arm's x)."""
    assert robot.coordinates == ("shoulder", "slide", "wrist")
    assert robot.coordinate_units == ("rad", "m", "rad")
    arm, carriage = (list(robot.body_names).index(b) for b in ("arm", "carriage"))
    q = rng.uniform(-np.pi, np.pi, (20, 3))
    fr = robot.frames(q)
    turn = np.angle(np.exp(1j * (fr[:, carriage, 2] - fr[:, arm, 2])))
    np.testing.assert_allclose(turn, TILT, rtol=0, atol=1e-14)
    step = q + [0.0, 0.1, 0.0]  # 0.1 m along the rail: along the arm's x axis
    moved = robot.frames(step)[:, carriage, :2] - fr[:, carriage, :2]
    along = 0.1 * np.column_stack([np.cos(fr[:, arm, 2]), np.sin(fr[:, arm, 2])])
    np.testing.assert_allclose(moved, along, rtol=0, atol=1e-14)


def _gravity(robot) -> np.ndarray:
    ux, uy = robot.library.manifest["gravity_direction"]
    return robot.parameters["g"] * np.array([ux, uy, 0.0])


def _pinocchio(path, robot, q, qd, qdd):
    """rnea and crba of the URDF file, in our coordinate order (a continuous joint's
    configuration is (cos q, sin q), a prismatic joint's d)."""
    model = pin.buildModelFromUrdf(str(path))
    model.gravity.linear = _gravity(robot)  # URDF has no gravity: the engine's is set
    data = model.createData()
    assert model.nv == robot.n and sorted(model.names[1:]) == sorted(robot.coordinates)
    ids = [model.getJointId(c) for c in robot.coordinates]
    cols = [model.idx_vs[j] for j in ids]
    tau, mass = np.empty_like(q), np.empty((len(q), robot.n, robot.n))
    for k in range(len(q)):
        cq, v, a = pin.neutral(model), np.zeros(model.nv), np.zeros(model.nv)
        for i, jid in enumerate(ids):
            iq, nq = model.idx_qs[jid], model.nqs[jid]
            cq[iq:iq + nq] = (np.cos(q[k, i]), np.sin(q[k, i])) if nq == 2 else q[k, i]
            v[cols[i]], a[cols[i]] = qd[k, i], qdd[k, i]
        tau[k] = pin.rnea(model, data, cq, v, a)[cols]
        m = pin.crba(model, data, cq)
        m = np.triu(m) + np.triu(m, 1).T  # crba fills the upper triangle
        mass[k] = m[np.ix_(cols, cols)]
    return tau, mass


def _mujoco(path, robot, q, qd, qdd):
    """mj_inverse and the dense mass matrix of the MJCF file, in our coordinate order."""
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    assert model.nq == model.nv == robot.n
    qa = [model.joint(c).qposadr[0] for c in robot.coordinates]
    va = [model.joint(c).dofadr[0] for c in robot.coordinates]
    tau, mass = np.empty_like(q), np.empty((len(q), robot.n, robot.n))
    unit, column = np.eye(model.nv), np.empty(model.nv)
    for k in range(len(q)):
        data.qpos[qa], data.qvel[va], data.qacc[va] = q[k], qd[k], qdd[k]
        mujoco.mj_inverse(model, data)
        tau[k] = data.qfrc_inverse[va]
        for i, a in enumerate(va):  # M column by column (mj_mulM: the same call in every
            mujoco.mj_mulM(model, data, column, unit[a])  # MuJoCo version, unlike mj_fullM)
            mass[k][:, i] = column[va]
    return tau, mass


@pytest.mark.parametrize("engine", ["pinocchio (URDF)", "mujoco (MJCF)"])
def test_the_exported_file_gives_our_dynamics(engine, robot, tmp_path, rng):
    """Reference: Pinocchio's rnea and crba on the URDF file, MuJoCo's mj_inverse and mass
    matrix on the MJCF file, joints matched by name."""
    q, qd, qdd = random_states(rng, 50, robot.n)
    if engine.startswith("pinocchio"):
        tau, mass = _pinocchio(write(robot, tmp_path / "r.urdf"), robot, q, qd, qdd)
    else:
        tau, mass = _mujoco(write(robot, tmp_path / "r.xml"), robot, q, qd, qdd)
    e_tau = rel_err(tau, robot.tree_inverse_dynamics(q, qd, qdd))
    e_mass = rel_err(mass, robot.mass_matrix(q))
    assert e_tau < GATE, e_tau
    assert e_mass < GATE, e_mass


@pytest.fixture(scope="module")
def tilted(tmp_path_factory):
    """The same robot with its rail tilted in the arm's frame (axis (0.6, 0.8)): the report's
    lumped parameters met sin(q + 30 deg) in a coefficient and the derivation failed with
    SymPy's PolynomialError (found by a helper session's export tests)."""
    src = (TEST_ROBOTS / "rotated_slider.toml").read_text()
    assert "axis = [1.0, 0.0]" in src
    folder = tmp_path_factory.mktemp("tilted")
    path = folder / "tilted_slider.toml"
    path.write_text(src.replace('name = "rotated_slider"', 'name = "tilted_slider"')
                    .replace("axis = [1.0, 0.0]", "axis = [0.6, 0.8]"))
    out = folder / "out"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("PLANAR_SYM_CACHE", str(tmp_path_factory.mktemp("cache")))
        assert main(["derive", str(path), "--out", str(out), "--quiet"]) == 0
        return ps.load(out / "tilted_slider")


def test_a_tilted_rail_derives_and_gives_pinocchio_dynamics(tilted, tmp_path, rng):
    q, qd, qdd = random_states(rng, 50, tilted.n)
    tau, mass = _pinocchio(write(tilted, tmp_path / "t.urdf"), tilted, q, qd, qdd)
    assert rel_err(tau, tilted.tree_inverse_dynamics(q, qd, qdd)) < GATE
    assert rel_err(mass, tilted.mass_matrix(q)) < GATE
