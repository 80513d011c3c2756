"""Optimal motion against opty (issue 27): minimum-effort rest-to-rest moves of a 2-DOF arm by
``planar_sym.optimal_move`` and by opty (direct collocation on SymPy equations, IPOPT through
cyipopt), on the same robot, end states, duration and objective, refined on the same grids.

* **The problem.** ``horizontal_2dof`` (test robot, no gravity, T = 1 s) and ``serial_2dof``
  (gravity, T = 0.5 s), rest to rest from q = (0, 0) to (pi/2, -pi/2) rad, minimising the
  integral of |tau|^2 dt, no limits, from the same cubic initial guess. ``serial_2dof`` is
  not run at T = 1 s: there the problem has many local minima (the elbow spinning round
  several times, each transcription landing in another one from grid to grid), so the
  optima of different transcriptions are not comparable.
* **opty's equations** are derived here with sympy.physics.mechanics (KanesMethod) from our
  parameters (names and values from ``robot.parameter_list``). Gate: they equal our generated
  inverse dynamics at random states (1e-12, relative).
* **The transcriptions differ.** Ours: accelerations constant per interval (positions and
  rates stepped exactly as a double integrator's), torques from the inverse dynamics at both
  ends of each interval, effort a trapezoid per interval: second order in h. opty integrates
  the first-order equations with node states and node torques: ``midpoint`` (states and
  torques averaged over each interval, second order; effort here the trapezoid of the node
  torques) or ``backward euler`` (the end of each interval, first order; effort the
  rectangle sum of the torques that enter; opty 1.5's ``create_objective_function`` is not
  used: for midpoint its gradient is the trapezoid's while its objective squares the averaged
  torques, so the two disagree). Each converges to the continuous optimum at its own
  order: Richardson from the two finest grids (order 2, 2; backward Euler, pre-asymptotic
  here, from the three finest, its h and h^2 terms eliminated) gives each one's estimate.
  Gate: those estimates agree (1e-4, relative).
* **The solvers differ.** opty gives IPOPT no Hessian, so cyipopt runs IPOPT (Debian's 3.11)
  with a limited-memory BFGS approximation; ours is CasADi's IPOPT with the exact Hessian.
  Both run to tol 1e-10. opty gets user scaling (positions, rates and torques each by the
  largest of their kind in the guess, the objective by the guess's): without it its L-BFGS
  iterations stall (the horizontal arm's torques are 0.01-0.04 N*m) and stop after thousands
  of iterations up to 1e-1 off the optimum, or in another local one. Gate: each opty optimum
  equals the exact optimum of its own transcription (the same NLP solved by CasADi with the
  exact Hessian, 1e-6), so what remains is the discretisation.
* **Times.** Ours: the whole ``optimal_move`` call (building the CasADi problem included).
  opty: ``Problem.solve`` alone, the Problem built beforehand; its one-off code generation and
  C compilation (cached by opty across grids and robots) is reported apart. Time to accuracy:
  the first grid whose objective is within 1e-4 of the continuous optimum (ours
  extrapolated), and that grid's solve time; where no grid is, the grid the error model
  (C h^order from the finest) needs and a time extrapolated as a power of N, marked "model".
"""

from __future__ import annotations

import math
import shutil
import tempfile
import time
from itertools import pairwise
from pathlib import Path

import numpy as np

from . import Config
from .report import Check, Section, Table
from .timing import Stats, fmt_stats, fmt_time, once_each, ratio

ROOT = Path(__file__).resolve().parent.parent
MOVE = (np.array([0.0, 0.0]), np.array([np.pi / 2, -np.pi / 2]))  # rad
#: (label, what ``planar_sym.load`` takes, duration s)
CASES = (("horizontal_2dof", str(ROOT / "tests" / "robots" / "horizontal_2dof.toml"), 1.0),
         ("serial_2dof", "serial_2dof", 0.5))
