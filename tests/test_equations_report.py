"""The equation report (generated/<robot>/equations.{txt,tex,md}, ``planar-sym equations``,
``planar_sym.outputs.equations``): the printed 2-DOF equations are the textbook closed form term by term,
and every printed equation evaluates to what the compiled library computes.

The text form is read back with ``sympify`` (display names as symbols, ``c12`` as
``cos(q1 + q2)``), so what is checked is what a reader sees.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp
from conftest import ALL_ROBOTS, CLOSED, GENERATED, ROOT, TEST_ROBOTS, rel_err

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.model import description
from planar_sym.outputs.equations import equations

GREEK = ("alpha", "beta", "delta", "epsilon", "zeta", "eta", "theta", "kappa", "mu", "nu", "xi",
         "rho", "sigma", "chi", "psi", "omega")


class Printed:
    """A robot's text report, parsed back into SymPy, with the seed values of its symbols."""

    def __init__(self, robot: str):
        desc = description.load(robot)
        n = len(desc.coordinates)
        self.q = sp.symbols(f"q1:{n + 1}", real=True)
        self.qd = sp.symbols(f"qd1:{n + 1}", real=True)
        self.qdd = sp.symbols(f"qdd1:{n + 1}", real=True)
        self.ns = {str(s): s for s in (*self.q, *self.qd, *self.qdd)}
        self.values = {}
        for p in desc.parameters():
            sym = sp.Symbol(desc.display.get(p.name, p.name), real=True)
            self.ns[sym.name] = sym
            self.values[sym] = p.value
        self.ns.update({g: sp.Symbol(g, real=True) for g in GREEK})
        self.ns.update({f"g{i + 1}": sp.Symbol(f"g{i + 1}", real=True) for i in range(n)})
        self.sections = equations(robot).sections()
        lumped = self.sections.get("Lumped parameters", {})
        self.lumped = {self.ns[k]: self.parse(v) for k, v in lumped.items()}

    def parse(self, rhs: str) -> sp.Expr:
        local = dict(self.ns)
        for head, idx in re.findall(r"\b([cs])(\d+)\b", rhs):
            angle = sum(self.q[int(i) - 1] for i in idx)
            local[head + idx] = (sp.cos if head == "c" else sp.sin)(angle)
        return sp.sympify(rhs, locals=local)

    def get(self, section: str, label: str) -> sp.Expr:
        return self.parse(self.sections[section][label])

    def numeric(self, expr: sp.Expr, q, qd=None, qdd=None) -> float:
        e = expr.xreplace(self.lumped).xreplace(self.values)
        subs = dict(zip(self.q, q))
        for syms, vals in ((self.qd, qd), (self.qdd, qdd)):
            if vals is not None:
                subs.update(zip(syms, vals))
        return float(e.xreplace(subs))


@pytest.fixture(scope="module")
def arm2() -> Printed:
    return Printed("serial_2dof")


@pytest.fixture(scope="module")
def textbook(arm2):
    """The hand-written textbook 2-DOF closed form (motor mass at the elbow)."""
    s = arm2.ns
    I1, I2, m1, m2, mM = s["I_1"], s["I_2"], s["m_1"], s["m_2"], s["m_M2"]
    a1, lc1, lc2, g = s["a_1"], s["l_c1"], s["l_c2"], s["g"]
    q1, q2 = arm2.q
    qd1, qd2 = arm2.qd
    alpha = I1 + I2 + m1 * lc1**2 + m2 * (a1**2 + lc2**2) + mM * a1**2
    beta = m2 * a1 * lc2
    delta = I2 + m2 * lc2**2
    h = -beta * sp.sin(q2)
    return {
        "alpha": alpha, "beta": beta, "delta": delta,
        "M": {"M11": alpha + 2 * beta * sp.cos(q2), "M12": delta + beta * sp.cos(q2),
              "M22": delta},
        "C": {"C11": h * qd2, "C12": h * (qd1 + qd2), "C21": -h * qd1},
        "g": {"g1": (m1 * lc1 + (m2 + mM) * a1) * g * sp.cos(q1) + m2 * lc2 * g * sp.cos(q1 + q2),
              "g2": m2 * lc2 * g * sp.cos(q1 + q2)},
    }


