"""The structure report (derive/report_structure.py): what a robot too big for expanded closed
forms prints instead, a kinematic recursion, the energies and how they are differentiated.

What a reader sees is what is checked: the text form is read back with ``sympify`` line by line
(through the same reader as ``planar_sym.equations(...).sections()``), evaluated at random poses
and compared with a plain numpy forward kinematics of the n-link pendulum and with the CasADi
recursion and energies the generated code is built from. The report must stay small (linear in
the number of bodies) and its LaTeX and Markdown well formed.
"""

from __future__ import annotations

import re

import casadi as ca
import numpy as np
import pytest
import sympy as sp
from conftest import ROBOTS_DIR, ROOT, TEST_ROBOTS

from benchmarks.chains import LENGTH_M, write_chain
from derive import ad_dynamics, quantities, recursion, report_structure, size
from planar_sym.model.description import GROUND, load
from planar_sym.outputs.equations import Equations

SIX_BAR = ROOT / "examples" / "six_bar_watt.toml"
RPR = ROBOTS_DIR / "serial_rpr.toml"  # prismatic
ARM3 = ROBOTS_DIR / "serial_3dof.toml"  # welds (motors)
BENT = TEST_ROBOTS / "bent_arm.toml"  # a weld turned by 0.64 rad, oblique gravity
INCLINE = TEST_ROBOTS / "cart_pole_incline.toml"  # an oblique prismatic axis, point masses
GEARED = ROOT / "examples" / "serial_2dof_geared.toml"  # rotor inertia, friction


def _operations(desc) -> dict[str, tuple[int, str]]:
    """What derive passes: per generated function, its operations and route."""
    gens = quantities.functions(ad_dynamics.quantities(desc))
    return {g.quantity: (g.operations, g.route) for g in gens}


def _render(desc) -> dict[str, str]:
    return report_structure.render(desc, _operations(desc))


@pytest.fixture(scope="module")
def chains(tmp_path_factory) -> dict[int, tuple]:
    folder = tmp_path_factory.mktemp("chains")
    out = {}
    for n in (5, 10, 15):
        desc = load(write_chain(n, folder))
        out[n] = (desc, _render(desc))
    return out


@pytest.fixture(scope="module")
def reports() -> dict[str, tuple]:
    out = {}
    for path in (SIX_BAR, RPR, ARM3, BENT, INCLINE, GEARED):
        desc = load(path)
        out[desc.name] = (desc, _render(desc))
    return out


# -- reading the text back -------------------------------------------------------------------


def _sections(desc, text: str) -> dict[str, dict[str, str]]:
    return Equations(desc.name, text, "", "").sections()


def _coordinate_names(desc) -> tuple[list[str], list[str]]:
    slide = [u == "m" for u in desc.coordinate_units]
    return ([f"{'d' if s else 'q'}{i + 1}" for i, s in enumerate(slide)],
            [f"{'dd' if s else 'qd'}{i + 1}" for i, s in enumerate(slide)])


def _flat(text: str) -> str:
    """The text with comment marks and line breaks gone: for finding a sentence."""
    return " ".join(re.sub(r"^  # ", "", text, flags=re.MULTILINE).split())


def _params(desc) -> dict[str, float]:
    return {desc.display.get(p.name, p.name): p.value for p in desc.parameters()}


def _evaluate(rows: dict[str, str], env: dict[str, float]) -> dict[str, float]:
    """Each printed ``label = rhs`` in turn, with every name it uses already known: the
    printed names are all defined before use, or this fails."""
    out = dict(env)
    for label, rhs in rows.items():
        e = sp.sympify(rhs, locals={k: sp.Float(v) for k, v in out.items()})
        assert not e.free_symbols, f"{label} = {rhs}: undefined {e.free_symbols}"
        out[label] = float(e)
    return out


def _recursion_at(desc, text: str, q) -> dict[str, float]:
    names, _ = _coordinate_names(desc)
    env = {**_params(desc), **dict(zip(names, q))}
    return _evaluate(_sections(desc, text)["Kinematic recursion"], env)


# -- size, content ---------------------------------------------------------------------------


