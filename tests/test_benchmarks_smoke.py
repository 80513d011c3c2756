"""The benchmark harness runs end to end (``python -m benchmarks --quick``, about 15 s), writes
every section with numeric ratios, and its baselines compute the same torques as planar_sym
(the correctness gates the harness applies before timing, asserted here directly)."""

from __future__ import annotations

import re
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT, rel_err

if str(ROOT) not in sys.path:  # the benchmarks package lives at the repository root
    sys.path.insert(0, str(ROOT))

SECTIONS = ("## Machine", "## Headlines", "## Correctness gates", "## 1. Inverse dynamics",
            "## 2. Forward dynamics", "## 3. Derive and compile times",
            "## 4. Import and first-torque latency",
            "## 5. Closed-loop control", "## 6. Design tools")
RATIO = re.compile(r"\d+(?:\.\d+)?(?:e[+-]?\d+)?x(?:\*\*)? \[\d")


def test_quick_run_writes_every_section_with_ratios(tmp_path):
    for baseline in ("mujoco", "pinocchio", "sympy"):  # the bench extra
        pytest.importorskip(baseline)
    out = tmp_path / "tmp" / "BENCHMARKS.md"
    proc = subprocess.run([sys.executable, "-m", "benchmarks", "--quick", "--out", str(out)],
                          check=False, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    text = out.read_text()
    for heading in SECTIONS:
        assert heading in text, f"{heading!r} missing from the report"
    for label in ("cpu", "simd", "avx2", "avx512f", "numpy", "casadi", "pinocchio", "mujoco",
                  "date"):
        assert label in text, f"machine description lacks {label!r}"
    # every section carries ratios: split the report at its numbered sections
    parts = re.split(r"^## \d\. ", text, flags=re.MULTILINE)[1:]
    assert len(parts) == 6
    for part in parts:
        assert RATIO.search(part), f"no 'N.NNx [min-...' ratio in section {part[:40]!r}"
    assert "FAIL" not in text
    headlines = text.split("## Headlines", 1)[1].split("\n## ", 1)[0]
    assert len(RATIO.findall(headlines)) >= 5


@pytest.mark.parametrize("name", ["serial_2dof", "serial_3dof"])
def test_baselines_agree_with_planar_sym(name):
    """MuJoCo mj_inverse, the C floor and pinocchio.rnea give planar_sym's torques to 1e-9."""
    pytest.importorskip("mujoco")
    pytest.importorskip("pinocchio")
    from benchmarks.baselines import cfloor, mujoco_model, pinocchio_model
    from benchmarks.inverse import GATE, serial_states
    from planar_sym import load
    from planar_sym.model import description

    robot, desc = load(name), description.load(name)
    q, qd, qdd = serial_states(robot.n, 200, seed=3)
    ref = robot.inverse_dynamics(q, qd, qdd)
    mm, md = mujoco_model.build(desc)
    assert rel_err(mujoco_model.inverse_loop(mm, md, q, qd, qdd), ref) < GATE
    floor = cfloor.compile_floor(name, robot.parameters)
    assert rel_err(floor(q, qd, qdd), ref) < GATE
    pm, pd = pinocchio_model.build(desc)
    assert rel_err(pinocchio_model.rnea_loop(pm, pd, q, qd, qdd), ref) < GATE
    # negative control: the gate sees a 1e-6 relative change of one mass
    heavier = robot.with_parameters(m_link2=robot.parameters["m_link2"] * (1 + 1e-6))
    assert rel_err(heavier.inverse_dynamics(q, qd, qdd), ref) > 100 * GATE


def test_mujoco_rk4_follows_planar_sym_simulate():
    """MuJoCo's RK4 on the generated MJCF integrates the same S1 motion (to its step error)."""
    pytest.importorskip("mujoco")
    from benchmarks.baselines import mujoco_model
    from planar_sym import load, simulate
    from planar_sym.model import description

    robot = load("serial_2dof")
    q0 = np.radians([-60.0, 0.0])
    mm, md = mujoco_model.build(description.load("serial_2dof"))
    t, q, _, dt = mujoco_model.simulate_rk4(mm, md, q0, np.zeros(2), 1.0, 1e-4)
    assert t[-1] == pytest.approx(1.0) and dt == pytest.approx(1e-4)
    sim = simulate(robot, q0, np.zeros(2), (0.0, 1.0), t_eval=t)
    assert np.max(np.abs(q - sim.q)) < 1e-9


@pytest.mark.parametrize("label, study", [("S3", "serial_2dof_cartesian_move"),
                                          ("S5", "five_bar_type1_move_x")])
def test_control_baselines_agree_with_the_compiled_loop(label, study):
    """The control section's Python controller (SciPy and MuJoCo baselines) commands the
    compiled controller's torques, and its MuJoCo model (the five-bar's cut joint a connect
    constraint) has planar_sym's mass matrix and bias forces, its loop closed at the start."""
    pytest.importorskip("mujoco")
    from benchmarks import control

    p = control.load_problem(label, study, 0.2)
    plant = control.MujocoPlant(p)
    for law in control.LAWS:
        ctl = control.make_controller(p, law)
        run = control.ours(p, ctl)
        law_py = control.PyController(p.robot, ctl, p.ref)
        py = np.array([law_py(t, q, qd) for t, q, qd in zip(run.t_s, run.q, run.qd)])
        assert rel_err(py, run.tau_cmd) < 1e-9
    assert all(c.ok for c in plant.check(p, run.q, run.qd))
    q, _, _ = control.mujoco_run(plant, p, ctl, law_py, 1e-3, True)
    assert q.shape == run.q.shape and np.max(np.abs(q - run.q)) < 1e-5
