"""The control laws the simulation engine runs (in C), as data: what each computes at every
step. Their gains are designed and checked in ``planar_sym.control``.

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
    "lqr"              full-state feedback about an equilibrium (x = (q, qd)), on every
                       coordinate, passive ones included (a cart-pole's pole angle):
                       tau = u_ref + K (x_ref - x),  K from planar_sym.lqr; or along
                       a motion, x_ref, u_ref and K of time (planar_sym.tvlqr)
    "none"             open loop: only the input torques (a table, a profile, a constant)

With an exact model, computed torque makes every error obey ``e'' + Kd e' + Kp e = 0``: the
robot tracks a reference it starts on to the integrator's accuracy. The models (``g``,
``ID``) use the controller's parameters; the plant may differ (a model error).

Units: PD gains are N*m/rad and N*m*s/rad (N/m and N*s/m at a slider); computed-torque gains
are 1/s^2 and 1/s (Kp = w^2 and Kd = 2 zeta w give a natural frequency w and damping zeta).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..motion.signals import Signal

KINDS = ("pd", "computed_torque", "lqr", "none")
MODE = {"none": 0, "pd": 1, "computed_torque": 2, "lqr": 3}


@dataclass(frozen=True)
class Controller:
    """A control law and its gains, one per actuated coordinate (SI).

    Make one with ``planar_sym.controller`` (which checks the gains).

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
    gain, x_ref, u_ref : tuple of float
        "lqr" only: K (actuated x 2n, row-major; N*m per rad, per rad/s...), the state it
        holds (2n: q then qd) and the torques that hold it there (actuated).
    schedule : Signal or None
        "lqr" along a motion (``planar_sym.tvlqr``): x_ref (2n), u_ref (actuated) and K
        (actuated x 2n, row-major) as functions of time, channels in that order; its last
        segment is constant (the end held). Replaces gain, x_ref and u_ref.
    """

    kind: str
    kp: tuple[float, ...] = ()
    kd: tuple[float, ...] = ()
    saturate: bool = True
    gain: tuple[float, ...] = ()
    x_ref: tuple[float, ...] = ()
    u_ref: tuple[float, ...] = ()
    schedule: Signal | None = None

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
