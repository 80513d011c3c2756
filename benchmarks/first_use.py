"""Part of section 3: the first torque of a fresh install, and what running without a compiler costs.

* **first torque**: a fresh interpreter with an empty ``PLANAR_SYM_CACHE`` imports planar_sym,
  loads a built-in robot and computes one torque (``inverse_dynamics``, or
  ``closed_chain_inverse_dynamics`` for a closed chain, at the drawn pose at rest): wall time
  of the whole subprocess. Three ways: with the libraries the install compiled (setup.py), with
  them set aside (``PLANAR_SYM_PREBUILT=0``: compiled on first use, the behaviour before), and
  with no compiler on the PATH either (CasADi's evaluator). Baseline in the same rounds: a
  subprocess that only imports planar_sym.
* **evaluator cost**: in-process, the saved CasADi functions (``model.evaluator``) against the
  compiled exact C on the same inputs: per sample in batches of 10^4, per single-sample call
  from Python, and per right-hand side of a free swing integrated by the C DOPRI5 (which calls
  the evaluator back through ctypes: what a simulation or a Newton step pays).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from . import Config
from .report import Table
from .timing import interleaved, once_each, ratio

ROOT = Path(__file__).resolve().parent.parent

FIRST = """
import planar_sym as ps, numpy as np
r = ps.load({robot!r})
q, z = r.q_drawn[None], np.zeros((1, r.n))
tau = r.closed_chain_inverse_dynamics(q, z, z)[0] if r.is_closed_chain else r.inverse_dynamics(q, z, z)
assert np.all(np.isfinite(tau))
"""


def _subprocess(code: str, **env):
    def run():
        with tempfile.TemporaryDirectory(prefix="planar_sym_first_") as tmp:
            e = {**os.environ, "PLANAR_SYM_CACHE": str(Path(tmp) / "cache"), **env}
            e.pop("PLANAR_SYM_EXACT", None)
            if env.get("PATH") == "":
                e["PATH"] = str(Path(tmp) / "no-compiler")
                e.pop("CC", None)
            subprocess.run([sys.executable, "-W", "ignore", "-c", code], env=e, check=True,
                           capture_output=True, cwd=tmp)
    return run


def first_torque(cfg: Config) -> tuple[Table, dict]:
    fns = {"import": _subprocess("import planar_sym")}
    for robot in cfg.build_robots:
        code = FIRST.format(robot=robot)
        fns[(robot, "installed")] = _subprocess(code)
        fns[(robot, "compiled on first use")] = _subprocess(code, PLANAR_SYM_PREBUILT="0")
        fns[(robot, "no compiler")] = _subprocess(code, PLANAR_SYM_PREBUILT="0", PATH="")
    st = once_each(fns, repeats=cfg.build_repeats)
    t = Table("First torque on an empty cache: a fresh `python -c` that imports planar_sym, "
              "loads the robot and computes one torque (wall time); ratio to a subprocess "
              "that only imports planar_sym, same rounds",
              ["robot", "libraries", "time", "ratio"])
    t.add("-", "`import planar_sym` only", st["import"], "1")
    for key, s in st.items():
        if key != "import":
            t.add(key[0], key[1], s, ratio(s, st["import"]))
    worst = max((k for k in st if k != "import" and k[1] == "installed"),
                key=lambda k: st[k].median)
    return t, {"first": st[worst], "worst": worst[0], "stats": st}


def evaluator_cost(cfg: Config) -> tuple[Table, float, float]:
    import planar_sym as ps
    from planar_sym.model.evaluator import CasadiFunction
    from planar_sym.model.library import Library
    from planar_sym.model.robot import Robot

    n = 1_000 if cfg.quick else 10_000
    t = Table(f"CasADi's evaluator (the saved functions, used when no compiler is at hand) "
              f"against the compiled exact C, same inputs: per sample in batches of {n}, and "
              "per single-sample call", ["robot", "function", "call", "C", "CasADi", "ratio"])
    batch, single = [], []
    for robot in cfg.build_robots:
        lib, p = Library(robot), ps.load(robot).p
        quantity = "closed_inverse_dynamics" if lib.manifest["constraints"] else "inverse_dynamics"
        c = lib.functions[quantity]
        saved = CasadiFunction(lib.folder / lib.manifest["functions"][quantity]["casadi"], c.spec)
        rng = np.random.default_rng(0)
        for size, label, store in ((n, "batch", batch), (1, "single", single)):
            args = {name: (p if name == "p" else rng.uniform(-1, 1, (size, k)))
                    for name, k in c.spec.inputs}
            st = interleaved({"C": lambda f=c, n=size, a=args: f(n, a),
                              "CasADi": lambda f=saved, n=size, a=args: f(n, a)},
                             repeats=cfg.repeats, per=size, min_block_s=cfg.min_block_s)
            r = ratio(st["CasADi"], st["C"])
            store.append(r.median)
            t.add(robot, quantity, label, st["C"], st["CasADi"], r)
    sims = []
    for robot in [r for r in cfg.build_robots if not ps.load(r).is_closed_chain]:
        fast, slow = Robot(robot, exact=True), _on_the_evaluator(robot)
        q0 = fast.q_drawn + 0.3
        runs = {k: (lambda r=r, q0=q0: ps.simulate(r, q0, np.zeros(r.n), (0.0, 0.5)))
                for k, r in (("C", fast), ("CasADi", slow))}
        per = runs["C"]().n_rhs
        st = interleaved(runs, repeats=max(2, cfg.repeats // 2), per=per, min_block_s=0.0)
        r = ratio(st["CasADi"], st["C"])
        sims.append(r.median)
        t.add(robot, "forward_dynamics", "DOPRI5 in C, per right-hand side", st["C"],
              st["CasADi"], r)
    return t, float(np.median(batch)), float(np.median(sims or single))


def _on_the_evaluator(robot: str):
    """The robot as it runs with no compiler: its Library holding the saved functions."""
    import planar_sym as ps
    from planar_sym.model.evaluator import CasadiFunction
    from planar_sym.model.library import Library
    from planar_sym.model.robot import Robot

    lib = Library(robot)
    lib.functions = {q: CasadiFunction(lib.folder / lib.manifest["functions"][q]["casadi"],
                                       f.spec) for q, f in lib.functions.items()}
    lib.lib = lib.simd = None
    lib.compiled = False
    return Robot(robot, lib, parameters=ps.load(robot).p, exact=True)