GRIDS = (50, 100, 200, 400)
METHODS = ("midpoint", "backward euler")
ORDER = {"ours": 2, "midpoint": 2, "backward euler": 1}
#: Richardson levels: first order is pre-asymptotic on these grids (observed 0.75 on
#: serial_2dof), so its h^2 term is eliminated too, from the three finest grids
LEVELS = {"ours": 1, "midpoint": 1, "backward euler": 2}
ACCURACY = 1e-4  # relative, of the continuous optimum
IPOPT = {"tol": 1e-10, "acceptable_tol": 1e-10, "max_iter": 3000, "print_level": 0, "sb": "yes"}
#: the parameters the equations below use, in ``robot.parameter_list``'s names
PARAMETERS = ("g", "m_link1", "izz_link1", "cgx_link1", "m_motor2", "izz_motor2", "m_link2",
              "izz_link2", "cgx_link2", "px_link1_CS2")


# -- opty's side: the equations, the problem, the solve -------------------------------------------

def two_link_equations():
    """The 2R arm (link1 from the ground, a point motor welded at its tip, link2 from there,
    each centre of gravity on its link's x axis, q2 relative, gravity along -y) by
    sympy.physics.mechanics' KanesMethod. Returns ``(states, inputs, params, eom, tau)``:
    states (q1, q2, u1, u2) and inputs (T1, T2) as functions of time, the parameter symbols
    (named as in ``PARAMETERS``), the implicit first-order equations ``eom`` (4, 1) = 0 that
    opty takes, and ``tau`` (2, 1): the inverse dynamics in q, u and the symbols ``ud1``,
    ``ud2`` (the accelerations)."""
    import sympy as sm
    import sympy.physics.mechanics as me

    q1, q2, u1, u2, T1, T2 = me.dynamicsymbols("q1 q2 u1 u2 T1 T2")
    g, m1, i1, c1, mm, im, m2, i2, c2, a1 = params = sm.symbols(PARAMETERS)
    ground = me.ReferenceFrame("N")
    f1 = ground.orientnew("A", "Axis", (q1, ground.z))
    f2 = f1.orientnew("B", "Axis", (q2, f1.z))
    f1.set_ang_vel(ground, u1 * ground.z)
    f2.set_ang_vel(f1, u2 * ground.z)
    origin = me.Point("O")
    origin.set_vel(ground, 0)
    cg1 = origin.locatenew("G1", c1 * f1.x)
    cg1.v2pt_theory(origin, ground, f1)
    elbow = origin.locatenew("E", a1 * f1.x)
    elbow.v2pt_theory(origin, ground, f1)
    cg2 = elbow.locatenew("G2", c2 * f2.x)
    cg2.v2pt_theory(elbow, ground, f2)
    bodies = [me.RigidBody("link1", cg1, f1, m1, (me.inertia(f1, 0, 0, i1), cg1)),
              me.RigidBody("motor2", elbow, f1, mm, (me.inertia(f1, 0, 0, im), elbow)),
              me.RigidBody("link2", cg2, f2, m2, (me.inertia(f2, 0, 0, i2), cg2))]
    loads = [(cg1, -m1 * g * ground.y), (elbow, -mm * g * ground.y), (cg2, -m2 * g * ground.y),
             (f1, (T1 - T2) * ground.z), (f2, T2 * ground.z)]
    kane = me.KanesMethod(ground, [q1, q2], [u1, u2], kd_eqs=[q1.diff() - u1, q2.diff() - u2])
    kane.kanes_equations(bodies, loads)
    x = sm.Matrix([q1, q2, u1, u2])
    eom = kane.mass_matrix_full * x.diff(me.dynamicsymbols._t) - kane.forcing_full
    ud = sm.Matrix(sm.symbols("ud1 ud2"))
    tau = (kane.mass_matrix * ud - kane.forcing).subs({T1: 0, T2: 0})
    return (q1, q2, u1, u2), (T1, T2), params, eom, tau


def _values(robot) -> list[float]:
    given = {p.name: p.value for p in robot.parameter_list}
    missing = [name for name in PARAMETERS if name not in given]
    if missing:
        raise ValueError(f"{robot.name} is not the 2R arm these equations describe "
                         f"(no {', '.join(missing)})")
    return [float(given[name]) for name in PARAMETERS]


