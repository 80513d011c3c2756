"""Joint loads (``planar_sym.dynamics.reactions``) as values, against references built here
without the load computation: the survivors of mutation testing (issue 30).

1. Closed chains (the five-bar, the 3-RRR with two cuts ending on one platform, the slider-
   crank with its prismatic joint): every body's free body by hand. Loads on a body: the
   reported force and couple of each tree joint (+ on its child at the child point, - on its
   parent at the parent point, at the child point for a slider), the cut forces from the
   multipliers of ``closed_chain_inverse_dynamics`` (+lambda on the cut's parent at the parent
   point, -lambda on its child at the child point), gravity at the cg. Their sum is m a_cg and
   their moment about the cg is I alpha, the cg and angular accelerations by Richardson-
   extrapolated second differences of the generated frames along q + qd t + qdd t^2 / 2 (not
   ``body_motion``). Measured residual 2e-11 of the largest force or moment term (asserted 1e-9);
   a cut force with the wrong incidence (on the child with the parent's sign) leaves 0.82 of
   the largest force and 1.2 of the largest moment unbalanced, a cut moment with the child's
   sign flipped 1.0 of the largest moment. The cut joints' own rows are -lambda, bit for bit.
2. A point-mass pendulum (tests/robots/point_pendulum.toml: m = 1.5 kg at L = 0.6 m, no izz),
   in closed form: the pivot carries F = m (a_bob - g) and the couple m L^2 qdd + m g L cos q.
3. Refusals, word for word: a joint name that does not exist; a generated folder whose
   manifest predates joint loads (no ``joints``, no ``gravity_direction``, or neither); a
   non-finite q, qd or qdd names its array, entry, sample and time.

``joint_loads`` keeps each robot's incidence matrices in ``reactions._CACHE`` (keyed by folder,
input hash and parameters). A fixture empties it for every test here: a process that ran the
loads before (a mutation worker forked after the clean run) would otherwise reuse structures
built by the unmutated ``_structure`` and never run the mutated one.
"""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
from conftest import GENERATED, TEST_ROBOTS

import planar_sym as ps
from planar_sym.dynamics import reactions
from planar_sym.dynamics.reactions import joint_loads
from planar_sym.errors import InputError, LibraryError
from planar_sym.model.library import Library
from planar_sym.model.robot import Robot
from planar_sym.motion.closure import complete_rates, solve_passive

FREE_BODY_TOL = 1e-9  # second differences: measured 2e-11 of the largest term
CLOSED_FORM_TOL = 1e-12


@pytest.fixture(autouse=True)
def fresh_structure_cache(monkeypatch):
    monkeypatch.setattr(reactions, "_CACHE", {})


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _in_world(frames, i, x, y):
    """Body-frame point (x, y) of body i in world axes (N, 2)."""
    c, s = np.cos(frames[:, i, 2]), np.sin(frames[:, i, 2])
    return frames[:, i, :2] + np.stack([c * x - s * y, s * x + c * y], axis=-1)


def _point(robot, frames, body, point):
    p = robot.parameters
    return _in_world(frames, list(robot.body_names).index(body),
                     p.get(f"px_{body}_{point}", 0.0), p.get(f"py_{body}_{point}", 0.0))


def _cg(robot, frames, body):
    p = robot.parameters
    return _in_world(frames, list(robot.body_names).index(body),
                     p.get(f"cgx_{body}", 0.0), p.get(f"cgy_{body}", 0.0))


