"""Targets the robots cannot reach, singular poses and bad inputs raise errors that name the time
(or sample) and the target, the earliest failing sample over every check, arm and leg; every failing case has a passing neighbour, so the checks are
neither silent nor always on.

The time and target a WorkspaceError names are parsed from its message and compared with the
first sample computed here, independently, from the reach of the arm (seed geometry).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from planar_sym.errors import InputError, WorkspaceError
from planar_sym.model.locate import load
from planar_sym.model.loops import COND_LIMIT
from planar_sym.motion import closure
from planar_sym.motion.ik import inverse_kinematics
from planar_sym.motion.profiles import coeff_3rd, cubic

T = 2.0
TIMES = np.linspace(0.0, T, 9)  # 0.25 s apart


def _ik(robot_name, x0, dx, t=TIMES, duration=T):
    return inverse_kinematics(load(robot_name), cubic(x0, dx, duration, t))


def _named(msg: str) -> tuple[float, dict[str, float]]:
    """(time in s, {task coordinate: value in mm or rad}) named by an error message."""
    m = re.search(r"at t = ([-+0-9.eE]+) s", msg)
    assert m, f"no time in {msg!r}"
    target = {k: float(v) for k, v in re.findall(r"\b(x|y) = ([-+0-9.eE]+) mm", msg)}
    target.update({k: float(v) for k, v in re.findall(r"\b(phi) = ([-+0-9.eE]+) rad", msg)})
    return float(m.group(1)), target


def _check_named(msg: str, k: int, x: np.ndarray):
    """The message names sample k: its time and its target (mm, 6 significant digits)."""
    t_named, target = _named(msg)
    assert t_named == pytest.approx(TIMES[k], abs=1e-9), msg
    assert f"sample {k}" in msg, msg
    assert target["x"] == pytest.approx(x[k, 0] * 1e3, rel=1e-5, abs=1e-9), msg
    assert target["y"] == pytest.approx(x[k, 1] * 1e3, rel=1e-5, abs=1e-9), msg
    if x.shape[1] == 3:
        assert target["phi"] == pytest.approx(x[k, 2], rel=1e-5, abs=1e-9), msg


def _first(bad: np.ndarray) -> int:
    assert bad.any() and not bad[0], "the case must start reachable and leave the workspace"
    return int(np.argmax(bad))


# -- outside the workspace -------------------------------------------------------------------------

def test_serial_2dof_beyond_reach():
    """Tip from (100, 100) mm by +300 mm in x: beyond a1 + a2 = 200 mm (seed Table 1)."""
    x0, dx = np.array([0.1, 0.1]), np.array([0.3, 0.0])
    x = cubic(x0, dx, T, TIMES).x
    k = _first(np.hypot(x[:, 0], x[:, 1]) > 0.2)
    with pytest.raises(WorkspaceError, match="outside the workspace") as exc:
        _ik("serial_2dof", x0, dx)
    _check_named(str(exc.value), k, x)
    assert "serial_2dof" in str(exc.value)
    _ik("serial_2dof", x0, [-0.2, 0.0])  # the seed's own move (S3) is fine


def test_serial_2dof_elbow_joint_limit():
    """Toward |p| = 195 mm at 45 deg: needs q2 = acos((0.195^2 - 0.02) / 0.02) = 25.68 deg, under
    the seed's 30 deg limit (which binds beyond |p| = 0.2 cos 15 deg = 193.19 mm)."""
    x0 = np.array([0.1, 0.1])
    end = 0.195 / np.sqrt(2) * np.ones(2)
    x = cubic(x0, end - x0, T, TIMES).x
    r = np.hypot(x[:, 0], x[:, 1])
    q2 = np.arccos((r**2 - 0.02) / 0.02)
    k = _first(q2 < np.radians(30))
    with pytest.raises(WorkspaceError, match=r"30 <= q2 <= 150 deg") as exc:
        _ik("serial_2dof", x0, end - x0)
    _check_named(str(exc.value), k, x)
    m = re.search(r"q2 = ([-0-9.]+) deg", str(exc.value))
    assert float(m.group(1)) == pytest.approx(np.degrees(q2[k]), rel=1e-5)
    end_ok = 0.193 / np.sqrt(2) * np.ones(2)  # just inside the limit
    _ik("serial_2dof", x0, end_ok - x0)


