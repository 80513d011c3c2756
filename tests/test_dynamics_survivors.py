"""Survivors of mutation testing in dynamics/ and control/track.py (issue 30), each killed by a
value checked against something computed here without the code under test.

Joint loads (``planar_sym.dynamics.reactions``):

* tilted gravity (``tests/robots/bent_arm.toml``: gravity = [1.2, -9.7] m/s^2, its x part not
  zero): at the drawn pose at rest every joint carries its subtree's weight and its moment, in
  closed form from the description file's own numbers (masses in g, points in mm, read here
  with tomllib); moving, each tree joint's force is the sum of m (a_cg - g) over its subtree,
  the cg accelerations by Richardson-extrapolated second differences of the generated frames
  (not ``body_motion``). A weight added instead of subtracted along x is 0.91 N off at the base
  (of 3.7 N);
* every field of the result by value: names and types as the file lists the joints, the drive
  torque the inverse dynamics' tau and the motor torque tau / N with N read from the file
  (``examples/serial_2dof_geared.toml``, N = 50: tau * N would be 2500 times off), a slider's
  axial and normal force against its own axis found by differences of the frames
  (``serial_rpr``: the axial force is the slide's Lagrangian force, no drive model there);
* a closed chain's refused sample is named by its time;
* the memo of structures is keyed by the folder too: a stale copy of a robot's generated code
  (same input hash and parameters, no joints in its manifest) is refused after the fresh one
  was memoised.

Inverse dynamics along a motion (``dynamics.along``): times that are not real numbers are
refused as times, word for word.

Tracking (``control.track``): the reference up to its end + 1e-12 s is the Hermite through the
samples, not held; a run started in a type-II singular pose of the five-bar (built here: the
distal links in line, cond_1(Phi_p) about 1e16) has its split refused by the time; the time-
varying LQR law feeds forward the inverse dynamics (compared with the compiled Lagrangian at
the start, where the error is zero) or the torques given, saturated at the file's motor limit
times the gear ratio, and its refusals carry the study's name.

Closed-chain forward dynamics (``dynamics.forward_closed.simulate_closed``): the default drift
limit (1e-6 m) refuses a loose run that drifts 2 mm; SciPy's failure names the time reached;
``project_state=True`` solves the passive joints of a start off the loops, the default refuses
it; the result carries the robot's labels.

Sizing (``dynamics.sizing``): a motor torque exactly on its allowance, limit x (1 + 1e-6), is
within (the gear ratio set to 64 so tau / N is exact); the next float up is reported.

Each test computes its loads itself (no module-scoped fixture): mutmut runs, for each mutant,
only the tests recorded as reaching the function, and a fixture shared by a module is recorded
for its first test only.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from conftest import ROOT, TEST_ROBOTS

import planar_sym as ps
from planar_sym.dynamics import reactions
from planar_sym.dynamics.along import inverse_along
from planar_sym.dynamics.reactions import joint_loads
from planar_sym.errors import InputError

BENT = TEST_ROBOTS / "bent_arm.toml"
GEARED = ROOT / "examples" / "serial_2dof_geared.toml"


@pytest.fixture(autouse=True)
def fresh_structure_cache(monkeypatch):
    """joint_loads memoises each robot's structure: built anew here, so the code under test
    (a mutant too) builds it."""
    monkeypatch.setattr(reactions, "_CACHE", {})


def _toml(path):
    return tomllib.loads(path.read_text())


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _cg_world(robot, frames):
    """Every body's cg in world axes (N, bodies, 2), from the generated frames."""
    p, out = robot.parameters, []
    for i, b in enumerate(robot.body_names):
        c, s = np.cos(frames[:, i, 2]), np.sin(frames[:, i, 2])
        x, y = p.get(f"cgx_{b}", 0.0), p.get(f"cgy_{b}", 0.0)
        out.append(frames[:, i, :2] + np.stack([c * x - s * y, s * x + c * y], axis=-1))
    return np.stack(out, axis=1)


def _cg_accelerations(robot, q, qd, qdd):
    """cg accelerations (N, bodies, 2) by second differences along q + qd t + qdd t^2 / 2
    (h = 1e-3 and 2e-3 s, Richardson: O(h^4))."""
    def at(t):
        return _cg_world(robot, robot.frames(q + qd * t + qdd * t * t / 2))

    def second(h):
        return (at(h) - 2 * at(0.0) + at(-h)) / h**2

    return (4 * second(1e-3) - second(2e-3)) / 3