def sympy_inverse_dynamics(robot):
    """``f(q, qd, qdd) -> tau`` (each (2,)) from ``two_link_equations`` with ``robot``'s values."""
    import sympy as sm

    (q1, q2, u1, u2), _, params, _, tau = two_link_equations()
    ud1, ud2 = sm.symbols("ud1 ud2")
    f = sm.lambdify([q1, q2, u1, u2, ud1, ud2, *params], list(tau), "math")
    values = _values(robot)
    return lambda q, qd, qdd: np.array(f(*q, *qd, *qdd, *values), dtype=float)


def equations_error(robot, samples: int = 200, seed: int = 0) -> float:
    """The largest relative difference between the SymPy inverse dynamics and ours at random
    states (|q| <= pi, |qd| <= 5 rad/s, |qdd| <= 50 rad/s^2)."""
    f = sympy_inverse_dynamics(robot)
    rng = np.random.default_rng(seed)
    worst = 0.0
    for _ in range(samples):
        q, qd, qdd = (rng.uniform(-s, s, 2) for s in (np.pi, 5.0, 50.0))
        ours = np.asarray(robot.inverse_dynamics(q, qd, qdd), dtype=float)
        worst = max(worst, float(np.abs(f(q, qd, qdd) - ours).max() / np.abs(ours).max()))
    return worst


def cubic_guess(robot, q0, q1, duration: float, intervals: int):
    """The cubic rest-to-rest move (the one ``optimal_move`` starts from) at the N + 1 nodes:
    q, qd and the inverse-dynamics torques there, each (N + 1, 2)."""
    from planar_sym.optimal.point_to_point import initial_guess

    t, q, qd, _ = initial_guess(q0, q1, intervals, duration)
    s = t / duration
    qdd = ((6 - 12 * s) / duration**2)[:, None] * (np.asarray(q1) - np.asarray(q0))[None, :]
    return q, qd, np.asarray(robot.inverse_dynamics(q, qd, qdd), dtype=float)


def opty_problem(robot, q0, q1, duration: float, intervals: int, method: str, *,
                 cache_dir: str | None = None, scaled: bool = True):
    """opty's Problem for the move on ``intervals`` intervals (N + 1 nodes) with ``method``
    ("midpoint" or "backward euler"); ``cache_dir``: opty's ``tmp_dir`` (its compiled C is
    reused across grids and robots). Returns ``(problem, guess, build_s)``."""
    import sympy.physics.mechanics as me
    from opty import Problem

    (q1s, q2s, u1s, u2s), _, params, eom, _ = two_link_equations()
    n, h = intervals + 1, duration / intervals
    weights = np.ones(n)
    if method == "midpoint":  # the trapezoid of the node torques
        weights[0] = weights[-1] = 0.5
    else:  # backward Euler: the first node's torques enter no equation
        weights[0] = 0.0
    weights = np.concatenate([weights, weights])

    def objective(free):
        return h * float(np.sum(weights * free[4 * n:] ** 2))

    def gradient(free):
        grad = np.zeros_like(free)
        grad[4 * n:] = 2 * h * weights * free[4 * n:]
        return grad

    ends = (q1s.func(0.0) - q0[0], q2s.func(0.0) - q0[1], u1s.func(0.0), u2s.func(0.0),
            q1s.func(duration) - q1[0], q2s.func(duration) - q1[1], u1s.func(duration),
            u2s.func(duration))
    start = time.perf_counter()
    prob = Problem(objective, gradient, eom, [q1s, q2s, u1s, u2s], n, h,
                   known_parameter_map=dict(zip(params, _values(robot))),
                   instance_constraints=ends, integration_method=method,
                   time_symbol=me.dynamicsymbols._t, tmp_dir=cache_dir)
    build_s = time.perf_counter() - start
    for key, value in IPOPT.items():
        prob.add_option(key, value)
    q, qd, tau = cubic_guess(robot, q0, q1, duration, intervals)
    guess = np.concatenate([q[:, 0], q[:, 1], qd[:, 0], qd[:, 1], tau[:, 0], tau[:, 1]])
    if scaled:  # each kind of variable by its largest value in the guess, the objective too
        x_scale = np.concatenate([np.full(2 * n, 1.0 / max(np.abs(v).max(), 1e-9)) for v in (q, qd, tau)])
        prob.add_option("nlp_scaling_method", "user-scaling")
        prob.set_problem_scaling(1.0 / objective(guess), x_scale, None)
    return prob, guess, build_s