def test_serial_2dof_shoulder_joint_limit():
    """Toward (-50, -50) mm: q1 leaves the seed's 0..180 deg (elbow-down solution below the
    x axis)."""
    x0, dx = np.array([0.1, 0.1]), np.array([-0.15, -0.15])
    with pytest.raises(WorkspaceError, match=r"0 <= q1 <= 180 deg") as exc:
        _ik("serial_2dof", x0, dx)
    t_named, _ = _named(str(exc.value))
    assert 0 < t_named <= T


def test_serial_3dof_beyond_reach():
    """Tool from (100, 120) mm, phi = pi/2 by +200 mm: the wrist (tool - a3 along phi) leaves
    the a1 + a2 = 170 mm circle."""
    x0, dx = np.array([0.1, 0.12, np.pi / 2]), np.array([0.2, 0.0, 0.0])
    x = cubic(x0, dx, T, TIMES).x
    wrist = x[:, :2] - 0.05 * np.column_stack([np.cos(x[:, 2]), np.sin(x[:, 2])])
    k = _first(np.hypot(wrist[:, 0], wrist[:, 1]) > 0.17)
    with pytest.raises(WorkspaceError, match="outside the workspace") as exc:
        _ik("serial_3dof", x0, dx)
    _check_named(str(exc.value), k, x)
    _ik("serial_3dof", x0, [-0.2, 0.0, 0.0])  # S4


def test_five_bar_type1_beyond_reach():
    """P from the S5 start by +200 mm in x: the left arm A-B-P reaches |AP| <= 100 + 128 mm."""
    x0, dx = np.array([0.060852, 0.154665]), np.array([0.2, 0.0])
    x = cubic(x0, dx, T, TIMES).x
    k = _first(np.hypot(x[:, 0], x[:, 1]) > 0.228)
    with pytest.raises(WorkspaceError, match="outside the workspace") as exc:
        _ik("five_bar_type1", x0, dx)
    _check_named(str(exc.value), k, x)
    _ik("five_bar_type1", x0, [0.05, 0.0])  # S5 move x


def _leg_reach_first_bad(x: np.ndarray) -> int:
    """First sample at which a 3-RRR leg cannot reach: |d| = |p + R(phi) B_i - A_i| > l1 + l2,
    seed geometry A_i = 150 mm, B_i = 35 mm along (0, 1), (-sqrt3/2, -1/2), (sqrt3/2, -1/2)."""
    dirs = np.array([[0.0, 1.0], [-np.sqrt(3) / 2, -0.5], [np.sqrt(3) / 2, -0.5]])
    c, s = np.cos(x[:, 2]), np.sin(x[:, 2])
    b = 0.035 * dirs
    rb = np.stack([c[:, None] * b[None, :, 0] - s[:, None] * b[None, :, 1],
                   s[:, None] * b[None, :, 0] + c[:, None] * b[None, :, 1]], axis=2)
    d = x[:, None, :2] + rb - 0.150 * dirs[None]
    return _first(np.any(np.linalg.norm(d, axis=2) > 0.2, axis=1))


def _named_sample_is_unreachable(robot_name, msg, x):
    """The message names a sample k whose target is x[k] and which on its own cannot be solved."""
    k = int(re.search(r"\(sample (\d+)\)", msg).group(1))
    _check_named(msg, k, x)
    with pytest.raises(WorkspaceError):
        inverse_kinematics(load(robot_name), cubic(x[k], np.zeros_like(x[k]), T, [0.0]))
    return k


def test_parallel_3rrr_beyond_reach():
    """Platform by +200 mm in x: a leg's d = p + B_i - A_i exceeds l1 + l2 = 200 mm."""
    x0, dx = np.zeros(3), np.array([0.2, 0.0, 0.0])
    x = cubic(x0, dx, T, TIMES).x
    with pytest.raises(WorkspaceError, match="outside the workspace") as exc:
        _ik("parallel_3rrr", x0, dx)
    _named_sample_is_unreachable("parallel_3rrr", str(exc.value), x)
    _ik("parallel_3rrr", x0, [0.05, 0.0, 0.0])  # S7 move x


