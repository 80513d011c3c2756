"""Section 5: closed-loop control, the compiled loop against a Python controller.
Here: the timing rounds (the compiled loop, its peers, the free run) and the report
section; the settings, problems and the compiled loop's runs are in ``control_problem.py``,
the SciPy and MuJoCo baselines (the controller in Python) in ``control_peers.py``.

Measured: wall time of a whole tracking run (5 s, states at 501 evenly spaced times) of
``planar_sym.simulate_controlled`` (``dynamics.engine``): the C Dormand-Prince 5(4) evaluating the controller
at every right-hand side (closed chains re-projected onto the loops every 0.1 s), rtol 1e-10,
atol 1e-12. Two laws at a 5 Hz bandwidth w: computed torque (Kp = w^2, Kd = 2 w) and PD +
gravity compensation (the same gains times each actuated joint's effective inertia at the
start). Two problems:

* **S3** ``serial_2dof_cartesian_move``: the 2-DOF arm, a 5 s Cartesian cubic move;
* **S5** ``five_bar_type1_move_x``: the five-bar (4 coordinates, A and E actuated), a 2 s
  move, then held to 5 s.

The reference is the study's joint motion on the actuated joints as quintic Hermite
polynomials (``motion.signals.from_motion``), built once before timing and given to every
method. Baselines, each timed in the same interleaved rounds as the compiled loop:

* (a) SciPy ``solve_ivp(method="DOP853")``, same rtol and atol, on a right-hand side that
  evaluates the same controller in Python around planar_sym's compiled single-sample functions
  (``library.SingleCall``) and the same piecewise polynomials; closed chains as
  ``simulate_closed`` does: the index-1 KKT system, restarted and projected onto the loops
  every 0.1 s. Its state carries the actuator work integral too, as the compiled loop's does,
  so both integrators control the same components.
* (b) MuJoCo RK4 at fixed steps (the model of ``baselines/mujoco_model.py``), the controller
  in Python two ways: a Python loop around ``mj_step`` (the controller evaluated once per step
  and held over it: a sampled-data controller, first order in dt), and MuJoCo's
  ``mjcb_control`` callback (evaluated at every RK4 stage). S3: PD + gravity from planar_sym's
  compiled gravity; computed torque from MuJoCo's own ``mj_fullM`` and ``qfrc_bias``. S5: the
  cut joint C as a ``connect`` equality constraint between two sites (soft: solimp 0.9999,
  solref time constant 2 dt, the stiffest MuJoCo allows by default); the controller from
  planar_sym's compiled closed-chain functions. Accuracy: max |q - q_ref| over every coordinate
  and output sample, q_ref from ``simulate_controlled`` at rtol 1e-13, atol 1e-14. "Equal
  accuracy" is the compiled loop's own error at the benchmark tolerance; each method's time at
  that level (and at a looser 1e-5 rad) is read off its work-precision front by log-log
  interpolation, as in section 2.
* (c) the zero-torque C path ``planar_sym.simulate`` (free motion from the same start, same
  grid, rtol and atol): what the controller adds to the plain forward dynamics. A free swing
  and a tracked motion take different numbers of steps, so the time per right-hand-side
  evaluation (whole call / RHS count) is given as well.
"""

from __future__ import annotations

import math
import time

import numpy as np

from . import Config
from .control_peers import MujocoPlant, PyController, mujoco_run, scipy_run
from .control_problem import (
    ATOL,
    CALLBACK,
    FIXED_S,
    GATE_REF,
    GATE_STATE,
    GATE_TORQUE,
    LAW_NAME,
    LAWS,
    LOOP,
    LOOSE,
    OURS,
    REF_ATOL,
    REF_RTOL,
    RTOL,
    SCIPY,
    STUDIES,
    TARGET_FREE,
    TARGET_SCIPY,
    Problem,
    Settings,
    load_problem,
    make_controller,
    ours,
    settings,
    short_run,
)
from .forward import level
from .inverse import rel_err
from .report import Check, Section, Table
from .timing import Ratio, Stats, _block, calibrate, fmt_time, interleaved, ratio

# -- work-precision runs -------------------------------------------------------------------------

