"""Argument checks shared by the motion profiles: each refusal names the value at fault."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .profiles import _floats


def duration(duration_s, what: str = "trajectory duration") -> float:
    """``duration_s`` as a float: a positive, finite number of seconds."""
    if isinstance(duration_s, bool) or not isinstance(duration_s, (int, float, np.number)) \
            or not np.isfinite(duration_s) or duration_s <= 0:
        raise InputError(f"{what} must be a positive number of seconds (got {duration_s!r})")
    return float(duration_s)


def times(t_s, t0: float, t1: float, what: str = "trajectory") -> np.ndarray:
    """Evaluation times (s), 1-D, finite and inside [t0, t1]; names the first one outside."""
    if np.ndim(t_s) > 1:
        raise InputError(f"trajectory times must be a 1-D array (got shape {np.shape(t_s)})")
    t = _floats("times", t_s)
    bad = ~np.isfinite(t) | (t < t0) | (t > t1)
    if bad.any():
        k = int(np.argmax(bad))
        if not np.isfinite(t[k]):
            raise InputError(f"time t = {t[k]} s (sample {k}) is not finite")
        raise InputError(f"time t = {t[k]} s (sample {k}) is outside the {what} "
                         f"[{t0:.6g}, {t1:.6g}] s")
    return t


def start_and_step(x0, dx) -> tuple[np.ndarray, np.ndarray]:
    """Start and displacement as flat float arrays of one length, finite."""
    x0, dx = _floats("start", x0), _floats("displacement", dx)
    if x0.shape != dx.shape:
        raise InputError(f"x0 and dx must have the same length (got {x0.size} and {dx.size})")
    if x0.size == 0:
        raise InputError("trajectory start and displacement need at least one channel")
    for name, v in (("start", x0), ("displacement", dx)):
        if not np.all(np.isfinite(v)):
            raise InputError(f"trajectory {name} must be finite (got {v.tolist()})")
    return x0, dx