def test_the_chain_report_is_small_and_grows_linearly(chains):
    sizes = {n: {fmt: len(r[fmt].encode()) for fmt in r} for n, (_, r) in chains.items()}
    assert sizes[10]["text"] < 20_000, sizes  # the expanded closed forms: 182 kB at 8 links
    for fmt in ("text", "latex", "markdown"):
        assert sizes[10][fmt] / sizes[5][fmt] < 2.5, (fmt, sizes)
        # linear: five more links add the same again (an n^2 term would add 3 times as much)
        first, second = sizes[10][fmt] - sizes[5][fmt], sizes[15][fmt] - sizes[10][fmt]
        assert first > 0 and 0.8 < second / first < 1.25, (fmt, sizes)
    lines = _sections(chains[10][0], chains[10][1]["text"])["Kinematic recursion"]
    assert len(lines) <= 5 * 10 + 2  # theta, origin x y, cg x y per link; the task point


def test_the_report_says_why_and_how_to_get_the_closed_forms(chains, reports):
    desc, r = chains[10]
    reason = size.measure(desc).reason()
    assert reason  # a 10-link chain is past the closed forms' limits
    flat = _flat(r["text"])
    assert reason in flat
    assert "planar-sym derive chain_10.toml --out DIR --equations closed" in flat
    for phrase in ("algorithmic differentiation", "CasADi", "recursion", "forward mode",
                   "reverse mode", "forward over reverse", "O(n) operations", "O(n^2)"):
        assert phrase in flat, phrase
    assert r"chain\_10" in r["latex"] and r"chain\_10" in r["markdown"]
    assert r"\texttt{planar-sym derive chain\_10.toml --out DIR --equations closed}" in r["latex"]
    assert "`planar-sym derive chain_10.toml --out DIR --equations closed`" in r["markdown"]
    # a robot whose closed forms fit says so instead of giving a reason
    rpr_text = _flat(reports["serial_rpr"][1]["text"])
    assert "they would fit for this robot" in rpr_text
    assert "python -m derive serial_rpr --equations closed" in rpr_text
    six_bar = _flat(reports["six_bar_watt"][1]["text"])
    # a user's file: the command that works from an install
    assert "planar-sym derive examples/six_bar_watt.toml --out DIR --equations closed" in six_bar


@pytest.mark.parametrize("robot", ["chain_10", "six_bar_watt", "serial_rpr", "serial_3dof"])
def test_every_body_and_parameter_appears(robot, chains, reports):
    desc, r = chains[10] if robot == "chain_10" else reports[robot]
    text = r["text"]
    rec = _sections(desc, text)["Kinematic recursion"]
    bodies = [b for b in desc.bodies if b != GROUND]
    tree_order = [j.child for j in desc.tree_joints]
    thetas = [k[len("theta_"):] for k in rec if k.startswith("theta_")]
    assert thetas == tree_order and sorted(thetas) == sorted(bodies)  # parents first, all
    for b in bodies:
        assert f"xc_{b}" in rec and f"yc_{b}" in rec, b
    secs = _sections(desc, text)
    used = " ".join(rhs for rows in secs.values() for rhs in rows.values())
    table = text.split("\nSymbols (")[1]
    for p in desc.parameters():
        assert re.search(rf"^  \S.*  {re.escape(p.name)}  ", table, re.MULTILINE), p.name
        shown = desc.display.get(p.name, p.name)
        assert re.search(rf"\b{re.escape(shown)}\b", used), f"{p.name} ({shown}) in no equation"
    for q, name in zip(_coordinate_names(desc)[0], desc.coordinates):
        assert f"{q} = {name}" in _flat(text)


def test_the_generated_functions_are_listed_with_their_cost(chains, reports):
    for desc, r in (chains[10], reports["six_bar_watt"]):
        ops = _operations(desc)
        block = r["text"].split("Generated functions (operations per sample, route):\n")[1]
        for quantity, (n, route) in ops.items():
            assert re.search(rf"^  {quantity} +{n}  {re.escape(route)}$", block, re.MULTILINE), quantity
            assert f"| `{quantity}` | {n} | {route} |" in r["markdown"]
    assert "closed_inverse_dynamics" in reports["six_bar_watt"][1]["text"]


def test_the_text_is_deterministic(chains):
    desc, r = chains[10]
    again = report_structure.render(desc, _operations(desc))
    assert again == r
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b|\d\d:\d\d:\d\d", r["text"])