def opty_solve(prob, guess, intervals: int) -> dict:
    """Solve; the objective, IPOPT's iterations and status, the node positions (N + 1, 2)."""
    n = intervals + 1
    prob.obj_value.clear()  # opty appends the objective at every iteration
    free, info = prob.solve(guess)
    return {"objective": float(info["obj_val"]), "iterations": len(prob.obj_value) - 1,
            "status": int(info["status"]), "q": free[:2 * n].reshape(2, n).T}


def transcription_optimum(robot, q0, q1, duration: float, intervals: int, method: str) -> float:
    """The exact optimum of opty's transcription ``method`` on the grid: the same NLP (node
    states and torques, the same equations, ends and objective) solved by CasADi's IPOPT with
    the exact Hessian from the same guess, tol 1e-12. The inverse dynamics are ours (the gate
    shows them equal to opty's equations)."""
    import casadi as ca

    f, p = robot.casadi_function("inverse_dynamics"), ca.DM(robot.p)
    N, h = intervals, duration / intervals
    opti = ca.Opti()
    Q, U, R = (opti.variable(2, N + 1) for _ in range(3))
    for k in range(N):
        if method == "midpoint":
            q, u, r = ((X[:, k] + X[:, k + 1]) / 2 for X in (Q, U, R))
        else:
            q, u, r = Q[:, k + 1], U[:, k + 1], R[:, k + 1]
        opti.subject_to((Q[:, k + 1] - Q[:, k]) / h == u)
        opti.subject_to(f(q, u, (U[:, k + 1] - U[:, k]) / h, p) == r)
    for cons in (Q[:, 0] == q0, Q[:, N] == q1, U[:, 0] == 0, U[:, N] == 0):
        opti.subject_to(cons)
    w = np.ones(N + 1)
    if method == "midpoint":
        w[0] = w[-1] = 0.5
    else:
        w[0] = 0.0
    opti.minimize(h * ca.dot(ca.sum1(R**2), ca.DM(w).T))
    q, qd, tau = cubic_guess(robot, q0, q1, duration, intervals)
    for var, val in ((Q, q), (U, qd), (R, tau)):
        opti.set_initial(var, val.T)
    opti.solver("ipopt", {"print_time": False},
                {"print_level": 0, "sb": "yes", "tol": 1e-12, "max_iter": 3000})
    return float(opti.solve().value(opti.f))


# -- convergence ----------------------------------------------------------------------------------

def richardson(grids, values, order: int, levels: int = 1) -> tuple[float, float | None]:
    """The continuous value from the ``levels + 1`` finest grids (each twice the last), the
    error taken as C1 h^order + C2 h^(order + 1) + ... (``levels`` terms eliminated, repeated
    Richardson); and the observed order from the three finest (None with fewer)."""
    if any(b != 2 * a for a, b in pairwise(grids)):
        raise ValueError(f"grids must double: {grids}")
    if len(values) < levels + 1:
        raise ValueError(f"{levels} level(s) need {levels + 1} grids, got {len(values)}")
    column = list(values[-(levels + 1):])
    for k in range(levels):
        factor = 2 ** (order + k) - 1
        column = [b + (b - a) / factor for a, b in pairwise(column)]
    observed = None
    if len(values) >= 3:
        j0, j1, j2 = values[-3:]
        if j1 != j2 and (j0 - j1) / (j1 - j2) > 0:
            observed = math.log2((j0 - j1) / (j1 - j2))
    return column[0], observed


def grid_for(grids, values, reference: float, order: int) -> tuple[int | None, int]:
    """The first grid within ``ACCURACY`` of ``reference``, and the grid the error model
    (C h^order, from the finest) says is needed."""
    errs = [abs(v - reference) / abs(reference) for v in values]
    first = next((g for g, e in zip(grids, errs) if e <= ACCURACY), None)
    needed = math.ceil(grids[-1] * (errs[-1] / ACCURACY) ** (1 / order)) if errs[-1] else 1
    return first, needed


