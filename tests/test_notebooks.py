"""The lecture notebooks (examples/notebooks/*.py, jupytext percent format) run in a real
Jupyter kernel of this interpreter, and what they print is recomputed here; Robot, Result and
Simulation show themselves as HTML in a notebook (and in the ``outputs.notebook`` functions).

The kernel is this test process's own Python (``sys.executable``), through a kernel spec written
into a temporary ``JUPYTER_PATH``: no installed kernel, network or standard input is needed.
"""

from __future__ import annotations

import base64
import io
import json
import re
import sys

import jupytext  # the test extra: jupytext, nbclient, nbformat, ipykernel
import nbclient
import nbformat
import numpy as np
import pytest
from conftest import ROOT

import planar_sym as ps
from planar_sym.outputs import notebook

NOTEBOOKS = ROOT / "examples" / "notebooks"
LECTURES = ("serial_2dof", "serial_3dof", "five_bar_type1", "five_bar_type2", "parallel_3rrr")
KERNEL = "planar-sym-test"
PNG = re.compile(r'<img src="data:image/png;base64,([A-Za-z0-9+/=]+)"')
GIF = re.compile(r'<img src="data:image/gif;base64,([A-Za-z0-9+/=]+)"')
PEAK = re.compile(r"^(\w+): peak \|(tau\d+)\| = (\S+) N\*m$", re.MULTILINE)
BALANCE = re.compile(r"^(\w+): motor work W = (\S+) J, energy change dE = (\S+) J$", re.MULTILINE)