def _same(a: sp.Expr, b: sp.Expr) -> bool:
    return sp.expand(a - b) == 0


def test_lumped_parameters_are_the_textbook_alpha_beta_delta(arm2, textbook):
    lumped = arm2.sections["Lumped parameters"]
    assert list(lumped) == ["alpha", "beta", "delta"]
    assert _same(arm2.parse(lumped["beta"]), textbook["beta"])
    assert _same(arm2.parse(lumped["delta"]), textbook["delta"])
    # the derivation keeps the motor's own inertia I_M2 (a parameter, 0 in the seed: the
    # textbook's point-mass motor); with it at the seed value alpha is the textbook's exactly
    alpha = arm2.parse(lumped["alpha"])
    I_M2 = arm2.ns["I_M2"]
    assert _same(alpha, textbook["alpha"] + I_M2)
    assert arm2.values[I_M2] == 0.0 and _same(alpha.subs(I_M2, 0), textbook["alpha"])
    assert "m_M2*a_1**2" in lumped["alpha"]  # the motor mass is in alpha


def test_mass_matrix_is_the_textbook_form_term_by_term(arm2, textbook):
    lumped = arm2.sections["Mass matrix in lumped parameters"]
    assert lumped == {"M11": "alpha + 2*beta*c2", "M12": "delta + beta*c2", "M22": "delta"}
    for label, want in textbook["M"].items():
        sub = {arm2.ns[k]: textbook[k] for k in ("alpha", "beta", "delta")}
        assert _same(arm2.parse(lumped[label]).xreplace(sub), want), label
        physical = arm2.get("Mass matrix M(q) = d2T/dqd2", label)
        I_M2 = arm2.ns["I_M2"]
        assert _same(physical.subs(I_M2, 0), want), label  # collected by mass, same terms


def test_coriolis_matrix_and_gravity_are_the_textbook_ones(arm2, textbook):
    sec = arm2.sections["Coriolis and centrifugal matrix C(q, qd) from the Christoffel symbols"]
    assert sec["C11"] == "-beta*s2*qd2" and sec["C21"] == "beta*s2*qd1"
    assert "C22" not in sec  # zero
    sub = {arm2.ns[k]: textbook[k] for k in ("alpha", "beta", "delta")}
    for label, want in textbook["C"].items():
        assert _same(arm2.parse(sec[label]).xreplace(sub), want), label
    grav = arm2.sections["Gravity terms g(q) = dV/dq"]
    for label, want in textbook["g"].items():
        assert _same(arm2.parse(grav[label]), want), label
    assert "c12" in grav["g1"] and "cos" not in grav["g1"]


def test_printed_equations_evaluate_to_the_compiled_library(arm2, rng):
    arm = ps.load("serial_2dof")
    q, qd, qdd = (rng.uniform(-3, 3, (5, 2)) for _ in range(3))
    mm = arm2.sections["Mass matrix M(q) = d2T/dqd2"]
    lumped = arm2.sections["Mass matrix in lumped parameters"]
    for k in range(5):
        M = arm.mass_matrix(q[k])
        for form in (mm, lumped):
            printed = np.array([[arm2.numeric(arm2.parse(form[f"M{min(i, j) + 1}{max(i, j) + 1}"]),
                                              q[k]) for j in range(2)] for i in range(2)])
            assert rel_err(printed[None], M[None]) < 1e-13
        # Euler-Lagrange rows, with g1, g2 from the gravity section
        el = next(v for s, v in arm2.sections.items() if s.startswith("Euler-Lagrange"))
        gsub = {arm2.ns[f"g{i}"]: arm2.get("Gravity terms g(q) = dV/dq", f"g{i}") for i in (1, 2)}
        tau = [arm2.numeric(arm2.parse(el[f"tau{i}"]).xreplace(gsub), q[k], qd[k], qdd[k])
               for i in (1, 2)]
        assert rel_err(np.array([tau]), arm.inverse_dynamics(q[k], qd[k], qdd[k])[None]) < 1e-13


