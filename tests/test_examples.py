"""Every example script runs (small sample counts, in a subprocess, from an empty folder), exits
0, writes no file unless asked, and prints numbers the runtime reproduces."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.motion.closure import from_actuated

EXAMPLES = ROOT / "examples"
LECTURES = sorted(p.name for p in EXAMPLES.glob("lecture_*.py"))
SAMPLES = 21
PEAK = re.compile(r"^(\w+): peak \|(tau\d+)\| = (\S+) N\*m$", re.MULTILINE)


def _run(script: str, *args: str, cwd, env=None) -> subprocess.CompletedProcess:
    # no plots unless a test asks for them: an exported PLANAR_SYM_PLOTS must not leak in
    base = {k: v for k, v in os.environ.items() if k != "PLANAR_SYM_PLOTS"}
    env = {**base, "PYTHONPATH": str(ROOT), **(env or {})}
    proc = subprocess.run([sys.executable, str(EXAMPLES / script), *args], cwd=cwd, env=env,
                          capture_output=True, text=True, check=False, timeout=300)
    assert proc.returncode == 0, f"{script} failed:\n{proc.stdout}\n{proc.stderr}"
    return proc


def test_there_is_a_lecture_per_robot():
    robots = ("serial_2dof", "serial_3dof", "five_bar_type1", "five_bar_type2", "parallel_3rrr")
    assert LECTURES == sorted(f"lecture_{r}.py" for r in robots)


@pytest.mark.parametrize("script", LECTURES)
def test_lecture_runs_and_its_peak_torques_match_the_runtime(script, tmp_path):
    out = _run(script, "--samples", str(SAMPLES), cwd=tmp_path).stdout
    peaks = PEAK.findall(out)
    assert peaks, f"{script} printed no peak torque:\n{out}"
    for scenario, key, value in peaks:
        ref = ps.run_study(scenario, SAMPLES).peak_torques()[key]
        assert float(value) == pytest.approx(ref, rel=1e-11), (scenario, key)
    assert "Closed-form equations" in out and " = " in out
    assert list(tmp_path.iterdir()) == [], "wrote files without being asked"


def test_lecture_saves_plots_when_asked(tmp_path):
    plots = tmp_path / "plots"
    _run("lecture_five_bar_type1.py", "--samples", "11", "--plot", str(plots), cwd=tmp_path)
    assert sorted(p.name for p in plots.iterdir()) == [
        "five_bar_type1_move_x.png", "five_bar_type1_move_y.png"]
    env_plots = tmp_path / "env_plots"
    _run("lecture_serial_3dof.py", "--samples", "11", cwd=tmp_path,
         env={"PLANAR_SYM_PLOTS": str(env_plots)})
    assert [p.name for p in env_plots.iterdir()] == ["serial_3dof_cartesian_move.png"]


def test_own_robot_walkthrough(tmp_path, monkeypatch):
    """Derives the four-bar into --out, prints the crank torque: the runtime agrees."""
    samples = 37
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))  # here and in the script
    out = _run("own_robot.py", "--samples", str(samples), "--out", str(tmp_path / "gen"),
               cwd=tmp_path).stdout
    assert "$ planar-sym derive" in out and "Phi1 =" in out
    robot = ps.load(tmp_path / "gen" / "four_bar")
    t = np.linspace(0.0, 1.0, samples)
    q_act = robot.q_drawn[0] + 2 * np.pi * t[:, None]  # one crank turn at 1 rev/s
    motion = from_actuated(robot, t, q_act, np.full_like(q_act, 2 * np.pi), 0 * q_act)
    tau, _ = robot.closed_chain_inverse_dynamics(motion.q, motion.qd, motion.qdd)
    printed = float(re.search(r"^peak \|tau1\| = (\S+) N\*m", out, re.MULTILINE).group(1))
    assert printed == pytest.approx(np.max(np.abs(tau)), rel=1e-11)
    assert printed > 0.01  # N*m: lifting the links, not a trivial zero


def test_own_robot_with_a_serial_robot(tmp_path):
    out = _run("own_robot.py", str(EXAMPLES / "heavy_motor_2dof.toml"), "--samples", "11",
               cwd=tmp_path, env={"PLANAR_SYM_CACHE": str(tmp_path / "cache")}).stdout
    assert "peak |tau2|" in out and "M11 =" in out
    assert [p.name for p in tmp_path.iterdir()] == ["cache"]  # its temp folder is gone


def test_opti_example_on_the_saved_casadi_functions(tmp_path):
    """casadi.Opti on mass_matrix, bias and constraint as Function.save wrote them: the optimal
    torques replayed in planar-sym's own simulation reach the goal within RK4's error (which
    shrinks about 16x when the intervals double: 4th order), and the Opti pose on Phi = 0 is
    the inverse kinematics' pose."""
    misses = []
    for n in ("40", "80"):
        out = _run("opti_min_effort.py", "--intervals", n, cwd=tmp_path).stdout
        misses.append(float(re.search(r"misses the goal by (\S+) rad", out).group(1)))
        ik_gap = float(re.search(r"IK by (\S+) rad", out).group(1))
        assert ik_gap < 1e-8
        assert float(re.search(r"peak \|tau\| (\S+) N\*m", out).group(1)) > 0.05
    assert misses[1] < 2e-3 and misses[0] / misses[1] > 4, misses  # seen: 6.4e-3, 8.7e-4
    assert list(tmp_path.iterdir()) == []


def test_lecture_equations_define_each_symbol_once():
    """A lecturer's trial: the lecture helper printed alpha, beta, delta, g1 and g2 twice, the
    second time in base parameters from the identification sections, with no heading between."""
    import sys

    sys.path.insert(0, str(ROOT / "examples"))
    from _lectures import equations

    labels = ("alpha", "beta", "delta", "g1", "g2")
    heads = [ln.split(" = ", 1)[0] for ln in equations("serial_2dof", labels) if " = " in ln]
    assert sorted(heads) == sorted(labels), heads
