"""The generic inverse kinematics (Newton continued sample to sample, in C) against the textbook's
closed forms, forward kinematics, mirror-image working modes, and its refusals.

References are independent of the solver under test: the seed's closed forms
(``motion/seed_ik.py``), forward kinematics of the compiled model (``robot.task``,
``robot.constraint``), the 2-DOF arm's mirror image computed by hand, and distances to the
workspace's edge from the seed's link lengths.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from conftest import ROBOTS_DIR, ROOT, study_motion

import planar_sym as ps
from planar_sym.errors import InputError, WorkspaceError
from planar_sym.model.loops import COND_LIMIT
from planar_sym.motion import newton
from planar_sym.motion.failures import Failures
from planar_sym.motion.ik import inverse_kinematics

#: the seed's scenarios S3-S7 in task space (their built-in study files)
SCENARIOS = ("serial_2dof_cartesian_move", "serial_3dof_cartesian_move",
             "five_bar_type1_move_x", "five_bar_type1_move_y",
             "five_bar_type2_move_x", "five_bar_type2_move_y",
             "parallel_3rrr_move_x", "parallel_3rrr_move_y")
#: the serial arms are drawn stretched out (a singular pose): they start from a bent elbow
#: (elbow down, q2 > 0, the seed's mode); the closed chains from their drawn configuration
START = {"serial_2dof": [0.5, 1.0], "serial_3dof": [0.5, 1.0, 0.0]}
AGREE_RAD = 1e-12
FK_M = 1e-12
T = 2.0
TIMES = np.linspace(0.0, T, 9)
A1 = A2 = 0.1  # serial_2dof link lengths (m), seed Table 1


def _named(msg: str) -> tuple[int, float]:
    """(sample, time in s) an error message names."""
    m = re.search(r"at t = ([-+0-9.eE]+) s \(sample (\d+)\)", msg)
    assert m, f"no time and sample in {msg!r}"
    return int(m.group(2)), float(m.group(1))


@pytest.mark.parametrize("name", SCENARIOS)
def test_reproduces_the_closed_forms(name, worst_errors):
    """S3-S7 at the studies' 201 samples: positions equal the seed's closed form to 1e-12 rad
    (measured worst 1.1e-13 rad, S7 move y, where the seed's half-angle formula cancels: its
    loops close only to 1.1e-14 m there, Newton's to 1.4e-16 m); forward kinematics of the
    Newton solution returns the target and closes the loops to 1e-12 m."""
    robot, traj, _ = study_motion(name)
    seed = inverse_kinematics(robot, traj, solver="seed")
    gen = inverse_kinematics(robot, traj, solver="newton", q_start=START.get(robot.name))
    assert (seed.solver, gen.solver) == ("seed closed form", "newton")
    err = float(np.max(np.abs(gen.q - seed.q)))
    worst_errors[f"generic IK vs closed form (rad): {name}"] = err
    print(f"\n{name}: generic IK vs closed form {err:.2e} rad")
    assert err < AGREE_RAD
    x, _, _ = robot.task(gen.q)
    assert np.max(np.abs(x - traj.x)) < FK_M
    if robot.is_closed_chain:
        assert np.max(np.abs(robot.constraint(gen.q))) < FK_M
    # rates are the same exact formula on the same positions
    assert np.max(np.abs(gen.qd - seed.qd)) < 1e-9 * max(1.0, np.max(np.abs(seed.qd)))


def test_coarse_sampling_keeps_the_branch():
    """S3 at only 3 samples (0, 2.5, 5 s): 0.52 and 1.05 rad between samples, more than Newton
    may correct at once, so the steps are subdivided; the result is still the seed's."""
    robot = ps.load("serial_2dof")
    t = np.linspace(0.0, 5.0, 3)
    traj = ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, t)
    run = newton.solve(robot, t, traj.x, START["serial_2dof"])
    assert run.failed is None and run.halvings > 0
    seed = inverse_kinematics(robot, traj, solver="seed")
    assert np.max(np.abs(run.q - seed.q)) < AGREE_RAD


def test_working_mode_follows_the_start_pose():
    """S3 from an elbow-down and an elbow-up start: mirror images. For a1 = a2 the mirror of
    (q1, q2) is (q1 + q2, -q2) (same tip: the elbow reflected in the line base-tip)."""
    robot = ps.load("serial_2dof")
    traj = ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, np.linspace(0.0, 5.0, 201))
    down = inverse_kinematics(robot, traj, solver="newton", q_start=[0.5, 1.0])
    up = inverse_kinematics(robot, traj, solver="newton", q_start=[0.5, -1.0])
    assert np.all(down.q[:, 1] > 0.5) and np.all(up.q[:, 1] < -0.5)
    mirror = np.column_stack([down.q[:, 0] + down.q[:, 1], -down.q[:, 1]])
    assert np.max(np.abs(up.q - mirror)) < AGREE_RAD
    assert np.max(np.abs(robot.task(up.q)[0] - traj.x)) < FK_M


