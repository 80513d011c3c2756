"""The limits an optimal motion respects, checked once for both (``time_optimal``,
``optimal_move``): torque limits per motor, N*m (N at a slider), from the caller or the
description's ``torque_limit``; speed limits per coordinate, rad/s (m/s)."""

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
        given = [a.get("torque_limit") for a in robot.actuators]
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
