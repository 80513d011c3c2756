"""Section 3c: how the cost grows with the robot's size, from the description to a torque.
Here: run timing against Pinocchio, growth fits, tables and the section; deriving,
compiling and measuring the generated code of each robot are in ``growth_build.py``.

Robots: the n-link pendulum of ``chains.py`` (every joint actuated) for the sizes of
``Config.growth_sizes`` (2 to 20 links), and the three-loop Jansen linkage
``examples/jansen_linkage.toml`` (7 coordinates, 3 loops, 1 actuated crank). Each robot is
derived, compiled and timed on its own, one after the other (one size at a time: the machine
has few cores and the compiler runs in parallel). Why: the generated code comes from
algorithmic differentiation of the energies of a recursive kinematics, with the sample loops
split into compile units compiled in parallel and ``-O1`` for a very big exact file, so that
deriving, compiling and running grow gently with the number of links; this section measures
that growth and fits its exponents.

* **derive**: ``python -m derive DESCRIPTION --out TMP`` in a fresh subprocess: its wall time,
  and derive's own ``derived NAME in X s`` (description, derivation, C generation; imports and
  compilation excluded). Baseline, same round: a subprocess that only imports what derive
  imports (``sympy``, ``casadi``, ``derive``).
* **first use**: a fresh subprocess with an empty ``PLANAR_SYM_CACHE`` and
  ``PLANAR_SYM_PREBUILT=0`` makes the robot from the derived folder and asks for the torques
  of its tree at the drawn pose: what a user waits for. A robot of one compile group (up to
  ``derive/groups.py``'s ``GROUP_PAST_OPS`` operations: every built-in robot, chains up to
  four links) compiles all its code then; a bigger one only the groups that call needs (one
  function each, the exact library and the loops in parallel). Then a second subprocess on
  the same cache compiles every other group (``Library.build_all``, what ``planar-sym build``
  does): **the other groups**. Wall times of the subprocesses, and the **peak memory of one
  compiler process** over both: ``getrusage(RUSAGE_CHILDREN).ru_maxrss`` (the largest resident
  set of any waited-for descendant: the biggest ``cc1``; two compilers run at once, so the
  machine may hold up to about twice that). Baseline, same round: the first-use subprocess
  again on the now filled cache (interpreter, import and loading without compiling). Derive
  plus first use (both walls) is held against the targets: under 30 s up to 8 links (the
  Jansen linkage, 7 coordinates, too), under 60 s up to 12, under 10 s past 12 (issue 28's
  target at 20 links); peak compiler memory under 300 MiB.
* **generated code**: bytes of ``<name>.c`` (exact, per sample) and ``<name>_simd.c`` (the sample
  loops); the operations of all generated functions (sum of the manifest's per-function
  ``operations``); the loops' compile units (manifest ``compile_units``); the exact
  libraries' optimisation flag (``compile.exact_flags``, per compile group where they
  differ); each function's route (closed form or algorithmic differentiation, +ABA where
  ``M^-1`` is the articulated-body recursion: all functions, then inverse dynamics, mass
  matrix and forward dynamics); and ``equations.txt``: its bytes, and whether it prints the expanded closed forms
  or the structure (the structure report says so).
* **run time per sample**, the public API on N random states (q uniform in [-pi, pi], qd and
  qdd in [-3, 3]): ``inverse_dynamics``, ``mass_matrix`` and ``forward_dynamics`` (with the
  torques of the inverse dynamics). The Jansen linkage: ``closed_chain_inverse_dynamics`` on
  one crank revolution from the drawn pose (``closure.from_actuated``, crank rate and
  acceleration uniform in [-3, 3]; the states are on the loops), ``mass_matrix`` on the same
  q; no forward dynamics (a closed chain is simulated with ``simulate``). Per round each
  function is timed best of a few blocks.
* **baseline**: native Pinocchio (``baselines/pinocchio_native.py``: ``pinocchio::rnea`` in a
  C++ loop over the same states, built once with ``-O3 -march=native``), on the URDF written by
  ``python -m planar_sym export FOLDER --format urdf``; in each round its best pass of as many
  passes, so the ratio Pinocchio / planar_sym is formed per round. Gate before timing: its
  torques match ours to 1e-9 (worst per-sample relative error). Target: at least 10x at every
  n up to 12. The same program times ``pinocchio::crba`` and ``pinocchio::aba`` (fed rnea's
  torques) on inputs packed beforehand, gated too (its mass matrices equal ours, aba gives
  back the accelerations, to 1e-9), against our ``mass_matrix`` and ``forward_dynamics``:
  targets at least 10x and 20x at every n up to 20. crba's timed loop keeps only the last
  matrix, where ours writes every sample's into the (N, n, n) array it returns; the same
  program therefore also times crba writing each matrix out (**crba + store**, into memory
  written before), and we time writing such an array alone (``np.ones``, **store alone**):
  at 20 links that write is most of our time. The Jansen linkage has no URDF (trees only);
  its closed-chain torques are held against the 2-link chain's inverse dynamics, timed again
  in the Jansen linkage's own interleaved rounds so that both sides of the ratio see the same
  load (target at most 10x).
* **growth exponents**: least squares of log(value) on log(n) over the chains from
  ``Config.growth_fit_from`` links (4) on, medians; value ~ n^p, and 2^p per doubling of n.
"""