def time_to_accuracy(grids, values, seconds, reference: float, order: int):
    """``(first grid within ACCURACY or None, grid needed by the error model, its solve time,
    whether that time is modelled)``: the time measured on the first grid within, else
    extrapolated from the finest as a power of N fitted to every grid (least squares, log-log)."""
    first, needed = grid_for(grids, values, reference, order)
    if first is not None:
        return first, needed, seconds[grids.index(first)], False
    slope = float(np.polyfit(np.log(grids), np.log(seconds), 1)[0])
    return None, needed, seconds[-1] * (needed / grids[-1]) ** slope, True


def _ours_call(ps, robot, q0, q1, duration, N, out):
    def call():
        mv = ps.optimal_move(robot, q0, q1, duration_s=duration, intervals=N)
        out["ours"] = {"objective": mv.objective, "iterations": mv.solver["iterations"],
                       "status": mv.solver["status"], "q": mv.trajectory.q}
    return call


def _opty_call(method, prob, guess, N, out):
    def call():
        out[method] = opty_solve(prob, guess, N)
    return call


# -- the section ----------------------------------------------------------------------------------

def run(cfg: Config) -> Section:
    sec = Section("opty_peer", "Optimal moves against opty", __doc__.split("\n\n", 1)[1].strip())
    try:
        import opty
    except ImportError:
        sec.notes.append("opty is not installed: pip install opty (it builds cyipopt against "
                         "the system Ipopt: Debian's coinor-libipopt-dev, liblapack-dev, "
                         "libblas-dev and pkg-config)")
        return sec
    import planar_sym as ps

    grids = (50, 100) if cfg.quick else GRIDS
    cases = CASES[:1] if cfg.quick else CASES
    methods = METHODS[:1] if cfg.quick else METHODS
    repeats = 1 if cfg.quick else 3
    series = ("ours",) + methods
    values = Table("Objective on each grid (N intervals; N^2*m^2*s) and its error against the "
                   "continuous optimum (ours extrapolated)",
                   ["robot", "N"] + [f"{s} (error)" for s in series]
                   + [f"{m}: own NLP gap" for m in methods])
    times = Table("Solve time and IPOPT iterations on each grid (ratio: opty's time / ours, "
                  "per round)",
                  ["robot", "N", "ours", "ours iter."]
                  + [c for m in methods for c in (f"opty {m}", "iter.", "ratio")])
    limits = Table("The continuous optimum from each transcription (Richardson) and the grid "
                   "and time to reach it within 1e-4",
                   ["robot", "transcription", "order (observed)", "extrapolated optimum",
                    "gap to ours", "gap (its NLP's exact optima)", "first grid within 1e-4",
                    "grid needed (model)", "solve time there", "vs ours"])
    tables = (values, times, limits)
    builds: dict[str, float] = {}
    cache = tempfile.mkdtemp(prefix="opty_peer_")
    try:
        _cases(ps, sec, cases, grids, methods, repeats, cache, builds, tables)
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    sec.notes.append("opty's first Problem per transcription (SymPy code generation and C "
                     "compilation, then cached): "
                     + ", ".join(f"{m} {fmt_time(b)}" for m, b in builds.items()))
    import cyipopt

    ipopt = ".".join(map(str, getattr(cyipopt, "IPOPT_VERSION", ()))) or "?"
    sec.notes.append(f"opty {opty.__version__}, cyipopt {cyipopt.__version__} on the system's "
                     f"IPOPT {ipopt} (L-BFGS Hessian); ours: CasADi's bundled IPOPT (exact "
                     "Hessian); both with MUMPS")
    sec.tables += list(tables)
    return sec