def test_printed_C_gives_the_bias_and_a_skew_symmetric_Mdot_minus_2C(arm2, rng):
    """C from the report: C qd + g is the compiled bias, and Mdot - 2C (Mdot by central
    differences of the compiled M along qd) is skew-symmetric."""
    arm = ps.load("serial_2dof")
    sec = arm2.sections["Coriolis and centrifugal matrix C(q, qd) from the Christoffel symbols"]
    for _ in range(5):
        q, qd = rng.uniform(-3, 3, 2), rng.uniform(-3, 3, 2)
        C = np.array([[arm2.numeric(arm2.parse(sec[f"C{i}{j}"]), q, qd) if f"C{i}{j}" in sec
                       else 0.0 for j in (1, 2)] for i in (1, 2)])
        h = arm.bias(q, qd) - arm.gravity(q)
        assert np.allclose(C @ qd, h, rtol=1e-12, atol=1e-15)
        eps = 1e-6
        mdot = (arm.mass_matrix(q + eps * qd) - arm.mass_matrix(q - eps * qd)) / (2 * eps)
        N = mdot - 2 * C
        assert np.abs(N + N.T).max() < 1e-8 * np.abs(N).max()


@pytest.mark.parametrize("robot", CLOSED)
def test_closed_chain_report_has_phi_jacobian_gamma_and_multipliers(robot, rng):
    pr, rob = Printed(robot), ps.load(robot)
    k, n = rob.n_constraints, rob.n
    phi = pr.sections["Loop closure Phi(q) = 0"]
    jac = pr.sections["Constraint Jacobian Phi_q = dPhi/dq"]
    gam = pr.sections["Acceleration term gamma = -(Phi_q qd)_q qd, so that Phi_q qdd = gamma"]
    assert list(phi) == [f"Phi{i + 1}" for i in range(k)]
    assert list(gam) == [f"gamma{i + 1}" for i in range(k)]
    q, qd = rng.uniform(-3, 3, n), rng.uniform(-3, 3, n)
    printed_phi = [pr.numeric(pr.parse(phi[f"Phi{i + 1}"]), q) for i in range(k)]
    assert np.allclose(printed_phi, rob.constraint(q), rtol=1e-12, atol=1e-15)
    printed_jac = [[pr.numeric(pr.parse(jac[f"Phi_q[{i + 1},{j + 1}]"]), q)
                    if f"Phi_q[{i + 1},{j + 1}]" in jac else 0.0 for j in range(n)]
                   for i in range(k)]
    assert np.allclose(printed_jac, rob.constraint_jacobian(q), rtol=1e-12, atol=1e-15)
    printed_gamma = [pr.numeric(pr.parse(gam[f"gamma{i + 1}"]), q, qd) for i in range(k)]
    assert np.allclose(printed_gamma, rob.constraint_bias(q, qd), rtol=1e-12, atol=1e-14)
    md = equations(robot).markdown
    assert "## Multiplier equation" in md
    assert r"M(q) \ddot q + C(q, \dot q) \dot q + g(q) &= S^\top \tau + \Phi_q^\top \lambda" in md
    words = " ".join(w for w in equations(robot).text.split() if w != "#")  # unwrapped
    for j in description.load(robot).loop_joints:  # the sign convention, per cut joint
        assert f"the force that body {j.child} (child of cut joint {j.name}) exerts on body " \
               f"{j.parent} (its parent)" in words


