"""Optimal-move studies (``kind = "optimal"``, issue 27 items 2, 4 and 6): the built-in
cart-pole swing-up tracked by the time-varying LQR and balanced, a move run as an inverse
study runs its motion (its torques re-computed by the inverse dynamics equal the solver's),
a closed chain's move on its loops, and every mistake in the file named once."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.study.checks import StudyError
from planar_sym.study.spec import parse

UP = 90.0


def test_cart_pole_swing_up_balances_on_a_heavier_bob():
    """The built-in study: least effort in 2 s under |F| <= 0.2 N (the plan), tracked on a
    plant whose bob is 10 % heavier, then held: upright to 1e-5 rad, the cart back at 0 to
    1e-5 m, the energy balance closed, the pole's error reported beside the cart's."""
    res = ps.run_study("cart_pole_swing_up")
    t, q2 = res.get("t").values, res.get("q", index=1).values
    assert t[-1] == 5.0 and len(t) == 501
    assert abs(q2[-1] - np.pi / 2) < 1e-5 and abs(res.get("q", index=0).values[-1]) < 1e-5
    e1, e2 = res.get("e", index=0).values, res.get("e", index=1).values
    assert np.abs(e1).max() < 5e-3 and np.abs(e2).max() < 5e-3  # 1.9 mm, 1.6 mrad seen
    assert abs(e2[-1]) < 1e-5
    # the plan's sentence and the tracking's, in the note and in the timing line
    assert res.timing.startswith("optimal move (effort): 2 s") and "peak |tau| 0.2 N" in res.timing
    assert "time-varying LQR" in res.note and "plant parameters differ: m_pole" in res.note
    tau = res.get("tau", index=0).values
    assert 0.2 <= np.abs(tau).max() < 0.25
    balance = res.get("balance").values
    assert np.abs(balance).max() < 1e-9 * max(np.abs(res.get("work").values).max(), 1e-3)


def test_a_move_run_as_an_inverse_study_has_the_solvers_torques(tmp_path):
    """serial_2dof, least effort in 0.8 s: the study's torques, from the inverse dynamics
    along the move at its nodes, equal the solver's (CasADi's graph of the same functions)
    and ps.optimal_move's called directly; resampled, the move passes through its nodes."""
    path = tmp_path / "arm_move.toml"
    path.write_text("""robot = "serial_2dof"
kind = "optimal"
[units]
angle = "deg"
[optimal]
start = [0.0, 0.0]
end = [60.0, -30.0]
duration = 0.8
intervals = 40
""")
    res = ps.run_study(path)
    move = ps.optimal_move(ps.load("serial_2dof"), [0.0, 0.0], np.radians([60.0, -30.0]),
                           duration_s=0.8, intervals=40)
    tau = np.column_stack([res.get("tau", index=i).values for i in range(2)])
    assert np.abs(tau - move.tau).max() <= 1e-9 * np.abs(move.tau).max()
    assert "jload_joint1" in "".join(res.columns)  # an inverse study's joint loads
    fine = ps.run_study(path, samples=81)  # every other sample is a node
    q = fine.get("q", index=1).values
    assert np.abs(q[::2] - move.trajectory.q[:, 1]).max() < 1e-12


def test_a_closed_chain_move_stays_on_its_loops(tmp_path):
    """five_bar_type1, fastest under 0.1 N*m per motor: on its loops at every sample (the
    passive joints from them), the torques within the limit."""
    path = tmp_path / "fb_fast.toml"
    path.write_text("""robot = "five_bar_type1"
kind = "optimal"
[units]
angle = "deg"
[optimal]
start = [118.8, 61.2]
end = [92.8, 41.1]
objective = "time"
intervals = 30
torque_limit = [0.1, 0.1]
""")
    res = ps.run_study(path)
    robot = ps.load("five_bar_type1")
    q = np.column_stack([res.get("q", index=i).values for i in range(robot.n)])
    assert np.abs(robot.constraint(q)).max() < 1e-9
    tau = np.column_stack([res.get("tau", index=i).values for i in robot.actuated])
    assert np.abs(tau).max() <= 0.1 * (1 + 1e-6)
    assert "optimal move (time)" in res.timing


def test_the_cart_pole_plan_alone_is_the_solvers_nodes(tmp_path):
    """A tree with a passive joint cannot be given a motion: without [control] the result is
    the plan itself, said so, with the force the solver found at each node."""
    path = tmp_path / "plan.toml"
    path.write_text("""robot = "cart_pole"
kind = "optimal"
[units]
angle = "deg"
[optimal]
start = [0.0, -90.0]
end = [0.0, 90.0]
objective = "time"
intervals = 60
torque_limit = [0.2]
""")
    res = ps.run_study(path)
    assert "hinge passive: no joint loads" in res.note
    assert np.abs(res.get("tau", index=0).values).max() == pytest.approx(0.2, rel=1e-6)
    assert res.get("t").values[-1] == pytest.approx(1.58, abs=0.02)  # 1.583 s at 100


