"""Studies as data: a study of one's own (another move, another robot, another parameter), the
``move`` command, and every problem of a bad study file reported at once, naming the field."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.errors import InputError
from planar_sym.motion.profiles import cubic
from planar_sym.study import spec
from planar_sym.study.run import run
from planar_sym.toml_write import dumps

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def write(tmp_path: Path, text: str, name: str = "study.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


DIAGONAL = """
title = "5-bar Type I, P 30 mm diagonally in 1.5 s"
robot = "five_bar_type1"
kind = "inverse"
[units]
length = "mm"
[motion]
space = "task"
start = [60.852, 154.665]
by = [30.0, 30.0]
duration = 1.5
samples = 151
"""


def test_a_new_move_of_a_built_in_robot(tmp_path):
    """The Type I 5-bar 30 mm diagonally in 1.5 s: torques against the API route by hand."""
    result = run(write(tmp_path, DIAGONAL))
    robot = ps.load("five_bar_type1")
    t = np.linspace(0.0, 1.5, 151)
    joints = ps.inverse_kinematics(robot, cubic([0.060852, 0.154665], [0.03, 0.03], 1.5, t))
    tau, lam = robot.closed_chain_inverse_dynamics(joints.q, joints.qd, joints.qdd)
    assert np.max(np.abs(result.columns["tau1_n_m"] - tau[:, 0])) <= 1e-12 * np.max(np.abs(tau))
    assert np.max(np.abs(result.columns["fy_C_n"] - lam[:, 1])) <= 1e-12 * np.max(np.abs(lam))
    end = [result.columns["x_mm"][-1], result.columns["y_mm"][-1]]
    assert end == pytest.approx([90.852, 184.665], abs=1e-9)


def test_parameter_override_in_description_units_and_with_a_unit(tmp_path):
    """m_motor2 = 0.6 (the description's kg) and "600 g" both give the heavier motor's torques,
    which differ from S3's by dm a1 (a1 qdd1 + g cos q1) + ... on joint 1 (checked against
    with_parameters, the SI route)."""
    base = Path(ps.__file__).parent / "studies" / "serial_2dof_cartesian_move.toml"
    text = base.read_text()
    heavy = run(write(tmp_path, text + "\n[parameters]\nm_motor2 = 0.6\n", "heavy.toml"))
    grams = run(write(tmp_path, text + "\n[parameters]\nm_motor2 = \"600 g\"\n", "grams.toml"))
    arm = ps.load("serial_2dof").with_parameters(m_motor2=0.6)
    q = np.column_stack([heavy.columns[f"q{k}_rad"] for k in (1, 2)])
    qd = np.column_stack([heavy.columns[f"qd{k}_rad_s"] for k in (1, 2)])
    qdd = np.column_stack([heavy.columns[f"qdd{k}_rad_s2"] for k in (1, 2)])
    tau = arm.inverse_dynamics(q, qd, qdd)
    np.testing.assert_allclose(heavy.columns["tau1_n_m"], tau[:, 0], rtol=1e-13, atol=1e-15)
    np.testing.assert_array_equal(grams.columns["tau1_n_m"], heavy.columns["tau1_n_m"])
    light = run("serial_2dof_cartesian_move")
    a1, g = 0.1, 9.81
    extra = (0.6 - 0.292) * a1 * (a1 * qdd[:, 0] + g * np.cos(q[:, 0]))
    assert np.max(np.abs(heavy.columns["tau1_n_m"] - light.columns["tau1_n_m"] - extra)) < 1e-12


def test_unknown_parameter_and_wrong_unit_are_named(tmp_path):
    base = Path(ps.__file__).parent / "studies" / "serial_2dof_cartesian_move.toml"
    path = write(tmp_path, base.read_text()
                 + "\n[parameters]\nm_motr2 = 0.6\nm_link1 = \"71 mm\"\n")
    with pytest.raises(InputError) as exc:
        run(path)
    text = str(exc.value)
    assert "parameters.m_motr2: not a parameter of serial_2dof" in text
    assert "parameters.m_link1" in text and "'mm'" in text


def test_a_description_file_as_the_robot(tmp_path):
    """robot = a description file (relative to the study): derived on first use; the crank
    of the four-bar turned in joint space, the passive joints completed by the loop."""
    study = write(tmp_path, f"""
