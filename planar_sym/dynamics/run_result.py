"""The result of every forward run, open loop (``planar_sym.simulate``) or controlled
(``simulate_controlled``): one type, ``Simulation``, whose control fields are None for an open
loop run. ``ControlledRun`` (``dynamics.engine``, ``planar_sym.control``) is another name for it.

Its data are typed ``series.Series`` (``series()``, ``get``): the column names of
``columns()``, the NPZ and the DataFrame are made from them, the same code for both kinds.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from .events import Event
from .laws import Controller
from .series import Series, columns_of, one, select


@dataclass(frozen=True)
class Simulation:
    """A forward-dynamics run: arrays of shape (N, n) at times ``t_s``; energies (J) per
    sample; for a controlled run also the reference, the commanded torques and the work
    integrals (None for an open-loop run).

    Attributes
    ----------
    t_s : ndarray, shape (N,)
        Output times (s).
    q, qd : ndarray, shape (N, n)
        Every coordinate (rad; m at a slider) and its rate (rad/s; m/s).
    tau : ndarray, shape (N, n) or (N, actuated)
        The applied torques at each output time (N*m; N at a slider): an open-loop tree's on
        every coordinate (0 at a passive joint); a closed chain's and a controlled run's on the
        actuated coordinates (after saturation).
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
        Each coordinate's unit, ``"rad"`` or ``"m"``: what gives the series their units.
    actuated : tuple of int
        The actuated coordinates (0-based): the columns of ``tau`` when it holds only those,
        and of ``q_ref``, ``qd_ref``, ``tau_cmd``.
    q_ref, qd_ref : ndarray, shape (N, actuated), or None
        Controlled runs: the reference and its rate on the actuated coordinates (rad, rad/s;
        m, m/s at a slider).
    tau_cmd : ndarray, shape (N, actuated), or None
        Controlled runs: the commanded torques, before saturation (N*m; N at a slider).
    work_j, friction_j : ndarray, shape (N,), or None
        The actuators' work int tau . qd dt and the friction loss int D(qd) . qd dt since the
        start (J): integrated with the state by the engine (controlled runs, SUNDIALS, tables
        of torques, dopri5 on a robot whose actuators rub), exact for constant torques without
        friction; None for a torque function of time on SciPy's methods. Columns of
        controlled runs only (an open-loop run's columns are the same on every route).
    controller : Controller or None
        Controlled runs: the control law and gains that ran.
    events : tuple of Event
        What happened along the run (joint limits, actuator limits, assembly changes).
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
    #: (0-based): what types the series (``series``, ``columns``, ``save_npz``)
    robot: str = ""
    coordinate_units: tuple[str, ...] = ()
    actuated: tuple[int, ...] = ()
    #: controlled runs only (None, or () for events, otherwise)
    q_ref: np.ndarray | None = None
    qd_ref: np.ndarray | None = None
    tau_cmd: np.ndarray | None = None
    work_j: np.ndarray | None = None
    friction_j: np.ndarray | None = None
    controller: Controller | None = None
    events: tuple[Event, ...] = ()

    @classmethod
    def of_robot(cls, robot, t_s: np.ndarray, q: np.ndarray, qd: np.ndarray, tau: np.ndarray,
                 method: str, rtol: float, atol: float, n_rhs: int, **fields) -> Simulation:
        """A run of ``robot`` (the machine that moved) at times ``t_s`` (N,) in s: ``q``, ``qd``
        (N, n) in rad, rad/s (m, m/s at a slider), ``tau`` as the attribute holds it; its
        labels (``labels``) and its kinetic and potential energy (J) at every sample made here,
        the one place every route makes them; ``fields``: the other attributes."""
        named = labels(robot)
        kin, pot = robot.energy(q, qd)
        return cls(t_s, q, qd, tau, kin, pot, method, rtol, atol, n_rhs, **named, **fields)

    @property
    def controlled(self) -> bool:
        """Whether a controller ran (``simulate_controlled``): the control fields are set."""
        return self.controller is not None

    def series(self, quantity: str | None = None, index: int | None = None,
               joint: str | None = None) -> tuple[Series, ...]:
        """The run as typed series, each (N,) in its unit, in column order: ``t`` (s);
        ``q``, ``qd`` of every coordinate (rad, rad/s; m, m/s at a slider); a controlled run's
        ``q_ref``, ``qd_ref`` and ``tau_cmd`` on the actuated coordinates; ``tau`` (N*m; N at
        a slider) on every coordinate or the actuated ones, as ``tau`` holds them;
        ``kinetic``, ``potential``, ``energy`` (J); a controlled run's ``work`` and
        ``friction`` (J). ``quantity``, ``index`` (0-based coordinate), ``joint`` select."""
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
        parts = [("q", self.q, range(n)), ("qd", self.qd, range(n))]
        if self.controlled:
            act = self.actuated
            parts += [("q_ref", self.q_ref, act), ("qd_ref", self.qd_ref, act),
                      ("tau_cmd", self.tau_cmd, act)]
        parts.append(("tau", self.tau, on))
        out = [Series("t", "s", self.t_s)]
        for kind, arr, idx in parts:
            out += [Series.of_coordinate(kind, k, units[k], arr[:, col])
                    for col, k in enumerate(idx)]
        out += [Series("kinetic", "J", self.kinetic_j), Series("potential", "J", self.potential_j),
                Series("energy", "J", self.energy_j)]
        if self.controlled:  # an open-loop run's columns are the same on every route
            out += [Series("work", "J", self.work_j), Series("friction", "J", self.friction_j)]
        return select(out, quantity, index, joint)

    def get(self, quantity: str, index: int | None = None, joint: str | None = None) -> Series:
        """The one series of ``quantity`` (of coordinate ``index``, 0-based), shape (N,), in its
        unit (``series``); KeyError if there is none or more than one."""
        return one(self.series(), quantity, index, joint)

    def columns(self) -> dict[str, np.ndarray]:
        """The run as named columns, each (N,), the unit in the name as in a study's CSV (the
        ``column`` of each of ``series()``): ``t_s``, ``q<k>_rad`` (``q<k>_m`` at a slider),
        ``qd<k>_rad_s`` (``_m_s``), a controlled run's ``q<k>_ref_rad``, ``qd<k>_ref_rad_s``
        and ``tau_cmd<k>_n_m``, ``tau<k>_n_m`` (``_n``; k numbering the robot's coordinates
        from 1, the actuated ones only when ``tau`` holds those), ``kinetic_j``,
        ``potential_j``, ``energy_j``, a controlled run's ``work_j`` and ``friction_j``."""
        return columns_of(self.series())

    def metadata(self) -> dict[str, str]:
        """What the NPZ and the DataFrame's ``attrs`` carry besides the columns; a controlled
        run's also its controller and events."""
        meta = {"robot": self.robot, "method": self.method, "rtol": repr(self.rtol),
                "atol": repr(self.atol), "n_rhs": str(self.n_rhs),
                "constraint_drift_m": repr(self.constraint_drift_m), "writer": "planar-sym"}
        if self.controlled:
            meta["controller"] = self.controller.kind
            meta["events"] = "; ".join(str(e) for e in self.events)
        return meta

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

    @property
    def stopped(self) -> Event | None:
        """The event that stopped the run, if one did."""
        return next((e for e in self.events if e.stopped), None)

    @property
    def error(self) -> np.ndarray | None:
        """Tracking error q_ref - q on the actuated coordinates (N, actuated), rad (m at a
        slider); None for an open-loop run."""
        if self.q_ref is None:
            return None
        return self.q_ref - self.q[:, list(self.actuated)]

    @property
    def balance_residual(self) -> float | None:
        """max |E(t) - E(0) - (W(t) - F(t))| over the run, relative to the largest of |E|,
        |W|, |F| and the kinetic energy (J/J): the energy the actuators put in, less friction,
        is what the robot gained, up to the integrator's accuracy (the kinetic energy keeps the
        scale where E stays near 0, a free swing from a pose whose potential is the zero).
        None for a run without work integrals (a torque function of time on SciPy's methods)."""
        if self.work_j is None or self.friction_j is None:
            return None
        e = self.energy_j - self.energy_j[0]
        gap = e - (self.work_j - self.friction_j)
        scale = max(np.max(np.abs(self.energy_j)), np.max(np.abs(self.work_j)),
                    np.max(np.abs(self.friction_j)), np.max(np.abs(self.kinetic_j)), 1e-300)
        return float(np.max(np.abs(gap)) / scale)


def labels(robot) -> dict:
    """The keyword arguments that let a ``Simulation`` of ``robot`` type its series: its name,
    each coordinate's unit and its actuated coordinates."""
    return {"robot": robot.name, "coordinate_units": tuple(robot.coordinate_units),
            "actuated": tuple(robot.actuated)}