def test_closed_chain_prints_the_loop_closure_and_its_derivatives(reports):
    desc, r = reports["six_bar_watt"]
    secs = _sections(desc, r["text"])
    assert list(secs["Loop closure Phi(q) = 0"]) == ["Phi1", "Phi2", "Phi3", "Phi4"]
    rows = secs["Constraint Jacobian, acceleration term and multipliers"]
    assert rows["Phi_q"] == "dPhi/dq" and rows["gamma"] == "-(Phi_q qd)_q qd"
    flat = _flat(r["text"])
    assert "force that body rocker (child of cut joint B) exerts on body coupler" in flat
    assert r"\Phi_{1}" in r["latex"] and r"\gamma" in r["markdown"]


# -- LaTeX and Markdown well formed ------------------------------------------------------------


def _balanced(tex: str) -> None:
    depth = 0
    for ch in re.sub(r"\\[{}]", "", tex):  # \{ and \} are characters, not groups
        depth += {"{": 1, "}": -1}.get(ch, 0)
        assert depth >= 0, "a } closes nothing"
    assert depth == 0, f"{depth} unclosed {{"
    stack = []
    for kind, env in re.findall(r"\\(begin|end)\{(\w+\*?)\}", tex):
        if kind == "begin":
            stack.append(env)
        else:
            assert stack and stack.pop() == env, f"\\end{{{env}}} without its \\begin"
    assert not stack, f"unclosed {stack}"


@pytest.mark.parametrize("robot", ["chain_10", "six_bar_watt", "serial_rpr", "serial_3dof",
                                   "bent_arm", "serial_2dof_geared"])
def test_latex_and_markdown_are_well_formed(robot, chains, reports):
    _desc, r = chains[10] if robot == "chain_10" else reports[robot]
    tex = r["latex"]
    assert tex.startswith(r"\documentclass") and tex.rstrip().endswith(r"\end{document}")
    _balanced(tex)
    for math in re.findall(r"(?<!\\)\$(.+?)(?<!\\)\$", tex):  # inline math groups close inside
        _balanced(math)
    md = r["markdown"]
    blocks = re.findall(r"^\$\$\n(.*?)\n\$\$$", md, re.MULTILINE | re.DOTALL)
    assert blocks and sum(ln == "$$" for ln in md.splitlines()) == 2 * len(blocks)
    for block in blocks:
        assert block.startswith(r"\begin{aligned}") and block.endswith(r"\end{aligned}")
        _balanced(block)
        assert all(not ln.endswith(r"\\") or ln.count(r"\\") == 1 for ln in block.splitlines())
    outside = re.sub(r"^\$\$\n.*?\n\$\$$", "", md, flags=re.MULTILINE | re.DOTALL)
    prose = [ln for ln in outside.splitlines() if not ln.startswith("|")]
    for ln in prose:  # inline $...$ pairs up on every line (escaped \$ aside)
        assert len(re.findall(r"(?<!\\)\$", ln)) % 2 == 0, ln


# -- the printed equations evaluate to the right numbers ---------------------------------------


def test_printed_recursion_gives_the_chain_tool_point(chains, rng):
    desc, r = chains[10]
    for _ in range(5):
        q = rng.uniform(-np.pi, np.pi, 10)
        v = _recursion_at(desc, r["text"], q)
        angle = np.cumsum(q)  # absolute angle of each link
        joints = np.concatenate([[[0.0, 0.0]], np.cumsum(
            LENGTH_M * np.column_stack([np.cos(angle), np.sin(angle)]), axis=0)])
        np.testing.assert_allclose([v["x_task"], v["y_task"]], joints[-1], atol=1e-12)
        for k in range(10):
            b = f"link{k + 1}"
            np.testing.assert_allclose(v[f"theta_{b}"], angle[k], atol=1e-12)
            np.testing.assert_allclose([v[f"xo_{b}"], v[f"yo_{b}"]], joints[k], atol=1e-12)
            mid = joints[k] + 0.5 * (joints[k + 1] - joints[k])
            np.testing.assert_allclose([v[f"xc_{b}"], v[f"yc_{b}"]], mid, atol=1e-12)


@pytest.mark.parametrize("robot", ["chain_10", "six_bar_watt", "serial_rpr", "serial_3dof",
                                   "bent_arm", "cart_pole_incline"])
