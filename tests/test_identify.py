"""Identification's regressor and base parameters, each against something independent.

* ``Y pi`` against the compiled inverse dynamics (a different derivation: energies in the
  description's parameters, not in the standard ones) at random states and random parameters,
  for every built-in robot, example and test robot; closed chains' torques and cut-joint forces.
* The inertial columns of trees against Pinocchio's joint-torque regressor, mapped to our
  standard parameters by the parallel-axis theorem (its parameters are per joint, about the
  joint frame's origin); friction columns against their closed form.
* Base parameter counts against the classical results (planar 2R and 3R arms: three per link,
  the masses regrouped) and against the rank of the stacked regressor by an SVD; the 2-DOF
  arm's regrouping against the parallel-axis theorem by hand.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import BUILTIN_ROBOTS, TEST_ROBOTS

import planar_sym as ps
from planar_sym.errors import InputError
from planar_sym.identify.base import base_parameters, from_stacked
from planar_sym.identify.regressor import regressor
from planar_sym.identify.standard import standard_parameters
from planar_sym.identify.states import random_states

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
TREE_FILES = [str(TEST_ROBOTS / f) for f in ("cart_pole.toml", "pendulum.toml",
                                             "rotated_slider.toml", "rpr_geared.toml",
                                             "point_pendulum.toml", "bent_arm.toml")]
ROBOTS = [*BUILTIN_ROBOTS, *TREE_FILES, str(EXAMPLES / "serial_2dof_geared.toml"),
          str(EXAMPLES / "four_bar.toml"), str(EXAMPLES / "six_bar_watt.toml")]


def _ids(robots):
    return [Path(r).stem for r in robots]


def _perturbed(robot, rng):
    """The robot with every inertial and drive parameter scaled by a random factor in
    [0.7, 1.3] (geometry kept: a closed chain must still assemble)."""
    keep = ("m_", "izz_", "cgx_", "cgy_", "jm_", "fv_", "fc_")
    values = {k: robot.parameters[k] * rng.uniform(0.7, 1.3) for k in robot.parameters
              if k.startswith(keep)}
    return robot.with_parameters(**values)


@pytest.mark.parametrize("name", ROBOTS, ids=_ids(ROBOTS))
def test_regressor_times_parameters_is_the_inverse_dynamics(name):
    rng = np.random.default_rng(7)
    robot = _perturbed(ps.load(name), rng)
    pi = standard_parameters(robot).values
    q, qd, qdd = random_states(robot, 40, seed=3)
    reg = regressor(robot, q, qd, qdd)
    if robot.is_closed_chain:
        tau, lam = robot.closed_chain_inverse_dynamics(q, qd, qdd)
        scale = max(np.abs(tau).max(), 1e-3)
        assert np.abs(reg.y @ pi - tau).max() <= 1e-12 * scale
        assert np.abs(reg.y_lambda @ pi - lam).max() <= 1e-12 * max(np.abs(lam).max(), 1e-3)
    else:
        tau = robot.tree_inverse_dynamics(q, qd, qdd)
        assert reg.rows == tuple(range(robot.n)) and reg.y_lambda is None
        assert np.abs(reg.y @ pi - tau).max() <= 1e-12 * max(np.abs(tau).max(), 1e-3)


def _pinocchio_map(desc, tree, names):
    """T (10 per Pinocchio joint, our standard columns): Pinocchio's dynamic parameters
    [m, mc (3), I (6) about the joint origin] of the joint each body hangs on, from ours:
    m; mc = m t + R (m c); Izz = izo + 2 t . R (m c) + m |t|^2 (t, R: the body frame's
    placement in the joint frame)."""
    cols = {n: k for k, n in enumerate(names)}
    t_map = np.zeros((10 * (tree.model.njoints - 1), len(names)))
    for body, (jid, pl) in tree.where.items():
        if jid == 0 or f"m_{body}" not in cols:
            continue
        r, t = pl.rotation[:2, :2], pl.translation[:2]
        base = 10 * (jid - 1)
        m, cx, cy, izo = (cols[f"{k}_{body}"] for k in ("m", "mcx", "mcy", "izo"))
        t_map[base, m] += 1.0
        t_map[base + 1:base + 3, m] += t
        t_map[base + 1:base + 3, cx] += r[:, 0]
        t_map[base + 1:base + 3, cy] += r[:, 1]
        t_map[base + 9, izo] += 1.0
        t_map[base + 9, cx] += 2 * t @ r[:, 0]
        t_map[base + 9, cy] += 2 * t @ r[:, 1]
        t_map[base + 9, m] += t @ t
    return t_map


PIN_TREES = ["serial_2dof", "serial_3dof", "serial_rpr", *TREE_FILES]


@pytest.mark.parametrize("name", PIN_TREES, ids=_ids(PIN_TREES))
def test_inertial_columns_against_pinocchio(name):
    pin = pytest.importorskip("pinocchio")
    from pinocchio_model import pinocchio_tree

    from planar_sym.model.description import load as load_description

    robot = ps.load(name)
    desc = load_description(name)
    tree = pinocchio_tree(desc)
    std = standard_parameters(robot)
    t_map = _pinocchio_map(desc, tree, std.names)
    q, qd, qdd = random_states(robot, 20, seed=11)
    y = regressor(robot, q, qd, qdd).y
    data = tree.model.createData()
    inertial = [k for k, n in enumerate(std.names) if n.split("_", 1)[0] in
                ("m", "mcx", "mcy", "izo")]
    for k in range(len(q)):
        y_pin = pin.computeJointTorqueRegressor(tree.model, data, tree.to_pin(q[k]),
                                                tree.to_pin(qd[k]), tree.to_pin(qdd[k]))
        ours = y[k][:, inertial]
        theirs = np.atleast_2d(y_pin)[list(tree.order)] @ t_map[:, inertial]  # rows: ours
        assert np.abs(ours - theirs).max() <= 1e-12 * max(np.abs(theirs).max(), 1.0)


def test_friction_columns_are_their_closed_form():
    robot = ps.load(str(EXAMPLES / "serial_2dof_geared.toml"))
    std = standard_parameters(robot)
    q, qd, qdd = random_states(robot, 10, seed=2)
    y = regressor(robot, q, qd, qdd).y
    for k, joint in enumerate(robot.coordinates):
        np.testing.assert_allclose(y[:, k, std.index(f"fv_{joint}")], qd[:, k], rtol=0,
                                   atol=1e-15)
        vs = robot.parameters.get(f"vs_{joint}", 0.01)
        np.testing.assert_allclose(y[:, k, std.index(f"fc_{joint}")], np.tanh(qd[:, k] / vs),
                                   rtol=0, atol=1e-15)
        other = 1 - k  # friction at one joint gives no torque at the other
        assert np.all(y[:, other, std.index(f"fv_{joint}")] == 0.0)


#: classical counts: a planar revolute arm with gravity in its plane keeps three inertial
#: parameters per link (izo, mcx, mcy; the masses regrouped into the links before them, the
#: first link's mass unidentifiable), plus two friction parameters per motor
KNOWN = {"serial_2dof": 3 * 2 + 2 * 2, "serial_3dof": 3 * 3 + 2 * 3,
         str(TEST_ROBOTS / "pendulum.toml"): 3 + 2}


@pytest.mark.parametrize("name", ROBOTS, ids=_ids(ROBOTS))
def test_base_parameter_count_is_the_rank(name):
    robot = ps.load(name)
    base = base_parameters(robot)
    # the rank by an independent route: singular values of the column-scaled stack at other
    # random states
    q, qd, qdd = random_states(robot, 150, seed=99)
    w = regressor(robot, q, qd, qdd).y.reshape(-1, len(base.standard))
    norms = np.linalg.norm(w, axis=0)
    sv = np.linalg.svd(w[:, norms > 0] / norms[norms > 0], compute_uv=False)
    assert len(base) == int(np.sum(sv > 1e-9 * sv[0]))
    if name in KNOWN:
        assert len(base) == KNOWN[name]
    assert base.margin[0] > 1e4 * max(base.margin[1], 1e-16)  # a clear gap
    # the base parameters reproduce every torque: Y pi == Y_kept beta
    pi = standard_parameters(robot).values
    y = w.reshape(len(q), -1, len(pi))
    np.testing.assert_allclose(y[..., list(base.kept)] @ base.values(), y @ pi,
                               rtol=0, atol=1e-10 * np.abs(y @ pi).max())


def test_two_link_regrouping_is_the_parallel_axis_theorem():
    """serial_2dof: motor2 is welded to link1 and link2 turns about joint 2; the masses hung
    beyond link1 regroup into link1's first moments and inertia as m d and m |d|^2, d their
    frame origin in link1's frame (from the compiled frames at q = 0)."""
    robot = ps.load("serial_2dof")
    base = base_parameters(robot)
    frames = robot.frames(np.zeros(robot.n))
    bodies = robot.library.manifest["bodies"]

    def offset(body):  # the body's frame origin in link1's frame (m)
        x0, y0, a0 = frames[bodies.index("link1")]
        x, y, _ = frames[bodies.index(body)]
        c, s = np.cos(a0), np.sin(a0)
        return np.array([c * (x - x0) + s * (y - y0), -s * (x - x0) + c * (y - y0)])

    row = {name: dict(zip(base.standard.names, r)) for name, r in zip(base.names,
                                                                       base.regrouping)}
    assert base.unidentifiable == ("m_link1",)
    assert set(base.regrouped()) == {"m_motor2", "mcx_motor2", "mcy_motor2", "izo_motor2",
                                     "m_link2"}
    for body in ("motor2", "link2"):
        d = offset(body)
        assert row["mcx_link1R"][f"m_{body}"] == pytest.approx(d[0], rel=1e-12, abs=1e-15)
        assert row["mcy_link1R"][f"m_{body}"] == pytest.approx(d[1], rel=1e-12, abs=1e-15)
        assert row["izo_link1R"][f"m_{body}"] == pytest.approx(d @ d, rel=1e-12)
    assert row["izo_link1R"]["izo_motor2"] == pytest.approx(1.0, rel=1e-12)
    assert row["izo_link1R"]["izo_link2"] == 0.0  # link2's own inertia is its own parameter
    assert "izo_link2" in base.names and "mcx_link2" in base.names