def test_serial_2dof_error_names_the_earliest_time():
    """Tip by +300 mm in x, 201 samples over 2 s: q2 < 30 deg (|p| > 193.19 mm) from
    t = 0.61 s, beyond reach (|p| > 200 mm) only from 0.65 s; the error must name 0.61 s."""
    t = np.linspace(0.0, T, 201)
    x = cubic([0.1, 0.1], [0.3, 0.0], T, t).x
    r = np.hypot(x[:, 0], x[:, 1])
    k = _first(r > 0.2 * np.cos(np.pi / 12))
    assert t[k] == pytest.approx(0.61)
    with pytest.raises(WorkspaceError) as exc:
        _ik("serial_2dof", [0.1, 0.1], [0.3, 0.0], t=t)
    assert f"t = {t[k]:.6g} s (sample {k})" in str(exc.value), str(exc.value)


def test_parallel_3rrr_error_names_the_earliest_time():
    """+200 mm in x: leg 2 cannot reach from t = 1.0 s (x = 100 mm, |d| = 207.7 mm), leg 1
    only from t = 1.5 s; the error must name t = 1.0 s (it once named 1.5 s)."""
    x0, dx = np.zeros(3), np.array([0.2, 0.0, 0.0])
    x = cubic(x0, dx, T, TIMES).x
    k = _leg_reach_first_bad(x)
    assert TIMES[k] == 1.0
    with pytest.raises(WorkspaceError) as exc:
        _ik("parallel_3rrr", x0, dx)
    _check_named(str(exc.value), k, x)


def test_five_bar_error_names_the_earliest_time():
    """five_bar_type1, P by -250 mm in x over 2 s (41 samples): the right arm E-D-C fails from
    t = 1.1 s (each sample solved on its own says so), the left arm only from 1.65 s."""
    robot = load("five_bar_type1")
    t = np.linspace(0.0, T, 41)
    tr = cubic([0.060852, 0.154665], [-0.25, 0.0], T, t)
    alone = []
    for xk in tr.x:
        try:
            inverse_kinematics(robot, cubic(xk, np.zeros(2), T, [0.0]))
            alone.append(False)
        except WorkspaceError:
            alone.append(True)
    k = _first(np.array(alone))
    with pytest.raises(WorkspaceError) as exc:
        inverse_kinematics(robot, tr)
    assert f"t = {t[k]:.6g} s (sample {k})" in str(exc.value), str(exc.value)


# -- singular poses: the condition-number check ----------------------------------------------------

def test_serial_3dof_driven_to_stretched_arm():
    """Tool from (100, 0) mm to (220, 0) mm, phi = 0: the wrist ends at 170 mm = a1 + a2, arm
    fully stretched (q2 = 0), the task Jacobian singular at t = T."""
    x0, dx = np.array([0.1, 0.0, 0.0]), np.array([0.12, 0.0, 0.0])
    x = cubic(x0, dx, T, TIMES).x
    with pytest.raises(WorkspaceError, match="singular pose") as exc:
        _ik("serial_3dof", x0, dx)
    msg = str(exc.value)
    _check_named(msg, len(TIMES) - 1, x)
    cond = float(re.search(r"condition number ([0-9.e+inf]+) >", msg).group(1))
    assert cond > COND_LIMIT
    _ik("serial_3dof", x0, [0.11, 0.0, 0.0])  # 10 mm short of stretched: fine


@pytest.mark.parametrize("robot_name, x0", [("five_bar_type1", (0.060852, 0.154665)),
                                            ("five_bar_type2", (0.1, 0.128))])
