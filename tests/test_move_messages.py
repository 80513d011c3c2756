"""``planar-sym move`` builds a study the user never wrote: its refusals name the options
(``--duration``, ``--from``, ``--by``), not the study's fields (found in a user trial), and a
start and a displacement of different lengths do not blame the displacement alone."""

from __future__ import annotations

import pytest

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