def test_dependent_columns_found_in_a_made_up_stack():
    """from_stacked on a matrix built to have known dependencies: c2 = 2 c0 - c1, c3 = 0."""
    rng = np.random.default_rng(0)
    a = rng.normal(size=(30, 2))
    w = np.column_stack([a[:, 0], a[:, 1], 2 * a[:, 0] - a[:, 1], np.zeros(30)])
    from planar_sym.identify.standard import StandardParameters

    std = StandardParameters(("izo_b", "mcx_b", "m_b", "mcy_b"), ("",) * 4, ("",) * 4,
                             np.array([1.0, 2.0, 3.0, 4.0]))
    base = from_stacked(w, std)
    assert base.kept == (0, 1) and base.unidentifiable == ("mcy_b",)
    np.testing.assert_allclose(base.regrouping, [[1, 0, 2, 0], [0, 1, -1, 0]], atol=1e-12)
    assert base.values().tolist() == pytest.approx([7.0, -1.0])
    assert base.expressions() == ["izo_bR = izo_b + 2 m_b", "mcx_bR = mcx_b - m_b"]


def test_a_state_off_the_loops_is_refused():
    robot = ps.load("five_bar_type1")
    q, qd, qdd = random_states(robot, 5, seed=1)
    q[3, 0] += 1e-3
    with pytest.raises(InputError, match="sample 3 .*off the loop constraints"):
        regressor(robot, q, qd, qdd)


