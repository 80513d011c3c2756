"""The runtime imports neither SymPy nor the derive package (a fresh interpreter checks it)."""

from __future__ import annotations

import subprocess
import sys

from conftest import ROOT

PROBE = """
import sys
import planar_sym
import planar_sym.model.locate, planar_sym.model.library, planar_sym.model.description, planar_sym.errors
robot = planar_sym.model.locate.load("serial_2dof")
robot.inverse_dynamics([0.1, 0.2], [0.0, 0.0], [0.0, 0.0])
heavy = sorted(m for m in sys.modules if m.split(".")[0] in ("sympy", "derive", "pinocchio"))
print(",".join(heavy) or "-")
print("casadi" in sys.modules)
"""


def test_runtime_does_not_import_sympy_or_derive():
    proc = subprocess.run([sys.executable, "-c", PROBE], cwd=ROOT, capture_output=True, text=True,
                          check=False, timeout=120)
    assert proc.returncode == 0, proc.stderr
    heavy, _ = proc.stdout.split()
    assert heavy == "-", f"the runtime imported {heavy}"


def test_probe_detects_an_import():
    """The probe itself works: importing the derive package is seen."""
    code = PROBE.replace("import planar_sym\n", "import planar_sym\nimport derive.model\n", 1)
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                          check=False, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "sympy" in proc.stdout and "derive" in proc.stdout