BAD = [
    ("[control]\nlaw = \"lqr\"\nr_weight = 1.0", "control.q_weight: missing"),
    ("[control]\nlaw = \"pd\"\nkp = 1.0\nkd = 1.0\nq_weight = [1.0]",
     "control.q_weight: only for law = \"lqr\""),
    ("[control]\nlaw = \"lqr\"\nkp = 1.0\nq_weight = 1.0\nr_weight = 1.0",
     "control.kp: not used by law = \"lqr\""),
    ("[motion]\nspace = \"joint\"", "motion: not for kind = \"optimal\""),
]


@pytest.mark.parametrize("extra, message", BAD)
def test_mistakes_in_the_file_are_named_once(extra, message):
    text = ("robot = \"cart_pole\"\nkind = \"optimal\"\n[optimal]\nstart = [0.0, -1.5]\n"
            "end = [0.0, 1.5]\nduration = 2.0\n" + extra)
    import tomllib

    with pytest.raises(StudyError) as err:
        parse(tomllib.loads(text), "bad")
    assert message in str(err.value) and len(err.value.problems) == 1, err.value.problems


def test_optimal_table_errors():
    import tomllib

    for text, message in [
        (("kind = \"inverse\"\n[motion]\nspace = \"joint\"\nstart = [0.0]\nby = [1.0]\n"
          "duration = 1.0\n[optimal]\nstart = [0.0]\nend = [1.0]"), "optimal: only for kind"),
        ("kind = \"optimal\"\n[optimal]\nstart = [0.0]\nend = [1.0, 2.0]\nduration = 1.0",
         "optimal.end: has 2 values and optimal.start 1: both need one per coordinate"),
        (("kind = \"optimal\"\n[optimal]\nstart = [0.0]\nend = [1.0]\nobjective = \"time\"\n"
          "duration = 1.0"), "optimal.duration: not used by objective = \"time\""),
        ("kind = \"optimal\"\n[optimal]\nstart = [0.0]\nend = [1.0]", "optimal.duration"),
        (("kind = \"optimal\"\n[optimal]\nstart = [0.0]\nend = [1.0]\nobjective = \"fast\"\n"
          "duration = 1.0"), "optimal.objective: must be one of time, effort"),
    ]:
        with pytest.raises(StudyError) as err:
            parse(tomllib.loads("robot = \"cart_pole\"\n" + text), "bad")
        assert message in str(err.value) and len(err.value.problems) == 1, err.value.problems


def test_a_start_of_the_wrong_width_names_the_field(tmp_path):
    path = tmp_path / "wide.toml"
    path.write_text("robot = \"cart_pole\"\nkind = \"optimal\"\n[optimal]\nstart = [0.0, -1.5, "
                    "0.0]\nend = [0.0, 1.5, 0.0]\nduration = 2.0\n")
    with pytest.raises(ps.InputError, match="wide.toml: optimal.start: cart_pole needs 2 "
                                            "values, one per coordinate"):
        ps.run_study(path)


def test_an_infeasible_move_is_named_by_the_study_and_its_field(tmp_path):
    """IPOPT's refusal said "lengthen duration_s" and no file: the study's own words now."""
    path = tmp_path / "rush.toml"
    path.write_text("robot = \"cart_pole\"\nkind = \"optimal\"\n[optimal]\nstart = [0.0, -1.5708]\n"
                    "end = [0.0, 1.5708]\nduration = 0.05\nintervals = 20\n"
                    "torque_limit = [0.2]\n")
    with pytest.raises(ps.SimulationError, match=r"rush.toml: optimal: cart_pole: IPOPT found no "
                                                 r"optimal move .*lengthen optimal.duration"):
        ps.run_study(path)