# -- joint loads: tilted gravity ----------------------------------------------------------------

def test_tilted_gravity_at_rest_in_closed_form():
    """bent_arm at its drawn pose, at rest: a joint's force is minus its subtree's weight,
    -sum m g, and its couple minus the weights' moment about the joint point,
    -sum (r_cg - r_joint) x m g; every number from the file (g, mm, kg*mm^2 as typed)."""
    d = _toml(BENT)
    g = np.array(d["gravity"])  # m/s^2
    assert g[0] != 0.0  # the x part the loads must subtract
    mass = {b["name"]: b["mass"] * 1e-3 for b in d["bodies"]}  # g -> kg
    point = {(b["name"], k): np.array(v) * 1e-3 for b in d["bodies"]
             for k, v in b["points"].items()}
    cg = {b["name"]: point[b["name"], b["cg_from"]] + np.array(b["cg"]) * 1e-3
          for b in d["bodies"]}  # world, drawn pose
    origin = np.array(d["ground"]["points"]["O"]) * 1e-3
    subtree = {"joint1": ("link1", "bracket", "link2"), "weld_bracket": ("bracket", "link2"),
               "joint2": ("link2",)}
    at = {"joint1": origin, "weld_bracket": point["link1", "CS2"],
          "joint2": point["bracket", "CS2"]}
    robot = ps.load(BENT)
    zero = np.zeros((1, robot.n))
    loads = joint_loads(robot, robot.q_drawn[None], zero, zero)
    assert loads.names == ("joint1", "weld_bracket", "joint2")
    for name, bodies in subtree.items():
        k = loads.index(name)
        force = -sum(mass[b] for b in bodies) * g
        couple = -sum(_cross(cg[b] - at[name], mass[b] * g) for b in bodies)
        assert np.abs(loads.force[0, k] - force).max() < 1e-12 * 4, (name, loads.force[0, k], force)
        assert abs(loads.couple[0, k] - couple) < 1e-12, (name, loads.couple[0, k], couple)


def test_tilted_gravity_moving_subtree_sums():
    """bent_arm moving: each tree joint's force is sum over its subtree of m (a_cg - g), a_cg
    by differences of the generated frames, g the file's [1.2, -9.7] m/s^2."""
    d = _toml(BENT)
    g = np.array(d["gravity"])
    robot = ps.load(BENT)
    rng = np.random.default_rng(3)
    n_s = 8
    q = robot.q_drawn + rng.uniform(-1.5, 1.5, (n_s, robot.n))
    qd, qdd = rng.uniform(-3, 3, (n_s, robot.n)), rng.uniform(-5, 5, (n_s, robot.n))
    loads = joint_loads(robot, q, qd, qdd)
    a_cg = _cg_accelerations(robot, q, qd, qdd)  # (N, bodies, 2)
    bodies = list(robot.body_names)
    mass = np.array([b["mass"] * 1e-3 for b in d["bodies"]])
    assert [b["name"] for b in d["bodies"]] == bodies
    inertial = mass[None, :, None] * (a_cg - g)  # (N, bodies, 2)
    for name, below in (("joint1", bodies), ("weld_bracket", ["bracket", "link2"]),
                        ("joint2", ["link2"])):
        want = inertial[:, [bodies.index(b) for b in below]].sum(axis=1)
        got = loads.force[:, loads.index(name)]
        assert np.abs(got - want).max() < 1e-7 * np.abs(want).max(), name


# -- joint loads: every field by value ----------------------------------------------------------

