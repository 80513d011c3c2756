"""Which designs of a sweep break an actuator limit, and how: the limits ``dynamics.sizing``
checks for one run (joint torque, motor torque, motor speed; the same ``ON_LIMIT`` margin), read
off each design's peaks at its own gear ratio.

A user trial: 9 of 12 designs of a gear-ratio sweep broke their motor's torque or speed limit
with no word in the table, the plot or the output, and the lowest peak motor torque belonged to
a design that overspeeds its motor by 68 %. Run alone, each design warned.
"""

from __future__ import annotations

import numpy as np

from ..dynamics.sizing import ON_LIMIT, RPM
from ..model.robot import Robot


def over_limits(robot: Robot, ratios: np.ndarray, peak_tau: np.ndarray,
                peak_speed: np.ndarray) -> dict[int, str]:
    """The designs (0-based, of this batch) whose peaks pass a limit, each with what it passes.

    Parameters
    ----------
    ratios : ndarray, shape (D, actuated)
        Each design's gear ratio per actuator (``sweep_motor.gear_ratios``).
    peak_tau : ndarray, shape (D, actuated)
        Largest |joint torque| (N*m; N at a slider) per design and actuator.
    peak_speed : ndarray, shape (D, actuated) or (actuated,)
        Largest |joint rate| (rad/s; m/s at a slider), per design or shared by all.
    """
    D = len(ratios)
    speed = np.broadcast_to(peak_speed, (D, len(robot.actuated)))
    out: dict[int, list[str]] = {}
    for k, d in enumerate(robot.drive_train.drives):
        what = "force" if d.unit == "N" else "torque"
        checks = ((d.torque_limit, peak_tau[:, k], 1.0, f"joint {what}", d.unit),
                  (d.motor_torque_limit, peak_tau[:, k] / ratios[:, k], 1.0, "motor torque",
                   "N*m"),
                  (d.motor_speed_limit_rad_s, speed[:, k] * ratios[:, k], RPM, "motor speed",
                   "rpm"))
        for limit, peak, scale, name, shown in checks:
            if limit is None:
                continue
            for j in np.flatnonzero(peak > limit * (1 + ON_LIMIT)):
                out.setdefault(int(j), []).append(
                    f"{d.joint}: {name} peak {peak[j] * scale:.4g} {shown} over its limit "
                    f"{limit * scale:.4g} {shown}")
    return {j: "; ".join(v) for j, v in sorted(out.items())}


def run_over_limits(result) -> str:
    """One run's limits passed, as one line, or "": a controlled run's events (commands beyond
    a torque limit, a motor too fast, a joint limit: its sizing would say the speed twice and
    never the clipped torque), else ``Result.sizing``'s sentences and any event."""
    said = [] if result.reference is not None else [s for a in result.sizing
                                                    for s in a.exceeded]
    said += [str(e) for e in result.events]
    return "; ".join(dict.fromkeys(said))
