"""Optimal point-to-point moves by direct collocation: CasADi's Opti and IPOPT on the robot's
generated functions (no SymPy at run time), rest to rest, for trees and closed chains.

On ``N`` intervals of length ``h = T / N`` the accelerations are constant per interval, so the
coordinates that are integrated move exactly as a double integrator's do:

.. code:: text

    q_{k+1} = q_k + h qd_k + h^2/2 qdd_k,   qd_{k+1} = qd_k + h qdd_k
    tau = ID(q, qd, qdd_k) at both ends of interval k, within the limits; |qd_k| <= limits
    minimise  T (objective "time")  or  h sum_k (|tau_k,start|^2 + |tau_k,end|^2) / 2
    (objective "effort", T given: the trapezoid over each interval), or the electrical
    energy h sum_k (P_k,start + P_k,end) / 2 (objective "energy", T given), with the motors'
    power P = sum_j R_j (tau_j / (N_j k_t,j))^2 + tau_j qd_j: the windings' losses and the
    work done, which a regenerative drive takes back where it is negative (each motor's
    torque constant k_t, winding resistance R and gear ratio N from the description)

Evaluating each interval at both ends matters: at one end only, an arm under gravity could
"fall freely" through each sample (zero torque there, any torque between), and the effort
problem has many spurious minima with accelerations of thousands of rad/s^2.

A tree integrates every coordinate; a passive joint's torque is held at 0 on average over
each interval (its values at the two ends cancel: held at one end only, the plan's passive
joint would be first-order accurate in h, and a cart-pole's plan 14 % off its own dynamics
at 100 intervals); a closed chain
integrates its actuated coordinates, and its passive ones are unknowns held on the loops at
every node (``Phi = 0``, ``Phi_q qd = 0``, ``Phi_q qdd = gamma`` from the generated
closed-chain inverse dynamics). The torque limits hold at the nodes.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError, SimulationError
from ..model.robot import Robot
from ..motion.profiles import JointTrajectory
from .ends import move_ends
from .limits import description_speed_limits, speed_limits, torque_limits

OBJECTIVES = ("time", "effort", "energy")
#: durations tried (1 s, doubling) for a first move within the limits when the fastest move
#: cannot be found from a cubic
WARM_TRIES = 6


@dataclass(frozen=True)
class OptimalMove:
    """The solution: ``trajectory`` at the ``N + 1`` nodes (times ``t_s`` (N + 1,) in s;
    ``q``, ``qd``, ``qdd`` each of shape (N + 1, n), ``qdd`` the interval's constant
    acceleration, the last node repeating the last interval's), ``tau`` (N + 1, actuated)
    N*m (N at a slider) there (each interval's start; the last node: the last interval's
    end: the plan's own torques, first order in the interval against the continuous optimum,
    whose peak is higher by about half an interval's change: a cart's least-effort peak
    2.4 % low at 40 intervals, 1.2 % at 80), ``duration_s``, ``objective`` (s for "time", N^2*m^2*s for "effort", J for
    "energy"; "effort" sums each interval's trapezoid of the torques at both its ends, of
    which ``tau`` keeps the starts: recomputed from ``tau`` alone it differs), and IPOPT's
    report ``solver``: iterations, status, the largest constraint violation, the last solve's
    time and the whole search's ``total_time_s`` (s)."""

    trajectory: JointTrajectory
    tau: np.ndarray
    duration_s: float
    objective: float
    solver: dict

    def sampled_at(self, robot: Robot, t) -> JointTrajectory:
        """The move at times ``t`` (N,) in s, clipped to it: exact on its constant-acceleration
        intervals, q, qd, qdd each (N, n) in rad, rad/s, rad/s^2 (m at a slider); a closed
        chain's passive joints from the loops (``from_actuated``), in the mode of the first
        node of the first sample's interval."""
        jt = self.trajectory
        t = np.clip(np.asarray(t, dtype=float), jt.t_s[0], jt.t_s[-1])
        k = np.clip(np.searchsorted(jt.t_s, t, side="right") - 1, 0, len(jt.t_s) - 2)
        dt = (t - jt.t_s[k])[:, None]
        acc = jt.qdd[k]
        q = jt.q[k] + jt.qd[k] * dt + acc * dt**2 / 2
        qd = jt.qd[k] + acc * dt
        if not robot.is_closed_chain:
            return JointTrajectory(t, q, qd, acc, jt.solver)
        from ..motion.closure import from_actuated

        act = list(robot.actuated)
        return from_actuated(robot, t, q[:, act], qd[:, act], acc[:, act], q_guess=jt.q[k[0]])


def optimal_move(robot: Robot, q_start, q_end, *, objective: str = "effort",
                 duration_s: float | None = None, torque_limit=None, speed_limit=None,
                 intervals: int = 40) -> OptimalMove:
    """The best rest-to-rest move from ``q_start`` to ``q_end`` (every coordinate of a tree;
    a closed chain's actuated coordinates, or every one on the loops), rad (m at a slider).

    ``objective``: "time" (needs ``torque_limit``), "effort" or "energy" (need
    ``duration_s``; "energy": each motor's ``torque_constant`` and ``winding_resistance``);
    ``torque_limit`` (actuated,) N*m (N), default the description's where it gives one
    (joint or motor through the gear: ``optimal.limits``); ``speed_limit`` (n,) rad/s (m/s),
    default the description's motor speed limits, if any; ``intervals``: the grid.

    Raises InputError for a bad request, SimulationError when IPOPT finds no solution.
    """
    if objective not in OBJECTIVES:
        raise InputError(f"objective must be one of {', '.join(OBJECTIVES)} (got {objective!r})")
    if not isinstance(intervals, (int, np.integer)) or not 2 <= intervals <= 10_000:
        raise InputError(f"intervals must be an integer from 2 to 10000 (got {intervals!r})")
    n, act, closed = robot.n, list(robot.actuated), robot.is_closed_chain
    lim = torque_limits(robot, torque_limit, (
        f"{robot.name}: objective \"time\" needs torque_limit (the description gives none for "
        "every actuator): one per actuated joint, N*m") if objective == "time" else None)
    if objective in ("effort", "energy") and (duration_s is None or not duration_s > 0):
        raise InputError(f"objective {objective!r} needs duration_s > 0 (s)")
    if objective == "time" and duration_s is not None:  # it was ignored without a word
        raise InputError(f"objective 'time' finds the duration: leave duration_s out (got "
                         f"{duration_s!r}), or minimise 'effort' or 'energy' in it")
    # each motor's losses per squared torque, once: refused here if a motor lacks its
    # electrical figures
    copper = copper_losses(robot) if objective == "energy" else None
    own = act if closed else list(range(n))  # the coordinates integrated
    a0, a1 = move_ends(robot, q_start, q_end, own)
    # a closed chain's start given as a pose on its loops: its assembly mode, where the
    # passive joints' first guess starts (else the drawn one's)
    seed = (np.asarray(q_start, dtype=float).ravel() if closed
            and np.size(q_start) == n else None)
    v = (description_speed_limits(robot) if speed_limit is None
         else speed_limits(robot, speed_limit))
    started = time.perf_counter()
    return _timed(_search(robot, a0, a1, objective, duration_s, lim, v, int(intervals), seed,
                          copper), started)


def _timed(move: OptimalMove, started: float) -> OptimalMove:
    """The move with the whole search's time since ``started`` (s) in its report:
    solve_time_s is the last solve's alone (a trial read 0.09 s of a 4 s call)."""
    return replace(move, solver={**move.solver, "total_time_s": time.perf_counter() - started})


def _search(robot: Robot, a0, a1, objective: str, duration_s, lim, v, intervals: int,
            seed, copper=None) -> OptimalMove:
    """The move: from a cubic, or for "time" where that fails, from a move within the limits
    (``copper``: ``copper_losses``, for "energy")."""
    if objective != "time":
        return _within_limits(robot, a0, a1, objective, duration_s, lim, v, int(intervals),
                              seed=seed, copper=copper)
    try:
        return _solve(robot, a0, a1, objective, duration_s, lim, v, int(intervals), seed=seed)
    except SimulationError as first:
        failed = first
    # the fastest move from a cubic guess can fail where the limits ask for a swing (a weak
    # motor and gravity): first any move within them, the least effort over a duration that
    # doubles until one is found, then the fastest from it (no slower than that one)
    duration = 1.0
    for _ in range(WARM_TRIES):
        try:
            warm = _within_limits(robot, a0, a1, "effort", duration, lim, v, int(intervals),
                                  seed=seed)
        except SimulationError:
            duration *= 2.0
            continue
        try:
            return _solve(robot, a0, a1, "time", None, lim, v, int(intervals), warm)
        except SimulationError:
            break
    raise failed


def _within_limits(robot: Robot, a0, a1, objective: str, duration: float, lim, v, N: int,
                   seed=None, copper=None) -> OptimalMove:
    """The best move of ``duration`` (s) by ``objective`` ("effort" or "energy") within the
    limits: from a cubic, or where that fails, from the same move without limits. Raises the
    first SimulationError when neither is found."""
    try:
        return _solve(robot, a0, a1, objective, duration, lim, v, N, seed=seed, copper=copper)
    except SimulationError as first:
        if lim is None and v is None:
            raise
        try:
            free = _solve(robot, a0, a1, objective, duration, None, None, N, seed=seed,
                          copper=copper)
            return _solve(robot, a0, a1, objective, duration, lim, v, N, free, copper=copper)
        except SimulationError:
            raise first from None


def _solve(robot: Robot, a0, a1, objective: str, duration_s, lim, v, N: int,
           warm: OptimalMove | None = None, seed=None, copper=None) -> OptimalMove:
    """One IPOPT solve (see the module docstring); ``warm``: a move to start from (else a
    cubic; ``seed``: a closed chain's start pose, whose assembly mode the cubic's passive
    joints take); ``copper``: ``copper_losses`` (actuated,), for "energy", checked by
    ``optimal_move``. Raises SimulationError when IPOPT finds no solution."""
    import casadi as ca

    n, act, closed = robot.n, list(robot.actuated), robot.is_closed_chain
    own = act if closed else list(range(n))  # the coordinates integrated
    pas = [i for i in range(n) if i not in act]
    p = ca.DM(robot.p)
    copper = None if objective != "energy" else ca.DM(copper)
    opti = ca.Opti()
    T = opti.variable() if objective == "time" else float(duration_s)
    h = T / N
    Qi, Vi = opti.variable(len(own), N + 1), opti.variable(len(own), N + 1)
    Ai = opti.variable(len(own), N)
    Qp = Vp = Ap = Ae = None
    if closed:  # passive accelerations at both ends of each interval: on the loops at each
        m = len(pas)
        Qp, Vp = opti.variable(m, N + 1), opti.variable(m, N + 1)
        Ap, Ae = opti.variable(m, N), opti.variable(m, N)
    # the unknowns' first values: a cubic, or the move to start from
    if warm is None:
        _guess(robot, opti, own, pas, closed, a0, a1, N, Qi, Vi, Ai, Qp, Vp, (Ap, Ae), T,
               duration_s, seed)
    else:
        _warm(opti, warm, own, pas, closed, Qi, Vi, Ai, Qp, Vp, (Ap, Ae), T)

    def full(own_part, pas_part):
        rows = {i: own_part[k] for k, i in enumerate(own)}
        rows.update({i: pas_part[k] for k, i in enumerate(pas)} if closed else {})
        return ca.vertcat(*[rows[i] for i in range(n)])

    opti.subject_to(Qi[:, 1:] == Qi[:, :-1] + h * Vi[:, :-1] + h**2 / 2 * Ai)
    opti.subject_to(Vi[:, 1:] == Vi[:, :-1] + h * Ai)
    opti.subject_to(Qi[:, 0] == a0)
    opti.subject_to(Qi[:, N] == a1)
    opti.subject_to(Vi[:, 0] == 0)
    opti.subject_to(Vi[:, N] == 0)
    f_id = robot.casadi_function("closed_inverse_dynamics" if closed else "inverse_dynamics")

    def torque(node: int, k: int, end: bool):
        """The actuated torques at ``node`` with interval ``k``'s accelerations (a closed
        chain: its passive ones at that end, held on the loops there)."""
        q = full(Qi[:, node], Qp[:, node] if closed else None)
        qd = full(Vi[:, node], Vp[:, node] if closed else None)
        qdd = full(Ai[:, k], (Ae if end else Ap)[:, k] if closed else None)
        if closed:  # each node on the loops once (the last from the last interval's end)
            tau, _, _, phi, phi_v, phi_a = f_id(q, qd, qdd, p)
            once = not end or node == N
            opti.subject_to((ca.vertcat(phi, phi_v, phi_a) if once else phi_a) == 0)
        else:
            every = f_id(q, qd, qdd, p)
            tau = every[act]
            if pas:  # a passive joint of a tree: no torque, on average over the interval
                passive.setdefault(k, []).append(every[pas])
        if lim is not None:
            opti.subject_to(opti.bounded(-lim, tau, lim))
        if v is not None:
            opti.subject_to(opti.bounded(-v, qd, v))
        if copper is not None:  # the motors' electrical power there
            powers.append(ca.dot(copper, tau**2) + ca.dot(tau, qd[act]))
        return tau

    # each interval's torques at its start and its end (the same constant accelerations):
    # the effort's trapezoid, and limits held at both ends
    passive: dict[int, list] = {}
    powers: list = []  # starts then ends, as the torques
    starts = [torque(k, k, False) for k in range(N)]
    ends = [torque(k + 1, k, True) for k in range(N)]
    for start, end in passive.values():  # the trapezoid: second order in the interval
        opti.subject_to(start + end == 0)
    taus = starts + ends[-1:]
    if objective == "time":
        opti.subject_to(T >= 1e-6)
        if warm is not None:  # no slower than the move it starts from
            opti.subject_to(T <= warm.duration_s)
        opti.minimize(T)
    elif objective == "energy":  # each interval's trapezoid of the power at its two ends
        opti.minimize(h / 2 * ca.sum1(ca.vertcat(*powers)))
    else:
        opti.minimize(h / 2 * (ca.sumsqr(ca.horzcat(*starts)) + ca.sumsqr(ca.horzcat(*ends))))
    opti.solver("ipopt", {"print_time": False, "expand": True},
                {"print_level": 0, "sb": "yes", "tol": 1e-10, "max_iter": 3000})
    start = time.perf_counter()
    try:
        sol = opti.solve()
    except RuntimeError as exc:
        stats = opti.stats()
        raise SimulationError(f"{robot.name}: IPOPT found no optimal move "
                              f"({stats.get('return_status', exc)}, {stats.get('iter_count')} "
                              "iterations): loosen the limits, lengthen duration_s, or change "
                              "the end points") from None
    took = time.perf_counter() - start
    g, lbg, ubg = (np.asarray(sol.value(x)).ravel() for x in (opti.g, opti.lbg, opti.ubg))
    violation = float(max(np.max(lbg - g, initial=0.0), np.max(g - ubg, initial=0.0)))
    duration = float(sol.value(T)) if objective == "time" else float(duration_s)
    t = np.linspace(0.0, duration, N + 1)
    q_all = np.zeros((N + 1, n))
    qd_all, qdd_all = np.zeros_like(q_all), np.zeros_like(q_all)
    for part, cols, nodes in ((Qi, own, q_all), (Vi, own, qd_all)):
        nodes[:, cols] = np.asarray(sol.value(part)).reshape(len(cols), -1).T
    acc = np.asarray(sol.value(Ai)).reshape(len(own), -1).T
    qdd_all[:, own] = np.vstack([acc, acc[-1:]])
    if closed:
        q_all[:, pas] = np.asarray(sol.value(Qp)).reshape(len(pas), -1).T
        qd_all[:, pas] = np.asarray(sol.value(Vp)).reshape(len(pas), -1).T
        accp = np.asarray(sol.value(Ap)).reshape(len(pas), -1).T
        last = np.asarray(sol.value(Ae[:, N - 1])).reshape(1, -1)
        qdd_all[:, pas] = np.vstack([accp, last])
    tau = np.asarray(sol.value(ca.horzcat(*taus))).reshape(len(act), -1).T
    stats = sol.stats()
    return OptimalMove(JointTrajectory(t, q_all, qd_all, qdd_all, "optimal (IPOPT)"), tau,
                       duration, float(sol.value(opti.f)),
                       {"iterations": int(stats["iter_count"]),
                        "status": str(stats["return_status"]),
                        "constraint_violation": violation, "solve_time_s": took})


def _warm(opti, warm: OptimalMove, own, pas, closed, Qi, Vi, Ai, Qp, Vp, Ap, T) -> None:
    """Start from another solution on the same grid (its duration if the time is free)."""
    jt = warm.trajectory
    opti.set_initial(Qi, jt.q[:, own].T)
    opti.set_initial(Vi, jt.qd[:, own].T)
    opti.set_initial(Ai, jt.qdd[:-1, own].T)
    if closed:
        opti.set_initial(Qp, jt.q[:, pas].T)
        opti.set_initial(Vp, jt.qd[:, pas].T)
        for var in Ap:
            opti.set_initial(var, jt.qdd[:-1, pas].T)
    if not isinstance(T, float):
        opti.set_initial(T, warm.duration_s)


def _guess(robot, opti, own, pas, closed, a0, a1, N, Qi, Vi, Ai, Qp, Vp, Ap, T, duration_s,
           seed=None) -> None:
    """A cubic rest-to-rest move between the ends over the duration (1 s when the time is
    free), its rates and its accelerations at the intervals' midpoints; a closed chain's
    passive joints from its loops, in the assembly mode of ``seed`` (a pose; default the
    drawn one) (``initial_guess`` gives the same for the integrated ones)."""
    t, q, qd, qdd = initial_guess(a0, a1, N, 1.0 if duration_s is None else duration_s)
    opti.set_initial(Qi, q.T)
    opti.set_initial(Vi, qd.T)
    opti.set_initial(Ai, qdd.T)
    if closed:
        from ..motion.closure import from_actuated

        mid = np.vstack([qdd, qdd[-1:]])
        jt = from_actuated(robot, t, q, qd, mid, q_guess=seed)
        opti.set_initial(Qp, jt.q[:, pas].T)
        opti.set_initial(Vp, jt.qd[:, pas].T)
        for var in Ap:
            opti.set_initial(var, jt.qdd[:-1, pas].T)
    if duration_s is None:
        opti.set_initial(T, 1.0)


def initial_guess(a0, a1, intervals: int, duration_s: float):
    """The cubic rest-to-rest move from ``a0`` to ``a1`` in ``duration_s`` on ``intervals``:
    node times (N + 1,), positions and rates (N + 1, k) and the interval accelerations (N, k),
    each the cubic's at the interval's midpoint (rad, rad/s, rad/s^2; m at a slider)."""
    a0, a1 = np.asarray(a0, float), np.asarray(a1, float)
    t = np.linspace(0.0, duration_s, intervals + 1)
    s = t / duration_s
    mid = (s[:-1] + s[1:]) / 2
    d = (a1 - a0)[None, :]
    q = a0[None, :] + (3 * s**2 - 2 * s**3)[:, None] * d
    qd = ((6 * s - 6 * s**2) / duration_s)[:, None] * d
    qdd = ((6 - 12 * mid) / duration_s**2)[:, None] * d
    return t, q, qd, qdd


def copper_losses(robot: Robot) -> np.ndarray:
    """Shape (actuated,): per actuated joint, R / (N k_t)^2 (W per (N*m)^2; per N^2 at a
    slider): the winding's losses per squared joint torque, i = tau / (N k_t), from the
    description's drive train. Raises InputError where a motor has no torque_constant and
    winding_resistance."""
    out, missing = [], []
    for act, drive in zip(robot.actuators, robot.drive_train.drives):
        kt, r = act.get("torque_constant"), act.get("winding_resistance")
        if kt is None or r is None:
            missing.append(act["joint"])
            continue
        out.append(r / (drive.gear_ratio * kt) ** 2)
    if missing:
        raise InputError(f"{robot.name}: objective \"energy\" needs each motor's "
                         "torque_constant (N*m/A) and winding_resistance (ohm) in its "
                         f"[joints.actuator]; {', '.join(missing)} "
                         f"{'has' if len(missing) == 1 else 'have'} none")
    return np.array(out)