def test_geared_arm_every_field():
    """The geared 2-DOF arm: names and types as the file lists its joints; drive is the
    inverse dynamics' tau (rotor and friction in it), motor_torque tau / N with the file's
    N = 50, at every actuated joint and nowhere else; no slider, so no axial or normal force;
    the forces are the subtrees' m (a_cg - g) sums, and at rest the couples the gravity
    torques (friction and rotor spin vanish at rest)."""
    d = _toml(GEARED)
    robot = ps.load(GEARED)
    rng = np.random.default_rng(5)
    n_s = 6
    q = robot.q_drawn + rng.uniform(-1, 1, (n_s, robot.n))
    qd, qdd = rng.uniform(-2, 2, (n_s, robot.n)), rng.uniform(-4, 4, (n_s, robot.n))
    loads = joint_loads(robot, q, qd, qdd)
    assert loads.names == tuple(j["name"] for j in d["joints"])
    assert loads.types == tuple(j["type"] for j in d["joints"])
    tau = robot.inverse_dynamics(q, qd, qdd)
    ratio = {j["name"]: j["actuator"]["gear_ratio"] for j in d["joints"] if "actuator" in j}
    assert ratio == {"joint1": 50, "joint2": 50}
    assert set(loads.drive) == set(ratio) == set(loads.motor_torque)
    for c, name in enumerate(("joint1", "joint2")):
        assert np.array_equal(loads.drive[name], tau[:, c])
        want = tau[:, c] / ratio[name]
        assert np.abs(loads.motor_torque[name] - want).max() <= 1e-15 * np.abs(want).max()
    assert loads.axial == {} and loads.normal == {}
    assert loads.force.shape == (n_s, 3, 2) and loads.couple.shape == (n_s, 3)
    # forces: subtree sums of m (a_cg - g), from the file's masses and gravity
    g = np.array(d["gravity"])
    mass = np.array([b["mass"] for b in d["bodies"]])  # kg
    inertial = mass[None, :, None] * (_cg_accelerations(robot, q, qd, qdd) - g)
    for name, below in (("joint1", [0, 1, 2]), ("weld_motor2", [1]), ("joint2", [2])):
        want = inertial[:, below].sum(axis=1)
        assert np.abs(loads.force[:, loads.index(name)] - want).max() < \
            1e-7 * np.abs(want).max(), name
    assert np.array_equal(loads.magnitude, np.hypot(loads.force[..., 0], loads.force[..., 1]))
    # at rest: each couple is minus the moment of its subtree's weights about the joint point
    zero = np.zeros((n_s, robot.n))
    rest = joint_loads(robot, q, zero, zero)
    frames = robot.frames(q)
    cgs = _cg_world(robot, frames)
    elbow = frames[:, 2, :2]  # link2's frame origin is its CS1, the elbow (motor2 welded there)
    w = mass[None, :, None] * g
    want = {"joint1": -_cross(cgs, w).sum(axis=1),
            "weld_motor2": -_cross(cgs[:, 1] - elbow, w[:, 1]),
            "joint2": -_cross(cgs[:, 2] - elbow, w[:, 2])}
    for name, m in want.items():
        assert np.abs(rest.couple[:, rest.index(name)] - m).max() < 1e-12, name


def test_slider_axial_and_normal_against_its_axis():
    """serial_rpr: the boom slides along an axis that turns with the sleeve; found here as the
    boom frame's displacement per metre of slide (differences of the frames), the axial force
    F . u is the slide's Lagrangian force (no drive model: nothing between) and the normal
    force F . (k x u)."""
    robot = ps.load("serial_rpr")
    rng = np.random.default_rng(9)
    n_s = 6
    q = robot.q_drawn + rng.uniform(-0.5, 0.5, (n_s, robot.n))
    qd, qdd = rng.uniform(-2, 2, (n_s, robot.n)), rng.uniform(-3, 3, (n_s, robot.n))
    loads = joint_loads(robot, q, qd, qdd)
    assert loads.types == ("revolute", "prismatic", "revolute")
    assert set(loads.axial) == set(loads.normal) == {"extend"}
    step = np.zeros(robot.n)
    step[1] = 1e-3
    boom = list(robot.body_names).index("boom")
    u = (robot.frames(q + step)[:, boom, :2] - robot.frames(q - step)[:, boom, :2]) / 2e-3
    assert np.allclose(np.hypot(*u.T), 1.0, atol=1e-9)
    f = loads.force[:, loads.index("extend")]
    tau = robot.inverse_dynamics(q, qd, qdd)
    assert np.abs(loads.axial["extend"] - tau[:, 1]).max() < 1e-12 * np.abs(tau[:, 1]).max()
    assert np.abs(loads.axial["extend"] - (f * u).sum(axis=1)).max() < 1e-9 * np.abs(f).max()
    normal = f[:, 1] * u[:, 0] - f[:, 0] * u[:, 1]
    assert np.abs(loads.normal["extend"] - normal).max() < 1e-9 * np.abs(f).max()
    assert np.abs(normal).max() > 0.1 * np.abs(f).max()  # not a vanishing part
    motor = {d.joint: d.gear_ratio for d in robot.drive_train.drives}
    for c, name in enumerate(("shoulder", "extend", "wrist")):
        assert np.array_equal(loads.drive[name], tau[:, c])
        assert np.array_equal(loads.motor_torque[name], tau[:, c] / motor[name])