def test_the_command_line_runs_it(tmp_path):
    out = subprocess.run([sys.executable, "-m", "planar_sym", "run", "cart_pole_swing_up",
                          "--out", str(tmp_path), "--samples", "101"], capture_output=True,
                         text=True, timeout=300, check=False)
    assert out.returncode == 0, out.stderr
    assert "optimal move (effort): 2 s" in out.stdout and "tracking error: max e1" in out.stdout
    header = (tmp_path / "cart_pole_swing_up.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["t_s", "q1_m", "q2_rad"] and "e2_rad" in header
    assert (tmp_path / "cart_pole_swing_up.gif").is_file()


@pytest.mark.parametrize("table, message", [
    ("end = [1.0]\nduration = 1.0", "optimal.start: missing"),
    ("start = [0.0]\nduration = 1.0", "optimal.end: missing"),
    ("start = [0.0]\nend = [1.0]\nduration = 1.0\nintervals = 1",
     "optimal.intervals: must be an integer from 2 to 10000 (got 1)"),
    ("start = [0.0]\nend = [1.0]\nduration = 1.0\ntorque_limit = [0.0]",
     "optimal.torque_limit: must be positive (got [0.0])"),
    ("start = [0.0]\nend = [1.0]\nduration = 1.0\nspeed_limit = [-2.0]",
     "optimal.speed_limit: must be positive (got [-2.0])"),
    ("start = [0.0]\nend = [1.0]\nduration = -1.0", "optimal.duration: must be > 0"),
    ("start = [0.0]\nend = [1.0]\nduration = 2e6", "optimal.duration: must be at most 1e+06"),
    ("start = [0.0]\nend = [1.0]\nobjective = \"energy\"", "optimal.duration: missing"),
    ("start = [0.0]\nend = [1.0]\nduration = 1.0\nspeed = 2.0", "optimal.speed: unknown key"),
    ("start = \"0\"\nend = [1.0]\nduration = 1.0", "optimal.start: must be a list of numbers"),
])
def test_each_field_of_the_optimal_table_is_named(table, message):
    import tomllib

    with pytest.raises(StudyError) as err:
        parse(tomllib.loads("robot = \"cart_pole\"\nkind = \"optimal\"\n[optimal]\n" + table),
              "bad")
    assert len(err.value.problems) == 1 and message in err.value.problems[0], err.value.problems


@pytest.mark.parametrize("name, edit, words", [
    # a tracking study (a user trial's slip): 3 s of the S3 arm's 5 s move
    ("serial_2dof_cartesian_track", ("duration = 6.0", "duration = 3.0"), ("3 s", "5 s")),
    # an optimal study tracked by LQR
    ("cart_pole_swing_up", ("duration = 5.0", "duration = 1.5"), ("1.5 s", "2 s"))])
def test_a_run_shorter_than_its_move_is_refused(tmp_path, name, edit, words):
    """A run that would stop in the middle of the move it tracks (silently unfinished before)
    is named by its field, on a tracking study and on an optimal one alike."""
    study = (ROOT / "planar_sym" / "studies" / f"{name}.toml").read_text()
    short = tmp_path / "short.toml"
    short.write_text(study.replace(*edit))
    with pytest.raises(ps.InputError, match=f"short.toml: control.duration {words[0]} ends "
                                            f"before the move it tracks \\({words[1]}\\)"):
        ps.run_study(short)


def test_weights_of_the_wrong_width_are_named(tmp_path):
    """A student's slip in an optimal study tracked by LQR: a q_weight of three values for a
    pendulum's two states, named by its field."""
    study = (ROOT / "planar_sym" / "studies" / "cart_pole_swing_up.toml").read_text()
    wide = tmp_path / "wide.toml"
    wide.write_text(study.replace("q_weight = [100.0, 100.0, 1.0, 1.0]", "q_weight = [1.0, 2.0]"))
    with pytest.raises(ps.InputError, match="wide.toml: control.q_weight: cart_pole needs 4 "
                                            "values, one per state"):
        ps.run_study(wide)
    one = tmp_path / "one.toml"  # one number: every state alike
    one.write_text(study.replace("q_weight = [100.0, 100.0, 1.0, 1.0]", "q_weight = 100.0"))
    assert abs(ps.run_study(one).get("q", index=1).values[-1] - np.pi / 2) < 1e-4


class _Searched(Exception):
    pass


@pytest.mark.parametrize("angle, start, end, said", [
    # in degrees, two turns of the pole: a move, not a slip (optimal_move's own warning, whose
    # advice is the Python API's, is the study's to replace)
    ("deg", "[0.0, -90.0]", "[0.0, 630.0]", None),
    # in radians, 90 meant in degrees: said once, by the study's file and field
    ("rad", "[0.0, -1.5707963]", "[0.0, 90.0]",
     ("optimal.end[1] = 90 rad is 14.3 turns (a warning beyond one): were the angles typed in "
      "degrees? ([units] angle = \"deg\" makes it 90 deg)")),
])
def test_an_optimal_study_s_turns_are_judged_by_its_units(tmp_path, monkeypatch, angle, start,
                                                            end, said):
    """optimal_move warns where a Python caller's angles pass a turn (degrees typed as
    radians); a study knows its [units]: its own rule speaks instead, naming the file and the
    field, and a move of several turns in a degree study is no slip. The search itself is
    replaced: only the warnings before it are tested."""
    import warnings

    from planar_sym.optimal import point_to_point
    from planar_sym.study.optimal_run import plan
    from planar_sym.study.run import load_study, robot_of

    def search(*a, **k):
        raise _Searched

    monkeypatch.setattr(point_to_point, "_search", search)
    text = (ROOT / "planar_sym" / "studies" / "cart_pole_swing_up.toml").read_text()
    text = text.replace('angle = "deg"', f'angle = "{angle}"').replace(
        "start = [0.0, -90.0]", f"start = {start}").replace("end = [0.0, 90.0]", f"end = {end}")
    path = tmp_path / "swing.toml"
    path.write_text(text)
    st = load_study(str(path))
    robot = robot_of(st)
    with warnings.catch_warnings(record=True) as rec, pytest.raises(_Searched):
        warnings.simplefilter("always")
        plan(st, robot)
    got = [str(w.message) for w in rec]
    assert got == ([] if said is None else [f"{path}: {said}"]), got
