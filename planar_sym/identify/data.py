"""One experiment's measurements as identification uses them: times, every coordinate with its
rate and acceleration, and the actuated torques, all SI.

Measured data usually hold positions and torques only: ``experiment`` then low-pass filters the
positions forward and backward (zero phase, SciPy's ``butter`` and ``filtfilt``), differentiates
them twice by central differences, and filters the torques the same way (so both sides of
``tau = Y pi`` see the same filter: *parallel filtering*), and it says so in ``notes``. A closed
chain's passive coordinates, when not given, are solved from the actuated ones on the loops.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..model.arrays import as_samples
from ..model.robot import Robot
from ..motion.closure import complete_rates, solve_passive

#: filter order of the zero-phase Butterworth low-pass (``filtfilt`` doubles it)
FILTER_ORDER = 4
#: time dropped at each end after filtering and differentiating, in periods of the cutoff
#: frequency: filtfilt's padding keeps q and qd continuous at the ends but not qdd, whose error
#: decays from about the signal's size to 1e-4 of it over 4 such periods (measured)
EDGE_PERIODS = 4.0
#: the default cutoff: this many times the highest frequency the positions carry
#: (``signal_band``), at most a tenth of the sampling rate. A cutoff far above the signal lets
#: through noise that differentiating twice amplifies, and noise in the accelerations (the
#: regressor's errors in variables) pulls the inertias towards zero: a trial's 6 s excitation,
#: nothing above 0.5 Hz, 16-bit encoders, 1 % torque noise: at the former default fs / 10 =
#: 20 Hz the shoulder's inertia came out 7.7 % low (3.9 standard deviations, every noise seed);
#: at 10 times the band (6.7 Hz) 0.2 % (0.1 of them)
BAND_FACTOR = 10.0
#: the signal's band: the frequency below which this share of the positions' power about their
#: mean lies (Hann window; the excitations' highest harmonic shows there for any share from
#: 0.999 to 1 - 1e-6, white encoder noise holds far less)
BAND_SHARE = 0.9999
#: after filtering, samples are kept at this multiple of the cutoff frequency (decimation):
#: filtered noise is correlated over about 1 / (2 cutoff), and the standard deviations of the
#: estimate assume independent residuals (Gautier's parallel filtering and decimation)
KEEP_RATE = 2.0


@dataclass(frozen=True)
class Experiment:
    """Measurements of one run: ``t_s`` (N,), ``q``, ``qd``, ``qdd`` (N, n) every coordinate
    (rad, rad/s, rad/s^2; m at a slider), ``tau`` (N, actuated) at the actuated coordinates
    (N*m; N at a slider); ``name`` where they came from (a file); ``notes`` say what was done
    to them."""

    t_s: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray
    name: str = ""
    notes: tuple[str, ...] = field(default_factory=tuple)

    def __len__(self) -> int:
        return len(self.t_s)


def experiment(robot: Robot, t, q, tau, qd=None, qdd=None, *, cutoff_hz: float | None = None,
               name: str = "") -> Experiment:
    """An ``Experiment`` from arrays (SI): ``t`` (N,) s; ``q`` every coordinate (N, n) or, for
    a closed chain, the actuated ones (N, actuated); ``tau`` (N, actuated); ``qd``, ``qdd``
    (N, n) where measured (else filtered and differentiated, ``cutoff_hz`` the low-pass
    corner, default ``BAND_FACTOR`` times the positions' band (``signal_band``), at most a
    tenth of the sampling rate)."""
    where = f"{name}: " if name else ""
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or len(t) < 3 or not np.all(np.isfinite(t)):
        raise InputError(f"{where}t must be at least 3 finite times (s), got shape {t.shape}")
    steps = np.diff(t)
    if not np.all(steps > 0):
        k = int(np.argmax(~(steps > 0)))
        raise InputError(f"{where}times must increase: t[{k + 1}] = {t[k + 1]:.6g} s after "
                         f"t[{k}] = {t[k]:.6g} s")
    na = len(robot.actuated)
    tau = as_samples(f"{where}tau", tau, na, times=t)
    q = np.asarray(q, dtype=float)
    notes = []
    if robot.is_closed_chain and q.ndim == 2 and q.shape[1] == na != robot.n:
        q_act = as_samples(f"{where}q", q, na, times=t)
        q = solve_passive(robot, q_act, t=t)
        notes.append("passive coordinates solved from the actuated ones on the loops")
    q = as_samples(f"{where}q", q, robot.n, times=t)
    if len(q) != len(t) or len(tau) != len(t):
        raise InputError(f"{where}t, q and tau must have the same number of samples, got "
                         f"{len(t)}, {len(q)}, {len(tau)}")
    if qd is not None and qdd is not None:
        qd, qdd = (as_samples(f"{where}{k}", a, robot.n, times=t)
                   for k, a in (("qd", qd), ("qdd", qdd)))
        return Experiment(t, q, qd, qdd, tau, name, tuple(notes))
    fs = 1.0 / float(np.median(steps))
    if not np.allclose(steps, 1.0 / fs, rtol=1e-6, atol=0):
        raise InputError(f"{where}filtering and differentiating needs evenly spaced times; "
                         f"the steps range from {steps.min():.6g} to {steps.max():.6g} s")
    band = signal_band(q, fs)
    by_band = cutoff_hz is None and 0 < BAND_FACTOR * band < fs / 10
    if cutoff_hz is not None:
        cutoff, chosen = float(cutoff_hz), "as asked"
    elif by_band:
        cutoff = BAND_FACTOR * band
        chosen = f"{BAND_FACTOR:g} times the positions' band, {band:.3g} Hz"
        # a short record cannot spare the ends a low corner drops: the lowest corner it can
        shortest = EDGE_PERIODS * fs / ((len(t) - 1) / 3 - 2)
        if cutoff < shortest:
            cutoff = min(fs / 10, shortest)
            chosen += f", raised to {cutoff:.3g} Hz: the record is too short for lower"
    else:
        cutoff, chosen = fs / 10, "a tenth of the sampling rate"
    if not 0 < cutoff < fs / 2:
        raise InputError(f"{where}cutoff_hz must be between 0 and half the sampling rate "
                         f"({fs / 2:.6g} Hz), got {cutoff_hz}")
    edge = int(np.ceil(EDGE_PERIODS * fs / cutoff - 1e-9)) + 1  # (fs from a median step)
    if len(t) <= 3 * edge:
        raise InputError(f"{where}{len(t)} samples are too few to filter at {cutoff:.4g} Hz and "
                         f"differentiate: {edge} are dropped at each end (the filter's edge "
                         f"effects), so more than {3 * edge} are needed")
    from scipy.signal import butter, filtfilt

    b, a = butter(FILTER_ORDER, cutoff / (fs / 2))
    qf = filtfilt(b, a, q, axis=0)
    qd = np.gradient(qf, t, axis=0)
    qdd = np.gradient(qd, t, axis=0)
    tf = filtfilt(b, a, tau, axis=0)
    step = max(1, int(fs // (KEEP_RATE * cutoff)))
    keep = slice(edge, len(t) - edge, step)
    qf, qd, qdd = qf[keep], qd[keep], qdd[keep]  # (decimated after differentiating)
    if robot.is_closed_chain:  # differentiated coordinates leave the loops: project the rates
        act = list(robot.actuated)
        qf = solve_passive(robot, qf[:, act], q_guess=qf[0], t=t[keep])
        qd, qdd = complete_rates(robot, qf, qd[:, act], qdd[:, act])
    notes.append(f"positions and torques low-pass filtered at {cutoff:.4g} Hz ({chosen}; "
                 f"Butterworth, "
                 f"order {FILTER_ORDER}, forward and backward: zero phase); rates and "
                 f"accelerations by central differences; {edge} samples ({edge / fs:.3g} s) dropped at "
                 f"each end; every {step} kept ({fs / step:.4g} Hz, {KEEP_RATE:g} times the cutoff: the "
                 "filtered noise stays about independent from sample to sample)")
    return Experiment(t[keep], qf, qd, qdd, tf[keep], name, tuple(notes))


def signal_band(q: np.ndarray, fs: float) -> float:
    """The highest frequency (Hz) the positions ``q`` (N, n), sampled at ``fs`` Hz, carry: per
    coordinate the frequency below which ``BAND_SHARE`` of its power about its mean lies (Hann
    window), the largest over the coordinates that move (0 where none does)."""
    x = q - q.mean(axis=0)
    power = np.abs(np.fft.rfft(x * np.hanning(len(x))[:, None], axis=0)) ** 2
    total = power.sum(axis=0)
    freq = np.fft.rfftfreq(len(x), 1.0 / fs)
    moving = total > 0
    if not np.any(moving):
        return 0.0
    share = np.cumsum(power[:, moving], axis=0) / total[moving]
    return float(max(freq[np.argmax(col >= BAND_SHARE)] for col in share.T))
