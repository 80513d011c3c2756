"""The controlled loop's binding to C: the ``Control`` struct of ``_integrate.c`` and the arrays
it points to, filled from a run's inputs (``_Setup``), and the entry points of the compiled
loop and of the controller alone (``control_values``).
"""

from __future__ import annotations

import ctypes
import functools

import numpy as np

from ..errors import SimulationError
from ..model.robot import Robot
from ..motion.signals import Signal
from .events import EventSpec
from .laws import Controller
from .segments import friction

_P = ctypes.c_void_p
MAX_EVENTS_LOGGED = 256
#: a tracking law (PD + gravity, computed torque) on a tree calls the generated fused
#: controller-and-plant function (``derive/tracking.py``) where the robot has one; False: the
#: controller's and the plant's functions one after the other (the same numbers to rounding)
FUSED = True
TRACKING = {1: "tracking_pd", 2: "tracking_ct"}  # Control.mode -> the fused function


class _CSignal(ctypes.Structure):
    _fields_ = [("n_knots", ctypes.c_int), ("n_ch", ctypes.c_int), ("deg", ctypes.c_int),
                ("T", _P), ("c", _P)]


class _CControl(ctypes.Structure):  # mirrors Control in _integrate.c
    _fields_ = [("mode", ctypes.c_int), ("saturate", ctypes.c_int),
                ("kp", _P), ("kd", _P), ("p_nom", _P), ("tau_const", _P), ("lo", _P),
                ("hi", _P), ("fv", _P), ("fc", _P), ("vs", _P),
                ("gravity", _P), ("inverse", _P), ("closed_inverse", _P), ("jac", _P),
                ("bias", _P), ("ref", _CSignal), ("input", _CSignal),
                ("n_ev", ctypes.c_int), ("ev_kind", _P), ("ev_index", _P), ("ev_stop", _P),
                ("ev_value", _P), ("armed", _P), ("max_log", ctypes.c_int),
                ("n_log", ctypes.c_int), ("log_ev", _P), ("log_t", _P),
                ("stopped", ctypes.c_int), ("t_stop", ctypes.c_double), ("y_stop", _P),
                ("hint_ref", ctypes.c_int), ("hint_input", ctypes.c_int),
                ("gain", _P), ("x_ref", _P), ("u_ref", _P), ("sched", _CSignal),
                ("sched_v", _P), ("hint_sched", ctypes.c_int), ("tracking", _P)]


def _array(a, dtype=float) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=dtype)