@pytest.mark.parametrize("name", ["serial_3dof", "five_bar_type1"])
def test_exact_route_agrees_with_the_loop(name, monkeypatch):
    """Without the vectorised loop (no compiler, or an older folder) the exact per-sample
    functions give the same regressors (the loop is compiled with -ffast-math)."""
    import importlib

    # (the package exports the function regressor, which hides the module of that name)
    reg_module = importlib.import_module("planar_sym.identify.regressor")

    robot = ps.load(name)
    q, qd, qdd = random_states(robot, 30, seed=4)
    fast = regressor(robot, q, qd, qdd)
    monkeypatch.setattr(reg_module, "loop_caller", lambda robot, quantity: None)
    other = robot.with_parameters()  # a new robot: no caller bound yet
    exact = regressor(other, q, qd, qdd)
    scale = np.abs(exact.y).max()
    assert np.abs(fast.y - exact.y).max() <= 1e-12 * scale
    if robot.is_closed_chain:
        assert np.abs(fast.y_lambda - exact.y_lambda).max() <= 1e-12 * np.abs(
            exact.y_lambda).max()


def test_the_reports_lumped_parameters_are_base_combinations():
    """The equation report's alpha, beta, delta and gravity coefficients of the 2-DOF arm
    (generated/serial_2dof/equations.txt, from the description's parameters) are sums of base
    parameters: alpha = izo_link1R + izo_link2, delta = izo_link2, beta = a1 mcx_link2, the
    gravity terms mcx_link1R and mcx_link2 (the cg on the link axes, as the seed draws it)."""
    robot = ps.load("serial_2dof")
    p = robot.parameters
    a1, lc1, lc2 = p["px_link1_CS2"], p["cgx_link1"], p["cgx_link2"]
    m1, m2, mm2 = p["m_link1"], p["m_link2"], p["m_motor2"]
    i1, i2, im2 = p["izz_link1"], p["izz_link2"], p["izz_motor2"]
    alpha = i1 + i2 + im2 + m1 * lc1**2 + m2 * (a1**2 + lc2**2) + mm2 * a1**2
    beta, delta = m2 * a1 * lc2, i2 + m2 * lc2**2
    g1, g2 = m1 * lc1 + m2 * a1 + mm2 * a1, m2 * lc2
    base = base_parameters(robot)
    b = dict(zip(base.names, base.values()))
    assert alpha == pytest.approx(b["izo_link1R"] + b["izo_link2"], rel=1e-14)
    assert delta == pytest.approx(b["izo_link2"], rel=1e-14)
    assert beta == pytest.approx(a1 * b["mcx_link2"], rel=1e-14)
    assert g1 == pytest.approx(b["mcx_link1R"], rel=1e-14)
    assert g2 == pytest.approx(b["mcx_link2"], rel=1e-14)


