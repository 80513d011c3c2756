"""Shared by both forward-dynamics paths: the result type, torque inputs, time grids, and the
adaptive Dormand-Prince 5(4) integrator in C (``_integrate.c``).

The C integrator calls the compiled dynamics with no Python per step: error control as in
Hairer, Norsett & Wanner, FSAL, steps shortened to land exactly on every output time.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError, SimulationError
from ..model.compile import load_helper
from ..model.robot import Robot
from .columns import coordinate_column

Torque = None | float | np.ndarray | Callable[[float], np.ndarray]
SCIPY_METHODS = ("DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA")


@dataclass(frozen=True)
class Simulation:
    """A forward-dynamics run: arrays of shape (N, n) at times ``t_s``; energies (J) per sample.

    Attributes
    ----------
    t_s : ndarray, shape (N,)
        Output times (s).
    q, qd : ndarray, shape (N, n)
        Every coordinate (rad; m at a slider) and its rate (rad/s; m/s).
    tau : ndarray, shape (N, n) or (N, actuated)
        The input torques at each output time (N*m; N at a slider): a tree's on every
        coordinate (0 at a passive joint), a closed chain's on its actuated coordinates.
    kinetic_j, potential_j : ndarray, shape (N,)
        Kinetic and potential energy (J).
    method : str
        The integrator that ran (``"dopri5"``, a SciPy method, ``"cvodes"``, ``"idas"``).
    rtol, atol : float
        Its relative and absolute tolerances (absolute in the state's SI units).
    n_rhs : int
        Evaluations of the dynamics it made.
    constraint_drift_m : float
        Closed chains: the largest loop residual max |Phi| over the run (m); 0 for a tree.
    initial_correction_rad : float
        How far ``project=True`` moved the passive joints of the initial state (rad).
    robot : str
        The simulated robot's name.
    coordinate_units : tuple of str
        Each coordinate's unit, ``"rad"`` or ``"m"``: what names the columns (``columns``).
    actuated : tuple of int
        The actuated coordinates (0-based): the columns of ``tau`` when it holds only those.
    """

    t_s: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    kinetic_j: np.ndarray
    potential_j: np.ndarray
    method: str
    rtol: float
    atol: float
    n_rhs: int
    constraint_drift_m: float = 0.0  # max |Phi| over the run (closed chains)
    initial_correction_rad: float = 0.0  # how far project=True moved the passive joints
    #: the robot's name, each coordinate's unit ("rad" or "m") and its actuated coordinates
    #: (0-based): what names the columns (``columns``, ``to_dataframe``, ``save_npz``)
    robot: str = ""
    coordinate_units: tuple[str, ...] = ()
    actuated: tuple[int, ...] = ()

    def columns(self) -> dict[str, np.ndarray]:
        """The run as named columns, each (N,), the unit in the name as in a study's CSV:
        ``t_s``, ``q<k>_rad`` (``q<k>_m`` at a slider), ``qd<k>_rad_s`` (``_m_s``),
        ``tau<k>_n_m`` (``_n``; k numbering the robot's coordinates from 1, the actuated ones
        only when ``tau`` holds those), ``kinetic_j``, ``potential_j``, ``energy_j``."""
        n = self.q.shape[1]
        units = self.coordinate_units
        if len(units) != n:
            raise InputError(f"this Simulation does not know its {n} coordinates' units (made "
                             "without a robot): use planar_sym.simulate's result, or "
                             "dataclasses.replace(sim, coordinate_units=('rad', 'm', ...))")
        width = self.tau.shape[1] if self.tau.ndim == 2 else 0
        on = (range(n) if width == n else self.actuated if width == len(self.actuated)
              else None)
        if on is None:
            raise InputError(f"tau has {width} columns, neither the {n} coordinates nor the "
                             f"{len(self.actuated)} actuated ones")
        out = {"t_s": self.t_s}
        for kind, arr, idx in (("q", self.q, range(n)), ("qd", self.qd, range(n)),
                               ("tau", self.tau, on)):
            for col, k in enumerate(idx):
                out[coordinate_column(kind, k, units[k])] = arr[:, col]
        out.update(kinetic_j=self.kinetic_j, potential_j=self.potential_j,
                   energy_j=self.energy_j)
        return out

    def metadata(self) -> dict[str, str]:
        """What the NPZ and the DataFrame's ``attrs`` carry besides the columns."""
        return {"robot": self.robot, "method": self.method, "rtol": repr(self.rtol),
                "atol": repr(self.atol), "n_rhs": str(self.n_rhs),
                "constraint_drift_m": repr(self.constraint_drift_m), "writer": "planar-sym"}

    def to_dataframe(self):
        """The run as a pandas DataFrame: one column per ``columns()`` entry (``t_s`` a column,
        not the index), ``attrs`` = ``metadata()``. Needs pandas (``pip install pandas``)."""
        from .columns import dataframe

        return dataframe(self.columns(), self.metadata())

    def save_npz(self, path) -> Path:
        """Write ``columns()`` and ``metadata()`` to the NPZ file ``path`` (whole or not at
        all); read it back with ``planar_sym.dynamics.columns.load_npz`` or ``np.load``."""
        from .columns import save_npz

        return save_npz(path, self.columns(), self.metadata())

    @property
    def energy_j(self) -> np.ndarray:
        """Total energy kinetic + potential (J), shape (N,)."""
        return self.kinetic_j + self.potential_j

    @property
    def energy_drift(self) -> float:
        """max |E(t) - E(0)| / max(|E(0)|, E scale) over the run (J/J): about the integrator's
        tolerance for a free motion without friction."""
        e = self.energy_j
        scale = max(abs(e[0]), np.max(np.abs(self.kinetic_j)), 1e-300)
        return float(np.max(np.abs(e - e[0])) / scale)


def labels(robot: Robot) -> dict:
    """The keyword arguments that let a ``Simulation`` of ``robot`` name its columns."""
    return {"robot": robot.name, "coordinate_units": tuple(robot.coordinate_units),
            "actuated": tuple(robot.actuated)}


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
    try:
        const = np.broadcast_to(np.asarray(torque, dtype=float), (n,)).copy()
    except (TypeError, ValueError) as exc:
        raise InputError(f"torque must be None, {n} numbers (N*m) or a function of time "
                         f"(got {torque!r}: {exc})") from None
    if not np.all(np.isfinite(const)):
        raise InputError(f"torque must be finite (got {const.tolist()})")
    return lambda t: const


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
    rc = integrator()(kind, n, m, len(act_arr), act_arr.ctypes.data, tau.ctypes.data,
                      robot.p.ctypes.data, fn, float(t[0]), y0.ctypes.data, len(t),
                      t.ctypes.data, rtol, atol, max_steps, out.ctypes.data, stats.ctypes.data,
                      ctypes.byref(t_fail))
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