class Run:
    """One method at one setting: its accuracy from one untimed run, then timed."""

    def __init__(self, law: str, method: str, setting: str, fn):
        self.law, self.method, self.setting, self.fn = law, method, setting, fn
        self.key = f"{law} {method} {setting}"
        self.error, self.extra, self.once_s, self.steps_s = math.nan, "", math.nan, math.nan

    def evaluate(self, q_ref: np.ndarray) -> None:
        t0 = time.perf_counter()
        q, self.extra, self.steps_s = self.fn(final=True)
        self.once_s = time.perf_counter() - t0
        self.error = float(np.max(np.abs(q - q_ref)))


def rounds(runs: list[Run], repeats: int, min_block_s: float) -> dict[str, Stats]:
    """``timing.interleaved`` with each block's call count from the untimed run (no second
    calibration run of the slow ones): rotated order, one block per run per round."""
    numbers = {r.key: (calibrate(r.fn, min_block_s) if r.once_s < min_block_s else 1)
               for r in runs}
    out: dict[str, list[float]] = {r.key: [] for r in runs}
    for k in range(repeats):
        order = runs[k % len(runs):] + runs[:k % len(runs)]
        for r in order:
            out[r.key].append(_block(r.fn, numbers[r.key]) / numbers[r.key])
    return {key: Stats(tuple(v)) for key, v in out.items()}


def _extrapolate(runs: list[Run], target: float, soft: bool) -> str:
    """Where a fixed-step method's two finest steps say it would reach ``target`` (not for a
    soft-constrained model, whose compliance changes with the step)."""
    fixed = sorted((r for r in runs if r.steps_s == r.steps_s), key=lambda r: r.steps_s)
    best = min(runs, key=lambda r: r.error)
    text = f"not reached (best {best.error:.1e} rad at {best.setting}"
    if soft:
        return text + ", soft loop constraint: not extrapolated)"
    if len(fixed) < 2:
        return text + ")"
    a, b = fixed[1], fixed[0]  # coarser, finer
    order = math.log(a.error / b.error) / math.log(a.steps_s / b.steps_s)
    if not order > 0.5:
        return text + f", the error stalls as dt shrinks: order {order:.2g})"
    dt = b.steps_s * (target / b.error) ** (1.0 / order)
    return (text + f", order {order:.2g} in dt: about dt {dt:.1g} s, "
            f"~{fmt_time(b.once_s * b.steps_s / dt)} per run)")


# -- the section ---------------------------------------------------------------------------------

