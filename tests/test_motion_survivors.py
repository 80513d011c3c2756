"""Motion profiles and inverse kinematics at the edges the other tests leave open, each against
something independent of the code under test:

- the trapezoid at its phase boundaries and at v^2 = a (the docstring's closed forms, with
  figures chosen so every boundary is an exact binary number), and a duration just above the
  minimum against the quadratic vc (T - vc / a) = 1 solved by hand;
- splines and profiles refusing bad inputs, word for word (the name in each message is the
  argument at fault);
- the seed's closed forms against the law of cosines of a 2R arm written out here, and every
  built-in robot's closed-form solution against forward kinematics (``robot.task``) and its
  loops (``robot.constraint``): the round trip returns the target; moved ground pivots and a
  moved platform frame (translation invariance) and scaled lengths (angles are unit-free)
  against the real robot's own solution.
"""

from __future__ import annotations

import numpy as np
import pytest

from planar_sym.errors import InputError
from planar_sym.motion.smooth import quintic, trapezoid, trapezoid_duration
from planar_sym.motion.splines import table, via


def _refusal(f) -> str:
    with pytest.raises(InputError) as exc:
        f()
    return str(exc.value)


# -- trapezoid ---------------------------------------------------------------------------------

def test_trapezoid_phase_boundaries_belong_to_the_cruise():
    """dx = 1, v_max = 1, a_max = 2: ta = v / a = 0.5 s, T = 1 / v + v / a = 1.5 s, every figure
    exact in binary. The docstring's pieces: 0 <= t < ta rising, ta <= t <= T - ta cruising
    (sdd = 0 at both of its ends), T - ta < t <= T falling."""
    tr = trapezoid([0.0], [1.0], [0.0, 0.25, 0.5, 1.0, 1.25, 1.5], v_max=1.0, a_max=2.0)
    np.testing.assert_array_equal(tr.x[:, 0], [0.0, 0.0625, 0.25, 0.75, 0.9375, 1.0])
    np.testing.assert_array_equal(tr.xd[:, 0], [0.0, 0.5, 1.0, 1.0, 0.5, 0.0])
    np.testing.assert_array_equal(tr.xdd[:, 0], [2.0, 2.0, 0.0, 0.0, -2.0, -2.0])