@pytest.mark.parametrize("robot", ALL_ROBOTS)
def test_properties_are_stated_and_hold(robot):
    text = " ".join(equations(robot).text.split())
    found = re.search(r"positive definite at (\d+) sampled poses .*?random-number seed (\d+)\): "
                      r"smallest eigenvalue found ([0-9.e+-]+) kg\*m\^2", text)
    assert found, "the SPD statement is missing"
    assert "Mdot - 2C is skew-symmetric (checked symbolically" in text
    samples, seed, smallest = int(found[1]), int(found[2]), float(found[3])
    rob = ps.load(robot)
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (samples, rob.n))
    eig = np.linalg.eigvalsh(rob.mass_matrix(q))  # the compiled M at the same poses
    assert eig.min() > 0
    assert float(f"{eig.min():.4g}") == smallest


def test_compact_notation_is_used_and_defined():
    eq = equations("serial_3dof")
    assert "c12 = cos(q1 + q2)" in " ".join(eq.text.split())
    assert r"c_{123} = \cos(q_{1} + q_{2} + q_{3})" in eq.markdown
    assert "c_{12}" in eq.latex and "s_{23}" in eq.markdown
    for section in equations("serial_2dof").sections().values():
        for label, rhs in section.items():
            assert "cos(" not in rhs and "sin(" not in rhs, (label, rhs)


@pytest.mark.parametrize("fmt, marks", [
    ("text", ["M11 = alpha + 2*beta*c2", "alpha = I_1 + I_2 + I_M2 + m_1*l_c1**2"]),
    ("markdown", ["$$", r"M_{11} &= \alpha + 2 \beta c_{2}", r"\alpha &= I_{1}"]),
    ("latex", [r"\documentclass", r"\begin{align*}", r"\beta &= m_{2} a_{1} l_{c2}"]),
])
def test_cli_formats(fmt, marks, capsys):
    assert main(["equations", "serial_2dof", "--format", fmt]) == 0
    out = capsys.readouterr().out
    assert all(m in out for m in marks), [m for m in marks if m not in out]
    assert "do not edit" not in out  # the generated-file header is not printed
    if fmt == "latex":
        assert main(["equations", "serial_2dof", "--latex"]) == 0
        assert capsys.readouterr().out == out


def test_markdown_renders_on_github_and_in_notebooks():
    raw = (GENERATED / "serial_2dof" / "equations.md").read_text()
    assert raw.startswith("<!--") and "do not edit: run `make derive`" in raw.split("-->")[0]
    assert "from planar_sym/robots/serial_2dof.toml" in raw.split("-->")[0]
    for robot in ALL_ROBOTS:
        md = equations(robot).markdown
        assert md.count("\n$$\n") % 2 == 0
        inside = False
        for line in md.splitlines():
            if line == "$$":
                inside = not inside
            elif inside:  # GitHub keeps a LaTeX line break only at the end of a source line
                assert "\\\\" not in line.rstrip("\\").rstrip(), line
        eq = equations(robot)
        assert eq._repr_markdown_() == eq.markdown
        latex = eq._repr_latex_()
        assert latex.startswith("$$") and latex.rstrip().endswith("$$")
        assert latex.count("$$") % 2 == 0


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="no pdflatex")
@pytest.mark.parametrize("robot", ["serial_2dof", "five_bar_type1"])
def test_latex_compiles(robot, tmp_path):
    (tmp_path / "eq.tex").write_text((GENERATED / robot / "equations.tex").read_text())
    proc = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "eq.tex"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120, check=False)
    assert proc.returncode == 0, proc.stdout[-2000:]


def test_runtime_equations_do_not_import_sympy():
    code = ("import sys; from planar_sym.outputs.equations import equations; "
            "e = equations('five_bar_type1'); e._repr_latex_(); e.sections(); "
            "assert 'sympy' not in sys.modules, 'sympy imported'; print(len(e.text))")
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, timeout=120, check=False)
    assert proc.returncode == 0, proc.stderr