robot = "{EXAMPLES / 'four_bar.toml'}"
kind = "inverse"
[units]
angle = "deg"
[motion]
space = "joint"
profile = "quintic"
start = [60.0]
by = [90.0]
duration = 1.0
samples = 101
""")
    result = run(study)
    four = ps.load(EXAMPLES / "four_bar.toml")
    q = np.column_stack([result.columns[f"q{k}_rad"] for k in range(1, four.n + 1)])
    assert np.max(np.abs(four.constraint(q))) < 1e-12
    assert result.columns["q1_rad"][-1] == pytest.approx(np.radians(150.0), abs=1e-12)


def test_forward_study_with_constant_torque(tmp_path):
    """Holding torque: the static gravity torque at q = (-60, 0) deg keeps the arm at rest."""
    arm = ps.load("serial_2dof")
    hold = arm.gravity(np.radians([-60.0, 0.0]))
    path = write(tmp_path, f"""
robot = "serial_2dof"
kind = "forward"
[units]
angle = "deg"
[simulation]
q0 = [-60.0, 0.0]
duration = 0.5
samples = 11
torque = [{float(hold[0])!r}, {float(hold[1])!r}]
""")
    result = run(path)
    assert np.max(np.abs(result.columns["q1_rad"] - np.radians(-60.0))) < 1e-12


def test_every_problem_of_a_study_at_once(tmp_path):
    path = write(tmp_path, """
