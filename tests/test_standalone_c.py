"""examples/c: the generated serial_2dof.c and a small main.c, compiled with the system C
compiler into a program without Python or heap, give the runtime's torques to 1e-12 relative
(in practice bit for bit: same source, same flags)."""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest
from conftest import GENERATED, ROOT

from planar_sym.model.locate import load

EXAMPLE = ROOT / "examples" / "c"
GEN = GENERATED / "serial_2dof"
CC = shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no system C compiler `cc`")


def _main_source() -> str:
    return (EXAMPLE / "main.c").read_text()


def test_main_uses_no_heap():
    code = re.sub(r"/\*.*?\*/", "", _main_source(), flags=re.DOTALL)  # comments may say anything
    for word in ("malloc", "calloc", "realloc", "free(", "alloca"):
        assert word not in code, f"main.c uses {word}"


def test_baked_in_parameters_match_the_manifest():
    """The const array P, in order and to the last bit, is the manifest's parameter vector."""
    block = re.search(r"static const casadi_real P\[N_P\] = \{(.*?)\};", _main_source(), re.DOTALL)
    values = [float(v) for v in re.findall(r"^\s*([-+0-9.eE]+),", block.group(1), re.MULTILINE)]
    manifest = json.loads((GEN / "manifest.json").read_text())
    assert values == [p["value"] for p in manifest["parameters"]]
    assert f"#define N_P {len(values)} " in _main_source()


@pytest.fixture(scope="module")
def program(tmp_path_factory):
    """Built as examples/c/Makefile builds it (same commands, same flags)."""
    if CC is None:
        pytest.skip("no system C compiler `cc`")
    build = tmp_path_factory.mktemp("c")
    flags = ["-O3", "-std=c99"]
    steps = [[CC, *flags, "-Wall", "-Wextra", "-pedantic", f"-I{GEN}", "-c",
              str(EXAMPLE / "main.c"), "-o", str(build / "main.o")],
             [CC, *flags, "-c", str(GEN / "serial_2dof.c"), "-o", str(build / "serial_2dof.o")],
             [CC, "-o", str(build / "serial_2dof_tau"), str(build / "main.o"),
              str(build / "serial_2dof.o"), "-lm"]]
    for i, cmd in enumerate(steps):
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        assert proc.returncode == 0, proc.stderr
        assert i > 0 or "warning" not in proc.stderr, proc.stderr  # main.c: -Wall -Wextra clean
    return build / "serial_2dof_tau"


def _run(program, *args) -> subprocess.CompletedProcess:
    return subprocess.run([str(program), *map(repr, args)], capture_output=True, text=True,
                          check=False, timeout=30)


@needs_cc
def test_torques_match_the_python_runtime(program, rng):
    robot = load("serial_2dof")
    states = [np.zeros(6), np.array([np.pi / 6, np.pi / 4, 1.0, -1.0, 2.0, 0.5])]
    states += list(rng.uniform(-3, 3, (8, 6)))
    for x in states:
        proc = _run(program, *map(float, x))
        assert proc.returncode == 0, proc.stderr
        tau_c = np.array([float(v) for v in proc.stdout.split()])
        tau_py = robot.inverse_dynamics(x[:2], x[2:4], x[4:])
        assert tau_c.shape == (2,)
        assert np.max(np.abs(tau_c - tau_py)) <= 1e-12 * np.max(np.abs(tau_py)), (x, tau_c)


@needs_cc
def test_bad_arguments(program):
    assert _run(program, 1.0, 2.0).returncode == 2
    proc = subprocess.run([str(program), "0", "0", "0", "0", "0", "x1"], capture_output=True,
                          text=True, check=False)
    assert proc.returncode == 2 and "argument 6 (x1) is not a number" in proc.stderr


@pytest.mark.skipif(CC is None or shutil.which("make") is None, reason="needs cc and make")
def test_the_makefile_builds_and_runs_it(tmp_path):
    # a user who followed the docs' `cd examples/c && make` has a binary there: fine, but this
    # run must neither write nor touch one (it builds in BUILD)
    binary = EXAMPLE / "serial_2dof_tau"
    before = binary.stat().st_mtime_ns if binary.exists() else None
    proc = subprocess.run(["make", "-s", "-C", str(EXAMPLE), f"BUILD={tmp_path}", "run"],
                          capture_output=True, text=True, check=False, timeout=120)
    assert proc.returncode == 0, proc.stderr
    tau = [float(v) for v in proc.stdout.split()]
    ref = load("serial_2dof").inverse_dynamics([np.pi / 6, np.pi / 4], [1, -1], [2, 0.5])
    np.testing.assert_allclose(tau, ref, rtol=1e-12)
    after = binary.stat().st_mtime_ns if binary.exists() else None
    assert after == before  # built in BUILD, not in the sources