def _values_note(robot: str) -> dict[str, tuple[float, str, bool]]:
    """The report's "With this robot's values" line: name -> (value, unit, negligible)."""
    text = (GENERATED / robot / "equations.txt").read_text()
    note = text.split("With this robot's values: ")[1].split(".\n")[0]
    note = " ".join(line.strip().lstrip("#").strip() for line in note.splitlines())
    out = {}
    for part in note.split("; "):
        name, rest = part.split(" = ")
        value, _, tail = rest.partition(" ")
        out[name] = (float(value), tail.split(" (")[0], "negligible" in tail)
    return out


@pytest.mark.parametrize("robot", ["serial_2dof", "five_bar_type1", "cart_pole"])
def test_the_lumped_values_are_the_printed_definitions_at_the_robots_values(robot):
    """Each value printed (4 digits) is its printed definition evaluated at the description's
    parameters; a CAD drawing's noise is named negligible (the seed five-bar's delta and theta,
    m l lcy with lcy a few 1e-4 mm: 1e-6 of beta), and nothing else."""
    printed = Printed(robot)
    note = _values_note(robot)
    assert set(note) == {s.name for s in printed.lumped}
    for sym, definition in printed.lumped.items():
        want = float(definition.xreplace(printed.values))
        got, unit, negligible = note[sym.name]
        assert got == pytest.approx(want, rel=6e-4), (sym, got, want)
        slider = {"alpha": "kg", "beta": "kg*m", "delta": "kg*m^2"}  # cart, pole on it
        assert unit == (slider[sym.name] if robot == "cart_pole" else "kg*m^2")
        assert negligible == (robot == "five_bar_type1" and sym.name in ("delta", "theta"))


def test_a_slanted_rail_prints_exact_fractions_and_the_words_fit_the_robot(tmp_path):
    """A cart on a 30 degree rail, gravity tilted to (0.6, -0.8): its rail's sine squared
    plus cosine squared printed ``1.00000000000000*m_cart`` and half a weight
    ``0.500000000000000*m_cart*g``; the note under V said "gravity along -y" and the
    properties sampled a slider "q uniform in [-pi, pi]" with eigenvalues in kg*m^2."""
    path = tmp_path / "cart_arm.toml"
    path.write_text((TEST_ROBOTS / "geared_cart_arm.toml").read_text().replace(
        "gravity = [0.0, -9810.0]", "gravity = [5886.0, -7848.0]"))
    text = str(equations(str(path)))
    flat = " ".join(line.strip().lstrip("#- ").strip() for line in text.splitlines())
    assert "1.00000000000000" not in text and "0.500000000000000" not in text
    assert "0.866025403784439" in text  # cos 30 deg is no simple fraction: kept as it is
    assert "gravity along (0.6, -0.8), the height measured against it" in flat
    assert "every coordinate uniform in [-pi, pi], rad or m at a slider" in flat
    assert "(SI: kg*m^2, kg*m or kg by the rows' joints)" in flat
    gx, gy = 5.886, -7.848  # the potential as printed, against the library's, at random poses
    printed = text.split("\n  V = ")[1].split("\n  L = ")[0]
    robot = ps.load(str(path))
    ns = {n: sp.Symbol(n) for n in ("d1", "q2", "q3")}
    for head, idx in re.findall(r"\b([cs])(\d+)\b", printed):
        angle = sum(ns[f"q{i}"] for i in idx)
        ns[head + idx] = (sp.cos if head == "c" else sp.sin)(angle)
    values = {desc_p.name: desc_p.value for desc_p in description.load(path).parameters()}
    ns.update({k: v for k, v in values.items()})
    v_expr = sp.sympify(" ".join(printed.split()), locals=ns)
    rng = np.random.default_rng(3)
    for q in rng.uniform(-1, 1, (5, 3)):
        got = float(v_expr.subs({ns["d1"]: q[0], ns["q2"]: q[1], ns["q3"]: q[2]}))
        want = float(robot.energy(q, np.zeros(3))[1])
        assert got == pytest.approx(want, rel=1e-12), (got, want, gx, gy)