def _finite_difference_accelerations(robot, q, qd, qdd):
    """cg accelerations (N, bodies, 2) and angular accelerations (N, bodies) by central second
    differences along q + qd t + qdd t^2 / 2 at t = 0 (h = 2e-3 and 1e-3 s, Richardson: O(h^4))."""
    def cgs_and_angles(t):
        fr = robot.frames(q + qd * t + qdd * t * t / 2)
        cgs = np.stack([_cg(robot, fr, b) for b in robot.body_names], axis=1)
        return cgs, fr[:, :, 2]

    def second_difference(h):
        (c_p, a_p), (c_0, a_0), (c_m, a_m) = (cgs_and_angles(t) for t in (h, 0.0, -h))
        wrap = lambda x: (x + np.pi) % (2 * np.pi) - np.pi
        return (c_p - 2 * c_0 + c_m) / h**2, (wrap(a_p - a_0) + wrap(a_m - a_0)) / h**2

    (c1, a1), (c2, a2) = second_difference(1e-3), second_difference(2e-3)
    return (4 * c1 - c2) / 3, (4 * a1 - a2) / 3


def _closed_states(robot, rng, n_s=12):
    """States on the loops near the drawn pose (Newton for the passive joints), random actuated
    rates and accelerations (rad/s, rad/s^2; m/s, m/s^2 at a slider)."""
    act = list(robot.actuated)
    q_act = robot.q_drawn[act] + rng.uniform(-0.05, 0.05, (n_s, len(act)))
    q = np.vstack([solve_passive(robot, qa[None], robot.q_drawn) for qa in q_act])
    qd, qdd = complete_rates(robot, q, rng.uniform(-2, 2, (n_s, len(act))),
                             rng.uniform(-2, 2, (n_s, len(act))))
    return q, qd, qdd


def free_body_by_hand(robot, q, qd, qdd, loads, lam):
    """Worst force and moment residual of every body, relative to the largest term of each."""
    par, manifest = robot.parameters, robot.library.manifest
    frames = robot.frames(q)
    a_cg, alpha = _finite_difference_accelerations(robot, q, qd, qdd)
    bodies = list(robot.body_names)
    n_s = len(q)
    gravity = par["g"] * np.array(manifest["gravity_direction"])
    forces = {b: [(_cg(robot, frames, b), np.broadcast_to(par[f"m_{b}"] * gravity, (n_s, 2)))]
              for b in bodies}
    couples = {b: [] for b in bodies}
    cut = 0
    for j in manifest["joints"]:
        at_child = _point(robot, frames, j["child"], j["child_point"])
        if j["closes_loop"]:  # lambda: the child on the parent
            f = lam[:, 2 * cut:2 * cut + 2]
            cut += 1
            if j["parent"] != "ground":
                forces[j["parent"]].append(
                    (_point(robot, frames, j["parent"], j["parent_point"]), f))
            if j["child"] != "ground":
                forces[j["child"]].append((at_child, -f))
            continue
        k = loads.index(j["name"])
        force, couple = loads.force[:, k], loads.couple[:, k]
        forces[j["child"]].append((at_child, force))
        couples[j["child"]].append(couple)
        if j["parent"] != "ground":
            at_parent = (at_child if j["type"] == "prismatic"
                         else _point(robot, frames, j["parent"], j["parent_point"]))
            forces[j["parent"]].append((at_parent, -force))
            couples[j["parent"]].append(-couple)
    res_f, res_m, terms_f, terms_m = [], [], [], []
    for i, b in enumerate(bodies):
        c = _cg(robot, frames, b)
        inertial_f = par[f"m_{b}"] * a_cg[:, i]
        inertial_m = par.get(f"izz_{b}", 0.0) * alpha[:, i]
        moments = [_cross(r - c, f) for r, f in forces[b]] + couples[b]
        res_f.append(sum(f for _, f in forces[b]) - inertial_f)
        res_m.append(sum(moments) - inertial_m)
        terms_f += [f for _, f in forces[b]] + [inertial_f]
        terms_m += moments + [inertial_m]
    scale_f = max(float(np.abs(f).max()) for f in terms_f)
    scale_m = max(float(np.abs(m).max()) for m in terms_m)
    return (max(float(np.abs(r).max()) for r in res_f) / scale_f,
            max(float(np.abs(r).max()) for r in res_m) / scale_m)


