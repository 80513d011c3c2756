"""Joint loads (planar_sym.dynamics.reactions) against independent things.

1. Every body's free-body balance, built here from the reported loads and nothing of the load
   computation: at each joint the reported force and couple on the child and their opposites on
   the parent, the cut forces from today's multipliers lambda (+lambda on the cut's parent at the
   parent point, -lambda on its child at the child point), gravity at the cg; their sum is
   ``m a_cg`` and their moment about the cg is ``I alpha`` (relative to the largest term, 1e-12),
   plus, on a body that carries a rotor's stator, the rotor's spin J (alpha + N qdd) (read from
   the parameters jm_<joint>, gear_<joint> here). Without a drive model the revolute couples
   equal the Lagrangian tau (M qdd + h through the multiplier solve) to 1e-12, so the moment
   balance also checks tau against Newton-Euler; with one, the drive balance holds:
   ``tau = couple + D(qd) + N J (alpha_parent + N qdd)`` (tests/test_joint_loads_drive.py).
2. The cut joints' forces against lambda; passive revolute joints carry no couple.
3. Serial arms against Pinocchio's RNEA: ``data.f[i]`` is the spatial force the parent
   transmits to joint i's subtree, in joint i's frame, about the joint point (1e-10 relative).
4. The generated body accelerations against a second difference of the generated frames.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from conftest import CLOSED, TREES, random_states, rel_err, study_motion
from pinocchio_model import pinocchio_model

import planar_sym as ps
from planar_sym.dynamics.reactions import JointLoads, joint_loads
from planar_sym.model import description
from planar_sym.motion.closure import complete_rates, solve_passive
from planar_sym.study.run import run

STUDIES = ("serial_2dof_cartesian_move", "serial_2dof_joint_move", "serial_3dof_cartesian_move",
           "five_bar_type1_move_x", "five_bar_type1_move_y", "five_bar_type2_move_x",
           "five_bar_type2_move_y", "parallel_3rrr_move_x", "parallel_3rrr_move_y")
FREE_BODY_TOL = 1e-12
PINOCCHIO_TOL = 1e-10


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _generalised_forces(robot, q, qd, qdd):
    """tau at every coordinate (0 at passive joints of a closed chain) and lambda (N, 2 loops)."""
    if not robot.is_closed_chain:
        return robot.tree_inverse_dynamics(q, qd, qdd), np.zeros((len(q), 0))
    tau_act, lam = robot.closed_chain_inverse_dynamics(q, qd, qdd)
    tau = np.zeros((len(q), robot.n))
    tau[:, list(robot.actuated)] = tau_act
    return tau, lam


def free_body_residuals(robot, q, qd, qdd, loads: JointLoads) -> tuple[float, float]:
    """Worst |sum F - m a| / largest force and |sum M_cg - I alpha| / largest moment term."""
    manifest = robot.library.manifest
    par = robot.parameters
    frames = robot.frames(q)
    acc = robot.body_motion(q, qd, qdd)[0].transpose(0, 2, 1)  # (N, bodies, 3)
    n_s, bodies = len(q), list(robot.body_names)
    tau, lam = _generalised_forces(robot, q, qd, qdd)

    def world(body, point=None):
        if body == "ground":  # the ground's points are never needed: it is not balanced
            return np.zeros((n_s, 2))
        key = f"cg{'{}'}_{body}" if point is None else f"p{'{}'}_{body}_{point}"
        lx, ly = par.get(key.format("x"), 0.0), par.get(key.format("y"), 0.0)
        o, th = frames[:, bodies.index(body), :2], frames[:, bodies.index(body), 2]
        return o + np.stack([np.cos(th) * lx - np.sin(th) * ly,
                             np.sin(th) * lx + np.cos(th) * ly], axis=-1)

    # every load on every body: (application point, force) and couples
    forces = {b: [] for b in bodies}
    couples = {b: [] for b in bodies}
    g = par.get("g", 0.0) * np.array(manifest["gravity_direction"])
    for b in bodies:
        forces[b].append((world(b), np.broadcast_to(par[f"m_{b}"] * g, (n_s, 2))))
    cut = 0
    for k, j in enumerate(manifest["joints"]):
        assert loads.names[k] == j["name"]
        at_child = world(j["child"], j["child_point"])
        if j["closes_loop"]:
            f = lam[:, 2 * cut:2 * cut + 2]
            cut += 1
            if j["parent"] != "ground":
                forces[j["parent"]].append((world(j["parent"], j["parent_point"]), f))
            if j["child"] != "ground":
                forces[j["child"]].append((at_child, -f))
            continue
        force, couple = loads.force[:, k], loads.couple[:, k]
        if j["type"] == "revolute" and f"jm_{j['name']}" not in par and \
                f"fv_{j['name']}" not in par:  # no drive model: the Lagrangian tau
            lagrange = tau[:, j["coordinate"]]
            assert np.abs(couple - lagrange).max() <= 1e-12 * max(np.abs(tau).max(), 1e-300)
        forces[j["child"]].append((at_child, force))
        couples[j["child"]].append(couple)
        if j["parent"] != "ground":
            # a prismatic joint's load acts at the child point on both bodies
            at_parent = (at_child if j["type"] == "prismatic"
                         else world(j["parent"], j["parent_point"]))
            forces[j["parent"]].append((at_parent, -force))
            couples[j["parent"]].append(-couple)
    spin = {b: np.zeros(n_s) for b in bodies}  # rotors' J (alpha_stator + N qdd)
    for j in manifest["joints"]:
        inertia = par.get(f"jm_{j['name']}", 0.0)
        if inertia and j["parent"] != "ground":
            ratio = par.get(f"gear_{j['name']}", 1.0)
            spin[j["parent"]] = spin[j["parent"]] + inertia * (
                acc[:, bodies.index(j["parent"]), 2] + ratio * qdd[:, j["coordinate"]])
    worst_f = worst_m = 0.0
    scale_f = max(np.abs(f).max() for b in bodies for _, f in forces[b])
    terms_m = []
    for i, b in enumerate(bodies):
        cg = world(b)
        total_f = sum(f for _, f in forces[b]) - par[f"m_{b}"] * acc[:, i, :2]
        moments = [_cross(r - cg, f) for r, f in forces[b]] + couples[b]
        terms_m += moments
        total_m = sum(moments) - par.get(f"izz_{b}", 0.0) * acc[:, i, 2] - spin[b]
        worst_f = max(worst_f, float(np.abs(total_f).max()))
        worst_m = max(worst_m, float(np.abs(total_m).max()))
    scale_m = max(float(np.abs(m).max()) for m in terms_m)
    return worst_f / scale_f, worst_m / scale_m


def _random_closed_state(robot, rng, n_s=20):
    """States on the loops near the drawn pose: actuated angles moved a little, Newton for the
    passive ones, random actuated rates and accelerations (rad/s, rad/s^2)."""
    act = list(robot.actuated)
    q_act = robot.q_drawn[act] + rng.uniform(-0.05, 0.05, (n_s, len(act)))
    q = np.vstack([solve_passive(robot, qa[None], robot.q_drawn) for qa in q_act])
    qd, qdd = complete_rates(robot, q, rng.uniform(-3, 3, (n_s, len(act))),
                             rng.uniform(-3, 3, (n_s, len(act))))
    return q, qd, qdd


@pytest.mark.parametrize("name", STUDIES)
def test_every_body_balances_along_the_studies(name):
    robot, _, jt = study_motion(name, np.linspace(0.0, 1.0, 41))
    loads = joint_loads(robot, jt.q, jt.qd, jt.qdd)
    res_f, res_m = free_body_residuals(robot, jt.q, jt.qd, jt.qdd, loads)
    assert res_f < FREE_BODY_TOL and res_m < FREE_BODY_TOL, (res_f, res_m)


@pytest.mark.parametrize("robot_name", TREES + CLOSED)
def test_every_body_balances_at_random_states(robot_name, rng):
    robot = ps.load(robot_name)
    if robot.is_closed_chain:
        q, qd, qdd = _random_closed_state(robot, rng)
    else:
        q, qd, qdd = random_states(rng, 50, robot.n)
    loads = joint_loads(robot, q, qd, qdd)
    res_f, res_m = free_body_residuals(robot, q, qd, qdd, loads)
    assert res_f < FREE_BODY_TOL and res_m < FREE_BODY_TOL, (res_f, res_m)
    # no drive model: the revolute couples agree with the Lagrangian tau to rounding
    scale = np.abs(loads.couple).max()
    for i, name in enumerate(loads.names):
        if loads.types[i] == "revolute" and name in loads.drive:
            assert np.abs(loads.couple[:, i] - loads.drive[name]).max() < 1e-12 * scale


@pytest.mark.parametrize("robot_name", CLOSED)
def test_cut_joints_carry_minus_lambda_and_passive_joints_no_couple(robot_name, rng):
    robot = ps.load(robot_name)
    q, qd, qdd = _random_closed_state(robot, rng)
    tau, lam = robot.closed_chain_inverse_dynamics(q, qd, qdd)
    loads = joint_loads(robot, q, qd, qdd)
    for k, cut in enumerate(robot.loops):
        i = loads.index(cut)
        assert np.array_equal(loads.force[:, i], -lam[:, 2 * k:2 * k + 2])  # parent on child
        assert np.array_equal(loads.couple[:, i], np.zeros(len(q)))
    joints = {j["name"]: j for j in robot.library.manifest["joints"]}
    scale = np.abs(tau).max()
    for i, name in enumerate(loads.names):
        j = joints[name]
        if j["type"] == "revolute" and not j["closes_loop"]:
            if j["actuated"]:
                col = list(robot.actuated).index(j["coordinate"])
                assert np.array_equal(loads.drive[name], tau[:, col])
                assert np.abs(loads.couple[:, i] - tau[:, col]).max() < 1e-12 * scale
            else:  # a passive joint: Newton-Euler finds no couple there
                assert name not in loads.drive
                assert np.abs(loads.couple[:, i]).max() < 1e-12 * scale


def _pinocchio_loads(robot_name, q, qd, qdd):
    """Per revolute tree joint (by name): world force (N, 2) and couple (N,) from RNEA."""
    desc = description.load(robot_name)
    model, _ = pinocchio_model(desc)
    data = model.createData()
    names = [model.names[i] for i in range(1, model.njoints)]
    force = {n: np.empty((len(q), 2)) for n in names}
    couple = {n: np.empty(len(q)) for n in names}
    for k in range(len(q)):
        pin.rnea(model, data, q[k], qd[k], qdd[k])
        pin.forwardKinematics(model, data, q[k])  # rnea leaves data.oMi as it was
        for i, n in enumerate(names, start=1):
            f = data.f[i]
            force[n][k] = (data.oMi[i].rotation @ f.linear)[:2]
            couple[n][k] = f.angular[2]
    return force, couple


@pytest.mark.parametrize("source", ["random", "study"])
@pytest.mark.parametrize("robot_name", TREES)
def test_serial_arms_against_pinocchio(robot_name, source, rng):
    robot = ps.load(robot_name)
    if source == "random":
        q, qd, qdd = random_states(rng, 50, robot.n)
    else:
        study = {"serial_2dof": "serial_2dof_cartesian_move",
                 "serial_3dof": "serial_3dof_cartesian_move"}[robot_name]
        _, _, jt = study_motion(study, np.linspace(0.0, 5.0, 51))
        q, qd, qdd = jt.q, jt.qd, jt.qdd
    loads = joint_loads(robot, q, qd, qdd)
    force, couple = _pinocchio_loads(robot_name, q, qd, qdd)
    assert set(force) == {n for n, t in zip(loads.names, loads.types) if t == "revolute"}
    ours = np.stack([loads.force[:, loads.index(n)] for n in force], axis=1)
    theirs = np.stack(list(force.values()), axis=1)
    assert rel_err(ours, theirs) < PINOCCHIO_TOL
    ours_m = np.stack([loads.couple[:, loads.index(n)] for n in couple], axis=1)
    assert rel_err(ours_m, np.stack(list(couple.values()), axis=1)) < PINOCCHIO_TOL


@pytest.mark.parametrize("robot_name", TREES + CLOSED)
def test_body_accelerations_are_the_second_derivative_of_the_frames(robot_name, rng):
    """Along q(t) = q + qd t + qdd t^2 / 2 the cg and the frame angle have at t = 0 exactly the
    generated accelerations; central second differences (h = 2e-3 and 1e-3 s, Richardson
    extrapolated) agree to O(h^4) and rounding."""
    robot = ps.load(robot_name)
    q, qd, qdd = random_states(rng, 10, robot.n)
    par = robot.parameters

    def cg_and_angle(t):
        fr = robot.frames(q + qd * t + qdd * t * t / 2)
        out = np.empty_like(fr)
        for i, b in enumerate(robot.body_names):
            cx, cy = par.get(f"cgx_{b}", 0.0), par.get(f"cgy_{b}", 0.0)
            c, s = np.cos(fr[:, i, 2]), np.sin(fr[:, i, 2])
            out[:, i] = np.stack([fr[:, i, 0] + c * cx - s * cy, fr[:, i, 1] + s * cx + c * cy,
                                  fr[:, i, 2]], axis=-1)
        return out

    def second_difference(h):
        return (cg_and_angle(h) - 2 * cg_and_angle(0.0) + cg_and_angle(-h)) / h**2

    h = 2e-3
    fd = (4 * second_difference(h / 2) - second_difference(h)) / 3  # Richardson: O(h^4)
    acc, cg = (a.transpose(0, 2, 1) for a in robot.body_motion(q, qd, qdd)[:2])
    assert rel_err(cg, cg_and_angle(0.0)[..., :2]) < 1e-14  # the cg as the frames place it
    assert rel_err(acc, fd) < 1e-8


def _sliding_studies() -> list[str]:
    """The built-in inverse-dynamics studies whose robot has a prismatic joint."""
    from planar_sym.study.builtin import names
    from planar_sym.study.run import load_study

    out = []
    for name in names():
        st = load_study(name)
        if st.kind == "inverse" and any(j["type"] == "prismatic" for j in
                                        ps.load(st.robot).library.manifest["joints"]):
            out.append(name)
    return out


@pytest.mark.parametrize("name", _sliding_studies() or [pytest.param("none", marks=pytest.mark.skip(
    reason="no built-in robot with a prismatic joint"))])
def test_prismatic_joints_balance_and_their_axial_force_is_the_actuator_force(name):
    """A prismatic joint: every body balances with its force and reaction moment; the force
    along the slide axis is the Lagrangian generalised force of its coordinate (the actuator
    force, 0 if passive), and the study reports the normal force and the moment."""
    result = run(name, 41)
    robot, _, jt = study_motion(name, result.columns["t_s"])
    loads = joint_loads(robot, jt.q, jt.qd, jt.qdd)
    res_f, res_m = free_body_residuals(robot, jt.q, jt.qd, jt.qdd, loads)
    assert res_f < FREE_BODY_TOL and res_m < FREE_BODY_TOL, (res_f, res_m)
    tau, _ = _generalised_forces(robot, jt.q, jt.qd, jt.qdd)
    scale = np.abs(loads.force).max()
    joints = {j["name"]: j for j in robot.library.manifest["joints"]}
    for name_j, axial in loads.axial.items():
        assert np.abs(axial - tau[:, joints[name_j]["coordinate"]]).max() < 1e-12 * scale
        i = loads.index(name_j)
        assert np.allclose(np.hypot(axial, loads.normal[name_j]), loads.magnitude[:, i],
                           rtol=1e-13, atol=1e-13 * scale)
        assert np.array_equal(result.columns[f"jfn_{name_j}_n"], loads.normal[name_j])
        assert np.array_equal(result.columns[f"jm_{name_j}_n_m"], loads.couple[:, i])


@pytest.mark.parametrize("robot_name", TREES + CLOSED)
def test_body_motion_against_sympy(robot_name, rng):
    """The generated body_motion against its SymPy expressions, lambdified (1e-12 relative)."""
    import sympy as sp

    from derive.model import build

    model = build(description.load(robot_name))
    s = model.sym
    exprs = [model.body_accelerations.T, model.cg_positions.T, model.joint_points.T]
    fn = sp.lambdify([*s.q, *s.qd, *s.qdd, *s.p], exprs, "numpy")
    robot = ps.load(robot_name)
    q, qd, qdd = random_states(rng, 10, robot.n)
    got = robot.body_motion(q, qd, qdd)
    for k in range(len(q)):
        want = fn(*q[k], *qd[k], *qdd[k], *robot.p)
        for a, b in zip(got, want):
            b = np.asarray(b, dtype=float)
            assert np.abs(a[k] - b).max() <= 1e-12 * np.abs(b).max()


def test_study_columns_and_the_bearing_load():
    res = run("five_bar_type1_move_x", 21)
    cols = res.columns
    robot = ps.load("five_bar_type1")
    for j in robot.library.manifest["joints"]:
        n = j["name"]
        assert np.allclose(cols[f"jload_{n}_n"], np.hypot(cols[f"jfx_{n}_n"], cols[f"jfy_{n}_n"]),
                           rtol=0, atol=0)
        assert f"jm_{n}_n_m" not in cols  # revolute: its couple is its torque column (or 0)
    for cut in robot.loops:  # the parent-on-child force is minus the force on the parent
        assert np.array_equal(cols[f"jfx_{cut}_n"], -cols[f"fx_{cut}_n"])
        assert np.array_equal(cols[f"jfy_{cut}_n"], -cols[f"fy_{cut}_n"])
    arm = run("serial_2dof_cartesian_move", 11).columns
    assert "jm_weld_motor2_n_m" in arm and "jm_joint1_n_m" not in arm
    assert "parent on child" in res.note


def test_one_sample_and_a_batch_agree():
    robot = ps.load("serial_3dof")
    q, qd, qdd = random_states(np.random.default_rng(3), 4, robot.n)
    batch = joint_loads(robot, q, qd, qdd)
    one = joint_loads(robot, q[2], qd[2], qdd[2])
    assert one.force.shape == (1, len(batch.names), 2)
    assert np.allclose(one.force[0], batch.force[2], rtol=1e-14, atol=0)
    assert one.magnitude.shape == (1, len(batch.names))
