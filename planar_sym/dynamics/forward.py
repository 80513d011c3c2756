"""Forward dynamics: integrate M(q) qdd + h(q, qd) = tau with error control.

Methods:

* ``"dopri5"`` (default): adaptive Dormand-Prince 5(4) written in C (planar_sym/dynamics/_integrate.c),
  calling the compiled forward dynamics with no Python per step; steps land exactly on the
  requested output times. For zero or constant torques.
* any SciPy ``solve_ivp`` method (``"DOP853"``, ``"RK45"``, ``"Radau"``, ``"BDF"``, ``"LSODA"``)
  on the compiled ``qdd = M^-1 (tau - h)``; Radau/BDF/LSODA get the compiled Jacobian. A torque
  that is a function of time always goes this way (DOP853 unless told otherwise);
* ``"cvodes"``, ``"idas"``: SUNDIALS through CasADi, in the simulation engine
  (``dynamics.engine``, the loop controlled runs use) under the open-loop law "none": zero or
  constant torques, or a table of them (``motion.signals.from_table``).

Closed chains are in ``planar_sym.dynamics.forward_closed``.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.integrate import solve_ivp

from ..errors import InputError, SimulationError
from ..model.library import SingleCall
from ..model.robot import Robot
from ..motion.signals import Signal
from ..progress import watching
from .engine_inputs import check_controller, engine_torque
from .forward_closed import start_state
from .integrate import (
    SCIPY_METHODS,
    Simulation,
    Torque,
    check_tolerances,
    check_torque,
    dopri5,
    time_grid,
    torque_function,
)


def simulate(robot: Robot, q0, qd0, t_span: tuple[float, float], *, torque: Torque = None,
             t_eval=None, rtol: float = 1e-11, atol: float = 1e-12,
             method: str = "dopri5", max_steps: int = 10_000_000,
             project: bool = False, progress=None) -> Simulation:
    """Integrate a robot from (q0 rad, qd0 rad/s) over ``t_span`` (s) under ``torque`` (N*m).

    ``torque``: None (zero), a constant vector, or a function of time returning one: one torque
    (N*m) per actuated joint (every joint of a fully actuated arm; passive joints get none);
    for a closed chain ``q0`` holds every coordinate, on the loops, and ``qd0`` is consistent
    with them (else InputError; ``project=True`` solves the passive joints from the actuated
    ones instead and reports ``initial_correction_rad``).
    Returns the state at ``t_eval`` (default: 1001 evenly spaced times), with energies.

    Parameters
    ----------
    robot : Robot
    q0, qd0 : array_like, shape (n,)
        Initial coordinates (rad; m at a slider) and rates (rad/s; m/s), every coordinate.
    t_span : (float, float)
        Start and end time (s).
    torque : None, array_like of shape (actuated,), Signal, or callable
        Zero, constant torques (N*m; N at a slider), a table of them over time
        (``motion.signals.from_table``: evaluated in C with dopri5 and SUNDIALS), or ``f(t)``
        returning them (t in s; SciPy methods only).
    t_eval : array_like, shape (N,), optional
        Output times (s), increasing, inside ``t_span``.
    rtol, atol : float
        Relative and absolute tolerances of the integrator (atol in the state's SI units).
    method : str
        ``"dopri5"`` (C, default), ``"cvodes"`` or ``"idas"`` (SUNDIALS in the engine), or a
        SciPy ``solve_ivp`` method (``"DOP853"``, ``"Radau"``, ...).
    max_steps : int
        Step limit of the C integrator.
    project : bool
        Closed chains: solve the passive joints of ``q0``, ``qd0`` from the actuated ones.
        Passive values equal to ``robot.q_drawn``'s are no guess: the drawn pose is continued
        along the loops to the actuated ones (its assembly mode kept). Other values are
        Newton's start, which picks the mode; one Newton must move far that closes another
        pose than the drawn mode's gets a warning naming both.
    progress : callable, optional
        Called as ``progress(t_s, t_end_s)`` about ten times a second while the compiled loop
        (dopri5) runs, with the time reached (e.g. ``planar_sym.progress.Clock``); the
        command line sets one for long runs on a terminal.

    Returns
    -------
    Simulation
        ``t_s`` (N,), ``q``, ``qd`` (N, n), torques and energies (J) per sample; on the
        engine's routes (SUNDIALS, a table of torques, and dopri5 on a robot whose actuators
        rub) also ``work_j`` and ``friction_j``, the actuators' work and the friction loss
        integrated with the state, so ``balance_residual`` checks the energy balance.

    Raises
    ------
    InputError
        Bad shapes, values, tolerances or method.
    SimulationError
        The integrator failed (naming the time).
    """
    if not isinstance(robot, Robot):
        raise InputError(f"simulate needs a Robot (planar_sym.load), got {type(robot).__name__}")
    if progress is not None:  # every route below reads it from there, down to the C loop
        with watching(progress):
            return simulate(robot, q0, qd0, t_span, torque=torque, t_eval=t_eval, rtol=rtol,
                            atol=atol, method=method, max_steps=max_steps, project=project)
    check_tolerances(rtol, atol)
    t = time_grid(t_span, t_eval)
    torque = check_torque(torque, len(robot.actuated))  # one rule for every route below
    table = isinstance(torque, Signal)  # evaluated in C by the engine; in Python by SciPy
    # the engine also integrates the actuators' work and friction loss beside the state: a
    # rubbing robot's dopri5 run goes there, so its energy balance can be checked
    engine = method in ("cvodes", "idas") or (method == "dopri5"
                                              and (table or robot.has_friction))
    if table and not engine:
        signal = torque

        def torque(tt: float) -> np.ndarray:  # SciPy calls it per step, in Python
            return signal(tt)[0]
    tau_of = _on_actuated(torque_function(torque, len(robot.actuated)), robot)
    if engine:  # the compiled loop's rule: a table that covers the run, or constant torques
        torque = engine_torque(torque, len(robot.actuated), float(t_span[0]), float(t_span[1]))
    # checked once here, for every route below (a closed chain's on its loops, or solved)
    q0, qd0, moved = start_state(robot, q0, qd0, project)
    if engine:
        return _in_the_engine(robot, q0, qd0, t_span, torque, t, rtol, atol, method, moved)
    run = _outside_the_engine(robot, q0, qd0, torque, tau_of, t, rtol, atol, method, max_steps,
                              moved)
    if callable(torque) or robot.has_friction:  # SciPy integrates the state alone
        return run
    # constant torques and no friction: the work is tau . (q - q0) exactly, the friction loss
    # zero, as the engine's integrals give
    tau = tau_of(t[0])
    return replace(run, work_j=(run.q - run.q[0]) @ tau, friction_j=np.zeros(len(run.t_s)))


def _outside_the_engine(robot: Robot, q0, qd0, torque, tau_of, t, rtol, atol, method: str,
                        max_steps: int, moved: float) -> Simulation:
    """The free C dopri5, SciPy's methods, or a closed chain's segments."""
    if robot.is_closed_chain:
        from .forward_closed import DRIFT_LIMIT_M, SEGMENT_S, run_closed

        return run_closed(robot, q0, qd0, t, torque=torque, rtol=rtol, atol=atol,
                          method=method, segment_s=SEGMENT_S, drift_limit_m=DRIFT_LIMIT_M,
                          correction=moved)
    n = robot.n
    x0 = np.concatenate([q0, qd0])
    if method == "dopri5" and not callable(torque):
        fd = robot.library.address("forward_dynamics")
        y, n_rhs = dopri5(robot, 0, fd, x0, t, tau_of(t[0]), rtol, atol, max_steps)
        q, qd = y[:, :n].copy(), y[:, n:].copy()
        return Simulation.of_robot(robot, t, q, qd, np.tile(tau_of(t[0]), (len(t), 1)), method,
                                   rtol, atol, n_rhs)
    method = "DOP853" if method == "dopri5" else method
    if method not in SCIPY_METHODS:
        raise InputError(f"unknown method {method!r}; known: dopri5, cvodes, idas, "
                         f"{', '.join(SCIPY_METHODS)}")
    fd = SingleCall(robot.library.functions["forward_dynamics"], robot.p)
    count, last_t = [0], [t[0]]

    def rhs(tt, x):
        count[0] += 1
        last_t[0] = tt
        (qdd,) = fd(x[:n], x[n:], tau_of(tt))
        if not np.all(np.isfinite(qdd)):  # else SciPy shrinks its step for ever
            raise SimulationError(f"{robot.name}: accelerations became {qdd.tolist()} at "
                                  f"t = {tt:.6g} s (state {x.tolist()})")
        return np.concatenate([x[n:], qdd])

    jac = None
    if method in ("Radau", "BDF", "LSODA"):
        fj = SingleCall(robot.library.functions["forward_dynamics_jacobian"], robot.p)

        def jac(tt, x):
            dq, dqd = fj(x[:n], x[n:], tau_of(tt))
            top = np.hstack([np.zeros((n, n)), np.eye(n)])
            return np.vstack([top, np.hstack([dq.reshape(n, n).T, dqd.reshape(n, n).T])])

    extra = {"jac": jac} if jac is not None else {}
    sol = solve_ivp(rhs, (t[0], t[-1]), x0, method=method, t_eval=t, rtol=rtol, atol=atol,
                    **extra)
    if not sol.success:
        raise SimulationError(f"{robot.name}: integration failed at t = {last_t[0]:.6g} s: "
                              f"{sol.message}")
    q, qd = sol.y[:n].T.copy(), sol.y[n:].T.copy()
    taus = np.array([tau_of(tt) for tt in t])
    return Simulation.of_robot(robot, t, q, qd, taus, method, rtol, atol, count[0])


def _on_actuated(tau_of, robot: Robot):
    """Torques of the actuated joints as a vector over every coordinate (zero at a passive
    joint): what the generated forward dynamics takes."""
    if len(robot.actuated) == robot.n:
        return tau_of
    act, full = list(robot.actuated), np.zeros(robot.n)

    def expanded(t: float) -> np.ndarray:
        full[act] = tau_of(t)
        return full.copy()
    return expanded


def _in_the_engine(robot: Robot, q0: np.ndarray, qd0: np.ndarray, t_span, torque,
                   t: np.ndarray, rtol: float, atol: float, method: str,
                   moved: float) -> Simulation:
    """SUNDIALS in the simulation engine under the open-loop law "none": its Simulation without
    the control fields (the events it saw kept). ``q0``, ``qd0`` (``start_state``: a closed
    chain's on its loops, its passive joints ``moved`` that far to get there), the input
    ``torque`` (``engine_torque``) and the output times ``t`` (s) are checked already
    (``simulate``), so the engine's run is entered past ``simulate_controlled``'s checks
    (``run_checked``)."""
    from .engine import run_checked
    from .laws import Controller

    n = robot.n
    none = Controller("none")
    check_controller(robot, none)  # a closed chain the loop cannot run is refused, by name
    act = list(robot.actuated)
    # no joint-limit events; the engine's own step limit (simulate's max_steps is dopri5's)
    run = run_checked(robot, robot, none, None, torque, q0, qd0, float(t_span[0]), t, None,
                      "stop", "continue", method, rtol, atol, 10_000_000)
    tau = run.tau
    if not robot.is_closed_chain:  # a tree's torques on every coordinate, 0 at a passive one
        tau = np.zeros((len(run.t_s), n))
        tau[:, act] = run.tau
    # the same type as the engine's: an open-loop run, so without the control fields (its
    # work and friction integrals kept: the energy balance of the run)
    return replace(run, tau=tau, initial_correction_rad=moved, q_ref=None, qd_ref=None,
                   tau_cmd=None, controller=None)
