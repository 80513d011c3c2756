"""Timing primitives: interleaved repeats, median with min-max, paired ratios.

Why interleaved and paired: the benchmark machine is shared (other processes come and go), so
an absolute time measured at 10:00:01 says little about one measured at 10:00:05. Every
figure is therefore measured *together with its baseline*: each repeat runs every candidate
once, in an order rotated from repeat to repeat, and a ratio is formed per repeat (candidate and
baseline of the same repeat saw nearly the same load) before taking the median and the min-max
of those per-repeat ratios. The garbage collector is off inside timed blocks (as in ``timeit``).
"""

from __future__ import annotations

import gc
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True)
class Stats:
    """Per-unit times (s) of the repeats of one measurement."""

    values: tuple[float, ...]

    @property
    def median(self) -> float:
        return statistics.median(self.values)

    @property
    def min(self) -> float:
        return min(self.values)

    @property
    def max(self) -> float:
        return max(self.values)

    def scaled(self, factor: float) -> Stats:
        return Stats(tuple(v * factor for v in self.values))


@dataclass(frozen=True)
class Ratio(Stats):
    """Per-repeat ratios a_i / b_i of two interleaved measurements (summarised like Stats)."""


def ratio(a: Stats, b: Stats) -> Ratio:
    """``a / b`` repeat by repeat (paired: both came from the same interleaved rounds)."""
    n = min(len(a.values), len(b.values))
    return Ratio(tuple(x / y for x, y in zip(a.values[:n], b.values[:n])))


def _block(fn: Callable[[], object], number: int) -> float:
    gc_was = gc.isenabled()
    gc.disable()
    try:
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        return time.perf_counter() - t0
    finally:
        if gc_was:
            gc.enable()


def calibrate(fn: Callable[[], object], min_block_s: float, max_number: int = 1_000_000) -> int:
    """Calls per timed block so that one block lasts at least ``min_block_s`` (after a warm-up)."""
    fn()
    number = 1
    while number < max_number:
        dt = _block(fn, number)
        if dt >= min_block_s:
            break
        grow = 10 if dt <= 0 else min(10.0, max(2.0, 1.2 * min_block_s / dt))
        number = int(number * grow) + 1
    return min(number, max_number)


def interleaved(fns: dict[str, Callable[[], object]], *, repeats: int, per: dict[str, float]
                | float = 1.0, min_block_s: float = 0.02) -> dict[str, Stats]:
    """Time every function ``repeats`` times, round-robin, rotating the order each round.

    ``per`` divides each block's time per call (e.g. the N samples of a batch call), so the
    result is seconds per unit. Each function is calibrated once to blocks of ``min_block_s``.
    """
    names = list(fns)
    numbers = {k: calibrate(fns[k], min_block_s) for k in names}
    out: dict[str, list[float]] = {k: [] for k in names}
    for r in range(repeats):
        order = names[r % len(names):] + names[:r % len(names)]
        for k in order:
            unit = per[k] if isinstance(per, dict) else per
            out[k].append(_block(fns[k], numbers[k]) / numbers[k] / unit)
    return {k: Stats(tuple(v)) for k, v in out.items()}


def once_each(fns: dict[str, Callable[[], object]], *, repeats: int) -> dict[str, Stats]:
    """Like ``interleaved`` with one call per block and no calibration: for slow things
    (subprocesses, compilations, whole simulations) whose single run is the unit."""
    names = list(fns)
    out: dict[str, list[float]] = {k: [] for k in names}
    for r in range(repeats):
        order = names[r % len(names):] + names[:r % len(names)]
        for k in order:
            out[k].append(_block(fns[k], 1))
    return {k: Stats(tuple(v)) for k, v in out.items()}


def fmt_time(s: float) -> str:
    """Seconds with a unit suited to the magnitude: ns, us, ms or s, 3 significant digits."""
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("us", 1e-6)):
        if abs(s) >= scale:
            return f"{s / scale:.3g} {unit}"
    return f"{s / 1e-9:.3g} ns"


def fmt_stats(st: Stats) -> str:
    """``median [min-max]`` with one unit for all three."""
    med = st.median
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("us", 1e-6), ("ns", 1e-9)):
        if abs(med) >= scale or unit == "ns":
            return (f"{med / scale:.3g} {unit} [{st.min / scale:.3g}-{st.max / scale:.3g}]")
    raise AssertionError


def fmt_ratio(r: Ratio, suffix: str = "x") -> str:
    return f"{_g(r.median)}{suffix} [{_g(r.min)}-{_g(r.max)}]"


def _g(v: float) -> str:
    return f"{v:.3g}" if v < 1000 else f"{v:,.0f}"