def test_closed_chain_refusal_names_the_time():
    """A closed-chain sample off the loops is refused by its time when times are given."""
    robot = ps.load("five_bar_type1")
    q = np.array([robot.q_drawn, robot.q_drawn + 0.3])
    zero = np.zeros_like(q)
    with pytest.raises(InputError) as info:
        joint_loads(robot, q, zero, zero, t=[0.25, 0.75])
    assert str(info.value).startswith(
        "five_bar_type1: sample 1 (t = 0.75 s) is off the loop constraints: ")


# -- inverse_along ------------------------------------------------------------------------------

@pytest.mark.parametrize("t_s,why", [
    (["a", "b"], "could not convert string to float: 'a'"),
    ([0j, 1j], "float() argument must be a string or a real number, not 'complex'")])
def test_inverse_along_times_must_be_real_numbers(t_s, why):
    """Times that are not real numbers are refused as times, with NumPy's reason (not as a
    sample array of shape (N, 1), nor as complex samples)."""
    robot = ps.load("serial_2dof")
    q = np.array([[0.1, 0.2], [0.2, 0.3]])
    with pytest.raises(InputError) as info:
        inverse_along(robot, t_s, q, np.zeros_like(q), np.zeros_like(q))
    assert str(info.value) == f"t_s must be an array of numbers, one time (s) per sample: {why}"


# -- control.track.reference ---------------------------------------------------------------------

def test_reference_within_a_picosecond_of_the_end_is_not_held():
    """A motion that ends moving, asked up to its end + 1e-12 s (the tolerance, inclusive), is
    the plain quintic Hermite through its samples (no hold, no refusal: its end segment
    extends); 1e-12 s beyond that tolerance it must be held, and is refused as ending moving."""
    from planar_sym.control.track import reference
    from planar_sym.motion.profiles import JointTrajectory

    t = np.array([0.0, 0.5, 1.0])
    q = np.array([[0.0, 0.1], [0.3, 0.2], [0.5, 0.4]])
    qd = np.array([[0.0, 0.0], [0.6, 0.3], [0.4, 0.2]])  # moving at the end
    qdd = np.array([[0.0, 0.0], [0.1, 0.1], [-0.2, 0.0]])
    jt = JointTrajectory(t, q, qd, qdd)
    ref = reference(jt, 1.0 + 1e-12, "")
    assert np.array_equal(ref.knots_s, t)  # not extended by a held segment
    assert np.abs(ref(t) - q).max() < 1e-15 and np.abs(ref(t, 1) - qd).max() < 1e-14
    with pytest.raises(InputError) as info:
        reference(jt, 1.0 + 2e-12, "")
    assert str(info.value).startswith("duration_s 1 s outlasts the motion (1 s), which ends "
                                      "moving (0.4 per s)")