def problem(cfg: Config, s: Settings, sec: Section, label: str, study: str) -> None:
    from planar_sym import simulate

    p = load_problem(label, study, s.t_end)
    robot = p.robot
    n = robot.n
    span = f"{p.t_end:g} s"

    def free():
        return simulate(robot, p.q0, p.qd0, (0.0, p.t_end), t_eval=p.t, rtol=RTOL, atol=ATOL)

    free_sim = free()

    def short_free():
        return simulate(robot, p.q0, p.qd0, (0.0, FIXED_S), t_eval=[0.0, FIXED_S], rtol=RTOL,
                        atol=ATOL)

    plant = MujocoPlant(p)
    ta = Table(f"{label} (a): {span} tracking run, compiled loop vs {SCIPY} (rtol {RTOL:g}, "
               f"atol {ATOL:g}; ratio = SciPy time / compiled time, same round)",
               ["law", "compiled loop", "SciPy DOP853", "ratio", "target",
                "RHS calls (compiled / SciPy)", "max abs(q - q_ref), rad (compiled / SciPy)",
                "energy balance residual (compiled)"])
    tc = Table(f"{label} (c): {span} tracking run vs the free zero-torque C path (same "
               "start, grid and tolerances; ratio = controlled / free, same round)",
               ["law", "controlled", "free", "ratio", "target",
                "RHS calls (controlled / free)", "time per RHS (controlled / free)",
                "per-RHS ratio",
                f"fixed cost of a call ({FIXED_S * 1e3:g} ms run; controlled / free)",
                "per-RHS ratio without the fixed cost"])
    wp = Table(f"{label} (b): work-precision of a {span} run (ratio = time / compiled loop at "
               f"rtol {RTOL:g}, same round)",
               ["law", "method", "setting", "time", "ratio", "max abs(q - q_ref), rad",
                "details"])
    lv = Table(f"{label} (b): time to reach an accuracy level (ratio = method time / compiled "
               "loop time at that level, same rounds)",
               ["law", "level, rad", "method", "cheapest setting reaching it", "time", "ratio",
                "interpolated time", "ratio (interpolated)"])
    for law in LAWS:
        ctl = make_controller(p, law)
        name = LAW_NAME[law]
        tight = ours(p, ctl, REF_RTOL, REF_ATOL)
        bench = ours(p, ctl)
        own_error = float(np.max(np.abs(bench.q - tight.q)))
        pyc = PyController(robot, ctl, p.ref)
        # gates, before any timing
        py_tau = np.array([pyc(t, q, qd) for t, q, qd in zip(bench.t_s, bench.q, bench.qd)])
        sec.checks.append(Check(f"{label} {name}: the baselines' Python controller vs the "
                                f"compiled one (tau_cmd at the {len(bench.t_s)} output states)",
                                rel_err(py_tau, bench.tau_cmd), GATE_TORQUE))
        ys, sp_rhs, sp_drift = scipy_run(p, ctl)
        mine = np.concatenate([bench.q[-1], bench.qd[-1], [bench.work_j[-1]]])
        gap = float(np.max(np.abs(ys[-1, :2 * n + 1] - mine)) / max(1.0, np.max(np.abs(mine))))
        sec.checks.append(Check(f"{label} {name}: SciPy baseline's final state (q, qd, work) vs "
                                "the compiled loop's, both at rtol 1e-10 (relative to max(1, "
                                "abs(y)))", gap, GATE_STATE))
        sp_error = float(np.max(np.abs(ys[:, :n] - tight.q)))
        sec.checks.append(Check(f"{label} {name}: SciPy baseline vs the compiled loop's rtol "
                                f"{REF_RTOL:g} reference, max abs(q - q_ref) over the run (rad; "
                                "an independent check of the reference)", sp_error, GATE_REF))
        scipy_ok = gap <= GATE_STATE
        if law == LAWS[0]:
            sec.checks.extend(plant.check(p, bench.q[::10], bench.qd[::10]))
        # (a) and (c): interleaved rounds
        fns = {"ours": lambda ctl=ctl: ours(p, ctl), "free": free,
               "ours_fixed": lambda ctl=ctl: short_run(p, ctl), "free_fixed": short_free,
               "reference": p.build_reference}
        if scipy_ok:
            fns["scipy"] = lambda ctl=ctl: scipy_run(p, ctl)
        times = interleaved(fns, repeats=s.repeats, min_block_s=s.min_block_s)
        drift = (f"; max abs(Phi) {bench.constraint_drift_m:.1e} m / {sp_drift:.1e} m"
                 if robot.is_closed_chain else "")
        if scipy_ok:
            ra = ratio(times["scipy"], times["ours"])
            met = "met" if ra.median >= TARGET_SCIPY else "**not met**"
            ta.add(name, times["ours"], times["scipy"], ra, f">= {TARGET_SCIPY:g}x: {met}",
                   f"{bench.n_rhs} / {sp_rhs}", f"{own_error:.1e} / {sp_error:.1e}{drift}",
                   f"{bench.balance_residual:.1e}")
            sec.headlines[f"ctl_{label}_{law}_a"] = (
                f"Control {label} {name} ({span}, rtol {RTOL:g}): the compiled loop "
                f"({times['ours'].median * 1e3:.3g} ms) is **{ra.median:.3g}x** "
                f"[{ra.min:.3g}-{ra.max:.3g}] faster than {SCIPY} (target >= "
                f"{TARGET_SCIPY:g}x: {met})")
        else:
            ta.add(name, times["ours"], "not timed (gate failed)", None, "-",
                   f"{bench.n_rhs} / {sp_rhs}", f"{own_error:.1e} / {sp_error:.1e}",
                   f"{bench.balance_residual:.1e}")
        rc = ratio(times["ours"], times["free"])
        per = ratio(times["ours"].scaled(1.0 / bench.n_rhs),
                    times["free"].scaled(1.0 / free_sim.n_rhs))
        net = Ratio(tuple(
            ((a - af) / bench.n_rhs) / ((b - bf) / free_sim.n_rhs) for a, af, b, bf in zip(
                times["ours"].values, times["ours_fixed"].values, times["free"].values,
                times["free_fixed"].values)))
        met = "met" if rc.median <= TARGET_FREE else "**not met**"
        tc.add(name, times["ours"], times["free"], rc, f"<= {TARGET_FREE:g}x: {met}",
               f"{bench.n_rhs} / {free_sim.n_rhs}",
               f"{fmt_time(times['ours'].median / bench.n_rhs)} / "
               f"{fmt_time(times['free'].median / free_sim.n_rhs)}", per,
               f"{fmt_time(times['ours_fixed'].median)} / "
               f"{fmt_time(times['free_fixed'].median)}", net)
        sec.headlines[f"ctl_{label}_{law}_c"] = (
            f"Control {label} {name}: a tracking run takes **{rc.median:.3g}x** "
            f"[{rc.min:.3g}-{rc.max:.3g}] the time of the free zero-torque C run (target <= "
            f"{TARGET_FREE:g}x: {met}; {bench.n_rhs} vs {free_sim.n_rhs} RHS calls; per RHS "
            f"evaluation **{per.median:.3g}x** [{per.min:.3g}-{per.max:.3g}], "
            f"{net.median:.3g}x without the fixed cost of a call)")
        rb = ratio(times["reference"], times["ours"])
        if law == LAWS[0]:
            sec.notes.append(
                f"{label}: building the reference from the joint motion "
                f"(`from_motion`, {len(p.ref.knots_s) - 1} segments, closed-form quintic Hermite) takes "
                f"{times['reference'].median * 1e3:.3g} ms, {rb.median:.3g}x the compiled "
                f"{name} run; it is built once, outside the timed runs. "
                "`simulate_controlled(reference=JointTrajectory)` builds it on every call.")
        # (b): work-precision, ours at several rtols, MuJoCo at several steps
        _mujoco_runs(s, sec, p, plant, ctl, law, pyc, tight, own_error, wp, lv)
    sec.tables += [ta, tc, wp, lv]


