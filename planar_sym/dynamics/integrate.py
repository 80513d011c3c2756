"""Shared by both forward-dynamics paths: torque inputs, time grids, and the adaptive
Dormand-Prince 5(4) integrator in C (``_integrate.c``). The result type, ``Simulation``, is
``run_result``'s (imported here too, where it used to live).

The C integrator calls the compiled dynamics with no Python per step: error control as in
Hairer, Norsett & Wanner, FSAL, steps shortened to land exactly on every output time.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..errors import InputError, SimulationError
from ..model.compile import load_helper
from ..model.robot import Robot
from ..motion.signals import Signal
from ..progress import ambient
from .run_result import Simulation, labels
from .watched import call_watched

__all__ = ["SCIPY_METHODS", "Simulation", "Torque", "check_tolerances", "check_torque", "dopri5",
           "helper", "integrator", "labels", "time_grid", "torque_function"]

Torque = None | float | np.ndarray | Callable[[float], np.ndarray]
SCIPY_METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")


def torque_function(torque: Torque, n: int) -> Callable[[float], np.ndarray]:
    """Zero, a constant vector, or a function of time (s) returning (n,) torques in N*m."""
    if torque is None:
        zero = np.zeros(n)
        return lambda t: zero
    if callable(torque):
        def checked(t: float) -> np.ndarray:
            try:
                tau = np.asarray(torque(t), dtype=float)
            except (TypeError, ValueError) as exc:
                raise InputError(f"torque function returned something that is not numbers at "
                                 f"t = {t:.6g} s ({exc})") from None
            if tau.shape != (n,) or not np.all(np.isfinite(tau)):
                raise InputError(f"torque function returned {tau!r} at t = {t:.6g} s; "
                                 f"expected {n} finite values (N*m)")
            return tau
        return checked
    rule = (f"torque must be None, {n} numbers (N*m; N at a slider), one for every actuated "
            "joint, or a function of time")
    if np.asarray(torque).dtype == np.bool_:  # True read as 1 N*m (a trial)
        raise InputError(f"{rule} (got booleans: {torque!r})")
    try:
        arr = np.asarray(torque, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{rule} (got {torque!r}: {exc})") from None
    if arr.shape == (1,) and n > 1:  # [0.2] for two joints: the first only, or both? ask
        raise InputError(f"torque {np.array2string(arr)} is one value for {n} actuated joints: "
                         f"give a number ({arr[0]:g}) for every joint, or {n} values")
    if arr.shape not in ((), (n,)):
        raise InputError(f"{rule} (got shape {arr.shape}: "
                         f"{np.array2string(arr, threshold=8)})")
    const = np.broadcast_to(arr, (n,)).copy()
    if not np.all(np.isfinite(const)):
        raise InputError(f"torque must be finite (got {const.tolist()})")
    return lambda t: const


def check_torque(torque, n: int):
    """A run's torque input checked once, by one rule on every route (the C integrator, the
    engine, SciPy): None; a function of time (checked as it is called); a Signal of ``n``
    channels; or constant torques, one number for every actuated joint or ``n`` of them (a
    list of one for several joints is refused: which it means is not clear), returned as a
    float (n,) array (N*m; N at a slider)."""
    if torque is None or (callable(torque) and not isinstance(torque, Signal)):
        return torque
    if isinstance(torque, Signal):
        if torque.channels != n:
            raise InputError(f"the torque table has {torque.channels} columns for {n} "
                             "actuated joints")
        return torque
    return torque_function(torque, n)(0.0)


def check_tolerances(rtol, atol) -> None:
    """InputError unless ``rtol`` and ``atol`` are positive numbers."""
    for name, v in (("rtol", rtol), ("atol", atol)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating)) or not v > 0:
            raise InputError(f"{name} must be a positive number (got {v!r})")


def time_grid(t_span: tuple[float, float], t_eval) -> np.ndarray:
    """The output times (s), shape (N,): ``t_eval`` checked (finite, increasing, inside
    ``t_span``, at least 2), or 1001 evenly spaced times over ``t_span`` = (t0, t1) in s."""
    try:
        t0, t1 = (float(v) for v in t_span)
    except (TypeError, ValueError):
        raise InputError(f"time span must be two numbers (t0, t1) in s (got {t_span!r})") from None
    if not (np.isfinite(t0) and np.isfinite(t1) and t1 > t0):
        raise InputError(f"time span must be finite with end > start (got {t_span})")
    if t_eval is None:
        return np.linspace(t0, t1, 1001)
    try:
        t = np.asarray(t_eval, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"t_eval must be an array of times in s ({exc})") from None
    if t.ndim != 1:
        raise InputError(f"t_eval must be a 1-D array of times, got shape {t.shape}")
    bad = ~np.isfinite(t)
    if bad.any():
        k = int(np.argmax(bad))
        raise InputError(f"t_eval[{k}] is {t[k]}: times must be finite")
    if t.size < 2 or np.any(np.diff(t) <= 0) or t[0] < t0 or t[-1] > t1:
        raise InputError(f"t_eval must be at least 2 increasing times inside {t_span}")
    return t


_DOPRI5_ERRORS = {1: "the right-hand side failed (singular mass or KKT matrix?)",
                  2: "the step size fell below 1e-14 s: the problem is stiff or singular here",
                  3: "too many steps (raise max_steps or loosen the tolerances)",
                  4: "the robot is too large for the built-in integrator (32 coordinates)"}


def dopri5(robot: Robot, kind: int, fn: int, y0: np.ndarray, t: np.ndarray, tau: np.ndarray,
           rtol: float, atol: float, max_steps: int, act: np.ndarray | None = None):
    """The C integrator: states (len(t), 2n) at ``t`` and the number of RHS evaluations.

    kind 0: tree (``fn`` = forward_dynamics batch); kind 1: closed chain (``fn`` =
    constrained_terms batch, ``tau`` on the actuated coordinates ``act``).

    ``y0`` (2n,) is the initial state [q, qd] (rad, rad/s), ``t`` (N,) the output times (s),
    ``tau`` the constant torques (N*m); each state row is [q, qd] at its time.
    """
    import ctypes

    if not (rtol > 0 and atol > 0):
        raise InputError(f"tolerances must be positive (rtol {rtol}, atol {atol})")
    n, m = robot.n, robot.n_constraints if kind == 1 else 0
    y0 = np.ascontiguousarray(y0, dtype=float)
    t = np.ascontiguousarray(t, dtype=float)
    tau = np.ascontiguousarray(tau, dtype=float)
    act_arr = np.ascontiguousarray(act if act is not None else [], dtype=np.intc)
    out = np.empty((len(t), 2 * n))
    stats = np.zeros(3, dtype=np.int64)
    t_fail = ctypes.c_double()
    rc = call_watched(lambda: integrator()(
        kind, n, m, len(act_arr), act_arr.ctypes.data, tau.ctypes.data, robot.p.ctypes.data, fn,
        float(t[0]), y0.ctypes.data, len(t), t.ctypes.data, rtol, atol, max_steps,
        out.ctypes.data, stats.ctypes.data, ctypes.byref(t_fail)), t_fail, float(t[-1]),
        ambient())
    if rc:
        raise SimulationError(f"{robot.name}: integration failed at t = {t_fail.value:.6g} s: "
                              f"{_DOPRI5_ERRORS.get(rc, rc)}")
    return out, int(stats[0])


_INTEGRATOR = None
_HELPER = None


def helper():
    """The compiled ``_integrate.c`` (once per source hash), loaded with ctypes."""
    global _HELPER
    if _HELPER is None:
        _HELPER = load_helper(Path(__file__).resolve().parent / "_integrate.c")
    return _HELPER


def integrator():
    """``planar_sym_dopri5`` from _integrate.c (compiled once per source hash), via ctypes."""
    global _INTEGRATOR
    if _INTEGRATOR is None:
        import ctypes

        fn = helper().planar_sym_dopri5
        ptr = ctypes.c_void_p
        fn.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_int, ptr, ptr, ptr,
                       ptr, ctypes.c_double, ptr, ctypes.c_int, ptr, ctypes.c_double,
                       ctypes.c_double, ctypes.c_longlong, ptr, ptr, ptr]
        fn.restype = ctypes.c_int
        _INTEGRATOR = fn
    return _INTEGRATOR
