"""Section 3b: what the actuator terms cost, from the description to the compiled call.

Pairs, each robot derived in this run by the working tree's ``derive`` from its description into
a temporary folder (``generated/`` is neither read nor written) and compiled into a temporary
``PLANAR_SYM_CACHE``:

* **tree**: ``serial_2dof`` (built in, ideal torque sources) against
  ``tests/robots/actuated_2dof.toml`` (the same arm; joint 1: gearbox, rotor, viscous and
  Coulomb friction, limits; joint 2: gearbox and rotor);
* **closed chain**: ``five_bar_type1`` against ``five_bar_type1_actuated``, a copy written here
  with a ``[joints.actuator]`` table (gear_ratio 50, rotor_inertia 0.5 kg*mm^2,
  viscous_friction 0.01 N*m*s/rad, coulomb_friction 0.02 N*m) on its actuated joints A and E.

Measured, every figure as actuated over plain in the same interleaved rounds:

* **derive**: ``python -m derive DESCRIPTION --out TMP``, one robot per fresh subprocess (in one
  process the first robot pays SymPy's warm-ups, which would favour whichever comes second).
  In-process: the span derive itself times (``derived NAME in X s``: reading the description,
  SymPy derivation, CasADi C generation; **C compilation excluded**, imports excluded), read at
  full resolution by wrapping ``derive.__main__.derive_robot``; wall: the whole subprocess
  (interpreter start and imports included, still no C compilation);
* **generated C**: bytes of ``<robot>.c`` (CasADi's per-sample functions) and
  ``<robot>_simd.c`` (the vectorised sample loops);
* **compile**: ``library.build`` plus ``library.build_simd`` forced into a fresh cache, what a
  first ``load`` adds to the derivation;
* **per sample**, public API, N = 1e4: ``inverse_dynamics`` and ``forward_dynamics`` (tree;
  uniform random states as in section 1, torques uniform in [-1, 1] N*m),
  ``closed_chain_inverse_dynamics`` and its tree part ``tree_inverse_dynamics`` (five-bar; the
  joint motion of ``five_bar_type1_move_x`` from the inverse kinematics, which closes the loops
  of both robots: the actuator tables change no geometry).

Gate before timing: with the rotor inertias and friction coefficients zeroed (parameters
``jm_*``, ``fv_*``, ``fc_*``) the actuated robot reproduces the plain one's results to 1e-9, so
the two robots of a pair differ by the actuator terms only.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import tomllib
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from . import Config
from .inverse import GATE, closed_states, rel_err, serial_states
from .report import Check, Section, Table
from .timing import Ratio, Stats, interleaved, once_each, ratio

ROOT = Path(__file__).resolve().parent.parent
#: the table added to the closed chain's actuated joints (the description's units: inertia in
#: kg*mm^2, as five_bar_type1.toml declares)
ACTUATOR = {"gear_ratio": 50, "rotor_inertia": 0.5, "viscous_friction": 0.01,
            "coulomb_friction": 0.02}
CLOSED_JOINTS = ("A", "E")
ZEROED = ("jm_", "fv_", "fc_")  # rotor inertia, viscous and Coulomb friction parameters
PAIR_LABEL = {"tree": "2-DOF arm (tree)", "closed": "five-bar (closed chain)"}


def actuated_copy(src: Path, folder: Path, joints: tuple[str, ...] = CLOSED_JOINTS,
                  table: dict[str, float] = ACTUATOR) -> Path:
    """``<name>_actuated.toml`` in ``folder``: the description ``src`` with ``table`` as the
    ``[joints.actuator]`` of each joint in ``joints`` and its name changed to the file stem."""
    text = src.read_text()
    name = tomllib.loads(text)["name"]
    new = f"{name}_actuated"
    text, count = re.subn(rf'(?m)^name = "{re.escape(name)}"', f'name = "{new}"', text, count=1)
    if count != 1:
        raise RuntimeError(f"{src}: no top-level name = {name!r} line to rename")
    body = "[joints.actuator]\n" + "".join(f"{k} = {v}\n" for k, v in table.items())
    blocks = re.split(r"(?m)^(?=\[)", text)  # each piece starts at a table header
    for i, block in enumerate(blocks):
        found = re.search(r'(?m)^name = "([^"]+)"', block)
        if block.startswith("[[joints]]") and found and found.group(1) in joints:
            blocks[i] = block.rstrip("\n") + "\n" + body + "\n"
    out = folder / f"{new}.toml"
    out.write_text("".join(blocks))
    data = tomllib.loads(out.read_text())
    got = {j["name"]: j.get("actuator") for j in data["joints"]}
    if data["name"] != out.stem or any((got[j] == table) != (j in joints) for j in got):
        raise RuntimeError(f"{out}: the actuator tables did not land on joints {joints}")
    return out


@contextmanager
def _cache(folder: Path):
    """``PLANAR_SYM_CACHE`` pointing at ``folder`` (restored afterwards)."""
    old = os.environ.get("PLANAR_SYM_CACHE")
    os.environ["PLANAR_SYM_CACHE"] = str(folder)
    try:
        yield
    finally:
        if old is None:
            del os.environ["PLANAR_SYM_CACHE"]
        else:
            os.environ["PLANAR_SYM_CACHE"] = old


#: ``python -m derive`` with derive's per-robot span (``derive_robot``: read, derive, render C;
#: the very call derive times and prints to 10 ms) reported at full resolution
DERIVE = """\
import sys, time
import derive.__main__ as m
inner = getattr(m, "derive_robot", None)
if inner is not None:
    def derive_robot(robot, *args):
        t0 = time.perf_counter()
        out = inner(robot, *args)
        print(f"derive_robot {out[0]} {time.perf_counter() - t0!r}", file=sys.stderr)
        return out
    m.derive_robot = derive_robot
