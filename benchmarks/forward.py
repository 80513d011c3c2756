"""Section 2: forward dynamics, work against precision.

Measured: wall time of a whole 1 s simulation (states at 101 evenly spaced times) against the
error of the final joint angles, max_i |q_i(1 s) - q_ref,i(1 s)| in rad, and the energy drift
max |E(t) - E(0)| / max(|E(0)|, max T) over the 101 states (planar_sym's definition, energies
from planar_sym's compiled ``energy`` for every method). Two problems:

* **S1**: serial_2dof released from q = [-60 deg, 0], zero torque, 1 s;
* **five-bar**: five_bar_type1 released at rest from its drawn pose ``q_drawn``, 1 s.

Methods, each at several settings (atol = rtol / 10 throughout):

* planar_sym ``simulate`` with its default method (named in the details column; closed chains
  projected onto the constraints every 0.1 s);
* planar_sym ``simulate(method="DOP853")``: SciPy's DOP853 driving the compiled right-hand side
  through a Python callback;
* MuJoCo RK4 at fixed steps, a Python loop of ``mj_step`` (S1 only; joint damping and armature
  zero, contacts and constraints disabled; its accelerations are checked against planar_sym's
  first);
* SciPy DOP853 on a pure-numpy right-hand side from SymPy ``lambdify`` of M and h (and Phi_q,
  gamma): the DOP853 route with the compiled functions swapped for uncompiled ones.

All runs of one problem are timed in the same interleaved rounds (runs shorter than the block
time are repeated within a block). The 1e-9 rad level (and a looser 1e-6 rad) is read off each
method's measurements as the cheapest setting that reaches it, and by log-log interpolation
between the two settings of its work-precision front that bracket it.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from . import Config
from .report import Check, Section, Table
from .timing import Ratio, Stats, interleaved, ratio

TARGET = 1e-9
TARGETS = (1e-9, 1e-6)  # the level the issue asks for, and a looser one every method reaches
REF_TOL = 1e-13
DEFAULT = "planar_sym `simulate` (default method)"
SCIPY = "planar_sym `simulate(method=\"DOP853\")` (SciPy, compiled RHS)"


def energy_drift(robot, q, qd) -> float:
    kin, pot = robot.energy(q, qd)
    e = kin + pot
    return float(np.max(np.abs(e - e[0])) / max(abs(e[0]), float(np.max(np.abs(kin))), 1e-300))


class Run:
    """One method at one setting: a timed callable, then its accuracy once (untimed)."""

    def __init__(self, method: str, setting: str, fn):
        self.method, self.setting, self.fn = method, setting, fn
        self.key = f"{method} {setting}"
        self.error = self.drift = math.nan
        self.extra = ""

    def evaluate(self, robot, q_ref_end) -> None:
        q, qd, self.extra = self.fn(final=True)
        self.error = float(np.max(np.abs(q[-1] - q_ref_end)))
        self.drift = energy_drift(robot, q, qd)


def _mujoco_forward_check(robot, mmodel, mdata) -> Check:
    """MuJoCo's accelerations (``mj_forward``, zero force) against planar_sym's, 256 states."""
    import mujoco

    from .inverse import GATE, rel_err, serial_states

    q, qd, _ = serial_states(robot.n, 256, seed=7)
    qacc = np.empty_like(q)
    for k in range(len(q)):
        mdata.qpos[:], mdata.qvel[:] = q[k], qd[k]
        mujoco.mj_forward(mmodel, mdata)
        qacc[k] = mdata.qacc
    ref = robot.forward_dynamics(q, qd, np.zeros_like(q))
    return Check(f"{robot.name}: MuJoCo mj_forward qacc vs planar_sym forward_dynamics (256 "
                 "random states, zero torque)", rel_err(qacc, ref), GATE)


def _problem_runs(cfg: Config, robot, q0, sym, t_eval, with_mujoco: bool,
                  checks: list[Check]) -> list[Run]:
    from planar_sym import simulate

    from .baselines import mujoco_model

    zero = np.zeros(robot.n)
    runs = []
    for label, method, rtols in ((DEFAULT, None, cfg.rtols),
                                 (SCIPY, "DOP853", cfg.numpy_rtols)):
        for rtol in rtols:
            def ps(final=False, rtol=rtol, method=method):
                extra = {"method": method} if method else {}
                sim = simulate(robot, q0, zero, (0.0, 1.0), t_eval=t_eval, rtol=rtol,
                               atol=rtol / 10, **extra)
                drift = (f"; max abs(Phi) {sim.constraint_drift_m:.1e} m"
                         if robot.is_closed_chain else "")
                return sim.q, sim.qd, f"{sim.method}, {sim.n_rhs} RHS calls{drift}"
            runs.append(Run(label, f"rtol {rtol:g}", ps))
    if with_mujoco:
        from planar_sym.model import description

        mmodel, mdata = mujoco_model.build(description.load(robot.name))
        checks.append(_mujoco_forward_check(robot, mmodel, mdata))
        for dt in cfg.mujoco_dts:
            def mj(final=False, dt=dt):
                _, q, qd, used = mujoco_model.simulate_rk4(mmodel, mdata, q0, zero, 1.0, dt)
                return q, qd, f"dt {used:.4g} s, {round(1 / used)} steps"
            runs.append(Run("MuJoCo RK4, Python loop of `mj_step`", f"dt {dt:g}", mj))
    simulate_numpy = sym.simulate_closed if robot.is_closed_chain else sym.simulate_serial
    for rtol in cfg.numpy_rtols:
        def npy(final=False, rtol=rtol):
            q, qd, count = simulate_numpy(q0, zero, 1.0, rtol=rtol, atol=rtol / 10,
                                          t_eval=t_eval)
            return q, qd, f"{count} RHS calls"
        runs.append(Run("SciPy DOP853, numpy RHS (lambdify, uncompiled)", f"rtol {rtol:g}",
                        npy))
    return runs


def _front(runs: list[Run], times: dict[str, Stats]) -> list[Run]:
    """The work-precision front: by median time, each run more accurate than all cheaper."""
    front, best = [], math.inf
    for r in sorted(runs, key=lambda r: times[r.key].median):
        if r.error < best:
            front.append(r)
            best = r.error
    return front


def level(runs: list[Run], times: dict[str, Stats], target: float):
    """(cheapest run reaching ``target`` or None, interpolated per-repeat Stats or None)."""
    ok = [r for r in runs if r.error <= target]
    cheapest = min(ok, key=lambda r: times[r.key].median) if ok else None
    front = _front(runs, times)
    interp = None
    for a, b in itertools.pairwise(front):
        if a.error > target >= b.error:
            w = (math.log(a.error) - math.log(target)) / (math.log(a.error) - math.log(b.error))
            interp = Stats(tuple(math.exp((1 - w) * math.log(x) + w * math.log(y))
                                 for x, y in zip(times[a.key].values, times[b.key].values)))
    if interp is None and front and front[0].error <= target:
        interp = times[front[0].key]
    return cheapest, interp


def problem(cfg: Config, sec: Section, label: str, robot, q0, sym, with_mujoco: bool) -> None:
    from planar_sym import simulate

    t_eval = np.linspace(0.0, 1.0, 101)
    zero = np.zeros(robot.n)
    ref = simulate(robot, q0, zero, (0.0, 1.0), t_eval=t_eval, rtol=REF_TOL, atol=REF_TOL,
                   method="DOP853")
    note = (f"{label} reference: planar_sym `simulate(method=\"DOP853\")`, rtol = atol = "
            f"{REF_TOL:g} "
            f"({ref.n_rhs} RHS calls)")
    if cfg.radau_check:
        check = simulate(robot, q0, zero, (0.0, 1.0), t_eval=t_eval, rtol=1e-12, atol=1e-13,
                         method="Radau")
        note += (f"; Radau (rtol 1e-12, atol 1e-13) agrees with it to "
                 f"{np.max(np.abs(check.q[-1] - ref.q[-1])):.1e} rad at t = 1 s, so errors "
                 "below about that are not resolved")
    q1 = np.array(q0, dtype=float)
    q1[0] += 1e-10
    moved = simulate(robot, q1, zero, (0.0, 1.0), t_eval=t_eval, rtol=REF_TOL, atol=REF_TOL,
                     method="DOP853")
    gain = float(np.max(np.abs(moved.q[-1] - ref.q[-1]))) / 1e-10
    note += (f". Conditioning: moving q1(0) by 1e-10 rad moves q(1 s) by {gain * 1e-10:.1e} rad "
             f"(x{gain:.2g}), so {TARGET:g} rad at t = 1 s needs errors near "
             f"{TARGET / gain:.0e} along the way")
    sec.notes.append(note + ".")
    runs = _problem_runs(cfg, robot, q0, sym, t_eval, with_mujoco, sec.checks)
    for r in runs:
        r.evaluate(robot, ref.q[-1])
    times = interleaved({r.key: r.fn for r in runs}, repeats=cfg.sim_repeats,
                        min_block_s=cfg.min_block_s)
    base = runs[0].key  # planar_sym at the loosest rtol: the shared timing reference
    wp = Table(f"{label}: work-precision (time of a 1 s run; ratio = time / planar_sym default "
               f"at {runs[0].setting}, same round)",
               ["method", "setting", "time", "ratio", "error q(1 s), rad", "energy drift",
                "details"])
    for r in runs:
        wp.add(r.method, r.setting, times[r.key], ratio(times[r.key], times[base]),
               f"{r.error:.1e}", f"{r.drift:.1e}", r.extra)
    sec.tables.append(wp)
    methods = list(dict.fromkeys(r.method for r in runs))
    for target in TARGETS:
        _level_table(sec, label, target, runs, times, methods)


def _level_table(sec: Section, label: str, target: float, runs: list[Run], times, methods):
    at = Table(f"{label}: time to reach {target:g} rad at t = 1 s (ratio = method time / "
               "planar_sym default-method time, same rounds)",
               ["method", "cheapest setting reaching it", "time", "ratio",
                "interpolated time", "ratio (interpolated)"])
    levels = {m: level([r for r in runs if r.method == m], times, target) for m in methods}
    # ratios are to planar_sym's default method, or, if it never reached the level, to the
    # first method that did (said in the table)
    ref_m = next((m for m in methods if levels[m][0] is not None), methods[0])
    ps_cheap, ps_interp = levels[ref_m]
    if ref_m != methods[0]:
        at.title += f"; the default method never reached it: ratios are to {ref_m}"
    for m in methods:
        cheap, interp = levels[m]
        at.add(m, cheap.setting if cheap else "not reached",
               times[cheap.key] if cheap else None,
               ratio(times[cheap.key], times[ps_cheap.key]) if cheap and ps_cheap else None,
               interp, ratio(interp, ps_interp) if interp and ps_interp else None)
    sec.tables.append(at)
    if target != TARGET and label == "S1":
        return  # S1's headlines are at the issue's 1e-9 rad; the looser level is in the table
    if ref_m != methods[0]:
        best = min((r for r in runs if r.method == methods[0]), key=lambda r: r.error)
        sec.headlines[f"fwd_{label}_{target}"] = (
            f"Forward {label} at {target:g} rad: planar_sym `simulate`'s default method did not "
            f"reach it in the settings tried (best: {best.error:.1e} rad at {best.setting})")
    if ps_cheap is None:
        sec.headlines[f"fwd_{label}_{target}"] = (
            f"Forward {label} at {target:g} rad: no method reached it in the settings tried")
        return
    for m in methods[methods.index(ref_m) + 1:]:
        cheap, _ = levels[m]
        key = f"fwd_{label}_{target}_{m}"
        if cheap is None:
            sec.headlines[key] = (f"Forward {label} at {target:g} rad: {m} did not reach it in "
                                  "the settings tried")
            continue
        r: Ratio = ratio(times[cheap.key], times[ps_cheap.key])
        sec.headlines[key] = (
            f"Forward {label} at {target:g} rad (cheapest setting reaching it): {m} "
            f"({cheap.setting}) takes **{r.median:.3g}x** [{r.min:.3g}-{r.max:.3g}] the time of "
            f"{'planar_sym `simulate`' if ref_m == methods[0] else ref_m} "
            f"({ps_cheap.extra.split(',')[0]}, {ps_cheap.setting}, "
            f"{times[ps_cheap.key].median * 1e3:.3g} ms)")


def run(cfg: Config) -> Section:
    from planar_sym import load

    from .baselines.lambdified import SymbolicRobot

    sec = Section("forward", "2. Forward dynamics: work against precision",
                  __doc__.split("\n\n", 1)[1])
    arm = load("serial_2dof")
    problem(cfg, sec, "S1", arm, np.radians([-60.0, 0.0]), SymbolicRobot(arm), True)
    five = load("five_bar_type1")
    problem(cfg, sec, "five-bar", five, five.q_drawn.copy(), SymbolicRobot(five), False)
    return sec