def test_auto_and_seed_choice():
    """auto: the closed form for a built-in robot, Newton once a start pose is given."""
    robot = ps.load("five_bar_type1")
    traj = ps.cubic([0.060852, 0.154665], [0.05, 0.0], 2.0, TIMES)
    assert inverse_kinematics(robot, traj).solver == "seed closed form"
    assert inverse_kinematics(robot, traj, q_start=robot.q_drawn).solver == "newton"
    with pytest.raises(InputError, match="cannot start from q_start"):
        inverse_kinematics(robot, traj, solver="seed", q_start=robot.q_drawn)
    with pytest.raises(InputError, match="unknown inverse-kinematics solver 'closed'"):
        inverse_kinematics(robot, traj, solver="closed")
    with pytest.raises(InputError, match=r"q_start must have shape \(N, 4\) or \(4,\)"):
        inverse_kinematics(robot, traj, solver="newton", q_start=[0.1, 0.2])


def test_user_robot_named_like_a_builtin_gets_newton(derived):
    """A copy of serial_2dof derived into another folder is the user's robot: no closed form."""
    folder, mine = derived(ROBOTS_DIR / "serial_2dof.toml")
    assert mine.name == "serial_2dof" and mine.library.folder == folder
    assert not mine.is_builtin
    traj = ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, np.linspace(0.0, 5.0, 51))
    jt = inverse_kinematics(mine, traj, q_start=START["serial_2dof"])
    assert jt.solver == "newton"
    seed = inverse_kinematics(ps.load("serial_2dof"), traj)
    assert seed.solver == "seed closed form"
    assert np.max(np.abs(jt.q - seed.q)) < AGREE_RAD
    with pytest.raises(InputError, match=r"serial_2dof \(from .*\): solver 'seed' is the "
                                         r"textbook's closed form of the built-in robots"):
        inverse_kinematics(mine, traj, solver="seed")
    # auto without a start pose: the drawn configuration is stretched out, so it cannot choose
    # the elbow: refused, not guessed
    with pytest.raises(WorkspaceError, match=r"drawn configuration q = \[0.0, 0.0\] rad is "
                                             r"singular .* give a start pose"):
        inverse_kinematics(mine, traj)


# -- refusals --------------------------------------------------------------------------------------

def test_unreachable_target():
    """Tip from (100, 100) mm by +300 mm in x: beyond a1 + a2 = 200 mm from sample 3 (t =
    0.75 s). The |F| reported is at least the target's distance to the reachable disc."""
    robot = ps.load("serial_2dof")
    traj = ps.cubic([0.1, 0.1], [0.3, 0.0], T, TIMES)
    r = np.hypot(traj.x[:, 0], traj.x[:, 1])
    k = int(np.argmax(r > A1 + A2))
    with pytest.raises(WorkspaceError, match="is unreachable") as exc:
        inverse_kinematics(robot, traj, solver="newton", q_start=START["serial_2dof"])
    msg = str(exc.value)
    assert _named(msg) == (k, pytest.approx(TIMES[k]))
    assert f"x = {traj.x[k, 0] * 1e3:.6g} mm, y = {traj.x[k, 1] * 1e3:.6g} mm" in msg
    residual = float(re.search(r"\|F\| reached ([0-9.e+-]+) m", msg).group(1))
    assert residual >= (r[k] - (A1 + A2)) / np.sqrt(2)  # inf-norm of a vector that long
    # the same move stopped short of the edge is fine
    inverse_kinematics(robot, ps.cubic([0.1, 0.1], [0.04, 0.0], T, TIMES), solver="newton",
                       q_start=START["serial_2dof"])
    # unreachable from the first sample on: named there, reached from the start pose
    far = ps.cubic([0.3, 0.1], [0.01, 0.0], T, TIMES)
    with pytest.raises(WorkspaceError, match="on the way from the start pose") as exc:
        inverse_kinematics(robot, far, solver="newton", q_start=START["serial_2dof"])
    assert _named(str(exc.value)) == (0, 0.0)


def test_start_pose_off_the_loops():
    """A closed chain's start pose only picks the assembly mode: 0.01 rad off every joint
    (the loops open by millimetres), Newton closes them and S5 is the closed form's."""
    robot = ps.load("five_bar_type1")
    traj = ps.cubic([0.060852, 0.154665], [0.05, 0.0], 2.0, np.linspace(0.0, 2.0, 41))
    start = robot.q_drawn + 0.01
    assert np.max(np.abs(robot.constraint(start))) > 1e-4
    gen = inverse_kinematics(robot, traj, solver="newton", q_start=start)
    seed = inverse_kinematics(robot, traj, solver="seed")
    assert np.max(np.abs(gen.q - seed.q)) < AGREE_RAD


