"""The limits an optimal motion respects, checked once for both (``time_optimal``,
``optimal_move``): torque limits per motor, N*m (N at a slider), from the caller or the
description's; speed limits per coordinate, rad/s (m/s), from the caller or the description's
motors.

The description's limits are read through the drive train the dynamics uses (as sizing reads
them): a joint's torque limit is the tighter of its ``torque_limit`` and its motor's
``motor_torque_limit`` times the gear ratio |N| (an ideal gearbox: tau = N tau_m); a joint's
speed limit is its motor's ``motor_speed_limit_rpm`` divided by |N|."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..model.robot import Robot


def _per(name: str, given, size: int, what: str) -> np.ndarray:
    try:
        arr = np.asarray(given, dtype=float)
        return np.broadcast_to(arr, (size,)).copy()
    except (TypeError, ValueError):
        raise InputError(f"{name} must be one number or {size}, one per {what} (got "
                         f"{given!r})") from None


def torque_limits(robot: Robot, given, missing: str | None) -> np.ndarray | None:
    """``given`` (one number or one per actuated joint), else the description's; when neither
    exists, InputError(``missing``), or None where ``missing`` is None (no limit)."""
    na = len(robot.actuated)
    if given is None:
        given = description_torque_limits(robot)
        if any(v is None for v in given):
            if missing is None:
                return None
            raise InputError(missing)
    lim = _per("torque_limit", given, na, "actuated joint")
    if not np.all(np.isfinite(lim)) or np.any(lim <= 0):
        raise InputError(f"torque_limit must be positive and finite, got {lim.tolist()}")
    return lim


def speed_limits(robot: Robot, given) -> np.ndarray:
    """``given`` (one number or one per coordinate), each positive."""
    v = _per("speed_limit", given, robot.n, "coordinate")
    if not np.all(v > 0):
        raise InputError(f"speed_limit must be positive, got {v.tolist()}")
    return v


def description_torque_limits(robot: Robot) -> list[float | None]:
    """Per actuated joint, N*m (N): the tighter of the joint's limit and its motor's through the
    gear; None where the description gives neither."""
    out = []
    for act, drive in zip(robot.actuators, robot.drive_train.drives):
        motor = act.get("motor_torque_limit")
        given = [v for v in (act.get("torque_limit"),
                             None if motor is None else abs(drive.gear_ratio) * motor)
                 if v is not None]
        out.append(min(given) if given else None)
    return out


def description_speed_limits(robot: Robot) -> np.ndarray | None:
    """Per coordinate, rad/s (m/s): the motor's speed limit over |N| where the description gives
    one, inf elsewhere; None where no motor has one."""
    v = np.full(robot.n, np.inf)
    for act, drive in zip(robot.actuators, robot.drive_train.drives):
        if act.get("motor_speed_limit_rad_s") is not None:
            v[act["coordinate"]] = act["motor_speed_limit_rad_s"] / abs(drive.gear_ratio)
    return v if np.isfinite(v).any() else None
