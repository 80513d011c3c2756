"""The command line: ``list``, ``run`` (CSV + PNG, all or nothing), ``equations``."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import planar_sym.outputs.results
from planar_sym.cli import main
from planar_sym.errors import PlanarSymError
from planar_sym.study.builtin import names
from planar_sym.study.run import run

SCENARIOS = names()

ROOT = Path(__file__).resolve().parent.parent
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _python(*args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.run([sys.executable, "-m", "planar_sym", *args], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=120, check=False)


def test_list(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    for name in SCENARIOS:
        assert name in out
    for robot in ("serial_2dof", "serial_3dof", "five_bar_type1", "five_bar_type2",
                  "parallel_3rrr"):
        assert robot in out


def test_run_writes_csv_and_png(tmp_path, capsys):
    out = tmp_path / "res"
    name = "serial_2dof_cartesian_move"
    assert main(["run", name, "--out", str(out), "--samples", "11"]) == 0
    assert name in capsys.readouterr().out
    assert sorted(p.name for p in out.iterdir()) == [f"{name}.csv", f"{name}.png"]
    lines = (out / f"{name}.csv").read_text().splitlines()
    assert lines[0] == ("t_s,x_mm,y_mm,q1_rad,q2_rad,qd1_rad_s,qd2_rad_s,qdd1_rad_s2,qdd2_rad_s2,"
                        "tau1_n_m,tau2_n_m,"
                        "jfx_joint1_n,jfy_joint1_n,jload_joint1_n,"
                        "jfx_weld_motor2_n,jfy_weld_motor2_n,jload_weld_motor2_n,"
                        "jm_weld_motor2_n_m,jfx_joint2_n,jfy_joint2_n,jload_joint2_n,p1_w,p2_w")
    assert len(lines) == 1 + 11
    table = np.loadtxt(lines[1:], delimiter=",")
    ref = run(name, 11)
    assert np.array_equal(table, ref.table())
    assert table[0, 1:3] == pytest.approx([100.0, 100.0], abs=1e-9)
    assert table[-1, 1:3] == pytest.approx([-100.0, 100.0], abs=1e-9)
    png = (out / f"{name}.png").read_bytes()
    assert png[:8] == PNG_SIGNATURE
    assert len(png) > 10_000


def test_run_unknown_scenario_writes_nothing(tmp_path, capsys):
    out = tmp_path / "res"
    code = main(["run", "serial_2dof_cartesian_move", "no_such_scenario", "--out", str(out)])
    err = capsys.readouterr().err
    assert code != 0
    assert "no_such_scenario" in err and "unknown study" in err
    assert not out.exists()  # every name is checked before anything runs


def test_run_bad_samples_writes_nothing(tmp_path, capsys):
    out = tmp_path / "res"
    assert main(["run", "serial_2dof_joint_move", "--out", str(out), "--samples", "1"]) != 0
    assert "--samples" in capsys.readouterr().err
    assert not out.exists() or not any(out.iterdir())


def test_run_without_names_fails(tmp_path, capsys):
    assert main(["run", "--out", str(tmp_path / "res")]) != 0
    assert "name at least one study" in capsys.readouterr().err


def _failing_save(result, path):
    Path(path).write_bytes(PNG_SIGNATURE + b"half a figure")  # half-written, then failure
    raise PlanarSymError("simulated failure while drawing the figure")


def test_run_failing_midway_leaves_no_files(tmp_path, capsys, monkeypatch):
    """The figure fails after the CSV text is written to its temporary file: neither the CSV
    nor the PNG nor any temporary file may remain."""
    monkeypatch.setattr(planar_sym.outputs.results, "save_figure", _failing_save)
    out = tmp_path / "res"
    code = main(["run", "five_bar_type1_move_x", "--out", str(out), "--samples", "11"])
    assert code != 0
    assert "simulated failure" in capsys.readouterr().err
    assert list(out.iterdir()) == []


def test_run_failing_midway_keeps_earlier_complete_files(tmp_path, capsys, monkeypatch):
    """Second scenario fails (a non-package error, e.g. the disk): the first one's files stay
    complete, the second leaves nothing, no temporary files anywhere."""
    calls = []
    real = planar_sym.outputs.results.save_figure

    def second_fails(result, path):
        calls.append(result.name)
        if len(calls) == 2:
            Path(path).write_bytes(b"partial")
            raise OSError(28, "No space left on device")
        real(result, path)

    monkeypatch.setattr(planar_sym.outputs.results, "save_figure", second_fails)
    out = tmp_path / "res"
    code = main(["--quiet", "run", "serial_2dof_joint_move", "serial_2dof_cartesian_move",
                 "--out", str(out), "--samples", "5"])
    assert code == 2
    assert "No space left on device" in capsys.readouterr().err  # a message, not a traceback
    assert sorted(p.name for p in out.iterdir()) == ["serial_2dof_joint_move.csv",
                                                     "serial_2dof_joint_move.png"]
    assert (out / "serial_2dof_joint_move.png").read_bytes()[:8] == PNG_SIGNATURE
    assert len((out / "serial_2dof_joint_move.csv").read_text().splitlines()) == 6


def test_run_overwrites_previous_results_atomically(tmp_path, monkeypatch):
    out = tmp_path / "res"
    name = "serial_2dof_joint_move"
    assert main(["--quiet", "run", name, "--out", str(out), "--samples", "5"]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    monkeypatch.setattr(planar_sym.outputs.results, "save_figure", _failing_save)
    assert main(["--quiet", "run", name, "--out", str(out), "--samples", "7"]) != 0
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before  # old results untouched


def test_equations(capsys):
    assert main(["equations", "serial_2dof"]) == 0
    text = capsys.readouterr().out
    assert "M11 =" in text and "M22 =" in text
    assert "M11 = I_1 + I_2 + I_M2 + m_1*l_c1**2" in text  # the textbook symbols
    assert main(["equations", "serial_2dof", "--latex"]) == 0
    assert "\\begin{align*}" in capsys.readouterr().out
    assert main(["equations", "five_bar_type1"]) == 0
    text = capsys.readouterr().out
    assert "Phi1 =" in text and "Phi2 =" in text and "Phi3 =" not in text
    assert main(["equations", "parallel_3rrr"]) == 0
    assert "Phi4 =" in capsys.readouterr().out  # two cut joints: four loop equations


def test_equations_unknown_robot(capsys):
    assert main(["equations", "no_such_robot"]) != 0
    assert "no_such_robot" in capsys.readouterr().err


def test_module_entry_point_subprocess(tmp_path):
    res = _python("list")
    assert res.returncode == 0, res.stderr
    assert all(name in res.stdout for name in SCENARIOS)
    res = _python("run", "no_such_scenario", "--out", str(tmp_path / "res"))
    assert res.returncode != 0
    assert "no_such_scenario" in res.stderr and "Traceback" not in res.stderr
    assert res.stdout == ""
    assert not (tmp_path / "res").exists()