from __future__ import annotations

import math
import shutil
import statistics
import tempfile
from pathlib import Path

import numpy as np

from . import Config
from .growth_build import ROOT, Robot, _build_rounds, _code, _export_urdf, _robot
from .inverse import GATE, rel_err, serial_states
from .report import Check, Section, Table
from .timing import Stats, _block, calibrate, fmt_ratio, fmt_time, ratio

JANSEN = ROOT / "examples" / "jansen_linkage.toml"
MEMORY_TARGET_B = 300 * 2**20  # one compiler process (issue 28: under 300 MiB at 20 links)
RATIO_TARGET = 10.0
CRBA_TARGET, ABA_TARGET = 10.0, 20.0  # Pinocchio crba / our M, aba / our forward dynamics
JANSEN_TARGET = 10.0  # the Jansen linkage's closed-chain torques / the 2-link chain's


def target_s(n: int) -> float:
    """The derive + first use target for a robot of n links (or coordinates): the older
    targets up to 12 links, issue 28's past them (each function compiles on first use)."""
    return 30.0 if n <= 8 else 60.0 if n <= 12 else 10.0


def _jansen_states(robot, size: int, seed: int = 1):
    """One crank revolution from the drawn pose, on the loops; rates uniform in [-3, 3]."""
    from planar_sym.motion import closure

    base = min(size, 10_000)
    rng = np.random.default_rng(seed)
    act = list(robot.actuated)
    q_act = robot.q_drawn[act] + np.linspace(0.0, 2 * np.pi, base)[:, None]
    jt = closure.from_actuated(robot, np.arange(base, dtype=float), q_act,
                               rng.uniform(-3, 3, (base, len(act))),
                               rng.uniform(-3, 3, (base, len(act))))
    reps = -(-size // base)
    return tuple(np.ascontiguousarray(np.tile(a, (reps, 1))[:size]) for a in (jt.q, jt.qd, jt.qdd))


def _best(fn, number: int, best_of: int) -> float:
    return min(_block(fn, number) / number for _ in range(best_of))


def _time_run(r: Robot, robot, cfg: Config, sec: Section, urdf: Path | None, exe,
              two_link=None) -> None:
    """Per-sample times of ``robot`` (and Pinocchio's); for the Jansen linkage, the 2-link
    chain ``two_link``'s inverse dynamics in the same interleaved rounds (the ratio's
    denominator, so both sides see the same load)."""
    from .baselines import pinocchio_native as pn

    n_s = cfg.growth_samples
    if r.chain:
        q, qd, qdd = serial_states(robot.n, n_s, seed=1)
        tau = robot.inverse_dynamics(q, qd, qdd)
        fns = {"ID": lambda: robot.inverse_dynamics(q, qd, qdd),
               "M": lambda: robot.mass_matrix(q),
               "FD": lambda: robot.forward_dynamics(q, qd, tau),
               # what storing the matrices costs alone: a fresh (N, n, n) array written once
               "store": lambda: np.ones((n_s, robot.n, robot.n))}
    else:
        q, qd, qdd = _jansen_states(robot, n_s)
        fns = {"ID": lambda: robot.closed_chain_inverse_dynamics(q, qd, qdd),
               "M": lambda: robot.mass_matrix(q)}
        if two_link is not None:
            q2, qd2, qdd2 = serial_states(2, n_s, seed=1)
            fns["ID_2link"] = lambda: two_link.inverse_dynamics(q2, qd2, qdd2)
    numbers = {k: calibrate(f, cfg.min_block_s) for k, f in fns.items()}
    pin_ok = False
    if urdf is not None and exe is not None:
        pin_n = min(cfg.growth_pin_samples, n_s)
        got = pn.run(urdf, q[:pin_n], qd[:pin_n], qdd[:pin_n], 1, exe=exe)
        checks = [Check(f"{r.label}: native Pinocchio rnea vs planar_sym inverse_dynamics "
                        f"({pin_n} random states)", rel_err(got["tau"], tau[:pin_n]), GATE),
                  Check(f"{r.label}: native Pinocchio crba vs planar_sym mass_matrix",
                        rel_err(got["M"].reshape(pin_n, -1),
                                robot.mass_matrix(q[:pin_n]).reshape(pin_n, -1)), GATE),
                  Check(f"{r.label}: native Pinocchio aba (fed rnea's torques) vs the "
                        "accelerations it was given", rel_err(got["qdd"], qdd[:pin_n]), GATE)]
        sec.checks.extend(checks)
        pin_ok = all(c.ok for c in checks)
        check = next((c for c in checks if not c.ok), checks[0])
        if not check.ok:
            r.pin_note = (f"**FAIL: Pinocchio disagrees** (worst relative error "
                          f"{check.error:.2e} > {GATE:g}): not timed")
    out: dict[str, list[float]] = {k: [] for k in fns}
    pins: list[float] = []
    rneas: list[float] = []
    crbas: list[float] = []
    stored: list[float] = []
    abas: list[float] = []
    names = list(fns)
    for k in range(cfg.growth_rounds):
        order = names[k % len(names):] + names[:k % len(names)]
        for key in order:
            out[key].append(_best(fns[key], numbers[key], cfg.growth_best_of) / n_s)
        if pin_ok:
            pin_n = min(cfg.growth_pin_samples, n_s)
            got = pn.run(urdf, q[:pin_n], qd[:pin_n], qdd[:pin_n], cfg.growth_best_of, exe=exe)
            pins.append(got["best_ns"] * 1e-9)
            rneas.append(got["rnea_best_ns"] * 1e-9)
            crbas.append(got["crba_best_ns"] * 1e-9)
            stored.append(got["crba_stored_best_ns"] * 1e-9)
            abas.append(got["aba_best_ns"] * 1e-9)
    r.run = {k: Stats(tuple(v)) for k, v in out.items()}
    if pins:
        r.pin, r.pin_rnea = Stats(tuple(pins)), Stats(tuple(rneas))
        r.pin_crba, r.pin_aba = Stats(tuple(crbas)), Stats(tuple(abas))
        r.pin_ratio = ratio(r.pin, r.run["ID"])
        r.crba_ratio = ratio(r.pin_crba, r.run["M"])
        r.pin_crba_stored = Stats(tuple(stored))
        r.crba_stored_ratio = ratio(r.pin_crba_stored, r.run["M"])
        if "FD" in r.run:
            r.aba_ratio = ratio(r.pin_aba, r.run["FD"])


def _pinocchio(cfg: Config):
    """(executable, None) or (None, why not)."""
    if not cfg.growth_pinocchio:
        return None, "not run with --quick (no native Pinocchio build)"
    try:
        from .baselines import pinocchio_native as pn

        return pn.build(), None
    except (RuntimeError, OSError, ImportError) as exc:
        return None, f"native Pinocchio baseline could not be built: {str(exc).splitlines()[0]}"


def fit(ns, values) -> float | None:
    """Exponent p of value ~ n^p, least squares in log-log."""
    pts = [(math.log(n), math.log(v)) for n, v in zip(ns, values) if v and v > 0]
    if len(pts) < 2:
        return None
    x, y = np.array(pts).T
    return float(np.polyfit(x, y, 1)[0])


def _mib(kib: float) -> str:
    return f"{kib / 1024:.0f} MiB"


def _kib(b: float) -> str:
    return f"{b / 1024:.0f} KiB"


def _pf(ok: bool | None) -> str:
    return "-" if ok is None else ("pass" if ok else "**fail**")


def run(cfg: Config) -> Section:
    sec = Section("growth", "3c. Growth with the robot's size", __doc__.split("\n\n", 1)[1])
    exe, why_not = _pinocchio(cfg)
    robots: list[Robot] = []
    two_link = None  # the 2-link chain's robot, timed again beside the Jansen linkage
    with tempfile.TemporaryDirectory(prefix="planar_sym_growth_") as tmp:
        from .chains import write_chain

        jobs = [(f"chain_{n}", n, True, lambda w, n=n: write_chain(n, w))
                for n in cfg.growth_sizes]
        if cfg.growth_jansen:
            jobs.append(("jansen_linkage", 7, False, lambda w: JANSEN))
        for label, n, chain, make in jobs:
            work = Path(tmp) / label
            work.mkdir()
            toml = make(work)
            r = Robot(label, n, chain)
            folder, cache = _build_rounds(r, toml, work, cfg.growth_build_repeats)
            r.code = _code(folder)
            robot = _robot(folder.name, folder, cache)
            urdf = None
            if chain and exe is not None:
                urdf = _export_urdf(toml, folder, cache, work)
            elif not chain:
                r.pin_note = "closed chain: no URDF (trees only)"
            _time_run(r, robot, cfg, sec, urdf, exe, None if chain else two_link)
            if chain and n == 2:
                two_link = robot  # its library stays loaded when its folder is removed
            del robot
            robots.append(r)
            print(f"  growth: {label} done", flush=True)
            shutil.rmtree(work, ignore_errors=True)
    _tables(sec, robots, cfg, why_not)
    return sec


def _tables(sec: Section, robots: list[Robot], cfg: Config, why_not: str | None) -> None:
    reps = cfg.growth_build_repeats
    t = Table(f"Derive and first use, {reps} round(s) per robot; derive's ratio is to the "
              "import-only subprocess of the same round, first use's to the same subprocess "
              "on the filled cache (no compiling) of the same round; the other groups: what "
              "first use left to compile; peak memory is the largest single compiler process "
              "(two run at once)",
              ["robot", "derive (wall)", "ratio", "derive (own timing)",
               "first use: compile (wall)", "ratio", "compile groups", "the other groups (wall)",
               "peak memory of one compiler", "derive + first use", "target", "time", "memory"])
    for r in robots:
        dw, co = Stats(tuple(r.derive_wall)), Stats(tuple(r.compile_wall))
        total = Stats(tuple(a + b for a, b in zip(r.derive_wall, r.compile_wall)))
        goal = target_s(r.n)
        peak = max(r.maxrss_kib)
        t.add(r.label, dw, ratio(dw, Stats(tuple(r.imports))), Stats(tuple(r.derive_own)), co,
              ratio(co, Stats(tuple(r.warm_wall))), str(r.groups), Stats(tuple(r.rest_wall)),
              _mib(peak), total, f"< {goal:.0f} s, < {MEMORY_TARGET_B / 2**20:.0f} MiB",
              _pf(total.median < goal), _pf(peak * 1024 < MEMORY_TARGET_B))
    sec.tables.append(t)

    c = Table("Generated code (routes: closed form CF / algorithmic differentiation AD, over all "
              "functions, then for inverse dynamics, mass matrix, forward dynamics)",
              ["robot", "<name>.c", "<name>_simd.c", "operations", "loop compile units",
               "exact flags", "routes CF / AD", "ID, M, FD", "equations.txt"])
    for r in robots:
        k = r.code
        c.add(r.label, _kib(k["c"]), _kib(k["simd"]), f"{k['ops']:,}", str(k["units"]),
              k["flag"], f"{k['cf']} / {k['ad']}", k["main"],
              f"{_kib(k['eq'])} ({k['eq_kind']})")
    sec.tables.append(c)

    n_s = cfg.growth_samples
    rt = Table(f"Per sample, N = {n_s:,} states, {cfg.growth_rounds} rounds of best-of-"
               f"{cfg.growth_best_of}; ratio: native Pinocchio rnea over our inverse dynamics, "
               f"per round (target >= {RATIO_TARGET:g}x up to 12 links)",
               ["robot", "inverse dynamics", "mass matrix", "forward dynamics",
                "Pinocchio rnea (native loop)", "of which rnea alone", "ratio", "target"])
    for r in robots:
        if r.pin is not None:
            pin, alone, rat = r.pin, r.pin_rnea, r.pin_ratio
            ok = rat.median >= RATIO_TARGET if r.n <= 12 else None
        else:
            pin, alone, rat, ok = r.pin_note or why_not or "-", "-", "-", None
        rt.add(r.label + ("" if r.chain else " (closed_chain_inverse_dynamics, crank turn)"),
               r.run["ID"], r.run["M"], r.run.get("FD", "-"), pin, alone, rat, _pf(ok))
    sec.tables.append(rt)
    mt = Table("Mass matrix and forward dynamics per sample against native Pinocchio on the same "
               "packed inputs (crba; aba fed rnea's torques; their packing is outside the "
               "timing, ours inside), per round; targets: at least "
               f"{CRBA_TARGET:g}x on the mass matrix and {ABA_TARGET:g}x on the forward "
               "dynamics at every n up to 20. crba's loop keeps only the last matrix; "
               "**crba + store** writes every sample's matrix out (into memory written before), "
               "as ours does into the fresh (N, n, n) array it returns; **store alone**: "
               "writing such an array (`np.ones`), the part of ours no algorithm removes",
               ["robot", "mass matrix", "store alone", "Pinocchio crba", "ratio", "target",
                "crba + store", "ratio", "forward dynamics", "Pinocchio aba", "ratio",
                "target"])
    for r in robots:
        if r.pin_crba is None or not r.chain:
            continue
        mt.add(r.label, r.run["M"], r.run["store"], r.pin_crba, r.crba_ratio,
               _pf(r.crba_ratio.median >= CRBA_TARGET), r.pin_crba_stored,
               r.crba_stored_ratio, r.run["FD"], r.pin_aba, r.aba_ratio,
               _pf(r.aba_ratio.median >= ABA_TARGET))
    if mt.rows:
        sec.tables.append(mt)
    if why_not:
        sec.notes.append(why_not)
    jansen = next((r for r in robots if not r.chain), None)
    two = next((r for r in robots if r.chain and r.n == 2), None)
    if jansen is not None and two is not None:
        paired = "ID_2link" in jansen.run  # timed in the Jansen linkage's own rounds
        base = jansen.run["ID_2link"] if paired else two.run["ID"]
        jr = ratio(jansen.run["ID"], base)
        how = ("both timed in the same interleaved rounds" if paired else
               "rounds paired in order, the robots timed one after the other")
        sec.headlines["jansen"] = (
            f"Three loops: the Jansen linkage's `closed_chain_inverse_dynamics` (7 coordinates, "
            f"its loop residuals and Phi_p's condition checked on every sample) takes "
            f"{fmt_time(jansen.run['ID'].median)} a sample, **{fmt_ratio(jr)}** the 2-link "
            f"chain's `inverse_dynamics` ({fmt_time(base.median)}; {how}; target <= "
            f"{JANSEN_TARGET:g}x: {'met' if jr.median <= JANSEN_TARGET else '**not met**'})")
    if any(not r.simd_built for r in robots):
        sec.notes.append("vectorised loops NOT built for: "
                         + ", ".join(r.label for r in robots if not r.simd_built))

    chains = [r for r in robots if r.chain]
    fitted = [r for r in chains if r.n >= cfg.growth_fit_from]
    if len(fitted) < 2:
        fitted = chains
    ns = [r.n for r in fitted]
    span = f"n = {min(ns)}..{max(ns)}" if ns else "-"
    # past size.py's limits a chain derives no closed forms: its every function is AD
    ad = [k for k, r in enumerate(fitted) if r.code["eq_kind"] == "structure"]
    ad_span = (f"n = {fitted[ad[0]].n}..{fitted[ad[-1]].n}" if len(ad) >= 2 else "")
    f = Table(f"Growth exponents p (value ~ n^p), log-log least squares over the chains, {span} "
              "(medians); x per doubling = 2^p; last column: the same fit over the chains whose "
              "report is the structure (no closed forms derived)",
              ["quantity", "p", "x per doubling", f"at n = {min(ns) if ns else '-'}",
               f"at n = {max(ns) if ns else '-'}",
               f"p over {ad_span}" if ad_span else "p, structure only"])
    med = statistics.median
    rows = [
        ("derive, own timing", [med(r.derive_own) for r in fitted], fmt_time),
        ("derive, wall", [med(r.derive_wall) for r in fitted], fmt_time),
        ("first use, wall", [med(r.compile_wall) for r in fitted], fmt_time),
        ("first use, in-process", [med(r.compile_lib) for r in fitted], fmt_time),
        ("the other groups, wall", [med(r.rest_wall) for r in fitted], fmt_time),
        ("peak memory of one compiler", [max(r.maxrss_kib) for r in fitted], _mib),
        ("generated C bytes (.c + _simd.c)", [r.code["c"] + r.code["simd"] for r in fitted],
         _kib),
        ("operations", [r.code["ops"] for r in fitted], lambda v: f"{v:,}"),
        ("equations.txt bytes", [r.code["eq"] for r in fitted], _kib),
        ("inverse dynamics per sample", [r.run["ID"].median for r in fitted], fmt_time),
        ("mass matrix per sample", [r.run["M"].median for r in fitted], fmt_time),
        ("forward dynamics per sample", [r.run["FD"].median for r in fitted], fmt_time),
    ]
    if all(r.pin is not None for r in fitted) and fitted:
        rows.append(("Pinocchio rnea (native) per sample", [r.pin.median for r in fitted],
                     fmt_time))
    exps, exps_ad = {}, {}
    for what, vals, fmt in rows:
        p = fit(ns, vals)
        q = fit([ns[k] for k in ad], [vals[k] for k in ad]) if ad_span else None
        exps[what], exps_ad[what] = p, q
        f.add(what, "-" if p is None else f"{p:.2f}", "-" if p is None else f"{2 ** p:.2f}x",
              fmt(vals[0]) if vals else "-", fmt(vals[-1]) if vals else "-",
              "-" if q is None else f"{q:.2f}")
    sec.tables.append(f)
    mixed = sorted({r.n for r in fitted if r.code["eq_kind"] != "structure"})
    if ad_span and mixed:
        sec.notes.append(
            f"n = {', '.join(map(str, mixed))} also derives the expanded closed forms (its "
            "report prints them; derive/size.py), the larger chains only the structure: the "
            f"{span} fit of derive time and report size spans that switch (hence a small or "
            f"negative exponent); the last column fits {ad_span} alone")

    big = max(chains, key=lambda r: r.n) if chains else robots[-1]
    total = Stats(tuple(a + b for a, b in zip(big.derive_wall, big.compile_wall)))
    goal = target_s(big.n)
    derive_x = ratio(Stats(tuple(big.derive_wall)), Stats(tuple(big.imports)))
    rest = Stats(tuple(big.rest_wall))
    text = (f"Growth: the {big.n}-link pendulum derives and gives its first torques in "
            f"**{total.median:.3g} s** [{total.min:.3g}-{total.max:.3g}] (derive "
            f"{fmt_ratio(derive_x)} an import-only subprocess; target < {goal:.0f} s: "
            f"{'pass' if total.median < goal else '**fail**'}; its {big.groups} compile "
            f"groups compile on first use, the rest in {rest.median:.3g} s more), peak compiler "
            f"memory {_mib(max(big.maxrss_kib))} (target < {MEMORY_TARGET_B / 2**20:.0f} MiB: "
            f"{'pass' if max(big.maxrss_kib) * 1024 < MEMORY_TARGET_B else '**fail**'}); "
            f"inverse dynamics {fmt_time(big.run['ID'].median)} per sample")
    if big.pin_ratio is not None:
        text += f", **{fmt_ratio(big.pin_ratio)}** faster than native Pinocchio rnea"
    if big.crba_ratio is not None and big.aba_ratio is not None:
        text += (f"; mass matrix **{fmt_ratio(big.crba_ratio)}** faster than crba "
                 f"({fmt_ratio(big.crba_stored_ratio)} than crba writing its matrices out; "
                 f"writing the (N, n, n) array alone takes {fmt_time(big.run['store'].median)} "
                 f"of our {fmt_time(big.run['M'].median)}), forward "
                 f"dynamics **{fmt_ratio(big.aba_ratio)}** faster than aba")
    p = {k: exps.get(k) for k in ("derive, own timing", "first use, wall",
                                  "generated C bytes (.c + _simd.c)",
                                  "inverse dynamics per sample")}
    if all(v is not None for v in p.values()):
        text += (f"; growth over {span}: ~n^{p['first use, wall']:.2f} (first use), "
                 f"n^{p['generated C bytes (.c + _simd.c)']:.2f} (code), "
                 f"n^{p['inverse dynamics per sample']:.2f} (inverse dynamics")
        pin = exps.get("Pinocchio rnea (native) per sample")
        text += f"; Pinocchio n^{pin:.2f})" if pin is not None else ")"
        d_ad = exps_ad.get("derive, own timing")
        text += (f", derive n^{d_ad:.2f} over {ad_span} (n^{p['derive, own timing']:.2f} over "
                 f"{span}, across the switch from closed forms)" if d_ad is not None
                 else f", derive n^{p['derive, own timing']:.2f}")
    sec.headlines["growth"] = text