@pytest.mark.parametrize("name", ["five_bar_type1", "parallel_3rrr", "slider_crank"])
def test_closed_chains_every_body_balances_by_hand(name):
    robot = ps.load(name)
    q, qd, qdd = _closed_states(robot, np.random.default_rng(30))
    _, lam = robot.closed_chain_inverse_dynamics(q, qd, qdd)
    loads = joint_loads(robot, q, qd, qdd)
    assert loads.force.dtype == np.float64 and np.isfinite(loads.force).all()
    for k, cut in enumerate(robot.loops):  # parent on child: -lambda, bit for bit
        assert np.array_equal(loads.force[:, loads.index(cut)], -lam[:, 2 * k:2 * k + 2])
        assert not np.any(loads.couple[:, loads.index(cut)])
    # the cut forces are a large part of the balance: a wrong incidence would show
    assert np.abs(lam).max() > 0.2 * np.abs(loads.force).max()
    res_f, res_m = free_body_by_hand(robot, q, qd, qdd, loads, lam)
    assert res_f < FREE_BODY_TOL and res_m < FREE_BODY_TOL, (res_f, res_m)


def test_point_pendulum_bearing_load_and_couple_in_closed_form():
    """A bob of m = 1.5 kg at L = 0.6 m on a massless rod (no izz parameter): the pivot pushes
    F = m (a_bob - g), a_bob = L (-s qdd - c qd^2, c qdd - s qd^2), g = (0, -9.81) m/s^2; the
    couple is m L^2 qdd + m g L cos q; |F| is the bearing load."""
    robot = ps.load(TEST_ROBOTS / "point_pendulum.toml")
    m, length, g = 1.5, 0.6, 9.81
    assert robot.parameters == {"g": g, "m_rod": m, "cgx_rod": length}
    rng = np.random.default_rng(7)
    q, qd, qdd = (rng.uniform(-3, 3, (40, 1)) for _ in range(3))
    loads = joint_loads(robot, q, qd, qdd)
    s, c = np.sin(q[:, 0]), np.cos(q[:, 0])
    force = m * np.column_stack([length * (-s * qdd[:, 0] - c * qd[:, 0] ** 2),
                                 length * (c * qdd[:, 0] - s * qd[:, 0] ** 2) + g])
    couple = m * length**2 * qdd[:, 0] + m * g * length * c
    assert loads.names == ("pivot",) and loads.types == ("revolute",)
    scale = np.abs(force).max()
    assert np.abs(loads.force[:, 0] - force).max() < CLOSED_FORM_TOL * scale
    assert np.abs(loads.magnitude[:, 0] - np.hypot(*force.T)).max() < CLOSED_FORM_TOL * scale
    assert np.abs(loads.couple[:, 0] - couple).max() < CLOSED_FORM_TOL * np.abs(couple).max()
    assert loads.axial == {} and loads.normal == {}


# -- refusals, word for word ---------------------------------------------------------------------

def test_a_joint_that_does_not_exist():
    loads = joint_loads(ps.load("serial_2dof"), [0.1, 0.2], [0.0, 0.0], [0.0, 0.0])
    assert loads.index("joint2") == 2
    with pytest.raises(InputError) as exc:
        loads.index("elbow")
    assert str(exc.value) == "no joint 'elbow'; joints: joint1, weld_motor2, joint2"


@pytest.mark.parametrize("dropped", [("joints",), ("gravity_direction",),
                                     ("joints", "gravity_direction")])
def test_a_manifest_from_before_joint_loads(dropped, tmp_path):
    folder = tmp_path / "serial_2dof"
    shutil.copytree(GENERATED / "serial_2dof", folder)
    manifest = json.loads((folder / "manifest.json").read_text())
    for key in dropped:
        manifest.pop(key)
    (folder / "manifest.json").write_text(json.dumps(manifest, indent=2))
    robot = Robot("serial_2dof", Library("serial_2dof", folder=folder))
    with pytest.raises(LibraryError) as exc:
        joint_loads(robot, [0.1, 0.2], [0.0, 0.0], [0.0, 0.0])
    assert str(exc.value) == (
        f"serial_2dof: the generated code in {folder} predates joint loads (its manifest lists "
        "no joints): re-derive it (`make derive`, or `planar-sym derive` for your own robot)")