def test_batch_route_checks_inputs_as_the_general_route():
    """A tree's (N, n) float64 batch goes straight to the compiled caller (no Python checks):
    it refuses what the general route refuses, naming the same sample, and gives the same Y as
    a list input (which goes through as_samples)."""
    robot = ps.load("serial_2dof")
    q, qd, qdd = random_states(robot, 6, seed=2)
    batch = regressor(robot, q, qd, qdd).y
    listed = regressor(robot, q.tolist(), qd.tolist(), qdd.tolist()).y
    assert batch.shape == listed.shape == (6, 2, 16)
    assert np.array_equal(batch, listed)
    one = regressor(robot, q[4], qd[4], qdd[4]).y  # one sample, (n,): still (1, rows, cols)
    # one sample goes through the exact library, a batch through the vectorised loop (vector
    # sin and cos, -ffast-math): equal to rounding, bit for bit only on some CPUs (AVX-512)
    assert one.shape == (1, 2, 16)
    assert np.abs(one[0] - batch[4]).max() <= 1e-14 * np.abs(batch[4]).max()
    for bad in (np.nan, np.inf):
        qd_bad = qd.copy()
        qd_bad[4, 1] = bad
        for arrays in ((q, qd_bad, qdd), (q.tolist(), qd_bad.tolist(), qdd.tolist())):
            with pytest.raises(InputError, match=r"qd\[4, 1\] is .* at sample 4: inputs must "
                                                 "be finite"):
                regressor(robot, *arrays)
    with pytest.raises(InputError, match="same number of samples"):
        regressor(robot, q, qd[:5], qdd)
    with pytest.raises(InputError, match=r"qdd must have shape \(N, 2\)"):
        regressor(robot, q, qd, np.zeros((6, 3)))