def _five_bar_stretched(robot):
    """five_bar_type1 with its distal links in line (B, C, D collinear, C between): a type-II
    singular pose on the loops. Link1 at 2.25 rad; the right crank found so |BD| is the two
    distal lengths (Brent on the generated frames), the distal links then laid along BD."""
    from scipy.optimize import brentq

    p, bodies = robot.parameters, list(robot.body_names)
    c_left = np.array([p["px_L_Link2_CS2"], p.get("py_L_Link2_CS2", 0.0)])  # C in each frame
    c_right = np.array([p["px_R_Link2_CS2"], p.get("py_R_Link2_CS2", 0.0)])
    reach = np.hypot(*c_left) + np.hypot(*c_right)
    a = 2.25

    def frames(q_e):
        return robot.frames(np.array([[a, 0.0, q_e, 0.0]]))[0]

    def gap(q_e):
        f = frames(q_e)
        return np.hypot(*(f[bodies.index("R_Link2"), :2] - f[bodies.index("L_Link2"), :2])) - reach

    q_e = brentq(gap, 0.8, 1.0, xtol=1e-16)
    f = frames(q_e)
    b_to_d = f[bodies.index("R_Link2"), :2] - f[bodies.index("L_Link2"), :2]
    along = np.arctan2(b_to_d[1], b_to_d[0])
    q = np.array([a, along - np.arctan2(c_left[1], c_left[0]) - f[bodies.index("L_Link1"), 2],
                  q_e, along + np.pi - np.arctan2(c_right[1], c_right[0])
                  - f[bodies.index("R_Link1"), 2]])
    return (q + np.pi) % (2 * np.pi) - np.pi


def test_track_through_a_singular_pose_names_its_time():
    """A closed chain started at rest in a type-II singular pose (five_bar_type1, distal links
    in line: cond_1(Phi_p) about 1e16; its KKT system stays regular, so the run goes on): the
    split of the applied torques cannot be formed there and names the sample by its time."""
    from planar_sym.control.track import Tracking, track
    from planar_sym.errors import WorkspaceError
    from planar_sym.motion.profiles import JointTrajectory

    robot = ps.load("five_bar_type1")
    q = _five_bar_stretched(robot)
    assert np.abs(robot.constraint(q)).max() < 1e-15
    jac = robot.constraint_jacobian(q).reshape(2, 4)[:, list(robot.passive)]
    assert np.linalg.cond(jac, 1) > 1e12
    t = np.array([0.0, 0.05, 0.1])
    jt = JointTrajectory(t, np.tile(q, (3, 1)), np.zeros((3, 4)), np.zeros((3, 4)))
    with pytest.raises(WorkspaceError) as info:
        track(robot, Tracking(jt, law="none", samples=3))
    assert str(info.value).startswith("five_bar_type1: singular pose at t = 0 s (sample 0): ")


# -- control.track with the time-varying LQR law ------------------------------------------------

def _geared_move():
    """The geared arm (examples/serial_2dof_geared.toml) from (0, 0.5) to (0.6, 1.0) rad in
    0.5 s, a quintic at rest at both ends, 11 samples, and its inverse dynamics (tau from the
    compiled Lagrangian directly, not through inverse_along)."""
    from planar_sym.motion.profiles import JointTrajectory

    robot = ps.load(GEARED)
    t = np.linspace(0.0, 0.5, 11)
    s = t / 0.5
    a, b = np.array([0.0, 0.5]), np.array([0.6, 1.0])
    p = 10 * s**3 - 15 * s**4 + 6 * s**5
    dp = (30 * s**2 - 60 * s**3 + 30 * s**4) / 0.5
    ddp = (60 * s - 180 * s**2 + 120 * s**3) / 0.25
    q, qd, qdd = a + np.outer(p, b - a), np.outer(dp, b - a), np.outer(ddp, b - a)
    return robot, JointTrajectory(t, q, qd, qdd), robot.inverse_dynamics(q, qd, qdd)


def test_track_lqr_feeds_the_inverse_dynamics_forward():
    """law "lqr" without torques: the feed-forward is the motion's inverse dynamics, so a run
    started on the motion applies exactly tau(q0, qd0, qdd0) at t = 0 (no error yet) and
    follows the motion (within 1e-3 rad; measured 6.5e-4 with the torques linear between
    0.05 s samples)."""
    from planar_sym.control.track import Tracking, track

    robot, jt, tau = _geared_move()
    out = track(robot, Tracking(jt, law="lqr", q_weight=1.0, r_weight=1.0, samples=11,
                                saturate=False))
    assert np.abs(out.run.tau[0] - tau[0]).max() < 1e-12 * np.abs(tau[0]).max()
    assert np.abs(out.run.q - jt.q).max() < 1e-3
    assert np.abs(out.run.tau).max() > 0.5  # above the motor's limit x N: not clipped