def test_closed_chain_unreachable_names_the_first_sample():
    """5-bar Type I, P by -250 mm in x (41 samples): the first sample the seed's closed form
    (solved alone) cannot reach is the one Newton's message names."""
    robot = ps.load("five_bar_type1")
    t = np.linspace(0.0, T, 41)
    traj = ps.cubic([0.060852, 0.154665], [-0.25, 0.0], T, t)
    with pytest.raises(WorkspaceError) as seed:
        inverse_kinematics(robot, traj, solver="seed")
    with pytest.raises(WorkspaceError, match="is unreachable") as gen:
        inverse_kinematics(robot, traj, solver="newton")
    assert _named(str(gen.value)) == _named(str(seed.value))


def test_singular_pose():
    """The 2-DOF tip driven radially to (1 - 1e-13) of full stretch: [Phi_q; J] singular at the
    last sample; 1e-6 short of it the arm stays elbow down (q2 > 0: the mirror image is only
    2 sqrt(2e-6) = 3e-3 rad away there, yet Newton does not cross)."""
    robot = ps.load("serial_2dof")
    x0 = np.array([0.1, 0.1])
    end = x0 / np.linalg.norm(x0) * (A1 + A2)
    with pytest.raises(WorkspaceError, match="singular pose") as exc:
        inverse_kinematics(robot, ps.cubic(x0, end * (1 - 1e-13) - x0, T, TIMES),
                           solver="newton", q_start=START["serial_2dof"])
    msg = str(exc.value)
    assert _named(msg) == (len(TIMES) - 1, pytest.approx(T))
    assert float(re.search(r"condition number ([0-9.e+inf]+) >", msg).group(1)) > COND_LIMIT
    jt = inverse_kinematics(robot, ps.cubic(x0, end * (1 - 1e-6) - x0, T, TIMES),
                            solver="newton", q_start=START["serial_2dof"])
    q2_end = np.arccos(((0.2 * (1 - 1e-6)) ** 2 - A1**2 - A2**2) / (2 * A1 * A2))
    assert np.all(jt.q[:, 1] > 0) and jt.q[-1, 1] == pytest.approx(q2_end, rel=1e-6)


def test_branch_jump_by_coarse_sampling():
    """S3 sampled at its two ends only: the arm is at rest at both, so the exact rates account
    for none of the 90 deg the shoulder turns; the step is refused at sample 1 (t = 5 s)."""
    robot = ps.load("serial_2dof")
    traj = ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, [0.0, 5.0])
    with pytest.raises(WorkspaceError, match="on another branch than sample 0, or the samples "
                                             "are too coarse") as exc:
        inverse_kinematics(robot, traj, solver="newton", q_start=START["serial_2dof"])
    msg = str(exc.value)
    assert _named(msg) == (1, 5.0)
    moved = float(re.search(r"moves by ([-0-9.e+]+) rad", msg).group(1))
    assert moved == pytest.approx(np.pi / 2, rel=1e-3)


def test_branch_check_sees_an_elbow_flip():
    """The check itself: the seed's elbow-down S3 with the mirror image (q1 + q2, -q2) spliced
    in from sample 120 on, rates from J qd = xd, is refused at sample 120, and only there."""
    robot = ps.load("serial_2dof")
    t = np.linspace(0.0, 5.0, 201)
    traj = ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, t)
    q = inverse_kinematics(robot, traj, solver="seed").q.copy()
    q[120:] = np.column_stack([q[120:, 0] + q[120:, 1], -q[120:, 1]])
    J = robot.task(q)[1]
    qd = np.linalg.solve(J, traj.xd[..., None])[..., 0]
    fails = Failures(robot, t, traj.x)
    newton.branch_check(fails, t, q, qd, np.ones(len(t), dtype=bool))
    assert [k for k, _ in fails.found] == [120]
    clean = Failures(robot, t, traj.x)
    q0 = inverse_kinematics(robot, traj, solver="seed")
    newton.branch_check(clean, t, q0.q, q0.qd, np.ones(len(t), dtype=bool))
    assert clean.found == []


def test_task_and_actuation_must_match():
    """The four-bar has 3 coordinates and 2 loop equations (1 degree of freedom) and a 2-D task
    point: task-space IK is refused, pointing to joint space."""
    four = ps.load(ROOT / "examples" / "four_bar.toml")
    traj = ps.cubic([0.06, 0.08], [0.001, 0.0], 1.0, [0.0, 1.0])
    with pytest.raises(WorkspaceError) as exc:
        inverse_kinematics(four, traj)
    msg = str(exc.value)
    for part in ("3 coordinates", "2 loop equations", "1 degree of freedom",
                 "2-coordinate task (x, y)", "1 actuated joint", "joint space"):
        assert part in msg, msg
