"""Actuator sizing along an inverse-dynamics motion: what each motor and gearbox must deliver.

Per actuated joint, from its torque tau(t) (N*m; N for a prismatic joint) and rate qd(t) at
the joint, and its actuator's gear ratio N (1 where the description gives no actuator):

.. code:: text

    motor torque  tau_m = tau / N        (an ideal gearbox: no loss beyond the friction
    motor speed   w_m   = N qd            the description gives at the joint)
    power         P     = tau qd   (W)    = tau_m w_m
    RMS           sqrt(1/T int tau^2 dt)  (trapezoidal rule over the samples)
    energy        int P dt  (J)           net work delivered over the motion

A limit the description gives (``torque_limit``, ``motor_torque_limit``,
``motor_speed_limit_rpm``) that the motion exceeds is reported with the first time it is
exceeded and the peak, never silently.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.drive import DriveTrain

RPM = 60.0 / (2.0 * math.pi)  # rad/s -> rpm
#: the trapezoidal rule: numpy 2 renamed trapz (numpy >= 1.26 is supported)
_trapezoid = getattr(np, "trapezoid", None) or np.trapz


@dataclass(frozen=True)
class ActuatorSizing:
    """What one actuator must deliver over a motion (SI; ``unit`` is N*m or N at the joint).

    Attributes
    ----------
    joint : str
        The actuated joint's name.
    coordinate : int
        Its coordinate (0-based index into q).
    unit : str
        ``"N*m"`` (revolute) or ``"N"`` (prismatic): the joint-side torque's unit.
    gear_ratio : float
        N: motor speed / joint speed (1 without an actuator model).
    peak_torque, rms_torque : float
        Largest |tau| and the RMS (trapezoidal rule) at the joint, in ``unit``.
    peak_motor_torque_n_m, rms_motor_torque_n_m : float
        The same at the motor, tau / N (N*m; through a screw at a slider).
    peak_speed : float
        Largest |qd| at the joint (rad/s; m/s at a slider).
    peak_motor_speed_rad_s : float
        Largest motor speed N |qd| (rad/s); ``peak_motor_speed_rpm`` in rpm.
    peak_power_w, mean_power_w : float
        Largest |tau qd| and the net energy over the duration (W).
    energy_j : float
        Net work delivered over the motion (J).
    exceeded : tuple of str
        One sentence per limit of the description the motion exceeds, with the first time.
    """

    joint: str
    coordinate: int  # 0-based index into q
    unit: str  # "N*m" (revolute) or "N" (prismatic)
    gear_ratio: float
    peak_torque: float  # at the joint, N*m or N
    rms_torque: float
    peak_motor_torque_n_m: float  # tau / N (N*m: for a prismatic joint, through a screw)
    rms_motor_torque_n_m: float
    peak_speed: float  # at the joint, rad/s or m/s
    peak_motor_speed_rad_s: float
    peak_power_w: float  # largest |tau qd|
    mean_power_w: float  # net energy / duration
    energy_j: float  # net work over the motion
    exceeded: tuple[str, ...] = ()  # one sentence per limit exceeded, with the time

    @property
    def peak_motor_speed_rpm(self) -> float:
        """The largest motor speed in rpm."""
        return self.peak_motor_speed_rad_s * RPM


#: a value this far (relative) above its limit is on it, not over it: an optimal motion rides
#: its limits to its solver's accuracy (IPOPT's constraint violation, about 1e-8)
ON_LIMIT = 1e-6


def rms_weights(t: np.ndarray) -> np.ndarray:
    """w (N,) with w @ v**2 the mean square of v(t) over the samples' times t (s) by the
    trapezoidal rule: the one RMS of every figure (a run's sizing, a sweep's columns; a trial
    found a sweep's plain mean 1e-3 off it on a fast move). The plain mean over one sample or
    no time span."""
    t = np.asarray(t, dtype=float)
    span = t[-1] - t[0] if len(t) > 1 else 0.0
    if span <= 0:
        return np.full(len(t), 1.0 / len(t))
    dt = np.diff(t)
    w = np.zeros(len(t))
    w[:-1] += dt / 2
    w[1:] += dt / 2
    return w / span


def rms(t: np.ndarray, v: np.ndarray) -> float:
    """The RMS of v(t) (``rms_weights``): t (N,) in s, v (N,) in any unit (N*m, N, rad); the
    result in v's unit."""
    return float(np.sqrt(rms_weights(t) @ (np.asarray(v, dtype=float) ** 2)))


def _first_over(t: np.ndarray, v: np.ndarray, limit: float | None, what: str,
                unit: str, scale: float = 1.0) -> list[str]:
    """The sentence for a limit ``v`` exceeds (|v| > limit beyond ``ON_LIMIT``), or nothing."""
    if limit is None:
        return []
    over = np.abs(v) > limit * (1 + ON_LIMIT)
    if not over.any():
        return []
    k = int(np.argmax(over))
    peak = int(np.argmax(np.abs(v)))
    return [(f"{what} exceeds its limit {limit * scale:.4g} {unit} from t = {t[k]:.6g} s "
             f"(sample {k}); peak {abs(v[peak]) * scale:.4g} {unit} at t = {t[peak]:.6g} s")]


def size(robot, t_s: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> tuple[ActuatorSizing, ...]:
    """Sizing of every actuator of ``robot`` along a motion.

    Parameters
    ----------
    robot : Robot
    t_s : ndarray, shape (N,)
        Time (s).
    qd : ndarray, shape (N, n)
        Every coordinate's rate (rad/s; m/s for a prismatic joint).
    tau : ndarray, shape (N, actuated)
        The actuated joints' torques (N*m) or forces (N), in ``robot.actuated`` order.
    """
    t = np.asarray(t_s, dtype=float)
    out = []
    # the drive train as the dynamics sees it (a gear_<joint> parameter wins over the file)
    drives = DriveTrain.of(robot.actuators, robot.parameters, np.shape(qd)[-1]).drives
    for k, act in enumerate(robot.actuators):
        i = act["coordinate"]
        ratio = drives[k].gear_ratio
        tq, w = tau[:, k], qd[:, i]
        power = tq * w
        energy = float(_trapezoid(power, t)) if len(t) > 1 else 0.0
        span = t[-1] - t[0] if len(t) > 1 else 0.0
        unit = act["unit"]
        exceeded = (_first_over(t, tq, act["torque_limit"], f"{act['joint']}: joint "
                                f"{'force' if unit == 'N' else 'torque'}", unit)
                    + _first_over(t, tq / ratio, act["motor_torque_limit"],
                                  f"{act['joint']}: motor torque", "N*m")
                    + _first_over(t, ratio * w, act["motor_speed_limit_rad_s"],
                                  f"{act['joint']}: motor speed", "rpm", RPM))
        peak, root, speed = float(np.max(np.abs(tq))), rms(t, tq), float(np.max(np.abs(w)))
        out.append(ActuatorSizing(
            joint=act["joint"], coordinate=i, unit=unit, gear_ratio=float(ratio),
            peak_torque=peak, rms_torque=root, peak_motor_torque_n_m=peak / ratio,
            rms_motor_torque_n_m=root / ratio, peak_speed=speed,
            peak_motor_speed_rad_s=speed * ratio,
            peak_power_w=float(np.max(np.abs(power))),
            mean_power_w=float(energy / span) if span > 0 else 0.0,
            energy_j=energy, exceeded=tuple(exceeded)))
    return tuple(out)


def table(sizing: tuple[ActuatorSizing, ...], events=()) -> str:
    """A Markdown table of the sizing, one row per actuator, units in the header. ``events``:
    a controlled run's (``Event``), whose actuator's are in its limits cell: its applied torque
    stays within by clipping, so "within" alone would read as "big enough" (a trial)."""
    if not sizing:
        return ""
    rows = [("| joint | gear | peak / RMS joint torque | peak / RMS motor torque (N*m) | "
             "peak joint speed | peak motor speed (rpm) | peak / mean power (W) | energy (J) | "
             "limits |"),
            "|---|---|---|---|---|---|---|---|---|"]
    for s in sizing:
        speed_unit = "m/s" if s.unit == "N" else "rad/s"
        said = [*s.exceeded, *dict.fromkeys(
            str(e) for e in events if f" {s.joint} " in f" {e.name} ")]
        limits = "; ".join(said) if said else "within"
        rows.append(f"| {s.joint} | {s.gear_ratio:.4g} | {s.peak_torque:.4g} / "
                    f"{s.rms_torque:.4g} {s.unit} | {s.peak_motor_torque_n_m:.4g} / "
                    f"{s.rms_motor_torque_n_m:.4g} | {s.peak_speed:.4g} {speed_unit} | "
                    f"{s.peak_motor_speed_rpm:.4g} | {s.peak_power_w:.4g} / "
                    f"{s.mean_power_w:.4g} | {s.energy_j:.4g} | {limits} |")
    return "\n".join(rows)
