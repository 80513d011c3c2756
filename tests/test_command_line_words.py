"""Messages in the words of the route the user took, one per mistake (a user trial, trial H).

Each case said something true in another route's words, or several lines for one slip: a
``--set`` warning was headed "parameters:", a sweep's error named ``vary['m_link1']``, a
semicolon-separated table gave one "missing column" per column, ``--out`` under a file was the
system's bare "Not a directory", and joint limits typed in degrees in a radian study fired "at
t = 0 s" with no file or field.
"""

from __future__ import annotations

import pytest
from conftest import ROOT

from planar_sym.cli import main

MOVE = ["move", "serial_2dof", "--task", "--from", "100,100", "--by=-200,0", "--duration", "2"]


def test_a_set_warning_names_the_option(tmp_path, capsys):
    assert main([*MOVE, "--set", "m_link2=75", "--out", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert err.startswith("warning: --set: parameter m_link2 = 75 kg (read in kg) is more than "
                          "osmium"), err
    assert "parameters:" not in err


def test_a_sweep_error_names_the_option(tmp_path, capsys):
    assert main(["sweep", "serial_2dof_cartesian_move", "--vary", "m_link1=nan,1", "--out",
                 str(tmp_path)]) == 2
    assert capsys.readouterr().err == "error: --vary m_link1 must be finite (got [nan, 1.0])\n"


def test_a_semicolon_table_is_one_message(tmp_path, capsys):
    table = tmp_path / "move.csv"
    table.write_text("t_s;x_mm;y_mm\n0;100;100\n1;90;100\n")
    study = tmp_path / "s.toml"
    study.write_text('robot = "serial_2dof"\nkind = "inverse"\n[units]\nlength = "mm"\n'
                     '[motion]\nspace = "task"\nprofile = "table"\n'
                     f'file = "{table.name}"\nsamples = 11\n')
    assert main(["run", str(study), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err == (f"error: {table}: line 1: the header 't_s;x_mm;y_mm' is one column: the "
                   "table's columns are separated by semicolons; separate them by commas (a CSV "
                   "file)\n")


def test_out_under_a_file_is_said_so(tmp_path, capsys):
    (tmp_path / "afile").write_text("")
    out = tmp_path / "afile" / "sub"
    assert main(["run", "serial_2dof_cartesian_move", "--out", str(out)]) == 2
    assert capsys.readouterr().err == (f"error: --out {out}: {tmp_path / 'afile'} is a file, so "
                                       "no folder can be made under it\n")


def test_joint_limits_in_degrees_in_a_radian_study_are_named(tmp_path, capsys):
    text = (ROOT / "planar_sym" / "studies" / "serial_2dof_cartesian_track_pd.toml").read_text()
    assert 'angle = "deg"' in text and "joint_limits = { joint2 = [-175.0, 175.0] }" in text
    study = tmp_path / "track.toml"
    study.write_text(text.replace('angle = "deg"\n', "").replace(
        "start_error = [2.0, -2.0]", "start_error = [0.03, -0.03]").split("[outputs]")[0])
    main(["run", str(study), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert (f"warning: {study}: events.joint_limits.joint2[0] = -175 rad is 27.9 turns (a "
            "warning beyond one): were the angles typed in degrees?") in err


def test_vary_takes_a_unit_after_its_values(tmp_path):
    """Two trials: --vary took SI only while --set and a study read a value with its unit. A
    unit after the values converts them (the grid's count stays a count); a unit of another
    quantity is refused naming the option."""
    from planar_sym.analysis.sweep import sweep
    from planar_sym.commands.sweep import parse_vary
    from planar_sym.errors import InputError
    from planar_sym.study.run import load_study, robot_of

    robot = robot_of(load_study("serial_2dof_cartesian_move"))
    assert parse_vary(["m_link2=50:90:5 g"], False, robot) == {"m_link2": (0.05, 0.09, 5.0)}
    assert parse_vary(["m_link2=60,90 g"], False, robot) == {"m_link2": [0.06, 0.09]}
    assert parse_vary(["px_link1_CS2,px_link2_CS2=90,110 mm"], False, robot) == {
        "px_link1_CS2,px_link2_CS2": [0.09, 0.11]}
    got = sweep("serial_2dof_cartesian_move", {"m_link2": [0.06, 0.09]}, workers=1)
    assert main(["sweep", "serial_2dof_cartesian_move", "--vary", "m_link2=60,90 g", "--out",
                 str(tmp_path)]) == 0
    header, *rows = (tmp_path / "serial_2dof_cartesian_move_sweep.csv").read_text().splitlines()
    assert [float(r.split(",")[0]) for r in rows] == [0.06, 0.09]
    k = header.split(",").index("peak_tau1_n_m")
    assert [float(r.split(",")[k]) for r in rows] == [float(f"{v:.12g}")
                                                        for v in got.columns["peak_tau1_n_m"]]
    with pytest.raises(InputError, match=r"--vary 'm_link2=60,90 mm': .* for a mass"):
        parse_vary(["m_link2=60,90 mm"], False, robot)


def test_booleans_are_not_numbers_on_any_route():
    """A trial: True was refused as a mass in a description and a study but read as 1 kg by
    with_parameters, as 1 rad by the compiled calls and as 1 N*m by simulate."""
    import numpy as np

    import planar_sym as ps
    from planar_sym.errors import InputError

    arm = ps.load("serial_2dof")
    calls = {"m_link1": lambda: arm.with_parameters(m_link1=True),
             "q (array)": lambda: arm.inverse_dynamics(np.ones((1, 2), bool), [[0, 0]],
                                                       [[0, 0]]),
             "q (list)": lambda: arm.mass_matrix([True, False]),
             "torque": lambda: ps.simulate(arm, [0, 1], [0, 0], (0, 0.1), torque=True),
             "q0": lambda: ps.simulate(arm, [True, False], [0, 0], (0, 0.1))}
    for what, call in calls.items():
        with pytest.raises(InputError, match=r"(booleans|must be a number)"):
            call()
            raise AssertionError(what)
    assert arm.mass_matrix([1, 0]).shape == (2, 2)  # integers are numbers


def test_vary_refuses_a_bare_number_where_the_description_is_not_si(tmp_path, capsys):
    """A trial: on the four-bar (a description in g and mm) ``--vary m_coupler=100:150:3``
    swept a 100 kg coupler, where ``--set m_coupler=100`` and a study's [parameters] read
    100 g: the same typed number, 1000 times apart by route, with no word. A bare length,
    mass or inertia is refused there, one message naming each ambiguous option; with its
    unit, or on a description in SI, it runs as before."""
    from planar_sym.commands.sweep import parse_vary
    from planar_sym.errors import InputError
    from planar_sym.study.run import load_study, robot_of

    four_bar = robot_of(load_study(str(ROOT / "examples" / "four_bar_turn.toml")))
    with pytest.raises(InputError) as err:
        parse_vary(["m_coupler=100:150:3", "px_coupler_B,cgx_coupler=20,30", "g=9.7,9.9"], False,
                   four_bar)
    text = str(err.value)
    assert text.startswith("ambiguous --vary values:")
    assert ("--vary 'm_coupler=100:150:3': four_bar's description gives mass in g, where "
            "--vary reads a bare number in SI (kg)") in text
    assert "'m_coupler=100:150:3 g' or 'm_coupler=100:150:3 kg'" in text
    assert "'px_coupler_B,cgx_coupler=20,30': four_bar's description gives length in mm" in text
    assert "'g=" not in text  # the description's acceleration is in m/s^2: bare is SI there
    assert parse_vary(["m_coupler=100:150:3 g"], False, four_bar) == {
        "m_coupler": (0.1, 0.15, 3.0)}
    assert parse_vary(["m_coupler=0.1,0.15 kg"], False, four_bar) == {"m_coupler": [0.1, 0.15]}
    si = robot_of(load_study("serial_2dof_cartesian_move"))  # in m and kg: bare is fine
    assert parse_vary(["m_link2=0.06,0.09"], False, si) == {"m_link2": [0.06, 0.09]}
    assert main(["sweep", str(ROOT / "examples" / "four_bar_turn.toml"), "--vary",
                 "m_coupler=100:150:3", "--out", str(tmp_path / "out")]) != 0
    err = capsys.readouterr().err
    assert err.count("error:") == 1 and "four_bar's description gives mass in g" in err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