def _cases(ps, sec, cases, grids, methods, repeats, cache, builds, tables) -> None:
    values, times, limits = tables
    q0, q1 = MOVE
    series = ("ours",) + methods
    for label, source, duration in cases:
        robot = ps.load(source)
        sec.checks.append(Check(f"{label}: SymPy (KanesMethod) inverse dynamics vs ours",
                                equations_error(robot), 1e-12))
        ps.optimal_move(robot, q0, q1, duration_s=duration, intervals=grids[0])  # warm-up
        got = {s: [] for s in series}
        clock: dict[str, list[Stats]] = {s: [] for s in series}
        own_gap = {m: [] for m in methods}
        exact_J = {m: [] for m in methods}
        last_q = {}
        for N in grids:
            probs = {}
            for m in methods:
                probs[m] = opty_problem(robot, q0, q1, duration, N, m,
                                        cache_dir=f"{cache}/{m.replace(' ', '_')}")
                builds.setdefault(m, probs[m][2])  # the first: code generation + compile
            out: dict[str, dict] = {}
            calls = {"ours": _ours_call(ps, robot, q0, q1, duration, N, out)}
            calls.update({m: _opty_call(m, *probs[m][:2], N, out) for m in methods})
            took = once_each(calls, repeats=repeats)
            for s in series:
                got[s].append(out[s])
                clock[s].append(took[s])
            for m in methods:
                exact = transcription_optimum(robot, q0, q1, duration, N, m)
                own_gap[m].append(abs(out[m]["objective"] - exact) / exact)
                exact_J[m].append(exact)
            last_q = {s: out[s]["q"] for s in series}
        J = {s: [g["objective"] for g in got[s]] for s in series}

        def limit(values, s):
            return richardson(grids, values, ORDER[s], LEVELS[s])[0]

        ref, p_ours = richardson(grids, J["ours"], ORDER["ours"], LEVELS["ours"])
        for k, N in enumerate(grids):
            values.add(label, N, *[f"{J[s][k]:.9g} ({(J[s][k] - ref) / ref:+.2e})"
                                   for s in series],
                       *[f"{own_gap[m][k]:.1e}" for m in methods])
            cells = [label, N, fmt_stats(clock["ours"][k]), got["ours"][k]["iterations"]]
            for m in methods:
                it = got[m][k]["iterations"]
                cells += [fmt_stats(clock[m][k]), it if got[m][k]["status"] in (0, 1)
                          else f"{it} (status {got[m][k]['status']})",
                          ratio(clock[m][k], clock["ours"][k])]
            times.add(*cells)
        at = {s: time_to_accuracy(grids, J[s], [c.median for c in clock[s]], ref, ORDER[s])
              for s in series}
        for s in series:
            est, observed = ((ref, p_ours) if s == "ours"
                             else richardson(grids, J[s], ORDER[s], LEVELS[s]))
            first, needed, t, modelled = at[s]
            gap = abs(est - ref) / ref
            limits.add(label, "ours" if s == "ours" else f"opty {s}",
                       f"{ORDER[s]} ({observed:.2f})" if observed else str(ORDER[s]),
                       f"{est:.9g}", "-" if s == "ours" else f"{gap:.1e}",
                       "-" if s == "ours" else f"{abs(limit(exact_J[s], s) - ref) / ref:.1e}",
                       first or f"none up to {grids[-1]}", needed,
                       fmt_time(t) + (" (model)" if modelled else ""),
                       "-" if s == "ours" else f"{t / at['ours'][2]:.3g}x")
            if s == "ours":
                continue
            sec.checks.append(Check(f"{label}: continuous optimum, opty {s} vs ours "
                                    "(Richardson)", gap, ACCURACY))
            sec.checks.append(Check(f"{label}: opty {s} at its own NLP's exact optimum "
                                    f"(worst of N = {', '.join(map(str, grids))})",
                                    max(own_gap[s]), 1e-6))
            dq = float(np.abs(last_q[s] - last_q["ours"]).max())
            sec.notes.append(f"{label}, N = {grids[-1]}: opty {s}'s positions differ from ours "
                             f"by at most {dq:.2e} rad at the nodes")
        reach = {s: (f"N = {at[s][0]}" if at[s][0] else f"N = {at[s][1]} (model)")
                 + f" in {fmt_time(at[s][2])}" + (" (model)" if at[s][3] else "")
                 for s in series}
        mid = "midpoint" if "midpoint" in methods else methods[0]
        sec.headlines[f"effort optimum vs opty, {label}"] = (
            f"{label} (T = {duration:g} s): continuous effort optimum {ref:.6g} N^2*m^2*s, "
            f"within 1e-4 by ours at {reach['ours']}, by opty ({mid}) at {reach[mid]}: "
            f"{at[mid][2] / at['ours'][2]:.3g}x ours; the extrapolated optima agree to "
            f"{abs(limit(J[mid], mid) - ref) / ref:.1e}")