robot = 3
kind = "inverse"
colour = "red"
[units]
length = "furlong"
[motion]
space = "sideways"
profile = "zigzag"
start = [1.0, "a"]
duration = -2
samples = 1
""")
    with pytest.raises(InputError) as exc:
        spec.load(path)
    problems = exc.value.problems
    expected = ["colour: unknown key", "robot: must be a non-empty string (got 3)",
                "units.length: unknown length unit 'furlong'", "motion.space: must be one of",
                "motion.profile: must be one of", "motion.samples: must be an integer from 2",
                "motion.start[1]: \"a\": unknown name a",
                "motion.duration: must be > 0 (got -2)"]
    for e in expected:
        assert any(e in p for p in problems), (e, problems)
    assert all(p.startswith(f"{path}: ") for p in problems)
    assert len(problems) == len(expected) + 1  # and: neither by nor end


def test_a_misspelt_table_is_one_message_and_its_fields_are_still_checked(tmp_path):
    """``[motoin]`` for ``[motion]`` gave the unknown key and then five fields of [motion] as
    missing: now one message, and a real mistake inside it is still found, at motion.*."""
    text = ('robot = "serial_2dof"\nkind = "inverse"\n[motoin]\nspace = "task"\n'
            'start = [100, 100]\nby = [0, 50]\nduration = {}\n')
    path = write(tmp_path, text.format(2))
    with pytest.raises(InputError) as exc:
        spec.load(path)
    assert exc.value.problems == [(f"{path}: motoin: unknown key: did you mean 'motion'? "
                                  "(checked as motion below)")]
    path = write(tmp_path, text.format(-2))
    with pytest.raises(InputError) as exc:
        spec.load(path)
    assert exc.value.problems[1:] == [f"{path}: motion.duration: must be > 0 (got -2)"]
    data = {"robot": "serial_2dof", "kind": "inverse", "motoin": {"space": "task"}}
    with pytest.raises(InputError):
        spec.parse(data, "x")
    assert "motoin" in data and "motion" not in data, "the caller's table was changed"


def test_forward_study_needs_a_simulation_table(tmp_path):
    path = write(tmp_path, 'robot = "serial_2dof"\nkind = "forward"\n[motion]\nspace = "task"\n')
    with pytest.raises(InputError) as exc:
        spec.load(path)
    assert any("simulation: missing table [simulation]" in p for p in exc.value.problems)
    assert any("motion: only for kind = \"inverse\"" in p for p in exc.value.problems)


def test_unknown_robot_and_missing_table_file(tmp_path):
    path = write(tmp_path, 'robot = "no_such_robot"\nkind = "inverse"\n[motion]\nspace = "task"\n'
                 'profile = "table"\nfile = "missing.csv"\n')
    with pytest.raises(InputError, match="missing.csv"):
        spec.load(path)
    path = write(tmp_path, DIAGONAL.replace("five_bar_type1", "no_such_robot"))
    with pytest.raises(ps.PlanarSymError, match="unknown robot 'no_such_robot'"):
        run(path)


def test_wrong_number_of_start_values(tmp_path):
    path = write(tmp_path, DIAGONAL.replace("start = [60.852, 154.665]",
                                            "start = [60.852, 154.665, 0.0]").replace(
        "by = [30.0, 30.0]", "by = [30.0, 30.0, 0.0]"))
    with pytest.raises(InputError, match=r"motion.start: five_bar_type1 needs 2 values, one per "
                                         r"task coordinate \(x, y\) \(got 3\)"):
        run(path)


def test_move_command_equals_the_study_file(tmp_path, capsys):
    out = tmp_path / "out"
    saved = tmp_path / "saved.toml"
    assert main(["move", "five_bar_type1", "--task", "--from", "60.852,154.665", "--by", "30,30",
                 "--duration", "1.5", "--samples", "151", "--out", str(out),
                 "--save-study", str(saved)]) == 0
    printed = capsys.readouterr().out
    assert "five_bar_type1_move: wrote" in printed and "peak |tau|: tau1 " in printed and " N*m" in printed
    table = np.genfromtxt(out / "five_bar_type1_move.csv", delimiter=",", names=True)
    ref = run(write(tmp_path, DIAGONAL))
    np.testing.assert_array_equal(table["tau3_n_m"], ref.columns["tau3_n_m"])
    again = run(saved)  # the saved study is the same move
    np.testing.assert_array_equal(again.columns["tau1_n_m"], ref.columns["tau1_n_m"])


def test_move_with_a_parameter_and_negative_numbers(tmp_path):
    out = tmp_path / "out"
    assert main(["--quiet", "move", "serial_2dof", "--task", "--from", "100,100", "--by=-200,0",
                 "--duration", "5", "--set", "m_motor2=600 g", "--out", str(out)]) == 0
    table = np.genfromtxt(out / "serial_2dof_move.csv", delimiter=",", names=True)
    arm = ps.load("serial_2dof").with_parameters(m_motor2=0.6)
    q = np.column_stack([table["q1_rad"], table["q2_rad"]])
    qd = np.column_stack([table["qd1_rad_s"], table["qd2_rad_s"]])
    qdd = np.column_stack([table["qdd1_rad_s2"], table["qdd2_rad_s2"]])
    np.testing.assert_allclose(table["tau1_n_m"], arm.inverse_dynamics(q, qd, qdd)[:, 0],
                               rtol=1e-13, atol=1e-15)


def test_move_refuses_bad_input_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["move", "serial_2dof", "--task", "--from", "100,abc", "--by", "1,1",
                 "--duration", "1", "--out", str(out)]) == 2
    assert "--from must be comma-separated numbers" in capsys.readouterr().err
    assert main(["move", "serial_2dof", "--task", "--from", "100,100", "--by", "1,1",
                 "--duration", "0", "--out", str(out)]) == 2
    assert "--duration: must be > 0" in capsys.readouterr().err
    assert not out.exists()


def test_saved_study_toml_round_trips():
    table = {"title": "a \"quoted\" title", "robot": "/x/y.toml", "kind": "inverse",
             "units": {"length": "mm"}, "motion": {"start": [1.0, -2.5], "samples": 3,
                                                    "split": False}}
    assert tomllib.loads(dumps(table)) == table


def test_list_shows_a_folder_of_ones_own(tmp_path, capsys):
    (tmp_path / "four_bar.toml").write_text((EXAMPLES / "four_bar.toml").read_text())
    write(tmp_path, DIAGONAL, "diagonal.toml")
    assert main(["list", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "serial_2dof_free_swing" in out and "parallel_3rrr" in out
    robots = out.split("robot descriptions")[1].split("generated robots")[0]
    studies = out.split("studies (planar-sym run FILE)")[1]
    assert "four_bar.toml" in robots and "diagonal.toml" in studies


@pytest.mark.parametrize("override, message", [
    ({"m_link1": -0.1}, "parameter m_link1 must be > 0 kg (got -0.1)"),
    ({"izz_link2": -1e-6}, "parameter izz_link2 must be >= 0 kg*m^2"),
    ({"izz_link1": 89.395}, "radius of gyration of 3.548e+04 mm"),  # kg*mm^2 typed as kg*m^2
    ({"izz_link1": 0.0}, "izz_link1 must be > 0 for a body with extent"),
    ({"g": 9810.0}, "parameter g (gravity magnitude) must be from 0 to 300 m/s^2 (got 9810)"),
    ({"m_motor2": float("inf")}, "parameter m_motor2 must be finite (got inf)"),
])
def test_parameters_changed_at_run_time_are_checked(override, message):
    with pytest.raises(InputError) as exc:
        ps.load("serial_2dof").with_parameters(**override)
    assert message in str(exc.value)


def test_the_point_mass_motor_may_have_zero_inertia():
    """motor2 is a point mass at the elbow (one point): izz = 0 is physical there."""
    arm = ps.load("serial_2dof").with_parameters(izz_motor2=0.0, m_motor2=0.5)
    assert arm.parameters["m_motor2"] == 0.5


def test_study_parameter_slip_is_refused(tmp_path):
    base = Path(ps.__file__).parent / "studies" / "serial_2dof_cartesian_move.toml"
    path = write(tmp_path, base.read_text() + "\n[parameters]\nm_link1 = \"-71 g\"\n")
    with pytest.raises(InputError, match=r"parameter m_link1 must be > 0 kg \(got -0.071\)"):
        run(path)


FREE_FIVE_BAR = """
robot = "five_bar_type2"
kind = "forward"
[units]
angle = "deg"
[simulation]
q0 = {q0}
duration = 0.2
samples = 21
"""


def test_closed_chain_forward_study_from_the_actuated_joints(tmp_path):
    """q0 = the actuated joints A, E (deg): the loop gives B and D; the drawn pose of the Type II
    5-bar is A = 0, E = 90 deg, so this starts exactly there."""
    result = run(write(tmp_path, FREE_FIVE_BAR.format(q0="[0.0, 90.0]")))
    five = ps.load("five_bar_type2")
    q0 = [result.columns[f"q{k}_rad"][0] for k in range(1, 5)]
    assert np.max(np.abs(np.array(q0) - five.q_drawn)) < 1e-12
    q = np.column_stack([result.columns[f"q{k}_rad"] for k in range(1, 5)])
    assert np.max(np.abs(five.constraint(q))) < 1e-9


def test_closed_chain_state_off_the_loops_is_refused(tmp_path):
    path = write(tmp_path, FREE_FIVE_BAR.format(q0="[0.0, 90.0, 92.0, 90.0]"))
    with pytest.raises(InputError, match=r"simulation.q0 does not close the loop at cut joint C: "
                                         r"the joint's two points are [0-9.]+ mm apart"):
        run(path)


def test_saved_study_names_a_description_file_relative_to_itself(tmp_path, capsys):
    """`move ROBOT.toml --save-study` wrote the robot's absolute path (issue 29): the study
    names it relative to the study file, so the pair can be moved together and run again."""
    import shutil

    work = tmp_path / "work"
    (work / "robots").mkdir(parents=True)
    robot = work / "robots" / "pendulum.toml"
    shutil.copy(Path(__file__).parent / "robots" / "pendulum.toml", robot)
    saved = work / "studies" / "swing.toml"
    saved.parent.mkdir()
    assert main(["--quiet", "move", str(robot), "--joint", "--from", "0", "--to", "30", "--duration",
                 "1", "--out", str(tmp_path / "out"), "--save-study", str(saved)]) == 0
    assert tomllib.loads(saved.read_text())["robot"] == "../robots/pendulum.toml"
    moved = tmp_path / "moved"
    shutil.move(str(work), str(moved))
    again = run(moved / "studies" / "swing.toml")  # still finds its robot
    first = np.genfromtxt(tmp_path / "out" / "pendulum_move.csv", delimiter=",", names=True)
    np.testing.assert_array_equal(again.columns["tau1_n_m"], first["tau1_n_m"])


def test_a_robot_without_a_task_or_a_motor_is_said_so(tmp_path):
    """'needs 0 values, one per task coordinate ()' said nothing useful (user trial): a robot
    with no [task] is told to move in joint space, one with no actuated joint that nothing
    takes a torque."""
    robots = Path(__file__).resolve().parent / "robots"
    path = write(tmp_path, f'robot = "{robots / "cart_pole.toml"}"\nkind = "inverse"\n'
                 '[motion]\nspace = "task"\nstart = [0.2, 0.0]\nby = [0.1, 0.0]\nduration = 1\n')
    with pytest.raises(InputError) as exc:
        run(path)
    assert str(exc.value).endswith("motion.start: " + str(robots / "cart_pole.toml")
                                   + ' has no task point (no [task] in its description): move '
                                   'its joints instead (space = "joint") (got 2 values)')
    free = tmp_path / "free_pendulum.toml"
    free.write_text((robots / "point_pendulum.toml").read_text().replace(
        "actuated = true", "actuated = false"))
    path = write(tmp_path, f'robot = "{free}"\nkind = "forward"\n[simulation]\nq0 = [0.5]\n'
                 'duration = 0.1\ntorque = [5.0]\n', name="push.toml")
    with pytest.raises(InputError) as exc:
        run(path)
    assert str(exc.value).endswith(f"simulation.torque: {free} has no actuated joint (every "
                                   "joint is passive): nothing takes a torque; mark the driven "
                                   "joint actuated = true in its description (got 1 value)")


def test_joint_angles_beyond_a_turn_in_radians_warn_once(tmp_path):
    """A study without [units] is in radians: start = [60], by = [360] meant in degrees ran
    57 turns in a second, 1699 N*m, without a word (user trial). Warned as the description
    warns its drawn angles, once for the slip; in degrees, or within a turn, nothing."""
    import warnings

    text = ('robot = "serial_2dof"\nkind = "inverse"\n{units}[motion]\nspace = "joint"\n'
            'start = [60.0, 0.0]\nby = [360.0, 0.0]\nduration = 1.0\nsamples = 11\n')
    path = write(tmp_path, text.format(units=""))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run(path)
    said = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert said == [(f"{path}: motion.start[0] = 60 rad is 9.55 turns (a warning beyond one): "
                    "were the angles typed in degrees? ([units] angle = \"deg\" makes it 60 "
                    "deg)")]
    for units in ('[units]\nangle = "deg"\n', ""):
        path = write(tmp_path, text.format(units=units) if units else
                     text.format(units="").replace("by = [360.0", "by = [-6.2").replace(
                         "start = [60.0", "start = [6.0"),
                     name="ok.toml")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            run(path)
        assert not [str(w.message) for w in caught if "turns" in str(w.message)]


def test_a_start_pose_and_a_start_error_typed_in_degrees_warn(tmp_path):
    """A trial: start_pose = [0, 90] in a radian file wrote q2 = 89.5 rad in every row, and
    start_error = [2, -2] (meant in degrees) started the controller 115 degrees off, both
    without a word (start, by and q0 warned). A start pose beyond a turn, a start error beyond a
    quarter turn warn, each naming its field; the study's own degrees, or small radians, do not."""
    import warnings

    pose = ('robot = "serial_2dof"\nkind = "inverse"\n[units]\nlength = "mm"\n[motion]\n'
            'space = "task"\nstart = [100.0, 100.0]\nby = [-200.0, 0.0]\nduration = 1.0\n'
            'samples = 11\nstart_pose = [0.0, {q2}]\n')
    track = (ROOT / "planar_sym" / "studies" / "serial_2dof_cartesian_track.toml").read_text()
    assert 'angle = "deg"' in track and "start_error = [2.0, -2.0]" in track
    cases = [(pose.format(q2="90.0"), ("motion.start_pose[1] = 90 rad is 14.3 turns (a warning "
                                       "beyond one)")),
             (track.replace('angle = "deg"\n', "").split("[outputs]")[0],
              "control.start_error[0] = 2 rad is 0.318 turns (a warning beyond a quarter)"),
             (pose.format(q2="1.5708"), None),
             (track.split("[outputs]")[0], None),
             (track.replace('angle = "deg"\n', "").replace("start_error = [2.0, -2.0]",
                                                           "start_error = [0.03, -0.03]")
              .split("[outputs]")[0], None)]
    for k, (text, want) in enumerate(cases):
        path = write(tmp_path, text, name=f"s{k}.toml")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            run(path, samples=11)
        said = [str(w.message) for w in caught if "turns" in str(w.message)]
        value = None if want is None else want.split(" = ")[1].split(" rad")[0]
        assert said == ([] if want is None else [
            (f"{path}: {want}: were the angles typed in degrees? ([units] angle = \"deg\" "
             f"makes it {value} deg)")]), k


