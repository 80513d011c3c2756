"""A geared revolute joint's link-side couple is a column of its own (a user trial, trial I).

With an actuator model the torque ``tau<k>`` is the motor's output at the joint, rotor and
friction included; the gearbox and the bearing carry the couple the link feels, ``M_j = tau_j -
D_j(qd_j) - N J_m (alpha_stator + N qdd_j)``. planar-sym computed it (``joint_loads``) but wrote
it nowhere, and the docs said a revolute joint's couple is its torque: on the trial's arm the two
differed by 20 % at the shoulder and 40 % at the elbow, and link 2's moment balance from the CSV
missed by 1.685 N*m. Now ``jm_<joint>_n_m`` is written for every revolute joint with an actuator
model, checked here against that formula by hand from the CSV's own columns and the
description's drive figures, and against link 2's free-body moment balance.
"""

from __future__ import annotations

import numpy as np
from conftest import ROOT

import planar_sym as ps

GEARED = ROOT / "examples" / "s3_geared.toml"


def test_the_couple_is_the_torque_less_friction_and_rotor():
    res = ps.run_study(GEARED)
    c = res.columns
    robot = ps.load(ROOT / "examples" / "serial_2dof_geared.toml")
    p = robot.parameters
    n1, n2, jm1, jm2 = p["gear_joint1"], p["gear_joint2"], p["jm_joint1"], p["jm_joint2"]
    qd1, qdd1, qdd2 = c["qd1_rad_s"], c["qdd1_rad_s2"], c["qdd2_rad_s2"]
    friction1 = p["fv_joint1"] * qd1 + p["fc_joint1"] * np.tanh(qd1 / p["vs_joint1"])
    # joint 1's stator stands on the ground; joint 2's rides on link 1 (alpha = qdd1)
    m1 = c["tau1_n_m"] - friction1 - n1 * jm1 * (0.0 + n1 * qdd1)
    m2 = c["tau2_n_m"] - n2 * jm2 * (qdd1 + n2 * qdd2)
    scale = np.max(np.abs(c["tau1_n_m"]))
    np.testing.assert_allclose(c["jm_joint1_n_m"], m1, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(c["jm_joint2_n_m"], m2, rtol=0, atol=1e-12 * scale)
    assert np.max(np.abs(c["jm_joint1_n_m"] - c["tau1_n_m"])) > 1e-3  # the column says more


def test_link2s_moment_balance_closes_with_the_couple():
    """Link 2 (mass m, izz about its cg, cg at c along it) hangs from joint 2 only: about its
    cg, M_2 + (r_joint - r_cg) x F_2 = izz alpha_2, alpha_2 = qdd1 + qdd2."""
    c = ps.run_study(GEARED).columns
    robot = ps.load(ROOT / "examples" / "serial_2dof_geared.toml")
    p = robot.parameters
    q1, q2 = c["q1_rad"], c["q2_rad"]
    a2 = q1 + q2
    d = p["cgx_link2"]  # from joint 2 to the cg, along link 2
    rx, ry = -d * np.cos(a2), -d * np.sin(a2)  # joint 2 from the cg
    fx, fy = c["jfx_joint2_n"], c["jfy_joint2_n"]
    lhs = c["jm_joint2_n_m"] + rx * fy - ry * fx
    rhs = p["izz_link2"] * (c["qdd1_rad_s2"] + c["qdd2_rad_s2"])
    np.testing.assert_allclose(lhs, rhs, rtol=0, atol=1e-12)
    # with the torque in place of the couple it does not close (the trial's 1.685 N*m, here less)
    assert np.max(np.abs(c["tau2_n_m"] + rx * fy - ry * fx - rhs)) > 1e-4


def test_no_couple_column_without_an_actuator_model():
    """The seed's arm: a revolute joint's couple is its torque, so it gets no column."""
    c = ps.run_study("serial_2dof_cartesian_move").columns
    assert [k for k in c if k.startswith("jm_")] == ["jm_weld_motor2_n_m"]


def test_the_split_plot_says_the_sum_its_parts_make():
    """A trial: the split's title said tau = M qdd + C qd + g above friction and rotor curves.
    Its title now sums the parts it draws, which add up to the torque."""
    from planar_sym.outputs.plots import split_figure

    for study, want in ((GEARED, "tau = M qdd + C qd + g + D(qd) + rotors"),
                        ("serial_2dof_cartesian_move", "tau = M qdd + C qd + g)")):
        res = ps.run_study(study)
        fig = split_figure(res)
        texts = " ".join([*(t.get_text() for t in fig.texts),
                          *(ax.get_title() for ax in fig.axes)])
        assert want in texts, texts
        parts = sum(res.split.values())
        np.testing.assert_allclose(parts[:, 0], res.columns["tau1_n_m"], rtol=0,
                                   atol=1e-12 * np.max(np.abs(res.columns["tau1_n_m"])))


def test_the_energy_note_names_the_rotors_it_sums(capsys):
    """A trial: T in the report held the rotors' gear_joint1**2*jm_joint1 terms while its note
    summed the bodies only. A robot with rotors says so; the seed's arm does not."""
    from planar_sym.cli import main

    geared = ROOT / "examples" / "serial_2dof_geared.toml"
    assert main(["equations", str(geared)]) == 0
    text = capsys.readouterr().out
    assert "gear_joint1**2*jm_joint1" in text
    assert "plus the rotors' 1/2 J_m (w_parent + N qd_k)^2" in text
    seed = (ROOT / "generated" / "serial_2dof" / "equations.txt").read_text()
    assert "T = 1/2 sum_b" in seed and "rotors'" not in seed


def test_a_description_warning_is_said_once_on_export(tmp_path, capsys):
    """A trial: export said a plausibility warning twice, the second time under the derived
    folder's copy of the file (a cache path)."""
    from planar_sym.cli import main

    text = (ROOT / "examples" / "serial_2dof_geared.toml").read_text()
    assert "mass = 0.292" in text
    path = tmp_path / "heavy.toml"
    path.write_text(text.replace("mass = 0.292", "mass = 2000", 1))
    assert main(["export", str(path), "--out", str(tmp_path / "heavy.xml")]) == 0
    err = capsys.readouterr().err
    assert err.count("more than osmium") == 1 and f"warning: {path}: " in err
