"""Control laws in the loop, and their gains: what each one computes at every step.

On the actuated coordinates ``a`` (every coordinate of a fully actuated arm), with the
reference ``q_r(t)`` and the error ``e = q_r - q``:

.. code:: text

    "pd"               PD with gravity compensation
                       tau = Kp e + Kd de/dt + g_a(q)
                       g_a: the torques that hold the robot still at q (tree: g(q) = dV/dq;
                       closed chain: the closed-chain inverse dynamics at qd = qdd = 0)
    "computed_torque"  feedback linearisation on the controller's model
                       tau = ID(q, qd, v),  v = qdd_r + Kd de/dt + Kp e
                       closed chain: v on the actuated joints, the passive accelerations
                       from Phi_q qdd = gamma, then the closed-chain inverse dynamics
    "none"             open loop: only the input torques (a table, a profile, a constant)

With an exact model, computed torque makes every error obey ``e'' + Kd e' + Kp e = 0``: the
robot tracks a reference it starts on to the integrator's accuracy. The models (``g``,
``ID``) use the controller's parameters; the plant may differ (a model error).

Units: PD gains are N*m/rad and N*m*s/rad (N/m and N*s/m at a slider); computed-torque gains
are 1/s^2 and 1/s (Kp = w^2 and Kd = 2 zeta w give a natural frequency w and damping zeta).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

KINDS = ("pd", "computed_torque", "none")
MODE = {"none": 0, "pd": 1, "computed_torque": 2}
#: a gain above this cannot be meant (the step size it forces would stall the integrator)
MAX_GAIN = 1e9


@dataclass(frozen=True)
class Controller:
    """A control law and its gains, one per actuated coordinate (SI).

    Make one with ``controller`` (which checks the gains).

    Attributes
    ----------
    kind : str
        ``"pd"``, ``"computed_torque"`` or ``"none"`` (the module's table).
    kp, kd : tuple of float
        Proportional and derivative gains per actuated coordinate (one value: every joint):
        N*m/rad and N*m*s/rad for PD (N/m, N*s/m at a slider), 1/s^2 and 1/s for computed
        torque (``gain_units``); empty for "none".
    saturate : bool
        Whether the commanded torques are clipped at the actuator limits of the description.
    """

    kind: str
    kp: tuple[float, ...] = ()
    kd: tuple[float, ...] = ()
    saturate: bool = True

    @property
    def mode(self) -> int:
        """The law's number in the compiled loop (``MODE``: 0 none, 1 PD, 2 computed torque)."""
        return MODE[self.kind]

    def gain_units(self, unit: str) -> tuple[str, str]:
        """Units of Kp and Kd at a coordinate measured in ``unit`` ("rad" or "m")."""
        if self.kind == "computed_torque":
            return "1/s^2", "1/s"
        force = "N" if unit == "m" else "N*m"
        return f"{force}/{unit}", f"{force}*s/{unit}"


def _gains(name: str, value, width: int | None) -> tuple[float, ...]:
    try:
        arr = np.asarray(value, dtype=float)
        arr = arr.reshape(-1) if width is None and arr.ndim <= 1 else \
            np.broadcast_to(arr, (width,))
    except (TypeError, ValueError):
        raise InputError(f"{name} must be one number or {width or 'several'} numbers, one per "
                         f"actuated joint (got {value!r})") from None
    for k, v in enumerate(arr):
        if not np.isfinite(v):
            raise InputError(f"{name}[{k}] is {v}: gains must be finite")
        if v < 0:
            raise InputError(f"{name}[{k}] is {v:g}: a negative gain pushes the joint away "
                             "from its reference (unstable); gains must be >= 0")
        if v > MAX_GAIN:
            raise InputError(f"{name}[{k}] is {v:g}: above {MAX_GAIN:g} (a unit slip?)")
    return tuple(float(v) for v in arr)


def controller(kind: str = "pd", kp=None, kd=None, *, width: int | None = None,
               saturate: bool = True) -> Controller:
    """A checked Controller for ``width`` actuated coordinates (None: as many as the robot it
    is used with has; one gain then serves every joint).

    ``kp``, ``kd``: one number (every joint) or one per actuated joint; required for "pd" and
    "computed_torque", not taken by "none". Negative, non-finite or absurd gains raise
    InputError; a computed-torque loop with Kp > 0 and Kd = 0 never settles (undamped), and
    is refused too.
    """
    if kind not in KINDS:
        raise InputError(f"controller must be one of {', '.join(KINDS)} (got {kind!r})")
    if kind == "none":
        if kp is not None or kd is not None:
            raise InputError("controller \"none\" (open loop) takes no gains")
        return Controller(kind, saturate=saturate)
    if kp is None or kd is None:
        raise InputError(f"controller {kind!r} needs both gains kp and kd")
    kp_, kd_ = _gains("kp", kp, width), _gains("kd", kd, width)
    for k, (p, d) in enumerate(zip(kp_, kd_)):
        if p > 0 and d == 0 and kind == "computed_torque":
            raise InputError(f"kd[{k}] is 0 with kp[{k}] = {p:g}: the error would oscillate "
                             "for ever (e'' + Kp e = 0); give some damping, e.g. kd = "
                             f"2 sqrt(kp) = {2 * np.sqrt(p):.4g} 1/s for critical damping")
        if p == 0 and d == 0:
            raise InputError(f"kp[{k}] and kd[{k}] are both 0: that joint has no feedback "
                             "(use controller = \"none\" for an open-loop run)")
    return Controller(kind, kp_, kd_, bool(saturate))