@pytest.fixture(scope="module")
def kernel_env(tmp_path_factory):
    """A kernel spec running ``sys.executable`` (the venv's Python), found first on a private
    JUPYTER_PATH; runtime and IPython folders private too."""
    root = tmp_path_factory.mktemp("jupyter")
    spec = root / "kernels" / KERNEL
    spec.mkdir(parents=True)
    (spec / "kernel.json").write_text(json.dumps({
        "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
        "display_name": "planar-sym tests", "language": "python",
        "env": {"PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}}))
    mp = pytest.MonkeyPatch()
    mp.setenv("JUPYTER_PATH", str(root))
    mp.setenv("JUPYTER_RUNTIME_DIR", str(root / "runtime"))
    mp.setenv("IPYTHONDIR", str(root / "ipython"))
    mp.setenv("JUPYTER_PLATFORM_DIRS", "1")
    yield root
    mp.undo()


def execute(nb, cwd):
    """Run every cell of ``nb`` in a fresh kernel (cwd ``cwd``); raises on a cell's error."""
    client = nbclient.NotebookClient(nb, kernel_name=KERNEL, timeout=120,
                                     resources={"metadata": {"path": str(cwd)}})
    client.execute()
    return nb


def printed(nb) -> str:
    return "".join(out.get("text", "") for cell in nb.cells if cell.cell_type == "code"
                   for out in cell.get("outputs", ()) if out.output_type == "stream")


def html_outputs(nb) -> list[str]:
    return [out["data"]["text/html"] for cell in nb.cells if cell.cell_type == "code"
            for out in cell.get("outputs", ()) if "text/html" in out.get("data", {})]


def image(fragment: str, pattern=PNG):
    """The first embedded picture of an HTML fragment, opened with Pillow."""
    from PIL import Image

    m = pattern.search(fragment)
    assert m, "no embedded picture"
    return Image.open(io.BytesIO(base64.b64decode(m.group(1))))


@pytest.fixture(scope="module")
def lectures(kernel_env):
    """Every lecture notebook, executed once for the tests below."""
    out = {}
    for name in LECTURES:
        nb = jupytext.read(NOTEBOOKS / f"lecture_{name}.py")
        out[name] = execute(nb, NOTEBOOKS)
    return out


def test_there_is_a_notebook_per_lecture():
    scripts = sorted(p.name for p in (ROOT / "examples").glob("lecture_*.py"))
    assert sorted(p.name for p in NOTEBOOKS.glob("lecture_*.py")) == scripts
    assert len(scripts) == len(LECTURES)


@pytest.mark.parametrize("name", LECTURES)
def test_lecture_notebook_numbers_match_the_runtime(lectures, name):
    nb = lectures[name]
    text = printed(nb)
    robot = ps.load(name)
    # the peaks it prints are those of the same studies run here
    peaks = PEAK.findall(text)
    assert peaks, text
    for study, key, value in peaks:
        assert float(value) == pytest.approx(ps.run_study(study).peak_torques()[key], rel=1e-11)
    # the power balance: its printed energy change is the compiled energy at the ends, here;
    # its printed work (the integral of tau . qd) matches that to the integration error
    balances = BALANCE.findall(text)
    assert balances, text
    for study, work, change in balances:
        result = ps.run_study(study)
        q = np.column_stack([result.columns[f"q{k + 1}_rad"] for k in range(robot.n)])
        qd = np.column_stack([result.columns[f"qd{k + 1}_rad_s"] for k in range(robot.n)])
        kinetic, potential = robot.energy(q, qd)
        energy = kinetic + potential
        assert float(change) == pytest.approx(energy[-1] - energy[0], rel=1e-8, abs=1e-12)
        assert float(work) == pytest.approx(energy[-1] - energy[0], rel=1e-6, abs=1e-9)
        assert abs(energy[-1] - energy[0]) > 1e-3, "a balance of nothing checks nothing"
    # the robot and each study show as HTML with the robot's own numbers and a picture
    fragments = html_outputs(nb)
    robot_html = next(f for f in fragments if f"Robot {name}" in f)
    first = robot.parameter_list[1]
    assert f"<td>{first.name}</td><td>{first.value:.6g}</td><td>{first.unit}</td>" in robot_html
    assert image(robot_html).size == (576, 432)  # 8 x 6 in at 72 dpi
    study_html = [f for f in fragments if "<h3>Study " in f]
    assert study_html and all(image(f).format == "PNG" for f in study_html)
    # the equations are shown as LaTeX/Markdown
    latex = [out["data"] for cell in nb.cells if cell.cell_type == "code"
             for out in cell.get("outputs", ()) if "text/latex" in out.get("data", {})]
    assert latex and r"\begin{aligned}" in latex[0]["text/latex"]


def test_serial_2dof_notebook_checks(lectures):
    """The 2-DOF notebook's own checks print what they should: the printed closed forms agree
    with the compiled torques, the free swing keeps its energy, a heavier motor costs more."""
    text = printed(lectures["serial_2dof"])
    diffs = re.findall(r"closed form vs compiled, max \|tau\d difference\| = (\S+) N\*m", text)
    assert len(diffs) == 2 and max(float(d) for d in diffs) < 1e-12
    swing = ps.run_study("serial_2dof_free_swing")
    e = swing.columns["energy_j"]
    m = re.search(r"max \|E - E\(0\)\| = (\S+) J of E\(0\) = (\S+) J", text)
    assert float(m.group(2)) == pytest.approx(e[0], abs=1e-6)
    assert float(m.group(1)) < 1e-9
    q_end = re.search(r"q\(1 s\) = \((\S+), (\S+)\) deg", text)
    assert float(q_end.group(1)) == pytest.approx(np.degrees(swing.columns["q1_rad"][-1]),
                                                   abs=1e-6)
    tau = dict(re.findall(r"S3 with a (\S+) kg motor: peak \|tau1\| = (\S+) N\*m", text))
    assert float(tau["0.6"]) > float(tau["0.292"]) * 1.1
    assert float(tau["0.292"]) == pytest.approx(
        ps.run_study("serial_2dof_cartesian_move").peak_torques()["tau1"], rel=1e-5)
    # the simulation is shown with its animation: a GIF of several frames
    sim_html = next(f for f in html_outputs(lectures["serial_2dof"]) if "<h3>Simulation" in f)
    assert "dopri5" in sim_html and image(sim_html, GIF).n_frames >= 10


def test_evaluating_objects_in_a_notebook_shows_html(kernel_env, tmp_path):
    """A notebook whose cells just evaluate a robot, a result and a simulation: each output
    carries text/html (the hook in planar_sym/__init__.py) besides text/plain."""
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(src) for src in (
        "import planar_sym as ps\nrobot = ps.load('serial_2dof')\nrobot",
        "ps.run_study('serial_2dof_joint_move', 21)",
        "ps.simulate(robot, [0.3, 0.0], [0.0, 0.0], (0.0, 0.5), t_eval=[0.0, 0.25, 0.5])")]
    execute(nb, tmp_path)
    robot_out, result_out, sim_out = (c.outputs[-1]["data"] for c in nb.cells)
    assert {"text/plain", "text/html"} <= set(robot_out)
    assert "<td>m_motor2</td><td>0.292</td><td>kg</td>" in robot_out["text/html"]
    assert image(robot_out["text/html"]).format == "PNG"
    peak = ps.run_study("serial_2dof_joint_move", 21).peak_torques()["tau1"]
    assert f"{peak:.6g} N*m" in result_out["text/html"]
    sim = ps.simulate(ps.load("serial_2dof"), [0.3, 0.0], [0.0, 0.0], (0.0, 0.5),
                      t_eval=[0.0, 0.25, 0.5])
    assert f"{sim.energy_j[-1]:.6g} J" in sim_out["text/html"]
    assert image(sim_out["text/html"], GIF).n_frames == 3  # the run names its robot


HOOK_PROBE = """
import sys
from IPython.core.interactiveshell import InteractiveShell
{shell}
import planar_sym as ps
print("matplotlib" in sys.modules, "planar_sym.outputs.notebook" in sys.modules)
shell = sys.modules["IPython"].get_ipython()
fmt = shell.display_formatter.formatters["text/html"] if shell is not None else None
shown = fmt(ps.load("serial_2dof")) if fmt is not None else None
print(shown is not None and "<td>m_motor2</td><td>0.292</td><td>kg</td>" in shown)
"""


@pytest.mark.parametrize("shell", [True, False])
def test_import_registers_the_display_only_inside_ipython(shell):
    """Inside an IPython shell, ``import planar_sym`` hooks the HTML display without loading
    matplotlib (drawing waits for the first display); with IPython merely imported (no shell)
    nothing is registered or imported for it."""
    import os
    import subprocess

    code = HOOK_PROBE.format(shell="InteractiveShell.instance()" if shell else "")
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, check=False, timeout=120,
                          env={**os.environ, "MPLBACKEND": "Agg"})
    assert proc.returncode == 0, proc.stderr
    modules, shown = proc.stdout.splitlines()
    assert modules == f"False {shell}"  # matplotlib never at import; the hook only in a shell
    assert shown == str(shell)


# -- the HTML functions themselves, in this process ----------------------------------------

def test_robot_html_lists_units_and_parameters():
    robot = ps.load("five_bar_type1").with_parameters(m_L_Link1=0.123)
    fragment = notebook.robot_html(robot)
    assert "<td>m_L_Link1</td><td>0.123</td><td>kg</td>" in fragment
    assert "q1 = A (rad (revolute))" in fragment
    assert "cut at C; 2 loop equations" in fragment
    assert "q1 = A, q3 = E" in fragment  # the actuated joints
    im = image(fragment)
    pixels = np.asarray(im.convert("L"))
    assert (pixels < 128).mean() > 0.005, "the drawing is blank"


def test_result_html_peaks_and_plot():
    result = ps.run_study("parallel_3rrr_move_x", 31)
    fragment = notebook.result_html(result)
    for key, value in result.peak_torques().items():
        assert f"peak |{key}|</td><td>{value:.6g} N*m" in fragment
    assert "2 s" in fragment  # the duration
    assert image(fragment).size[0] == 504  # 7 in at 72 dpi


def test_simulation_html_with_and_without_robot():
    import dataclasses

    arm = ps.load("serial_2dof")
    sim = ps.simulate(arm, [-1.0, 0.5], [0.0, 0.0], (0.0, 0.4), t_eval=np.linspace(0, 0.4, 41))
    anonymous = dataclasses.replace(sim, robot="")  # a run that does not name its robot
    bare = notebook.simulation_html(anonymous)
    assert f"{sim.energy_drift:.3g}" in bare and "<td>rtol</td><td>1e-11</td>" in bare
    assert not GIF.search(bare) and "not animated" not in bare  # no robot, no animation
    full = notebook.simulation_html(sim, arm)
    assert image(full, GIF).n_frames == 30  # FRAMES of the 41 samples
    # a run that names its robot is animated, as with the robot given
    assert image(notebook.simulation_html(sim), GIF).n_frames == 30
    # ... unless the named robot's parameters are not the ones that ran: then it says why
    heavy = arm.with_parameters(m_motor2=0.6)
    run = ps.simulate(heavy, [-1.0, 0.5], [0.0, 0.0], (0.0, 0.4), t_eval=[0.0, 0.2, 0.4])
    assert run.robot == "serial_2dof"
    fragment = notebook.simulation_html(run)
    assert not GIF.search(fragment) and "parameters were changed" in fragment
    assert image(notebook.simulation_html(run, heavy), GIF).n_frames == 3
    closed = ps.load("five_bar_type1")
    run = ps.simulate(closed, closed.q_drawn, np.zeros(closed.n), (0.0, 0.2),
                      t_eval=np.linspace(0, 0.2, 5))
    fragment = notebook.simulation_html(run, closed, picture=False)
    assert f"{run.constraint_drift_m:.3g} m" in fragment and "<img" not in fragment


def test_register_hooks_the_html_formatter():
    from IPython.core.formatters import HTMLFormatter

    class Shell:
        display_formatter = type("F", (), {"formatters": {"text/html": HTMLFormatter()}})()

    shell = Shell()
    notebook.register(shell)
    fmt = shell.display_formatter.formatters["text/html"]
    robot = ps.load("serial_2dof")
    assert "Robot serial_2dof" in fmt(robot)
    assert fmt(object()) is None  # nothing else is touched


ZMAX = re.compile(r"^max \|z\| = (\S+)$", re.MULTILINE)
VALIDATION = re.compile(r"^(\w+): RMS error identified (\S+) N\*m, drawing (\S+) N\*m \(torque "
                        r"noise (\S+) N\*m", re.MULTILINE)


def test_identification_notebook(kernel_env):
    """The identification notebook (examples/notebooks/identify_five_bar.py) runs, its
    estimates lie within 3 standard deviations of its hidden truth, and the identified model
    predicts a second experiment within the torque noise and far better than the drawing."""
    nb = execute(jupytext.read(NOTEBOOKS / "identify_five_bar.py"), NOTEBOOKS)
    text = printed(nb)
    (zmax,) = ZMAX.findall(text)
    assert float(zmax) < 3.0, text
    rows = VALIDATION.findall(text)
    assert [r[0] for r in rows] == ["A", "E"], text
    for _, identified, drawing, noise in rows:
        assert float(identified) < float(noise)
        assert float(identified) < 0.2 * float(drawing)


SWING = re.compile(r"^swing-up: T = (\S+) s, peak \|F\| = (\S+) N, effort = (\S+) N\^2\*s",
                   re.MULTILINE)
POLES = re.compile(r"^closed-loop poles: (.+)$", re.MULTILINE)
END = re.compile(r"^end: \|q - q_up\| = (\S+), peak \|F\| = (\S+) N$", re.MULTILINE)
OPEN = re.compile(r"^open loop: the pole ends (\S+) deg from upright$", re.MULTILINE)


def test_cart_pole_notebook(kernel_env):
    """The cart-pole lecture (examples/notebooks/cart_pole_swing_up.py) runs; its LQR poles
    are python-control's for the same A, B and weights, its plan's effort is optimal_move's
    recomputed here, and the tracked swing-up ends upright where the plan alone falls."""
    control = pytest.importorskip("control")
    nb = execute(jupytext.read(NOTEBOOKS / "cart_pole_swing_up.py"), NOTEBOOKS)
    text = printed(nb)
    robot = ps.load("cart_pole")
    lin = ps.linearize(robot, [0.0, np.pi / 2])
    _, _, poles = control.lqr(lin.a, lin.b, np.diag([100.0, 100.0, 1.0, 1.0]), [[1.0]])
    (shown,) = POLES.findall(text)
    got = sorted((complex(p) for p in shown.split(", ")), key=abs)
    assert np.abs(np.array(got) - sorted(poles, key=abs)).max() < 1e-4 * np.abs(poles).max()
    ((duration, peak, effort),) = SWING.findall(text)
    plan = ps.optimal_move(robot, [0.0, -np.pi / 2], [0.0, np.pi / 2], objective="effort",
                           duration_s=2.0, torque_limit=[0.2], intervals=100)
    assert float(effort) == pytest.approx(plan.objective, rel=1e-6)
    assert float(duration) == 2.0 and float(peak) == pytest.approx(0.2, rel=1e-6)
    ((end, peak_run),) = END.findall(text)
    assert float(end) < 1e-5 and 0.2 < float(peak_run) < 0.25
    (fallen,) = OPEN.findall(text)
    assert abs(float(fallen)) > 90.0


def test_a_driven_rubbing_run_shows_its_energy_change_and_its_balance():
    """A trial: a driven run with friction showed "energy drift 0.91" (the work the motors put
    in, less friction) beside nothing that said the balance closed. The row now says energy
    change there, and the balance E - E(0) - (W - F) is its own row, as small as the
    integrator's tolerance; a free frictionless run keeps "energy drift"."""
    geared = ps.load(ROOT / "examples" / "serial_2dof_geared.toml")
    assert geared.has_friction
    sim = ps.simulate(geared, [-1.0, 0.5], [0.0, 0.0], (0.0, 0.4), torque=[0.4, 0.1],
                      t_eval=np.linspace(0, 0.4, 21))
    html = notebook.simulation_html(sim, picture=False)
    assert sim.energy_drift > 0.05 and sim.balance_residual < 1e-8
    assert (f"<td>energy change max|E - E(0)| / scale (work and friction change E)</td>"
            f"<td>{sim.energy_drift:.3g}</td>") in html
    assert (f"<td>energy balance max|E - E(0) - (W - F)| / scale</td>"
            f"<td>{sim.balance_residual:.3g}</td>") in html
    assert "energy drift" not in html
    free = ps.simulate(ps.load("serial_2dof"), [-1.0, 0.5], [0.0, 0.0], (0.0, 0.4))
    assert f"<td>energy drift max|E - E(0)| / scale</td><td>{free.energy_drift:.3g}</td>" in (
        notebook.simulation_html(free, picture=False))