@pytest.mark.parametrize("which", ["q", "qd", "qdd"])
def test_a_non_finite_input_is_named_with_its_time(which):
    robot = ps.load("serial_2dof")
    arrays = {k: np.full((3, 2), 0.5) for k in ("q", "qd", "qdd")}
    arrays[which][1, 1] = np.nan
    with pytest.raises(InputError) as exc:
        joint_loads(robot, *arrays.values(), t=np.array([0.0, 0.25, 0.5]))
    assert str(exc.value) == (f"{which}[1, 1] is nan at sample 1 (t = 0.25 s): inputs must be "
                              "finite")


@pytest.mark.parametrize("q", [(0.4, -1.1), (-2.0, 0.7), (1.3, 2.9)])
def test_weights_under_tilted_gravity(q):
    """At rest under gravity (1.2, -9.7) m/s^2 (bent_arm: every other robot's gravity is along
    -y, so an x weight term would go unseen): each joint carries minus the weight of every
    body beyond it, by hand from the masses; the revolute joints' couples are the Lagrangian
    gravity torques g(q), a second route to the same moments."""
    robot = ps.load(TEST_ROBOTS / "bent_arm.toml")
    g_vec = np.array([1.2, -9.7])
    assert robot.parameters["g"] == pytest.approx(np.hypot(*g_vec), rel=1e-15)
    mass = {b: robot.parameters[f"m_{b}"] for b in robot.body_names}
    beyond = {"joint1": ("link1", "bracket", "link2"), "weld_bracket": ("bracket", "link2"),
              "joint2": ("link2",)}
    z = np.zeros(2)
    loads = joint_loads(robot, np.array(q), z, z)
    assert loads.names == tuple(beyond)
    for k, name in enumerate(loads.names):
        want = -sum(mass[b] for b in beyond[name]) * g_vec
        assert loads.force[0, k] == pytest.approx(want, rel=1e-12, abs=1e-14), name
    grav = robot.gravity(np.array(q))
    assert loads.couple[0, 0] == pytest.approx(grav[0], rel=1e-12, abs=1e-14)
    assert loads.couple[0, 2] == pytest.approx(grav[1], rel=1e-12, abs=1e-14)


def test_a_given_inverse_is_used_as_given_for_one_sample_and_many():
    """``inverse=`` hands joint_loads the inverse dynamics it would compute (not computed
    twice): for one sample given 1-D, as the robot returns it for a 1-D q, the loads equal
    those computed from scratch; a different tau given is the drive torque reported (so it is
    used, not recomputed)."""
    for name in ("serial_2dof", "five_bar_type1"):
        robot = ps.load(name)
        q = np.array(robot.q_drawn, dtype=float)
        qd, qdd = np.linspace(0.1, 0.4, robot.n), np.linspace(-0.3, 0.2, robot.n)
        if robot.is_closed_chain:  # on the loops: the actuated rates give the rest
            from planar_sym.motion.closure import from_actuated

            act = list(robot.actuated)
            jt = from_actuated(robot, [0.0], q[act][None], qd[act][None], qdd[act][None])
            q, qd, qdd = jt.q[0], jt.qd[0], jt.qdd[0]
            inverse = robot.closed_chain_inverse_dynamics(q, qd, qdd)
        else:
            inverse = (robot.tree_inverse_dynamics(q, qd, qdd), None)
        scratch = joint_loads(robot, q, qd, qdd)
        given = joint_loads(robot, q, qd, qdd, inverse=inverse)
        assert np.array_equal(given.force, scratch.force), name
        assert np.array_equal(given.couple, scratch.couple), name
        doubled = (2 * np.asarray(inverse[0]), inverse[1])
        twice = joint_loads(robot, q, qd, qdd, inverse=doubled)
        for joint, tau in scratch.drive.items():
            assert np.array_equal(twice.drive[joint], 2 * tau), (name, joint)
