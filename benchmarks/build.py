"""Section 3: what it costs to get from a description to a loaded library.

* **derive**: ``python -m derive ROBOT... --out TMP`` in a subprocess (a fresh interpreter, as
  ``make derive`` runs it), all robots in one process, into a temporary folder (``generated/``
  is never touched). Per robot: derive's own in-process timing of that robot (it prints
  ``derived NAME in X s``: SymPy derivation and C generation, imports excluded); in total: the
  subprocess's wall time. Baseline, interleaved: a subprocess that only imports what derive
  imports (``sympy``, ``casadi``, ``derive``), the fixed cost of any derivation.
* **compile**: ``planar_sym.model.library.build(folder, manifest, force=True)`` in-process, with
  ``PLANAR_SYM_CACHE`` pointing at a fresh temporary folder every time, i.e. the committed C
  compiled with the runtime's own compiler and flags; likewise ``build_simd`` (the vectorised
  ``<robot>_simd.c``) where the library and the robot have one, since a first use builds both.
  Baseline, interleaved: the same compiler and the exact flags on a one-line C file (compiler
  start-up and linking).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from . import Config
from .report import Section, Table
from .timing import Stats, once_each, ratio

ROOT = Path(__file__).resolve().parent.parent


def _derive(robots: tuple[str, ...], per_robot: dict[str, list[float]]):
    def run():
        with tempfile.TemporaryDirectory(prefix="planar_sym_derive_") as tmp:
            proc = subprocess.run([sys.executable, "-m", "derive", *robots, "--out", tmp],
                                  check=False, cwd=ROOT, capture_output=True, text=True)
            if proc.returncode != 0:
                raise RuntimeError(f"python -m derive failed:\n{proc.stderr}")
            for name, secs in re.findall(r"derived (\S+) in ([0-9.]+) s", proc.stderr):
                per_robot.setdefault(name, []).append(float(secs))
    return run


def _imports_only():
    subprocess.run([sys.executable, "-c", "import sympy, casadi, derive.model, derive.codegen"],
                   cwd=ROOT, check=True, capture_output=True)


def _compile(robot: str, flavour: str):
    """A timed build of one flavour ("exact": ``build``; "simd": ``build_simd`` where the
    library and the robot have one, else None) into a fresh cache, and its source size."""
    from planar_sym.model import compile as library
    from planar_sym.model.folders import find_generated, read_manifest

    folder = find_generated(robot)
    manifest = read_manifest(folder)
    builder = library.build if flavour == "exact" else getattr(library, "build_simd", None)
    src = folder / (f"{robot}.c" if flavour == "exact" else f"{robot}_simd.c")
    if builder is None or not src.exists():
        return None, 0

    def run():
        old = os.environ.get("PLANAR_SYM_CACHE")
        with tempfile.TemporaryDirectory(prefix="planar_sym_cache_") as tmp:
            os.environ["PLANAR_SYM_CACHE"] = tmp
            try:
                builder(folder, manifest, force=True)
            finally:
                if old is None:
                    del os.environ["PLANAR_SYM_CACHE"]
                else:
                    os.environ["PLANAR_SYM_CACHE"] = old
    return run, src.stat().st_size


def _trivial_compile(workdir: Path):
    from planar_sym.model.compile import CFLAGS, _compiler

    src = workdir / "trivial.c"
    src.write_text("double trivial(double x) { return 2.0 * x; }\n")

    def run():
        subprocess.run([_compiler(), *CFLAGS, "-o", str(workdir / "trivial.so"), str(src), "-lm"],
                       check=True, capture_output=True)
    return run


def run(cfg: Config) -> Section:
    from planar_sym.model.compile import CFLAGS

    sec = Section("build", "3. Derive and compile times", __doc__.split("\n\n", 1)[1])
    per_robot: dict[str, list[float]] = {}
    robots = cfg.derive_robots
    st = once_each({"derive": _derive(robots, per_robot), "imports": _imports_only},
                   repeats=cfg.build_repeats)
    imports = st["imports"]
    t = Table(f"`python -m derive` ({len(robots)} robot(s), one subprocess per round); ratio to "
              "the import-only subprocess of the same round", ["what", "time", "ratio"])
    t.add("import-only subprocess (`sympy`, `casadi`, `derive`)", imports, "1")
    total = st["derive"]
    t.add(f"whole `python -m derive {' '.join(robots)}` (wall)", total, ratio(total, imports))
    for name in robots:
        s = Stats(tuple(per_robot[name]))
        t.add(f"{name}: derivation in-process (derive's own timing)", s, ratio(s, imports))
    sec.tables.append(t)
    derived = Stats(tuple(sum(v[i] for v in per_robot.values())
                          for i in range(cfg.build_repeats)))
    sec.headlines["derive"] = (
        f"Deriving {'all ' + str(len(robots)) + ' robots' if len(robots) > 1 else robots[0]}: "
        f"**{derived.median:.3g} s** [{derived.min:.3g}-{derived.max:.3g}] in-process "
        f"({total.median:.3g} s wall for `python -m derive` in a fresh interpreter, "
        f"{ratio(total, imports).median:.3g}x the import-only subprocess)")

    with tempfile.TemporaryDirectory(prefix="planar_sym_trivial_") as tmp:
        fns, sizes = {"trivial": _trivial_compile(Path(tmp))}, {}
        for name in cfg.build_robots:
            for flavour in ("exact", "simd"):
                fn, size = _compile(name, flavour)
                if fn is not None:
                    fns[(name, flavour)], sizes[(name, flavour)] = fn, size
        st = once_each(fns, repeats=cfg.build_repeats)
    c = Table(f"Compile the generated C into a fresh cache: `library.build` (`cc "
              f"{' '.join(CFLAGS)}`) and, where there is one, `library.build_simd` (the "
              "vectorised sample loops); ratio to compiling a one-line C file with the exact "
              "flags in the same round",
              ["robot", "flavour", "generated C", "time", "ratio"])
    c.add("one-line C file", "exact", "-", st["trivial"], "1")
    for key in fns:
        if key != "trivial":
            c.add(key[0], key[1], f"{sizes[key] / 1024:.0f} KiB", st[key],
                  ratio(st[key], st["trivial"]))
    sec.tables.append(c)
    keys = [k for k in fns if k != "trivial"]
    all_c = Stats(tuple(sum(st[k].values[i] for k in keys) for i in range(cfg.build_repeats)))
    per_robot = {n: sum(st[k].median for k in keys if k[0] == n) for n in cfg.build_robots}
    from .first_use import evaluator_cost, first_torque

    table, first = first_torque(cfg)
    sec.tables.append(table)
    st = first["stats"]
    compiled = max(st[k].median for k in st if k != "import" and k[1] == "compiled on first use")
    sec.headlines["first torque"] = (
        f"First torque of a fresh install, empty cache, whole process: **{first['first'].median:.3g} s**"
        f" at worst ({first['worst']}; `import planar_sym` alone {st['import'].median:.3g} s), "
        f"with the libraries compiled at install; {compiled:.3g} s when compiled on first use")
    table, batch, single = evaluator_cost(cfg)
    sec.tables.append(table)
    sec.headlines["no compiler"] = (
        f"Without a C compiler (CasADi's evaluator): the same numbers, **{batch:.3g}x** slower per "
        f"sample in batches and **{single:.3g}x** per step of a simulation (medians over robots)")
    sec.headlines["compile"] = (
        f"Compiling {len(cfg.build_robots)} robot(s) from scratch (every flavour a first use "
        f"builds): **{all_c.median:.3g} s** [{all_c.min:.3g}-{all_c.max:.3g}] in total; per "
        f"robot up to {max(per_robot.values()):.3g} s ({max(per_robot, key=per_robot.get)})")
    return sec