def test_printed_recursion_is_what_the_code_computes(robot, chains, reports, rng):
    """Every body's angle and centre of gravity, the task point and the loop residuals, read
    from the text, against ``recursion.walk`` (what the generated code is built from)."""
    desc, r = chains[10] if robot == "chain_10" else reports[robot]
    tree = recursion.walk(desc)
    s = tree.sym
    bodies = [b for b in desc.bodies if b != GROUND]
    outs = [ca.vertcat(tree.frames[b].angle, tree.cg(b)) for b in bodies]
    if desc.task_point is not None:
        outs.append(tree.at(*desc.task_point))
    for j in desc.loop_joints:
        outs.append(tree.at(j.parent, j.parent_point) - tree.at(j.child, j.child_point))
    f = ca.Function("kin", [s.q, s.p], [ca.vertcat(*outs)])
    p = desc.parameter_values()
    secs = _sections(desc, r["text"])
    for _ in range(5):
        q = rng.uniform(-1.5, 1.5, len(desc.coordinates))
        v = _recursion_at(desc, r["text"], q)
        printed = [x for b in bodies for x in (v[f"theta_{b}"], v[f"xc_{b}"], v[f"yc_{b}"])]
        if desc.task_point is not None:
            printed += [v["x_task"], v["y_task"]]
        if desc.loop_joints:
            phi = _evaluate(secs["Loop closure Phi(q) = 0"], v)
            printed += [phi[f"Phi{i + 1}"] for i in range(2 * len(desc.loop_joints))]
        want = np.asarray(f(q, p)).ravel()
        np.testing.assert_allclose(printed, want, atol=1e-9 * max(1.0, np.abs(want).max()))


@pytest.mark.parametrize("robot", ["chain_5", "serial_rpr", "bent_arm", "cart_pole_incline",
                                   "serial_2dof_geared", "six_bar_watt"])
def test_printed_energies_are_what_the_code_differentiates(robot, chains, reports, rng):
    """T and V as printed (velocities: the printed recursion differentiated along qd by central
    differences) against the CasADi energies of ``ad_dynamics``, rotors included."""
    desc, r = chains[5] if robot == "chain_5" else reports[robot]
    d = ad_dynamics.derive(desc)
    s = d.sym
    f = ca.Function("energy", [s.q, s.qd, s.p], [d.kinetic, d.potential])
    p = desc.parameter_values()
    rows = _sections(desc, r["text"])["Kinetic and potential energy, Lagrangian"]
    bodies = [b for b in desc.bodies if b != GROUND]
    _, rate_names = _coordinate_names(desc)
    h = 1e-6
    for _ in range(3):
        n = len(desc.coordinates)
        q, qd = rng.uniform(-1.5, 1.5, n), rng.uniform(-2.0, 2.0, n)
        plus = _recursion_at(desc, r["text"], q + h * qd)
        minus = _recursion_at(desc, r["text"], q - h * qd)
        here = _recursion_at(desc, r["text"], q)
        env = {**here, **dict(zip(rate_names, qd))}
        for b in bodies:
            for name, key in ((f"vx_{b}", f"xc_{b}"), (f"vy_{b}", f"yc_{b}"),
                              (f"w_{b}", f"theta_{b}")):
                env[name] = (plus[key] - minus[key]) / (2 * h)
        got = _evaluate({"T": rows["T"], "V": rows["V"]}, env)
        kinetic, potential = (float(x) for x in f(q, qd, p))
        assert got["T"] == pytest.approx(kinetic, rel=1e-7, abs=1e-9)
        assert got["V"] == pytest.approx(potential, rel=1e-9, abs=1e-9)


def test_rotors_and_friction_are_printed_where_described(reports):
    desc, r = reports["serial_2dof_geared"]
    secs = _sections(desc, r["text"])
    assert "jm_joint1" in secs["Kinetic and potential energy, Lagrangian"]["T"]
    assert "w_link1" in secs["Kinetic and potential energy, Lagrangian"]["T"]  # the stator turns
    friction = secs["Actuator friction D(qd)"]
    assert friction["D1"] == "fv_joint1*qd1 + fc_joint1*tanh(qd1/vs_joint1)"
    assert "+ D(qd)" in secs["Equations of motion"]["h(q, qd)"]
    assert "Actuator friction" not in reports["serial_rpr"][1]["text"]


def test_twelve_links_stay_readable(tmp_path):
    desc = load(write_chain(12, tmp_path))
    text = report_structure.render(desc, {"inverse_dynamics": (1000, ("algorithmic "
                                                                     "differentiation"))})["text"]
    assert len(text.encode()) < 25_000
    assert max(len(ln) for ln in text.splitlines()) <= 110  # the symbol table's meaning column
    rec = _sections(desc, text)["Kinematic recursion"]
    assert max(len(v) for v in rec.values()) < 60  # each line one step of the recursion
