"""The drive train: each actuated joint's gearbox, rotor and friction, as one part of the model.

Every consumer (dynamics checks, the torque split, joint loads, sizing, control, exports) reads
these figures from here, built from the robot's manifest and its current parameter vector, so
a gear ratio or a friction changed by ``with_parameters``, a study or a sweep reaches them all.

.. code:: text

    joint side    tau_j = (M qdd + h)_j          h includes the rotor's inertia and D_j
    friction      D_j(qd) = b qd_j + c tanh(qd_j / v_s)          N*m (N at a slider)
    motor side    tau_m = tau_j / N,   w_m = N qd_j              an ideal gearbox
    rotor         T_rotor = 1/2 J_m (w_parent + N qd_j)^2        (in M: N^2 J_m on the diagonal,
                                                                  N J_m coupling to the parent)

Figures are SI: ``rotor_inertia`` kg*m^2 about the motor axis, ``viscous`` N*m*s/rad (N*s/m),
``coulomb`` N*m (N), ``smoothing`` rad/s (m/s), joint-side like the friction they describe.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .description.types import COULOMB_SMOOTHING


@dataclass(frozen=True)
class Drive:
    """One actuated joint's drive: gear, rotor, friction and limits (SI, joint side)."""

    joint: str
    coordinate: int  # 0-based index into q
    unit: str  # "N*m" (revolute) or "N" (prismatic) at the joint
    gear_ratio: float  # motor rad per joint rad (per m at a slider)
    rotor_inertia: float  # kg*m^2
    viscous: float
    coulomb: float
    smoothing: float
    torque_limit: float | None  # at the joint
    motor_torque_limit: float | None  # N*m
    motor_speed_limit_rad_s: float | None
    modelled: bool  # the description gave an actuator model (gear, rotor or friction)

    @property
    def has_friction(self) -> bool:
        return self.viscous != 0.0 or self.coulomb != 0.0


@dataclass(frozen=True)
class DriveTrain:
    """Every actuated joint's ``Drive`` in ``actuated`` order, for a robot of ``n`` coordinates."""

    drives: tuple[Drive, ...]
    n: int

    @classmethod
    def of(cls, actuators, parameters: dict[str, float], n: int) -> DriveTrain:
        """From a manifest's ``actuators`` and the parameter values in use (name -> SI): the
        parameters ``gear_<joint>``, ``jm_<joint>``, ``fv_<joint>``, ``fc_<joint>`` and
        ``vs_<joint>`` win over the manifest's figures (they are what the compiled code uses)."""
        drives = []
        for act in actuators:
            j = act["joint"]
            drives.append(Drive(
                joint=j, coordinate=int(act["coordinate"]), unit=act["unit"],
                gear_ratio=float(parameters.get(f"gear_{j}", act.get("gear_ratio", 1.0))),
                rotor_inertia=float(parameters.get(f"jm_{j}", 0.0)),
                viscous=float(parameters.get(f"fv_{j}", 0.0)),
                coulomb=float(parameters.get(f"fc_{j}", 0.0)),
                smoothing=float(parameters.get(f"vs_{j}", COULOMB_SMOOTHING)),
                torque_limit=act.get("torque_limit"),
                motor_torque_limit=act.get("motor_torque_limit"),
                motor_speed_limit_rad_s=act.get("motor_speed_limit_rad_s"),
                modelled=bool(act.get("model", False))))
        return cls(tuple(drives), n)

    # -- per coordinate (n,) vectors: 0 (or 1 for ratios) where no drive --------------------------
    def _per_coordinate(self, field: str, default: float) -> np.ndarray:
        out = np.full(self.n, default)
        for d in self.drives:
            out[d.coordinate] = getattr(d, field)
        return out

    @property
    def viscous(self) -> np.ndarray:
        """b per coordinate, shape (n,)."""
        return self._per_coordinate("viscous", 0.0)

    @property
    def coulomb(self) -> np.ndarray:
        """c per coordinate, shape (n,)."""
        return self._per_coordinate("coulomb", 0.0)

    @property
    def smoothing(self) -> np.ndarray:
        """v_s per coordinate, shape (n,) (1 where no drive: any positive value does)."""
        return self._per_coordinate("smoothing", 1.0)

    @property
    def has_friction(self) -> bool:
        return any(d.has_friction for d in self.drives)

    @property
    def has_rotors(self) -> bool:
        return any(d.rotor_inertia != 0.0 for d in self.drives)

    def friction(self, qd) -> np.ndarray:
        """D(qd) = b qd + c tanh(qd / v_s) per coordinate, shape like ``qd`` (N, n) or (n,):
        N*m (N at a slider), the torque the joint's friction takes (0 without a drive)."""
        return self.viscous * qd + self.coulomb * np.tanh(qd / self.smoothing)

    def coulomb_slope(self, qd) -> np.ndarray:
        """d/dqd of the smoothed Coulomb friction, c / v_s sech^2(qd / v_s), per coordinate
        (shape like ``qd``): N*m*s/rad (N*s/m), the damping a linearisation counts it as, which
        holds only within about v_s of that rate (c / v_s at rest)."""
        return self.coulomb / self.smoothing * (1.0 - np.tanh(qd / self.smoothing) ** 2)

    def friction_power(self, qd) -> np.ndarray:
        """D(qd) . qd (W), the power friction dissipates (>= 0), shape (N,) or ()."""
        return np.sum(self.friction(qd) * qd, axis=-1)
