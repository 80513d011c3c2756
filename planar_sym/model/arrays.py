"""Per-sample input arrays checked at the door: shape, real, finite, the bad sample named.

Every runtime function that takes q, qd, qdd or tau passes them through ``as_samples`` (a
trajectory) or ``as_vector`` (one state), so a wrong shape or a NaN is refused with the array's
name, the sample and its time before any compiled code sees it.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def when(t, k: int) -> str:
    """``"t = 0.25 s (sample 5)"``, or ``"sample 5"`` without times: how a refusal names a
    sample."""
    return f"t = {t[k]:.6g} s (sample {k})" if t is not None else f"sample {k}"


def as_vector(name: str, a, width: int) -> np.ndarray:
    """``a`` as one finite float64 vector of ``width`` values: (width,) or (1, width) only,
    never the first row of several (a second initial state is a mistake to report).

    Units are the caller's (the values are not converted: SI throughout the package); a bad
    shape or a non-finite value raises InputError naming ``name``. Returns shape (width,).
    """
    arr = as_samples(name, a, width)
    if len(arr) != 1:
        raise InputError(f"{name} must be one vector of {width} values, got {len(arr)} rows "
                         f"(shape {np.shape(a)})")
    return arr[0].copy()


def as_samples(name: str, a, width: int, *, times: np.ndarray | None = None) -> np.ndarray:
    """``a`` as a C-contiguous float64 (N, width) array; names the first bad sample.

    ``a`` is (N, width) or (width,) (one sample); its values are kept as given (SI
    throughout the package, not converted). ``times`` (N,), in s, lets the error name the
    time of a non-finite sample too.
    """
    try:
        raw = np.asarray(a)
        complex_ = np.iscomplexobj(raw)
        arr = raw.astype(np.float64, copy=False) if not complex_ else raw
    except (TypeError, ValueError, OverflowError) as exc:
        raise InputError(f"{name} must be an array of numbers of shape (N, {width}) or "
                         f"({width},): {exc}") from None
    if complex_:
        raise InputError(f"{name} must be real, got complex values")
    if raw.dtype == np.bool_:  # True read as 1 rad, 1 N*m (a trial): a description refuses it
        raise InputError(f"{name} must be numbers, got booleans (True/False)")
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != width:
        raise InputError(f"{name} must have shape (N, {width}) or ({width},), "
                         f"got {np.shape(a)}")
    # a finite sum means every entry is finite (one pass, no mask); an inf or NaN sum may be
    # an overflow of finite values, so only then is the mask built
    with np.errstate(over="ignore", invalid="ignore"):  # the fallback below decides
        total = arr.sum()
    if not np.isfinite(total) and (bad := ~np.isfinite(arr)).any():
        k, col = np.argwhere(bad)[0]
        when_ = f" (t = {times[k]:.6g} s)" if times is not None and k < len(times) else ""
        raise InputError(f"{name}[{k}, {col}] is {arr[k, col]} at sample {k}{when_}: "
                         "inputs must be finite")
    return np.ascontiguousarray(arr)


def as_times(t, samples: int, of: str) -> np.ndarray:
    """Sample times ``t`` (N,) or (N, 1) in s as a float64 (N,) array, each finite, one for
    each of the ``samples`` samples of the array named ``of``."""
    t = as_samples("t", np.reshape(t, (-1, 1)) if np.ndim(t) == 1 else t, 1)[:, 0]
    if len(t) != samples:
        raise InputError(f"t has {len(t)} times for {samples} samples of {of}")
    return t


def as_sample_set(width_of: dict[str, int], arrays: dict, *,
                  times: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
    """Several arrays of one trajectory checked together: each as ``as_samples`` checks it
    (``width_of[name]`` columns), and all with the same number of samples, which a refusal
    names. Returns them in ``arrays``' order, each C-contiguous float64 (N, width)."""
    out = tuple(as_samples(name, a, width_of[name], times=times) for name, a in arrays.items())
    sizes = {name: len(a) for name, a in zip(arrays, out)}
    if len(set(sizes.values())) > 1:
        raise InputError(f"{', '.join(sizes)} must have the same number of samples, got "
                         + ", ".join(f"{k}: {v}" for k, v in sizes.items()))
    return out


def as_state(q0, qd0, width: int) -> tuple[np.ndarray, np.ndarray]:
    """An initial state checked at the door: ``q0`` and ``qd0`` as ``as_vector`` checks them
    (``width`` values each; ``qd0`` None means at rest)."""
    q0 = as_vector("q0", q0, width)
    return q0, (np.zeros(width) if qd0 is None else as_vector("qd0", qd0, width))
