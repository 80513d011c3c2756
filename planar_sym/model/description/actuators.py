"""Actuator models of actuated joints (``[joints.actuator]``): gearbox, rotor, friction, limits.

All optional; a joint without one is today's ideal torque (or force) source. In the equations:

.. code:: text

    T_rotor = 1/2 J_m (w_parent + N qd_j)^2        (rotor inertia J_m, gear ratio N; the
                                                    stator on the parent body)
    D_j(qd) = b qd_j + c tanh(qd_j / v_s)          (viscous b, Coulomb c smoothed over v_s)
    M(q) qdd + C qd + g + D(qd) = S^T tau          (tau at the joint)
    motor torque tau / N, motor speed N qd_j       (an ideal gearbox)
    current i = tau / (N k_t), electrical power R i^2 + tau qd   (torque constant k_t and
                                                    winding resistance R: a DC motor)

Figures are at the joint side, SI (N*m, N*m*s/rad; N, N*s/m for a prismatic joint, whose gear
ratio is motor radians per metre of travel, a screw's 2 pi / lead); the rotor inertia is in
``[units].inertia``. numpy-free: shared by derive and the runtime.
"""

from __future__ import annotations

import math

from ...spelling import unknown_keys
from ..units import UNITS
from .fields import Fields
from .quantities import ACTUATOR_QUANTITY, QUANTITIES, doubt
from .types import COULOMB_SMOOTHING, Actuator

#: keys of ``[joints.actuator]`` and what each holds (for messages)
ACTUATOR_KEYS = {
    "gear_ratio": "motor turns per joint turn (rad per m for a prismatic joint), > 0",
    "rotor_inertia": "rotor inertia about its axis, in [units].inertia, >= 0",
    "viscous_friction": "joint-side viscous friction, N*m*s/rad (N*s/m), >= 0",
    "coulomb_friction": "joint-side Coulomb friction, N*m (N), >= 0",
    "coulomb_smoothing": "speed over which Coulomb friction is smoothed, rad/s (m/s), > 0",
    "torque_limit": "largest joint torque (force), N*m (N), > 0",
    "motor_torque_limit": "largest motor torque, N*m, > 0",
    "motor_speed_limit_rpm": "largest motor speed, rpm, > 0",
    "torque_constant": "motor torque per ampere k_t, N*m/A, > 0",
    "winding_resistance": "motor winding resistance R, ohm, > 0",
    "notes": "free text",
}


class Actuators(Fields):
    """The actuator stage of the validator (one joint's ``actuator`` table)."""

    def _actuator(self, raw: dict, f: str, jtype, actuated, scale) -> Actuator | None:
        if "actuator" not in raw:
            return None
        a = raw["actuator"]
        f = f"{f}.actuator"
        if not isinstance(a, dict):
            self.err(f, "must be a table of actuator figures ([joints.actuator])")
            return None
        if actuated is False:
            self.err(f, "only an actuated joint has an actuator (actuated = true)")
            return None
        unknown_keys(a, ACTUATOR_KEYS, lambda key, msg: self.err(f"{f}.{key}", msg))
        values: dict[str, float] = {}
        slider = jtype == "prismatic"
        for key, meaning in ACTUATOR_KEYS.items():
            if key == "notes" or key not in a:
                continue
            v = self._num(a, key, f"{f}.{key}")
            if v is None:
                continue
            q = QUANTITIES[ACTUATOR_QUANTITY[key][slider]]
            units = self.data.get("units")
            unit = units.get("inertia") if key == "rotor_inertia" and isinstance(units, dict) \
                else None
            unit = unit if isinstance(unit, str) and unit in UNITS["inertia"] else None
            if (msg := q.error(v, unit)) is not None:
                self.err(f"{f}.{key}", f"{msg}: {meaning}")
                continue
            if (doubtful := doubt(q, v, unit)) is not None:
                self.warn(f"{f}.{key}", doubtful)
            values[key] = v
        for key, other in (("torque_constant", "winding_resistance"),
                           ("winding_resistance", "torque_constant")):
            if key in values and other not in a:  # the copper losses need both
                self.err(f"{f}.{key}", f"only with {other} (the winding's losses R (tau_m / "
                                       "k_t)^2 need both)")
        if "coulomb_smoothing" in values and "coulomb_friction" not in a:
            self.err(f"{f}.coulomb_smoothing", "only with coulomb_friction (it smooths it)")
        inertia = scale.get("inertia")
        if "rotor_inertia" in values and inertia is not None:
            values["rotor_inertia"] *= inertia
            self._rotor_against_motor(f, a["rotor_inertia"], values)
        if "rotor_inertia" in a and "gear_ratio" not in a and jtype == "prismatic":
            self.err(f"{f}.rotor_inertia", "a prismatic joint's rotor needs gear_ratio (rad of "
                                           "motor per m of travel) to move with the slide")
        rpm = values.pop("motor_speed_limit_rpm", None)
        return Actuator(
            gear_ratio=values.get("gear_ratio", 1.0),
            rotor_inertia_kg_m2=values.get("rotor_inertia", 0.0),
            viscous=values.get("viscous_friction", 0.0),
            coulomb=values.get("coulomb_friction", 0.0),
            smoothing=values.get("coulomb_smoothing", COULOMB_SMOOTHING),
            torque_limit=values.get("torque_limit"),
            motor_torque_limit=values.get("motor_torque_limit"),
            motor_speed_limit_rad_s=None if rpm is None else rpm * 2.0 * math.pi / 60.0,
            torque_constant=values.get("torque_constant"),
            winding_resistance=values.get("winding_resistance"),
            given=frozenset(a) - {"notes"})

    def _rotor_against_motor(self, f: str, typed: float, values: dict) -> None:
        """A rotor inertia its own motor could not plausibly turn: the motor torque limit
        over J_m (rad/s^2, the unloaded rotor's acceleration) outside ROTOR_ACCELERATION, a
        unit slip (a trial: a kg*cm^2 catalogue figure typed in g*mm^2 made the motor torque
        3.7 times too low, typed in kg*m^2 a 65 kN*m crank torque, both with no word)."""
        j, limit = values["rotor_inertia"], values.get("motor_torque_limit")
        lo, hi = ROTOR_ACCELERATION
        if not j or limit is None or lo <= limit / j <= hi:
            return
        unit = self.data["units"]["inertia"]
        fits = {u: limit / (typed * k) for u, k in UNITS["inertia"].items()
                if u != unit and lo <= limit / (typed * k) <= hi}
        hint = "; ".join(f"in {u} it would be {a:.3g} rad/s^2" for u, a in fits.items())
        si = "" if unit == "kg*m^2" else f" = {j:.3g} kg*m^2"
        self.warn(f"{f}.rotor_inertia",
                  f"{typed:g} {unit}{si} against a motor torque limit of {limit:g} N*m: the "
                  f"motor would turn its own rotor at {limit / j:.3g} rad/s^2 unloaded "
                  f"(catalogue motors: about 3e3 to 2e5; warned outside {lo:g} to {hi:g}): a "
                  "unit slip?" + (f" ({hint})" if hint else ""))


#: rad/s^2: the plausible range of a motor's torque limit over its rotor inertia (catalogue
#: motors, from micro motors to servo and torque motors, lie between about 3e3 and 2e5)
ROTOR_ACCELERATION = (1e2, 1e7)