def test_track_lqr_given_torques_saturated_at_the_motor_limit():
    """Given torques (1.5 x the inverse dynamics) are the feed-forward as given; saturated at
    the file's motor_torque_limit x gear_ratio = 0.01 x 50 = 0.5 N*m at the joint, the
    command is not."""
    from planar_sym.control.track import Tracking, track

    robot, jt, tau = _geared_move()
    d = _toml(GEARED)
    limit = [j["actuator"]["motor_torque_limit"] * j["actuator"]["gear_ratio"]
             for j in d["joints"] if "actuator" in j]
    assert limit == [0.5, 0.5] and 1.5 * tau[0, 0] > 0.5 > 1.5 * abs(tau[0, 1])
    out = track(robot, Tracking(jt, law="lqr", q_weight=1.0, r_weight=1.0, samples=11,
                                tau=1.5 * tau))
    assert np.abs(out.run.tau_cmd[0] - 1.5 * tau[0]).max() < 1e-12
    assert np.abs(out.run.tau[0] - [0.5, 1.5 * tau[0, 1]]).max() < 1e-12
    assert np.abs(out.run.tau).max() <= 0.5 * (1 + 1e-12)


@pytest.mark.parametrize("where", ["", "S1"])
def test_track_lqr_refusals_name_the_study(where):
    """Missing weights (either) are refused by track, an error of tvlqr (weights of the wrong
    shape) is passed on prefixed by the study's name, word for word tvlqr's own."""
    from planar_sym.control.track import Tracking, track

    robot, jt, tau = _geared_move()
    lead = f"{where}: " if where else ""
    for q_w, r_w in ((None, 1.0), (1.0, None)):
        with pytest.raises(InputError) as info:
            track(robot, Tracking(jt, law="lqr", q_weight=q_w, r_weight=r_w, where=where))
        assert str(info.value) == f'{lead}law "lqr" needs q_weight and r_weight'
    with pytest.raises(InputError) as own:
        ps.tvlqr(robot, jt, tau, q_weight=[1.0, 2.0, 3.0], r_weight=1.0)
    with pytest.raises(InputError) as info:
        track(robot, Tracking(jt, law="lqr", q_weight=[1.0, 2.0, 3.0], r_weight=1.0,
                              where=where))
    assert str(info.value) == lead + str(own.value)


# -- forward dynamics of a closed chain ----------------------------------------------------------

def test_simulate_closed_default_drift_limit_is_a_micrometre():
    """slider_crank under 1 N*m at rtol = atol = 1e-2 over one 0.1 s segment drifts off its
    loop by about 2 mm (measured with the limit raised to 1 m): with the default limit, 1e-6 m,
    that segment is refused, naming its drift and the limit; the result of the run allowed to
    drift names the robot, its coordinates' units and its actuated joint."""
    from planar_sym.dynamics.forward_closed import simulate_closed
    from planar_sym.errors import SimulationError

    robot = ps.load("slider_crank")
    args = (robot, robot.q_drawn, np.zeros(3), (0.0, 0.1))
    kw = {"t_eval": [0.0, 0.1], "torque": [1.0], "rtol": 1e-2, "atol": 1e-2}
    loose = simulate_closed(*args, **kw, drift_limit_m=1.0)
    drift = np.abs(robot.constraint(loose.q)).max()
    assert 1e-4 < drift < 1e-1 and loose.constraint_drift_m == drift
    assert (loose.robot, loose.coordinate_units, loose.actuated) == (
        "slider_crank", tuple(robot.coordinate_units), (0,))
    assert loose.coordinate_units == ("rad", "rad", "m")
    with pytest.raises(SimulationError) as info:
        simulate_closed(*args, **kw)
    assert str(info.value).startswith(
        f"slider_crank: the loops drifted apart by {drift:.3g} m between t = 0 s and 0.1 s "
        "(limit 1e-06 m): ")


def test_simulate_closed_scipy_failure_names_the_time():
    """A torque that changes sign faster than any step can resolve (100 sin(1e20 t) N*m: its
    value at neighbouring floats is unrelated) makes SciPy give up on its first step: the
    refusal names the time it reached, the start, 1 s."""
    from planar_sym.dynamics.forward_closed import simulate_closed
    from planar_sym.errors import SimulationError

    robot = ps.load("slider_crank")
    with pytest.raises(SimulationError) as info:
        simulate_closed(robot, robot.q_drawn, np.zeros(3), (1.0, 1.1), t_eval=[1.0, 1.1],
                        torque=lambda t: np.array([100.0 * np.sin(1e20 * t)]), method="RK23")
    assert str(info.value) == ("slider_crank: integration failed at t = 1 s: Required step "
                               "size is less than spacing between numbers.")