def test_trapezoid_with_a_duration_below_one_second_squared():
    """dx = 1, a_max = 4, T = 1.25 s (the minimum, triangular, is 1 s): vc (T - vc / a) = 1
    by hand gives vc = (a T - sqrt(a^2 T^2 - 4 a)) / 2 = (5 - 3) / 2 = 1 /s and ta = 0.25 s.
    Here T^2 - 4 / a = 0.5625 < 1, a range the other tests do not reach."""
    t = np.array([0.0, 0.25, 0.625, 1.0, 1.25])
    tr = trapezoid([0.5], [1.0], t, v_max=10.0, a_max=4.0, duration_s=1.25)
    np.testing.assert_allclose(tr.xd[:, 0], [0.0, 1.0, 1.0, 1.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(tr.x[:, 0], 0.5 + np.array([0.0, 0.125, 0.5, 0.875, 1.0]),
                               atol=1e-15)


def test_trapezoid_duration_at_the_limit_of_the_tolerance_is_accepted():
    """A duration below the minimum by the stated relative slack 1e-12 (exactly) is accepted:
    the refusal is for T < T_min (1 - 1e-12); dx = 0.2, v 0.1, a 0.5: T_min = 2.2 s."""
    T = trapezoid_duration([0.2], 0.1, 0.5) * (1 - 1e-12)
    tr = trapezoid([0.0], [0.2], [0.0, T], v_max=0.1, a_max=0.5, duration_s=T)
    assert tr.x[-1, 0] == pytest.approx(0.2, abs=1e-15) and abs(tr.xd[-1, 0]) < 1e-12


def test_trapezoid_at_v_squared_equal_a_is_the_triangle():
    """v^2 = a exactly (dx 1, v_max 0.29, a_max 0.0841 = 0.29^2 in binary too): the docstring's
    triangle T = 2 / sqrt(a) = 2 / 0.29 s; in arithmetic the trapezoid's 1 / v + v / a is the
    same, but at these figures it rounds 1 ulp lower, and a motion evaluated at the triangle's
    T would then be refused as outside."""
    assert 0.29 * 0.29 == 0.0841
    T = trapezoid_duration([1.0], 0.29, 0.0841)
    assert T == 2 / 0.29
    tr = trapezoid([0.0], [1.0], [0.0, T / 2, 2 / 0.29], v_max=0.29, a_max=0.0841)
    assert tr.xd[1, 0] == pytest.approx(0.29, rel=1e-15) and tr.x[-1, 0] == 1.0
    # the refusal names the triangle too: v^2 >= a is "the speed limit is not reached"
    assert _refusal(lambda: trapezoid([0.0], [1.0], [0.0], v_max=2.0, a_max=4.0,
                                      duration_s=0.5)) == (
        "trapezoid: a duration of 0.5 s is shorter than the 1 s the speed and acceleration "
        "limits allow (triangular, the speed limit is not reached; acceleration set by "
        "channel 1 of 1: |dx| = 1, a_max = 4 per s^2)")


def test_trapezoid_refusals_word_for_word():
    assert _refusal(lambda: trapezoid([0], [1], [0.0], v_max="fast", a_max=1.0)) == (
        "trajectory v_max must be numbers (got 'fast': could not convert string to float: "
        "'fast')")
    assert _refusal(lambda: trapezoid([0], [1], [0.0], v_max=1.0, a_max="hard")) == (
        "trajectory a_max must be numbers (got 'hard': could not convert string to float: "
        "'hard')")
    assert _refusal(lambda: trapezoid_duration("one", 1.0, 1.0)) == (
        "trajectory displacement must be numbers (got 'one': could not convert string to "
        "float: 'one')")
    # trapezoid_duration has no start_and_step in front: its own finiteness check speaks
    assert _refusal(lambda: trapezoid_duration([np.nan, 1.0], 1.0, 1.0)) == (
        "trajectory displacement must be finite (got [nan, 1.0])")
    assert _refusal(lambda: trapezoid_duration([0.0, 0.0], 1.0, 1.0)) == (
        "trapezoid: the displacement dx is zero in every channel: nothing to move (a "
        "trapezoid's duration follows from its length)")
    assert _refusal(lambda: trapezoid([0], [1], [0.0], v_max=1.0, a_max=1.0,
                                      duration_s=-1)) == (
        "trapezoid duration must be a positive number of seconds (got -1)")


def test_quintic_keeps_its_times():
    """The trajectory carries the evaluation times it was given (as floats)."""
    tr = quintic([0.0], [1.0], 2.0, [0, 1, 2])
    assert tr.t_s.dtype == float
    np.testing.assert_array_equal(tr.t_s, [0.0, 1.0, 2.0])
    np.testing.assert_array_equal(tr.x[:, 0], [0.0, 0.5, 1.0])  # s(1/2) = 1/2 by symmetry


# -- splines -----------------------------------------------------------------------------------

@pytest.mark.parametrize("make, what", [(via, "via"), (table, "table")])
def test_spline_refusals_word_for_word(make, what):
    # (2, 1) times would flatten to a valid 2-point spline: refused, not reshaped
    assert _refusal(lambda: make([[0.0], [1.0]], [0.0, 1.0], [0.5])) == (
        f"{what} times must be a 1-D array (got shape (2, 1))")
    assert _refusal(lambda: make(["0", "x"], [0.0, 1.0], [0.5])) == (
        f"trajectory {what} times must be numbers (got ['0', 'x']: could not convert string "
        "to float: 'x')")
    assert _refusal(lambda: make([0.0, 1.0], ["a", "b"], [0.5])) == (
        f"{what} points must be numbers, (K, channels) (could not convert string to float: "
        "'a')")
    # a missing value (None) is a NaN point, named as not finite
    assert _refusal(lambda: make([0.0, 1.0], [0.0, None], [0.5])) == (
        f"{what} point 1 must be finite (t = 1.0 s, [nan])")
    assert _refusal(lambda: make([0.0, 1.0, 2.0], [0.0, 1.0], [0.5])) == (
        f"{what}: 3 times need 3 points (rows of (K, channels)), got shape (2,)")


# -- the seed's closed forms -------------------------------------------------------------------
# The closed forms read their lengths from robot.parameters (a mapping) and name the robot and
# its task in their refusals; a stand-in carrying just those lets them meet lengths and
# offsets the built-in descriptions do not have. References: forward kinematics of the real
# robots (robot.task, robot.constraint) and the 2R law of cosines written out here.

from types import SimpleNamespace

import planar_sym as ps
from planar_sym.errors import WorkspaceError
from planar_sym.motion import seed_ik
from planar_sym.motion.profiles import cubic

TOL = 1e-9  # rad: seed_ik.ANGLE_TOL_RAD, an angle this close to a limit counts as on it


def _stand_in(name, parameters, task=("x", "y", "phi"), q_drawn=None):
    return SimpleNamespace(name=name, parameters=parameters, task_names=task, q_drawn=q_drawn)


def _seed(robot, x):
    x = np.atleast_2d(np.asarray(x, dtype=float))
    return seed_ik.SEED_SOLVERS[robot.name](robot, np.arange(len(x), dtype=float), x)


def _seed_refusal(robot, x, t=None) -> str:
    x = np.atleast_2d(np.asarray(x, dtype=float))
    t = np.arange(len(x), dtype=float) if t is None else t
    with pytest.raises(WorkspaceError) as exc:
        seed_ik.SEED_SOLVERS[robot.name](robot, t, x)
    return str(exc.value)


def _fk3(a, q):
    """Tool (x, y, phi) of a 3R arm with links a = (a1, a2, a3) on their axes, by hand."""
    s1, s12, phi = q[:, 0], q[:, 0] + q[:, 1], q[:, 0] + q[:, 1] + q[:, 2]
    return np.column_stack([a[0] * np.cos(s1) + a[1] * np.cos(s12) + a[2] * np.cos(phi),
                            a[0] * np.sin(s1) + a[1] * np.sin(s12) + a[2] * np.sin(phi), phi])


def _fk2(q, a=0.1):
    s = q[:, 0] + q[:, 1]
    return a * np.column_stack([np.cos(q[:, 0]) + np.cos(s), np.sin(q[:, 0]) + np.sin(s)])


def test_off_axis_links_are_refused_by_name():
    """The closed forms assume joints and tool on the link axes: any py_link*_CS2 != 0 is
    refused, every such parameter named, in order."""
    base2 = {"px_link1_CS2": 0.1, "px_link2_CS2": 0.1}
    base3 = {**base2, "px_link3_CS2": 0.05}
    head = "the seed's closed-form IK assumes joints and tool on the link axes, but "
    for name, base, offs in (("serial_2dof", base2, ["py_link1_CS2", "py_link2_CS2"]),
                             ("serial_3dof", base3,
                              ["py_link1_CS2", "py_link2_CS2", "py_link3_CS2"])):
        robot = _stand_in(name, {**base}, ("x", "y", "phi")[:2 + (name == "serial_3dof")])
        x = [0.1, 0.1, 0.0][:len(robot.task_names)]
        assert np.all(np.isfinite(_seed(robot, x)))  # on the axes: solved
        for off in offs:
            robot.parameters = {**base, off: 0.01}
            assert _seed_refusal(robot, x) == f"{name}: {head}{off} are non-zero"
        robot.parameters = {**base, **{off: -0.01 for off in offs}}
        assert _seed_refusal(robot, x) == f"{name}: {head}{', '.join(offs)} are non-zero"


def test_serial_3dof_stretched_arm_and_the_wrap_tolerance():
    """Links 0.125 m each (binary-exact), phi = 0, tool at (0.375, y): the wrist (0.25, y) is at
    full stretch, kappa = 1 exactly (inside the workspace: |kappa| <= 1), q2 = 0 and
    q1 = atan(4 y / 1) (the law of cosines with delta = (a1 + a2)^2). q1 = -1e-9 rad is within
    the tolerance of 0 and is kept; q1 = -2e-9 rad is wrapped to 2 pi - 2e-9 (seed: [0, 2 pi))."""
    robot = _stand_in("serial_3dof", {"px_link1_CS2": 0.125, "px_link2_CS2": 0.125,
                                      "px_link3_CS2": 0.125})
    x = np.array([[0.375, 0.0, 0.0], [0.375, -2.5e-10, 0.0], [0.375, -5e-10, 0.0]])
    q = _seed(robot, x)
    np.testing.assert_array_equal(q[:, 1], 0.0)
    assert q[0, 0] == 0.0 and q[1, 0] == -1e-9  # atan(-1e-9) rounds to -1e-9
    assert q[2, 0] == pytest.approx(2 * np.pi - 2e-9, abs=1e-15)
    np.testing.assert_allclose(_fk3((0.125,) * 3, q)[:, :2], x[:, :2], rtol=0, atol=1e-15)


def test_serial_3dof_below_the_axis_is_wrapped():
    """The real serial_3dof at q = (-0.5, 1.2, 0.3): forward kinematics by robot.task, then
    the closed form returns q1 + 2 pi (the seed's 0 <= q1 < 2 pi) and q2, q3 as they were."""
    robot = ps.load("serial_3dof")
    q = np.array([[-0.5, 1.2, 0.3]])
    x = np.asarray(robot.task(q)[0]).reshape(1, 3)
    np.testing.assert_allclose(_seed(robot, x), [[2 * np.pi - 0.5, 1.2, 0.3 - 2 * np.pi]],
                               atol=1e-12)


@pytest.mark.parametrize("scale", [100.0, 0.01])
def test_serial_3dof_is_scale_free(scale):
    """Angles do not depend on the unit of length: every length and the target times `scale`
    give the same q. The reference is the real robot (a = 0.1, 0.07, 0.05 m) at
    q2 = 160 deg, whose tool robot.task gives; its closed form returns q."""
    robot = ps.load("serial_3dof")
    q = np.array([[0.3, np.radians(160.0), -0.5], [1.0, np.radians(100.0), 0.2]])
    x = np.asarray(robot.task(q)[0]).reshape(2, 3)
    np.testing.assert_allclose(_seed(robot, x), q, atol=1e-12)
    p = robot.parameters
    big = _stand_in("serial_3dof", {k: scale * p[k] for k in
                                    ("px_link1_CS2", "px_link2_CS2", "px_link3_CS2")})
    np.testing.assert_allclose(_seed(big, x * [scale, scale, 1.0]), q, atol=1e-12)


def test_serial_3dof_tool_at_the_wrist():
    """Without px_link3_CS2 (no third link: the tool at the wrist) the wrist's own target gives
    the real robot's q: wrist = tool - a3 (cos phi, sin phi), a3 = 0.05 m."""
    robot = ps.load("serial_3dof")
    q = np.array([[0.4, 1.1, -0.3], [1.2, 0.7, 0.5]])
    x = np.asarray(robot.task(q)[0]).reshape(2, 3)
    a3 = robot.parameters["px_link3_CS2"]
    wrist = x - a3 * np.column_stack([np.cos(x[:, 2]), np.sin(x[:, 2]), np.zeros(2)])
    short = _stand_in("serial_3dof", {"px_link1_CS2": robot.parameters["px_link1_CS2"],
                                      "px_link2_CS2": robot.parameters["px_link2_CS2"]})
    np.testing.assert_allclose(_seed(short, wrist), q, atol=1e-12)


def test_serial_2dof_joint_limits_at_their_edges():
    """The seed's limits 0 <= q1 <= 180 deg, 30 <= q2 <= 150 deg, with 1e-9 rad of slack:
    targets by the hand-written forward kinematics (a = 0.1 m) of poses just inside the
    slack are solved (returning the pose), poses beyond a limit refused with their angle."""
    robot = ps.load("serial_2dof")
    inside = np.array([[0.5, np.pi / 6 - TOL / 2], [0.5, 5 * np.pi / 6 + TOL / 2],
                       [np.pi + TOL / 2, 1.0], [1.0, np.radians(140.0)]])
    np.testing.assert_allclose(_seed(robot, _fk2(inside)), inside, atol=1e-13)
    # exactly on the bound (targets found by search: q = pi + 1e-9 and 150 deg + 1e-9 as floats)
    on = np.array([[-0.15403023050265827, -0.08414709863482542],
                   [-0.012213899995061056, 0.050302212289539246]])
    q = _seed(robot, on)
    assert q[0, 0] == np.pi + TOL and q[1, 1] == 5 * np.pi / 6 + TOL
    np.testing.assert_allclose(_fk2(q), on, atol=1e-16)
    msg = _seed_refusal(robot, _fk2(np.array([[1.5, np.radians(160.0)]])), t=np.array([0.5]))
    assert msg.startswith("serial_2dof: target (x = ") and msg.endswith(
        "at t = 0.5 s (sample 0) violates the joint limit 30 <= q2 <= 150 deg (q2 = 160 deg)")
    msg = _seed_refusal(robot, _fk2(np.array([[-0.2, 1.0]])))
    assert msg.endswith("violates the joint limit 0 <= q1 <= 180 deg (q1 = "
                        f"{np.degrees(2 * np.pi - 0.2):.6g} deg)")


def test_outside_the_workspace_word_for_word():
    """Beyond reach the message gives kappa = (|p|^2 - a1^2 - a2^2) / (2 a1 a2) by the law of
    cosines (here by hand), naming the arm of a five-bar."""
    robot = ps.load("serial_2dof")
    assert _seed_refusal(robot, [[0.3, 0.1]], t=np.array([0.5])) == (
        "serial_2dof: target (x = 300 mm, y = 100 mm) at t = 0.5 s (sample 0) is outside the "
        "workspace (cos of the elbow angle would be 4, beyond +-1)")
    for name, x, k, arm in (("five_bar_type1", [0.2, 0.154665], 5, "left"),
                            ("five_bar_type2", [0.2, 0.128], 3, "left"),
                            ("five_bar_type1", [-0.11, 0.154665], 5, "right")):
        five = ps.load(name)
        p = five.parameters
        l2, l36 = p["px_L_Link1_CS2"], p["px_L_Link2_CS3"]
        x = np.array([x]) * np.ones((k + 1, 1))  # sample k is the first named
        x[:k] = np.asarray(five.task(five.q_drawn)[0]).reshape(-1)  # the drawn pose: solved
        msg = _seed_refusal(five, x, t=np.linspace(0.0, 1.0, k + 1))
        head = (f"{name}: target (x = {x[k, 0] * 1e3:.6g} mm, y = {x[k, 1] * 1e3:.6g} mm) at "
                f"t = 1 s (sample {k}) is outside the workspace ({arm} arm: cos of "
                "the elbow angle would be ")
        assert msg.startswith(head) and msg.endswith(", beyond +-1)"), msg
        kappa = float(msg[len(head):-len(", beyond +-1)")])
        left = (x[k, 0] ** 2 + x[k, 1] ** 2 - l2**2 - l36**2) / (2 * l2 * l36)  # A at 0
        if arm == "left":
            assert kappa == pytest.approx(left, rel=1e-5)
        else:  # the left arm reaches; the right one cannot
            assert abs(left) <= 1 and kappa > 1


@pytest.mark.parametrize("name", ["five_bar_type1", "five_bar_type2"])
def test_five_bar_moved_on_the_ground(name):
    """Moving both ground pivots A and E by s moves the workspace by s: the target x + s gives
    the real robot's q at x. s puts E at x = 0 (px_ground_E left out: its default 0) and
    A, E at y = 0.03 m (py_ground_A, py_ground_E, absent from the built-ins). The real
    robot's forward kinematics returns x and closes its loops at that q."""
    robot = ps.load(name)
    t = np.linspace(0.0, 1.0, 5)
    x0 = np.asarray(robot.task(robot.q_drawn)[0]).reshape(-1)
    x = cubic(x0, [0.02, -0.015], 1.0, t).x
    q = _seed(robot, x)
    np.testing.assert_allclose(np.asarray(robot.task(q)[0]).reshape(-1, 2), x, atol=1e-13)
    assert np.max(np.abs(robot.constraint(q))) < 1e-13
    p = {k: robot.parameters[k] for k in robot.parameters}
    s = np.array([-p.pop("px_ground_E"), 0.03])
    moved = _stand_in(name, {**p, "px_ground_A": s[0], "py_ground_A": s[1],
                             "py_ground_E": s[1]}, ("x", "y"), robot.q_drawn)
    np.testing.assert_allclose(_seed(moved, x + s), q, atol=1e-12)


def test_parallel_3rrr_moved_on_the_ground_and_reframed():
    """3-RRR: ground pivots moved by s (A2 to y = 0, py_ground_A2 left out) and the platform
    frame moved to platform point 1 (b_i - b_1: px/py_platform_CS1 left out), the target
    moved to match, x' = x + s + R(phi) b_1: the same q as the real robot's, whose forward
    kinematics returns x and closes its loops."""
    robot = ps.load("parallel_3rrr")
    t = np.linspace(0.0, 1.0, 5)
    x0 = np.asarray(robot.task(robot.q_drawn)[0]).reshape(-1)
    x = cubic(x0, [0.01, 0.02, 0.1], 1.0, t).x
    q = _seed(robot, x)
    np.testing.assert_allclose(np.asarray(robot.task(q)[0]).reshape(-1, 3), x, atol=1e-13)
    assert np.max(np.abs(robot.constraint(q))) < 1e-13
    p = {k: robot.parameters[k] for k in robot.parameters}
    s = np.array([0.0, -p["py_ground_A2"]])
    b1 = np.array([p.get("px_platform_CS1", 0.0), p["py_platform_CS1"]])
    moved = {k: v for k, v in p.items() if k not in ("py_ground_A2", "py_platform_CS1")}
    for i in (1, 2, 3):
        for axis, shift in (("x", s[0]), ("y", s[1])):
            key = f"p{axis}_ground_A{i}"
            if key in p or shift:
                moved[key] = p.get(key, 0.0) + shift
            if i != 1:
                moved[f"p{axis}_platform_CS{i}"] = p.get(f"p{axis}_platform_CS{i}", 0.0) - \
                    b1["xy".index(axis)]
    moved.pop("py_ground_A2", None)  # its value is 0 now: left to the default
    c, sn = np.cos(x[:, 2]), np.sin(x[:, 2])
    x_moved = x + np.column_stack([s[0] + c * b1[0] - sn * b1[1], s[1] + sn * b1[0] + c * b1[1],
                                   np.zeros(len(x))])
    q_moved = _seed(_stand_in("parallel_3rrr", moved, q_drawn=robot.q_drawn), x_moved)
    np.testing.assert_allclose(q_moved, q, atol=1e-12)


def test_parallel_3rrr_legs_at_full_stretch():
    """Every leg 0.125 + 0.125 m from the origin, platform points at its origin, target
    (0.25, 0, 0): each leg reaches exactly (e1^2 + e2^2 - e3^2 = 0, the edge of its reach,
    still inside) and lies stretched along x: q = 0, which its own equation
    A + l1 e(th) + l2 e(th + elbow) = p confirms."""
    p = {f"px_Link{i}_{j}_CS2": 0.125 for i in (1, 2, 3) for j in (1, 2)}
    robot = _stand_in("parallel_3rrr", p, q_drawn=np.zeros(7))
    q = _seed(robot, [0.25, 0.0, 0.0])
    np.testing.assert_array_equal(q, np.zeros((1, 7)))