class _Setup:
    """The C Control struct and every array it points to (kept alive here)."""

    def __init__(self, robot: Robot, plant: Robot, ctl: Controller, ref: Signal | None,
                 torque: np.ndarray | Signal | None, events: list[EventSpec],
                 bound: np.ndarray):
        na, n = len(robot.actuated), robot.n
        lib = robot.library
        self.keep = []
        c = _CControl()
        c.mode = ctl.mode
        c.saturate = int(ctl.saturate and np.isfinite(bound).any())
        c.kp = self._ptr(ctl.kp or np.zeros(na))
        c.kd = self._ptr(ctl.kd or np.zeros(na))
        c.p_nom = self._ptr(robot.p)
        c.lo, c.hi = self._ptr(-bound), self._ptr(bound)
        c.gain = self._ptr(ctl.gain or np.zeros(1))
        c.x_ref = self._ptr(ctl.x_ref or np.zeros(1))
        c.u_ref = self._ptr(ctl.u_ref or np.zeros(1))
        if ctl.schedule is not None:  # a time-varying LQR: x_ref, u_ref and K of time
            c.sched = self._signal(ctl.schedule)
            self.sched_v = np.zeros(ctl.schedule.channels)
            c.sched_v = self.sched_v.ctypes.data
        fv, fc, vs = friction(plant)
        c.fv, c.fc, c.vs = self._ptr(fv), self._ptr(fc), self._ptr(vs)
        if isinstance(torque, Signal):
            c.input = self._signal(torque)
        elif torque is not None:
            c.tau_const = self._ptr(torque)
        if ref is not None:
            c.ref = self._signal(ref)
        for slot, quantity in (("gravity", "gravity"), ("inverse", "inverse_dynamics"),
                               ("closed_inverse", "closed_inverse_dynamics"),
                               ("jac", "constraint_jacobian"), ("bias", "constraint_bias")):
            if quantity in lib.manifest["functions"]:
                setattr(c, slot, lib.address(quantity))
        fused = TRACKING.get(ctl.mode) if FUSED and not plant.n_constraints else None
        if fused in lib.manifest["functions"]:  # (a description derived before has none)
            c.tracking = lib.address(fused)
        c.n_ev = len(events)
        c.ev_kind = self._ptr([e.kind for e in events], np.intc)
        c.ev_index = self._ptr([e.index for e in events], np.intc)
        c.ev_stop = self._ptr([int(e.stop) for e in events], np.intc)
        c.ev_value = self._ptr([e.value for e in events])
        self.armed = _array(np.ones(max(len(events), 1)), np.intc)
        c.armed = self.armed.ctypes.data
        c.max_log = MAX_EVENTS_LOGGED
        self.log_ev = np.zeros(MAX_EVENTS_LOGGED, dtype=np.intc)
        self.log_t = np.zeros(MAX_EVENTS_LOGGED)
        c.log_ev, c.log_t = self.log_ev.ctypes.data, self.log_t.ctypes.data
        self.y_stop = np.zeros(2 * n + 2)
        c.y_stop = self.y_stop.ctypes.data
        self.c = c
        self.act = _array(robot.actuated, np.intc)
        self.bound = bound

    def _ptr(self, a, dtype=float) -> int:
        arr = _array(a if len(a) else [0], dtype)
        self.keep.append(arr)
        return arr.ctypes.data

    def _signal(self, s: Signal) -> _CSignal:
        out = _CSignal()
        out.n_knots, out.n_ch, out.deg = len(s.knots_s), s.channels, s.degree
        out.T, out.c = self._ptr(s.knots_s), self._ptr(s.coefficients.ravel())
        return out


@functools.cache
def _functions():
    """The C entry points, their argument types declared once per process."""
    from .integrate import helper

    lib = helper()
    run = lib.planar_sym_dopri5_ctl
    run.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_int, _P, _P, _P, _P,
                    ctypes.POINTER(_CControl), ctypes.c_double, _P, ctypes.c_int, _P,
                    ctypes.c_double, ctypes.c_double, ctypes.c_longlong, _P, _P, _P]
    run.restype = ctypes.c_int
    ev = lib.planar_sym_control_eval
    ev.argtypes = [ctypes.c_int, ctypes.c_int, ctypes.c_int, _P, _P, ctypes.POINTER(_CControl),
                   ctypes.c_longlong, _P, _P, _P, _P, _P, _P, _P]
    ev.restype = ctypes.c_int
    return run, ev


def control_values(robot: Robot, setup: _Setup, t: np.ndarray, y: np.ndarray):
    """Commanded and applied torques (N, actuated), event values (N, events) and the tracked
    reference with its rate (each (N, actuated), rad or m and /s; None for a law that tracks
    none) at states ``y`` (N, 2n) and times ``t`` (s), from the compiled controller."""
    _, ev = _functions()
    na, n_ev = len(robot.actuated), setup.c.n_ev
    t, y = _array(t), _array(y[:, :2 * robot.n])
    cmd, app = np.empty((len(t), na)), np.empty((len(t), na))
    g = np.empty((len(t), max(n_ev, 1)))
    tracks = setup.c.mode in (1, 2)  # PD + gravity, computed torque: the reference's values
    ref, ref_d = (np.empty((len(t), na)), np.empty((len(t), na))) if tracks else (None, None)
    rc = ev(robot.n, robot.n_constraints, na, setup.act.ctypes.data, robot.p.ctypes.data,
            ctypes.byref(setup.c), len(t), t.ctypes.data, y.ctypes.data, cmd.ctypes.data,
            app.ctypes.data, g.ctypes.data, ref.ctypes.data if tracks else None,
            ref_d.ctypes.data if tracks else None)
    if rc:
        raise SimulationError(f"{robot.name}: the controller failed at t = {t[rc - 1]:.6g} s "
                              "(a singular pose of the controller's model?)")
    return cmd, app, g[:, :n_ev], ref, ref_d