def test_simulate_closed_project_state_solves_the_passive_joints():
    """project_state=True from a start off the loops (the passive joints 0.05 rad/m off):
    the run starts on the loops with the actuated joint where it was given, and reports how
    far the passive joints were moved; without it the start is refused."""
    from planar_sym.dynamics.forward_closed import simulate_closed

    robot = ps.load("slider_crank")
    q0 = robot.q_drawn + np.array([0.0, 0.05, 0.05])
    sim = simulate_closed(robot, q0, np.zeros(3), (0.0, 0.01), t_eval=[0.0, 0.01],
                          project_state=True)
    assert sim.q[0, 0] == q0[0]
    assert np.abs(robot.constraint(sim.q[:1])).max() < 1e-12
    assert sim.initial_correction_rad == np.abs(sim.q[0] - q0).max() > 0.01
    with pytest.raises(InputError):
        simulate_closed(robot, q0, np.zeros(3), (0.0, 0.01), t_eval=[0.0, 0.01])


# -- sizing: a limit's allowance is inclusive ----------------------------------------------------

def test_a_motor_torque_exactly_on_its_allowance_is_within():
    """The geared arm's motor torque limit is 0.01 N*m (the file), allowed to 1 + 1e-6 of it (an
    optimal motion rides its limits): with the gear ratio set to 64 (a power of two: tau / 64
    is exact), a joint torque whose motor torque is exactly 0.01 * (1 + 1e-6) is within; the
    next float up is reported, with its time and peak."""
    from planar_sym.dynamics.sizing import ON_LIMIT, size

    robot = ps.load(GEARED).with_parameters(gear_joint1=64.0)
    limit = _toml(GEARED)["joints"][0]["actuator"]["motor_torque_limit"]
    on = limit * (1 + ON_LIMIT)
    assert (on * 64) / 64 == on
    t, qd = np.array([0.0, 0.5, 1.0]), np.zeros((3, 2))
    over = ("joint1: motor torque exceeds its limit 0.01 N*m from t = 0.5 s (sample 1); peak "
            "0.01 N*m at t = 0.5 s")
    for value, said in ((on * 64, ()), (np.nextafter(on * 64, 1.0), (over,))):
        tau = np.array([[0.0, 0.0], [value, 0.0], [0.0, 0.0]])
        assert size(robot, t, qd, tau)[0].exceeded == said


def test_a_stale_copy_of_a_robot_is_not_served_from_the_memo(tmp_path):
    """joint_loads memoises each robot's structure by its folder, input hash and parameters: a
    copy of serial_2dof's generated folder whose manifest predates joint loads (no "joints"),
    same input hash and parameters, is still refused after the fresh folder's loads were
    computed (and memoised) in the same process."""
    import json
    import shutil

    from conftest import GENERATED

    from planar_sym.errors import LibraryError
    from planar_sym.model.library import Library
    from planar_sym.model.robot import Robot

    fresh = ps.load("serial_2dof")
    loads = joint_loads(fresh, [0.1, 0.2], [0.0, 0.0], [0.0, 0.0])
    assert loads.names == ("joint1", "weld_motor2", "joint2")
    folder = tmp_path / "serial_2dof"
    shutil.copytree(GENERATED / "serial_2dof", folder)
    manifest = json.loads((folder / "manifest.json").read_text())
    del manifest["joints"]
    (folder / "manifest.json").write_text(json.dumps(manifest, indent=2))
    stale = Robot("serial_2dof", Library("serial_2dof", folder=folder))
    assert stale.library.manifest["input_hash"] == fresh.library.manifest["input_hash"]
    assert np.array_equal(stale.p, fresh.p)
    with pytest.raises(LibraryError) as info:
        joint_loads(stale, [0.1, 0.2], [0.0, 0.0], [0.0, 0.0])
    assert "predates joint loads" in str(info.value)
