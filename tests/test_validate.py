"""``planar-sym validate``: passes on every built-in robot and on a derived one, and fails, naming
the row, on a robot whose compiled mass matrix was tampered with (a constant changed in the C,
the manifest's file hash recomputed so the loader accepts it)."""

from __future__ import annotations

import hashlib
import json
import shutil
import sys

import pytest
from conftest import ALL_ROBOTS, GENERATED, ROOT

from planar_sym.analysis import validate
from planar_sym.cli import main
from planar_sym.model.locate import load

ROW_COUNT = {"tree": 4, "closed": 7}


def _rows(out: str) -> dict[str, list[str]]:
    """Table lines by check label, e.g. '(a)' -> the words of that line."""
    rows = {}
    for line in out.splitlines():
        if line.startswith("("):
            rows.setdefault(line.split(")")[0] + ")", []).append(line)
    return rows


@pytest.mark.parametrize("robot", ALL_ROBOTS)
def test_every_builtin_robot_passes(robot, capsys):
    # about a second each (the 3-RRR's 1 s closed-chain simulation is the slowest)
    assert main(["validate", robot]) == 0
    out = capsys.readouterr().out
    n = ROW_COUNT["closed" if load(robot).is_closed_chain else "tree"]
    assert f"{robot}: all {n} checks pass" in out
    assert "FAIL" not in out and "skipped" not in out
    assert set(_rows(out)) == ({"(a)", "(b)", "(c)", "(d)", "(e)"} if n == 7
                               else {"(a)", "(b)", "(c)", "(d)"})


@pytest.fixture
def tampered(tmp_path, monkeypatch):
    """serial_2dof with 2*a_1*l_c2*m_2*cos(q2) in M11 turned into 2.5*...: only the compiled
    mass_matrix function changes; energy, bias and inverse dynamics stay right."""
    # a private cache: the library cache is keyed by the input hash, which tampering keeps
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    folder = tmp_path / "serial_2dof"
    shutil.copytree(GENERATED / "serial_2dof", folder)
    src = folder / "serial_2dof.c"
    text = src.read_text()
    start, end = text.index("/* serial_2dof_mass_matrix:"), text.index("/* serial_2dof_bias:")
    body = text[start:end]
    assert body.count("(2.*") == 1, "the generated mass matrix changed shape: update this test"
    src.write_text(text[:start] + body.replace("(2.*", "(2.5*") + text[end:])
    manifest = json.loads((folder / "manifest.json").read_text())
    manifest["files"]["serial_2dof.c"] = hashlib.sha256(src.read_bytes()).hexdigest()
    (folder / "manifest.json").write_text(json.dumps(manifest, indent=2))
    return folder


def test_a_tampered_mass_matrix_fails_validation(tampered, capsys):
    assert main(["validate", str(tampered)]) == 1
    out = capsys.readouterr().out
    rows = _rows(out)
    for label in ("(a)", "(b)"):  # both routes see it (the exact path), and name the function
        assert "FAIL" in rows[label][0] and "mass_matrix.M" in rows[label][0], out
    for label in ("(c)", "(d)"):  # these use energy and inverse dynamics: untouched
        assert "pass" in rows[label][0], out
    assert "serial_2dof: FAILED: 2 of 4 checks" in out


def test_quiet_prints_only_the_failing_rows(tampered, capsys):
    assert main(["validate", str(tampered), "--quiet"]) == 1
    out = capsys.readouterr().out
    assert set(_rows(out)) == {"(a)", "(b)"}
    assert main(["validate", "serial_2dof", "--quiet"]) == 0
    assert capsys.readouterr().out == ""


def test_without_sympy_the_symbolic_row_is_skipped(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "sympy", None)  # import sympy now raises ImportError
    assert main(["validate", "serial_2dof"]) == 0
    (row,) = _rows(capsys.readouterr().out)["(a)"]
    assert "skipped" in row and "needs SymPy" in row


def test_a_derived_robot_validates_with_its_own_description(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    toml = ROOT / "examples" / "four_bar.toml"
    assert main(["derive", str(toml), "--out", str(tmp_path), "--quiet"]) == 0
    assert main(["validate", str(tmp_path / "four_bar")]) == 0
    out = capsys.readouterr().out
    assert "four_bar: all 7 checks pass" in out
    assert str(tmp_path / "four_bar" / "description.toml") in _rows(out)["(a)"][0]


def test_rows_as_functions():
    """The checks are plain functions returning rows; a wrong reference fails its row."""
    robot = load("serial_2dof")
    row = validate.check_energy_route(robot, samples=5)
    assert row.status == "pass" and row.worst < row.tolerance
    heavier = robot.with_parameters(m_motor2=0.5)  # same compiled code, other parameters
    assert validate.check_symbolic(heavier, samples=3).status == "pass"
    bad = validate.row("x", 2e-3, 1e-3)
    assert bad.status == "FAIL" and validate.row("x", float("nan"), 1.0).status == "FAIL"


def test_tampered_fast_loops_fail_validation(tmp_path, monkeypatch, capsys):
    """The vectorised loops are a second compiled copy of every function: a wrong factor there
    (2 a_1 l_c2 m_2 c2 -> 2.5 ... in the loop of the mass matrix) must be caught by 'fast' rows."""
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    folder = tmp_path / "serial_2dof"
    shutil.copytree(GENERATED / "serial_2dof", folder)
    src = folder / "serial_2dof_simd.c"
    text = src.read_text()
    start = text.index("serial_2dof_mass_matrix_loop(")
    end = text.index("serial_2dof_bias_loop(")
    body = text[start:end]
    assert body.count("(2.0 * ") == 1, "the generated loop changed shape: update this test"
    src.write_text(text[:start] + body.replace("(2.0 * ", "(2.5 * ") + text[end:])
    manifest = json.loads((folder / "manifest.json").read_text())
    manifest["files"]["serial_2dof_simd.c"] = hashlib.sha256(src.read_bytes()).hexdigest()
    (folder / "manifest.json").write_text(json.dumps(manifest, indent=2))
    assert main(["validate", str(folder)]) == 1
    rows = _rows(capsys.readouterr().out)
    assert "FAIL" in rows["(a)"][0] and "fast mass_matrix.M" in rows["(a)"][0]