def _mujoco_runs(s: Settings, sec: Section, p: Problem, plant: MujocoPlant, ctl, law: str,
                 pyc: PyController, tight, own_error: float, wp: Table, lv: Table) -> None:
    robot = p.robot
    name = LAW_NAME[law]
    runs: list[Run] = []
    for rtol in s.ours_rtols:
        def run_ours(final=False, rtol=rtol):
            r = ours(p, ctl, rtol, rtol * ATOL / RTOL)
            drift = (f"; max abs(Phi) {r.constraint_drift_m:.1e} m"
                     if robot.is_closed_chain else "")
            return r.q, f"{r.n_rhs} RHS calls{drift}", math.nan
        runs.append(Run(law, OURS, f"rtol {rtol:g}", run_ours))
    for method, dts, cb in ((LOOP, s.loop_dts[p.label], False),
                            (CALLBACK, s.cb_dts[p.label], True)):
        for dt in dts:
            def run_mj(final=False, dt=dt, cb=cb):
                q, steps, h = mujoco_run(plant, p, ctl, pyc, dt, cb)
                extra = f"{steps} steps"
                if robot.is_closed_chain:
                    extra += (f"; max abs(Phi) {np.max(np.abs(robot.constraint(q))):.1e} m "
                              f"(solref {2 * h:g} s)")
                return q, extra, h
            runs.append(Run(law, method, f"dt {dt:g}", run_mj))
    for r in runs:
        r.evaluate(tight.q)
    times = rounds(runs, s.mj_repeats, s.min_block_s)
    base = next(r for r in runs if r.method == OURS and r.setting == f"rtol {RTOL:g}")
    for r in runs:
        wp.add(name, r.method, r.setting, times[r.key], ratio(times[r.key], times[base.key]),
               f"{r.error:.1e}", r.extra)
    by_method = {m: [r for r in runs if r.method == m] for m in (OURS, LOOP, CALLBACK)}
    parts = []
    for target in (own_error, LOOSE):
        ps_cheap, ps_interp = level(by_method[OURS], times, target)
        for method, mruns in by_method.items():
            cheap, interp = level(mruns, times, target)
            soft = method != OURS and robot.is_closed_chain
            setting = cheap.setting if cheap else _extrapolate(mruns, target, soft)
            lv.add(name, f"{target:.1e}", method, setting,
                   times[cheap.key] if cheap else None,
                   ratio(times[cheap.key], times[ps_cheap.key]) if cheap and ps_cheap else None,
                   interp, ratio(interp, ps_interp) if interp and ps_interp else None)
            if method == OURS or (target == LOOSE and method != LOOP):
                continue
            short = "Python loop" if method == LOOP else "`mjcb_control`"
            at = "" if target == own_error else f" at {target:g} rad"
            if interp is not None and ps_interp is not None:
                rr = ratio(interp, ps_interp)
                parts.append(f"{short}{at} **{rr.median:.3g}x** [{rr.min:.3g}-{rr.max:.3g}] "
                             "(interpolated)")
            elif cheap is not None and ps_cheap is not None:
                rr = ratio(times[cheap.key], times[ps_cheap.key])
                parts.append(f"{short}{at} ({cheap.setting}) **{rr.median:.3g}x** "
                             f"[{rr.min:.3g}-{rr.max:.3g}]")
            else:
                parts.append(f"{short}{at}: {_extrapolate(mruns, target, soft)}")
    sec.headlines[f"ctl_{p.label}_{law}_b"] = (
        f"Control {p.label} {name}, MuJoCo RK4 time / compiled loop time at equal accuracy "
        f"({own_error:.1e} rad, the compiled loop's error at rtol {RTOL:g}): "
        + "; ".join(parts))


