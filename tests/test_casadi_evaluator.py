"""Without a C compiler the runtime evaluates each robot's saved CasADi functions
(``<quantity>.casadi``, written by ``Function.save`` at derive time). They must give the compiled
C's numbers: every function of every built-in robot, at random inputs, through the batch
interface and through the C-callable pointer the integrator and the Newton loop call."""

from __future__ import annotations

import ctypes
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.model.description import builtin_robots
from planar_sym.model.evaluator import CasadiFunction
from planar_sym.model.library import Library

ROOT = Path(__file__).resolve().parent.parent


def _inputs(spec, n, p, rng):
    return {name: (p if name == "p" else rng.uniform(-1.5, 1.5, (n, size)))
            for name, size in spec.inputs}


@pytest.mark.parametrize("robot", builtin_robots())
def test_saved_functions_equal_the_compiled_c(robot):
    lib = Library(robot)
    p = ps.load(robot).p
    rng = np.random.default_rng(7)
    worst = 0.0
    for quantity, spec in lib.manifest["functions"].items():
        compiled = lib.functions[quantity]
        saved = CasadiFunction(lib.folder / spec["casadi"], compiled.spec)
        args = _inputs(compiled.spec, 17, p, rng)
        want, got = compiled(17, args), saved(17, args)
        for name in want:
            assert got[name].shape == want[name].shape, (quantity, name)
            scale = max(np.max(np.abs(want[name])), 1.0)
            worst = max(worst, float(np.max(np.abs(got[name] - want[name])) / scale))
    assert worst < 1e-12, f"{robot}: saved CasADi functions differ from the C by {worst:.3g}"


def test_the_callback_has_the_batch_signature():
    """The pointer handed to C loops writes the same numbers as the compiled batch symbol."""
    lib = Library("five_bar_type1")
    spec = lib.functions["constraint_jacobian"].spec
    saved = CasadiFunction(lib.folder / "constraint_jacobian.casadi", spec)
    rng = np.random.default_rng(3)
    args = _inputs(spec, 5, ps.load("five_bar_type1").p, rng)
    outs = [np.zeros((5, r * c)) for _, r, c, _ in spec.outputs]
    ptrs = [np.ascontiguousarray(args[name]).ctypes.data for name, _ in spec.inputs]
    fn = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_longlong,
                          *[ctypes.c_void_p] * (len(ptrs) + len(outs)))(saved.address)
    assert fn(5, *ptrs, *[o.ctypes.data for o in outs]) == 0
    want = lib.functions["constraint_jacobian"](5, args)["phi_q"]
    got = outs[0].reshape(5, spec.outputs[0][2], spec.outputs[0][1]).transpose(0, 2, 1)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-13)
    # a failure inside becomes a failure status (not an unwritten output reported as success)
    assert fn(5, *ptrs[:-1], 0, *[o.ctypes.data for o in outs]) == 1
    assert saved.error is not None


NO_COMPILER = """
import json, sys, warnings
import numpy as np
import planar_sym as ps
out = {}
res = ps.run_study("five_bar_type1_move_x")
out["s5"] = np.column_stack(list(res.columns.values())).tolist()
arm = ps.load("serial_2dof")
out["compiled"] = arm.library.compiled
sim = ps.simulate(arm, [0.3, -0.2], [0.0, 0.0], (0.0, 0.5), t_eval=np.linspace(0, 0.5, 11))
out["swing"] = sim.q.tolist()
out["drift"] = sim.energy_drift
json.dump(out, open(sys.argv[1], "w"))
"""


def test_runs_with_no_compiler_on_the_path(tmp_path):
    """PATH stripped of compilers, CC unset, an empty cache and the install's libraries set
    aside: a closed-chain study (the generic Newton IK and inverse dynamics through the
    callbacks) and a free swing (the C integrator through the callback) give the compiled
    numbers, with one warning line per robot that states the speed cost."""
    env = {k: v for k, v in os.environ.items() if k not in ("CC", "PLANAR_SYM_EXACT")}
    env.update(PATH=str(tmp_path / "empty"), PLANAR_SYM_CACHE=str(tmp_path / "cache"),
               PLANAR_SYM_PREBUILT="0", PYTHONPATH=str(ROOT))
    script = tmp_path / "run.py"
    script.write_text(NO_COMPILER)
    proc = subprocess.run([sys.executable, str(script), str(tmp_path / "out.json")], env=env,
                          capture_output=True, text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr
    warned = [ln for ln in proc.stderr.splitlines() if "RuntimeWarning" in ln]
    assert len(warned) == 2 and all("CasADi's own evaluator" in w and "slower" in w
                                    for w in warned), proc.stderr
    import json

    got = json.loads((tmp_path / "out.json").read_text())
    assert got["compiled"] is False
    res = ps.run_study("five_bar_type1_move_x")
    want = np.column_stack(list(res.columns.values()))
    scale = np.max(np.abs(want), axis=0) + 1e-300
    assert np.max(np.abs(np.array(got["s5"]) - want) / scale) < 1e-13  # seen: 3.1e-15
    sim = ps.simulate(ps.load("serial_2dof"), [0.3, -0.2], [0.0, 0.0], (0.0, 0.5),
                      t_eval=np.linspace(0, 0.5, 11))
    np.testing.assert_allclose(got["swing"], sim.q, rtol=0, atol=1e-13)  # seen: equal
    assert got["drift"] < 1e-9


def test_derive_without_a_compiler_says_so(tmp_path):
    """`planar-sym derive` with no compiler used to print "compiled None" (issue 29): it says
    the robot was written, not compiled, and how to compile it later."""
    env = {k: v for k, v in os.environ.items() if k not in ("CC", "PLANAR_SYM_EXACT")}
    env.update(PATH=str(tmp_path / "empty"), PLANAR_SYM_CACHE=str(tmp_path / "cache"),
               PLANAR_SYM_PREBUILT="0", PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-m", "planar_sym", "derive",
                           str(ROOT / "tests" / "robots" / "pendulum.toml"), "--out",
                           str(tmp_path / "out")], env=env, capture_output=True, text=True,
                          timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr
    assert "None" not in proc.stdout
    assert (f"pendulum: wrote {tmp_path / 'out' / 'pendulum'}/, not compiled (no C compiler: "
            "it runs on CasADi's evaluator, slower; with a compiler, `planar-sym build "
            f"{tmp_path / 'out' / 'pendulum'}`)") in proc.stdout
