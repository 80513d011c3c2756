"""Sweeps' motor-side figures: per actuator and design, peak and RMS motor torque (with each
design's own gear ratio), peak motor speed and peak power, as ``dynamics.sizing`` gives them for
one run (the trapezoidal RMS, the per-sample product tau qd)."""

from __future__ import annotations

import numpy as np

from ..dynamics.series import coordinate_unit
from ..dynamics.sizing import RPM, rms_weights
from ..model.robot import Robot
from .figures import Figure

#: designs per numpy pass of the motor-side figures (their torques at every sample, designs x
#: samples x coordinates): a few hundred keep a pass in cache
MOTOR_CHUNK = 256


def has_drives(robot: Robot) -> bool:
    """Whether the description models an actuator (``[joints.actuator]``: a gear, a rotor or
    friction). Without one every gear ratio is 1 and the motor figures would repeat the joint's."""
    return any(d.modelled for d in robot.drive_train.drives)


def gear_ratios(robot: Robot, P: np.ndarray) -> np.ndarray:
    """Each design's gear ratio per actuator, shape (D, actuated), dimensionless (motor rad per
    joint rad, per m at a slider): its ``gear_<joint>`` parameter where the robot has one (what
    the compiled code and ``DriveTrain.of`` use), else the description's figure (1 without an
    actuator model). ``P``: the designs' parameter vectors, shape (D, parameters), SI."""
    names = [par.name for par in robot.parameter_list]
    out = np.empty((len(P), len(robot.actuated)))
    for k, drive in enumerate(robot.drive_train.drives):
        key = f"gear_{drive.joint}"
        out[:, k] = P[:, names.index(key)] if key in names else drive.gear_ratio
    return out


def motor_figure_keys(i: int) -> tuple[Figure, Figure, Figure, Figure]:
    """The motor-side figures of coordinate ``i`` (0-based): peak and RMS motor torque
    (N*m, also behind a slider's screw: ``peak_motor_tau<k>_n_m``), peak motor speed (rpm),
    peak power (W)."""
    return (Figure.of("peak", "motor_tau", "N*m", i), Figure.of("rms", "motor_tau", "N*m", i),
            Figure.of("peak", "motor_speed", "rpm", i), Figure.of("peak", "power", "W", i))


def peak_torque(robot: Robot, i: int) -> Figure:
    """The figure of coordinate ``i``'s peak joint torque (N*m; N at a slider)."""
    return Figure.of("peak", "tau", coordinate_unit("tau", robot.coordinate_units[i]), i)


def motor_figures(robot: Robot, fn, P: np.ndarray, motion: tuple, t: np.ndarray,
                   joint: dict[Figure, np.ndarray]) -> dict[Figure, np.ndarray]:
    """Motor-side figures of the designs ``P`` along ``motion`` (q, qd, qdd: (N, n) shared or
    (D, N, n) per design): the torques again at every sample, ``MOTOR_CHUNK`` designs at a
    time, for the trapezoidal RMS and the peak power |tau qd| (a per-sample product the C
    loop's reduction cannot give); the peak motor torque from the joint's peak (``joint``)."""
    closed = robot.is_closed_chain
    q, qd, qdd = motion
    per_design = q.ndim == 3
    D, act = len(P), list(robot.actuated)
    ratios = gear_ratios(robot, P)
    w = rms_weights(t)
    ms, power = np.empty((D, len(act))), np.empty((D, len(act)))
    for s in range(0, D, MOTOR_CHUNK):
        sl = slice(s, s + MOTOR_CHUNK)
        args = (q[sl], qd[sl], qdd[sl]) if per_design else (q, qd, qdd)
        out = fn.designs(P[sl], *args)
        tau = out[0] if closed else out  # closed: the actuated torques; tree: every coordinate
        for k, i in enumerate(act):
            tk = tau[:, :, k if closed else i]  # (d, N), strided: each product below is new
            p = tk * args[1][..., i]  # the product sizing takes: tau * qd
            power[sl, k] = np.abs(p, out=p).max(axis=1)
            ms[sl, k] = np.square(tk) @ w
    speed = np.abs(qd[..., act]).max(axis=-2)  # (actuated,) shared, (D, actuated) per design
    figs = {}
    for k, i in enumerate(act):
        peak_t, rms_t, peak_w, peak_p = motor_figure_keys(i)
        peak = joint[peak_torque(robot, i)]
        figs[peak_t] = peak / ratios[:, k]
        figs[rms_t] = np.sqrt(ms[:, k]) / ratios[:, k]
        figs[peak_w] = speed[..., k] * ratios[:, k] * RPM
        figs[peak_p] = power[:, k]
    return figs