def run(cfg: Config) -> Section:
    s = settings(cfg)
    sec = Section("control", "5. Closed-loop control: the compiled loop vs a Python controller",
                  __doc__.split("\n\n", 1)[1])
    for label, study in STUDIES:
        problem(cfg, s, sec, label, study)
    sec.notes.append(
        "MuJoCo with the controller in a Python loop around `mj_step` holds each torque over "
        "a step (sampled-data control): its error against the continuous-time reference is "
        "first order in dt whatever the integrator, so the compiled loop's accuracy is out of "
        "its reach (the extrapolated step and run time are in the level tables). The "
        "`mjcb_control` callback evaluates the controller at every RK4 stage and converges "
        "at RK4's order; it is the fair MuJoCo figure at equal accuracy.")
    sec.notes.append(
        "S5 in MuJoCo: the loop is closed by a soft `connect` constraint (impedance 0.9999, "
        "time constant 2 dt), so MuJoCo simulates a slightly compliant five-bar: its error "
        "against the rigid reference includes that compliance, which shrinks with dt but sets "
        "a floor at any one dt (max abs(Phi) in the details column); the levels are not "
        "extrapolated for it. The S5 reference holds its end after the 2 s cubic move, so its "
        "acceleration jumps at t = 2 s; an RK4 step ending there evaluates its last stage on "
        "the held side, and computed torque feeds qdd_r straight into the torque: a "
        "first-order error in dt (checked: over the 2 s move alone, without the hold, the "
        "callback's computed-torque error falls from 1.7e-8 to 4.4e-9 rad from dt 1e-3 to "
        "5e-4, as PD's does). The compiled loop and SciPy step exactly onto t = 2 s.")
    sec.notes.append(
        "(c), where the time goes: the controlled run = its fixed cost per call (setting up "
        "the controller, torques and energies at the outputs: the 'fixed cost' column, a "
        "small part of a 5 s run) + RHS calls x time per RHS. The controlled right-hand side "
        "evaluates the reference polynomials and g(q) (PD) or a whole inverse dynamics "
        "(computed torque) besides the forward dynamics, and carries two more state "
        "components (work, friction) through every stage: on the 2-DOF arm, whose forward "
        "dynamics costs tens of ns, that is more than twice the free RHS; on the five-bar, "
        "where the KKT solve dominates, less. The step counts differ by problem: the tracked "
        "S3 motion takes more steps than S3's free swing, the free S5 fall many more than "
        "the tracked S5 move.")
    sec.notes.append(
        "At loose tolerances the compiled loop's cost is bounded below by the 501 output "
        "times its steps land on; its error there is far below 1e-5 rad, so the 1e-5 rad "
        "ratios overstate what it needs at that level.")
    sec.notes.append(
        "The SciPy baseline of S5 restarts and projects every 0.1 s like the compiled loop "
        "(its drift is in the (a) table); its right-hand side takes Phi_q and gamma for the "
        "computed-torque law from the same `constrained_terms` call as the plant (plant = "
        "model), one fewer pair of calls than the compiled controller makes.")
    return sec