def test_a_robot_description_given_as_a_study_is_one_message(tmp_path, capsys):
    """A robot file where a study is expected gave ten 'unknown key' lines and 'robot:
    missing' (user trial): one message says what it is and what a study needs."""
    robot = Path(__file__).resolve().parent / "robots" / "pendulum.toml"
    assert main(["run", str(robot), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err == (f"error: invalid study:\n  {robot}: a robot description, not a study: a "
                   'study names its robot (robot = "<this file>") and says what to do with it '
                   "(kind, [motion]...); `planar-sym move` runs one move of a robot without a "
                   "study\n")


def test_a_task_start_out_of_reach_in_metres_asks_about_millimetres(tmp_path):
    """start = [100, 100] meant in mm, read in the default m: 'target x = 100000 mm
    unreachable' said nothing of the unit (user trial); a start 10 m or more away asks."""
    text = ('robot = "serial_2dof"\nkind = "inverse"\n[motion]\nspace = "task"\n'
            "start = [{0}, {0}]\nby = [-0.2, 0.0]\nduration = 1.0\n")
    with pytest.raises(ps.WorkspaceError) as exc:
        run(write(tmp_path, text.format(100.0)))
    assert str(exc.value).endswith("; the study's lengths are in m ([units] length, default "
                                   'm): were they typed in mm? ([units] length = "mm")')
    with pytest.raises(ps.WorkspaceError) as exc:  # out of reach, but not by a unit
        run(write(tmp_path, text.format(0.5), name="near.toml"))
    assert "typed in mm" not in str(exc.value)


def test_a_name_near_no_known_one_suggests_nothing(tmp_path, capsys):
    """The did-you-mean only for a near name (difflib's ratio at least spelling.CUTOFF = 0.75):
    `mot` (0.67 of `motion`) lists the known keys instead; a study name near no built-in one
    ends with the list, no suggestion."""
    path = write(tmp_path, 'robot = "serial_2dof"\nkind = "inverse"\n[mot]\nspace = "task"\n')
    with pytest.raises(InputError) as exc:
        spec.load(path)
    assert exc.value.problems[0] == (f"{path}: mot: unknown key (known: constants, control, "
                                     "events, kind, motion, notes, optimal, optimise, outputs, "
                                     "parameters, robot, simulation, title, units)")
    assert main(["run", "zzzz"]) == 2
    assert capsys.readouterr().err.rstrip().endswith("nor a study file (.toml)")