sys.exit(m.main(sys.argv[1:]))
"""


def _derive(description: Path, out: Path, inproc: dict[str, list[float]]):
    """A timed ``python -m derive DESCRIPTION --out OUT`` in a fresh interpreter; derive's own
    in-process time of the robot is appended to ``inproc[name]``."""
    def run():
        proc = subprocess.run([sys.executable, "-c", DERIVE, str(description), "--out",
                               str(out)], check=False, cwd=ROOT, capture_output=True, text=True)
        if proc.returncode != 0:
            raise RuntimeError(f"python -m derive {description} failed:\n{proc.stderr}")
        found = (re.findall(r"derive_robot (\S+) ([0-9.e+-]+)", proc.stderr)
                 or re.findall(r"derived (\S+) in ([0-9.]+) s", proc.stderr))
        if len(found) != 1:
            raise RuntimeError(f"python -m derive {description}: no timing line in\n"
                               f"{proc.stderr}")
        inproc.setdefault(found[0][0], []).append(float(found[0][1]))
    return run


def _compile(folder: Path, rounds: int, keep: Path):
    """A timed forced ``build`` and ``build_simd`` of a derived folder into a fresh cache; the
    last of ``rounds`` calls builds into ``keep`` (then loading from it compiles nothing)."""
    from planar_sym.model import compile as library
    from planar_sym.model.folders import read_manifest

    manifest = read_manifest(folder)
    calls = []

    def run():
        calls.append(1)
        with tempfile.TemporaryDirectory(prefix="planar_sym_cache_") as tmp, _cache(
                keep if len(calls) == rounds else Path(tmp)):
            library.build(folder, manifest, force=True)
            library.build_simd(folder, manifest, force=True)
    return run


def _zeroed(robot):
    return robot.with_parameters(**{p.name: 0.0 for p in robot.parameter_list
                                    if p.name.startswith(ZEROED)})


def _gate(sec: Section, what: str, plain_out, act, zeroed_out) -> None:
    """Zeroed actuator terms reproduce the plain robot; the real ones change the result (a
    benchmark of an actuator table that was silently ignored would time nothing)."""
    sec.checks.append(Check(f"{what} with rotor inertia and friction zeroed vs the plain robot",
                            rel_err(zeroed_out, plain_out), GATE))
    change = rel_err(act, plain_out)
    sec.notes.append(f"{what}: the actuator terms change the result by up to {change:.2g} "
                     "(worst per-sample normwise relative change over the gate's samples)")
    if not change > 1e3 * GATE:
        sec.checks.append(Check(f"{what}: actuator terms present (relative change "
                                f"{change:.2g}, must exceed {1e3 * GATE:g}; error shown as "
                                "its inverse)", 1.0 / max(change, 1e-300), 1.0 / (1e3 * GATE)))


def _tree_timing(cfg: Config, sec: Section, plain, act, size: int) -> dict[str, Stats]:
    q, qd, qdd = serial_states(plain.n, size)
    tau = np.random.default_rng(2).uniform(-1.0, 1.0, (size, plain.n))
    g = serial_states(plain.n, 256, seed=99)
    gt = np.random.default_rng(98).uniform(-1.0, 1.0, (256, plain.n))
    zero = _zeroed(act)
    _gate(sec, f"{act.name} inverse_dynamics", plain.inverse_dynamics(*g),
          act.inverse_dynamics(*g), zero.inverse_dynamics(*g))
    _gate(sec, f"{act.name} forward_dynamics", plain.forward_dynamics(g[0], g[1], gt),
          act.forward_dynamics(g[0], g[1], gt), zero.forward_dynamics(g[0], g[1], gt))
    fns = {("inverse_dynamics", "plain"): lambda: plain.inverse_dynamics(q, qd, qdd),
           ("inverse_dynamics", "actuated"): lambda: act.inverse_dynamics(q, qd, qdd),
           ("forward_dynamics", "plain"): lambda: plain.forward_dynamics(q, qd, tau),
           ("forward_dynamics", "actuated"): lambda: act.forward_dynamics(q, qd, tau)}
    return interleaved(fns, repeats=cfg.repeats, per=size, min_block_s=cfg.min_block_s)


def _closed_timing(cfg: Config, sec: Section, plain, act, size: int) -> dict[str, Stats]:
    q, qd, qdd = closed_states(plain, size)
    g = closed_states(plain, 256)
    zero = _zeroed(act)
    ref, got, off = (np.hstack(r.closed_chain_inverse_dynamics(*g)) for r in (plain, act, zero))
    _gate(sec, f"{act.name} closed_chain_inverse_dynamics (tau, lambda)", ref, got, off)
    fns = {("closed_chain_inverse_dynamics", "plain"):
           lambda: plain.closed_chain_inverse_dynamics(q, qd, qdd),
           ("closed_chain_inverse_dynamics", "actuated"):
           lambda: act.closed_chain_inverse_dynamics(q, qd, qdd),
           ("tree_inverse_dynamics", "plain"): lambda: plain.tree_inverse_dynamics(q, qd, qdd),
           ("tree_inverse_dynamics", "actuated"): lambda: act.tree_inverse_dynamics(q, qd, qdd)}
    return interleaved(fns, repeats=cfg.repeats, per=size, min_block_s=cfg.min_block_s)


def _fmt_n(n: int) -> str:
    return f"1e{int(np.log10(n))}" if n >= 1000 and 10 ** int(np.log10(n)) == n else str(n)


def _r(r: Ratio) -> str:
    return f"**{r.median:.3g}x** [{r.min:.3g}-{r.max:.3g}]"


def run(cfg: Config) -> Section:
    from planar_sym import load
    from planar_sym.model.description.reader import resolve

    sec = Section("actuators", "3b. Actuator terms: derivation and compiled cost",
                  __doc__.split("\n\n", 1)[1])
    size = cfg.actuator_samples
    with tempfile.TemporaryDirectory(prefix="planar_sym_actuators_") as tmp:
        work = Path(tmp)
        pairs: dict[str, tuple[Path, Path]] = {}
        if "tree" in cfg.actuator_pairs:
            pairs["tree"] = (resolve("serial_2dof"), ROOT / "tests" / "robots"
                             / "actuated_2dof.toml")
        if "closed" in cfg.actuator_pairs:
            plain = resolve("five_bar_type1")
            pairs["closed"] = (plain, actuated_copy(plain, work))
        names = {k: tuple(tomllib.loads(p.read_text())["name"] for p in v)
                 for k, v in pairs.items()}
        out, cache = work / "derived", work / "cache"
        cache.mkdir()

        inproc: dict[str, list[float]] = {}
        fns = {names[k][i]: _derive(pairs[k][i], out, inproc) for k in pairs for i in (0, 1)}
        wall = once_each(fns, repeats=cfg.actuator_rounds)
        derive = {n: Stats(tuple(v)) for n, v in inproc.items()}
        dt = Table(f"`python -m derive DESCRIPTION` (one robot per fresh subprocess, "
                   f"{cfg.actuator_rounds} interleaved round(s); no C compilation); "
                   "ratio = actuated / plain in the same round",
                   ["pair", "robot", "derivation in-process", "ratio", "subprocess wall",
                    "ratio"])
        for k, (p, a) in names.items():
            dt.add(PAIR_LABEL[k], p, derive[p], "1", wall[p], "1")
            dt.add(PAIR_LABEL[k], a, derive[a], ratio(derive[a], derive[p]), wall[a],
                   ratio(wall[a], wall[p]))
        sec.tables.append(dt)

        folders = {n: out / n for pair in names.values() for n in pair}
        st = once_each({n: _compile(f, cfg.actuator_rounds, cache) for n, f in folders.items()},
                      repeats=cfg.actuator_rounds)
        ct = Table(f"Generated C and its compilation (forced `build` + `build_simd` into a fresh "
                   f"cache, {cfg.actuator_rounds} interleaved round(s)); ratios = actuated / plain",
                   ["pair", "robot", "`<robot>.c`", "ratio", "`<robot>_simd.c`", "ratio",
                    "compile", "ratio"])
        sizes = {}
        for n, f in folders.items():
            simd = f / f"{n}_simd.c"
            sizes[n] = ((f / f"{n}.c").stat().st_size, simd.stat().st_size if simd.exists()
                        else None)
        for k, (p, a) in names.items():
            for n in (p, a):
                c, s = sizes[n]
                rc = f"{c / sizes[p][0]:.3g}x"
                rs = f"{s / sizes[p][1]:.3g}x" if s and sizes[p][1] else "-"
                ct.add(PAIR_LABEL[k], n, f"{c / 1024:.1f} KiB",
                       "1" if n == p else rc, f"{s / 1024:.1f} KiB" if s else "-",
                       "1" if n == p else rs, st[n],
                       "1" if n == p else ratio(st[n], st[p]))
        sec.tables.append(ct)

        with _cache(cache):
            robots = {n: load(f) for n, f in folders.items()}
        tt = Table(f"Compiled evaluation, public API, N = {_fmt_n(size)} samples: time per "
                   "sample; ratio = actuated / plain in the same rounds",
                   ["pair", "function", "robot", "time per sample", "ratio"])
        timed = {}
        for k, (p, a) in names.items():
            fn = _tree_timing if k == "tree" else _closed_timing
            timed[k] = fn(cfg, sec, robots[p], robots[a], size)
            for what in dict.fromkeys(w for w, _ in timed[k]):
                base = timed[k][(what, "plain")]
                tt.add(PAIR_LABEL[k], f"`{what}`", p, base, "1")
                tt.add(PAIR_LABEL[k], f"`{what}`", a, timed[k][(what, "actuated")],
                       ratio(timed[k][(what, "actuated")], base))
        sec.tables.append(tt)

    for k, (p, a) in names.items():
        t = timed[k]
        per = [f"`{w}` {_r(ratio(t[(w, 'actuated')], t[(w, 'plain')]))}"
               for w in dict.fromkeys(w for w, _ in t)]
        simd = (f", {sizes[a][1] / sizes[p][1]:.3g}x SIMD C" if sizes[a][1] and sizes[p][1]
                else "")
        sec.headlines[f"actuators_{k}"] = (
            f"Actuator terms, {PAIR_LABEL[k]}: `{a}` / `{p}` in the same run: derivation "
            f"{_r(ratio(derive[a], derive[p]))} ({derive[a].median:.3g} s vs "
            f"{derive[p].median:.3g} s in-process, no C compilation), generated C "
            f"{sizes[a][0] / sizes[p][0]:.3g}x{simd}, compile "
            f"{ratio(st[a], st[p]).median:.3g}x; per sample at N = {_fmt_n(size)}: "
            + ", ".join(per))
    return sec
