"""``planar-sym move`` builds a study the user never wrote: its refusals name the options
(``--duration``, ``--from``, ``--by``), not the study's fields (found in a user trial), and a
start and a displacement of different lengths do not blame the displacement alone."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROBOTS_DIR

from planar_sym.cli import main


@pytest.mark.parametrize("argv, words", [
    (["--joint", "--from", "0,0", "--by", "10,10", "--duration", "-5"],
     "invalid move:\n  --duration: must be > 0 (got -5.0)"),
    (["--task", "--from", "100,100,5", "--by", "0,10", "--duration", "1"],
     "invalid move:\n  --by: has 2 values and --from 3: both need one per coordinate moved"),
    (["--task", "--from", "100,100,5", "--by", "0,10,0", "--duration", "1"],
     ("serial_2dof_move: --from: serial_2dof needs 2 values, one per task coordinate (x, y) "
     "(got 3)")),
])
def test_move_refusals_name_the_options(tmp_path, capsys, argv, words):
    assert main(["move", "serial_2dof", *argv, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert words in err and "motion." not in err, err
    assert not list(tmp_path.iterdir()), "nothing half-written"


def test_a_robot_name_where_a_study_is_expected_points_to_move(capsys):
    """`planar-sym animate serial_2dof` said only 'unknown study' (user trial); a misspelt
    study name gets the nearest one."""
    assert main(["animate", "serial_2dof"]) == 2
    err = capsys.readouterr().err
    assert err.rstrip().endswith("; serial_2dof is a robot: `planar-sym move serial_2dof ...` "
                                 "runs a move of it without a study"), err
    assert main(["run", "serial_2dof_cartesain_move"]) == 2
    assert capsys.readouterr().err.rstrip().endswith(
        "nor a study file (.toml); did you mean 'serial_2dof_cartesian_move'?")


def test_a_robot_drawn_stretched_moves_from_a_start_pose(tmp_path, capsys):
    """A 2-link arm drawn straight (the first tutorial's advice) cannot start a task move from
    its singular drawn pose; the refusal pointed to a start pose that `move` had no option for.
    Now it names --start-pose, and with it the move gives the seed's closed-form IK's torques
    (the built-in serial_2dof, elbow down) to 1e-12 N*m."""
    arm = tmp_path / "arm2.toml"
    arm.write_text((ROBOTS_DIR / "serial_2dof.toml").read_text().replace(
        'name = "serial_2dof"', 'name = "arm2"', 1))
    move = ["--task", "--from", "100,100", "--to", "120,120", "--duration", "1"]
    assert main(["move", str(arm), *move, "--out", str(tmp_path / "a")]) == 2
    err = capsys.readouterr().err
    assert "give a start pose in the mode you want (--start-pose), e.g. with the elbow bent" \
        in err and "motion.start_pose" not in err, err
    assert main(["--quiet", "move", str(arm), *move, "--start-pose", "0,90", "--out",
                 str(tmp_path / "b")]) == 0
    assert main(["--quiet", "move", "serial_2dof", *move, "--out", str(tmp_path / "c")]) == 0
    got = np.genfromtxt(tmp_path / "b" / "arm2_move.csv", delimiter=",", names=True)
    seed = np.genfromtxt(tmp_path / "c" / "serial_2dof_move.csv", delimiter=",", names=True)
    for col in ("tau1_n_m", "tau2_n_m", "q2_rad"):
        assert np.abs(got[col] - seed[col]).max() < 1e-12, col


def test_a_robot_without_a_task_is_told_the_joint_option(tmp_path, capsys):
    assert main(["move", "slider_crank", "--task", "--from", "100,0", "--to", "150,0",
                 "--duration", "1", "--out", str(tmp_path)]) == 2
    assert "move its joints instead (--joint)" in capsys.readouterr().err