def test_five_bar_driven_to_stretched_left_arm(robot_name, x0):
    """P driven radially out to |AP| = (1 - 1e-13) (l2 + |BP|): the left arm stretched to
    rounding, the stacked Jacobian [Phi_q; J] singular at t = T; 1e-6 short of it is fine."""
    robot = load(robot_name)
    p = robot.parameters
    reach = p["px_L_Link1_CS2"] + p["px_L_Link2_CS3"]
    x0 = np.array(x0)
    end = x0 / np.linalg.norm(x0) * reach
    x = cubic(x0, end * (1 - 1e-13) - x0, T, TIMES).x
    with pytest.raises(WorkspaceError, match="singular pose") as exc:
        _ik(robot_name, x0, end * (1 - 1e-13) - x0)
    _check_named(str(exc.value), len(TIMES) - 1, x)
    _ik(robot_name, x0, end * (1 - 1e-6) - x0)


def test_five_bar_type2_actuated_route_to_parallel_singularity():
    """Actuated angles from (0, 90 deg) to (90, 90) deg: B = (0, 100), D = (200, 100) mm, the
    distal links B-C-D in one line (|BD| = l3 + l4): Phi_p singular at t = 1 s."""
    robot = load("five_bar_type2")
    t = np.linspace(0.0, 1.0, 5)
    tr = cubic([0.0, np.pi / 2], [np.pi / 2, 0.0], 1.0, t)
    # met where it is (the steps shrink as the pose nears it, never past it): at the sample,
    # or on the way to it, named by the two samples
    with pytest.raises(WorkspaceError, match=r"singular pose (between t = 0.75 s \(sample 3\) "
                                             r"and |at )t = 1 s \(sample 4\)"):
        closure.from_actuated(robot, t, tr.x, tr.xd, tr.xdd)
    tr = cubic([0.0, np.pi / 2], [np.pi / 3, 0.0], 1.0, t)  # 60 deg: fine
    closure.from_actuated(robot, t, tr.x, tr.xd, tr.xdd)


def test_closed_chain_inverse_dynamics_at_parallel_singularity():
    """The same stretched pose fed to closed_chain_inverse_dynamics: the actuation matrix
    [S^T Phi_q^T] is singular (the loop force along B-C-D is undetermined)."""
    robot = load("five_bar_type2")
    q = np.array([[np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2]])  # A, B, E, D
    assert np.max(np.abs(robot.constraint(q))) < 1e-15
    z = np.zeros_like(q)
    with pytest.raises(WorkspaceError, match=r"singular pose at t = 0.5 s \(sample 0\)"):
        robot.closed_chain_inverse_dynamics(q, z, z, t=np.array([0.5]))


# -- bad inputs ------------------------------------------------------------------------------------

@pytest.mark.parametrize("duration", [0.0, -1.0, np.nan, np.inf])
def test_non_positive_duration(duration):
    with pytest.raises(InputError, match="duration"):
        cubic([0.1, 0.1], [0.05, 0.0], duration, [0.0])
    with pytest.raises(InputError, match="duration"):
        coeff_3rd([0.0], [0.0], [1.0], [0.0], duration)


def test_times_outside_trajectory():
    with pytest.raises(InputError, match=r"t = 2.5 s \(sample 1\)"):
        cubic([0.1], [0.05], 2.0, [0.0, 2.5])


@pytest.mark.parametrize("which", ["q", "qd", "qdd"])
def test_nan_in_closed_chain_inverse_dynamics(which):
    robot = load("five_bar_type1")
    t = np.linspace(0.0, 2.0, 6)
    jt = inverse_kinematics(robot, cubic([0.060852, 0.154665], [0.05, 0.0], 2.0, t))
    arrays = {"q": jt.q.copy(), "qd": jt.qd.copy(), "qdd": jt.qdd.copy()}
    robot.closed_chain_inverse_dynamics(*arrays.values(), t=t)  # fine before
    arrays[which][3, 1] = np.nan
    with pytest.raises(InputError, match=rf"{which}\[3, 1\] is nan at sample 3"):
        robot.closed_chain_inverse_dynamics(*arrays.values(), t=t)


def test_nan_time_named_for_positions():
    robot = load("parallel_3rrr")
    q = np.tile(robot.q_drawn, (4, 1))
    q[2, 0] = np.inf
    z = np.zeros_like(q)
    with pytest.raises(InputError, match=r"sample 2 \(t = 0.2 s\)"):
        robot.closed_chain_inverse_dynamics(q, z, z, t=np.array([0.0, 0.1, 0.2, 0.3]))
